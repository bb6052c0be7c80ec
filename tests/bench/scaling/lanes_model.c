/* tests/bench/scaling/lanes_model.c — the whole-lane schedule (issue 36) modelled from the
 * isolated-lane runs (lanes_run.c), and its report (--schedule lanes).
 *
 * Every worker holds all V views and a replica of the optimizer's state; the coordinator plans a
 * group of up to K edges (K = workers x --lanes-per-worker, at most LM_MAX_EDGES_IN_FLIGHT),
 * sends each lane's request (SC_LANE_REQUEST_BYTES: its edge and a reference to the group's
 * start) with the last group's merged commits, the workers run whole lanes, the coordinator merges
 * the results in lane order (re-validating a lane as one evaluation on a worker, a round trip each,
 * in order) and the next group's requests carry the merged commits to every worker. Group j of the
 * measured run, n_j lanes, on W workers (in lane order, each lane to the worker that frees first,
 * as views_remote_lanes.c dispatches):
 *     T_j(W) = P_j + pot_j / min(W, V)                                      planning
 *            + RTT/2 + (W * B_{j-1} + n_j * q) / bandwidth                  handing out
 *            + D_j                                                          dispatching
 *            + A_{j-1} + M_{j-1}                                            the replicas updated
 *            + max_w sum_{i on w} (e_i * t * a + S_j / n_j)                 the slowest worker
 *            + RTT/2 + sum_i b_i / bandwidth                                results back
 *            + C_j                                                          the merge
 *            + r_j * RTT + R_j                                              re-validations
 * and for the whole run, once per regrid of the job (every js->regrid_every evaluations), G = Y +
 * E: the process CPU of one regrid in process, Y its targets' renders (the new views made), E the
 * rest (the energies), which every worker spends at once, since each holds all views. On W >= 2
 * workers the targets are rendered split (views_remote_layout.c): each worker renders
 * ceil(V / k) of them, k = min(W, V), the coordinator reads them back (a round trip each round)
 * and ships one targets asset of Y_b bytes to every worker (in turn on its link), then the views
 * are assigned with it (about 4 more round trips):
 *     G(W) = Y ceil(V / k) / V + E + (ceil(V / k) + 4) RTT + (1 + W) Y_b / bandwidth,  G(1) = G
 * and T(W) = sum_j T_j(W) + n_G G(W).
 * P_j, D_j and C_j are the coordinator's CPU measured on the remote run of the same job
 * (sc_run_lanes_remote: the same groups; where they differ, its CPU per evaluation in its own
 * proportions): from the last merge to the group (the plan, the potentials' requests), while the
 * lanes run (their starts, queues and requests encoded, the results decoded), and the merge (the
 * re-validations' requests, the commits' messages to the workers); a the remote run's lanes run
 * twice (1 + audits / lanes: the audit's second worker). Without a remote run P_j and C_j are the
 * in-process planning and merge, D_j = 0 and a = 1.
 * with e_i a lane's measured evaluations (the distribution, not the mean), t a worker's time per
 * evaluation (the lanes' measured time over their evaluations), S_j the snapshots, b_i a lane's
 * result bytes, B_j the merged commits' bytes, A_j the workers' time applying them and M_j the
 * coordinator's merge CPU (a worker replays the same logs to keep its replica: charged as M_j),
 * r_j the re-validations and R_j their views' time. In one process the same run:
 * T_1 = sum (plan + pot + S + lanes + M + R + A) + n_G G. Speed-up T_1 / T(W), efficiency
 * speed-up / W; the coordinator's CPU per evaluation sum (P + D + C) / evaluations (the report
 * also gives the remote run's with its regrids). "No barrier" (what
 * groups overlapping could reach at best): the slowest workers' term replaced by the lanes' work
 * spread evenly, sum_j sum_i (e_i t + S_j / n_j) / W. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/lanes.h"
#include "scaling.h"

static const uint32_t workers[] = {1, 2, 4, 8, 16, 128};
#define N_W (sizeof workers / sizeof *workers)

/* The slowest worker's time in group g: its lanes in lane order, each to the worker that frees
 * first (the lowest-numbered on a tie), as views_remote_lanes.c dispatches them; *sum the workers'
 * time together. */
static double slowest(const lanes_run *r, const group_rec *g, uint32_t w, double *sum)
{
    double worst = 0, snap = g->n ? g->snap_s / g->n : 0;
    /* lanes a second worker runs again (the remote run's audits), spread over the lanes */
    double audit = r->coord && r->coord->n_l ? 1 + (double)r->coord->audits / r->coord->n_l : 1;
    uint32_t used = w < g->n ? w : g->n;
    double *busy = calloc(used ? used : 1, sizeof *busy);
    LM_ASSERT(busy);
    *sum = 0;
    for (uint32_t i = 0; i < g->n; i++) {
        uint32_t free_first = 0;
        for (uint32_t k = 1; k < used; k++)
            free_first = busy[k] < busy[free_first] ? k : free_first;
        double t = r->l[g->first + i].evals * r->eval_s * audit + snap;
        busy[free_first] += t;
        *sum += t;
    }
    for (uint32_t k = 0; k < used; k++)
        worst = busy[k] > worst ? busy[k] : worst;
    free(busy);
    return worst;
}

/* The coordinator's CPU in group j of the in-process run r, from the remote run c of the same
 * K: its group j when the runs formed the same groups, else its CPU per evaluation times the
 * group's evaluations, in c's proportions of planning, dispatch and merge. */
static group_rec coord_group(const lanes_run *r, const lanes_run *c, size_t j)
{
    if (c->n_g == r->n_g)
        return c->g[j];
    const group_rec *g = &r->g[j];
    double ev = 0, plan = 0, lanes = 0, merge = 0;
    for (uint32_t i = 0; i < g->n; i++)
        ev += r->l[g->first + i].evals;
    for (size_t i = 0; i < c->n_g; i++)
        plan += c->g[i].cpu_plan, lanes += c->g[i].cpu_lanes, merge += c->g[i].cpu_merge;
    double per = ev / (double)(c->evals ? c->evals : 1);
    group_rec x = *g;
    x.cpu_plan = (float)(plan * per), x.cpu_lanes = (float)(lanes * per);
    x.cpu_merge = (float)(merge * per);
    return x;
}

/* The run's regrids on w workers over V views: G(w) summed over them (the formula at the top). */
static double regrid_at(const opts *o, const lanes_run *r, uint32_t views, uint32_t w)
{
    if (w < 2 || !r->regrids || !views)
        return r->regrid_cpu_s;
    double rtt = o->rtt_us * 1e-6, bw = o->gbps * 1e9 / 8.0;
    uint32_t k = w < views ? w : views, per = (views + k - 1) / k;
    double split = r->regrid_target_cpu_s * per / views;
    double rest = r->regrid_cpu_s - r->regrid_target_cpu_s;
    double wire = r->regrids * ((per + 4) * rtt + (1.0 + w) * r->target_bytes / bw);
    return split + (rest > 0 ? rest : 0) + wire;
}

lanes_model sc_lanes_at(const opts *o, const lanes_run *r, uint32_t views, uint32_t w)
{
    double rtt = o->rtt_us * 1e-6, bw = o->gbps * 1e9 / 8.0, ranges = w < views ? w : views;
    const lanes_run *c = r->coord;
    lanes_model x;
    memset(&x, 0, sizeof x);
    x.coord_measured = c != NULL;
    const group_rec *prev = &r->g[r->n_g - 1]; /* steady state: the run cycles */
    for (size_t j = 0; j < r->n_g; j++) {
        const group_rec *g = &r->g[j];
        double results = 0, sum = 0;
        for (uint32_t i = 0; i < g->n; i++)
            results += r->l[g->first + i].result_bytes;
        double lanes = slowest(r, g, w, &sum);
        /* the coordinator: in process its planning and merge; measured on a remote run, its
           whole CPU of each phase (the requests' encoding and the answers' decoding included) */
        group_rec cg = c ? coord_group(r, c, j) : *g;
        double plan_cpu = c ? cg.cpu_plan : g->plan_s, merge_cpu = c ? cg.cpu_merge : g->merge_s;
        double dispatch = c ? cg.cpu_lanes : 0;
        double plan = plan_cpu + g->pot_s / ranges;
        double hand_out = rtt / 2 + (w * prev->commit_bytes + g->n * SC_LANE_REQUEST_BYTES) / bw;
        double update = prev->apply_s + prev->merge_s;
        double back = rtt / 2 + results / bw;
        double reval = g->revals * rtt + g->reval_s;
        x.t1 +=
            g->plan_s + g->pot_s + g->snap_s + g->lanes_s + g->merge_s + g->reval_s + g->apply_s;
        x.tw += plan + hand_out + dispatch + update + lanes + back + merge_cpu + reval;
        x.plan += plan, x.hand_out += hand_out, x.update += update, x.lanes += lanes;
        x.dispatch += dispatch;
        x.results += back, x.merge += merge_cpu, x.revalidate += reval, x.balanced += sum / w;
        x.coord_s += plan_cpu + dispatch + merge_cpu;
        x.evals += g->revals;
        prev = g;
    }
    /* the regrids: the targets rendered split, read back and shipped (formula above); the
       energies on them on every worker at once */
    x.t1 += r->regrid_cpu_s;
    x.regrid = regrid_at(o, r, views, w);
    x.tw += x.regrid;
    x.evals += (double)r->evals;
    return x;
}

const lanes_run *sc_lanes_for(const lanes_run *runs, uint32_t n, uint32_t w, uint32_t per)
{
    uint32_t want = w * per;
    const lanes_run *best = NULL, *largest = &runs[0];
    for (uint32_t i = 0; i < n; i++) {
        if (runs[i].k >= want && (!best || runs[i].k < best->k))
            best = &runs[i];
        largest = runs[i].k > largest->k ? &runs[i] : largest;
    }
    return best ? best : largest;
}

/* ---- the run's distributions ----------------------------------------------------------------- */

typedef struct lane_stats {
    double evals_mean, evals_p50, evals_p90, evals_p99, evals_max;
    double group_mean, kept_exact, kept_reval, dropped_replay, dropped_reval, with_ops;
    double wasted;                     /* evaluations of dropped lanes over all */
    double result_bytes;               /* mean per lane */
    double commit_bytes;               /* mean per group */
    double plan_us, merge_us, snap_us; /* per lane */
} lane_stats;

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

static lane_stats stats_of(const lanes_run *r)
{
    lane_stats s;
    memset(&s, 0, sizeof s);
    size_t n = r->n_l ? r->n_l : 1;
    uint32_t *ev = calloc(n, sizeof *ev);
    LM_ASSERT(ev);
    double all = 0, dropped = 0;
    for (size_t i = 0; i < r->n_l; i++) {
        const lane_rec *l = &r->l[i];
        ev[i] = l->evals;
        all += l->evals;
        s.result_bytes += l->result_bytes;
        s.with_ops += l->ops > 0;
        s.kept_exact += l->outcome == LM_LANE_KEPT_EXACT;
        s.kept_reval += l->outcome == LM_LANE_KEPT_REVALIDATED;
        s.dropped_replay += l->outcome == LM_LANE_DROPPED_REPLAY;
        s.dropped_reval += l->outcome == LM_LANE_DROPPED_REVALIDATION;
        if (l->outcome == LM_LANE_DROPPED_REPLAY || l->outcome == LM_LANE_DROPPED_REVALIDATION)
            dropped += l->evals;
    }
    qsort(ev, n, sizeof *ev, cmp_u32);
    s.evals_mean = all / (double)n;
    s.evals_p50 = ev[n / 2], s.evals_p90 = ev[n * 9 / 10], s.evals_p99 = ev[n * 99 / 100];
    s.evals_max = ev[n - 1];
    free(ev);
    s.wasted = all > 0 ? dropped / all : 0;
    s.result_bytes /= (double)n;
    for (size_t j = 0; j < r->n_g; j++) {
        s.commit_bytes += r->g[j].commit_bytes;
        s.plan_us += 1e6 * r->g[j].plan_s;
        s.merge_us += 1e6 * r->g[j].merge_s;
        s.snap_us += 1e6 * r->g[j].snap_s;
    }
    s.group_mean = (double)r->n_l / (double)(r->n_g ? r->n_g : 1);
    s.commit_bytes /= (double)(r->n_g ? r->n_g : 1);
    s.plan_us /= (double)n, s.merge_us /= (double)n, s.snap_us /= (double)n;
    return s;
}

static double coord_us(const lanes_model *x)
{
    return x->evals > 0 ? 1e6 * x->coord_s / x->evals : 0;
}

/* ---- the report ------------------------------------------------------------------------------ */

/* The remote run's coordinator CPU in all: per group's phases, per evaluation (the regrids apart,
 * and with them). */
typedef struct coord_stats {
    double plan_ms, dispatch_ms, merge_ms; /* per group */
    double us_per_eval, us_per_eval_all;   /* the groups'; the whole run's (regrids included) */
    double evals_per_s;                    /* the remote run's, on this machine */
} coord_stats;

static coord_stats coord_of(const lanes_run *c)
{
    coord_stats s;
    memset(&s, 0, sizeof s);
    double n = c->n_g ? (double)c->n_g : 1, ev = c->evals ? (double)c->evals : 1;
    for (size_t j = 0; j < c->n_g; j++)
        s.plan_ms += c->g[j].cpu_plan, s.dispatch_ms += c->g[j].cpu_lanes,
            s.merge_ms += c->g[j].cpu_merge;
    s.us_per_eval = 1e6 * (s.plan_ms + s.dispatch_ms + s.merge_ms) / ev;
    s.us_per_eval_all = 1e6 * c->coord_cpu_s / ev;
    s.plan_ms *= 1e3 / n, s.dispatch_ms *= 1e3 / n, s.merge_ms *= 1e3 / n;
    s.evals_per_s = c->wall_s > 0 ? ev / c->wall_s : 0;
    return s;
}

static void print_coordinator_human(const lanes_run *r, uint32_t views)
{
    (void)views;
    if (r->regrids)
        printf(
            "    the job's regrids: %u, each %.3f s of CPU in process, %.3f s of it the targets' "
            "renders (split over the workers), the rest the energies (every worker); one targets "
            "asset %.0f bytes\n",
            r->regrids, r->regrid_cpu_s / r->regrids, r->regrid_target_cpu_s / r->regrids,
            r->target_bytes);
    const lanes_run *c = r->coord;
    if (!c)
        return;
    coord_stats s = coord_of(c);
    printf("    the coordinator measured on --lanes remote with %u local workers: %zu groups, %llu "
           "evaluations, per group planning %.2f ms, dispatching the lanes %.2f ms (starts, "
           "queues, requests, results), merging %.2f ms (re-validations' and commits' messages "
           "included) of CPU; coordinator CPU per evaluation %.2f us (%.2f us with the regrids' "
           "%.3f s each); %llu lanes audited; that run: %.0f evaluations/s here (%.2f s, "
           "%u regrids of %.2f s wall each)\n",
           c->workers, c->n_g, (unsigned long long)c->evals, s.plan_ms, s.dispatch_ms, s.merge_ms,
           s.us_per_eval, s.us_per_eval_all, c->regrids ? c->regrid_cpu_s / c->regrids : 0,
           (unsigned long long)c->audits, s.evals_per_s, c->wall_s, c->regrids,
           c->regrids ? c->regrid_wall_s / c->regrids : 0);
}

static void print_run_human(const opts *o, const lanes_run *r, uint32_t views)
{
    lane_stats s = stats_of(r);
    lanes_model one = sc_lanes_at(o, r, views, 1);
    double n = (double)r->n_l;
    printf("  K %u: %zu groups of %.1f lanes on average over %llu evaluations (%.2f s in process, "
           "energy %.4f of the start); evaluations per lane mean %.0f, median %.0f, p90 %.0f, "
           "p99 %.0f, max %.0f; a worker's time per evaluation %.1f us of CPU (%.2f us per "
           "patch and view; %.1f us of wall time here); the coordinator per lane: planning %.1f "
           "us, merge %.1f us (snapshots %.1f us, "
           "the workers'), so %.3f us per evaluation; lanes with operations %.0f%%: kept exact "
           "%.0f%%, re-validated and kept %.0f%%, dropped at replay %.0f%%, dropped at "
           "re-validation %.0f%% (of all lanes), %.1f%% of the evaluations wasted; messages: "
           "request %.0f B, result %.0f B per lane, commits %.0f B per group (to every worker)\n",
           r->k, r->n_g, s.group_mean, (unsigned long long)r->evals, r->wall_s, r->energy_rel,
           s.evals_mean, s.evals_p50, s.evals_p90, s.evals_p99, s.evals_max, 1e6 * r->eval_s,
           r->per_patch_view_us, 1e6 * r->eval_wall_s, s.plan_us, s.merge_us, s.snap_us,
           coord_us(&one), 100 * s.with_ops / n, 100 * s.kept_exact / n, 100 * s.kept_reval / n,
           100 * s.dropped_replay / n, 100 * s.dropped_reval / n, 100 * s.wasted,
           SC_LANE_REQUEST_BYTES, s.result_bytes, s.commit_bytes);
    print_coordinator_human(r, views);
    printf("    predicted at %.0f us RTT, %.0f Gb/s with K %u:", o->rtt_us, o->gbps, r->k);
    for (size_t i = 0; i < N_W; i++) {
        lanes_model x = sc_lanes_at(o, r, views, workers[i]);
        printf(" %u: x%.1f (%.0f%%)", workers[i], x.t1 / x.tw, 100 * x.t1 / x.tw / workers[i]);
    }
    printf("\n      without the group barrier:");
    for (size_t i = 0; i < N_W; i++) {
        lanes_model x = sc_lanes_at(o, r, views, workers[i]);
        double spread = x.tw - x.lanes + x.balanced;
        printf(" %u: x%.1f (%.0f%%)", workers[i], x.t1 / spread, 100 * x.t1 / spread / workers[i]);
    }
    printf("\n      evaluations per second (each worker one core of this machine's CPU time):");
    for (size_t i = 0; i < N_W; i++) {
        lanes_model x = sc_lanes_at(o, r, views, workers[i]);
        printf(" %u: %.0f", workers[i], x.evals / x.tw);
    }
    printf("\n");
}

static void print_where(const lanes_model *x, uint32_t w, uint32_t k)
{
    double all = x->tw / 100, spread = x->tw - x->lanes + x->balanced;
    printf("    %u workers, K %u: x%.1f (%.0f%%); where the time goes: planning %.0f%%, handing "
           "out %.0f%%, dispatching (the coordinator's CPU) %.0f%%, replicas updated %.0f%%, the "
           "slowest workers %.0f%% (the lanes spread evenly would take %.0f%%), results back "
           "%.0f%%, merging %.0f%%, re-validating %.0f%%, regrids %.0f%%; the coordinator's CPU "
           "%.0f%% busy (%s), %.2f us per evaluation; with the lanes spread evenly (no group "
           "barrier) x%.1f (%.0f%%)\n",
           w, k, x->t1 / x->tw, 100 * x->t1 / x->tw / w, x->plan / all, x->hand_out / all,
           x->dispatch / all, x->update / all, x->lanes / all, x->balanced / all, x->results / all,
           x->merge / all, x->revalidate / all, x->regrid / all, 100 * x->coord_s / x->tw,
           x->coord_measured ? "measured on a remote run" : "in process: planning and merge",
           coord_us(x), x->t1 / spread, 100 * x->t1 / spread / w);
}

/* The job's start, as the report names it. */
static const char *start_name(const opts *o)
{
    return o->initial ? o->initial : o->start == CO_JOB_START_ADAPTIVE ? "adaptive" : "qem";
}

void sc_print_lanes_human(const opts *o, const co_job_setup *js, const lanes_run *runs, uint32_t n,
                          uint32_t views)
{
    printf("bench scaling, whole lanes (isolated lanes on workers holding all views), the job's "
           "set-up: %s, start %s (%u vertices), attributes 0x%x, %u views of %d px, %llu "
           "evaluations per run, %u lanes per worker, plans of %u edges%s\n",
           o->model, start_name(o), js->coarse->live_verts, js->attrs, views, js->o.size,
           (unsigned long long)o->edge_evals, o->lanes_per_worker,
           js->o.edges_per_iteration ? js->o.edges_per_iteration : LM_DEFAULT_EDGES_PER_ITERATION,
           o->lanes_detached ? ", lanes detached (through their messages and a lane host)" : "");
    for (uint32_t i = 0; i < n; i++)
        print_run_human(o, &runs[i], views);
    printf("  predicted at %.0f us RTT, %.0f Gb/s (K = workers x lanes per worker, at most the "
           "largest K run):",
           o->rtt_us, o->gbps);
    for (size_t i = 0; i < N_W; i++) {
        const lanes_run *r = sc_lanes_for(runs, n, workers[i], o->lanes_per_worker);
        lanes_model x = sc_lanes_at(o, r, views, workers[i]);
        printf(" %u: x%.1f (%.0f%%, K %u)", workers[i], x.t1 / x.tw, 100 * x.t1 / x.tw / workers[i],
               r->k);
    }
    printf("\n");
    for (uint32_t per = 1; per <= 8; per *= 2) {
        printf("    %u lanes per worker:", per);
        for (uint32_t w = 2; w <= 128; w *= 8) {
            const lanes_run *r = sc_lanes_for(runs, n, w, per);
            lanes_model x = sc_lanes_at(o, r, views, w);
            printf(" %u: x%.1f (%.0f%%, K %u)", w, x.t1 / x.tw, 100 * x.t1 / x.tw / w, r->k);
        }
        printf("\n");
    }
    for (uint32_t w = 2; w <= 128; w *= 8) {
        const lanes_run *r = sc_lanes_for(runs, n, w, o->lanes_per_worker);
        lanes_model x = sc_lanes_at(o, r, views, w);
        print_where(&x, w, r->k);
    }
}

/* The remote run's coordinator measurement of a K, as JSON keys (null without one). */
static void print_coordinator_json(const lanes_run *r)
{
    const lanes_run *c = r->coord;
    if (!c) {
        printf("\"coordinator_measured\": null, ");
        return;
    }
    coord_stats s = coord_of(c);
    printf("\"coordinator_measured\": {\"workers\": %u, \"groups\": %zu, \"evals\": %llu, "
           "\"plan_ms_per_group\": %.3f, \"dispatch_ms_per_group\": %.3f, "
           "\"merge_ms_per_group\": %.3f, \"cpu_per_eval_us\": %.3f, "
           "\"cpu_per_eval_us_with_regrids\": %.3f, \"lanes\": %zu, \"audits\": %llu, \"regrids\": "
           "%u, "
           "\"regrid_wall_s\": %.3f, \"wall_s\": %.3f, \"evals_per_s\": %.1f}, ",
           c->workers, c->n_g, (unsigned long long)c->evals, s.plan_ms, s.dispatch_ms, s.merge_ms,
           s.us_per_eval, s.us_per_eval_all, c->n_l, (unsigned long long)c->audits, c->regrids,
           c->regrids ? c->regrid_wall_s / c->regrids : 0, c->wall_s, s.evals_per_s);
}

void sc_print_lanes_json(const opts *o, const co_job_setup *js, const lanes_run *runs, uint32_t n,
                         uint32_t views)
{
    printf("{\"bench\": \"scaling\", \"schedule\": \"lanes\", \"model\": \"%s\", \"start\": "
           "\"%s\", \"start_verts\": %u, \"attrs\": %u, \"views\": %u, \"size\": %d, "
           "\"edge_evals\": %llu, \"model_rtt_us\": %.1f, \"model_gbps\": %.1f, "
           "\"lanes_per_worker\": %u, \"plan\": %u, \"lanes\": [",
           o->model, start_name(o), js->coarse->live_verts, js->attrs, views, js->o.size,
           (unsigned long long)o->edge_evals, o->rtt_us, o->gbps, o->lanes_per_worker,
           js->o.edges_per_iteration ? js->o.edges_per_iteration : LM_DEFAULT_EDGES_PER_ITERATION);
    for (uint32_t i = 0; i < n; i++) {
        const lanes_run *r = &runs[i];
        lane_stats s = stats_of(r);
        lanes_model one = sc_lanes_at(o, r, views, 1);
        double nl = r->n_l ? (double)r->n_l : 1;
        printf("%s{\"edges_in_flight\": %u, \"groups\": %zu, \"lanes\": %zu, \"evals\": %llu, "
               "\"group_mean\": %.3f, \"evals_per_lane_mean\": %.2f, \"evals_per_lane_p50\": "
               "%.0f, \"evals_per_lane_p90\": %.0f, \"evals_per_lane_p99\": %.0f, "
               "\"evals_per_lane_max\": %.0f, \"worker_us_per_eval\": %.3f, "
               "\"worker_wall_us_per_eval\": %.3f, \"us_per_patch_view\": %.3f, "
               "\"coordinator_plan_us_per_lane\": %.3f, "
               "\"coordinator_merge_us_per_lane\": %.3f, \"snapshot_us_per_lane\": %.3f, "
               "\"coordinator_cpu_per_eval_us\": %.3f, \"with_ops_share\": %.4f, "
               "\"kept_exact_share\": %.4f, \"revalidated_kept_share\": %.4f, "
               "\"dropped_replay_share\": %.4f, \"dropped_revalidation_share\": %.4f, "
               "\"wasted_evals_share\": %.4f, \"request_bytes\": %.0f, \"result_bytes_mean\": "
               "%.1f, \"commit_bytes_per_group\": %.1f, \"energy_rel\": %.5f, \"wall_s\": %.3f, "
               "\"regrids\": %u, \"regrid_cpu_s\": %.4f, \"regrid_target_cpu_s\": %.4f, "
               "\"target_bytes\": %.0f, ",
               i ? ", " : "", r->k, r->n_g, r->n_l, (unsigned long long)r->evals, s.group_mean,
               s.evals_mean, s.evals_p50, s.evals_p90, s.evals_p99, s.evals_max, 1e6 * r->eval_s,
               1e6 * r->eval_wall_s, r->per_patch_view_us, s.plan_us, s.merge_us, s.snap_us,
               coord_us(&one), s.with_ops / nl, s.kept_exact / nl, s.kept_reval / nl,
               s.dropped_replay / nl, s.dropped_reval / nl, s.wasted, SC_LANE_REQUEST_BYTES,
               s.result_bytes, s.commit_bytes, r->energy_rel, r->wall_s, r->regrids,
               r->regrids ? r->regrid_cpu_s / r->regrids : 0,
               r->regrids ? r->regrid_target_cpu_s / r->regrids : 0, r->target_bytes);
        print_coordinator_json(r);
        printf("\"predicted\": [");
        for (size_t k = 0; k < N_W; k++) {
            lanes_model x = sc_lanes_at(o, r, views, workers[k]);
            printf("%s{\"workers\": %u, \"speedup\": %.3f, \"efficiency\": %.3f, "
                   "\"speedup_no_barrier\": %.3f, \"evals_per_s\": %.1f, "
                   "\"coordinator_cpu_per_eval_us\": %.3f, \"coordinator_busy\": %.3f}",
                   k ? ", " : "", workers[k], x.t1 / x.tw, x.t1 / x.tw / workers[k],
                   x.t1 / (x.tw - x.lanes + x.balanced), x.evals / x.tw, coord_us(&x),
                   x.coord_s / x.tw);
        }
        printf("]}");
    }
    printf("], \"predicted\": [");
    for (size_t k = 0; k < N_W; k++) {
        const lanes_run *r = sc_lanes_for(runs, n, workers[k], o->lanes_per_worker);
        lanes_model x = sc_lanes_at(o, r, views, workers[k]);
        printf("%s{\"workers\": %u, \"edges_in_flight\": %u, \"speedup\": %.3f, \"efficiency\": "
               "%.3f, \"coordinator_cpu_per_eval_us\": %.3f, \"coordinator_busy\": %.3f, "
               "\"speedup_no_barrier\": %.3f}",
               k ? ", " : "", workers[k], r->k, x.t1 / x.tw, x.t1 / x.tw / workers[k], coord_us(&x),
               x.coord_s / x.tw, x.t1 / (x.tw - x.lanes + x.balanced));
    }
    printf("]}\n");
}
