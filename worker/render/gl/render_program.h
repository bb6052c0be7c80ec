/* worker/render/gl/render_program.h — the renderer's GLSL ES 3.00 programs (private to
 * worker/render*.c): the shading program in two variants (with and without a texture; a material
 * without texture would sample white, so the variant without one computes the same colour with less
 * work), both again for normal-mapped materials (lit per fragment) and the region program
 * (background grey at a given depth). Per-view data (view-projection, light) and per-material data
 * (diffuse) come from uniform blocks at fixed binding points. */
#ifndef LM_WORKER_RENDER_PROGRAM_H
#define LM_WORKER_RENDER_PROGRAM_H

#include <GLES3/gl3.h>

#include "common/error.h"

/* Vertex attribute locations of the stream. */
enum { WK_ATTR_POS = 0, WK_ATTR_NORMAL = 1, WK_ATTR_UV = 2, WK_ATTR_COLOR = 3 };
/* Uniform block binding points. */
enum { WK_BLOCK_VIEW = 0, WK_BLOCK_MATERIAL = 1 };

/* std140 layouts of the blocks. */
typedef struct wk_view_block {
    float view_proj[16];
    float light[4];
} wk_view_block;
typedef struct wk_material_block {
    float diffuse[4];
} wk_material_block;

/* The texture unit of normal maps (colour textures use unit 0). */
#define WK_NORMAL_MAP_UNIT 1

typedef struct wk_render_programs {
    GLuint shade[2];        /* [0] untextured, [1] textured */
    GLuint shade_normal[2]; /* the same with a tangent-space normal map */
    GLuint clear;
} wk_render_programs;

/* background: the clear colour in 8-bit units. */
lm_status wk_render_programs_create(wk_render_programs *out, int background);
void wk_render_programs_destroy(wk_render_programs *p);

#endif
