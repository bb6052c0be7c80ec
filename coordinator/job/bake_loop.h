/* coordinator/job/bake_loop.h — maps in the loop (issue 39, point 3; `optimize --bake KINDS
 * --bake-every N`): the maps of the original baked onto the optimizer's current mesh every N
 * evaluations, and a views wrapper through which the optimizer's renders of the current mesh
 * wear them, so that the geometry is optimised with the maps on.
 *
 * Texture coordinates: the maps go through a per-triangle atlas keyed by triangle id
 * (common/uv_atlas.h, lm_atlas_by_id): triangle t's chart is cell t mod cells² of a grid sized at
 * each bake for the mesh's triangle slots and a quarter more (room for the ids the moves make).
 * The mesh's own coordinates are never used (they may overlap, or be absent), nor changed: the
 * wrapper rewrites the coordinates of every triangle it passes on to the views (set_mesh, the
 * patches of evaluate and commit) with its id's chart. Between bakes a triangle a move changed
 * keeps its id's chart (its map moved with it, stretched as the triangle is); a triangle a move
 * made under a reused id gets that id's old chart, under a new id an empty cell (its gutters):
 * approximate until the next bake, which bakes every triangle alive then. With a colour bake
 * the triangles' vertex colours become white (the map holds them); without one, the mesh's own
 * textures are resampled into the atlas at each bake (so its coordinates are not optimised:
 * the job drops uv from the optimised attributes).
 *
 * Determinism: a bake is a function of the original and the mesh (common/bake_walk.h: the same
 * bits on every host); the wrapper's coordinates a function of the ids and the grid. Workers: the
 * materials (with their maps) travel as any set_materials does, so any worker count gives the same
 * bytes. */
#ifndef LM_COORDINATOR_JOB_BAKE_LOOP_H
#define LM_COORDINATOR_JOB_BAKE_LOOP_H

#include "common/bake_walk.h"
#include "common/views_api.h"

typedef struct co_bake_loop co_bake_loop;

/* The loop's bakes of `original` (borrowed; must outlive it): maps `kinds` (CO_BAKE_*) of size x
 * size texels. Nothing is baked yet: until the first bake the wrapper passes triangles through
 * unchanged. LM_E_NOMEM. */
lm_status co_bake_loop_create(const lm_mesh *original, unsigned kinds, int size,
                              co_bake_loop **out);
void co_bake_loop_destroy(co_bake_loop *b);

/* A views object over `inner` (ownership taken, also on failure: destroyed with the wrapper) that
 * rewrites triangles as above and forwards everything else. LM_E_NOMEM. */
lm_status co_bake_loop_wrap(co_bake_loop *b, lm_views *inner, lm_views **out);

/* Bakes the maps onto mesh m (the optimizer's; its triangle ids are the wrapper's keys): a new
 * grid, the materials with the maps (co_bake_loop_materials). The caller then hands the
 * materials to the views and the mesh again (its coordinates changed with the grid). Blocking;
 * stats may be NULL; LM_E_INVALID (the grid does not fit the size: one line), LM_E_NOMEM. */
lm_status co_bake_loop_bake(co_bake_loop *b, const lm_mesh *m, lm_bake_stats *stats);

/* The materials of the last bake (m's, with the maps), *n their count; NULL before the first. */
const lm_material *co_bake_loop_materials(const co_bake_loop *b, uint32_t *n);

/* The grid's side of the last bake (0 before the first). */
uint32_t co_bake_loop_cells(const co_bake_loop *b);

#endif
