/* tests/bench/bench_simplify.c — the image-driven simplifier's speed: one model (QEM to --start
 * vertices first when larger) simplified by image-driven collapses to --target vertices, in this
 * process and through 1, 2, ... lumesh-worker processes (--workers LIST), reporting collapses per
 * second, evaluations, evaluate calls and the queue's re-pricing, and checking that every run made
 * the same mesh. Numbers, not pass/fail (the machine's other load moves them: compare ratios of
 * runs made together).
 *
 * usage: bench_simplify MODEL [--target N (100)] [--start N (10 x target)] [--views N (20)]
 *        [--size S (256)] [--workers LIST (0,1,2)] [--method image|shard] [--device D (host)]
 *        [--batch N (256)] [--rebatch N (64)] [--no-footprints] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "coordinator/pool/pool.h"
#include "coordinator/quality/view_setup.h"
#include "coordinator/simplify/isimp.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/simplify/work.h"

typedef struct opts {
    const char *path, *device, *workers;
    uint32_t target, start, views, size, batch, rebatch;
    co_price_method method;
    int no_footprints;
} opts;

static int parse(int argc, char **argv, opts *o)
{
    *o = (opts){.device = "host", .workers = "0,1,2", .target = 100, .views = 20, .size = 256};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--no-footprints")) {
            o->no_footprints = 1;
            continue;
        }
        if (a[0] != '-') {
            o->path = a;
            continue;
        }
        if (!v)
            return 0;
        i++;
        if (!strcmp(a, "--target"))
            o->target = (uint32_t)atoi(v);
        else if (!strcmp(a, "--start"))
            o->start = (uint32_t)atoi(v);
        else if (!strcmp(a, "--views"))
            o->views = (uint32_t)atoi(v);
        else if (!strcmp(a, "--size"))
            o->size = (uint32_t)atoi(v);
        else if (!strcmp(a, "--batch"))
            o->batch = (uint32_t)atoi(v);
        else if (!strcmp(a, "--rebatch"))
            o->rebatch = (uint32_t)atoi(v);
        else if (!strcmp(a, "--workers"))
            o->workers = v;
        else if (!strcmp(a, "--device"))
            o->device = v;
        else if (!strcmp(a, "--method"))
            o->method = !strcmp(v, "shard") ? CO_PRICE_SHARD : CO_PRICE_IMAGE;
        else
            return 0;
    }
    return o->path != NULL;
}

/* One run with `workers` worker processes (0: in process); the result's hash. */
static lm_status run(const opts *o, const lm_mesh *orig, const lm_mesh *start, uint32_t workers,
                     uint64_t *hash)
{
    lm_mesh *m = NULL;
    lm_view_set *vs = NULL;
    co_pool *pool = NULL;
    lm_views *v = NULL;
    int derived = 0;
    lm_status st = lm_mesh_clone(start, &m);
    if (!st)
        st = co_simplify_prepare(m, &derived);
    if (!st)
        st = co_view_set_around(orig, o->views, (int)o->size, 0, &vs);
    co_simplify_workers w = {.local = workers};
    if (!st)
        st = co_simplify_pool_start(&w, o->device, &pool);
    if (!st)
        st = co_simplify_make_views(o->method, orig, m, vs, o->device, pool, &v);
    co_isimp_config cfg = {.method = o->method,
                           .target_verts = o->target,
                           .views = vs,
                           .derived_normals = derived,
                           .max_batch = o->batch,
                           .rebatch_edges = o->rebatch,
                           .unsafe_no_footprints = o->no_footprints};
    co_isimp_stats s;
    if (!st)
        st = co_isimp_run(m, v, &cfg, &s);
    if (!st) {
        *hash = lm_mesh_hash(m);
        printf("{\"workers\": %u, \"start_verts\": %u, \"verts\": %u, \"collapses\": %u, "
               "\"seconds\": %.2f, \"collapses_per_s\": %.2f, \"evaluations\": %llu, "
               "\"evals_per_s\": %.1f, \"calls\": %llu, \"edge_prices\": %llu, \"stale_pops\": "
               "%llu, \"marked_stale\": %llu, \"renders\": %llu, \"hash\": \"%016llx\"}\n",
               workers, start->live_verts, m->live_verts, s.collapses, s.seconds,
               s.collapses / s.seconds, (unsigned long long)s.evaluations,
               s.evaluations / s.seconds, (unsigned long long)s.calls,
               (unsigned long long)s.edge_prices, (unsigned long long)s.stale_pops,
               (unsigned long long)s.marked_stale, (unsigned long long)s.renders,
               (unsigned long long)*hash);
        fflush(stdout);
    }
    lm_views_destroy(v);
    co_pool_destroy(pool);
    free(vs);
    lm_mesh_destroy(m);
    return st;
}

int main(int argc, char **argv)
{
    opts o;
    if (!parse(argc, argv, &o)) {
        fprintf(stderr, "usage: bench_simplify MODEL [--target N] [--start N] [--views N] "
                        "[--size S] [--workers LIST] [--method image|shard] [--device D] "
                        "[--batch N] [--rebatch N] [--no-footprints]\n");
        return 1;
    }
    lm_mesh *orig = NULL, *start = NULL;
    lm_status st = lm_mesh_load(o.path, NULL, &orig);
    uint32_t n = st ? 0 : co_simplify_start_verts(orig->live_verts, o.target, o.start);
    if (!st && n < orig->live_verts) {
        st = co_simplify(orig, CO_SIMPLIFY_QEM, n, &start);
        st = st == LM_E_RANGE && start ? LM_OK : st;
    } else if (!st) {
        st = lm_mesh_clone(orig, &start);
    }
    uint64_t first = 0, h = 0;
    for (const char *p = o.workers; !st && p && *p;
         p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL) {
        st = run(&o, orig, start, (uint32_t)atoi(p), &h);
        if (!st && first && h != first)
            fprintf(stderr, "bench_simplify: results differ between runs!\n");
        first = first ? first : h;
    }
    if (st)
        fprintf(stderr, "bench_simplify: %s\n", lm_last_error());
    lm_mesh_destroy(orig);
    lm_mesh_destroy(start);
    return st ? 2 : 0;
}
