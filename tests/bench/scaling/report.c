/* tests/bench/scaling/report.c — bench_scaling's report, for people and as --json: the
 * per-evaluation runs' costs and predictions, the measured edges, the rounds model and, with
 * --schedule window, the window model over lags and node sizes. Per modelled worker count the
 * speed-up and the efficiency, and the coordinator's CPU per evaluation. */
#include <stdio.h>
#include <string.h>

#include "scaling.h"

static const uint32_t workers[] = {1, 2, 4, 8, 16, 128};
#define N_W (sizeof workers / sizeof *workers)

static void print_whole_edges_human(const opts *o, const edges_run *er, uint32_t views);
static void print_whole_edges_json(const opts *o, const edges_run *er, uint32_t views);
static void print_window_human(const opts *o, const edges_run *er, uint32_t views, double sync);
static void print_window_json(const opts *o, const edges_run *er, uint32_t views, double sync);
static void print_capped_human(const opts *o, const edges_run *er, uint32_t views, double sync);
static void print_capped_json(const opts *o, const edges_run *er, uint32_t views, double sync);

/* A node's synchronisation per evaluation: --sync-us, else a local worker's link round trip. */
static double sync_us(const opts *o, const rtts *t)
{
    return o->sync_us >= 0 ? o->sync_us : t->link;
}

/* --cap given: the window over every (N, D, G) of the lists. */
static int capped(const opts *o)
{
    return o->n_caps > 1 || o->caps[0] > 0;
}

void sc_print_human(const opts *o, const costs *c, uint32_t views, const rtts *t,
                    const edges_run *er)
{
    printf(
        "bench scaling: %s, %u views of %u px, %llu evaluations per run; round trip here "
        "(small request) %.0f us over a local worker's link (%.0f us with both on one core), "
        "%.0f us over ZeroMQ ipc, %.0f us over a plain Unix socket, asleep between (the floor)\n",
        o->model, views, o->size, (unsigned long long)o->evals, t->link, t->link_one_core, t->zmq,
        t->floor);
    for (int r = 0; r < 2; r++) {
        const costs *x = &c[r];
        printf(
            "  %u in flight: %.1f us per (patch, view); coordinator %.1f us per evaluation in "
            "process (%.1f of it the geometric term, which workers can price) and %.1f us of the "
            "views' commits and oracle, which workers do; %.1f patches and "
            "%.0f bytes per batch (%.0f per commit); %.1f triangles a patch, %.0f%% of them "
            "moved; the optimizer's set-up %.2f s, once\n",
            x->k, x->per_patch_view_us, x->coord_us_per_eval, x->overlap_us_per_eval,
            x->state_us_per_eval, x->patches_per_batch, x->bytes_per_batch, x->commit_bytes,
            x->tris_per_patch, 100.0 * x->moved_share, x->setup_s);
        printf("    predicted at %.0f us RTT, %.0f Gb/s:", o->rtt_us, o->gbps);
        for (size_t i = 0; i < N_W; i++) {
            double s = sc_speedup(o, x, views, workers[i]);
            printf(" %u: x%.1f (%.0f%%)", workers[i], s, 100.0 * s / workers[i]);
        }
        printf("\n    2 workers at best on this machine: x%.2f over links, x%.2f over ZeroMQ, "
               "x%.2f at the floor\n",
               sc_speedup_at(o, x, views, 2, t->link), sc_speedup_at(o, x, views, 2, t->zmq),
               sc_speedup_at(o, x, views, 2, t->floor));
    }
    print_whole_edges_human(o, er, views);
    if (o->schedule == SCHEDULE_WINDOW)
        print_window_human(o, er, views, sync_us(o, t));
    if (o->schedule == SCHEDULE_WINDOW && capped(o))
        print_capped_human(o, er, views, sync_us(o, t));
}

void sc_print_json(const opts *o, const costs *c, uint32_t views, const rtts *t,
                   const edges_run *er)
{
    printf("{\"bench\": \"scaling\", \"model\": \"%s\", \"views\": %u, \"size\": %u, "
           "\"evals\": %llu, \"rtt_here_us\": %.1f, \"rtt_one_core_us\": %.1f, \"zmq_rtt_us\": "
           "%.1f, \"floor_rtt_us\": %.1f, \"model_rtt_us\": %.1f, \"model_gbps\": %.1f, "
           "\"runs\": [",
           o->model, views, o->size, (unsigned long long)o->evals, t->link, t->link_one_core,
           t->zmq, t->floor, o->rtt_us, o->gbps);
    for (int r = 0; r < 2; r++) {
        const costs *x = &c[r];
        printf("%s{\"edges_in_flight\": %u, \"us_per_patch_view\": %.3f, "
               "\"coordinator_us_per_eval\": %.3f, \"geometric_us_per_eval\": %.3f, "
               "\"patches_per_batch\": %.3f, "
               "\"bytes_per_batch\": %.1f, \"bytes_per_commit\": %.1f, "
               "\"tris_per_patch\": %.2f, \"moved_share\": %.3f, \"state_us_per_eval\": %.3f, "
               "\"two_workers_here\": %.3f, \"two_workers_zmq\": %.3f, "
               "\"two_workers_floor\": %.3f, \"predicted\": [",
               r ? ", " : "", x->k, x->per_patch_view_us, x->coord_us_per_eval,
               x->overlap_us_per_eval, x->patches_per_batch, x->bytes_per_batch, x->commit_bytes,
               x->tris_per_patch, x->moved_share, x->state_us_per_eval,
               sc_speedup_at(o, x, views, 2, t->link), sc_speedup_at(o, x, views, 2, t->zmq),
               sc_speedup_at(o, x, views, 2, t->floor));
        for (size_t i = 0; i < N_W; i++) {
            double s = sc_speedup(o, x, views, workers[i]);
            printf("%s{\"workers\": %u, \"speedup\": %.3f, \"efficiency\": %.3f}", i ? ", " : "",
                   workers[i], s, s / workers[i]);
        }
        printf("]}");
    }
    printf("]");
    print_whole_edges_json(o, er, views);
    if (o->schedule == SCHEDULE_WINDOW)
        print_window_json(o, er, views, sync_us(o, t));
    if (o->schedule == SCHEDULE_WINDOW && capped(o))
        print_capped_json(o, er, views, sync_us(o, t));
    printf("}\n");
}

static void print_whole_edges_human(const opts *o, const edges_run *er, uint32_t views)
{
    edge_stats s = sc_edge_stats(er);
    whole_edges at = sc_rounds_at(o, er, views, 1, o->round);
    printf("  whole edges: %zu edges optimised one at a time over %llu evaluations (%llu planned, "
           "the others gone before their turn; the start has %zu edges): evaluations per edge "
           "mean %.1f, median %.0f, 90th percentile %.0f, 99th %.0f, max %.0f; one edge in "
           "process %.2f ms mean, %.2f ms max, the costliest 1%% of the edges %.0f%% of the work "
           "(%.1f us per (patch, view), the views %.2f CPU seconds a second: under 1, a busy "
           "machine); %.2f operations kept per edge, %.0f%% of the edges keep "
           "some, %.0f bytes of commits each; %llu operations replayed at %.1f us each (%llu "
           "mismatches)\n",
           er->n, (unsigned long long)er->evals, (unsigned long long)er->planned, er->mesh_edges,
           s.evals_mean, s.evals_median, s.evals_p90, s.evals_p99, s.evals_max, s.ms_mean, s.ms_max,
           100.0 * s.top_share, er->per_patch_view_us, er->views_cpu_per_wall, s.ops_mean,
           100.0 * s.with_ops, s.bytes_mean, (unsigned long long)er->replays,
           er->replays ? 1e6 * er->replay_s / (double)er->replays : 0,
           (unsigned long long)er->mismatches);
    printf(
        "    coordinator CPU per evaluation %.2f us (planning %.2f, merges %.2f), rounds of %u\n",
        1e6 * (at.plan_s + at.merge_s) / at.evals, 1e6 * at.plan_s / at.evals,
        1e6 * at.merge_s / at.evals, o->round);
    uint32_t rs[3], nr = sc_report_rounds(o, rs);
    for (uint32_t k = 0; k < nr; k++) {
        printf("    rounds of %u edges, predicted at %.0f us RTT, %.0f Gb/s:", rs[k], o->rtt_us,
               o->gbps);
        for (size_t i = 0; i < N_W; i++) {
            double x = sc_rounds_speedup(o, er, views, workers[i], rs[k]);
            printf(" %u: x%.1f (%.0f%%)", workers[i], x, 100.0 * x / workers[i]);
        }
        printf("\n");
    }
    for (uint32_t w = 16; w <= 128; w *= 8) {
        whole_edges x = sc_rounds_at(o, er, views, w, o->round);
        printf("    where the time of %u workers goes, rounds of %u: the edges %.0f%% (spread "
               "perfectly %.0f%%), applying the last round's commits %.0f%%, planning %.0f%%, "
               "handing out %.0f%%, merging %.0f%%, re-validating %.0f%%\n",
               w, o->round, 100 * x.edges / x.tw, 100 * x.balanced / x.tw, 100 * x.apply / x.tw,
               100 * x.plan / x.tw, 100 * x.hand_out / x.tw, 100 * x.merge / x.tw,
               100 * x.revalidate / x.tw);
    }
    uint32_t r16 = sc_round_for(o, er, views, 16, 0.8), r128 = sc_round_for(o, er, views, 128, 0.6);
    printf("    smallest round (a power of 2) for efficiency >= 0.8 on 16 workers: %u; >= 0.6 on "
           "128 workers: %u (0: none up to 65536; there, 16 workers %.0f%%, 128 workers %.0f%%)\n",
           r16, r128, 100 * sc_rounds_speedup(o, er, views, 16, 65536) / 16,
           100 * sc_rounds_speedup(o, er, views, 128, 65536) / 128);
}

static void print_whole_edges_json(const opts *o, const edges_run *er, uint32_t views)
{
    edge_stats s = sc_edge_stats(er);
    whole_edges at = sc_rounds_at(o, er, views, 1, o->round);
    printf(", \"round\": %u, \"coordinator_cpu_per_eval_us\": %.3f, \"whole_edge_costs\": "
           "{\"edges\": %zu, \"planned_edges\": %llu, \"evals\": %llu, \"mesh_edges\": %zu, "
           "\"evals_per_edge_mean\": %.1f, \"evals_per_edge_median\": %.0f, "
           "\"evals_per_edge_p90\": %.0f, \"evals_per_edge_p99\": %.0f, "
           "\"evals_per_edge_max\": %.0f, \"edge_ms_mean\": %.3f, \"edge_ms_max\": %.3f, "
           "\"costliest_1pc_share\": %.3f, \"views_cpu_per_wall\": %.2f, "
           "\"us_per_patch_view\": %.3f, \"ops_per_edge_mean\": %.3f, \"share_with_ops\": %.3f, "
           "\"commit_bytes_per_edge\": %.1f, \"replay_us_per_op\": %.2f, \"replay_mismatches\": "
           "%llu, \"planning_us_per_eval\": %.3f, \"merge_us_per_eval\": %.3f}, \"whole_edges\": [",
           o->round, 1e6 * (at.plan_s + at.merge_s) / at.evals, er->n,
           (unsigned long long)er->planned, (unsigned long long)er->evals, er->mesh_edges,
           s.evals_mean, s.evals_median, s.evals_p90, s.evals_p99, s.evals_max, s.ms_mean, s.ms_max,
           s.top_share, er->views_cpu_per_wall, er->per_patch_view_us, s.ops_mean, s.with_ops,
           s.bytes_mean, er->replays ? 1e6 * er->replay_s / (double)er->replays : 0,
           (unsigned long long)er->mismatches, 1e6 * at.plan_s / at.evals,
           1e6 * at.merge_s / at.evals);
    uint32_t rs[3], nr = sc_report_rounds(o, rs);
    for (uint32_t k = 0; k < nr; k++)
        for (size_t i = 0; i < N_W; i++) {
            whole_edges x = sc_rounds_at(o, er, views, workers[i], rs[k]);
            printf("%s{\"round\": %u, \"workers\": %u, \"speedup\": %.3f, \"efficiency\": %.3f, "
                   "\"coordinator_cpu_per_eval_us\": %.3f}",
                   k || i ? ", " : "", rs[k], workers[i], x.t1 / x.tw, x.t1 / x.tw / workers[i],
                   1e6 * (x.plan_s + x.merge_s) / x.evals);
        }
    printf("], \"round_for_efficiency_0_8_at_16\": %u, \"round_for_efficiency_0_6_at_128\": %u, "
           "\"efficiency_at_round_65536\": [%.3f, %.3f]",
           sc_round_for(o, er, views, 16, 0.8), sc_round_for(o, er, views, 128, 0.6),
           sc_rounds_speedup(o, er, views, 16, 65536) / 16,
           sc_rounds_speedup(o, er, views, 128, 65536) / 128);
}

/* ---- the window ------------------------------------------------------------------------------ */

static const uint32_t lags[] = {64, 128, 256, 512, 1024, 2048, 4096};
#define N_LAGS (sizeof lags / sizeof *lags)
static const uint32_t groups[] = {1, 4, 16};
#define N_GROUPS (sizeof groups / sizeof *groups)

static double coord_us(const window *x)
{
    return 1e6 * x->coord_s / x->evals;
}

static double eff(const window *x, uint32_t w)
{
    return x->t1 / x->tw / w;
}

/* The smallest lag (a power of 2, at most 65536) with efficiency >= e on w processes in nodes of
 * g; 0 if none. */
static uint32_t lag_for(const opts *o, const edges_run *er, uint32_t views, uint32_t w, uint32_t g,
                        double sync, double e)
{
    for (uint32_t d = 1; d <= 65536; d *= 2) {
        window x = sc_window_at(o, er, views, w, d, g, sync, 0);
        if (eff(&x, w) >= e)
            return d;
    }
    return 0;
}

/* With cap (not 0) the line begins with it. */
static void print_window_where(const window *x, uint32_t cap, uint32_t lag, uint32_t w)
{
    double all = x->nodes * x->tw / 100;
    if (cap)
        printf("    cap %u,", cap);
    printf(
        "%slag %u, where the time of %u processes (%u nodes of %u) goes: the edges %.0f%% (of it "
        "synchronisation %.0f%%), applying others' commits %.0f%%, re-validating %.0f%%, "
        "waiting for the window %.0f%%, planning %.0f%%, idle at the end %.0f%%; the "
        "coordinator's CPU %.0f%% busy, its link %.0f%%\n",
        cap ? " " : "    ", lag, w, x->nodes, x->per, x->work / all, x->sync / all, x->apply / all,
        x->reval / all, x->wait_window / all, x->wait_plan / all, x->tail / all,
        100 * x->coord_s / x->tw, 100 * x->link_s / x->tw);
}

static void print_window_human(const opts *o, const edges_run *er, uint32_t views, double sync)
{
    window at = sc_window_at(o, er, views, 1, o->lag, o->group, sync, 0);
    printf("  window (no barrier), lag %u, nodes of %u processes, %.1f us of synchronisation per "
           "evaluation in a node: coordinator CPU per evaluation %.2f us; re-validated %.0f%% of "
           "the edges that kept operations\n",
           o->lag, o->group, sync, coord_us(&at),
           at.with_ops ? 100 * at.revalidated / at.with_ops : 0);
    printf("    predicted at %.0f us RTT, %.0f Gb/s (processes):", o->rtt_us, o->gbps);
    for (size_t i = 0; i < N_W; i++) {
        window x = sc_window_at(o, er, views, workers[i], o->lag, o->group, sync, 0);
        printf(" %u: x%.1f (%.0f%%)", workers[i], x.t1 / x.tw, 100 * eff(&x, workers[i]));
    }
    printf("\n");
    for (size_t j = 0; j < N_GROUPS; j++)
        for (uint32_t w = 16; w <= 128; w *= 8) {
            window x = sc_window_at(o, er, views, w, o->lag, groups[j], sync, 0);
            print_window_where(&x, 0, o->lag, w);
        }
    printf("    lag x node size: 16 processes, 128 processes, re-validated, coordinator us per "
           "evaluation\n");
    for (size_t j = 0; j < N_GROUPS; j++)
        for (size_t i = 0; i < N_LAGS; i++) {
            window a = sc_window_at(o, er, views, 16, lags[i], groups[j], sync, 0);
            window b = sc_window_at(o, er, views, 128, lags[i], groups[j], sync, 0);
            printf("    lag %4u, nodes of %2u: x%.1f (%.0f%%), x%.1f (%.0f%%), %.0f%%, %.2f us\n",
                   lags[i], groups[j], a.t1 / a.tw, 100 * eff(&a, 16), b.t1 / b.tw,
                   100 * eff(&b, 128), b.with_ops ? 100 * b.revalidated / b.with_ops : 0,
                   coord_us(&b));
        }
    for (size_t j = 0; j < N_GROUPS; j++)
        printf("    nodes of %u: smallest lag (a power of 2) for efficiency >= 0.8 on 16 "
               "processes: %u; >= 0.6 on 128: %u (0: none up to 65536)\n",
               groups[j], lag_for(o, er, views, 16, groups[j], sync, 0.8),
               lag_for(o, er, views, 128, groups[j], sync, 0.6));
}

static void print_window_json(const opts *o, const edges_run *er, uint32_t views, double sync)
{
    printf(", \"schedule\": \"window\", \"lag\": %u, \"group\": %u, \"sync_us\": %.3f, "
           "\"window\": [",
           o->lag, o->group, sync);
    int first = 1;
    for (size_t j = 0; j < N_GROUPS; j++)
        for (size_t i = 0; i < N_LAGS; i++)
            for (size_t k = 0; k < N_W; k++) {
                window x = sc_window_at(o, er, views, workers[k], lags[i], groups[j], sync, 0);
                printf("%s{\"lag\": %u, \"group\": %u, \"workers\": %u, \"speedup\": %.3f, "
                       "\"efficiency\": %.3f, \"coordinator_cpu_per_eval_us\": %.3f, "
                       "\"revalidated_share\": %.3f}",
                       first ? "" : ", ", lags[i], groups[j], workers[k], x.t1 / x.tw,
                       eff(&x, workers[k]), coord_us(&x),
                       x.with_ops ? x.revalidated / x.with_ops : 0);
                first = 0;
            }
    printf("], \"window_at_lag\": [");
    for (size_t k = 0; k < N_W; k++) {
        window x = sc_window_at(o, er, views, workers[k], o->lag, o->group, sync, 0);
        printf("%s{\"workers\": %u, \"speedup\": %.3f, \"efficiency\": %.3f}", k ? ", " : "",
               workers[k], x.t1 / x.tw, eff(&x, workers[k]));
    }
    printf("]");
}

/* ---- capped visits --------------------------------------------------------------------------- */

/* The lists' (N, D, G) number i, in the order N, D, G (G fastest). */
static void capped_at(const opts *o, uint32_t i, uint32_t *n, uint32_t *d, uint32_t *g)
{
    *g = o->groups[i % o->n_groups], i /= o->n_groups;
    *d = o->lags[i % o->n_lags], i /= o->n_lags;
    *n = o->caps[i];
}

static void print_capped_human(const opts *o, const edges_run *er, uint32_t views, double sync)
{
    uint32_t all = o->n_caps * o->n_lags * o->n_groups, best = 0, n, d, g, met = 0;
    double best_e = -1;
    printf("  capped visits (a visit stops after N evaluations, the rest of the edge a "
           "continuation D or more visits later; operations and commits with the last visit): "
           "N, D, G: 16 processes, 128 processes, visits per edge, visits modelled (the run; the "
           "last D visits' commits are never applied), continuations' restarts if "
           "each re-evaluated its start once (not charged), re-validated, coordinator us per "
           "evaluation\n");
    for (uint32_t i = 0; i < all; i++) {
        capped_at(o, i, &n, &d, &g);
        window a = sc_window_at(o, er, views, 16, d, g, sync, n);
        window b = sc_window_at(o, er, views, 128, d, g, sync, n);
        printf("    N %4u, D %4u, G %2u: x%.1f (%.0f%%), x%.1f (%.0f%%), %.2f, %.0f, +%.1f%% "
               "evaluations, %.0f%%, %.2f us\n",
               n, d, g, a.t1 / a.tw, 100 * eff(&a, 16), b.t1 / b.tw, 100 * eff(&b, 128),
               b.visits / b.edges, b.visits, 100 * b.restarts / b.evals,
               b.with_ops ? 100 * b.revalidated / b.with_ops : 0, coord_us(&b));
        if (eff(&a, 16) >= 0.8 && eff(&b, 128) >= 0.6)
            met++;
        if (d >= b.visits)
            printf("      (D at least the pass: nothing waits for the window nor is applied)\n");
        if (eff(&b, 128) > best_e && (n || o->n_caps == 1)) /* the best capped */
            best_e = eff(&b, 128), best = i;
    }
    capped_at(o, best, &n, &d, &g);
    printf("    (N, D, G) with efficiency >= 0.8 on 16 processes and >= 0.6 on 128: %u of %u; "
           "the best capped on 128 (N %u, D %u, G %u):\n",
           met, all, n, d, g);
    for (uint32_t w = 16; w <= 128; w *= 8) {
        window x = sc_window_at(o, er, views, w, d, g, sync, n);
        print_window_where(&x, n, d, w);
    }
}

static void print_capped_json(const opts *o, const edges_run *er, uint32_t views, double sync)
{
    uint32_t all = o->n_caps * o->n_lags * o->n_groups, n, d, g;
    printf(", \"capped\": [");
    for (uint32_t i = 0; i < all; i++) {
        capped_at(o, i, &n, &d, &g);
        for (size_t k = 0; k < N_W; k++) {
            window x = sc_window_at(o, er, views, workers[k], d, g, sync, n);
            printf("%s{\"cap\": %u, \"lag\": %u, \"group\": %u, \"workers\": %u, \"speedup\": "
                   "%.3f, \"efficiency\": %.3f, \"coordinator_cpu_per_eval_us\": %.3f, "
                   "\"visits_per_edge\": %.3f, \"restarts_share\": %.4f}",
                   i || k ? ", " : "", n, d, g, workers[k], x.t1 / x.tw, eff(&x, workers[k]),
                   coord_us(&x), x.visits / x.edges, x.restarts / x.evals);
        }
    }
    printf("]");
}
