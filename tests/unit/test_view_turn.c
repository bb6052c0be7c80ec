/* tests/unit/test_view_turn.c — the job's other view sets (view_turn.h, `optimize
 * --validate-every`): lm_view_turn shows the scene turned (a point projects where its turned-back
 * image did); the rotations are proper, a function of (seed, stream) alone, and differ between
 * streams; upper keeps the hemisphere and cameras stay within ±15 degrees; the sphere's validation
 * views are none of the training, held-out or dense directions; stream 0 changes nothing. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "common/view.h"
#include "coordinator/job/view_turn.h"
#include "test_support.h"

static const float centre[3] = {0.1f, -0.2f, 0.3f};

static lm_view_set *make_set(lm_view_set_kind kind, lm_view_dist dist)
{
    lm_view_set *vs = malloc(sizeof *vs);
    assert_non_null(vs);
    lm_view_spec spec = {.dist = dist, .count = 30};
    assert_int_equal(lm_view_set_make_spec(vs, &spec, kind, 64, centre, 1.5f), LM_OK);
    return vs;
}

static void check_rotation(const double r[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double dot = 0;
            for (int k = 0; k < 3; k++)
                dot += r[i * 3 + k] * r[j * 3 + k];
            assert_float_equal(dot, i == j ? 1.0 : 0.0, 1e-12);
        }
    double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                 r[2] * (r[3] * r[7] - r[4] * r[6]);
    assert_float_equal(det, 1.0, 1e-12);
}

static void test_turn_projects_the_turned_scene(void **state)
{
    (void)state;
    lm_view_set *vs = make_set(LM_VIEWS_TRAINING, LM_VIEW_DIST_SPHERE);
    double r[9];
    co_view_turn_matrix(LM_VIEW_DIST_SPHERE, 3, CO_VIEW_TURN_VALIDATION, r);
    for (uint32_t i = 0; i < vs->count; i++) {
        lm_view turned = vs->views[i];
        lm_view_turn(&turned, centre, r);
        for (int k = 0; k < 10; k++) {
            const float p[3] = {0.1f + 0.1f * (float)(k % 3) - 0.1f, -0.2f + 0.05f * (float)k,
                                0.3f - 0.04f * (float)k};
            float back[3];
            for (int a = 0; a < 3; a++) { /* R^T (p - c) + c */
                double s = centre[a];
                for (int b = 0; b < 3; b++)
                    s += r[b * 3 + a] * (p[b] - centre[b]);
                back[a] = (float)s;
            }
            float x[2], y[2], wx, wy;
            assert_true(lm_view_project(&turned, p, x, &wx));
            assert_true(lm_view_project(&vs->views[i], back, y, &wy));
            assert_float_equal(x[0], y[0], 2e-3);
            assert_float_equal(x[1], y[1], 2e-3);
            assert_float_equal(wx, wy, 1e-4);
        }
    }
    free(vs);
}

static void test_rotations(void **state)
{
    (void)state;
    const lm_view_dist dists[3] = {LM_VIEW_DIST_SPHERE, LM_VIEW_DIST_UPPER, LM_VIEW_DIST_CAMERAS};
    for (int d = 0; d < 3; d++)
        for (uint32_t stream = 1; stream < 6; stream++) {
            double r[9], again[9], other[9];
            co_view_turn_matrix(dists[d], 1, stream, r);
            co_view_turn_matrix(dists[d], 1, stream, again);
            co_view_turn_matrix(dists[d], 1, stream + 1, other);
            check_rotation(r);
            assert_memory_equal(r, again, sizeof r);
            assert_memory_not_equal(r, other, sizeof r);
            co_view_turn_matrix(dists[d], 2, stream, other); /* another seed */
            assert_memory_not_equal(r, other, sizeof r);
            if (dists[d] != LM_VIEW_DIST_SPHERE) /* about +Y */
                assert_float_equal(r[4], 1.0, 1e-12);
            if (dists[d] == LM_VIEW_DIST_CAMERAS) /* cos of at most 15 degrees */
                assert_true(r[0] >= cos(CO_VIEW_TURN_CAMERA_DEG * 3.14159265358979 / 180) - 1e-12);
        }
}

/* The smallest angle between a direction of `a` and one of `b`, in radians. */
static double min_angle(const lm_view_set *a, const lm_view_set *b)
{
    double best = 10;
    for (uint32_t i = 0; i < a->count; i++)
        for (uint32_t j = 0; j < b->count; j++) {
            double dot = 0;
            for (int k = 0; k < 3; k++)
                dot += (double)a->views[i].dir[k] * b->views[j].dir[k];
            double ang = acos(dot > 1 ? 1 : dot);
            best = ang < best ? ang : best;
        }
    return best;
}

static void test_validation_views_are_unseen(void **state)
{
    (void)state;
    lm_view_set *train = make_set(LM_VIEWS_TRAINING, LM_VIEW_DIST_SPHERE);
    lm_view_set *val = make_set(LM_VIEWS_TRAINING, LM_VIEW_DIST_SPHERE);
    lm_view_set *held = make_set(LM_VIEWS_HELDOUT, LM_VIEW_DIST_SPHERE);
    lm_view_set *dense = make_set(LM_VIEWS_DENSE, LM_VIEW_DIST_SPHERE);
    lm_view_set *same = make_set(LM_VIEWS_TRAINING, LM_VIEW_DIST_SPHERE);
    co_view_turn_apply(same, LM_VIEW_DIST_SPHERE, 1, 0, centre); /* stream 0: as made */
    assert_memory_equal(same, train, sizeof *same);
    co_view_turn_apply(val, LM_VIEW_DIST_SPHERE, 1, CO_VIEW_TURN_VALIDATION, centre);
    double a = min_angle(val, train), b = min_angle(val, held), c = min_angle(val, dense);
    assert_true(a > 0.01 && b > 0.01 && c > 0.01);
    free(train);
    free(val);
    free(held);
    free(dense);
    free(same);
    lm_view_set *up = make_set(LM_VIEWS_TRAINING, LM_VIEW_DIST_UPPER);
    co_view_turn_apply(up, LM_VIEW_DIST_UPPER, 1, CO_VIEW_TURN_VALIDATION, centre);
    for (uint32_t i = 0; i < up->count; i++) /* still above the centre */
        assert_true(up->views[i].eye[1] > centre[1]);
    free(up);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_turn_projects_the_turned_scene),
        cmocka_unit_test(test_rotations),
        cmocka_unit_test(test_validation_views_are_unseen),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
