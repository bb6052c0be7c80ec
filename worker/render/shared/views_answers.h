/* worker/render/shared/views_answers.h — the views ops both backends answer the same way from
 * their image store (energy, the oracle's potentials) and the info they fill alike. Each checks
 * that a mesh was set first (LM_E_INVALID otherwise). */
#ifndef LM_WORKER_RENDER_SHARED_VIEWS_ANSWERS_H
#define LM_WORKER_RENDER_SHARED_VIEWS_ANSWERS_H

#include <stddef.h>
#include <stdint.h>

#include "common/views_api.h"
#include "worker/render/shared/image_store.h"
#include "worker/render/shared/views_stats.h"

/* views_api.h's energy: the image store's exact sums. */
lm_status wk_views_answer_energy(int mesh_set, const wk_image_store *img, int64_t *total,
                                 int64_t *per_view);
/* views_api.h's potentials: the oracle's blurred differences at the points, over `views`. */
lm_status wk_views_answer_potentials(int mesh_set, const wk_image_store *img,
                                     const lm_view_set *views, const float (*points)[3], size_t n,
                                     int64_t *out);
/* views_api.h's info: sizes, state counter, counts and the renderer's name. */
void wk_views_answer_info(lm_views_info *out, const lm_view_set *views, int width, int height,
                          uint64_t seq, const wk_views_local_stats *stats, const char *renderer);

#endif
