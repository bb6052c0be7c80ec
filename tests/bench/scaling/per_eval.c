/* tests/bench/scaling/per_eval.c — today's schedule, one evaluation the unit of remote work: a
 * real optimisation run (one edge at a time, then K edges in flight) behind the meter, and the
 * speed-up it predicts.
 *
 * The model for W workers over V views, per batch i of n_i patches (perfect balance, a (patch,
 * view) pair the smallest piece of work), the coordinator's work split into the geometric term
 * (geo_i, as the in-process views price it) and the rest; the term is priced where that is
 * faster (surface_term.h): here while the workers render, or by them, each group of views a share
 * of the triangles:
 *     out_i  = RTT + bytes_i * min(W, V) / bandwidth
 *     T_i(W) = rest_i + min(max(geo_i, out_i + n_i * V * c / p_i),
 *                           out_i + (n_i * V * c + geo_i) / p_i),   p_i = min(W, n_i * V)
 * plus, once for the run, the views' other work S (commits, meshes, energies and the oracle's
 * potentials: the workers', each on its share of the views), a round trip per energy or
 * potentials request and the commits' bytes to every group: S / min(W, V) + requests * RTT +
 * commit bytes * min(W, V) / bandwidth (in process: S);
 * against the in-process T_i = rest_i + geo_i + n_i * V * c; speed-up = sum T / sum T(W),
 * efficiency = speed-up / W. Printed for W = 1, 2, 4, 8, 16, 128 at --rtt-us (default 100) and
 * --gbps (default 10), both orders of edges; and for 2 workers at the round trips measured here
 * (ZeroMQ, and the floor): what local multi-process mode can reach on this machine at best (the
 * model gives the coordinator a core of its own, so on a machine with as many cores as workers the
 * real figure is lower).
 */
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/optimizer.h"
#include "scaling.h"

lm_status sc_run_once(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                      const lm_view_set *vs, uint32_t k, meter *m, costs *c)
{
    lm_mesh *mesh = NULL;
    lm_optimizer *opt = NULL;
    lm_status st = sc_meter_start(o, orig, coarse, vs, 0, m, &mesh);
    /* as a job from a QEM start: the geometric term on, its weight from LM_SURFACE_SHARE */
    lm_params params = {.seed = 1, .edges_in_flight = k, .surface = orig};
    double c_create = sc_cpu();
    if (st == LM_OK)
        st = lm_optimizer_create(mesh, &m->base, &params, &opt);
    /* the optimizer's set-up (the start's energies, the term's weight, the edge queue) is done
       once a job: not a cost per evaluation */
    double c0 = sc_cpu(), state0 = m->state_cpu_s;
    uint64_t trips0 = m->round_trips;
    for (int guard = 0; st == LM_OK && guard < 100000; guard++) {
        lm_progress p;
        lm_optimizer_progress(opt, &p);
        if (p.evals >= o->evals)
            break;
        st = lm_optimizer_step(opt, o->evals);
    }
    double total_cpu = sc_cpu() - c0;
    m->state_cpu_s -= state0;
    m->round_trips -= trips0;
    lm_optimizer_destroy(opt);
    lm_views_destroy(m->in);
    lm_replica_free(&m->rep);
    if (st != LM_OK)
        return st;
    double views = vs->count, bytes = 0;
    for (size_t i = 0; i < m->batches; i++)
        bytes += m->bytes[i];
    *c = (costs){.k = k, .evals = m->patches, .batches = m->batches, .m = m};
    c->setup_s = c0 - c_create;
    c->per_patch_view_us = 1e6 * m->views_s / ((double)m->patches * views);
    c->coord_us_per_eval = 1e6 * (total_cpu - m->views_cpu_s - m->state_cpu_s) / (double)m->patches;
    c->state_us_per_eval = 1e6 * m->state_cpu_s / (double)m->patches;
    c->round_trips = (double)m->round_trips;
    c->commits = (double)m->commits;
    c->total_commit_bytes = (double)m->commit_bytes;
    c->overlap_us_per_eval = 1e6 * m->overlap_cpu_s / (double)m->patches;
    c->bytes_per_batch = bytes / (double)m->batches;
    c->patches_per_batch = (double)m->patches / (double)m->batches;
    c->commit_bytes = m->commits ? (double)m->commit_bytes / (double)m->commits : 0;
    c->tris_per_patch = (double)m->added / (double)m->patches;
    c->moved_share = m->added ? 1.0 - (double)m->kept_pos / (double)m->added : 0;
    return LM_OK;
}

/* Predicted speed-up over in process for w workers at a round trip of rtt_us. */
double sc_speedup_at(const opts *o, const costs *c, uint32_t views, uint32_t w, double rtt_us)
{
    double t1 = 0, tw = 0, rtt = rtt_us * 1e-6, bw = o->gbps * 1e9 / 8.0;
    double cost = c->per_patch_view_us * 1e-6;
    double rest = (c->coord_us_per_eval - c->overlap_us_per_eval) * 1e-6; /* the coordinator's */
    for (size_t i = 0; i < c->m->batches; i++) {
        double n = c->m->n[i], work = n * views * cost, geo = c->m->overlap[i];
        double pieces = n * views < w ? n * views : w;
        double ranges = w < views ? w : views;
        double round = rtt + c->m->bytes[i] * ranges / bw; /* the batch out and back */
        double by_workers = round + (work + geo) / pieces, here = round + work / pieces;
        here = here > geo ? here : geo; /* the term priced here while they render */
        t1 += rest * n + geo + work;
        tw += rest * n + (here < by_workers ? here : by_workers);
    }
    /* the views' other work (commits, meshes, energies, potentials) on the workers, each its
       share of the views, with a round trip per request and the commits' bytes to every group */
    double ranges = w < views ? w : views, state = c->state_us_per_eval * 1e-6 * (double)c->evals;
    t1 += state;
    tw += state / ranges + c->round_trips * rtt + c->total_commit_bytes * ranges / bw;
    return t1 / tw;
}

double sc_speedup(const opts *o, const costs *c, uint32_t views, uint32_t w)
{
    return sc_speedup_at(o, c, views, w, o->rtt_us);
}
