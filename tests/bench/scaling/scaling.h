/* tests/bench/scaling/scaling.h — bench_scaling's internal header: its options, the measuring
 * views (meter.c), the costs its runs record (per_eval.c, edge_costs.c), the round trips
 * measured here (rtt.c), the models of the whole-edge schedules (rounds.c, window.c) and the
 * report (report.c). Not a library: only tests/bench/bench_scaling.c and these files use it. */
#ifndef LUMESH_BENCH_SCALING_H
#define LUMESH_BENCH_SCALING_H

#include <stddef.h>
#include <stdint.h>

#include "common/replica.h"
#include "common/view.h"
#include "coordinator/job/job.h"
#include "coordinator/views/views.h"
#include "proto/wire_records.h"

typedef enum { SCHEDULE_ROUNDS, SCHEDULE_WINDOW, SCHEDULE_LANES } schedule_kind;

#define SC_MAX_LIST 8 /* values in a list option */

typedef struct opts {
    const char *model, *device;
    uint64_t evals, edge_evals;
    uint32_t in_flight, views, size, round, target_verts;
    double rtt_us, gbps;
    int json;
    schedule_kind schedule; /* --schedule: rounds (default) or window (also prints the window) */
    uint32_t lag, group;    /* --lag D, --group G: the window's lag, processes per node */
    /* --cap N: visits of at most N evaluations (visits.c; 0: none). --cap, --lag, --group take
     * comma-separated lists (lag, group: their first); with --cap the window is also modelled
     * over every (N, D, G) of the lists */
    uint32_t caps[SC_MAX_LIST], lags[SC_MAX_LIST], groups[SC_MAX_LIST];
    uint32_t n_caps, n_lags, n_groups;
    double sync_us; /* --sync-us: a node's synchronisation per evaluation (<0: measured) */
    /* --schedule lanes: the isolated-lane runs' group sizes K (--lanes-k), lanes per worker */
    uint32_t lanes_k[SC_MAX_LIST], n_lanes_k, lanes_per_worker;
    uint32_t plan; /* --plan: the lanes' runs' edges per iteration (0: the job's default) */
    /* --schedule lanes: the job's start (co_job_setup_make): --initial MESH, else --start qem
       (the default here) or adaptive */
    const char *initial;
    co_job_start start;
    uint64_t regrid_every; /* --regrid-every: the job's (0: never); regrid_set 0: default */
    int regrid_set;
    uint32_t coordinator_workers; /* --coordinator-workers: the remote runs' workers (0: none) */
    int lanes_detached; /* --lanes-detached: each lane through its wire messages and a lane host
                           (lm_optimizer_set_lanes_detached), a worker's per-lane work measured */
} opts;

/* ---- the measuring views (meter.c) ----------------------------------------------------------- */

typedef struct meter {
    lm_views base;
    lm_views *in;
    uint32_t *n;     /* patches of batch i */
    uint32_t *bytes; /* its Evaluate message for one worker */
    float *overlap;  /* seconds of the coordinator's work done while batch i is out */
    size_t batches, cap;
    uint64_t patches, commits, commit_bytes;
    uint64_t added, kept_pos; /* added triangle records; of them, with the workers' positions */
    double views_s, views_cpu_s, encode_cpu_s, overlap_cpu_s;
    double state_cpu_s;   /* the views' commits, meshes, energies and potentials: the workers' */
    uint64_t round_trips; /* energy and potentials requests (each a round trip with workers) */
    double overlap_now;   /* the overlap of the batch being evaluated */
    lm_wire_arena arena;
    lm_replica rep; /* the workers' current records, which patches are encoded against */
    /* the whole-edge run's (run_edges): batches are not recorded nor encoded there */
    int light;
    double commit_enc_s;  /* encoding the commits' messages (the coordinator's, with workers) */
    double replica_s;     /* the replica of the workers' records that they are encoded against */
    double state_wall_s;  /* the views' state requests' time (their CPU: state_cpu_s) */
    double commit_wall_s; /* of which the commits: what every worker spends applying them */
    double pot_wall_s;    /* and the potentials: the views' work for the oracle */
    double plan_s;        /* the optimizer's own work around it: the oracle's ranking, the plan */
    double step_c0, pot_end; /* CPU at the step's start, at the end of its potentials */
    int plan_open;           /* potentials done, the optimizer still planning */
} meter;

double sc_wall(void);
double sc_cpu(void);
/* The first request after an iteration's potentials: the planning around them is over. */
void sc_close_plan(meter *m);
/* The meter over new in-process views, and *mesh a copy of the start for an optimizer. */
lm_status sc_meter_start(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                         const lm_view_set *vs, int light, meter *m, lm_mesh **mesh);
/* The lanes' runs' meter, as the job's views: the geometric term where the views hold it
 * (surface_term and evaluate_surface forwarded; sc_meter_start's meter offers neither); over
 * remote views of the pool's workers, each serving every view (co_views_desc.whole, lanes on the
 * workers), with the audit rule (NULL: none), or with pool NULL in-process views. */
lm_status sc_meter_start_on(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                            const lm_view_set *vs, int light, co_pool *pool,
                            const co_audit_rule *audit, meter *m, lm_mesh **mesh);

/* ---- today's schedule: one evaluation the unit (per_eval.c) ---------------------------------- */

typedef struct costs {
    uint32_t k;
    uint64_t evals, batches;
    double per_patch_view_us;   /* c */
    double coord_us_per_eval;   /* the optimizer and encoding */
    double overlap_us_per_eval; /* of which the geometric term (the workers' with workers) */
    double bytes_per_batch, patches_per_batch, commit_bytes;
    double tris_per_patch, moved_share; /* added records a patch; share with corners moved */
    double state_us_per_eval;           /* the views' commits, meshes, energies, potentials */
    double round_trips, commits, total_commit_bytes; /* of the run */
    double setup_s;                                  /* the optimizer's set-up, once */
    double t_local_s;                                /* sum of the in-process T_i */
    const meter *m;
} costs;

lm_status sc_run_once(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                      const lm_view_set *vs, uint32_t k, meter *m, costs *c);
/* Predicted speed-up over in process for w workers at a round trip of rtt_us. */
double sc_speedup_at(const opts *o, const costs *c, uint32_t views, uint32_t w, double rtt_us);
double sc_speedup(const opts *o, const costs *c, uint32_t views, uint32_t w);

/* ---- whole edges, one at a time: the costs per edge (edge_costs.c) --------------------------- */

/* One step of the optimizer in the whole-edge run: one planned edge (with the planned edges
 * before it that were gone, which cost nothing), its costs in seconds. */
typedef struct edge_rec {
    uint32_t evals, edges, ops; /* evaluations; planned edges; operations it kept (accepted) */
    uint32_t plans;             /* oracle requests before it (an iteration began) */
    uint32_t near; /* with operations: edges back to the last earlier edge whose footprint meets
                      its own (0: none); footprint: the vertices of its patch's triangles */
    float cost_s;  /* in process on one worker: the views' time and all other CPU of the edge */
    float views_s; /* of which the views' time (what a node's processes split) */
    float plan_s;  /* the coordinator's planning before it (the oracle's ranking, the plan) */
    float pot_s;   /* the views' work of that planning (potentials) */
    float apply_s; /* the views' commits of its operations: what every worker does to apply them */
    float merge_s; /* the coordinator's merge: replay, patch, encoding (0 without operations) */
    float bytes;   /* its operations' Commit messages (0 without operations) */
} edge_rec;

typedef struct edges_run {
    edge_rec *e;
    size_t n, cap;
    uint64_t evals, planned, replays, mismatches;
    double per_patch_view_us, geo_us_per_eval, replay_s;
    double views_cpu_per_wall; /* the views' evaluations: CPU seconds per second (threads) */
    size_t mesh_edges;         /* of the start */
    uint32_t *last;            /* per vertex: 1 + the last edge whose footprint held it */
    size_t cap_last;
} edges_run;

/* One edge at a time, each optimiser step one edge, until --edge-evals: the costs per edge. */
lm_status sc_run_edges(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                       const lm_view_set *vs, meter *m, edges_run *er);

/* Edge i of a modelled pass: the measured sequence, cycled. */
static inline const edge_rec *sc_pass_edge(const edges_run *er, size_t i)
{
    return &er->e[i % er->n];
}

/* The distribution of the measured edges. */
typedef struct edge_stats {
    double evals_mean, evals_median, evals_p90, evals_p99, evals_max;
    double ms_mean, ms_max, top_share; /* top_share: of all the edges' cost, the costliest 1%'s */
    double ops_mean, with_ops, bytes_mean;
} edge_stats;

edge_stats sc_edge_stats(const edges_run *er);

/* ---- the rounds model (rounds.c) ------------------------------------------------------------- */

typedef struct whole_edges {
    double t1, tw;          /* the pass in process; with w workers */
    double plan_s, merge_s; /* the coordinator's CPU: planning, merges */
    double evals;           /* evaluations, the merges' re-validations included */
    /* where tw goes: planning (with its requests), handing out (a round trip, the commits'
     * bytes), applying the last round's commits, the edges (makespan, results back), merging,
     * re-validating; and the edges' work spread perfectly (their sum / w) */
    double plan, hand_out, apply, edges, merge, revalidate, balanced;
} whole_edges;

/* The pass as rounds of r edges on w workers over V views. */
whole_edges sc_rounds_at(const opts *o, const edges_run *er, uint32_t views, uint32_t w,
                         uint32_t r);
double sc_rounds_speedup(const opts *o, const edges_run *er, uint32_t views, uint32_t w,
                         uint32_t r);
/* The smallest round (a power of 2, at most 65536) with efficiency >= eff on w workers; 0 if
 * none. */
uint32_t sc_round_for(const opts *o, const edges_run *er, uint32_t views, uint32_t w, double eff);
/* The rounds the report prints: 64, --round, 1024, in order, once each. */
uint32_t sc_report_rounds(const opts *o, uint32_t out[3]);

/* ---- the window's plan order as visits (visits.c) -------------------------------------------- */

/* The visits in plan order: an edge's optimisation cut after `cap` evaluations (0: never), the
 * rest a continuation at least d positions later (the rule: visits.c). */
typedef struct visits {
    edge_rec *v;
    size_t n, cap;
    size_t edges;    /* the pass's edges (the measured ones, cycled) */
    size_t started;  /* edges with a visit placed: the pass's and those filling in */
    double restarts; /* continuation visits (n - started) */
} visits;

void sc_visits_make(const edges_run *er, uint32_t cap, uint32_t d, visits *out);
void sc_visits_free(visits *v);

/* ---- the window model (window.c) ------------------------------------------------------------- */

typedef struct window {
    double t1, tw;       /* the pass in process; with w processes */
    double coord_s;      /* the coordinator's CPU: planning and merges */
    double evals;        /* evaluations, re-validations included */
    double revalidated;  /* edges re-validated */
    double with_ops;     /* edges that kept operations */
    uint32_t nodes, per; /* nodes, processes per node */
    /* of the nodes' time (nodes * tw): the edges' work (of it the synchronisation), applying
     * the others' commits, re-validating, waiting for the window, for a plan, idle at the end */
    double work, sync, apply, reval, wait_window, wait_plan, tail;
    double link_s; /* the coordinator's link: every commit to every node, the edges out */
    double visits, edges, restarts; /* visits modelled, edges begun in them, continuations */
} window;

/* The pass in plan order on w processes in nodes of `group`, lag d, a node's synchronisation
 * per evaluation sync_us, visits capped at `cap` evaluations (0: whole edges). */
window sc_window_at(const opts *o, const edges_run *er, uint32_t views, uint32_t w, uint32_t d,
                    uint32_t group, double sync_us, uint32_t cap);

/* ---- whole lanes on workers: the isolated-lane engine measured (lanes_run.c) ----------------- */

/* A lane of the run as the merge saw it. */
typedef struct lane_rec {
    uint32_t evals, ops;
    int outcome;        /* LM_LANE_* (common/optimizer/lanes.h) */
    float result_bytes; /* its result message (records, logs, touched set; lanes_run.c) */
} lane_rec;

/* A group of the run: its lanes lanes[first .. first + n); the costs in seconds of CPU. */
typedef struct group_rec {
    uint32_t first, n;
    uint32_t revals;    /* re-validations (one evaluation each) */
    float plan_s;       /* the coordinator's CPU before it: the oracle's ranking, the plan */
    float pot_s;        /* the views' work of that planning (potentials: the workers') */
    float snap_s;       /* the lanes' snapshots (a worker's copies of its replica's state) */
    float lanes_s;      /* the lanes in process: the views' time and the lanes' own CPU */
    float merge_s;      /* the coordinator's merge CPU: replays, logs, encoding the commits */
    float reval_s;      /* the views' CPU of its re-validations */
    float apply_s;      /* the views' commits: what every worker spends applying them */
    float commit_bytes; /* the merged commits' messages (what is broadcast) */
    /* the process's whole CPU in the group's phases: from the last merge to its start (planning,
       the potentials' requests), its lanes (with --lanes remote: the coordinator dispatching
       them, encoding the starts, queues and requests, decoding the results), its merge (the
       re-validations' requests and the commits to the remote views included) */
    float cpu_plan, cpu_lanes, cpu_merge;
} group_rec;

typedef struct lanes_run {
    uint32_t k; /* edges in flight (lanes per group at most) */
    group_rec *g;
    size_t n_g, cap_g;
    lane_rec *l;
    size_t n_l, cap_l;
    uint64_t evals;     /* the lanes' evaluations (re-validations apart) */
    double eval_s;      /* a worker's time per evaluation, all views (the lanes' CPU) */
    double eval_wall_s; /* the same from the lanes' wall time (this machine is shared) */
    double lanes_wall_s, lanes_views_cpu_s;
    double per_patch_view_us; /* the views' share of eval_s, per view */
    double energy_rel;        /* the energy at the end over the start's */
    double wall_s;            /* the run in process */
    /* the remote run's (sc_run_lanes_remote): the lanes' runs on workers, audits included */
    uint32_t workers;
    uint64_t lane_runs, audits;
    double coord_cpu_s; /* the coordinator's CPU over the run (every phase) */
    co_lane_stats lane_stats;
    /* the job's regrids in the run (every js->regrid_every evaluations): count, the process's CPU
       (in process: what each worker spends, every worker rendering every view's targets) and wall
       time */
    uint32_t regrids;
    double regrid_cpu_s, regrid_wall_s;
    /* of regrid_cpu_s, the targets' renders (the new views made); one targets asset's bytes (the
       view set's luminance: what a split bring-up ships to every worker, proto/asset.h) */
    double regrid_target_cpu_s, target_bytes;
    /* in process: the remote run of the same K (sc_run_lanes_remote), whose coordinator's CPU the
       model takes (NULL: the in-process planning and merge only) */
    const struct lanes_run *coord;
} lanes_run;

#define SC_LANE_REQUEST_BYTES 64.0 /* a lane's request: its edge, index, group, snapshot id */

/* The job's set-up (co_job_setup_make) for --schedule lanes: the model, --initial or --start,
 * --target-verts, --views, --size (0: the job's defaults), --plan, seed 1. */
lm_status sc_job_setup(const opts *o, co_job_setup *js);
/* The isolated-lane engine (lm_params.lane_isolation) at k edges in flight, until --edge-evals,
 * with the job's parameters and tuning (js). */
lm_status sc_run_lanes(const opts *o, const co_job_setup *js, uint32_t k, lanes_run *out);
/* The same job as --lanes remote runs it on `workers` local lumesh-worker processes (the job's
 * audit rule, no spinning): what the coordinator's own CPU costs per group (group_rec.cpu_*) and
 * per evaluation; its lanes' evaluations are those of the lanes' reports. The worker program:
 * LUMESH_WORKER, else beside lumesh's build (the pool's search). */
lm_status sc_run_lanes_remote(const opts *o, const co_job_setup *js, uint32_t k, uint32_t workers,
                              lanes_run *out);
void sc_lanes_free(lanes_run *r);

/* ---- the whole-lane model (lanes_model.c) ---------------------------------------------------- */

typedef struct lanes_model {
    double t1, tw;  /* the run in one process; on w workers */
    double coord_s; /* the coordinator's CPU: planning and merges */
    double evals;   /* evaluations, re-validations included */
    /* where tw goes: planning, handing out (with the last commits), the workers' replicas
     * updated, the groups' slowest workers, results back, the merges, re-validations; and the
     * lanes' work spread perfectly (their sum / w) */
    double plan, hand_out, update, lanes, results, merge, revalidate, balanced;
    double dispatch; /* the coordinator's CPU dispatching the lanes (remote run measured; else 0) */
    double regrid;   /* the job's regrids: the targets rendered split over the workers (each
                        ceil(V / min(W, V)) views), read back, shipped to every worker; the rest of
                        each regrid (the energies) on every worker at once */
    double coord_measured; /* 1: the coordinator's terms from a remote run */
} lanes_model;

/* The run's groups on w workers over V views (the formula: lanes_model.c). */
lanes_model sc_lanes_at(const opts *o, const lanes_run *r, uint32_t views, uint32_t w);
/* The run (of runs[0..n)) whose K a cluster of w workers uses: the smallest K >= w x per (lanes
 * per worker), else the largest. */
const lanes_run *sc_lanes_for(const lanes_run *runs, uint32_t n, uint32_t w, uint32_t per);
void sc_print_lanes_human(const opts *o, const co_job_setup *js, const lanes_run *runs, uint32_t n,
                          uint32_t views);
void sc_print_lanes_json(const opts *o, const co_job_setup *js, const lanes_run *runs, uint32_t n,
                         uint32_t views);

/* ---- round trips measured here (rtt.c) ------------------------------------------------------- */

/* Round trips measured here, in µs. */
typedef struct rtts {
    double link, zmq, floor; /* a local worker's link, the ZeroMQ ipc socket, a bare socketpair */
    double link_one_core;    /* the link, coordinator and worker on one core (0: not measured) */
} rtts;

lm_status sc_measure_rtt(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                         const lm_view_set *vs, int socket_only, double *us);
lm_status sc_measure_rtt_one_core(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                                  const lm_view_set *vs, double *us);
lm_status sc_measure_floor_rtt(double *us);

/* ---- report (report.c) ----------------------------------------------------------------------- */

void sc_print_human(const opts *o, const costs *c, uint32_t views, const rtts *t,
                    const edges_run *er);
void sc_print_json(const opts *o, const costs *c, uint32_t views, const rtts *t,
                   const edges_run *er);

#endif
