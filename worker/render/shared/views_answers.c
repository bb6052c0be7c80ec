/* worker/render/shared/views_answers.c — energy, potentials and info as both backends answer them.
 */
#include "worker/render/shared/views_answers.h"

#include <stdio.h>
#include <string.h>

lm_status wk_views_answer_energy(int mesh_set, const wk_image_store *img, int64_t *total,
                                 int64_t *per_view)
{
    if (!mesh_set)
        return lm_fail(LM_E_INVALID, "energy asked before a mesh was set");
    wk_image_store_energies(img, total, per_view);
    return LM_OK;
}

lm_status wk_views_answer_potentials(int mesh_set, const wk_image_store *img,
                                     const lm_view_set *views, const float (*points)[3], size_t n,
                                     int64_t *out)
{
    if (!mesh_set)
        return lm_fail(LM_E_INVALID, "potentials asked before a mesh was set");
    return wk_image_store_potentials(img, views, WK_ORACLE_RADIUS, points, n, out);
}

void wk_views_answer_info(lm_views_info *out, const lm_view_set *views, int width, int height,
                          uint64_t seq, const wk_views_local_stats *stats, const char *renderer)
{
    memset(out, 0, sizeof *out);
    out->n_views = views->count;
    out->width = width;
    out->height = height;
    out->seq = seq;
    out->evaluations = stats->evaluations;
    out->regions = stats->regions;
    out->region_pixels = stats->region_pixels;
    out->tris_drawn = stats->tris_drawn;
    snprintf(out->renderer, sizeof out->renderer, "%s", renderer);
}
