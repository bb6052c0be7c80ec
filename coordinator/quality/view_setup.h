/* coordinator/quality/view_setup.h — what `energy`, `render` and `bench` share: the view set framed
 * by the original's bounding sphere, and in-process views holding the original's target images and
 * a model as the current mesh. */
#ifndef LM_COORDINATOR_VIEW_SETUP_H
#define LM_COORDINATOR_VIEW_SETUP_H

#include "common/mesh.h"
#include "common/view.h"
#include "common/views_api.h"

/* n views of size x size around `framing` (LM_VIEWS_HELDOUT: the 24 held-out views, LM_VIEWS_DENSE:
 * the 96 of the dense check; n ignored for both). *out is allocated; free() it. */
lm_status co_view_set_around(const lm_mesh *framing, uint32_t n, int size, lm_view_set_kind kind,
                             lm_view_set **out);

/* In-process views of `original` on device `device` with `model` as the current mesh. When model
 * is not the original its own materials are used for its triangles. */
lm_status co_views_with_model(const lm_mesh *original, const lm_mesh *model,
                              const lm_view_set *views, const char *device, lm_views **out);

/* Seconds on a monotonic clock. */
double co_now_s(void);

#endif
