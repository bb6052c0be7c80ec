/* proto/wire_records.c — triangle records, patches and cameras to and from wire messages, with
 * the checks of every decoded count, number and index; the encoding arena. */
#include "proto/wire_records.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

/* ---- arena ----------------------------------------------------------------------------------- */

void lm_wire_arena_init(lm_wire_arena *a)
{
    memset(a, 0, sizeof *a);
}

void lm_wire_arena_reset(lm_wire_arena *a)
{
    for (size_t i = 0; i < a->n_old; i++)
        free(a->old[i]);
    a->n_old = 0;
    a->used = 0;
}

void lm_wire_arena_free(lm_wire_arena *a)
{
    lm_wire_arena_reset(a);
    free(a->old);
    free(a->block);
    memset(a, 0, sizeof *a);
}

/* A bigger block; the current one is kept until the next reset (pointers into it live on). */
static int arena_grow(lm_wire_arena *a, size_t need)
{
    /* the next block twice the last at least, and as big as need */
    size_t cap = lm_grow_cap(a->cap, need > a->cap ? need : a->cap + 1, 65536, SIZE_MAX);
    uint8_t *b = cap ? malloc(cap) : NULL;
    if (!b)
        return 0;
    if (a->block && a->used) {
        if (a->n_old == a->cap_old && !LM_GROW(&a->old, &a->cap_old, a->n_old + 1, 8)) {
            free(b);
            return 0;
        }
        a->old[a->n_old++] = a->block;
    } else {
        free(a->block);
    }
    a->block = b;
    a->cap = cap;
    a->used = 0;
    return 1;
}

void *lm_wire_arena_alloc(lm_wire_arena *a, size_t n)
{
    n = (n + 15) & ~(size_t)15;
    if (a->used + n > a->cap && !arena_grow(a, n))
        return NULL;
    void *p = a->block + a->used;
    a->used += n;
    memset(p, 0, n);
    return p;
}

/* ---- encoding -------------------------------------------------------------------------------- */

void lm_wire_tri_point(const lm_tri_data *t, Lumesh__Tri *out)
{
    lumesh__tri__init(out);
    out->id = t->id;
    out->material = t->material;
    out->n_corners = LM_WIRE_FLOATS_PER_TRI;
    out->corners = (float *)(void *)t->c; /* 3 lm_corner = 36 consecutive floats */
}

lm_status lm_wire_tris_encode(const lm_tri_data *tris, size_t n, lm_wire_arena *a,
                              Lumesh__Tri ***out)
{
    Lumesh__Tri **ptrs = lm_wire_arena_alloc(a, n * sizeof *ptrs);
    Lumesh__Tri *w = lm_wire_arena_alloc(a, n * sizeof *w);
    if (n && (!ptrs || !w))
        return lm_fail(LM_E_NOMEM, "out of memory encoding %zu triangles", n);
    for (size_t i = 0; i < n; i++) {
        lm_wire_tri_point(&tris[i], &w[i]);
        ptrs[i] = &w[i];
    }
    *out = ptrs;
    return LM_OK;
}

/* The fields of a corner, in its order of floats (LM_WIRE_FIELD_*). */
static const struct {
    uint32_t at, n;
} fields[4] = {{0, 3}, {3, 3}, {6, 2}, {8, 4}};

static const float *corner_floats(const lm_tri_data *t, int v)
{
    return (const float *)(const void *)&t->c[v];
}

/* Floats a record carries when the fields of `same` are left out. */
static size_t carried(uint32_t same)
{
    size_t n = 0;
    for (int v = 0; v < 3; v++)
        for (int f = 0; f < 4; f++)
            n += same & LM_WIRE_SAME_BIT(v, f) ? 0 : fields[f].n;
    return n;
}

static uint32_t same_fields(const lm_tri_data *t, const lm_tri_data *cur)
{
    uint32_t same = 0;
    for (int v = 0; v < 3; v++)
        for (int f = 0; f < 4; f++)
            if (!memcmp(corner_floats(t, v) + fields[f].at, corner_floats(cur, v) + fields[f].at,
                        fields[f].n * sizeof(float)))
                same |= LM_WIRE_SAME_BIT(v, f);
    return same;
}

/* t's record against cur: the fields that differ, corner by corner. */
static lm_status tri_against(const lm_tri_data *t, const lm_tri_data *cur, lm_wire_arena *a,
                             Lumesh__Tri *out)
{
    lm_wire_tri_point(t, out);
    uint32_t same = cur ? same_fields(t, cur) : 0;
    if (!same)
        return LM_OK;
    size_t n = carried(same);
    float *x = n ? lm_wire_arena_alloc(a, n * sizeof *x) : NULL;
    if (n && !x)
        return lm_fail(LM_E_NOMEM, "out of memory encoding a triangle");
    size_t k = 0;
    for (int v = 0; v < 3; v++)
        for (int f = 0; f < 4; f++)
            if (!(same & LM_WIRE_SAME_BIT(v, f))) {
                memcpy(x + k, corner_floats(t, v) + fields[f].at, fields[f].n * sizeof *x);
                k += fields[f].n;
            }
    out->same = same;
    out->n_corners = n;
    out->corners = x;
    return LM_OK;
}

lm_status lm_wire_patch_encode_against(const lm_patch *p, lm_wire_current_fn current,
                                       const void *ctx, lm_wire_arena *a, Lumesh__Patch *out)
{
    lumesh__patch__init(out);
    out->n_removed = p->n_removed;
    out->removed = p->removed;
    out->n_added = p->n_added;
    if (!current)
        return lm_wire_tris_encode(p->added, p->n_added, a, &out->added);
    Lumesh__Tri **ptrs = lm_wire_arena_alloc(a, p->n_added * sizeof *ptrs);
    Lumesh__Tri *w = lm_wire_arena_alloc(a, p->n_added * sizeof *w);
    if (p->n_added && (!ptrs || !w))
        return lm_fail(LM_E_NOMEM, "out of memory encoding %u triangles", p->n_added);
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < p->n_added && st == LM_OK; i++) {
        st = tri_against(&p->added[i], current(ctx, p->added[i].id), a, &w[i]);
        ptrs[i] = &w[i];
    }
    out->added = ptrs;
    return st;
}

lm_status lm_wire_patch_encode(const lm_patch *p, lm_wire_arena *a, Lumesh__Patch *out)
{
    return lm_wire_patch_encode_against(p, NULL, NULL, a, out);
}

/* A float array of the arena holding a copy of src (the View message points at it). */
static float *floats(lm_wire_arena *a, const float *src, size_t n)
{
    float *f = lm_wire_arena_alloc(a, n * sizeof *f);
    if (f)
        memcpy(f, src, n * sizeof *f);
    return f;
}

lm_status lm_wire_view_encode(const lm_view *v, lm_wire_arena *a, Lumesh__View *out)
{
    lumesh__view__init(out);
    out->n_eye = out->n_dir = 3;
    out->n_view = out->n_proj = out->n_view_proj = 16;
    out->eye = floats(a, v->eye, 3);
    out->dir = floats(a, v->dir, 3);
    out->view = floats(a, v->view, 16);
    out->proj = floats(a, v->proj, 16);
    out->view_proj = floats(a, v->view_proj, 16);
    if (!out->eye || !out->dir || !out->view || !out->proj || !out->view_proj)
        return lm_fail(LM_E_NOMEM, "out of memory encoding a camera");
    return LM_OK;
}

/* ---- decoding -------------------------------------------------------------------------------- */

static int all_finite(const float *f, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(f[i]))
            return 0;
    return 1;
}

lm_status lm_wire_tri_decode(const Lumesh__Tri *t, uint32_t n_materials, lm_tri_data *out)
{
    if (t->same)
        return lm_fail(LM_E_FORMAT,
                       "triangle %u is given against a current record where none "
                       "may be",
                       t->id);
    if (t->n_corners != LM_WIRE_FLOATS_PER_TRI)
        return lm_fail(LM_E_FORMAT, "triangle %u has %zu corner values, not %u", t->id,
                       t->n_corners, LM_WIRE_FLOATS_PER_TRI);
    if (t->id >= LM_MESH_MAX_TRIS)
        return lm_fail(LM_E_RANGE, "triangle id %u exceeds the limit", t->id);
    if (t->material >= n_materials)
        return lm_fail(LM_E_RANGE, "triangle %u uses material %u of %u", t->id, t->material,
                       n_materials);
    if (!all_finite(t->corners, LM_WIRE_FLOATS_PER_TRI))
        return lm_fail(LM_E_RANGE, "triangle %u has a corner value that is not a finite number",
                       t->id);
    out->id = t->id;
    out->material = t->material;
    memcpy(out->c, t->corners, sizeof out->c);
    return LM_OK;
}

/* A record against the current one of its id: the fields it leaves out from there. */
static lm_status tri_decode_against(const Lumesh__Tri *t, uint32_t n_materials,
                                    lm_wire_current_fn current, const void *ctx, lm_tri_data *out)
{
    if (!t->same || !current)
        return lm_wire_tri_decode(t, n_materials, out);
    const lm_tri_data *cur = current(ctx, t->id);
    if (t->same & ~LM_WIRE_SAME_ALL)
        return lm_fail(LM_E_FORMAT, "triangle %u leaves out fields %#x that no record has", t->id,
                       t->same);
    if (!cur)
        return lm_fail(LM_E_FORMAT,
                       "triangle %u is given against a current record of its id, "
                       "which is not in the mesh",
                       t->id);
    if (t->n_corners != carried(t->same))
        return lm_fail(LM_E_FORMAT, "triangle %u has %zu corner values, not %zu", t->id,
                       t->n_corners, carried(t->same));
    if (t->material >= n_materials)
        return lm_fail(LM_E_RANGE, "triangle %u uses material %u of %u", t->id, t->material,
                       n_materials);
    if (!all_finite(t->corners, t->n_corners))
        return lm_fail(LM_E_RANGE, "triangle %u has a corner value that is not a finite number",
                       t->id);
    *out = *cur;
    out->material = t->material;
    size_t k = 0;
    for (int v = 0; v < 3; v++)
        for (int f = 0; f < 4; f++)
            if (!(t->same & LM_WIRE_SAME_BIT(v, f))) {
                memcpy((float *)(void *)&out->c[v] + fields[f].at, t->corners + k,
                       fields[f].n * sizeof(float));
                k += fields[f].n;
            }
    return LM_OK;
}

lm_status lm_wire_patch_decode(const Lumesh__Patch *w, uint32_t n_materials, lm_patch *p)
{
    return lm_wire_patch_decode_against(w, n_materials, NULL, NULL, p);
}

lm_status lm_wire_patch_decode_against(const Lumesh__Patch *w, uint32_t n_materials,
                                       lm_wire_current_fn current, const void *ctx, lm_patch *p)
{
    lm_patch_reset(p);
    if (w->n_removed > LM_WIRE_MAX_PATCH_TRIS || w->n_added > LM_WIRE_MAX_PATCH_TRIS)
        return lm_fail(LM_E_RANGE, "a patch of %zu removed and %zu added triangles exceeds %u",
                       w->n_removed, w->n_added, LM_WIRE_MAX_PATCH_TRIS);
    lm_status st = LM_OK;
    for (size_t i = 0; i < w->n_removed && st == LM_OK; i++) {
        if (w->removed[i] >= LM_MESH_MAX_TRIS)
            return lm_fail(LM_E_RANGE, "removed triangle id %u exceeds the limit", w->removed[i]);
        st = lm_patch_remove(p, w->removed[i]);
    }
    for (size_t i = 0; i < w->n_added && st == LM_OK; i++) {
        lm_tri_data t;
        st = tri_decode_against(w->added[i], n_materials, current, ctx, &t);
        if (st == LM_OK)
            st = lm_patch_add(p, &t);
    }
    return st;
}

static lm_status check_len(const char *what, size_t n, size_t want)
{
    if (n != want)
        return lm_fail(LM_E_FORMAT, "a camera's %s has %zu values, not %zu", what, n, want);
    return LM_OK;
}

lm_status lm_wire_view_decode(const Lumesh__View *w, int width, int height, lm_view *out)
{
    lm_status st = check_len("eye", w->n_eye, 3);
    if (st == LM_OK)
        st = check_len("direction", w->n_dir, 3);
    if (st == LM_OK)
        st = check_len("view matrix", w->n_view, 16);
    if (st == LM_OK)
        st = check_len("projection", w->n_proj, 16);
    if (st == LM_OK)
        st = check_len("view-projection", w->n_view_proj, 16);
    if (st != LM_OK)
        return st;
    if (!all_finite(w->eye, 3) || !all_finite(w->dir, 3) || !all_finite(w->view, 16) ||
        !all_finite(w->proj, 16) || !all_finite(w->view_proj, 16))
        return lm_fail(LM_E_RANGE, "a camera has a value that is not a finite number");
    if (width < 16 || width > LM_MAX_VIEW_SIZE || height < 16 || height > LM_MAX_VIEW_SIZE)
        return lm_fail(LM_E_RANGE, "views of %dx%d are outside 16..%d", width, height,
                       LM_MAX_VIEW_SIZE);
    memcpy(out->eye, w->eye, sizeof out->eye);
    memcpy(out->dir, w->dir, sizeof out->dir);
    memcpy(out->view, w->view, sizeof out->view);
    memcpy(out->proj, w->proj, sizeof out->proj);
    memcpy(out->view_proj, w->view_proj, sizeof out->view_proj);
    out->width = width;
    out->height = height;
    return LM_OK;
}
