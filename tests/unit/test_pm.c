/* tests/unit/test_pm.c — progressive meshes: the simplifier's collapses recorded as vertex splits
 * and written; pm-extract at every vertex count between the coarsest mesh and the start writes the
 * same bytes (PLY at every count, OBJ with its MTL and textures and GLB at some) as the simplifier
 * stopped at that count; hostile files (truncated, flipped bytes, ids out of range, bad magic) are
 * refused with one message and never crash. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/folders.h"
#include "common/io/mesh_io.h"
#include "coordinator/simplify/isimp.h"
#include "coordinator/simplify/pm.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/simplify/work.h"
#include "test_support.h"

typedef struct run {
    char *dir;
    co_pm_recorder *rec;
    uint32_t start, end;
} run;

/* DIR/NAME (NAME a printf format of the count), its folder made. */
static void save_as(const lm_mesh *m, const char *dir, const char *name, uint32_t n)
{
    char rel[256], path[600];
    snprintf(rel, sizeof rel, name, n, n);
    snprintf(path, sizeof path, "%s/%s", dir, rel);
    assert_int_equal(lm_make_parent_folders(path), LM_OK);
    lm_mesh *out;
    assert_int_equal(co_simplify_output_copy(m, &out), LM_OK);
    assert_int_equal(lm_mesh_save(path, out), LM_OK);
    lm_mesh_destroy(out);
}

static int every_format(uint32_t n)
{
    return n % 17 == 0;
}

static void save_all(const lm_mesh *m, const char *dir, const char *what, uint32_t n)
{
    char name[128];
    snprintf(name, sizeof name, "%s_%%u.ply", what);
    save_as(m, dir, name, n);
    if (every_format(n)) {
        snprintf(name, sizeof name, "%s_%%u.glb", what);
        save_as(m, dir, name, n);
        snprintf(name, sizeof name, "%s_obj_%%u/m_%%u.obj", what);
        save_as(m, dir, name, n);
    }
}

static lm_status on_step(void *ctx, const lm_mesh *m, co_isimp_step *s)
{
    run *r = ctx;
    assert_non_null(s->split);
    save_all(m, r->dir, "simplify", m->live_verts);
    return co_pm_recorder_take(r->rec, s->split);
}

static uint8_t *slurp(const char *path, size_t *n)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    fseek(fp, 0, SEEK_END);
    long len = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    uint8_t *buf = malloc((size_t)len + 1);
    assert_non_null(buf);
    assert_int_equal(fread(buf, 1, (size_t)len, fp), (size_t)len);
    fclose(fp);
    *n = (size_t)len;
    return buf;
}

static void same_file(const char *dir, const char *rel_a, const char *rel_b)
{
    char a[600], b[600];
    snprintf(a, sizeof a, "%s/%s", dir, rel_a);
    snprintf(b, sizeof b, "%s/%s", dir, rel_b);
    size_t na, nb;
    uint8_t *x = slurp(a, &na), *y = slurp(b, &nb);
    if (na != nb || memcmp(x, y, na))
        fail_msg("%s and %s differ", a, b);
    free(x);
    free(y);
}

/* The spider, QEM to 160 vertices, image-driven to 60 with every step saved. */
static void simplify_recorded(run *r, char *pm_path, size_t cap)
{
    lm_mesh *orig, *m;
    assert_int_equal(lm_mesh_load(lmt_spider_path(), NULL, &orig), LM_OK);
    lm_status st = co_simplify(orig, CO_SIMPLIFY_QEM, 160, &m);
    assert_true(st == LM_OK || (st == LM_E_RANGE && m));
    lm_clear_error();
    int derived;
    assert_int_equal(co_simplify_prepare(m, &derived), LM_OK);
    float c[3], rad;
    lm_mesh_bounding_sphere(orig, c, &rad);
    lm_view_set vs;
    assert_int_equal(lm_view_set_make(&vs, 6, 48, c, rad), LM_OK);
    lm_views *v;
    assert_int_equal(co_simplify_make_views(CO_PRICE_IMAGE, orig, m, &vs, "host", NULL, &v), LM_OK);
    r->start = m->live_verts;
    save_all(m, r->dir, "simplify", m->live_verts);
    assert_int_equal(co_pm_recorder_create(&r->rec), LM_OK);
    co_isimp_config cfg = {.target_verts = 60,
                           .views = &vs,
                           .derived_normals = derived,
                           .record_splits = 1,
                           .on_step = on_step,
                           .ctx = r};
    co_isimp_stats s;
    assert_int_equal(co_isimp_run(m, v, &cfg, &s), LM_OK);
    r->end = m->live_verts;
    assert_int_equal(r->start - r->end, co_pm_recorder_count(r->rec));
    snprintf(pm_path, cap, "%s/spider.pm", r->dir);
    assert_int_equal(co_pm_write(pm_path, m, r->rec, r->start), LM_OK);
    co_pm_recorder_destroy(r->rec);
    lm_views_destroy(v);
    lm_mesh_destroy(m);
    lm_mesh_destroy(orig);
}

static void extract_every_count(const char *dir, const char *pm_path, uint32_t lo, uint32_t hi)
{
    co_pm *pm;
    assert_int_equal(co_pm_read(pm_path, &pm), LM_OK);
    uint32_t b, f;
    co_pm_range(pm, &b, &f);
    assert_int_equal(b, lo);
    assert_int_equal(f, hi);
    for (uint32_t n = lo; n <= hi; n++) {
        lm_mesh *m;
        assert_int_equal(co_pm_extract(pm, n, &m), LM_OK);
        assert_int_equal(m->live_verts, n);
        save_all(m, dir, "pm", n);
        lm_mesh_destroy(m);
        char a[64], x[64];
        snprintf(a, sizeof a, "simplify_%u.ply", n);
        snprintf(x, sizeof x, "pm_%u.ply", n);
        same_file(dir, a, x);
        if (every_format(n)) {
            snprintf(a, sizeof a, "simplify_%u.glb", n);
            snprintf(x, sizeof x, "pm_%u.glb", n);
            same_file(dir, a, x);
            const char *files[] = {"m_%u.obj", "m_%u.mtl"};
            for (int k = 0; k < 2; k++) {
                char fa[128], fx[128], name[32];
                snprintf(name, sizeof name, files[k], n);
                snprintf(fa, sizeof fa, "simplify_obj_%u/%s", n, name);
                snprintf(fx, sizeof fx, "pm_obj_%u/%s", n, name);
                same_file(dir, fa, fx);
            }
        }
    }
    lm_mesh *m;
    assert_int_equal(co_pm_extract(pm, lo - 1, &m), LM_E_RANGE);
    assert_int_equal(co_pm_extract(pm, hi + 1, &m), LM_E_RANGE);
    lm_clear_error();
    co_pm_destroy(pm);
}

/* Truncations, flipped bytes and rewritten counts: refused with LM_E_FORMAT, or (for a flip in
 * a float) read into a mesh that passes lm_mesh_validate; never a crash. */
static void hostile_files(const char *pm_path)
{
    size_t n;
    uint8_t *buf = slurp(pm_path, &n);
    co_pm *pm;
    uint64_t s = 12345;
    for (int i = 0; i < 300; i++) {
        size_t cut = (size_t)(lmt_urand(&s) * (double)n);
        lm_status st = co_pm_read_memory(buf, cut, 0, &pm);
        assert_int_equal(st, LM_E_FORMAT);
    }
    uint8_t *copy = malloc(n);
    assert_non_null(copy);
    uint32_t refused = 0;
    for (int i = 0; i < 300; i++) {
        memcpy(copy, buf, n);
        /* in the last twentieth: the splits (most of the file before them is texture PNG) */
        size_t at = n - 1 - (size_t)(lmt_urand(&s) * (double)(n / 20));
        copy[at] ^= (uint8_t)(1u << (i % 8));
        if (i % 3 == 0)
            memset(copy + at, 0xff, at + 4 <= n ? 4 : n - at);
        lm_status st = co_pm_read_memory(copy, n, 0, &pm);
        assert_true(st == LM_OK || st == LM_E_FORMAT);
        refused += st != LM_OK;
        if (st == LM_OK) {
            uint32_t lo, hi;
            lm_mesh *m = NULL;
            co_pm_range(pm, &lo, &hi);
            st = co_pm_extract(pm, hi, &m);
            assert_true(st == LM_OK || st == LM_E_FORMAT);
            lm_mesh_destroy(m);
            co_pm_destroy(pm);
        }
    }
    /* most flips land in floats (a valid file still) or turn an id into another valid one */
    assert_true(refused > 30);
    memcpy(copy, buf, n);
    copy[0] = 'X';
    assert_int_equal(co_pm_read_memory(copy, n, 0, &pm), LM_E_FORMAT);
    assert_non_null(strstr(lm_last_error(), "LMPM"));
    lm_clear_error();
    free(copy);
    free(buf);
}

static void pm_extract_equals_simplifier_at_every_count(void **state)
{
    (void)state;
    run r = {.dir = lmt_mkdtemp()};
    char pm_path[600];
    simplify_recorded(&r, pm_path, sizeof pm_path);
    assert_true(r.start - r.end >= 60);
    extract_every_count(r.dir, pm_path, r.end, r.start);
    hostile_files(pm_path);
    lmt_rmdir(r.dir);
}

int main(void)
{
    if (!lmt_spider_path()) {
        fprintf(stderr, "test_pm: spider.obj missing (scripts/install-deps.sh)\n");
        return 77;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(pm_extract_equals_simplifier_at_every_count),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
