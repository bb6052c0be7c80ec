/* worker/render/shared/materials.c — a material table's colours and texture handles, filled
 * alike for both backends (see materials.h). */
#include "worker/render/shared/materials.h"

#include <stdlib.h>
#include <string.h>

lm_status wk_materials_fill(const lm_material *mats, uint32_t n, size_t handle_size,
                            wk_texture_make make, uint32_t *n_out, float (**diffuse)[4],
                            void **handles)
{
    uint8_t *h = calloc(n ? n : 1, handle_size);
    float(*d)[4] = calloc(n ? n : 1, sizeof *d);
    *n_out = 0;
    *diffuse = NULL;
    *handles = NULL;
    if (!h || !d) {
        free(h);
        free(d);
        return lm_fail(LM_E_NOMEM, "out of memory for %u materials", n);
    }
    *n_out = n;
    *diffuse = d;
    *handles = h;
    lm_status st = LM_OK;
    for (uint32_t i = 0; st == LM_OK && i < n; i++) {
        memcpy(d[i], mats[i].diffuse, sizeof d[i]);
        if (mats[i].texture)
            st = make(mats[i].texture, h + i * handle_size);
    }
    return st;
}

lm_status wk_materials_fill_normal_maps(const lm_material *mats, uint32_t n, size_t handle_size,
                                        wk_texture_make make, void **handles)
{
    uint8_t *h = NULL;
    lm_status st = LM_OK;
    for (uint32_t i = 0; st == LM_OK && i < n; i++) {
        if (!mats[i].normal_map)
            continue;
        if (!h && !(*handles = h = calloc(n, handle_size)))
            return lm_fail(LM_E_NOMEM, "out of memory for %u materials", n);
        st = make(mats[i].normal_map, h + i * handle_size);
    }
    return st;
}
