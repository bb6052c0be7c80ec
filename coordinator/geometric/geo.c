/* coordinator/geometric/geo.c — OptimizeMesh of Hoppe et al. 1993 end to end: the points, the
 * first inner loop, the spring constant's schedule (an outer loop at each κ, then the inner loop
 * again), and the target: --target-verts N is a floor no move crosses; while the mesh has more
 * than N vertices after the schedule, c_rep doubles and the outer loop runs again at the last κ.
 * Also the start (the original itself when small, else QEM at a multiple of N). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "coordinator/geometric/geo_internal.h"
#include "coordinator/simplify/simplify.h"

/* Hoppe et al.'s schedule of the spring constant (their §4.4: 10⁻², 10⁻³, 10⁻⁴, 10⁻⁸). */
static const double kappa_schedule[] = {1e-2, 1e-3, 1e-4, 1e-8};
#define N_KAPPA (sizeof kappa_schedule / sizeof kappa_schedule[0])
#define INNER_FIRST 10 /* rounds of the first inner loop */
#define INNER_LEVEL 4  /* after each outer loop */
#define MAX_RAMP 60    /* doublings of c_rep at most (2^60 times the user's) */

lm_status co_geo_parse_improvements(const char *list, uint32_t *bits)
{
    *bits = 0;
    if (!strcmp(list, "all")) {
        *bits = CO_GEO_ALL;
        return LM_OK;
    }
    if (!strcmp(list, "none"))
        return LM_OK;
    const char *p = list;
    while (*p) {
        size_t n = strcspn(p, ",");
        if (n == 13 && !strncmp(p, "collapse-only", n))
            *bits |= CO_GEO_COLLAPSE_ONLY;
        else if (n == 6 && !strncmp(p, "stored", n))
            *bits |= CO_GEO_STORED;
        else if (n == 8 && !strncmp(p, "deferred", n))
            *bits |= CO_GEO_DEFERRED;
        else
            return lm_fail(LM_E_INVALID,
                           "--geo-improvements: '%.*s' is none of collapse-only, stored, "
                           "deferred (or all, none)",
                           (int)n, p);
        p += n + (p[n] == ',');
    }
    return LM_OK;
}

lm_status co_geo_make_start(const lm_mesh *original, uint32_t target_verts, uint32_t multiple,
                            lm_mesh **out)
{
    *out = NULL;
    uint64_t k = (uint64_t)target_verts * (multiple ? multiple : CO_GEO_START_MULTIPLE);
    lm_status st;
    if (!target_verts || original->live_verts <= k) {
        st = lm_mesh_clone(original, out);
        if (st == LM_OK)
            st = lm_mesh_compact(*out);
    } else {
        int short_of;
        st = co_simplify_best(original, CO_SIMPLIFY_QEM, (uint32_t)k, out, &short_of);
        if (short_of)
            lm_clear_error();
    }
    if (st == LM_OK)
        st = lm_mesh_build_adjacency(*out);
    if (st != LM_OK && *out) {
        lm_mesh_destroy(*out);
        *out = NULL;
    }
    return st;
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void progress(co_geo_state *g, const char *phase)
{
    if (g->o.on_progress)
        g->o.on_progress(g->o.ctx, phase, 0, 0);
}

static lm_status setup(co_geo_state *g, const lm_mesh *original)
{
    float lo[3], hi[3];
    lm_mesh_bounds(original, lo, hi);
    double diag2 = 0;
    for (int k = 0; k < 3; k++)
        diag2 += ((double)hi[k] - lo[k]) * ((double)hi[k] - lo[k]);
    if (!(diag2 > 0))
        return lm_fail(LM_E_INVALID, "the original is flat to a point");
    uint32_t n = g->o.points;
    if (!n) {
        uint64_t want = (uint64_t)CO_GEO_POINTS_PER_VERT *
                        (g->o.target_verts ? g->o.target_verts : g->m->live_verts);
        n = want < CO_GEO_MIN_POINTS ? CO_GEO_MIN_POINTS
            : want > 2000000         ? 2000000
                                     : (uint32_t)want;
    }
    g->n_pts = n;
    g->w_len = 1 / diag2;
    g->w_dist = 1e4 / ((double)n * diag2);
    g->pt = malloc((size_t)n * sizeof *g->pt);
    if (!g->pt)
        return lm_fail(LM_E_NOMEM, "out of memory for %u points", n);
    lm_rng_seed(&g->rng, g->o.seed);
    lm_status st = co_geo_sample(original, n, g->o.seed, g->pt);
    if (st == LM_OK)
        st = lm_journal_create(&g->j);
    return st;
}

/* The schedule of κ, then the c_rep ramp to the target. */
static lm_status schedule(co_geo_state *g, co_geo_edge_memo *memo)
{
    lm_status st = LM_OK;
    char phase[96];
    for (size_t i = 0; i < N_KAPPA && st == LM_OK; i++) {
        g->kappa = kappa_schedule[i];
        co_geo_retotal(g);
        snprintf(phase, sizeof phase, "geometric: moves at spring %g", g->kappa);
        progress(g, phase);
        st = co_geo_outer(g, memo, i == 0);
        if (st == LM_OK)
            st = co_geo_inner(g, INNER_LEVEL);
    }
    for (int r = 0; st == LM_OK && g->o.target_verts && g->m->live_verts > g->o.target_verts; r++) {
        if (r == MAX_RAMP)
            return lm_fail(LM_E_RANGE,
                           "the geometric optimization stopped at %u vertices, above the target "
                           "%u (no legal collapse is left)",
                           g->m->live_verts, g->o.target_verts);
        g->c_rep *= 2;
        snprintf(phase, sizeof phase, "geometric: to %u vertices (%u now)", g->o.target_verts,
                 g->m->live_verts);
        progress(g, phase);
        st = co_geo_outer(g, memo, 0);
        if (st == LM_OK)
            st = co_geo_inner(g, 1);
    }
    return st == LM_OK ? co_geo_inner(g, INNER_LEVEL) : st;
}

lm_status co_geo_optimize(const lm_mesh *original, lm_mesh *start, const co_geo_options *o,
                          co_geo_summary *sum)
{
    double t0 = now_s();
    memset(sum, 0, sizeof *sum);
    co_geo_state g = {.m = start, .o = *o, .c_rep = o->c_rep, .sum = sum};
    g.kappa = kappa_schedule[0];
    sum->start_verts = start->live_verts;
    co_geo_edge_memo *memo = NULL;
    progress(&g, "geometric: points and the first least-squares fit");
    lm_status st = setup(&g, original);
    if (st == LM_OK)
        st = co_geo_memo_create(&memo);
    if (st == LM_OK)
        st = co_geo_project_all(&g);
    if (st == LM_OK) {
        co_geo_retotal(&g);
        sum->e_start = co_geo_total(&g);
        st = co_geo_inner(&g, INNER_FIRST);
    }
    if (st == LM_OK)
        st = schedule(&g, memo);
    if (st == LM_OK) {
        co_geo_retotal(&g);
        sum->verts = start->live_verts;
        sum->points = g.n_pts;
        sum->e_dist = g.e_dist;
        sum->e_spring = g.e_spring;
        sum->e_rep = o->c_rep * start->live_verts;
        sum->e_total = sum->e_dist + sum->e_spring + sum->e_rep;
        sum->c_rep_final = g.c_rep;
    }
    sum->seconds = now_s() - t0;
    co_geo_memo_destroy(memo);
    lm_journal_destroy(g.j);
    free(g.pt);
    free(g.head);
    free(g.pidx);
    free(g.ptmp);
    return st;
}
