/* coordinator/job/view_turn.c — seeded rotations of the job's view set (view_turn.h). */
#include "coordinator/job/view_turn.h"

#include <math.h>

#include "common/optimizer/rng.h"

#define TURN_PI 3.14159265358979323846

/* A rotation about +Y by angle a. */
static void turn_y(double a, double r[9])
{
    double c = cos(a), s = sin(a);
    const double m[9] = {c, 0, s, 0, 1, 0, -s, 0, c};
    for (int i = 0; i < 9; i++)
        r[i] = m[i];
}

/* A uniform random rotation from three uniforms (Shoemake 1992). */
static void turn_any(double u1, double u2, double u3, double r[9])
{
    double a = sqrt(1 - u1), b = sqrt(u1);
    double w = a * sin(2 * TURN_PI * u2), x = a * cos(2 * TURN_PI * u2);
    double y = b * sin(2 * TURN_PI * u3), z = b * cos(2 * TURN_PI * u3);
    const double m[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                         2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                         2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
    for (int i = 0; i < 9; i++)
        r[i] = m[i];
}

void co_view_turn_matrix(lm_view_dist dist, uint64_t seed, uint32_t stream, double r[9])
{
    lm_rng g;
    lm_rng_seed(&g, seed ^ 0x7475726e2d766965ull ^ ((uint64_t)stream << 20));
    double u1 = lm_rng_unit(&g), u2 = lm_rng_unit(&g), u3 = lm_rng_unit(&g);
    if (dist == LM_VIEW_DIST_SPHERE)
        turn_any(u1, u2, u3, r);
    else if (dist == LM_VIEW_DIST_UPPER)
        turn_y(2 * TURN_PI * u1, r);
    else
        turn_y((2 * u1 - 1) * CO_VIEW_TURN_CAMERA_DEG * TURN_PI / 180, r);
}

void co_view_turn_apply(lm_view_set *s, lm_view_dist dist, uint64_t seed, uint32_t stream,
                        const float centre[3])
{
    if (!stream)
        return;
    double r[9];
    co_view_turn_matrix(dist, seed, stream, r);
    for (uint32_t i = 0; i < s->count; i++)
        lm_view_turn(&s->views[i], centre, r);
}
