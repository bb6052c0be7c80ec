/* tests/bench/bench_optimize.c — the optimizer end to end on a real model: QEM-simplify the
 * original to a fraction of its vertices, optimise against N views, and report at intervals the
 * energy on the optimisation views and on the 24 held-out views (both relative to the QEM start),
 * evaluations per second and moves by kind. The quality goal is measured with this.
 *
 * usage: bench_optimize ORIGINAL [--frac F (0.01)] [--verts N] [--views N (20)] [--size S (256)]
 *        [--evals N (300000)] [--every N (25000)] [--seed S (1)] [--device D (auto)]
 *        [--attrs normal,uv,color] [--cluster] [--out FILE] [--initial FILE] [--epd N]
 *        [--set NAME=VALUE ...] (tuning, see set_tuning; surface_weight=W: the geometric term)
 *        [--k K [--isolated [--detached]]] (K edges in flight, isolated lanes, run detached: each
 *        lane through its wire messages on a host of its own; prints their sizes at the end) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/io/mesh_io.h"
#include "common/log.h"
#include "common/mesh_topology.h"
#include "common/optimizer/optimizer.h"
#include "common/optimizer/optimizer_tuning.h"
#include "common/view.h"
#include "coordinator/simplify/simplify.h"
#include "worker/render/views_local.h"

typedef struct opts {
    const char *path, *device, *out, *initial;
    double frac;
    uint32_t verts, views, attrs;
    int size, cluster;
    uint64_t evals, every, seed;
    uint32_t evals_per_dim;
    uint32_t k;
    int isolated, detached;
    lm_tuning tune;
} opts;

/* --set NAME=VALUE for the tuning numbers. */
static int set_tuning(lm_tuning *t, const char *kv)
{
    const char *eq = strchr(kv, '=');
    if (!eq)
        return 0;
    double x = atof(eq + 1);
    size_t n = (size_t)(eq - kv);
    struct {
        const char *name;
        double *d;
        uint32_t *u;
    } f[] = {{"pos_step", &t->moves.pos_step, NULL},
             {"normal_step", &t->moves.normal_step, NULL},
             {"uv_step", &t->moves.uv_step, NULL},
             {"color_step", &t->moves.color_step, NULL},
             {"size_tol", &t->moves.size_tol, NULL},
             {"f_rtol", &t->moves.f_rtol, NULL},
             {"max_set", NULL, &t->moves.max_set_verts},
             {"max_dim", NULL, &t->moves.max_dim},
             {"thr_half_life", &t->teleport.threshold_half_life, NULL},
             {"improve_half_life", &t->teleport.stats_half_life, NULL},
             {"search_evals", NULL, &t->teleport.max_search_evals},
             {"half_life", &t->stats_half_life, NULL},
             {"min_weight", &t->stats_min_weight, NULL},
             {"share", &t->oracle_share, NULL},
             {"share_min", &t->oracle_min_share, NULL},
             {"share_max", &t->oracle_max_share, NULL},
             {"surface_weight", &t->surface_weight, NULL}};
    for (size_t i = 0; i < sizeof f / sizeof *f; i++)
        if (strlen(f[i].name) == n && !strncmp(f[i].name, kv, n)) {
            if (f[i].d)
                *f[i].d = x;
            else
                *f[i].u = (uint32_t)x;
            return 1;
        }
    return 0;
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int parse(int argc, char **argv, opts *o)
{
    *o = (opts){.device = "auto",
                .frac = 0.01,
                .views = 20,
                .size = 256,
                .evals = 300000,
                .every = 25000,
                .seed = 1};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (a[0] != '-') {
            o->path = a;
            continue;
        }
        int *flag = !strcmp(a, "--cluster")    ? &o->cluster
                    : !strcmp(a, "--isolated") ? &o->isolated
                    : !strcmp(a, "--detached") ? &o->detached
                                               : NULL;
        if (flag) {
            *flag = 1;
            continue;
        }
        if (!v)
            return 0;
        i++;
        if (!strcmp(a, "--frac"))
            o->frac = atof(v);
        else if (!strcmp(a, "--verts"))
            o->verts = (uint32_t)atol(v);
        else if (!strcmp(a, "--views"))
            o->views = (uint32_t)atol(v);
        else if (!strcmp(a, "--size"))
            o->size = atoi(v);
        else if (!strcmp(a, "--evals"))
            o->evals = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--every"))
            o->every = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--seed"))
            o->seed = strtoull(v, NULL, 10);
        else if (!strcmp(a, "--device"))
            o->device = v;
        else if (!strcmp(a, "--out"))
            o->out = v;
        else if (!strcmp(a, "--set")) {
            if (!set_tuning(&o->tune, v))
                return 0;
        } else if (!strcmp(a, "--k"))
            o->k = (uint32_t)atol(v);
        else if (!strcmp(a, "--epd"))
            o->evals_per_dim = (uint32_t)atol(v);
        else if (!strcmp(a, "--initial"))
            o->initial = v;
        else if (!strcmp(a, "--attrs"))
            o->attrs = (strstr(v, "normal") ? LM_ATTR_NORMAL : 0) |
                       (strstr(v, "uv") ? LM_ATTR_UV : 0) |
                       (strstr(v, "color") ? LM_ATTR_COLOR : 0);
        else
            return 0;
    }
    return o->path != NULL;
}

static lm_status energy_of(lm_views *v, const lm_mesh *m, int64_t *e)
{
    lm_tri_data *t;
    size_t n;
    lm_status st = lm_mesh_export_tris(m, &t, &n);
    if (st)
        return st;
    st = v->ops->set_mesh(v, t, n);
    free(t);
    return st ? st : v->ops->energy(v, e, NULL);
}

static lm_status make_coarse(const opts *o, const lm_mesh *orig, lm_mesh **out)
{
    lm_status st;
    if (o->initial) {
        st = lm_mesh_load(o->initial, NULL, out);
    } else {
        uint32_t target = o->verts ? o->verts : (uint32_t)(o->frac * orig->live_verts + 0.5);
        st = co_simplify(orig, o->cluster ? CO_SIMPLIFY_CLUSTER : CO_SIMPLIFY_QEM, target, out);
        if (st == LM_E_RANGE && *out)
            st = LM_OK;
    }
    if (st)
        return st;
    if (!(o->attrs & LM_ATTR_NORMAL)) {
        lm_mesh_merge_wedges(*out, LM_ATTR_UV | LM_ATTR_COLOR);
        lm_mesh_compute_normals(*out);
    }
    if (!(st = lm_mesh_compact(*out)))
        st = lm_mesh_build_adjacency(*out);
    return st;
}

static void report(lm_optimizer *opt, lm_views *held, int64_t held0, double t0)
{
    lm_progress p;
    lm_optimizer_progress(opt, &p);
    int64_t h = 0;
    energy_of(held, lm_optimizer_mesh(opt), &h);
    double dt = now() - t0;
    printf("evals %8llu  train %6.2f%%  heldout %6.2f%%  %6.0f ev/s  %5.0fs  it %llu  "
           "noop %llu/%llu swap %llu/%llu tele %llu/%llu coll %llu/%llu  verts %u\n",
           (unsigned long long)p.evals, 100.0 * p.energy / p.energy_start, 100.0 * h / held0,
           p.evals / (dt > 0 ? dt : 1), dt, (unsigned long long)p.iterations,
           (unsigned long long)p.accepted[0], (unsigned long long)p.attempted[0],
           (unsigned long long)p.accepted[1], (unsigned long long)p.attempted[1],
           (unsigned long long)p.accepted[2], (unsigned long long)p.attempted[2],
           (unsigned long long)p.accepted[3], (unsigned long long)p.attempted[3], p.live_verts);
    fflush(stdout);
}

/* What detached lanes sent and got back. */
static void print_traffic(const lm_optimizer *opt, double seconds)
{
    lm_lane_traffic t;
    lm_optimizer_lane_traffic(opt, &t);
    double n = t.lanes ? (double)t.lanes : 1;
    printf("detached lanes %llu: request %.0f B mean, %llu max; result %.0f B mean, %llu max; "
           "%.1f evaluations per lane; %.3f ms per lane\n",
           (unsigned long long)t.lanes, (double)t.request_bytes / n,
           (unsigned long long)t.request_max, (double)t.result_bytes / n,
           (unsigned long long)t.result_max, (double)t.evals / n, 1e3 * seconds / n);
}

static lm_status bench(const opts *o)
{
    lm_mesh *orig, *coarse;
    lm_status st = lm_mesh_load(o->path, NULL, &orig);
    if (st || (st = make_coarse(o, orig, &coarse)))
        return st;
    printf("original %u vertices, coarse %u vertices %u triangles\n", orig->live_verts,
           coarse->live_verts, coarse->live_tris);
    float c[3], r;
    lm_mesh_bounding_sphere(orig, c, &r);
    lm_view_set *vs = malloc(sizeof *vs), *hs = malloc(sizeof *hs);
    lm_views *v = NULL, *held = NULL;
    int64_t held0 = 0;
    if (!(st = lm_view_set_make(vs, o->views, o->size, c, r)) &&
        !(st = lm_view_set_make_heldout(hs, o->size, c, r)) &&
        !(st = wk_views_local_create(orig, vs, 0, 0, o->device, &v)) &&
        !(st = wk_views_local_create(orig, hs, 0, 0, o->device, &held)))
        st = energy_of(held, coarse, &held0);
    lm_optimizer *opt = NULL;
    lm_params p = {.seed = o->seed,
                   .attrs = o->attrs,
                   .simplex_evals_per_dim = o->evals_per_dim,
                   .edges_in_flight = o->k,
                   .lane_isolation = (uint32_t)o->isolated,
                   .surface = orig};
    if (!st)
        st = lm_optimizer_create_tuned(coarse, v, &p, &o->tune, &opt);
    if (!st)
        st = lm_optimizer_set_lanes_detached(opt, o->detached);
    else
        lm_mesh_destroy(coarse);
    double t0 = now();
    for (uint64_t next = o->every; !st;) {
        lm_progress pr;
        lm_optimizer_progress(opt, &pr);
        if (pr.evals >= next || pr.evals >= o->evals) {
            report(opt, held, held0, t0);
            next += o->every;
        }
        if (pr.evals >= o->evals)
            break;
        st = lm_optimizer_step(opt, o->evals);
    }
    if (!st && o->detached)
        print_traffic(opt, now() - t0);
    if (!st && o->out)
        st = lm_mesh_save(o->out, lm_optimizer_mesh(opt));
    lm_optimizer_destroy(opt);
    lm_views_destroy(v);
    lm_views_destroy(held);
    lm_mesh_destroy(orig);
    free(vs);
    free(hs);
    return st;
}

int main(int argc, char **argv)
{
    opts o;
    if (getenv("LUMESH_DEBUG"))
        lm_log_set_level(LM_LOG_DEBUG);
    if (!parse(argc, argv, &o)) {
        fprintf(stderr, "usage: bench_optimize ORIGINAL [--frac F] [--verts N] [--views N] "
                        "[--size S] [--evals N] [--every N] [--seed S] [--device D] "
                        "[--attrs LIST] [--cluster] [--initial FILE] [--out FILE] "
                        "[--k K [--isolated [--detached]]]\n");
        return 1;
    }
    lm_status st = bench(&o);
    if (st) {
        fprintf(stderr, "bench_optimize: %s\n", lm_last_error());
        return lm_exit_code(st);
    }
    return 0;
}
