/* worker/render/shared/materials.h — filling a backend's material table from lm_material records:
 * what both backends do alike (the diffuse colours, copied; a texture handle per material, zero
 * where untextured; the normal maps' handles) around the texture each makes its own way (a
 * pyramid on the CPU, a GL texture on the device). */
#ifndef LM_WORKER_RENDER_SHARED_MATERIALS_H
#define LM_WORKER_RENDER_SHARED_MATERIALS_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"
#include "common/image.h"
#include "common/mesh.h"

/* Make the backend's texture of RGBA8 image img into *handle (a handle of the table's type). */
typedef lm_status (*wk_texture_make)(const lm_image *img, void *handle);

/* A table of n materials: *diffuse gets their colours, *handles n zeroed handles of handle_size
 * bytes, and make fills the handle of each textured material in order, up to the first failure
 * (whose status is returned). *n_out is n once both arrays are there (0 and both NULL when they
 * could not be had: LM_E_NOMEM); the caller owns them and the handles made, failure or not. */
lm_status wk_materials_fill(const lm_material *mats, uint32_t n, size_t handle_size,
                            wk_texture_make make, uint32_t *n_out, float (**diffuse)[4],
                            void **handles);

/* The handles of the materials' normal maps: *handles stays NULL when no material has one, else n
 * zeroed handles of handle_size bytes with make filling those of the mapped materials in order, up
 * to the first failure (whose status is returned). The caller owns the array and the handles made,
 * failure or not. */
lm_status wk_materials_fill_normal_maps(const lm_material *mats, uint32_t n, size_t handle_size,
                                        wk_texture_make make, void **handles);

#endif
