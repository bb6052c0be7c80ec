/* coordinator/simplify/lod_manifest.c — the levels measured against the original (held-out image
 * energy and surface distance, the way `lumesh energy --heldout --distance` measures a file), their
 * switch distances, and the manifest lods.json written atomically. */
#include "coordinator/simplify/lod_manifest.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/folders.h"
#include "common/io/atomic_file.h"
#include "coordinator/quality/compare.h"
#include "coordinator/quality/json_text.h"
#include "coordinator/quality/phase_meter.h"
#include "coordinator/quality/view_setup.h"

#define LOD_PI 3.14159265358979323846

typedef struct measuring {
    const co_lod_options *o;
    co_lod_summary *sum;
    co_meter meter;
} measuring;

/* The judge (co_judge_fn): held-out energies of every level, then each level's distance. */
static lm_status judge(void *ctx, const lm_mesh *orig, const lm_mesh *const *levels,
                       const lm_view_set *vs)
{
    measuring *M = ctx;
    uint32_t n = M->sum->n_levels;
    int64_t total[LM_MESH_MAX_LODS];
    double pixels = (double)vs->count * vs->views[0].width * vs->views[0].width;
    co_meter_phase(&M->meter, "held-out energies of %u levels (%u views)", n, vs->count);
    lm_status st = co_compare_energies(orig, vs, M->o->device, levels, n, total, NULL, NULL,
                                       M->sum->heldout_renderer);
    M->sum->heldout_views = vs->count;
    co_meter_phase(&M->meter, "surface distance of every level");
    for (uint32_t k = 0; k < n && st == LM_OK; k++) {
        co_lod_measure *m = &M->sum->level[k].m;
        m->heldout = total[k];
        m->heldout_mse = (double)total[k] / pixels;
        co_meter_show(&M->meter, NULL, k, n, 0);
        st = co_surface_distance_measure(orig, levels[k], 0, &m->distance);
    }
    co_meter_end(&M->meter);
    return st;
}

/* The same judge on the levels in memory (one GLB: no file per level to load). */
static lm_status judge_in_memory(measuring *M, const lm_mesh *const *levels)
{
    lm_mesh *orig = NULL;
    lm_view_set *vs = NULL;
    lm_status st = lm_mesh_load(M->o->input_path, NULL, &orig);
    if (st == LM_OK)
        st = co_view_set_of(orig, &M->o->views, M->o->size, LM_VIEWS_HELDOUT, &vs);
    if (st == LM_OK)
        st = judge(M, orig, levels, vs);
    free(vs);
    lm_mesh_destroy(orig);
    return st;
}

lm_status co_lod_measure_levels(const co_lod_options *o, co_lod_summary *sum,
                                const lm_mesh *const *levels)
{
    measuring M = {.o = o, .sum = sum};
    co_meter_init(&M.meter, "lumesh lod", o->progress ? CO_METER_TTY : CO_METER_NONE, stderr);
    const char *paths[LM_MESH_MAX_LODS];
    if (o->progress)
        fprintf(stderr,
                "lumesh lod: measuring %u levels against the original (held-out views, "
                "surface distance)\n",
                sum->n_levels);
    for (uint32_t k = 0; k < sum->n_levels; k++)
        paths[k] = sum->level[k].path;
    co_meter_phase(&M.meter, "loading %s and the levels", o->input_path);
    lm_status st = o->msft_lod ? judge_in_memory(&M, levels)
                               : co_judge_files(o->input_path, paths, sum->n_levels, &o->views,
                                                o->size, LM_VIEWS_HELDOUT, judge, &M);
    co_meter_destroy(&M.meter);
    if (st == LM_OK)
        co_lod_switch_distances(o, sum);
    return st;
}

void co_lod_switch_distances(const co_lod_options *o, co_lod_summary *sum)
{
    double tan_half = tan(o->fov_deg * LOD_PI / 360.0), e = 0;
    for (uint32_t k = 0; k < sum->n_levels; k++) {
        co_lod_measure *m = &sum->level[k].m;
        e = m->distance.max > e ? m->distance.max : e;
        m->switch_error = e;
        m->screen_error_px =
            m->distance.diagonal > 0 ? e * o->screen_height / m->distance.diagonal : 0;
        m->switch_distance = e * o->screen_height / (2.0 * tan_half * o->pixel_error);
    }
}

void co_lod_manifest_path(const co_lod_options *o, char *buf, size_t cap)
{
    if (o->manifest_path) {
        snprintf(buf, cap, "%s", o->manifest_path);
        return;
    }
    const char *slash = strrchr(o->output_path, '/');
    int dir = slash ? (int)(slash - o->output_path + 1) : 0;
    snprintf(buf, cap, "%.*s%s", dir, o->output_path, CO_LOD_MANIFEST_NAME);
}

/* A path as the manifest names it: relative to the manifest's folder when it is in it. */
static const char *as_seen_from(const char *manifest, const char *path)
{
    const char *ms = strrchr(manifest, '/'), *ps = strrchr(path, '/');
    size_t md = ms ? (size_t)(ms - manifest + 1) : 0, pd = ps ? (size_t)(ps - path + 1) : 0;
    return md == pd && !strncmp(manifest, path, md) ? path + pd : path;
}

static double ratio(double x, double diagonal)
{
    return diagonal > 0 ? x / diagonal : 0;
}

static void write_level(FILE *f, const co_lod_options *o, const co_lod_summary *sum, uint32_t k)
{
    const co_lod_level_result *r = &sum->level[k];
    const co_surface_distance *d = &r->m.distance;
    char node[16];
    fprintf(f, "    {\"level\": %u, \"file\": ", k);
    co_json_string(f, as_seen_from(sum->manifest, o->msft_lod ? o->output_path : r->path));
    snprintf(node, sizeof node, "LOD%u", k);
    if (o->msft_lod)
        fprintf(f, ", \"node\": \"%s\"", node);
    fprintf(f,
            ", \"vertices\": %u, \"triangles\": %u, \"parts\": %u,\n"
            "     \"distance\": {\"mean\": %.9g, \"rms\": %.9g, \"max\": %.9g, \"mean_rel\": %.9g, "
            "\"max_rel\": %.9g, \"samples\": %u},\n"
            "     \"heldout\": {\"total\": %lld, \"mse\": %.6f},\n"
            "     \"switch\": {\"error\": %.9g, \"error_rel\": %.9g, \"screen_error_px\": %.9g, "
            "\"distance\": %.9g}}%s\n",
            r->verts, r->tris, r->parts, d->mean, d->rms, d->max, ratio(d->mean, d->diagonal),
            ratio(d->max, d->diagonal), d->samples, (long long)r->m.heldout, r->m.heldout_mse,
            r->m.switch_error, ratio(r->m.switch_error, d->diagonal), r->m.screen_error_px,
            r->m.switch_distance, k + 1 < sum->n_levels ? "," : "");
}

static void write_json(FILE *f, const co_lod_options *o, const co_lod_summary *sum)
{
    fprintf(f, "{\n  \"original\": ");
    co_json_string(f, o->input_path);
    fprintf(f,
            ",\n  \"vertices\": %u, \"triangles\": %u, \"parts\": %u, \"diagonal\": %.9g,\n"
            "  \"screen\": {\"height_px\": %u, \"fov_deg\": %.9g, \"pixel_error\": %.9g},\n"
            "  \"switch_formula\": \"pixels(d) = error * height_px / (2 d tan(fov/2)); a level is "
            "shown from distance = error * height_px / (2 tan(fov/2) pixel_error) on; error = the "
            "running maximum of distance.max down the chain\",\n"
            "  \"heldout\": {\"views\": %u, \"size\": %d, \"renderer\": ",
            sum->in_verts, sum->in_tris, sum->in_parts,
            sum->n_levels ? sum->level[0].m.distance.diagonal : 0.0, o->screen_height, o->fov_deg,
            o->pixel_error, sum->heldout_views, o->size);
    co_json_string(f, sum->heldout_renderer);
    fprintf(f, "},\n  \"levels\": [\n");
    for (uint32_t k = 0; k < sum->n_levels; k++)
        write_level(f, o, sum, k);
    fprintf(f, "  ]\n}\n");
}

lm_status co_lod_manifest_write(const co_lod_options *o, co_lod_summary *sum)
{
    co_lod_manifest_path(o, sum->manifest, sizeof sum->manifest);
    lm_atomic_file f;
    lm_status st = lm_make_parent_folders(sum->manifest);
    if (st == LM_OK)
        st = lm_atomic_open(&f, sum->manifest);
    if (st != LM_OK)
        return st;
    write_json(f.fp, o, sum);
    return lm_atomic_commit(&f);
}
