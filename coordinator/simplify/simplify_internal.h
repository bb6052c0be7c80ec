/* coordinator/simplify/simplify_internal.h — the two initial simplifiers behind co_simplify()
 * (coordinator/simplify/simplify.c) and the small helpers they share. Private to common/ (and unit
 * tests): other folders call co_simplify(). Both simplifiers follow the contract of co_simplify():
 * *out is set on LM_OK and on LM_E_RANGE (best mesh reached), NULL on any other status — and also
 * NULL in the one LM_E_RANGE case where no triangle at all survives (clustering so coarse that
 * every face degenerates). */
#ifndef LM_COMMON_SIMPLIFY_INTERNAL_H
#define LM_COMMON_SIMPLIFY_INTERNAL_H

#include "coordinator/simplify/simplify.h"

/* The searches aim at |live - target| <= 5% of target; a result at most 5% above the target meets
 * it (the target is an upper bound, with that tolerance). */
#define CO_SIMPLIFY_TOLERANCE 0.05

/* What a simplifier did (for reports and tests). */
typedef struct co_simplify_stats {
    uint32_t passes;               /* simplifier runs made by the search */
    uint32_t double_sided_removed; /* clustering: triangles dropped as double-sided pairs */
    uint32_t duplicates_removed;   /* clustering: repeated triangles (same orientation) dropped */
    uint32_t degenerate_removed;   /* triangles that collapsed to an edge or a point */
    double cell_size;              /* clustering: grid cell side chosen by the search */
} co_simplify_stats;

/* QEM (meshoptimizer's edge collapser), target count searched over its index budget. */
lm_status co_simplify_qem(const lm_mesh *in, uint32_t target_verts, co_simplify_stats *stats,
                          lm_mesh **out);

/* Rossignac–Borrel clustering, grid resolution searched. */
lm_status co_simplify_cluster(const lm_mesh *in, uint32_t target_verts, co_simplify_stats *stats,
                              lm_mesh **out);
/* One clustering pass with a given cell side (> 0), no search. */
lm_status co_simplify_cluster_grid(const lm_mesh *in, double cell_size, co_simplify_stats *stats,
                                   lm_mesh **out);

/* Helpers (coordinator/simplify/simplify.c). */
/* 1 when live is within CO_SIMPLIFY_TOLERANCE of target (what the searches aim for). */
int co_simplify_within(uint32_t live, uint32_t target);
/* 1 when live meets the target as an upper bound: at most CO_SIMPLIFY_TOLERANCE above it. */
int co_simplify_reached(uint32_t live, uint32_t target);
/* Copy every material of src into dst (textures cloned). */
lm_status co_simplify_copy_materials(const lm_mesh *src, lm_mesh *dst);
/* A compact copy of in's live triangles (and what they use), its parts and materials kept. */
lm_status co_simplify_copy_live(const lm_mesh *in, lm_mesh **out);

/* Build a compact mesh from `n` triangles given as input wedge ids (w[3], material, part) of `in`:
 * only the vertices and wedges they use are kept (ascending input order), every material and part
 * is kept.
 * Triangles that repeat a vertex are dropped (counted in *dropped, may be NULL). Adjacency built.
 */
lm_status co_simplify_build_from_tris(const lm_mesh *in, const lm_tri *tris, size_t n,
                                      uint32_t *dropped, lm_mesh **out);
/* Every part of `in` that holds triangles there and none in `out` (a mesh built from `in`, with
 * its part table) appended to out at its smallest non-empty QEM form, simplified alone; *kept
 * counts them. Adjacency rebuilt when any was. */
lm_status co_simplify_keep_parts(const lm_mesh *in, lm_mesh *out, uint32_t *kept);
/* Finish an output mesh: validate, build adjacency. On failure destroys *m and sets it NULL. */
lm_status co_simplify_finish(lm_mesh **m);

#endif
