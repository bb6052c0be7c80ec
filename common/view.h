/* common/view.h — viewpoints and cameras. Views are placed uniformly on a sphere around the
 * ORIGINAL model (or its upper hemisphere, or given cameras: lm_view_dist) (icosahedron for 12,
 * dodecahedron for 20, spherical Fibonacci otherwise), looking at its bounding-sphere centre,
 * framed so the whole sphere is visible; perspective projection. Held-out views (the paper's
 * evaluation protocol) are a fixed set of 24 directions that differ from every optimisation set;
 * the dense check is a third set of 96 at three distances. Matrices are column-major, OpenGL
 * conventions. */
#ifndef LM_COMMON_VIEW_H
#define LM_COMMON_VIEW_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"

#define LM_MAX_VIEWS 256
#define LM_MAX_VIEW_SIZE 4096
/* The paper's view set: 20 views (a dodecahedron) of 256 x 256 pixels. Every command that renders
 * views defaults to these. */
#define LM_DEFAULT_VIEWS 20u
#define LM_DEFAULT_VIEW_SIZE 256

typedef struct lm_view {
    float eye[3];
    float dir[3];   /* unit vector from eye towards the centre (the light shines along it) */
    float view[16]; /* world -> eye */
    float proj[16]; /* eye -> clip */
    float view_proj[16];
    int width, height; /* pixels */
} lm_view;

typedef struct lm_view_set {
    uint32_t count;
    lm_view views[LM_MAX_VIEWS];
} lm_view_set;

/* Views first, first + stride, ... (count of them) of a set: the share one worker serves.
 * Neighbours in a set's order look from one side of the model, so a contiguous share (stride 1)
 * gets all or nothing of a patch there; dealt with a stride, every share sees all sides and a
 * patch's work splits evenly. A stride of 0 counts as 1. */
typedef struct lm_view_deal {
    uint32_t first, count, stride;
} lm_view_deal;

/* Whether d names 1 or more views, all among a set of n. */
int lm_view_deal_fits(lm_view_deal d, uint32_t n);
/* The set's index of d's i-th view. */
uint32_t lm_view_deal_view(lm_view_deal d, uint32_t i);
/* Whether view h is one of d's; if so, *i is its place among them. */
int lm_view_deal_place(lm_view_deal d, uint32_t h, uint32_t *i);
/* d for people: "4-9" (stride 1), "1,3..29" (dealt), "5" (one view), "-" (none). */
void lm_view_deal_text(lm_view_deal d, char *buf, size_t cap);

/* n in 1..LM_MAX_VIEWS, size in 16..LM_MAX_VIEW_SIZE, radius > 0 and finite. */
lm_status lm_view_set_make(lm_view_set *out, uint32_t n, int size, const float centre[3],
                           float radius);
/* The 24 held-out views. */
lm_status lm_view_set_make_heldout(lm_view_set *out, int size, const float centre[3], float radius);

/* The dense check (`lumesh energy --dense`, scripts/fidelity.sh): LM_DENSE_VIEWS views, a third
 * each at 2, 3 and 5 bounding-sphere radii, every one framing the whole sphere, in directions that
 * are neither an optimisation set's nor the held-out set's. */
#define LM_DENSE_VIEWS 96u
lm_status lm_view_set_make_dense(lm_view_set *out, int size, const float centre[3], float radius);

/* Which set a command measures on: the optimisation views (--views N), the 24 held-out views or
 * the dense check. */
typedef enum lm_view_set_kind {
    LM_VIEWS_TRAINING,
    LM_VIEWS_HELDOUT,
    LM_VIEWS_DENSE
} lm_view_set_kind;

/* Where a set's views are (`--views N`, `--views upper[:N]`, `--views-from FILE`):
 *  SPHERE  the placements above, all around the model (the default, the value 0);
 *  UPPER   the hemisphere above the model's centre, +Y up as in glTF (assets standing on the
 *          ground): n spherical Fibonacci directions with y uniform in (0, 1); the held-out and
 *          dense sets are the sphere's directions MIRRORED into it (y -> |y|), so they keep their
 *          24 and 96 views and stay uniform over the hemisphere;
 *  CAMERAS given cameras (a camera file), each framing what it says (no reframing) with near and
 *          far planes from the model's bounding sphere; the held-out and dense sets stay the
 *          sphere's (no set of unseen cameras follows from a list of cameras). */
typedef enum lm_view_dist {
    LM_VIEW_DIST_SPHERE = 0,
    LM_VIEW_DIST_UPPER = 1,
    LM_VIEW_DIST_CAMERAS = 2
} lm_view_dist;

/* One camera of a camera file: where it is, what it looks at, which way is up, and its vertical
 * field of view in degrees (square images: the horizontal one is the same). */
typedef struct lm_camera {
    float position[3], target[3], up[3];
    float fov_deg;
} lm_camera;

/* The views a command renders. count 0 stands for the command's default (SPHERE, UPPER); for
 * CAMERAS it is the number of cameras (borrowed, not owned). */
typedef struct lm_view_spec {
    lm_view_dist dist;
    uint32_t count;
    const lm_camera *cameras;
} lm_view_spec;

/* The set of `kind` for spec (count already resolved: 1..LM_MAX_VIEWS), as the distribution says;
 * SPHERE gives exactly lm_view_set_make / _heldout / _dense. */
lm_status lm_view_set_make_spec(lm_view_set *out, const lm_view_spec *spec, lm_view_set_kind kind,
                                int size, const float centre[3], float radius);

/* Whether a camera can be used: finite numbers, position != target, an up vector of non-zero
 * length not parallel to the line of sight, a field of view in (0, 180) degrees. NULL when it
 * can, else what is wrong ("position equals target", ...). */
const char *lm_camera_problem(const lm_camera *c);

/* The distribution's name for messages and checkpoints: "sphere", "upper", "cameras". */
const char *lm_view_dist_name(lm_view_dist d);

/* Shift view v's picture by (dx, dy) pixels (x right, y up) while the camera stays where it is:
 * by a fraction of a pixel, the same sight sampled at other pixel centres (an off-centre
 * perspective; proj and view_proj updated). */
void lm_view_shift(lm_view *v, double dx, double dy);

/* Turn view v with the scene's rotation r (row-major 3x3, orthonormal) about `centre`: the camera
 * moves to centre + r (eye - centre) and looks along r dir; its picture is the same as before of
 * the model turned by r^T (a validation set or a new training set of the same distribution). */
void lm_view_turn(lm_view *v, const float centre[3], const double r[9]);

/* Project a world point: window coordinates in pixels (x right, y up from the bottom row as GL
 * does) and clip w. Returns 0 if w <= a small epsilon (behind or at the eye). */
int lm_view_project(const lm_view *v, const float p[3], float win[2], float *w);

#endif
