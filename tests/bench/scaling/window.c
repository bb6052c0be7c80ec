/* tests/bench/scaling/window.c — the whole-edge schedule without a barrier (the window), on nodes
 * of co-located processes: the model, simulated edge by edge from the measured edges.
 *
 * Edge i (plan order) is optimised against the mesh with every edge <= i - D merged, for a fixed
 * lag D: the output depends on D, never on the workers. The pass modelled: the measured edges,
 * cycled to at least one pass over the start's edges, as visits (visits.c): with --cap N an
 * edge's optimisation is cut into visits of at most N evaluations, each continuation D or more
 * positions after the visit before it; below, "edge" is a visit. W processes form W / g nodes of
 * g = min(G, W) processes; a node holds every view once, over shared memory, its processes a
 * share s = ceil(V / g) / V of them each. Per edge e (measured one at a time, edge_costs.c):
 *     t_e = (views_e + evals_e g_term) * s + (cost_e - views_e - evals_e g_term)
 *          + [g > 1] evals_e * sync
 * (the views' work and the geometric term split, as local workers split them today, each its
 * views and a share of the triangles; the simplex and moves on one process; a barrier of the
 * node's processes per evaluation: sync, by default this machine's local-worker link round trip).
 * In plan order each edge goes to the node free first; it starts at
 *     max(node free, plan ready, merged_{i-D} + RTT/2 + b_{i-D} / bandwidth) + apply
 * where apply = the commits of edges <= i - D the node has not applied yet, sum apply_e * s (a
 * node applies every commit once, each process its share of the views). An iteration's plan
 * (edge i with oracle requests) is made one iteration ahead: when the previous iteration, from
 * edge p, begins, against p's snapshot (as soon as edge p - D is merged): the potentials on the
 * node free first (pot_e * s), a round trip per request and the coordinator's ranking (plan_e);
 * no edge from i on starts before it is ready. A result reaches the coordinator RTT/2 +
 * b_e / bandwidth after the edge ends. Merges go strictly in plan order:
 *     merged_i = max(merged_{i-1}, result_i + [r_i] RTT) + [r_i] reval + merge_e
 * r_i: the edge kept operations and its footprint meets that of one of the edges i - D + 1 ..
 * i - 1 it did not see (edge_rec.near < D); its operations are then re-evaluated, as one
 * evaluation of their merged patch, on a worker node (the one that ran it: it is charged there)
 * holding the merged state, reval = V c s + g_term + [g > 1] sync; the round trip to it is
 * latency on that edge's merge, the evaluation itself in the merge's serial order. The
 * coordinator holds no views: its CPU is the planning and the merges (replay, patch, encoding),
 * printed per evaluation. The pass ends at the last merge, or later if the coordinator's link
 * (every commit to every node, 16 bytes an edge out) or its CPU take longer. In process:
 * sum (cost_e + plan_e + pot_e). Not modelled: that a lagged edge accepts other operations than
 * the one-at-a-time run measured, screen-space overlap between edges (footprints are
 * topological), taking edges out of plan order. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/error.h"
#include "scaling.h"

typedef struct sim {
    double rtt, bw, share, sync, reval_s, geo;
    uint32_t d, g;
    size_t pass;       /* visits modelled (visits.c): the measured edges, cycled, cut by --cap */
    const edge_rec *v; /* the visits in plan order */
    double *free_at;   /* per node: when it is free */
    size_t *applied;   /* per node: commits of edges before this one applied */
    double *merged;    /* per edge: when its merge is done */
    double *apply_at;  /* prefix sums of apply_e (apply_at[i]: edges before i) */
} sim;

static double max2(double a, double b)
{
    return a > b ? a : b;
}

static uint32_t first_free(const sim *s, uint32_t nodes)
{
    uint32_t k = 0;
    for (uint32_t j = 1; j < nodes; j++)
        k = s->free_at[j] < s->free_at[k] ? j : k;
    return k;
}

/* The edge's time on a node of g processes: the views' work and the geometric term split. */
static double edge_time(const sim *s, const edge_rec *e, window *out)
{
    double sync = s->g > 1 ? e->evals * s->sync : 0, split = e->views_s + e->evals * s->geo;
    split = split < e->cost_s ? split : e->cost_s;
    out->sync += sync;
    return split * s->share + (e->cost_s - split) + sync;
}

/* Edge i to the node free first: when it starts there (the window, the plan, the commits). */
static double start_edge(sim *s, size_t i, uint32_t k, double plan_ready, window *out)
{
    double t = s->free_at[k], ready = plan_ready;
    if (ready > t)
        out->wait_plan += ready - t, t = ready;
    if (i >= s->d) {
        double in = s->merged[i - s->d] + s->rtt / 2 + s->v[i - s->d].bytes / s->bw;
        if (in > t)
            out->wait_window += in - t, t = in;
    }
    size_t upto = i >= s->d ? i - s->d + 1 : 0; /* commits of the edges before upto */
    if (upto > s->applied[k]) {
        double a = (s->apply_at[upto] - s->apply_at[s->applied[k]]) * s->share;
        out->apply += a, t += a;
        s->applied[k] = upto;
    }
    return t;
}

/* Edge i begins an iteration: its plan, made one iteration ahead (when the previous iteration,
 * from edge `prev`, begins), against prev's snapshot, the potentials by the node free first; when
 * it is ready. */
static double plan_ahead(sim *s, size_t i, size_t prev, uint32_t nodes, window *out)
{
    const edge_rec *e = &s->v[i];
    uint32_t k = first_free(s, nodes);
    double snap = prev >= s->d ? s->merged[prev - s->d] + s->rtt / 2 : 0, t = s->free_at[k];
    if (snap > t)
        out->wait_window += snap - t, t = snap;
    double pot = e->pot_s * s->share;
    s->free_at[k] = t + pot;
    out->wait_plan += pot;
    return t + pot + e->plans * s->rtt + e->plan_s;
}

static void run_sim(sim *s, uint32_t nodes, window *out)
{
    double plan_ready = 0, next_ready = 0, last_merge = 0;
    int planned = 0; /* the first iteration's plan made */
    for (size_t i = 0; i < s->pass; i++) {
        const edge_rec *e = &s->v[i];
        if (e->plans) { /* this iteration's plan is ready then; the next one's is begun */
            plan_ready = planned ? next_ready : plan_ahead(s, i, i, nodes, out);
            planned = 1;
            size_t j = i + 1;
            while (j < s->pass && !s->v[j].plans)
                j++;
            if (j < s->pass)
                next_ready = plan_ahead(s, j, i, nodes, out);
        }
        uint32_t k = first_free(s, nodes);
        double t = start_edge(s, i, k, plan_ready, out), run = edge_time(s, e, out);
        s->free_at[k] = t + run;
        out->work += run;
        double result = t + run + s->rtt / 2 + e->bytes / s->bw;
        int reval = e->ops && e->near && e->near < s->d;
        double m = max2(last_merge, result + (reval ? s->rtt : 0));
        if (reval) {
            m += s->reval_s;
            s->free_at[k] += s->reval_s;
            out->reval += s->reval_s;
            out->revalidated += 1;
        }
        s->merged[i] = last_merge = m + e->merge_s;
        out->t1 += e->cost_s + e->plan_s + e->pot_s;
        out->coord_s += e->plan_s + e->merge_s;
        out->evals += e->evals + reval;
        out->with_ops += e->ops > 0;
    }
    out->tw = last_merge;
    for (uint32_t k = 0; k < nodes; k++)
        out->tail += max2(0, last_merge - s->free_at[k]);
}

window sc_window_at(const opts *o, const edges_run *er, uint32_t views, uint32_t w, uint32_t d,
                    uint32_t group, double sync_us, uint32_t cap)
{
    window out;
    memset(&out, 0, sizeof out);
    visits vs;
    sc_visits_make(er, cap, d ? d : 1, &vs);
    uint32_t g = group < w ? group : w, nodes = w / g ? w / g : 1;
    sim s = {.rtt = o->rtt_us * 1e-6,
             .bw = o->gbps * 1e9 / 8.0,
             .share = ceil((double)views / g) / views,
             .sync = sync_us * 1e-6,
             .geo = er->geo_us_per_eval * 1e-6,
             .d = d ? d : 1,
             .g = g,
             .pass = vs.n,
             .v = vs.v};
    s.reval_s = views * er->per_patch_view_us * 1e-6 * s.share + er->geo_us_per_eval * 1e-6 +
                (g > 1 ? s.sync : 0);
    s.free_at = calloc(nodes, sizeof *s.free_at);
    s.applied = calloc(nodes, sizeof *s.applied);
    s.merged = calloc(s.pass, sizeof *s.merged);
    s.apply_at = calloc(s.pass + 1, sizeof *s.apply_at);
    LM_ASSERT(s.free_at && s.applied && s.merged && s.apply_at);
    double bytes = 0;
    for (size_t i = 0; i < s.pass; i++) {
        s.apply_at[i + 1] = s.apply_at[i] + vs.v[i].apply_s;
        bytes += vs.v[i].bytes;
    }
    run_sim(&s, nodes, &out);
    out.link_s = (nodes * bytes + 16.0 * (double)s.pass) / s.bw;
    out.tw = max2(max2(out.tw, out.link_s), out.coord_s);
    out.nodes = nodes, out.per = g;
    out.visits = (double)vs.n, out.edges = (double)vs.started, out.restarts = vs.restarts;
    free(s.free_at), free(s.applied), free(s.merged), free(s.apply_at);
    sc_visits_free(&vs);
    return out;
}
