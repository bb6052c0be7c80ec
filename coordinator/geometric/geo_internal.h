/* coordinator/geometric/geo_internal.h — the state of one geometric optimization shared by its
 * files: the sampled points and their projections (triangle, barycentrics, squared distance,
 * chained per triangle), the energy's constants and running terms, the mesh and its journal. */
#ifndef LM_COORDINATOR_GEOMETRIC_GEO_INTERNAL_H
#define LM_COORDINATOR_GEOMETRIC_GEO_INTERNAL_H

#include "common/mesh_topology.h"
#include "common/optimizer/rng.h"
#include "coordinator/geometric/geo.h"

typedef struct co_geo_point {
    double x[3];
    uint32_t tri;   /* projection: triangle id */
    uint32_t next;  /* next point on the same triangle (LM_NONE) */
    double bary[3]; /* for the triangle's corners 0..2 */
    double d2;      /* squared distance to the projection */
} co_geo_point;

struct co_geo_state {
    lm_mesh *m;
    lm_journal *j;
    co_geo_point *pt;
    uint32_t n_pts;
    uint32_t *head; /* [cap_head] first point of each triangle id (LM_NONE) */
    uint32_t cap_head;
    double w_dist; /* 1e4 / (n_pts * D²): E_dist as if 10,000 points, D = the bounding diagonal */
    double w_len;  /* 1 / D² for spring lengths */
    double kappa, c_rep;
    double e_dist, e_spring; /* tracked: w_dist Σ d², kappa w_len Σ |e|² */
    co_geo_options o;
    lm_rng rng;
    co_geo_summary *sum;
    uint32_t *pidx;     /* [pcap] scratch: the points a move re-projects */
    co_geo_point *ptmp; /* [pcap] scratch: their projections after the move */
    uint32_t pcap;
};

/* sample.c: n points on original's surface, area-weighted, from the seed. */
lm_status co_geo_sample(const lm_mesh *original, uint32_t n, uint64_t seed, co_geo_point *out);

/* project.c */
lm_status co_geo_project_all(co_geo_state *g);
/* Project point p onto the best of the live triangles tris[0..n) (writes tri, bary, d2). */
void co_geo_project_onto(const lm_mesh *m, co_geo_point *p, const uint32_t *tris, uint32_t n);
/* Make head[] hold every triangle id of the mesh (after it grew); LM_E_NOMEM. */
lm_status co_geo_heads_fit(co_geo_state *g);

/* solve.c: one least-squares step of every position for the current projections. */
lm_status co_geo_solve_positions(co_geo_state *g);

/* energy.c */
double co_geo_spring_sum(const lm_mesh *m); /* Σ |e|² over edges (model units) */
double co_geo_vertex_spring(const lm_mesh *m, uint32_t v, const float p[3], uint32_t skip);
double co_geo_dist_sum(const co_geo_state *g); /* Σ d² over points */
void co_geo_retotal(co_geo_state *g);          /* e_dist, e_spring from scratch */
double co_geo_total(const co_geo_state *g);    /* e_dist + e_spring + c_rep * verts */
/* The inner loop: project, solve, until E falls by less than a relative 1e-4 or `rounds` done;
 * keeps positions only where E fell. */
lm_status co_geo_inner(co_geo_state *g, int rounds);

/* moves.c: try one move on edge (a, b); 1 accepted, 0 refused; *dd and *ds (may be NULL) get the
 * change of w_dist Σ d² and of w_len Σ |e|² the move would make (NAN when illegal). */
enum { CO_GEO_MOVE_COLLAPSE, CO_GEO_MOVE_SWAP, CO_GEO_MOVE_SPLIT };
int co_geo_try_move(co_geo_state *g, int kind, uint32_t a, uint32_t b, double *dd, double *ds);
/* Vertex count the target allows no lower (0: none). */

/* outer.c: the outer loop at the current kappa and c_rep until no candidate is left. */
typedef struct co_geo_edge_memo co_geo_edge_memo;
lm_status co_geo_memo_create(co_geo_edge_memo **out);
void co_geo_memo_destroy(co_geo_edge_memo *memo);
lm_status co_geo_outer(co_geo_state *g, co_geo_edge_memo *memo, int first_pass);

#endif
