/* tests/unit/test_render_exact.c — incremental rendering is exact: over thousands of random
 * optimizer-like moves (vertex moves of 1-ring patches, attribute changes, edge collapses, splits
 * and swaps) on a generated sphere (also normal-mapped), the QEM-simplified bunny and the textured
 * spider (coarse and full), the images kept up to date by commit() equal a full re-render of the
 * new mesh pixel for pixel, evaluate()'s ΔE equals E(after) - E(before) of full renders exactly,
 * and an evaluated but rejected move leaves the images untouched. A second views object (same
 * device) does the full renders; LUMESH_TEST_LIGHT=1 makes a quarter of the moves. LUMESH_DEVICE
 * names the device (ctest runs it as "cpu" and "host"); unset, "auto", which is skipped where it
 * means the CPU rasteriser or llvmpipe (covered by those runs). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/mesh_io.h"
#include "common/mesh_topology.h"
#include "common/patch.h"
#include "common/view.h"
#include "coordinator/simplify/simplify.h"
#include "test_support.h"
#include "worker/render/views_local.h"

#define N_VIEWS 20
#define VIEW_SIZE 128
#define MAX_RING 512

typedef struct harness {
    lm_mesh *m; /* the mesh being changed (owned) */
    lm_views *inc, *full;
    lm_journal *journal;
    lm_patch patch;
    uint64_t rng;
    float step; /* typical vertex displacement */
    size_t plane;
    uint8_t *a, *b;
    int moves, commits, delta_checks, image_checks;
} harness;

static uint64_t next_u64(harness *h)
{
    h->rng ^= h->rng << 13;
    h->rng ^= h->rng >> 7;
    h->rng ^= h->rng << 17;
    return h->rng;
}

static double uniform(harness *h)
{
    return (double)(next_u64(h) >> 11) / 9007199254740992.0;
}

static const char *device(void)
{
    const char *d = getenv("LUMESH_DEVICE");
    return d && *d ? d : "auto";
}

/* Skip the test when LUMESH_DEVICE is unset and "auto" means a device another run covers. */
static void skip_if_auto_is_covered(void)
{
    const char *d = getenv("LUMESH_DEVICE");
    if (d && *d)
        return;
    lm_mesh *m = lmt_make_sphere(1);
    float c[3], r;
    lm_mesh_bounding_sphere(m, c, &r);
    lm_view_set *vs = malloc(sizeof *vs);
    assert_int_equal(lm_view_set_make(vs, 1, 16, c, r), LM_OK);
    lm_views *v;
    assert_int_equal(wk_views_local_create(m, vs, 0, 0, "auto", &v), LM_OK);
    lm_views_info info;
    v->ops->info(v, &info);
    lm_views_destroy(v);
    free(vs);
    lm_mesh_destroy(m);
    if (strncmp(info.renderer, "cpu:", 4) == 0 || strstr(info.renderer, "llvmpipe")) {
        printf("# auto is %s here, which the cpu and host runs test: skipped\n", info.renderer);
        skip();
    }
}

static void set_full_mesh(lm_views *v, const lm_mesh *m)
{
    lm_tri_data *tris;
    size_t n;
    assert_int_equal(lm_mesh_export_tris(m, &tris, &n), LM_OK);
    assert_int_equal(v->ops->set_mesh(v, tris, n), LM_OK);
    free(tris);
}

static int64_t total_energy(lm_views *v)
{
    int64_t e;
    assert_int_equal(v->ops->energy(v, &e, NULL), LM_OK);
    return e;
}

static void harness_init(harness *h, const lm_mesh *original, const lm_mesh *coarse, uint64_t seed,
                         int occlusion)
{
    memset(h, 0, sizeof *h);
    assert_int_equal(lm_mesh_clone(coarse, &h->m), LM_OK);
    assert_int_equal(lm_mesh_build_adjacency(h->m), LM_OK);
    float c[3], r;
    lm_mesh_bounding_sphere(original, c, &r);
    lm_view_set *vs = malloc(sizeof *vs);
    assert_int_equal(lm_view_set_make(vs, N_VIEWS, VIEW_SIZE, c, r), LM_OK);
    assert_int_equal(wk_views_local_create(original, vs, 0, 0, device(), &h->inc), LM_OK);
    assert_int_equal(wk_views_local_create(original, vs, 0, 0, device(), &h->full), LM_OK);
    free(vs);
    if (!occlusion)
        assert_int_equal(wk_views_local_set_occlusion(h->inc, 0), LM_OK);
    set_full_mesh(h->inc, h->m);
    assert_int_equal(lm_journal_create(&h->journal), LM_OK);
    lm_patch_init(&h->patch);
    h->rng = seed * 0x9E3779B97F4A7C15ull + 1;
    /* about a third of a typical edge of the coarse mesh */
    h->step = 0.33f * 2.0f * r / sqrtf((float)(coarse->live_verts > 4 ? coarse->live_verts : 4));
    h->plane = (size_t)VIEW_SIZE * VIEW_SIZE;
    h->a = malloc(h->plane * N_VIEWS);
    h->b = malloc(h->plane * N_VIEWS);
}

static void harness_free(harness *h)
{
    lm_views_destroy(h->inc);
    lm_views_destroy(h->full);
    lm_journal_destroy(h->journal);
    lm_patch_free(&h->patch);
    lm_mesh_destroy(h->m);
    free(h->a);
    free(h->b);
}

static void snapshot(lm_views *v, uint8_t *out)
{
    for (uint32_t k = 0; k < N_VIEWS; k++)
        assert_int_equal(
            v->ops->read_image(v, LM_IMAGE_CURRENT_LUMA, k, out + k * (VIEW_SIZE * VIEW_SIZE)),
            LM_OK);
}

/* The incremental images equal a full re-render of the mesh, pixel for pixel. */
static void check_images(harness *h)
{
    set_full_mesh(h->full, h->m);
    snapshot(h->inc, h->a);
    snapshot(h->full, h->b);
    for (uint32_t k = 0; k < N_VIEWS; k++) {
        const uint8_t *x = h->a + k * h->plane, *y = h->b + k * h->plane;
        size_t diff = 0, first = 0;
        for (size_t i = 0; i < h->plane; i++)
            if (x[i] != y[i] && diff++ == 0)
                first = i;
        if (diff)
            fail_msg("after %d moves view %u: %zu pixels differ, first at (%zu,%zu): %d vs %d",
                     h->moves, k, diff, first % VIEW_SIZE, first / VIEW_SIZE, x[first], y[first]);
    }
    int64_t ei[N_VIEWS], ef[N_VIEWS];
    assert_int_equal(h->inc->ops->energy(h->inc, NULL, ei), LM_OK);
    assert_int_equal(h->full->ops->energy(h->full, NULL, ef), LM_OK);
    assert_memory_equal(ei, ef, sizeof ei);
    h->image_checks++;
}

/* Triangles incident to any of the vertices (sorted, unique ids). */
static uint32_t ring(const lm_mesh *m, const uint32_t *verts, int nv, uint32_t *out)
{
    uint32_t n = 0;
    for (int i = 0; i < nv; i++)
        if (verts[i] != LM_NONE && m->vert_alive[verts[i]])
            n += lm_mesh_vertex_tris(m, verts[i], out + n, MAX_RING - n);
    for (uint32_t i = 1; i < n; i++) /* insertion sort + unique */
        for (uint32_t j = i; j > 0 && out[j - 1] > out[j]; j--) {
            uint32_t t = out[j];
            out[j] = out[j - 1];
            out[j - 1] = t;
        }
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++)
        if (k == 0 || out[k - 1] != out[i])
            out[k++] = out[i];
    return k;
}

static uint32_t random_vertex(harness *h)
{
    for (;;) {
        uint32_t v = (uint32_t)(next_u64(h) % h->m->n_verts);
        if (h->m->vert_alive[v] && lm_mesh_vertex_tris(h->m, v, NULL, 0) > 0)
            return v;
    }
}

static void random_edge(harness *h, uint32_t *a, uint32_t *b)
{
    for (;;) {
        uint32_t t = (uint32_t)(next_u64(h) % h->m->n_tris);
        if (!h->m->tri_alive[t])
            continue;
        int k = (int)(next_u64(h) % 3);
        *a = lm_tri_vertex(h->m, t, k);
        *b = lm_tri_vertex(h->m, t, (k + 1) % 3);
        return;
    }
}

/* A vertex move (the simplex's evaluation); now and then a large one, or a change of the
 * attributes of one of its wedges. */
static void move_vertex(harness *h, uint32_t v)
{
    float p[3], s = h->step * (uniform(h) < 0.1 ? 6.0f : 1.0f);
    for (int k = 0; k < 3; k++)
        p[k] = h->m->pos[v][k] + s * (float)(2.0 * uniform(h) - 1.0);
    lm_mesh_set_pos(h->m, v, p, h->journal);
    if (uniform(h) < 0.2) {
        for (uint32_t w = 0; w < h->m->n_wedges; w++)
            if (h->m->wedge_alive[w] && h->m->wedges[w].vertex == v) {
                lm_wedge nw = h->m->wedges[w];
                for (int k = 0; k < 3; k++)
                    nw.normal[k] *= (float)(0.5 + uniform(h));
                nw.uv[0] += 0.05f * (float)(uniform(h) - 0.5);
                nw.color[1] = (float)uniform(h);
                lm_mesh_set_wedge(h->m, w, &nw, h->journal);
                break;
            }
    }
}

/* Apply one random legal move to the mesh (journaled); fills h->patch. Returns 0 if refused. */
static int random_move(harness *h, int kinds)
{
    uint32_t before[MAX_RING], after[MAX_RING], verts[3] = {LM_NONE, LM_NONE, LM_NONE};
    int kind = (int)(next_u64(h) % (uint64_t)kinds), nb;
    lm_status st = LM_OK;
    if (kind == 0) {
        verts[0] = random_vertex(h);
    } else {
        random_edge(h, &verts[0], &verts[1]);
    }
    nb = (int)ring(h->m, verts, 2, before);
    if (kind == 0) {
        move_vertex(h, verts[0]);
    } else if (kind == 1) {
        const float *pa = h->m->pos[verts[0]], *pb = h->m->pos[verts[1]];
        float mid[3] = {(pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2};
        st = lm_mesh_collapse_edge(h->m, verts[0], verts[1], mid, h->journal);
    } else if (kind == 2) {
        st = lm_mesh_split_edge(h->m, verts[0], verts[1], &verts[2], h->journal);
    } else {
        st = lm_mesh_swap_edge(h->m, verts[0], verts[1], h->journal);
    }
    if (st != LM_OK)
        return 0;
    uint32_t na = ring(h->m, verts, 3, after);
    assert_int_equal(lm_patch_build(&h->patch, h->m, before, (size_t)nb, after, na), LM_OK);
    return 1;
}

/* E of the full views for `base` (ascending ids) with patch p applied. */
static int64_t full_energy_patched(harness *h, const lm_tri_data *base, size_t n, const lm_patch *p)
{
    lm_tri_data *t = malloc((n + p->n_added + 1) * sizeof *t);
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        int gone = 0;
        for (uint32_t r = 0; r < p->n_removed; r++)
            gone |= p->removed[r] == base[i].id;
        if (!gone)
            t[k++] = base[i];
    }
    for (uint32_t a = 0; a < p->n_added; a++)
        t[k++] = p->added[a];
    assert_int_equal(h->full->ops->set_mesh(h->full, t, k), LM_OK); /* sorts by id itself */
    free(t);
    return total_energy(h->full);
}

/* Several alternatives evaluated in one call (more than one readback group): each ΔE equals the
 * full renders'; the last alternative stays applied and is committed (from the batch's pixels). */
#define BATCH 6
static void batch_check(harness *h, int kinds)
{
    lm_patch alts[BATCH];
    lm_tri_data *base;
    size_t n_base;
    assert_int_equal(lm_mesh_export_tris(h->m, &base, &n_base), LM_OK);
    for (int k = 0; k < BATCH; k++) {
        lm_patch_init(&alts[k]);
        size_t mark;
        do {
            mark = lm_journal_mark(h->journal);
            if (random_move(h, kinds))
                break;
            lm_journal_rollback(h->m, h->journal, mark);
        } while (1);
        assert_int_equal(
            lm_patch_build(&alts[k], h->m, h->patch.removed, h->patch.n_removed, NULL, 0), LM_OK);
        for (uint32_t a = 0; a < h->patch.n_added; a++)
            assert_int_equal(lm_patch_add(&alts[k], &h->patch.added[a]), LM_OK);
        if (k < BATCH - 1)
            lm_journal_rollback(h->m, h->journal, mark);
    }
    int64_t e0 = total_energy(h->inc), delta[BATCH];
    assert_int_equal(h->inc->ops->evaluate(h->inc, alts, BATCH, delta), LM_OK);
    for (int k = 0; k < BATCH; k++) {
        int64_t e = full_energy_patched(h, base, n_base, &alts[k]);
        if (delta[k] != e - e0)
            fail_msg("batch alternative %d: incremental dE %lld, full renders %lld", k,
                     (long long)delta[k], (long long)(e - e0));
        h->delta_checks++;
    }
    assert_int_equal(h->inc->ops->commit(h->inc, &alts[BATCH - 1]), LM_OK);
    assert_true(total_energy(h->inc) == e0 + delta[BATCH - 1]);
    lm_journal_clear(h->journal);
    h->commits++;
    for (int k = 0; k < BATCH; k++)
        lm_patch_free(&alts[k]);
    free(base);
}

/* A simplex's evaluations: one vertex moved several times in a row, each time against the same
 * mesh, with the same removed triangles (the rings of the vertex and of a neighbour, whose
 * triangles away from the vertex come back unchanged: twins); each ΔE equals the full renders'.
 * Then the last move is committed (the same triangle ids, moved) and the vertex moved again from
 * there: the same removed ids against other images. This is the pattern the CPU views replay a
 * view's holes for (cpu_holes.h), and the commit is what must end a replay. */
#define SIMPLEX_STEPS 4
#define SIMPLEX_CHECKS 12
static void simplex_check(harness *h)
{
    uint32_t verts[2], before[MAX_RING], after[MAX_RING];
    random_edge(h, &verts[0], &verts[1]);
    for (int round = 0; round < 2; round++) {
        uint32_t nb = ring(h->m, verts, 2, before);
        lm_tri_data *base;
        size_t n_base;
        assert_int_equal(lm_mesh_export_tris(h->m, &base, &n_base), LM_OK);
        int64_t e0 = total_energy(h->inc);
        for (int step = 0; step < SIMPLEX_STEPS; step++) {
            size_t mark = lm_journal_mark(h->journal);
            move_vertex(h, verts[0]);
            uint32_t na = ring(h->m, verts, 2, after);
            assert_int_equal(lm_patch_build(&h->patch, h->m, before, nb, after, na), LM_OK);
            int64_t delta = 0;
            assert_int_equal(h->inc->ops->evaluate(h->inc, &h->patch, 1, &delta), LM_OK);
            int64_t e = full_energy_patched(h, base, n_base, &h->patch);
            if (delta != e - e0)
                fail_msg("simplex round %d step %d: incremental dE %lld, full renders %lld", round,
                         step, (long long)delta, (long long)(e - e0));
            h->delta_checks++;
            if (round == 0 && step == SIMPLEX_STEPS - 1) {
                assert_int_equal(h->inc->ops->commit(h->inc, &h->patch), LM_OK);
                assert_true(total_energy(h->inc) == e0 + delta);
                lm_journal_clear(h->journal);
                h->commits++;
            } else {
                lm_journal_rollback(h->m, h->journal, mark);
            }
        }
        free(base);
    }
}

static void run_moves(harness *h, int n_moves, int kinds, int delta_every)
{
    int64_t e_before = total_energy(h->inc);
    while (h->moves < n_moves) {
        size_t mark = lm_journal_mark(h->journal);
        if (!random_move(h, kinds)) {
            lm_journal_rollback(h->m, h->journal, mark);
            continue;
        }
        h->moves++;
        int check_reject = h->moves % 7 == 0;
        if (check_reject)
            snapshot(h->inc, h->a);
        int64_t delta = 0;
        assert_int_equal(h->inc->ops->evaluate(h->inc, &h->patch, 1, &delta), LM_OK);
        if (h->moves % delta_every == 0) {
            set_full_mesh(h->full, h->m);
            int64_t e_after = total_energy(h->full);
            if (delta != e_after - e_before)
                fail_msg("move %d: incremental dE %lld, full renders %lld", h->moves,
                         (long long)delta, (long long)(e_after - e_before));
            h->delta_checks++;
        }
        if (uniform(h) < 0.5) {
            assert_int_equal(h->inc->ops->commit(h->inc, &h->patch), LM_OK);
            e_before += delta;
            assert_true(total_energy(h->inc) == e_before);
            h->commits++;
            lm_journal_clear(h->journal);
        } else {
            lm_journal_rollback(h->m, h->journal, mark);
            if (check_reject) {
                snapshot(h->inc, h->b);
                assert_memory_equal(h->a, h->b, h->plane * N_VIEWS);
            }
        }
        if (h->moves % 25 == 12) { /* simplexes between the moves: on llvmpipe this sequence
                                    * found a kept sliver taken as hidden behind its own pixel
                                    * (its depth extrapolated there; wk_footprint's zmin) */
            simplex_check(h);
            e_before = total_energy(h->inc);
        }
        if (h->moves % 25 == 0) {
            batch_check(h, kinds);
            e_before = total_energy(h->inc);
        }
        if (h->moves % 50 == 0)
            check_images(h);
    }
    check_images(h);
}

/* The sanitizer stage (LUMESH_TEST_LIGHT=1) makes a quarter of the moves: the same kinds, checks
 * and models. */
static int scaled_moves(int n)
{
    const char *light = getenv("LUMESH_TEST_LIGHT");
    return light && strcmp(light, "1") == 0 ? n / 4 : n;
}

static void exercise(const lm_mesh *original, const lm_mesh *coarse, int n_moves, int delta_every,
                     uint64_t seed, int occlusion, const char *name)
{
    n_moves = scaled_moves(n_moves);
    harness h;
    harness_init(&h, original, coarse, seed, occlusion);
    check_images(&h);
    lm_views_info info;
    h.inc->ops->info(h.inc, &info);
    /* vertex moves (with attribute changes), then all four kinds of move */
    run_moves(&h, n_moves / 2, 1, delta_every);
    run_moves(&h, n_moves, 4, delta_every);
    /* then simplexes (after the moves, which thereby stay the sequence they always were) */
    for (int i = 0; i < SIMPLEX_CHECKS; i++)
        simplex_check(&h);
    check_images(&h);
    wk_views_local_stats stats;
    wk_views_local_get_stats(h.inc, &stats);
    printf("# %s on %s: %d moves (%d committed), %d dE checks, %d image checks, %u tris now, "
           "occlusion %s (%llu view renders skipped)\n",
           name, info.renderer, h.moves, h.commits, h.delta_checks, h.image_checks, h.m->live_tris,
           occlusion ? "on" : "off", (unsigned long long)stats.views_skipped);
    harness_free(&h);
}

static lm_mesh *load_or_skip(const char *path)
{
    if (!path) {
        printf("# test model missing (run scripts/install-deps.sh)\n");
        return NULL;
    }
    lm_mesh *m;
    assert_int_equal(lm_mesh_load(path, NULL, &m), LM_OK);
    return m;
}

static lm_mesh *qem(const lm_mesh *m, uint32_t target)
{
    lm_mesh *out = NULL;
    lm_status st = co_simplify(m, CO_SIMPLIFY_QEM, target, &out);
    assert_true(st == LM_OK || (st == LM_E_RANGE && out));
    assert_int_equal(lm_mesh_build_adjacency(out), LM_OK);
    return out;
}

static void test_sphere(void **state)
{
    (void)state;
    skip_if_auto_is_covered();
    lm_mesh *orig = lmt_make_sphere(4), *coarse = lmt_make_sphere(2);
    exercise(orig, coarse, 1000, 3, 1, 0, "sphere");
    lm_mesh_destroy(orig);
    lm_mesh_destroy(coarse);
}

/* A normal map (a lumpy one of 8x8 texels) on the sphere: both backends light each pixel from it
 * and the triangle's tangent frame. */
static lm_image *lumpy_normal_map(void)
{
    lm_image *img;
    assert_int_equal(lm_image_create(8, 8, &img), LM_OK);
    for (int i = 0; i < 64; i++) {
        img->pixels[4 * i] = (uint8_t)(64 + 37 * (i % 5));
        img->pixels[4 * i + 1] = (uint8_t)(200 - 23 * (i % 7));
        img->pixels[4 * i + 2] = (uint8_t)(180 + 9 * (i % 3));
        img->pixels[4 * i + 3] = 255;
    }
    return img;
}

static void test_normal_mapped_sphere(void **state)
{
    (void)state;
    skip_if_auto_is_covered();
    lm_mesh *orig = lmt_make_sphere(4), *coarse = lmt_make_sphere(2);
    assert_int_equal(lm_mesh_set_normal_map(orig, 0, NULL, lumpy_normal_map()), LM_OK);
    assert_int_equal(lm_mesh_set_normal_map(coarse, 0, NULL, lumpy_normal_map()), LM_OK);
    exercise(orig, coarse, 600, 3, 5, 1, "normal-mapped sphere");
    lm_mesh_destroy(orig);
    lm_mesh_destroy(coarse);
}

static void test_bunny(void **state)
{
    (void)state;
    skip_if_auto_is_covered();
    lm_mesh *orig = load_or_skip(lmt_bunny_path());
    if (!orig)
        skip();
    lm_mesh *coarse = qem(orig, orig->live_verts / 100);
    exercise(orig, coarse, 2000, 4, 2, 1, "bunny 1%");
    lm_mesh_destroy(coarse);
    lm_mesh_destroy(orig);
}

static void test_spider(void **state)
{
    (void)state;
    skip_if_auto_is_covered();
    lm_mesh *orig = load_or_skip(lmt_spider_path());
    if (!orig)
        skip();
    lm_mesh *coarse = qem(orig, 300);
    exercise(orig, coarse, 1500, 4, 3, 1, "spider 300 verts");
    exercise(orig, orig, 600, 4, 4, 1, "spider full");
    lm_mesh_destroy(coarse);
    lm_mesh_destroy(orig);
}

/* Refused input changes nothing; vertices behind the eye, at the eye plane and very far stay
 * exact (whole-view footprints, near-plane clipping). */
static void test_bad_patches_and_extreme_moves(void **state)
{
    (void)state;
    skip_if_auto_is_covered();
    lm_mesh *orig = lmt_make_sphere(3), *coarse = lmt_make_sphere(1);
    harness h;
    harness_init(&h, orig, coarse, 7, 1);
    lm_tri_data *tris;
    size_t n;
    assert_int_equal(lm_mesh_export_tris(h.m, &tris, &n), LM_OK);
    int64_t d[2];
    lm_patch p;
    lm_patch_init(&p);
    snapshot(h.inc, h.a);
    /* removing a triangle that is not there, twice the same, adding one that is alive */
    assert_int_equal(lm_patch_remove(&p, 100000), LM_OK);
    assert_int_equal(h.inc->ops->evaluate(h.inc, &p, 1, d), LM_E_INVALID);
    lm_patch_reset(&p);
    assert_int_equal(lm_patch_remove(&p, tris[0].id), LM_OK);
    assert_int_equal(lm_patch_remove(&p, tris[0].id), LM_OK);
    assert_int_equal(h.inc->ops->commit(h.inc, &p), LM_E_INVALID);
    lm_patch_reset(&p);
    assert_int_equal(lm_patch_add(&p, &tris[1]), LM_OK);
    assert_int_equal(h.inc->ops->evaluate(h.inc, &p, 1, d), LM_E_INVALID);
    lm_patch_reset(&p);
    lm_tri_data bad = tris[2];
    bad.material = 99;
    assert_int_equal(lm_patch_remove(&p, tris[2].id), LM_OK);
    assert_int_equal(lm_patch_add(&p, &bad), LM_OK);
    assert_int_equal(h.inc->ops->evaluate(h.inc, &p, 1, d), LM_E_RANGE);
    bad.material = 0;
    bad.id = LM_MESH_MAX_TRIS;
    p.added[0] = bad;
    assert_int_equal(h.inc->ops->evaluate(h.inc, &p, 1, d), LM_E_RANGE);
    /* a mesh with an id twice */
    tris[1].id = tris[0].id;
    assert_int_equal(h.full->ops->set_mesh(h.full, tris, n), LM_E_INVALID);
    snapshot(h.inc, h.b);
    assert_memory_equal(h.a, h.b, h.plane * N_VIEWS);
    /* extreme positions for one vertex: behind the eye of view 0, on its eye plane, far away */
    lm_view_set *vs = malloc(sizeof *vs);
    float c[3], r;
    lm_mesh_bounding_sphere(orig, c, &r);
    assert_int_equal(lm_view_set_make(vs, N_VIEWS, VIEW_SIZE, c, r), LM_OK);
    const lm_view *v0 = &vs->views[0];
    float places[4][3];
    for (int k = 0; k < 3; k++) {
        places[0][k] = v0->eye[k] - 0.5f * r * v0->dir[k];
        places[1][k] = v0->eye[k] + 0.3f * r * (k == 0 ? 1.0f : 0.0f);
        places[2][k] = c[k] + 1e6f * (k == 1 ? 1.0f : 0.3f);
        places[3][k] = v0->eye[k] + 0.2f * r * v0->dir[k];
    }
    for (int i = 0; i < 4; i++) {
        uint32_t vtx = random_vertex(&h), before[MAX_RING];
        uint32_t nb = ring(h.m, &vtx, 1, before);
        lm_mesh_set_pos(h.m, vtx, places[i], NULL);
        assert_int_equal(lm_patch_build(&h.patch, h.m, before, nb, before, nb), LM_OK);
        int64_t e0 = total_energy(h.inc);
        assert_int_equal(h.inc->ops->evaluate(h.inc, &h.patch, 1, d), LM_OK);
        set_full_mesh(h.full, h.m);
        if (total_energy(h.full) - e0 != d[0])
            fail_msg("extreme move %d: incremental dE %lld, full %lld", i, (long long)d[0],
                     (long long)(total_energy(h.full) - e0));
        assert_int_equal(h.inc->ops->commit(h.inc, &h.patch), LM_OK);
        check_images(&h);
    }
    free(vs);
    free(tris);
    lm_patch_free(&p);
    harness_free(&h);
    lm_mesh_destroy(orig);
    lm_mesh_destroy(coarse);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_patches_and_extreme_moves),
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_normal_mapped_sphere),
        cmocka_unit_test(test_bunny),
        cmocka_unit_test(test_spider),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
