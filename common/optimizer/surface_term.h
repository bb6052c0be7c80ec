/* common/optimizer/surface_term.h — the optimizer's geometric term: views that add to the
 * image energy of the views they wrap a penalty on the coarse mesh drifting off the original's
 * surface, so that vertices the images cannot place (hidden, grazing or seen by few views) stay on
 * the surface instead of being painted for the views that see them.
 *
 *   E_geo = Σ_t e(t),  e(t) = round(k · area(t) · mean over q of dist(q, original)²)
 *
 * with q the three edge midpoints and the centroid of triangle t, and k = weight · views · (S/2r)²
 * · (256/2r)²: area in pixels of the training views (S wide, framing the bounding sphere of radius
 * r), distance in pixels of a 256-wide view, once per view, so that weight 1 costs a triangle what
 * one squared unit of luminance per pixel and view would if every view saw it a pixel off.
 *
 * Every e(t) is an int64 computed from the triangle's corner positions alone (common/
 * surface_table.h: double precision, no contracted multiply-adds, the same bits on every
 * platform), so evaluate's ΔE stays an exact integer and E_geo does not depend on how views are
 * split or on the order of anything. The wrapped views are borrowed; every op is passed on to
 * them, evaluate adds each patch's ΔE_geo, energy adds E_geo to the total (per_view stays the
 * image energies).
 *
 * Where the wrapped views hold the term too (lm_views_surface_term: workers in other processes),
 * the ΔE_geo of an evaluation can be priced there, each group of views a share of the triangle
 * ids, so that it costs the coordinator no distance query (it keeps only E_geo: set_mesh,
 * commit): on a cluster the coordinator's own work is what caps the speed-up. Where this
 * process has a processor to itself, pricing it here while they render can be faster; by default
 * the wrapper measures both ways now and then and keeps the faster, and where the workers busy
 * every processor of this machine (lm_views_info.overlap_costs) they always price it
 * (lm_surface_views_set_pricing). The answers are the same bits either way. */
#ifndef LM_COMMON_OPTIMIZER_SURFACE_TERM_H
#define LM_COMMON_OPTIMIZER_SURFACE_TERM_H

#include <stdint.h>

#include "common/mesh.h"
#include "common/views_api.h"

/* Views over `inner` (borrowed, must outlive them) with the geometric term against `surface`
 * (borrowed likewise; its live triangles, at least one) of weight `weight` (> 0). */
lm_status lm_surface_views_create(lm_views *inner, const lm_mesh *surface, double weight,
                                  lm_views **out);

/* Wrap `inner` (borrowed) instead of the views given so far, handing it the term where it takes
 * it; the caller sets the mesh on v next. k is computed again by the rule above from inner's count
 * and width with the weight in force, so that where the views grow (a view schedule's stage: more
 * views, more pixels, hence about that much more image energy) the term keeps the share of the
 * energy it had: views of the same count and size keep k's bits (a regrid, new training views),
 * and k is a function of the weight and the views in force alone, not of the views before (a
 * resume straight into a later stage finds the same). Fails only as inner's surface_term op does.
 */
lm_status lm_surface_views_set_inner(lm_views *v, lm_views *inner);

/* k now (e(t) = round(k · area · mean d²)). */
double lm_surface_views_scale(const lm_views *v);

/* 1 when the wrapped views hold the term (lm_views_surface_term took it), so they can price the
 * evaluations' ΔE_geo. */
int lm_surface_views_offloaded(const lm_views *v);

typedef enum lm_surface_pricing {
    LM_SURFACE_AUTO = 0, /* whichever way measures faster (the default) */
    LM_SURFACE_HERE,     /* always here */
    LM_SURFACE_WORKERS,  /* always by the wrapped views, where they hold the term */
} lm_surface_pricing;

/* Where evaluations' ΔE_geo is priced (the answers are the same bits: tests and benchmarks). The
 * default comes from LUMESH_SURFACE_PRICING (here, workers; else auto). */
void lm_surface_views_set_pricing(lm_views *v, lm_surface_pricing p);

/* The share of evaluated patches whose ΔE_geo the wrapped views priced. */
double lm_surface_views_worker_share(const lm_views *v);

/* E_geo of the current mesh (0 before the first set_mesh). `v` must come from
 * lm_surface_views_create. */
int64_t lm_surface_views_energy(const lm_views *v);

/* E_geo of the current mesh at weight 1, unrounded (Σ over triangle ids in increasing order, so
 * the same bits for the same mesh): what lm_optimizer scales a relative weight by. */
double lm_surface_views_unit_energy(const lm_views *v);

/* The weight that makes E_geo of the current mesh `share` times its image energy (the energy of
 * the wrapped views), at most LM_SURFACE_MAX_WEIGHT; 1 when either is 0. A function of the mesh and
 * the views alone (E_geo at weight 1 summed in triangle-id order, the image energy exact), so the
 * same for any split of the views. Fails only as the wrapped views' energy op does. */
lm_status lm_surface_views_weight_for_share(lm_views *v, double share, double *weight);

/* Change the weight (> 0) and recompute every e(t) of the current mesh with it (and hand the new
 * scale to wrapped views that price the term). Fails only as their surface_term op does. */
lm_status lm_surface_views_set_weight(lm_views *v, double weight);

/* e(t) of one triangle (for tests and the scale above). */
int64_t lm_surface_views_tri(const lm_views *v, const float p[3][3]);

#endif
