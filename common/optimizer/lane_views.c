/* common/optimizer/lane_views.c — a lane's views: composite patches against the group's
 * start, virtual commits, reverts by difference, requests handed to the scheduler. */
#include "common/optimizer/lane_views.h"

#include <stdlib.h>
#include <string.h>

static lm_lane_views *as_lane(lm_views *v)
{
    return (lm_lane_views *)v;
}

/* ---- composition (all lists sorted by id) ---------------------------------------------------- */

static int has_id(const uint32_t *ids, uint32_t n, uint32_t id)
{
    uint32_t lo = 0, hi = n;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (ids[mid] < id)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && ids[lo] == id;
}

static int adds_id(const lm_patch *p, uint32_t id)
{
    uint32_t lo = 0, hi = p->n_added;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (p->added[mid].id < id)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < p->n_added && p->added[lo].id == id;
}

/* removed: acc's, and P's that acc did not add (those existed at the start). */
static lm_status compose_removed(const lm_patch *acc, const lm_patch *p, lm_patch *out)
{
    uint32_t i = 0, j = 0;
    lm_status st = LM_OK;
    while (st == LM_OK && (i < acc->n_removed || j < p->n_removed)) {
        if (j < p->n_removed && adds_id(acc, p->removed[j])) {
            j++;
            continue;
        }
        uint32_t a = i < acc->n_removed ? acc->removed[i] : UINT32_MAX;
        uint32_t b = j < p->n_removed ? p->removed[j] : UINT32_MAX;
        st = lm_patch_remove(out, a < b ? a : b);
        i += a <= b;
        j += b <= a;
    }
    return st;
}

/* added: acc's that P does not remove, and P's (merged by id). */
static lm_status compose_added(const lm_patch *acc, const lm_patch *p, lm_patch *out)
{
    uint32_t i = 0, j = 0;
    lm_status st = LM_OK;
    while (st == LM_OK && (i < acc->n_added || j < p->n_added)) {
        if (i < acc->n_added && has_id(p->removed, p->n_removed, acc->added[i].id)) {
            i++;
            continue;
        }
        int take_acc = i < acc->n_added && (j >= p->n_added || acc->added[i].id < p->added[j].id);
        st = lm_patch_add(out, take_acc ? &acc->added[i++] : &p->added[j++]);
    }
    return st;
}

/* out := compose(acc, p): start -> (lane + p). */
static lm_status compose(const lm_patch *acc, const lm_patch *p, lm_patch *out)
{
    lm_patch_reset(out);
    lm_status st = compose_removed(acc, p, out);
    return st == LM_OK ? compose_added(acc, p, out) : st;
}

/* out := the difference from the start to tris (sorted by id). */
static lm_status diff_from_start(const lm_lane_views *v, const lm_tri_data *tris, size_t n,
                                 lm_patch *out)
{
    lm_patch_reset(out);
    size_t i = 0, j = 0;
    lm_status st = LM_OK;
    while (st == LM_OK && (i < v->n_start || j < n)) {
        uint32_t a = i < v->n_start ? v->start[i].id : UINT32_MAX;
        uint32_t b = j < n ? tris[j].id : UINT32_MAX;
        if (a == b && !memcmp(&v->start[i], &tris[j], sizeof tris[j])) {
            i++, j++;
            continue;
        }
        if (a <= b)
            st = lm_patch_remove(out, a);
        if (st == LM_OK && b <= a)
            st = lm_patch_add(out, &tris[j]);
        i += a <= b;
        j += b <= a;
    }
    return st;
}

/* ---- ops ------------------------------------------------------------------------------------- */

static lm_status reserve_req(lm_lane_views *v, uint32_t n)
{
    if (n <= v->cap_req)
        return LM_OK;
    lm_patch *p = realloc(v->req, n * sizeof *p);
    int64_t *r = realloc(v->res, n * sizeof *r);
    if (p)
        v->req = p;
    if (r)
        v->res = r;
    if (!p || !r)
        return lm_fail(LM_E_NOMEM, "out of memory for a lane's request of %u patches", n);
    for (uint32_t i = v->cap_req; i < n; i++)
        lm_patch_init(&v->req[i]);
    v->cap_req = n;
    return LM_OK;
}

static lm_status lv_evaluate(lm_views *base, const lm_patch *patches, uint32_t n, int64_t *delta)
{
    lm_lane_views *v = as_lane(base);
    lm_status st = reserve_req(v, n);
    for (uint32_t i = 0; i < n && st == LM_OK; i++)
        st = compose(&v->acc, &patches[i], &v->req[i]);
    v->n_req = n;
    if (st == LM_OK)
        st = v->direct ? v->direct->ops->evaluate(v->direct, v->req, n, v->res)
                       : lm_lane_post(v->lane);
    for (uint32_t i = 0; i < n && st == LM_OK; i++)
        delta[i] = v->res[i] - v->d_acc;
    return st;
}

static lm_status lv_commit(lm_views *base, const lm_patch *patch)
{
    lm_lane_views *v = as_lane(base);
    lm_status st = compose(&v->acc, patch, &v->tmp);
    if (st != LM_OK)
        return st;
    lm_patch t = v->acc;
    v->acc = v->tmp;
    v->tmp = t;
    v->d_acc += v->pending;
    v->pending = 0;
    return LM_OK;
}

/* A revert: acc from the difference (d_acc was restored by the observer). */
static lm_status lv_set_mesh(lm_views *base, const lm_tri_data *tris, size_t n)
{
    lm_lane_views *v = as_lane(base);
    return diff_from_start(v, tris, n, &v->acc);
}

static lm_status lv_refuse(const char *what)
{
    return lm_fail(LM_E_INTERNAL, "a lane's moves asked its views for %s", what);
}

static lm_status lv_set_materials(lm_views *base, const lm_material *m, uint32_t n)
{
    (void)base, (void)m, (void)n;
    return lv_refuse("new materials");
}

static lm_status lv_energy(lm_views *base, int64_t *total, int64_t *per_view)
{
    (void)base, (void)total, (void)per_view;
    return lv_refuse("energies");
}

static lm_status lv_potentials(lm_views *base, const float (*p)[3], size_t n, int64_t *out)
{
    (void)base, (void)p, (void)n, (void)out;
    return lv_refuse("potentials");
}

static lm_status lv_read_image(lm_views *base, lm_image_kind k, uint32_t view, uint8_t *out)
{
    (void)base, (void)k, (void)view, (void)out;
    return lv_refuse("an image");
}

static void lv_info(lm_views *base, lm_views_info *out)
{
    lm_lane_views *v = as_lane(base);
    v->real->ops->info(v->real, out);
}

static void lv_destroy(lm_views *base)
{
    (void)base; /* owned by its lane: lm_lane_views_free */
}

static const lm_views_ops lane_ops = {
    .set_mesh = lv_set_mesh,
    .set_materials = lv_set_materials,
    .evaluate = lv_evaluate,
    .commit = lv_commit,
    .energy = lv_energy,
    .potentials = lv_potentials,
    .read_image = lv_read_image,
    .info = lv_info,
    .destroy = lv_destroy,
};

void lm_lane_views_init(lm_lane_views *v, lm_lane *lane, lm_views *real)
{
    memset(v, 0, sizeof *v);
    v->base.ops = &lane_ops;
    v->lane = lane;
    v->real = real;
    lm_patch_init(&v->acc);
    lm_patch_init(&v->tmp);
}

void lm_lane_views_free(lm_lane_views *v)
{
    lm_patch_free(&v->acc);
    lm_patch_free(&v->tmp);
    for (uint32_t i = 0; i < v->cap_req; i++)
        lm_patch_free(&v->req[i]);
    free(v->req);
    free(v->res);
}

void lm_lane_views_reset(lm_lane_views *v, const lm_tri_data *start, size_t n_start)
{
    v->start = start;
    v->n_start = n_start;
    lm_patch_reset(&v->acc);
    v->d_acc = v->pending = 0;
    v->n_req = 0;
}
