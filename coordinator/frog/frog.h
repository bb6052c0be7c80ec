/* coordinator/frog/frog.h — the project's own demo asset: a procedural frog-style model in the
 * spirit of the paper's Figure 10. Seven SEPARATE closed parts — body, two hind legs, two front
 * legs (each a bent tube from hip/shoulder through knee/elbow to a flattened foot), two eyes
 * (spheres sticking out of the head) — interpenetrate where they meet, which is what makes cracks
 * appear after simplification. Each part has its own UV chart (seam along one meridian, poles as
 * fans) in one generated 1024x1024 texture with sharp-edged patterns (dark spots on the back, a
 * pale belly, stripes on the legs, black pupils on yellow irises), so texture stretch is easy to
 * see.
 *
 * Axes: y up, x forward (the head), z to the frog's left; about 2.4 units long, feet at y ~ 0.
 * UVs follow the OpenGL/OBJ convention: (0,0) is the bottom-left of the image (image rows are
 * stored top to bottom, so v = 1 - (row + 0.5) / height).
 * Normals are smooth per vertex (lm_mesh_compute_normals); attrs = LM_ATTR_NORMAL | LM_ATTR_UV.
 * One material, "frog_skin", texture path "frog_skin.png". Seven named parts: body,
 * hind_leg_left, hind_leg_right, front_leg_left, front_leg_right, eye_left, eye_right. Adjacency is
 * built. */
#ifndef LM_COMMON_FROG_H
#define LM_COMMON_FROG_H

#include <stdint.h>

#include "common/mesh.h"

#define CO_FROG_MIN_TRIS 500u
#define CO_FROG_MAX_TRIS (1u << 26)
#define CO_FROG_TEXTURE_SIZE 1024
#define CO_FROG_PARTS 7

/* Generate the frog with about target_tris triangles (within ~2% for 2,000 and more; exact
 * shares per part), in [CO_FROG_MIN_TRIS, CO_FROG_MAX_TRIS] else LM_E_RANGE. The same seed gives
 * the same mesh (bit for bit); the seed varies spot and stripe placement and small shape jitter.
 * Memory is linear in target_tris (tests/bench/bench_foundation.c measures it). */
lm_status co_frog_generate(uint32_t target_tris, uint64_t seed, lm_mesh **out);

/* The frog's texture alone (what co_frog_generate puts in its material). */
lm_status co_frog_texture(uint64_t seed, lm_image **out);

#endif
