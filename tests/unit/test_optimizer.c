/* tests/unit/test_optimizer.c — the whole optimizer against the real in-process views (software
 * device, 12 views of 64x64) on a noisy coarse sphere: energy falls and the tracked energy equals
 * the views'; the vertex count stays; the same seed gives the same mesh; save -> load -> continue
 * ends in exactly the state of an uninterrupted run (mesh hash, counters, and the whole saved
 * state byte for byte), also when saved in the middle of an iteration; bad checkpoints are refused
 * and leave the optimizer as it was. With the geometric term: the image energy is still the
 * views', the term is what a fresh one says of the result and falls, runs are deterministic and
 * resume exactly, and a checkpoint of one kind is refused by the other. With K edges in flight
 * and isolated lanes (lm_params.lane_isolation): running each group's lanes in another order
 * (reversed, shuffled) leaves the whole saved state byte for byte as in lane order, for K = 4 and
 * 8, while shared lanes depend on it; the energy still falls and is the views'; a resume is exact
 * and a state of the other lane mode is refused. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/mesh_topology.h"
#include "common/optimizer/lane_host.h"
#include "common/optimizer/lane_runner.h"
#include "common/optimizer/lane_start.h"
#include "common/optimizer/lane_wire.h"
#include "common/optimizer/optimizer.h"
#include "common/optimizer/optimizer_tuning.h"
#include "common/optimizer/surface_term.h"
#include "common/view.h"
#include "test_support.h"
#include "worker/render/views_local.h"

#define N_VIEWS 12
#define SIZE 64

/* runs with the geometric term (surface_term.h) against the original: 1 of weight SURFACE_WEIGHT,
 * 2 of SURFACE_SHARE of the start's image energy */
static int g_surface;
#define SURFACE_WEIGHT 1.0
#define SURFACE_SHARE 0.25
/* the views' device: the host's, or the CPU rasteriser's (the lanes' tests) */
static const char *g_device = "host";
/* the start's subdivision level (the original is one finer) */
static int g_level = 2;
/* lanes run detached (lm_optimizer_set_lanes_detached) in the runs started; their traffic */
static int g_detached; /* 1: lm_optimizer_set_lanes_detached; 2: a lane runner (below) */
static lm_lane_traffic g_traffic;

/* A lane runner as a worker process would be (--lanes remote): the config and the start mesh
 * through their bytes into a mesh of its own (placeholder materials), each lane's request and
 * result through theirs, the lanes run in reverse order against the views (committed to the
 * start). */
typedef struct test_runner {
    lm_views *views;
    lm_lane_host *host;
    uint64_t groups;
} test_runner;
static test_runner g_runner;

static lm_status test_run_lanes(void *ctx, const lm_lane_batch *b)
{
    test_runner *t = ctx;
    uint8_t *buf = NULL;
    size_t len = 0;
    lm_moves_config cfg;
    assert_int_equal(lm_lane_config_encode(b->cfg, &buf, &len), LM_OK);
    assert_int_equal(lm_lane_config_decode(buf, len, &cfg), LM_OK);
    free(buf);
    if (!t->host)
        assert_int_equal(lm_lane_host_create(&cfg, &t->host), LM_OK);
    lm_mesh *start = NULL;
    assert_int_equal(lm_lane_mesh_encode(b->start, &buf, &len), LM_OK);
    assert_int_equal(lm_mesh_create(&start), LM_OK);
    assert_int_equal(lm_lane_mesh_decode(buf, len, start), LM_OK);
    free(buf);
    assert_true(lm_mesh_hash(start) == lm_mesh_hash(b->start));
    lm_lane_request q;
    lm_lane_result r;
    lm_lane_request_init(&q);
    lm_lane_result_init(&r);
    for (uint32_t j = b->n; j-- > 0;) { /* a request is its head followed by the queue */
        uint8_t *whole = malloc(b->req_len[j] + b->queue_len);
        assert_non_null(whole);
        memcpy(whole, b->req[j], b->req_len[j]);
        memcpy(whole + b->req_len[j], b->queue, b->queue_len);
        assert_int_equal(lm_lane_request_decode(whole, b->req_len[j] + b->queue_len, &q), LM_OK);
        free(whole);
        assert_int_equal(lm_lane_host_run(t->host, start, t->views, &q, t->groups + 1, &r), LM_OK);
        assert_int_equal(lm_lane_result_encode(&r, &buf, &len), LM_OK);
        assert_int_equal(lm_lane_result_decode(buf, len, b->n_verts, b->res[j]), LM_OK);
        *b->result_bytes += len;
        free(buf);
    }
    lm_lane_request_free(&q);
    lm_lane_result_free(&r);
    lm_mesh_destroy(start);
    t->groups++;
    return LM_OK;
}

typedef struct run {
    lm_mesh *orig;
    lm_view_set vs;
    lm_views *v;
    lm_optimizer *o;
} run;

static lm_mesh *noisy_sphere(void)
{
    lm_mesh *m = lmt_make_sphere(g_level);
    for (uint32_t i = 0; i < m->n_verts; i++)
        for (int k = 0; k < 3; k++)
            m->pos[i][k] *= 1.0f + 0.12f * sinf(7.0f * (float)i + 1.0f);
    return m;
}

/* A run with k edges in flight, isolated lanes or not, its lanes run in `order`
 * (lm_optimizer_set_lane_order). */
static void run_start_lanes(run *r, uint64_t seed, uint32_t k, uint32_t isolated, uint64_t order);

static void run_start(run *r, uint64_t seed)
{
    run_start_lanes(r, seed, 1, 0, 0);
}

static void run_start_lanes(run *r, uint64_t seed, uint32_t k, uint32_t isolated, uint64_t order)
{
    memset(r, 0, sizeof *r);
    r->orig = lmt_make_sphere(g_level + 1);
    float c[3], rad;
    lm_mesh_bounding_sphere(r->orig, c, &rad);
    assert_int_equal(lm_view_set_make(&r->vs, N_VIEWS, SIZE, c, rad), LM_OK);
    assert_int_equal(wk_views_local_create(r->orig, &r->vs, 0, 0, g_device, &r->v), LM_OK);
    lm_params p = {.seed = seed,
                   .edges_in_flight = k,
                   .lane_isolation = isolated,
                   .surface = g_surface ? r->orig : NULL};
    lm_tuning t = {.surface_weight = g_surface == 1 ? SURFACE_WEIGHT : 0,
                   .surface_share = g_surface == 2 ? SURFACE_SHARE : 0};
    assert_int_equal(lm_optimizer_create_tuned(noisy_sphere(), r->v, &p, &t, &r->o), LM_OK);
    lm_optimizer_set_lane_order(r->o, order);
    assert_int_equal(lm_optimizer_set_lanes_detached(r->o, g_detached == 1), LM_OK);
    if (g_detached == 2) {
        lm_lane_host_destroy(g_runner.host);
        g_runner = (test_runner){.views = r->v};
        lm_optimizer_set_lane_runner(r->o, &(lm_lane_runner){test_run_lanes, &g_runner});
    }
}

static void run_free(run *r)
{
    lm_optimizer_destroy(r->o);
    lm_views_destroy(r->v);
    lm_mesh_destroy(r->orig);
}

static void run_to(run *r, uint64_t evals)
{
    lm_progress p;
    for (int guard = 0; guard < 10000; guard++) {
        lm_optimizer_progress(r->o, &p);
        if (p.evals >= evals)
            return;
        assert_int_equal(lm_optimizer_step(r->o, evals), LM_OK);
    }
    fail_msg("no progress towards %llu evaluations", (unsigned long long)evals);
}

static int64_t views_energy(lm_views *v)
{
    int64_t e;
    assert_int_equal(v->ops->energy(v, &e, NULL), LM_OK);
    return e;
}

static void test_energy_falls(void **state)
{
    (void)state;
    run r;
    run_start(&r, 1);
    lm_progress p0, p;
    lm_optimizer_progress(r.o, &p0);
    assert_true(p0.energy_start > 0 && p0.energy == p0.energy_start && p0.evals == 0);
    run_to(&r, 3000);
    lm_optimizer_progress(r.o, &p);
    assert_true(p.evals >= 3000);
    assert_true(p.energy < p0.energy_start * 0.8);
    assert_true(p.energy == views_energy(r.v));
    assert_int_equal(p.live_verts, p0.live_verts);
    assert_true(p.attempted[LM_MOVE_NOOP] > 0 && p.accepted[LM_MOVE_NOOP] > 0);
    uint64_t att = 0, acc = 0;
    for (int k = 0; k < LM_MOVE_KINDS; k++) {
        att += p.attempted[k];
        acc += p.accepted[k];
    }
    assert_true(acc <= att);
    assert_int_equal(lm_mesh_validate(lm_optimizer_mesh(r.o)), LM_OK);
    /* a fresh full render of the result agrees with the tracked energy */
    lm_views *f;
    assert_int_equal(wk_views_local_create(r.orig, &r.vs, 0, 0, "host", &f), LM_OK);
    lm_tri_data *t;
    size_t n;
    assert_int_equal(lm_mesh_export_tris(lm_optimizer_mesh(r.o), &t, &n), LM_OK);
    assert_int_equal(f->ops->set_mesh(f, t, n), LM_OK);
    free(t);
    assert_true(views_energy(f) == p.energy);
    lm_views_destroy(f);
    run_free(&r);
}

static void test_determinism(void **state)
{
    (void)state;
    run a, b, c;
    run_start(&a, 5);
    run_start(&b, 5);
    run_start(&c, 6);
    run_to(&a, 1500);
    run_to(&b, 1500);
    run_to(&c, 1500);
    uint64_t ha = lm_mesh_hash(lm_optimizer_mesh(a.o)), hb = lm_mesh_hash(lm_optimizer_mesh(b.o));
    assert_true(ha == hb);
    assert_true(lm_mesh_hash(lm_optimizer_mesh(c.o)) != ha); /* the seed matters */
    run_free(&a);
    run_free(&b);
    run_free(&c);
}

static char *save_bytes(const lm_optimizer *o, size_t *len)
{
    char *buf = NULL;
    FILE *fp = open_memstream(&buf, len);
    assert_non_null(fp);
    assert_int_equal(lm_optimizer_save(o, fp), LM_OK);
    assert_int_equal(fclose(fp), 0);
    return buf;
}

static lm_status load_bytes(lm_optimizer *o, const char *buf, size_t len)
{
    FILE *fp = fmemopen((void *)buf, len, "rb");
    assert_non_null(fp);
    lm_status st = lm_optimizer_load(o, fp);
    fclose(fp);
    return st;
}

static void test_resume_equals_uninterrupted(void **state)
{
    (void)state;
    const uint64_t stops[2] = {700, 1900}; /* likely in the middle of an iteration */
    for (int s = 0; s < 2; s++) {
        run a, b;
        run_start(&a, 3);
        run_to(&a, stops[s]);
        size_t len;
        char *ck = save_bytes(a.o, &len);
        run_to(&a, 3200);
        run_start(&b, 3);
        assert_int_equal(load_bytes(b.o, ck, len), LM_OK);
        lm_progress pa, pb;
        lm_optimizer_progress(b.o, &pb);
        assert_true(pb.evals >= stops[s]);
        run_to(&b, 3200);
        lm_optimizer_progress(a.o, &pa);
        lm_optimizer_progress(b.o, &pb);
        assert_memory_equal(&pa, &pb, sizeof pa);
        /* the run went through every kind of move, teleports (split + collapse search) included */
        for (int k = 0; k < LM_MOVE_KINDS; k++)
            assert_true(pa.attempted[k] > 0);
        assert_true(pa.accepted[LM_MOVE_SPLIT] > 0);
        assert_true(lm_mesh_hash(lm_optimizer_mesh(a.o)) == lm_mesh_hash(lm_optimizer_mesh(b.o)));
        size_t la, lb;
        char *sa = save_bytes(a.o, &la), *sb = save_bytes(b.o, &lb);
        assert_int_equal(la, lb);
        assert_memory_equal(sa, sb, la);
        assert_true(views_energy(b.v) == pb.energy);
        free(sa);
        free(sb);
        free(ck);
        run_free(&a);
        run_free(&b);
    }
}

static void test_bad_checkpoints(void **state)
{
    (void)state;
    run a, b;
    run_start(&a, 9);
    run_to(&a, 800);
    size_t len;
    char *ck = save_bytes(a.o, &len);
    run_start(&b, 9);
    uint64_t h = lm_mesh_hash(lm_optimizer_mesh(b.o));
    /* truncated anywhere */
    const size_t cuts[] = {0, 5, 40, len / 3, len / 2, len - 1};
    for (size_t i = 0; i < sizeof cuts / sizeof *cuts; i++)
        assert_int_equal(load_bytes(b.o, ck, cuts[i]), LM_E_FORMAT);
    /* a corrupted magic */
    char *bad = malloc(len);
    memcpy(bad, ck, len);
    bad[0] ^= 0x55;
    assert_int_equal(load_bytes(b.o, bad, len), LM_E_FORMAT);
    free(bad);
    assert_true(lm_mesh_hash(lm_optimizer_mesh(b.o)) == h);
    lm_progress p;
    lm_optimizer_progress(b.o, &p);
    assert_int_equal(p.evals, 0);
    /* another seed */
    run c;
    run_start(&c, 10);
    assert_int_equal(load_bytes(c.o, ck, len), LM_E_FORMAT);
    /* and the real thing still loads */
    assert_int_equal(load_bytes(b.o, ck, len), LM_OK);
    assert_true(lm_mesh_hash(lm_optimizer_mesh(b.o)) == lm_mesh_hash(lm_optimizer_mesh(a.o)));
    free(ck);
    run_free(&a);
    run_free(&b);
    run_free(&c);
}

/* E_geo of a mesh as a fresh geometric term over fresh views computes it. */
static int64_t fresh_geometric(run *r, const lm_mesh *m)
{
    lm_views *g;
    assert_int_equal(lm_surface_views_create(r->v, r->orig, SURFACE_WEIGHT, &g), LM_OK);
    assert_int_equal(lm_views_set_mesh_from(g, m), LM_OK);
    int64_t e = lm_surface_views_energy(g);
    lm_views_destroy(g);
    return e;
}

static void test_geometric_term(void **state)
{
    (void)state;
    g_surface = 1;
    run a, b;
    run_start(&a, 5);
    run_start(&b, 5);
    lm_progress p0, p;
    lm_optimizer_progress(a.o, &p0);
    assert_true(p0.geometric_start > 0 && p0.geometric == p0.geometric_start);
    assert_true(p0.energy_start == views_energy(a.v));
    run_to(&a, 2500);
    run_to(&b, 2500);
    lm_optimizer_progress(a.o, &p);
    assert_true(p.energy == views_energy(a.v));
    assert_true(p.energy < p0.energy_start);
    assert_true(p.geometric < p0.geometric_start); /* the noisy sphere moves towards the surface */
    assert_true(p.geometric == fresh_geometric(&a, lm_optimizer_mesh(a.o)));
    assert_true(lm_mesh_hash(lm_optimizer_mesh(a.o)) == lm_mesh_hash(lm_optimizer_mesh(b.o)));
    /* a checkpoint with the term is not for an optimizer without it, and the other way round */
    size_t len, len2;
    char *ck = save_bytes(a.o, &len);
    g_surface = 0;
    run c;
    run_start(&c, 5);
    assert_int_equal(load_bytes(c.o, ck, len), LM_E_FORMAT);
    char *ck2 = save_bytes(c.o, &len2);
    assert_int_equal(load_bytes(b.o, ck2, len2), LM_E_FORMAT);
    free(ck);
    free(ck2);
    run_free(&a);
    run_free(&b);
    run_free(&c);
}

static void test_resume_with_geometric_term(void **state)
{
    g_surface = 1;
    test_resume_equals_uninterrupted(state);
    g_surface = 0;
}

/* A relative weight: E_geo at the start is the share of the image energy there, and the run
 * resumes to the uninterrupted one's bytes (the weight comes back the same). */
static void test_relative_weight(void **state)
{
    g_surface = 2;
    run a;
    run_start(&a, 5);
    lm_progress p0;
    lm_optimizer_progress(a.o, &p0);
    double want = SURFACE_SHARE * (double)p0.energy_start;
    assert_true(p0.geometric_start > 0 && fabs((double)p0.geometric_start - want) <= 1e-3 * want);
    run_free(&a);
    test_resume_equals_uninterrupted(state);
    g_surface = 0;
}

/* ---- edges in flight: isolated lanes ------------------------------------------------------- */

/* Teleports (collapse searches on the lanes' queues) start after ~3000 evaluations. */
#define LANES_EVALS 6000

/* The saved state after LANES_EVALS evaluations with k lanes in `order`, from a start of
 * subdivision `level`: 2, whose groups are mostly 2-3 edges, teleports done; 3, where groups of 6
 * (two) share the start's statistics, and lanes that shared them would show it. */
static char *lanes_state(int level, uint32_t k, uint32_t isolated, uint64_t order, size_t *len)
{
    run r;
    g_surface = 0;
    g_device = "cpu";
    g_level = level;
    run_start_lanes(&r, 7, k, isolated, order);
    g_level = 2;
    run_to(&r, LANES_EVALS);
    lm_progress p;
    lm_optimizer_progress(r.o, &p);
    assert_true(level > 2 || p.accepted[LM_MOVE_SPLIT] > 0);
    lm_optimizer_lane_traffic(r.o, &g_traffic);
    char *s = save_bytes(r.o, len);
    run_free(&r);
    return s;
}

/* lanes_state of isolated lanes in lane order, kept between tests (a copy, caller frees): the
 * order test and the detached test compare against the same runs. */
static char *isolated_state(int level, uint32_t k, size_t *len)
{
    static struct {
        int level;
        uint32_t k;
        char *s;
        size_t len;
    } kept[4];
    int i = 0;
    while (i < 4 && kept[i].s && (kept[i].level != level || kept[i].k != k))
        i++;
    assert_true(i < 4);
    if (!kept[i].s) {
        kept[i].level = level, kept[i].k = k;
        kept[i].s = lanes_state(level, k, 1, 0, &kept[i].len);
    }
    char *s = malloc(kept[i].len);
    memcpy(s, kept[i].s, kept[i].len);
    *len = kept[i].len;
    return s;
}

static int same_state(const char *a, size_t la, const char *b, size_t lb)
{
    return la == lb && memcmp(a, b, la) == 0;
}

static void test_isolated_lanes_order_free(void **state)
{
    (void)state;
    const uint32_t ks[3] = {4, 8, 8};
    const int levels[3] = {2, 2, 3};
    const uint64_t orders[2] = {1, 0x5eed}; /* reversed, a shuffle */
    for (int i = 0; i < 3; i++) {
        size_t l0;
        char *s0 = isolated_state(levels[i], ks[i], &l0);
        for (int j = 0; j < (ks[i] == 8 ? 2 : 1); j++) {
            size_t l1;
            char *s1 = lanes_state(levels[i], ks[i], 1, orders[j], &l1);
            print_message("isolated K=%u, level %d, order %llu: %s\n", ks[i], levels[i],
                          (unsigned long long)orders[j],
                          same_state(s0, l0, s1, l1) ? "same state" : "DIFFERENT state");
            assert_true(same_state(s0, l0, s1, l1));
            free(s1);
        }
        free(s0);
    }
}

/* Why isolation: shared lanes see each other's clock, statistics and queue as they go. */
static void test_shared_lanes_depend_on_order(void **state)
{
    (void)state;
    size_t l0, l1;
    char *s0 = lanes_state(2, 8, 0, 0, &l0), *s1 = lanes_state(2, 8, 0, 1, &l1);
    print_message("shared K=8, reversed: %s\n",
                  same_state(s0, l0, s1, l1) ? "same state" : "different state");
    assert_false(same_state(s0, l0, s1, l1));
    free(s0);
    free(s1);
}

/* Isolated lanes run as another process would (each lane's request to bytes and back, the lane run
 * on a host of its own with its own mesh copy and the same views, its result to bytes and back,
 * then merged) end in the state of the lanes run in process. */
static void test_detached_lanes_same_state(void **state)
{
    (void)state;
    const uint32_t ks[2] = {4, 8};
    const int levels[2] = {2, 3};
    for (int i = 0; i < 2; i++) {
        size_t l0, l1;
        char *s0 = isolated_state(levels[i], ks[i], &l0);
        g_detached = 1;
        char *s1 = lanes_state(levels[i], ks[i], 1, 0x5eed, &l1);
        g_detached = 0;
        const lm_lane_traffic *t = &g_traffic;
        print_message(
            "detached K=%u, level %d: %s; %llu lanes, request %.0f B (max %llu), result "
            "%.0f B (max %llu), %.1f evaluations per lane\n",
            ks[i], levels[i], same_state(s0, l0, s1, l1) ? "same state" : "DIFFERENT state",
            (unsigned long long)t->lanes, (double)t->request_bytes / (double)t->lanes,
            (unsigned long long)t->request_max, (double)t->result_bytes / (double)t->lanes,
            (unsigned long long)t->result_max, (double)t->evals / (double)t->lanes);
        assert_true(t->lanes > 0 && t->evals > 0);
        assert_true(same_state(s0, l0, s1, l1));
        free(s0);
        free(s1);
    }
}

/* Isolated lanes handed to a runner (lm_optimizer_set_lane_runner, as --lanes remote does), the
 * start mesh sent as bytes and the lanes run in reverse order, end in the state of the lanes run
 * in process. */
static void test_runner_lanes_same_state(void **state)
{
    (void)state;
    const uint32_t ks[2] = {4, 8};
    const int levels[2] = {2, 3};
    for (int i = 0; i < 2; i++) {
        size_t l0, l1;
        char *s0 = isolated_state(levels[i], ks[i], &l0);
        g_detached = 2;
        char *s1 = lanes_state(levels[i], ks[i], 1, 0, &l1);
        g_detached = 0;
        print_message("runner K=%u, level %d: %s; %llu groups, %llu lanes\n", ks[i], levels[i],
                      same_state(s0, l0, s1, l1) ? "same state" : "DIFFERENT state",
                      (unsigned long long)g_runner.groups, (unsigned long long)g_traffic.lanes);
        assert_true(g_runner.groups > 0 && g_traffic.lanes > 0);
        assert_true(same_state(s0, l0, s1, l1));
        lm_lane_host_destroy(g_runner.host);
        g_runner.host = NULL;
        free(s0);
        free(s1);
    }
}

static void test_isolated_lanes_energy_and_resume(void **state)
{
    (void)state;
    run a, b, c;
    g_surface = 0;
    g_device = "cpu";
    run_start_lanes(&a, 7, 8, 1, 0);
    lm_progress p0, pa, pb;
    lm_optimizer_progress(a.o, &p0);
    run_to(&a, 1500);
    size_t len;
    char *ck = save_bytes(a.o, &len);
    run_to(&a, 4000);
    lm_optimizer_progress(a.o, &pa);
    assert_true(pa.energy < p0.energy_start * 0.8);
    assert_true(pa.energy == views_energy(a.v));
    assert_int_equal(pa.live_verts, p0.live_verts);
    assert_int_equal(lm_mesh_validate(lm_optimizer_mesh(a.o)), LM_OK);
    /* a resume of the isolated run ends in the same state; shared lanes refuse its state */
    run_start_lanes(&b, 7, 8, 1, 0);
    assert_int_equal(load_bytes(b.o, ck, len), LM_OK);
    run_to(&b, 4000);
    lm_optimizer_progress(b.o, &pb);
    assert_memory_equal(&pa, &pb, sizeof pa);
    size_t la, lb;
    char *sa = save_bytes(a.o, &la), *sb = save_bytes(b.o, &lb);
    assert_true(same_state(sa, la, sb, lb));
    run_start_lanes(&c, 7, 8, 0, 0);
    assert_int_equal(load_bytes(c.o, ck, len), LM_E_FORMAT);
    free(sa);
    free(sb);
    free(ck);
    run_free(&a);
    run_free(&b);
    run_free(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_energy_falls),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_resume_equals_uninterrupted),
        cmocka_unit_test(test_bad_checkpoints),
        cmocka_unit_test(test_geometric_term),
        cmocka_unit_test(test_resume_with_geometric_term),
        cmocka_unit_test(test_relative_weight),
        cmocka_unit_test(test_isolated_lanes_order_free),
        cmocka_unit_test(test_detached_lanes_same_state),
        cmocka_unit_test(test_runner_lanes_same_state),
        cmocka_unit_test(test_shared_lanes_depend_on_order),
        cmocka_unit_test(test_isolated_lanes_energy_and_resume),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
