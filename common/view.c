/* common/view.c — viewpoints and cameras (see view.h): directions uniform on the sphere
 * (icosahedron for 12, dodecahedron for 20, spherical Fibonacci otherwise, a rotated Fibonacci set
 * of 24 for the held-out views) or on the upper hemisphere (Fibonacci; the held-out and dense
 * sets mirrored into it), look-at and perspective matrices framing the bounding sphere or as given
 * cameras say, and the projection of world points to window pixels. */
#include "common/view.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define LM_VIEW_DISTANCE 3.0  /* eye distance from the centre, in bounding-sphere radii */
#define LM_VIEW_MARGIN 1.05   /* field-of-view margin around the sphere */
#define LM_VIEW_DEPTH_PAD 1.1 /* near/far planes this many radii in front of/behind the centre */
#define LM_HELDOUT_COUNT 24
#define LM_DENSE_RINGS 3    /* the dense check: LM_DENSE_VIEWS / 3 directions at each distance */
#define LM_CAMERA_NEAR 1e-3 /* a camera inside the bounding sphere: near plane at this x far */

static void normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l;
    v[1] /= l;
    v[2] /= l;
}

static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* The 12 vertices of a regular icosahedron (0, ±1, ±φ) and cyclic permutations. */
static void icosahedron_dirs(double (*d)[3])
{
    const double p = (1.0 + sqrt(5.0)) / 2.0;
    int k = 0;
    for (int s1 = -1; s1 <= 1; s1 += 2)
        for (int s2 = -1; s2 <= 1; s2 += 2) {
            double a = s1, b = s2 * p;
            d[k][0] = 0, d[k][1] = a, d[k][2] = b, k++;
            d[k][0] = a, d[k][1] = b, d[k][2] = 0, k++;
            d[k][0] = b, d[k][1] = 0, d[k][2] = a, k++;
        }
}

/* The dodecahedron's vertices are listed along a nearest-neighbour tour (from the first vertex
 * made, always to the nearest one not yet visited, the first of equals): consecutive views look
 * from neighbouring directions, so dealing every G-th view to each of G workers (lm_view_deal)
 * gives each share one view of every neighbourhood, and a patch seen from one side is priced by
 * all of them about equally. The order they are made in groups them by a coordinate's sign
 * instead (the first 8, the cube's corners, alternate in x), and dealt in halves one worker had
 * all four +x corners: evaluating the bench's patches over 20 views of 256², the busier half
 * took 1.23× the mean share of time, along the tour 1.06× (four shares: 1.38× and 1.21×);
 * `lumesh bench eval --workers 2`, two workers ×1.04–1.14 evaluations/s (three alternated runs). */
static const uint8_t dodecahedron_tour[20] = {0, 8,  1, 13, 3,  14, 2,  10, 16, 4,
                                              9, 15, 5, 11, 17, 6,  12, 18, 7,  19};

/* The 20 vertices of a regular dodecahedron: (±1, ±1, ±1) and cyclic (0, ±1/φ, ±φ). */
static void dodecahedron_dirs(double (*d)[3])
{
    const double p = (1.0 + sqrt(5.0)) / 2.0;
    double m[20][3];
    int k = 0;
    for (int i = 0; i < 8; i++) {
        m[k][0] = (i & 1) ? 1 : -1;
        m[k][1] = (i & 2) ? 1 : -1;
        m[k][2] = (i & 4) ? 1 : -1;
        k++;
    }
    for (int s1 = -1; s1 <= 1; s1 += 2)
        for (int s2 = -1; s2 <= 1; s2 += 2) {
            double a = s1 / p, b = s2 * p;
            m[k][0] = 0, m[k][1] = a, m[k][2] = b, k++;
            m[k][0] = a, m[k][1] = b, m[k][2] = 0, k++;
            m[k][0] = b, m[k][1] = 0, m[k][2] = a, k++;
        }
    for (int i = 0; i < 20; i++)
        for (int c = 0; c < 3; c++)
            d[i][c] = m[dodecahedron_tour[i]][c];
}

/* Spherical Fibonacci points: z uniform in (1 - span, 1) from the top down (span 2: the sphere,
 * 1: the upper hemisphere), longitude advancing by the golden angle. */
static void fibonacci_span(double (*d)[3], uint32_t n, double span)
{
    const double golden = M_PI * (3.0 - sqrt(5.0));
    for (uint32_t i = 0; i < n; i++) {
        double z = 1.0 - span * (i + 0.5) / n;
        double r = sqrt(fmax(0.0, 1.0 - z * z));
        double phi = golden * i;
        d[i][0] = r * cos(phi);
        d[i][1] = z;
        d[i][2] = r * sin(phi);
    }
}

static void fibonacci_dirs(double (*d)[3], uint32_t n)
{
    fibonacci_span(d, n, 2.0);
}

/* Rotate v about a unit axis by angle (Rodrigues). */
static void rotate3(double v[3], const double axis[3], double angle)
{
    double c = cos(angle), s = sin(angle), k[3], kv[3];
    double dot = axis[0] * v[0] + axis[1] * v[1] + axis[2] * v[2];
    memcpy(k, axis, sizeof k);
    cross3(k, v, kv);
    for (int i = 0; i < 3; i++)
        v[i] = v[i] * c + kv[i] * s + k[i] * dot * (1.0 - c);
}

/* Column-major look-at: eye looking along unit `fwd`, `up` not parallel to it. */
static void look_at_up(const double eye[3], const double fwd[3], const double up[3], float out[16])
{
    double s[3], u[3];
    cross3(fwd, up, s);
    normalize3(s);
    cross3(s, fwd, u);
    memset(out, 0, 16 * sizeof(float));
    for (int i = 0; i < 3; i++) {
        out[i * 4 + 0] = (float)s[i];
        out[i * 4 + 1] = (float)u[i];
        out[i * 4 + 2] = (float)-fwd[i];
    }
    out[12] = (float)-(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]);
    out[13] = (float)-(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]);
    out[14] = (float)(fwd[0] * eye[0] + fwd[1] * eye[1] + fwd[2] * eye[2]);
    out[15] = 1.0f;
}

/* look_at_up with an up vector that avoids the poles. */
static void look_at(const double eye[3], const double fwd[3], float out[16])
{
    double up[3] = {0, 1, 0};
    if (fabs(fwd[1]) > 0.95) {
        up[1] = 0;
        up[2] = 1;
    }
    look_at_up(eye, fwd, up, out);
}

static void perspective(double half_fov, double aspect, double n, double f, float out[16])
{
    double t = 1.0 / tan(half_fov);
    memset(out, 0, 16 * sizeof(float));
    out[0] = (float)(t / aspect);
    out[5] = (float)t;
    out[10] = (float)(-(f + n) / (f - n));
    out[11] = -1.0f;
    out[14] = (float)(-2.0 * f * n / (f - n));
}

static void mat4_mul(const float a[16], const float b[16], float out[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += (double)a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = (float)s;
        }
}

/* Camera on direction d (unit, from the centre towards the eye), `distance` bounding-sphere radii
 * from the centre (> 1), framing the whole sphere. */
static void make_view(lm_view *v, const double d[3], int size, const float centre[3], float radius,
                      double distance)
{
    double dist = distance * radius, eye[3], fwd[3];
    for (int i = 0; i < 3; i++) {
        eye[i] = centre[i] + dist * d[i];
        fwd[i] = -d[i];
        v->eye[i] = (float)eye[i];
        v->dir[i] = (float)fwd[i];
    }
    double half_fov = asin(1.0 / distance) * LM_VIEW_MARGIN;
    double n = dist - LM_VIEW_DEPTH_PAD * radius, f = dist + LM_VIEW_DEPTH_PAD * radius;
    look_at(eye, fwd, v->view);
    perspective(half_fov, 1.0, n, f, v->proj);
    mat4_mul(v->proj, v->view, v->view_proj);
    v->width = size;
    v->height = size;
}

void lm_view_shift(lm_view *v, double dx, double dy)
{
    /* clip x += t·w with w = -z_eye (the projection's last row 0 0 -1 0): the column of z */
    v->proj[8] = (float)((double)v->proj[8] - 2.0 * dx / v->width);
    v->proj[9] = (float)((double)v->proj[9] - 2.0 * dy / v->height);
    mat4_mul(v->proj, v->view, v->view_proj);
}

void lm_view_turn(lm_view *v, const float centre[3], const double r[9])
{
    /* world point p of the turned scene was R^T (p - c) + c before: view' = view · M */
    float m[16] = {0}, view[16];
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++)
            m[c * 4 + k] = (float)r[c * 3 + k]; /* (R^T)[k][c] = R[c][k] */
    for (int k = 0; k < 3; k++) {
        double t = centre[k];
        for (int c = 0; c < 3; c++)
            t -= r[c * 3 + k] * centre[c];
        m[12 + k] = (float)t;
    }
    m[15] = 1.0f;
    double eye[3], dir[3];
    for (int i = 0; i < 3; i++) {
        eye[i] = centre[i];
        dir[i] = 0;
        for (int k = 0; k < 3; k++) {
            eye[i] += r[i * 3 + k] * ((double)v->eye[k] - centre[k]);
            dir[i] += r[i * 3 + k] * v->dir[k];
        }
    }
    for (int i = 0; i < 3; i++) {
        v->eye[i] = (float)eye[i];
        v->dir[i] = (float)dir[i];
    }
    mat4_mul(v->view, m, view);
    memcpy(v->view, view, sizeof view);
    mat4_mul(v->proj, v->view, v->view_proj);
}

static lm_status check_args(int size, const float centre[3], float radius)
{
    if (size < 16 || size > LM_MAX_VIEW_SIZE)
        return lm_fail(LM_E_RANGE, "view size %d is outside 16..%d", size, LM_MAX_VIEW_SIZE);
    if (!(radius > 0.0f) || !isfinite(radius))
        return lm_fail(LM_E_RANGE, "bounding-sphere radius %g is not a positive finite number",
                       (double)radius);
    for (int i = 0; i < 3; i++)
        if (!isfinite(centre[i]))
            return lm_fail(LM_E_RANGE, "bounding-sphere centre is not finite");
    return LM_OK;
}

int lm_view_deal_fits(lm_view_deal d, uint32_t n)
{
    uint64_t stride = d.stride ? d.stride : 1;
    return d.count >= 1 && d.first < n && d.first + (uint64_t)(d.count - 1) * stride < n;
}

uint32_t lm_view_deal_view(lm_view_deal d, uint32_t i)
{
    return d.first + i * (d.stride ? d.stride : 1);
}

int lm_view_deal_place(lm_view_deal d, uint32_t h, uint32_t *i)
{
    uint32_t stride = d.stride ? d.stride : 1;
    if (h < d.first || (h - d.first) % stride || (h - d.first) / stride >= d.count)
        return 0;
    *i = (h - d.first) / stride;
    return 1;
}

void lm_view_deal_text(lm_view_deal d, char *buf, size_t cap)
{
    uint32_t last = d.count ? lm_view_deal_view(d, d.count - 1) : 0;
    if (!d.count)
        snprintf(buf, cap, "-");
    else if (d.count == 1)
        snprintf(buf, cap, "%u", d.first);
    else if (d.stride <= 1)
        snprintf(buf, cap, "%u-%u", d.first, last);
    else
        snprintf(buf, cap, "%u,%u..%u", d.first, d.first + d.stride, last);
}

/* upper: n Fibonacci directions on the upper hemisphere instead of the sphere's placements. */
static lm_status make_placed(lm_view_set *out, uint32_t n, int size, const float centre[3],
                             float radius, int upper)
{
    if (n < 1 || n > LM_MAX_VIEWS)
        return lm_fail(LM_E_RANGE, "view count %u is outside 1..%d", n, LM_MAX_VIEWS);
    lm_status st = check_args(size, centre, radius);
    if (st != LM_OK)
        return st;
    double dirs[LM_MAX_VIEWS][3];
    if (upper)
        fibonacci_span(dirs, n, 1.0);
    else if (n == 12)
        icosahedron_dirs(dirs);
    else if (n == 20)
        dodecahedron_dirs(dirs);
    else
        fibonacci_dirs(dirs, n);
    out->count = n;
    for (uint32_t i = 0; i < n; i++) {
        normalize3(dirs[i]);
        make_view(&out->views[i], dirs[i], size, centre, radius, LM_VIEW_DISTANCE);
    }
    return LM_OK;
}

lm_status lm_view_set_make(lm_view_set *out, uint32_t n, int size, const float centre[3],
                           float radius)
{
    return make_placed(out, n, size, centre, radius, 0);
}

/* mirror: the directions folded into the upper hemisphere (y -> |y|). */
static lm_status make_heldout(lm_view_set *out, int size, const float centre[3], float radius,
                              int mirror)
{
    lm_status st = check_args(size, centre, radius);
    if (st != LM_OK)
        return st;
    /* A Fibonacci set of 24 turned by an irrational-looking rotation: no direction coincides with
     * the icosahedron, the dodecahedron or any Fibonacci set (whose first point is near +y). */
    double dirs[LM_HELDOUT_COUNT][3], axis[3] = {0.3, 0.8, 0.52};
    normalize3(axis);
    fibonacci_dirs(dirs, LM_HELDOUT_COUNT);
    out->count = LM_HELDOUT_COUNT;
    for (uint32_t i = 0; i < LM_HELDOUT_COUNT; i++) {
        rotate3(dirs[i], axis, 0.61);
        normalize3(dirs[i]);
        if (mirror)
            dirs[i][1] = fabs(dirs[i][1]);
        make_view(&out->views[i], dirs[i], size, centre, radius, LM_VIEW_DISTANCE);
    }
    return LM_OK;
}

lm_status lm_view_set_make_heldout(lm_view_set *out, int size, const float centre[3], float radius)
{
    return make_heldout(out, size, centre, radius, 0);
}

static lm_status make_dense(lm_view_set *out, int size, const float centre[3], float radius,
                            int mirror)
{
    lm_status st = check_args(size, centre, radius);
    if (st != LM_OK)
        return st;
    /* Per distance a Fibonacci set of 32 turned about its own axis by its own angle: none of these
     * directions is one of the optimisation sets' (unturned Fibonacci, icosahedron, dodecahedron)
     * or the held-out set's (axis (0.3, 0.8, 0.52), 0.61 rad). */
    static const double distance[LM_DENSE_RINGS] = {2.0, 3.0, 5.0};
    static const double axis[LM_DENSE_RINGS][3] = {
        {0.7, -0.2, 0.45}, {-0.35, 0.6, 0.9}, {0.15, 0.95, -0.4}};
    static const double angle[LM_DENSE_RINGS] = {0.83, 1.37, 0.29};
    const uint32_t per = LM_DENSE_VIEWS / LM_DENSE_RINGS;
    double dirs[LM_DENSE_VIEWS / LM_DENSE_RINGS][3];
    out->count = 0;
    for (int r = 0; r < LM_DENSE_RINGS; r++) {
        double ax[3] = {axis[r][0], axis[r][1], axis[r][2]};
        normalize3(ax);
        fibonacci_dirs(dirs, per);
        for (uint32_t i = 0; i < per; i++) {
            rotate3(dirs[i], ax, angle[r]);
            normalize3(dirs[i]);
            if (mirror)
                dirs[i][1] = fabs(dirs[i][1]);
            make_view(&out->views[out->count++], dirs[i], size, centre, radius, distance[r]);
        }
    }
    return LM_OK;
}

lm_status lm_view_set_make_dense(lm_view_set *out, int size, const float centre[3], float radius)
{
    return make_dense(out, size, centre, radius, 0);
}

static int finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static double length3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

const char *lm_camera_problem(const lm_camera *c)
{
    if (!finite3(c->position) || !finite3(c->target) || !finite3(c->up) || !isfinite(c->fov_deg))
        return "a number is not finite";
    if (!(c->fov_deg > 0.0f && c->fov_deg < 180.0f))
        return "fov is outside (0, 180) degrees";
    double fwd[3], up[3], s[3];
    for (int i = 0; i < 3; i++) {
        fwd[i] = (double)c->target[i] - c->position[i];
        up[i] = c->up[i];
    }
    double lf = length3(fwd), lu = length3(up);
    if (!(lf > 0.0))
        return "position equals target";
    if (!(lu > 0.0))
        return "up has zero length";
    cross3(fwd, up, s);
    if (!(length3(s) > 1e-6 * lf * lu))
        return "up is parallel to the line of sight";
    return NULL;
}

/* A camera of a file as it is, near and far planes from the bounding sphere (in front of the
 * camera: a tiny fraction of far when the camera is inside the sphere). */
static void make_camera_view(lm_view *v, const lm_camera *c, int size, const float centre[3],
                             float radius)
{
    double eye[3], fwd[3], up[3], to_c[3];
    for (int i = 0; i < 3; i++) {
        eye[i] = c->position[i];
        fwd[i] = (double)c->target[i] - eye[i];
        up[i] = c->up[i];
        to_c[i] = (double)centre[i] - eye[i];
    }
    normalize3(fwd);
    double dist = length3(to_c);
    double f = dist + LM_VIEW_DEPTH_PAD * radius;
    double n = fmax(dist - LM_VIEW_DEPTH_PAD * radius, LM_CAMERA_NEAR * f);
    for (int i = 0; i < 3; i++) {
        v->eye[i] = (float)eye[i];
        v->dir[i] = (float)fwd[i];
    }
    look_at_up(eye, fwd, up, v->view);
    perspective(0.5 * c->fov_deg * M_PI / 180.0, 1.0, n, f, v->proj);
    mat4_mul(v->proj, v->view, v->view_proj);
    v->width = size;
    v->height = size;
}

static lm_status make_cameras(lm_view_set *out, const lm_view_spec *spec, int size,
                              const float centre[3], float radius)
{
    if (spec->count < 1 || spec->count > LM_MAX_VIEWS || !spec->cameras)
        return lm_fail(LM_E_RANGE, "camera count %u is outside 1..%d", spec->count, LM_MAX_VIEWS);
    lm_status st = check_args(size, centre, radius);
    for (uint32_t i = 0; st == LM_OK && i < spec->count; i++) {
        const char *why = lm_camera_problem(&spec->cameras[i]);
        if (why)
            return lm_fail(LM_E_INVALID, "camera %u: %s", i, why);
    }
    if (st != LM_OK)
        return st;
    out->count = spec->count;
    for (uint32_t i = 0; i < spec->count; i++)
        make_camera_view(&out->views[i], &spec->cameras[i], size, centre, radius);
    return LM_OK;
}

lm_status lm_view_set_make_spec(lm_view_set *out, const lm_view_spec *spec, lm_view_set_kind kind,
                                int size, const float centre[3], float radius)
{
    int upper = spec->dist == LM_VIEW_DIST_UPPER;
    if (kind == LM_VIEWS_HELDOUT)
        return make_heldout(out, size, centre, radius, upper);
    if (kind == LM_VIEWS_DENSE)
        return make_dense(out, size, centre, radius, upper);
    if (spec->dist == LM_VIEW_DIST_CAMERAS)
        return make_cameras(out, spec, size, centre, radius);
    return make_placed(out, spec->count, size, centre, radius, upper);
}

const char *lm_view_dist_name(lm_view_dist d)
{
    return d == LM_VIEW_DIST_UPPER ? "upper" : d == LM_VIEW_DIST_CAMERAS ? "cameras" : "sphere";
}

int lm_view_project(const lm_view *v, const float p[3], float win[2], float *w)
{
    const float *m = v->view_proj;
    float c[4];
    for (int r = 0; r < 4; r++)
        c[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    if (w)
        *w = c[3];
    /* The near plane sits at eye depth -proj[14]/(1-proj[10]); a tiny fraction of it is "at the
     * eye". */
    float near = v->proj[14] / (v->proj[10] - 1.0f);
    if (!(c[3] > 1e-4f * near))
        return 0;
    win[0] = (c[0] / c[3] * 0.5f + 0.5f) * (float)v->width;
    win[1] = (c[1] / c[3] * 0.5f + 0.5f) * (float)v->height;
    return 1;
}
