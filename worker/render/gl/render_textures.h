/* worker/render/gl/render_textures.h — a material table on the device: diffuse colours and textures
 * (private to worker/render*.c). */
#ifndef LM_WORKER_RENDER_TEXTURES_H
#define LM_WORKER_RENDER_TEXTURES_H

#include <GLES3/gl3.h>
#include <stdint.h>

#include "common/mesh.h"

typedef struct wk_material_table {
    uint32_t n;
    GLuint *tex;         /* [n]; 0 for untextured materials */
    GLuint *nrm;         /* [n] normal maps (0 where none), or NULL when no material has one */
    float (*diffuse)[4]; /* [n] */
    GLuint ubo;          /* n material blocks, `stride` bytes apart */
    GLsizeiptr stride;
} wk_material_table;

/* Replace the table's contents (uploads every texture). */
lm_status wk_material_table_set(wk_material_table *t, const lm_material *mats, uint32_t n);
void wk_material_table_free(wk_material_table *t);

#endif
