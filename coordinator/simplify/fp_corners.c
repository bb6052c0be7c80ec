/* coordinator/simplify/fp_corners.c — a change's footprint from its distinct corners, each
 * projected once per view (the points hashed bit for bit). */
#include "coordinator/simplify/fp_corners.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

#define CO_FPC_FIRST_SLOTS 256

void co_fp_corners_init(co_fp_corners *c)
{
    memset(c, 0, sizeof *c);
}

void co_fp_corners_free(co_fp_corners *c)
{
    free(c->pos);
    free(c->win);
    free(c->ok);
    free(c->tri);
    free(c->slot);
    memset(c, 0, sizeof *c);
}

void co_fp_corners_reset(co_fp_corners *c)
{
    c->n_pos = c->n_tri = 0;
    if (c->slot)
        memset(c->slot, 0, (size_t)c->cap_slot * sizeof *c->slot);
}

static uint32_t hash_point(const float p[3])
{
    uint32_t b[3];
    memcpy(b, p, sizeof b);
    uint64_t h = (uint64_t)b[0] * 0x9E3779B97F4A7C15ull;
    h = (h ^ b[1]) * 0xC2B2AE3D27D4EB4Full;
    h = (h ^ b[2]) * 0x165667B19E3779F9ull;
    return (uint32_t)(h >> 32);
}

static uint32_t *find_slot(const co_fp_corners *c, const float p[3])
{
    uint32_t mask = c->cap_slot - 1;
    for (uint32_t i = hash_point(p) & mask;; i = (i + 1) & mask)
        if (!c->slot[i] || !memcmp(c->pos[c->slot[i] - 1], p, sizeof c->pos[0]))
            return &c->slot[i];
}

/* Twice the slots (or the first ones), every point hashed again. */
static lm_status rehash(co_fp_corners *c)
{
    uint32_t cap = c->cap_slot ? 2 * c->cap_slot : CO_FPC_FIRST_SLOTS;
    uint32_t *slot = calloc(cap, sizeof *slot);
    if (!slot)
        return lm_fail(LM_E_NOMEM, "out of memory for footprint corners");
    free(c->slot);
    c->slot = slot;
    c->cap_slot = cap;
    for (uint32_t i = 0; i < c->n_pos; i++)
        *find_slot(c, c->pos[i]) = i + 1;
    return LM_OK;
}

/* The index of point p, added when new. */
static lm_status point_index(co_fp_corners *c, const float p[3], uint32_t *out)
{
    lm_status st = 2 * (c->n_pos + 1) > c->cap_slot ? rehash(c) : LM_OK;
    if (st)
        return st;
    uint32_t *s = find_slot(c, p);
    if (!*s) {
        uint32_t cap = c->cap_pos, cap_ok = c->cap_pos;
        if (!LM_GROW32(&c->pos, &c->cap_pos, c->n_pos + 1, 64) ||
            !LM_GROW32(&c->win, &cap, c->cap_pos, 64) ||
            !LM_GROW32(&c->ok, &cap_ok, c->cap_pos, 64))
            return lm_fail(LM_E_NOMEM, "out of memory for footprint corners");
        memcpy(c->pos[c->n_pos], p, sizeof c->pos[0]);
        *s = ++c->n_pos;
    }
    *out = *s - 1;
    return LM_OK;
}

lm_status co_fp_corners_add_tri(co_fp_corners *c, const lm_tri_data *t)
{
    if (!LM_GROW32(&c->tri, &c->cap_tri, c->n_tri + 1, 64))
        return lm_fail(LM_E_NOMEM, "out of memory for footprint corners");
    lm_status st = LM_OK;
    for (int k = 0; k < 3 && st == LM_OK; k++)
        st = point_index(c, t->c[k].pos, &c->tri[c->n_tri][k]);
    c->n_tri += st == LM_OK;
    return st;
}

/* View h where some point does not project: triangle by triangle, as co_fp_add_tri. */
static void apply_by_triangle(const co_fp_corners *c, co_rect *r)
{
    for (uint32_t t = 0; t < c->n_tri; t++) {
        const uint32_t *v = c->tri[t];
        if (!c->ok[v[0]] || !c->ok[v[1]] || !c->ok[v[2]]) {
            co_fp_grow_plane(r);
            continue;
        }
        float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int k = 0; k < 3; k++)
            for (int d = 0; d < 2; d++) {
                float w = c->win[v[k]][d];
                lo[d] = w < lo[d] ? w : lo[d];
                hi[d] = w > hi[d] ? w : hi[d];
            }
        co_fp_grow_box(r, lo, hi);
    }
}

void co_fp_corners_apply(co_fp_corners *c, co_rect *fp, const lm_view_set *vs)
{
    if (!c->n_tri)
        return;
    for (uint32_t h = 0; h < vs->count; h++) {
        float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        int all = 1;
        for (uint32_t i = 0; i < c->n_pos; i++) {
            float *w = c->win[i];
            c->ok[i] = (uint8_t)co_fp_project(&vs->views[h], c->pos[i], w);
            all &= c->ok[i];
            for (int d = 0; d < 2 && c->ok[i]; d++) {
                lo[d] = w[d] < lo[d] ? w[d] : lo[d];
                hi[d] = w[d] > hi[d] ? w[d] : hi[d];
            }
        }
        if (all)
            co_fp_grow_box(&fp[h], lo, hi);
        else
            apply_by_triangle(c, &fp[h]);
    }
}
