/* tests/unit/test_view_spec.c — the views' distributions (view.h: lm_view_dist): the upper
 * hemisphere (every eye at or above the centre, counts, deterministic, held-out and dense sets
 * mirrored into it and distinct), the sphere's sets unchanged through lm_view_set_make_spec,
 * cameras as a file gives them, and the camera file parser (common/io/camera_file.h): a valid
 * file and each way a file can be wrong. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/io/camera_file.h"
#include "common/view.h"
#include "test_support.h"

static const float centre[3] = {1, 2, 3};
static const float radius = 1.5f;

static lm_view_set *make(lm_view_dist d, uint32_t n, lm_view_set_kind kind)
{
    lm_view_set *vs = malloc(sizeof *vs);
    assert_non_null(vs);
    lm_view_spec s = {.dist = d, .count = n};
    assert_int_equal(lm_view_set_make_spec(vs, &s, kind, 64, centre, radius), LM_OK);
    return vs;
}

static float dot3(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Every eye at or above the centre, all directions apart, the centre in the middle. */
static void check_upper(const lm_view_set *vs, uint32_t n)
{
    assert_int_equal(vs->count, n);
    for (uint32_t i = 0; i < n; i++) {
        const lm_view *v = &vs->views[i];
        assert_true(v->eye[1] >= centre[1]);
        assert_true(v->dir[1] <= 0.0f);
        float win[2], w;
        assert_true(lm_view_project(v, centre, win, &w));
        assert_true(fabsf(win[0] - 32.0f) < 1e-3f && fabsf(win[1] - 32.0f) < 1e-3f);
        for (uint32_t j = 0; j < i; j++)
            assert_true(dot3(v->dir, vs->views[j].dir) < 0.9999f);
    }
}

static void test_upper_hemisphere(void **state)
{
    (void)state;
    static const uint32_t counts[] = {1, 7, 12, 20, 30, LM_MAX_VIEWS};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
        lm_view_set *a = make(LM_VIEW_DIST_UPPER, counts[k], LM_VIEWS_TRAINING);
        lm_view_set *b = make(LM_VIEW_DIST_UPPER, counts[k], LM_VIEWS_TRAINING);
        check_upper(a, counts[k]);
        assert_memory_equal(a->views, b->views, counts[k] * sizeof a->views[0]);
        free(a);
        free(b);
    }
    lm_view_set *h = make(LM_VIEW_DIST_UPPER, 20, LM_VIEWS_HELDOUT);
    check_upper(h, 24);
    lm_view_set *d = make(LM_VIEW_DIST_UPPER, 20, LM_VIEWS_DENSE);
    assert_int_equal(d->count, LM_DENSE_VIEWS);
    for (uint32_t i = 0; i < d->count; i++)
        assert_true(d->views[i].eye[1] >= centre[1]);
    /* the held-out upper views are none of the upper optimisation views */
    lm_view_set *t = make(LM_VIEW_DIST_UPPER, 20, LM_VIEWS_TRAINING);
    for (uint32_t i = 0; i < h->count; i++)
        for (uint32_t j = 0; j < t->count; j++)
            assert_true(dot3(h->views[i].dir, t->views[j].dir) < 0.9999f);
    free(h);
    free(d);
    free(t);
    lm_view_set vs;
    lm_view_spec none = {.dist = LM_VIEW_DIST_UPPER, .count = 0};
    assert_int_equal(lm_view_set_make_spec(&vs, &none, LM_VIEWS_TRAINING, 64, centre, radius),
                     LM_E_RANGE);
}

/* The sphere through lm_view_set_make_spec: the very sets of lm_view_set_make and friends. */
static void test_sphere_unchanged(void **state)
{
    (void)state;
    lm_view_set *a = malloc(sizeof *a);
    assert_non_null(a);
    static const uint32_t counts[] = {12, 20, 30};
    for (size_t k = 0; k < 3; k++) {
        lm_view_set *b = make(LM_VIEW_DIST_SPHERE, counts[k], LM_VIEWS_TRAINING);
        assert_int_equal(lm_view_set_make(a, counts[k], 64, centre, radius), LM_OK);
        assert_memory_equal(a->views, b->views, counts[k] * sizeof a->views[0]);
        free(b);
    }
    lm_view_set *b = make(LM_VIEW_DIST_SPHERE, 0, LM_VIEWS_HELDOUT);
    assert_int_equal(lm_view_set_make_heldout(a, 64, centre, radius), LM_OK);
    assert_memory_equal(a->views, b->views, 24 * sizeof a->views[0]);
    free(b);
    b = make(LM_VIEW_DIST_SPHERE, 0, LM_VIEWS_DENSE);
    assert_int_equal(lm_view_set_make_dense(a, 64, centre, radius), LM_OK);
    assert_memory_equal(a->views, b->views, LM_DENSE_VIEWS * sizeof a->views[0]);
    free(b);
    free(a);
}

static const char valid[] =
    "[{\"name\": \"street\", \"position\": [1, 2, 13], \"target\": [1, 2, 3], \"up\": [0, 1, 0],"
    "  \"fov\": 30},"
    " {\"position\": [6, 7, 3], \"target\": [1, 2, 3], \"up\": [0, 0, 2], \"fov\": 60.5}]";

static void test_cameras_valid(void **state)
{
    (void)state;
    lm_camera c[LM_MAX_VIEWS];
    uint32_t n = 0;
    assert_int_equal(lm_cameras_parse(valid, strlen(valid), "t.json", c, &n), LM_OK);
    assert_int_equal(n, 2);
    assert_true(c[0].position[2] == 13.0f && c[0].fov_deg == 30.0f && c[1].fov_deg == 60.5f);
    assert_true(c[1].up[2] == 2.0f && c[1].target[1] == 2.0f);
    /* the views look where the file says: the target in the image's middle, eye as given */
    lm_view_set *vs = malloc(sizeof *vs);
    assert_non_null(vs);
    lm_view_spec s = {.dist = LM_VIEW_DIST_CAMERAS, .count = n, .cameras = c};
    assert_int_equal(lm_view_set_make_spec(vs, &s, LM_VIEWS_TRAINING, 64, centre, radius), LM_OK);
    assert_int_equal(vs->count, 2);
    for (uint32_t i = 0; i < 2; i++) {
        float win[2], w;
        assert_true(lm_view_project(&vs->views[i], c[i].target, win, &w));
        assert_true(fabsf(win[0] - 32.0f) < 1e-3f && fabsf(win[1] - 32.0f) < 1e-3f);
        assert_memory_equal(vs->views[i].eye, c[i].position, sizeof c[i].position);
    }
    /* fov 30 at distance 10: a point 10·tan(15°) above the target is at the top edge */
    float top[3] = {1, 2 + 10.0f * tanf(15.0f * (float)M_PI / 180.0f), 3}, win[2], w;
    assert_true(lm_view_project(&vs->views[0], top, win, &w));
    assert_true(fabsf(win[1] - 64.0f) < 1e-2f);
    /* the held-out set stays the sphere's */
    lm_view_set *h = malloc(sizeof *h), *sphere = malloc(sizeof *sphere);
    assert_true(h && sphere);
    assert_int_equal(lm_view_set_make_spec(h, &s, LM_VIEWS_HELDOUT, 64, centre, radius), LM_OK);
    assert_int_equal(lm_view_set_make_heldout(sphere, 64, centre, radius), LM_OK);
    assert_memory_equal(h->views, sphere->views, 24 * sizeof h->views[0]);
    free(h);
    free(sphere);
    free(vs);
}

static void expect_refused(const char *json, const char *why)
{
    lm_camera c[LM_MAX_VIEWS];
    uint32_t n = 7;
    lm_status st = lm_cameras_parse(json, strlen(json), "bad.json", c, &n);
    if (st != LM_E_FORMAT || !strstr(lm_last_error(), why) || !strstr(lm_last_error(), "bad.json"))
        fail_msg("%s: status %d, '%s', expected '%s'", json, st, lm_last_error(), why);
    assert_int_equal(n, 7);
}

#define CAM(pos, tgt, up, fov) "{\"position\": " pos ", \"target\": " tgt ", \"up\": " up fov "}"
#define OK_FOV ", \"fov\": 40"

static void test_cameras_invalid(void **state)
{
    (void)state;
    expect_refused("[", "not JSON");
    expect_refused("{}", "expected an array of cameras");
    expect_refused("[]", "no cameras");
    expect_refused("[3]", "camera 0: not an object");
    expect_refused("[" CAM("[0, 0, 1]", "[0, 0, 0]", "[0, 1, 0]", "") "]", "missing \"fov\"");
    expect_refused("[{\"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov\": 40}]",
                   "missing \"position\"");
    expect_refused("[" CAM("[0, 0, 1]", "[0, 0, 0]", "[0, 1, 0]",
                           OK_FOV) "," CAM("[0, 0, 1]", "[0, 0]", "[0, 1, 0]", OK_FOV) "]",
                   "camera 1: \"target\" is not 3 numbers");
    expect_refused("[" CAM("[0, 0, \"1\"]", "[0, 0, 0]", "[0, 1, 0]", OK_FOV) "]",
                   "\"position\" is not 3 numbers");
    expect_refused("[" CAM("[0, 0, 1]", "[0, 0, 0]", "[0, 1, 0]", ", \"fov\": \"wide\"") "]",
                   "\"fov\" is not a number");
    expect_refused("[" CAM("[0, 0, NaN]", "[0, 0, 0]", "[0, 1, 0]", OK_FOV) "]", "not JSON");
    expect_refused("[" CAM("[0, 0, 1e999]", "[0, 0, 0]", "[0, 1, 0]", OK_FOV) "]", "not JSON");
    expect_refused("[" CAM("[0, 0, 1e39]", "[0, 0, 0]", "[0, 1, 0]", OK_FOV) "]", "not finite");
    expect_refused("[" CAM("[0, 0, 1]", "[0, 0, 1]", "[0, 1, 0]", OK_FOV) "]",
                   "position equals target");
    expect_refused("[" CAM("[0, 0, 1]", "[0, 0, 0]", "[0, 0, 0]", OK_FOV) "]",
                   "up has zero length");
    expect_refused("[" CAM("[0, 0, 1]", "[0, 0, 0]", "[0, 0, -3]", OK_FOV) "]",
                   "up is parallel to the line of sight");
    expect_refused("[" CAM("[0, 0, 1]", "[0, 0, 0]", "[0, 1, 0]", ", \"fov\": 0") "]",
                   "fov is outside (0, 180) degrees");
    expect_refused("[" CAM("[0, 0, 1]", "[0, 0, 0]", "[0, 1, 0]", ", \"fov\": 180") "]",
                   "fov is outside (0, 180) degrees");
    expect_refused("[" CAM("[0, 0, 1]", "[0, 0, 0]", "[0, 1, 0]", OK_FOV ", \"weight\": 2") "]",
                   "\"weight\" is not supported");
    expect_refused("[" CAM("[0, 0, 1]", "[0, 0, 0]", "[0, 1, 0]", OK_FOV ", \"zoom\": 2") "]",
                   "unknown key \"zoom\"");
    /* more than LM_MAX_VIEWS cameras */
    const char *one = CAM("[0, 0, 1]", "[0, 0, 0]", "[0, 1, 0]", OK_FOV) ",";
    size_t len = strlen(one), n = LM_MAX_VIEWS + 1;
    char *many = malloc(n * len + 2);
    assert_non_null(many);
    many[0] = '[';
    for (size_t i = 0; i < n; i++)
        memcpy(many + 1 + i * len, one, len);
    many[n * len] = ']';
    many[n * len + 1] = 0;
    expect_refused(many, "257 cameras, at most 256");
    many[(n - 1) * len] = ']';
    many[(n - 1) * len + 1] = 0;
    lm_camera c[LM_MAX_VIEWS];
    uint32_t got = 0;
    assert_int_equal(lm_cameras_parse(many, strlen(many), "max.json", c, &got), LM_OK);
    assert_int_equal(got, LM_MAX_VIEWS);
    free(many);
}

static void test_cameras_file(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char path[4096];
    snprintf(path, sizeof path, "%s/cams.json", dir);
    lm_camera c[LM_MAX_VIEWS];
    uint32_t n = 0;
    assert_int_equal(lm_cameras_read(path, c, &n), LM_E_IO); /* missing */
    assert_non_null(strstr(lm_last_error(), "cannot read camera file"));
    assert_int_equal(lm_cameras_read(dir, c, &n), LM_E_IO); /* a folder */
    FILE *fp = fopen(path, "w");
    assert_non_null(fp);
    fputs(valid, fp);
    fclose(fp);
    assert_int_equal(lm_cameras_read(path, c, &n), LM_OK);
    assert_int_equal(n, 2);
    remove(path);
    lmt_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_upper_hemisphere), cmocka_unit_test(test_sphere_unchanged),
        cmocka_unit_test(test_cameras_valid),    cmocka_unit_test(test_cameras_invalid),
        cmocka_unit_test(test_cameras_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
