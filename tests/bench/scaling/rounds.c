/* tests/bench/scaling/rounds.c — the whole-edge schedule in rounds (issue 36): a worker holding
 * all V views optimises whole edges against the round's start; the coordinator merges them in
 * plan order, re-validates as one batch, and every worker applies every commit.
 *
 * The measured sequence, cycled to whole rounds, is cut into rounds of R planned edges; round j,
 * its k_j = (edges that kept operations) - 1 re-validations (the first merge needs none), on W
 * workers:
 *     T_j(W) = sum plan_e + P_j * RTT + sum pot_e / min(W, V)               planning
 *            + RTT + (W * B_{j-1} + 16 R) / bandwidth                       handing out
 *            + A_{j-1}                                                      the last commits
 *            + makespan_W + B_j / bandwidth                                 the edges
 *            + sum merge_e                                                  merging
 *            + [k_j > 0] (RTT + k_j (V c + g) / min(W, k_j V)
 *                         + B_j * min(W, V) / bandwidth)                    re-validating
 * with P_j the potentials requests, B_j = sum b_e, A_j = sum apply_e (round j - 1 of the cycle
 * before the first), makespan_W the list schedule of the cost_e in plan order (each to the worker
 * free first), c the cost per (patch, view) and g the geometric term per evaluation of this run;
 * in process sum (cost_e + plan_e + pot_e). Speed-up = sum in process / sum T_j(W), efficiency =
 * speed-up / W; the coordinator's CPU per evaluation = sum (plan_e + merge_e) / (evaluations +
 * re-validations). Printed for rounds of 64, --round (default 256) and 1024 edges, where the time
 * of 16 and 128 workers goes at --round, and the smallest round (a power of 2, at most 65536)
 * that reaches efficiency 0.8 on 16 workers and 0.6 on 128 (with the efficiencies at 65536).
 */
#include <stdlib.h>
#include <string.h>

#include "scaling.h"

/* One round's sums over its edges. */
typedef struct round_sums {
    double cost, plan, pot, apply, merge, bytes, evals, plans, with_ops;
} round_sums;

static round_sums round_of(const edges_run *er, size_t first, size_t count)
{
    round_sums s = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (size_t i = first; i < first + count; i++) {
        const edge_rec *e = sc_pass_edge(er, i);
        s.cost += e->cost_s, s.plan += e->plan_s, s.pot += e->pot_s, s.apply += e->apply_s;
        s.merge += e->merge_s, s.bytes += e->bytes, s.evals += e->evals, s.plans += e->plans;
        s.with_ops += e->ops > 0;
    }
    return s;
}

/* The workers' makespan of a round: its edges in plan order, each to the worker free first. */
static double makespan(const edges_run *er, size_t first, size_t count, uint32_t w, double *free_at)
{
    double end = 0;
    for (uint32_t k = 0; k < w; k++)
        free_at[k] = 0;
    for (size_t i = first; i < first + count; i++) {
        uint32_t next = 0;
        for (uint32_t k = 1; k < w; k++)
            next = free_at[k] < free_at[next] ? k : next;
        free_at[next] += sc_pass_edge(er, i)->cost_s;
        end = free_at[next] > end ? free_at[next] : end;
    }
    return end;
}

/* The pass as rounds of r edges on w workers over V views (the formula at the top). */
whole_edges sc_rounds_at(const opts *o, const edges_run *er, uint32_t views, uint32_t w, uint32_t r)
{
    double rtt = o->rtt_us * 1e-6, bw = o->gbps * 1e9 / 8.0, ranges = w < views ? w : views;
    double per_patch = views * er->per_patch_view_us * 1e-6 + er->geo_us_per_eval * 1e-6;
    size_t rounds = (er->n + r - 1) / r;
    double *free_at = calloc(w, sizeof *free_at);
    whole_edges out;
    memset(&out, 0, sizeof out);
    LM_ASSERT(free_at);
    round_sums prev = round_of(er, (rounds - 1) * r, r); /* steady state: the pass cycles */
    for (size_t j = 0; j < rounds; j++) {
        round_sums s = round_of(er, j * r, r);
        double k = s.with_ops > 1 ? s.with_ops - 1 : 0; /* re-validations */
        double pieces = w < k * views ? w : k * views;
        double plan = s.plan + s.plans * rtt + s.pot / ranges;
        double hand_out = rtt + (w * prev.bytes + 16.0 * r) / bw;
        double edges = makespan(er, j * r, r, w, free_at) + s.bytes / bw;
        double revalidate = k ? rtt + k * per_patch / pieces + s.bytes * ranges / bw : 0;
        out.t1 += s.cost + s.plan + s.pot;
        out.tw += plan + hand_out + prev.apply + edges + s.merge + revalidate;
        out.plan += plan, out.hand_out += hand_out, out.apply += prev.apply, out.edges += edges;
        out.merge += s.merge, out.revalidate += revalidate, out.balanced += s.cost / w;
        out.plan_s += s.plan;
        out.merge_s += s.merge;
        out.evals += s.evals + k;
        prev = s;
    }
    free(free_at);
    return out;
}

double sc_rounds_speedup(const opts *o, const edges_run *er, uint32_t views, uint32_t w, uint32_t r)
{
    whole_edges x = sc_rounds_at(o, er, views, w, r);
    return x.t1 / x.tw;
}

uint32_t sc_round_for(const opts *o, const edges_run *er, uint32_t views, uint32_t w, double eff)
{
    for (uint32_t r = 1; r <= 65536; r *= 2)
        if (sc_rounds_speedup(o, er, views, w, r) / w >= eff)
            return r;
    return 0;
}

uint32_t sc_report_rounds(const opts *o, uint32_t out[3])
{
    uint32_t c[3] = {64, o->round, 1024}, n = 0;
    for (int i = 0; i < 3; i++) {
        uint32_t least = 0;
        for (int k = 0; k < 3; k++)
            if (c[k] && (!least || c[k] < least))
                least = c[k];
        if (!least)
            break;
        out[n++] = least;
        for (int k = 0; k < 3; k++)
            c[k] = c[k] == least ? 0 : c[k];
    }
    return n;
}
