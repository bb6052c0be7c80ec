/* coordinator/frog/frog_texture.c — the frog's generated skin texture: one RGBA8 image holding
 * three charts (body, legs, eyes; see frog_internal.h). Every pattern edge is sharp (no blending),
 * so texture stretch and misplaced UVs show up clearly in rendered images. */
#include <math.h>
#include <string.h>

#include "coordinator/frog/frog.h"
#include "coordinator/frog/frog_internal.h"

#define SPOTS 34

typedef struct skin {
    double spot[SPOTS][3]; /* chart s, chart f, radius (surface units) */
    double stripe_phase;
    double stripe_freq;
} skin;

typedef struct rgb {
    uint8_t r, g, b;
} rgb;

static const rgb GREEN = {72, 142, 52}, DARK = {30, 62, 26}, BELLY = {226, 216, 152};
static const rgb FOLD = {168, 196, 92}, LEG = {84, 150, 56}, STRIPE = {38, 74, 30};
static const rgb FOOT = {120, 164, 74}, PUPIL = {8, 8, 10}, IRIS = {228, 186, 34};
static const rgb RING = {70, 44, 12}, LID = {66, 132, 48};

static void skin_init(skin *k, uint64_t seed)
{
    co_frog_rng r = {seed ^ 0x7E47u};
    for (int i = 0; i < SPOTS; i++) {
        k->spot[i][0] = co_frog_uniform(&r, 0.22, 0.78);
        k->spot[i][1] = co_frog_uniform(&r, 0.06, 0.92);
        k->spot[i][2] = co_frog_uniform(&r, 0.035, 0.10);
    }
    k->stripe_phase = co_frog_uniform(&r, 0.0, 1.0);
    k->stripe_freq = co_frog_uniform(&r, 8.0, 11.0);
}

/* Body: pale belly below sharp flanks, light dorsolateral folds, dark round spots. The spot test
 * measures distance on the surface (around ~2.8 units, along ~2.3) so spots look round. */
static rgb body_colour(const skin *k, double s, double f)
{
    double side = fabs(s - 0.5);
    if (side > 0.34)
        return BELLY;
    if (side > 0.215 && side < 0.24 && f > 0.2 && f < 0.86)
        return FOLD;
    for (int i = 0; i < SPOTS; i++) {
        double ds = (s - k->spot[i][0]) * 2.8, df = (f - k->spot[i][1]) * 2.3;
        if (ds * ds + df * df < k->spot[i][2] * k->spot[i][2])
            return DARK;
    }
    return GREEN;
}

/* Legs: dark bands across the thigh and shin, pale underside, lighter feet. */
static rgb leg_colour(const skin *k, double s, double f)
{
    if (f > 0.8)
        return FOOT;
    if (fabs(s - 0.5) > 0.38)
        return BELLY;
    double x = f * k->stripe_freq + k->stripe_phase;
    return x - floor(x) < 0.38 ? STRIPE : LEG;
}

/* Eyes: the end pole is the pupil (slightly horizontal), then a dark ring, a golden iris, lid. */
static rgb eye_colour(double s, double f)
{
    double pupil = 0.86 - 0.04 * cos(4.0 * M_PI * s);
    if (f > pupil)
        return PUPIL;
    if (f > 0.64)
        return IRIS;
    if (f > 0.61)
        return RING;
    return LID;
}

static double clamp01(double x)
{
    return x < 0 ? 0 : x > 1 ? 1 : x;
}

static rgb texel(const skin *k, double u, double v)
{
    int chart = u < 0.5 ? CO_FROG_CHART_BODY : v < 0.5 ? CO_FROG_CHART_LEGS : CO_FROG_CHART_EYES;
    const float *c = co_frog_charts[chart];
    double s = clamp01((u - c[0]) / (c[2] - c[0])), f = clamp01((v - c[1]) / (c[3] - c[1]));
    if (chart == CO_FROG_CHART_BODY)
        return body_colour(k, s, f);
    return chart == CO_FROG_CHART_LEGS ? leg_colour(k, s, f) : eye_colour(s, f);
}

lm_status co_frog_texture(uint64_t seed, lm_image **out)
{
    lm_image *img;
    lm_status st = lm_image_create(CO_FROG_TEXTURE_SIZE, CO_FROG_TEXTURE_SIZE, &img);
    if (st)
        return st;
    skin k;
    skin_init(&k, seed);
    for (int y = 0; y < img->height; y++) {
        double v = 1.0 - (y + 0.5) / img->height;
        uint8_t *row = img->pixels + (size_t)y * img->width * 4;
        for (int x = 0; x < img->width; x++) {
            rgb c = texel(&k, (x + 0.5) / img->width, v);
            row[4 * x + 0] = c.r;
            row[4 * x + 1] = c.g;
            row[4 * x + 2] = c.b;
            row[4 * x + 3] = 255;
        }
    }
    *out = img;
    return LM_OK;
}
