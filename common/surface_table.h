/* common/surface_table.h — the geometric term's per-triangle energies, kept by triangle id for
 * the current coarse mesh (or for one share of its ids), so that a patch's ΔE_geo costs distance
 * queries only for the triangles whose corners moved:
 *
 *   e(t) = round(k · area(t) · mean over q of dist(q, surface)²)
 *
 * with q the three edge midpoints and the centroid of t (what k means: the optimizer's
 * common/optimizer/surface_term.h). Every e(t) is an int64 computed from the triangle's
 * corner positions alone, in double precision without contracted multiply-adds, so the same
 * triangle gives the same bits in the coordinator and in every worker, on every platform.
 *
 * Shares: a table of share s of n holds and prices only the ids with id % n == s, so n tables of
 * shares 0..n-1 (the workers of a job's n groups of views, each pricing its own) together give
 * exactly the ΔE_geo and E_geo of one table of share 0 of 1, whatever the patch. */
#ifndef LM_COMMON_SURFACE_TABLE_H
#define LM_COMMON_SURFACE_TABLE_H

#include <stddef.h>
#include <stdint.h>

#include "common/bvh.h"
#include "common/error.h"
#include "common/patch.h"

/* Distances remembered by point (distance_memo.h): 2^14 slots, 512 KiB. On the bunny at 378
 * vertices about half of an evaluation's queries are answered from it. */
#define LM_SURFACE_MEMO_LOG2 14u

typedef struct lm_surface_table lm_surface_table;

/* An empty table of share `share` of `shares` (share < shares) with scale k (finite, > 0) against
 * `surface` (borrowed: it must outlive the table). */
lm_status lm_surface_table_create(const lm_bvh *surface, double k, uint32_t share, uint32_t shares,
                                  lm_surface_table **out);
void lm_surface_table_destroy(lm_surface_table *t);

/* The table holds exactly the triangles of tris (ids distinct) that are in its share. */
lm_status lm_surface_table_set_mesh(lm_surface_table *t, const lm_tri_data *tris, size_t n);

/* The patch applied: its removed ids dropped, its added triangles of the share priced and kept.
 * Fails only for memory; the table then holds the mesh before the patch, less what was dropped
 * (the caller sets the mesh again, as after any failed change of state). */
lm_status lm_surface_table_commit(lm_surface_table *t, const lm_patch *p);

/* ΔE_geo of the patch over the share: Σ e(added) − Σ e(removed), e of a kept triangle (same id,
 * same corners) taken from the table. Changes nothing but the distance memo, which never
 * changes an answer. */
int64_t lm_surface_table_delta(lm_surface_table *t, const lm_patch *p);

/* E_geo of the share: Σ e(t) over the triangles held. */
int64_t lm_surface_table_total(const lm_surface_table *t);

/* A new scale: every e(t) held is computed again. */
void lm_surface_table_set_k(lm_surface_table *t, double k);

/* Σ k1 · area · mean d² over the triangles held, unrounded, in increasing id order (the same bits
 * for the same mesh): E_geo at scale k1 before rounding. */
double lm_surface_table_unit_energy(lm_surface_table *t, double k1);

/* e(t) at the table's scale for a triangle with corners p (for tests and scaling). */
int64_t lm_surface_table_tri(lm_surface_table *t, const float p[3][3]);

#endif
