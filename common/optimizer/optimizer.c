/* common/optimizer/optimizer.c — the Lindstrom–Turk optimizer (paper §5) as one object:
 * iterations of 64 edges chosen by the oracle and at random, each edge optimised by edge.c (one at
 * a time, or several in flight by lanes.c). Checkpointing lives in optimizer_state.c. */
#include "common/optimizer/optimizer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "common/mesh_topology.h"
#include "common/optimizer/edge.h"
#include "common/optimizer/lanes.h"
#include "common/optimizer/optimizer_internal.h"
#include "common/optimizer/surface_term.h"

static lm_status prepare_mesh(lm_optimizer *o)
{
    lm_mesh *m = o->mesh;
    lm_status st = lm_mesh_build_adjacency(m);
    if (st)
        return st;
    if (!(o->attrs & LM_ATTR_NORMAL)) {
        /* derived normals: no seams from normals, and every normal as the moves derive them */
        lm_mesh_merge_wedges(m, LM_ATTR_UV | LM_ATTR_COLOR);
        lm_mesh_compute_normals(m);
    }
    return lm_views_set_mesh_from(o->views, m);
}

void lm_tuning_defaults(lm_tuning *t)
{
    lm_tuning d = {.stats_half_life = 20000,
                   .stats_min_weight = 1.0,
                   .oracle_share = 0.5,
                   .oracle_min_share = 0.125,
                   .oracle_max_share = 0.875,
                   .oracle_max_age = 16,
                   .surface_weight = LM_SURFACE_WEIGHT,
                   .surface_share = LM_SURFACE_SHARE};
    lm_moves_config_defaults(&d.moves);
    lm_teleport_config_defaults(&d.teleport);
    *t = d;
}

#define DEF(field)                                                                                 \
    if (!(t->field > 0))                                                                           \
    t->field = d.field

static void resolve_tuning(lm_tuning *t)
{
    lm_tuning d;
    lm_tuning_defaults(&d);
    DEF(stats_half_life);
    DEF(stats_min_weight);
    DEF(oracle_share);
    DEF(oracle_min_share);
    DEF(oracle_max_share);
    DEF(oracle_max_age);
    if (t->surface_weight == 0 || !isfinite(t->surface_weight))
        t->surface_weight = d.surface_weight;
    if (t->surface_share == 0 || !isfinite(t->surface_share))
        t->surface_share = d.surface_share;
    DEF(moves.max_set_verts);
    DEF(moves.max_dim);
    DEF(moves.pos_step);
    DEF(moves.normal_step);
    DEF(moves.uv_step);
    DEF(moves.color_step);
    DEF(moves.size_tol);
    DEF(teleport.threshold_half_life);
    DEF(teleport.stats_half_life);
    DEF(teleport.max_search_evals);
}

#undef DEF

static lm_status make_moves(lm_optimizer *o)
{
    lm_moves_config *mc = &o->moves_cfg;
    *mc = o->tuning.moves;
    mc->attrs = o->attrs;
    mc->evals_per_dim = o->params.simplex_evals_per_dim;
    float r;
    lm_mesh_bounding_sphere(o->mesh, mc->centre, &r);
    mc->bound_radius = 4.0f * r;
    lm_status st = lm_moves_create(o->mesh, o->views, mc, &o->mv);
    if (st == LM_OK && o->params.edges_in_flight > 1)
        st = lm_lanes_create(o, o->params.edges_in_flight, &o->lanes);
    return st;
}

static lm_status alloc_iteration(lm_optimizer *o)
{
    uint32_t n = o->params.edges_per_iteration;
    o->it.plan = calloc(n, sizeof *o->it.plan);
    o->it.no_progress = calloc(n, sizeof *o->it.no_progress);
    o->totals = calloc(o->params.edges_in_flight, sizeof *o->totals);
    if (!o->it.plan || !o->it.no_progress || !o->totals)
        return lm_fail(LM_E_NOMEM, "out of memory for an iteration of %u edges", n);
    return LM_OK;
}

/* The geometric term between the moves and the caller's views, where there is a surface: of the
 * tuning's weight, or else of weight 1 until relative_weight sets it from the share. */
static lm_status wrap_views(lm_optimizer *o)
{
    lm_tuning *t = &o->tuning;
    if (!o->params.surface || t->surface_weight < 0 ||
        (!(t->surface_weight > 0) && !(t->surface_share > 0))) {
        t->surface_weight = -1; /* none: a checkpoint says so */
        return LM_OK;
    }
    double w = t->surface_weight > 0 ? t->surface_weight : 1.0;
    lm_status st = lm_surface_views_create(o->views, o->params.surface, w, &o->surface);
    if (st == LM_OK)
        o->views = o->surface;
    return st;
}

/* Without a weight of its own the term gets the one that makes E_geo at the start the tuning's
 * share of the image energy there (weight 1 if either is 0). The weight is a function of the start
 * mesh and the views alone, so a --resume finds the same one; the checkpoint records it. */
static lm_status relative_weight(lm_optimizer *o)
{
    if (!o->surface || o->tuning.surface_weight > 0)
        return LM_OK;
    lm_status st = lm_surface_views_weight_for_share(o->surface, o->tuning.surface_share,
                                                     &o->tuning.surface_weight);
    if (st == LM_OK)
        st = lm_surface_views_set_weight(o->surface, o->tuning.surface_weight);
    return st;
}

static lm_status create_parts(lm_optimizer *o)
{
    lm_status st = wrap_views(o);
    if (!st)
        st = prepare_mesh(o);
    if (!st)
        st = relative_weight(o);
    if (!st)
        st = make_moves(o);
    if (!st)
        st = lm_teleport_init(&o->tp, &o->tuning.teleport, o->mesh);
    if (!st)
        st = alloc_iteration(o);
    if (!st)
        st = o->views->ops->energy(o->views, &o->prog.energy_start, NULL);
    o->prog.energy = o->prog.energy_start;
    o->prog.geometric_start = o->surface ? lm_surface_views_energy(o->surface) : 0;
    return st;
}

lm_status lm_optimizer_create(lm_mesh *mesh, lm_views *views, const lm_params *params,
                              lm_optimizer **out)
{
    return lm_optimizer_create_tuned(mesh, views, params, NULL, out);
}

lm_status lm_optimizer_create_tuned(lm_mesh *mesh, lm_views *views, const lm_params *params,
                                    const lm_tuning *tuning, lm_optimizer **out)
{
    *out = NULL;
    if (!mesh || !views)
        return lm_fail(LM_E_INVALID, "optimizer: a mesh and views are required");
    lm_optimizer *o = calloc(1, sizeof *o);
    if (!o)
        return lm_fail(LM_E_NOMEM, "out of memory creating the optimizer");
    o->mesh = mesh;
    o->views = views;
    if (params)
        o->params = *params;
    if (tuning)
        o->tuning = *tuning;
    resolve_tuning(&o->tuning);
    if (!o->params.seed)
        o->params.seed = 1;
    if (!o->params.edges_per_iteration)
        o->params.edges_per_iteration = LM_DEFAULT_EDGES_PER_ITERATION;
    if (!o->params.simplex_evals_per_dim)
        o->params.simplex_evals_per_dim = 32;
    if (!o->params.edges_in_flight)
        o->params.edges_in_flight = 1;
    o->params.lane_isolation = o->params.lane_isolation && o->params.edges_in_flight > 1;
    if (o->params.edges_per_iteration > LM_MAX_EDGES_PER_ITERATION ||
        o->params.simplex_evals_per_dim > 1u << 16 ||
        o->params.edges_in_flight > LM_MAX_EDGES_IN_FLIGHT) {
        lm_optimizer_destroy(o); /* the mesh was taken: it goes too */
        return lm_fail(LM_E_RANGE, "optimizer: edges per iteration, evaluations per dimension or "
                                   "edges in flight out of range");
    }
    o->attrs = o->params.attrs & (LM_ATTR_NORMAL | (mesh->attrs & (LM_ATTR_UV | LM_ATTR_COLOR)));
    lm_rng_seed(&o->rng, o->params.seed);
    lm_move_stats_init(&o->stats, o->tuning.stats_half_life, o->tuning.stats_min_weight);
    lm_oracle_init(&o->oracle);
    o->oracle.share = o->tuning.oracle_share;
    o->oracle.min_share = o->tuning.oracle_min_share;
    o->oracle.max_share = o->tuning.oracle_max_share;
    o->oracle.max_age = o->tuning.oracle_max_age;
    lm_idset_init(&o->it.touched);
    lm_status st = create_parts(o);
    if (st) {
        lm_optimizer_destroy(o);
        return st;
    }
    *out = o;
    return LM_OK;
}

void lm_optimizer_destroy(lm_optimizer *opt)
{
    if (!opt)
        return;
    lm_lanes_destroy(opt->lanes);
    lm_moves_destroy(opt->mv);
    lm_teleport_free(&opt->tp);
    lm_oracle_free(&opt->oracle);
    free(opt->it.plan);
    free(opt->it.no_progress);
    free(opt->totals);
    lm_idset_free(&opt->it.touched);
    lm_views_destroy(opt->surface);
    lm_mesh_destroy(opt->mesh);
    free(opt);
}

/* The new views where everything that prices moves holds them: the geometric term's wrapper, or
 * the moves and the lanes themselves. */
static lm_status install_views(lm_optimizer *o, lm_views *views)
{
    if (o->surface)
        return lm_surface_views_set_inner(o->surface, views);
    o->views = views;
    lm_moves_set_views(o->mv, views);
    if (o->lanes)
        lm_lanes_set_views(o->lanes, views);
    return LM_OK;
}

lm_status lm_optimizer_replace_views(lm_optimizer *opt, lm_views *views, int rescale_start)
{
    if (!views)
        return lm_fail(LM_E_INVALID, "optimizer: views are required");
    int64_t geo = opt->surface ? lm_surface_views_energy(opt->surface) : 0;
    double k = opt->surface ? lm_surface_views_scale(opt->surface) : 0;
    int64_t old_image = opt->prog.energy - geo;
    int64_t total = 0;
    lm_status st = install_views(opt, views);
    if (st == LM_OK)
        st = lm_views_set_mesh_from(opt->views, opt->mesh);
    if (st != LM_OK || !rescale_start)
        return st;
    st = opt->views->ops->energy(opt->views, &total, NULL);
    if (st != LM_OK)
        return st;
    int64_t start_image = opt->prog.energy_start - opt->prog.geometric_start;
    int64_t new_geo = opt->surface ? lm_surface_views_energy(opt->surface) : 0;
    int64_t new_image = total - new_geo;
    if (old_image > 0)
        start_image = llround((double)start_image * ((double)new_image / (double)old_image));
    double new_k = opt->surface ? lm_surface_views_scale(opt->surface) : 0;
    if (k > 0 && new_k != k) /* the term's scale went with the views' (surface_term.h) */
        opt->prog.geometric_start = llround((double)opt->prog.geometric_start * (new_k / k));
    opt->prog.energy_start = start_image + opt->prog.geometric_start;
    opt->prog.energy = total;
    return LM_OK;
}

const lm_mesh *lm_optimizer_mesh(const lm_optimizer *opt)
{
    return opt->mesh;
}

void lm_optimizer_progress(const lm_optimizer *opt, lm_progress *out)
{
    *out = opt->prog;
    /* prog counts the sum the moves minimise; callers see the image energy and the term apart */
    out->geometric = opt->surface ? lm_surface_views_energy(opt->surface) : 0;
    out->geometric_by_workers = opt->surface ? lm_surface_views_worker_share(opt->surface) : 0;
    out->energy = opt->prog.energy - out->geometric;
    out->energy_start = opt->prog.energy_start - opt->prog.geometric_start;
    out->evals = lm_moves_evals(opt->mv);
    out->live_verts = opt->mesh->live_verts;
    out->live_tris = opt->mesh->live_tris;
}

/* ---- iterations (paper §5.4) ----------------------------------------------------------------- */

static lm_status begin_iteration(lm_optimizer *o)
{
    lm_iteration *it = &o->it;
    uint32_t(*edges)[2];
    size_t n;
    lm_status st = lm_mesh_list_edges(o->mesh, &edges, &n);
    if (st)
        return st;
    lm_ranked_edge *ranked = NULL;
    if (n)
        st = lm_oracle_rank(o->views, o->mesh, (const uint32_t(*)[2])edges, n, &ranked);
    free(edges);
    it->n_plan = 0;
    if (!st && n)
        st = lm_oracle_plan(&o->oracle, ranked, n, &o->rng, o->params.edges_per_iteration, it->plan,
                            &it->n_plan);
    free(ranked);
    it->pos = 0;
    it->gain[0] = it->gain[1] = 0;
    it->count[0] = it->count[1] = 0;
    it->n_no_progress = 0;
    it->active = !st;
    return st;
}

/* Debug log: the statistics behind Inequality 3, once per iteration. */
static void log_stats(const lm_optimizer *o)
{
    if (lm_log_get_level() < LM_LOG_DEBUG)
        return;
    static const char *names[LM_MOVE_KINDS] = {"noop", "swap", "tele", "coll"};
    uint64_t now = lm_moves_evals(o->mv);
    for (int k = 0; k < LM_MOVE_KINDS; k++)
        for (int l = 0; l < LM_LEVELS; l++) {
            lm_stat_view v;
            lm_stat_get(&o->stats.op[k][l], now, o->stats.half_life, &v);
            if (o->stats.op[k][l].count)
                lm_debug("stats %s%d: n %llu f %.2f dE %.0f sd %.0f t %.1f eff %.2f", names[k], l,
                         (unsigned long long)o->stats.op[k][l].count, v.f, v.mean, v.sigma, v.t,
                         v.mean / (v.t > 0 ? v.t : 1));
        }
    lm_debug("iteration %llu: share %.2f gain oracle %.0f/%u random %.0f/%u threshold %lld "
             "searches %llu failed %llu",
             (unsigned long long)o->prog.iterations, o->oracle.share, o->it.gain[1], o->it.count[1],
             o->it.gain[0], o->it.count[0], (long long)lm_teleport_threshold(&o->tp, now),
             (unsigned long long)o->tp.searches, (unsigned long long)o->tp.searches_failed);
}

static int touched_vertex(const void *ctx, uint32_t v)
{
    return lm_idset_has((const lm_idset *)ctx, v);
}

static lm_status end_iteration(lm_optimizer *o)
{
    lm_iteration *it = &o->it;
    log_stats(o);
    it->active = 0;
    lm_oracle_balance(&o->oracle, it->gain[1], it->count[1], it->gain[0], it->count[0]);
    lm_status st = lm_oracle_update_stale(&o->oracle, o->prog.iterations, it->no_progress,
                                          it->n_no_progress, touched_vertex, &it->touched);
    o->prog.iterations++;
    lm_idset_clear(&it->touched);
    return st;
}

/* The iteration's bookkeeping for planned edge e, whose operations committed `total`. */
static void edge_done(lm_iteration *it, const lm_planned_edge *e, int64_t total)
{
    int src = e->from_oracle ? 1 : 0;
    it->gain[src] += (double)-total;
    it->count[src]++;
    if (total >= 0)
        it->no_progress[it->n_no_progress++] = lm_edge_key(e->a, e->b);
}

void lm_optimizer_set_lane_order(lm_optimizer *opt, uint64_t order)
{
    if (opt->lanes)
        lm_lanes_set_run_order(opt->lanes, order);
}

lm_status lm_optimizer_set_lanes_detached(lm_optimizer *opt, int on)
{
    return opt->lanes ? lm_lanes_set_detached(opt->lanes, on) : LM_OK;
}

void lm_optimizer_set_lane_runner(lm_optimizer *opt, const lm_lane_runner *runner)
{
    if (opt->lanes)
        lm_lanes_set_runner(opt->lanes, runner);
}

void lm_optimizer_lane_traffic(const lm_optimizer *opt, lm_lane_traffic *traffic)
{
    memset(traffic, 0, sizeof *traffic);
    if (opt->lanes)
        lm_lanes_traffic(opt->lanes, traffic);
}

/* The next planned edges: one on the optimizer's mesh, or a group in flight in the lanes. */
static lm_status next_edges(lm_optimizer *opt)
{
    lm_iteration *it = &opt->it;
    lm_planned_edge *e = &it->plan[it->pos];
    int64_t *totals = opt->totals;
    uint32_t n = 1;
    lm_status st;
    if (opt->lanes) {
        n = lm_lanes_group(opt->lanes, e, it->n_plan - it->pos);
        lm_debug("edges in flight: a group of %u", n);
        st = lm_lanes_run(opt->lanes, e, n, totals);
    } else {
        lm_edge_ctx c = {.o = opt, .mesh = opt->mesh, .mv = opt->mv};
        st = lm_edge_optimise(&c, e->a, e->b, &totals[0]);
    }
    for (uint32_t i = 0; i < n && st == LM_OK; i++)
        edge_done(it, &e[i], totals[i]);
    if (st == LM_OK)
        it->pos += n;
    return st;
}

lm_status lm_optimizer_step(lm_optimizer *opt, uint64_t max_evals)
{
    lm_iteration *it = &opt->it;
    lm_status st = LM_OK;
    if (lm_moves_evals(opt->mv) >= max_evals)
        return LM_OK;
    if (!it->active && (st = begin_iteration(opt)))
        return st;
    while (it->pos < it->n_plan) {
        if (lm_moves_evals(opt->mv) >= max_evals)
            return LM_OK;
        if ((st = next_edges(opt)))
            return st;
    }
    return end_iteration(opt);
}
