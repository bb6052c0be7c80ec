/* coordinator/compare.h — models judged against their original through the in-process renderer:
 * image energies over a view set (e.g. the 24 held-out views), and a picture grid with one row per
 * view and the columns original | model 1 | model 2 ... for before/after images.
 * Each model is drawn with its own materials (as loaded from its file). */
#ifndef LM_COORDINATOR_COMPARE_H
#define LM_COORDINATOR_COMPARE_H

#include <stdint.h>

#include "common/image.h"
#include "common/mesh.h"
#include "common/view.h"

#define CO_COMPARE_GAP 4 /* pixels between the cells of a grid */

/* energy[i] = E(models[i]) against the original over `views`; renderer (may be NULL, 128 bytes)
 * receives the renderer's description. */
lm_status co_compare_energies(const lm_mesh *original, const lm_view_set *views,
                              const char *device_spec, const lm_mesh *const *models, uint32_t n,
                              int64_t *energy, char *renderer);

/* A grid image: views->count rows, 1 + n columns (the original first), CO_COMPARE_GAP pixels of
 * dark grey between cells. Caller destroys *out. */
lm_status co_compare_grid(const lm_mesh *original, const lm_view_set *views,
                          const char *device_spec, const lm_mesh *const *models, uint32_t n,
                          lm_image **out);

#endif
