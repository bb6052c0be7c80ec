/* coordinator/quality/view_setup.h — what `energy`, `compare`, `render` and `bench` share: the view
 * set framed by the original's bounding sphere, in-process views holding the original's target
 * images and a model as the current mesh, and an original and its models loaded from files. */
#ifndef LM_COORDINATOR_VIEW_SETUP_H
#define LM_COORDINATOR_VIEW_SETUP_H

#include "common/mesh.h"
#include "common/view.h"
#include "common/views_api.h"

/* n views of size x size around `framing` (LM_VIEWS_HELDOUT: the 24 held-out views, LM_VIEWS_DENSE:
 * the 96 of the dense check; n ignored for both). *out is allocated; free() it. */
lm_status co_view_set_around(const lm_mesh *framing, uint32_t n, int size, lm_view_set_kind kind,
                             lm_view_set **out);
/* The same for views as spec says (count 0: LM_DEFAULT_VIEWS): the sphere's, the upper
 * hemisphere's, a camera file's (lm_view_set_make_spec). */
lm_status co_view_set_of(const lm_mesh *framing, const lm_view_spec *spec, int size,
                         lm_view_set_kind kind, lm_view_set **out);

/* In-process views of `original` on device `device` with `model` as the current mesh. When model
 * is not the original its own materials are used for its triangles. */
lm_status co_views_with_model(const lm_mesh *original, const lm_mesh *model,
                              const lm_view_set *views, const char *device, lm_views **out);

/* Judges models against their original over views: what co_judge_files calls. */
typedef lm_status (*co_judge_fn)(void *ctx, const lm_mesh *original, const lm_mesh *const *models,
                                 const lm_view_set *views);

/* Loads the original and the n models from their files, makes the views of size x size of `kind`
 * around the original as `views` says (co_view_set_of), calls judge(ctx, ...) with them and frees
 * them all; returns the first failure. */
lm_status co_judge_files(const char *original, const char *const *models, uint32_t n,
                         const lm_view_spec *views, int size, lm_view_set_kind kind,
                         co_judge_fn judge, void *ctx);

/* Seconds on a monotonic clock. */
double co_now_s(void);

#endif
