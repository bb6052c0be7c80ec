/* coordinator/simplify/pm_read.c — reading a progressive mesh with every count, id and reference
 * checked (the file may be hostile: fuzzed by tests/fuzz/fuzz_pm.c), a dry run of all its splits
 * (each must bring back exactly one vertex), and the extraction of the mesh of any vertex count. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "common/image.h"
#include "common/io/image_io.h"
#include "coordinator/simplify/pm_internal.h"

struct co_pm {
    uint32_t attrs, slots[3], n_splits, base_verts, full_verts;
    lm_mesh *tmpl; /* materials and parts, no geometry */
    co_pm_split base;
    co_pm_split *splits; /* coarse to fine */
};

typedef struct rd {
    const uint8_t *p;
    size_t n, pos;
    lm_status st;
} rd;

static int need(rd *r, size_t k, const char *what)
{
    if (r->st)
        return 0;
    if (k > r->n - r->pos) {
        r->st = lm_fail(LM_E_FORMAT, "progressive mesh: truncated in %s", what);
        return 0;
    }
    return 1;
}

static uint32_t get_u32(rd *r, const char *what)
{
    if (!need(r, 4, what))
        return 0;
    const uint8_t *p = r->p + r->pos;
    r->pos += 4;
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float get_f32(rd *r, const char *what)
{
    uint32_t u = get_u32(r, what);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static void get_floats(rd *r, float *x, int n, const char *what)
{
    for (int k = 0; k < n; k++)
        x[k] = get_f32(r, what);
}

/* Record "WHAT V is out of range (LIMIT)" unless an error is already there. */
static void bad(rd *r, const char *what, uint32_t v, uint32_t limit)
{
    if (!r->st)
        r->st =
            lm_fail(LM_E_FORMAT, "progressive mesh: %s %u is out of range (%u)", what, v, limit);
}

/* A string of at most cap-1 bytes (longer ones are refused). */
static void get_str(rd *r, char *buf, size_t cap, const char *what)
{
    uint32_t n = get_u32(r, what);
    buf[0] = 0;
    if (n >= cap)
        bad(r, what, n, (uint32_t)cap - 1);
    if (r->st || !need(r, n, what))
        return;
    memcpy(buf, r->p + r->pos, n);
    buf[n] = 0;
    r->pos += n;
}

/* ---- elements ------------------------------------------------------------------------------ */

static uint32_t get_id(rd *r, uint32_t slots, const char *what)
{
    uint32_t id = get_u32(r, what);
    if (id >= slots)
        bad(r, what, id, slots);
    return id;
}

static uint32_t get_alive(rd *r)
{
    uint32_t a = get_u32(r, "alive flag");
    if (a > 1)
        bad(r, "alive flag", a, 1);
    return a;
}

static void get_vert(rd *r, const co_pm *pm, co_pm_vert *v)
{
    v->id = get_id(r, pm->slots[0], "vertex id");
    v->alive = get_alive(r);
    get_floats(r, v->pos, 3, "vertex");
}

static void get_wedge(rd *r, const co_pm *pm, co_pm_wedge *w)
{
    w->id = get_id(r, pm->slots[1], "wedge id");
    w->alive = get_alive(r);
    w->w.vertex = get_id(r, pm->slots[0], "wedge vertex");
    get_floats(r, w->w.normal, 3, "wedge");
    get_floats(r, w->w.uv, 2, "wedge");
    get_floats(r, w->w.color, 4, "wedge");
}

static void get_tri(rd *r, const co_pm *pm, co_pm_tri *t)
{
    t->id = get_id(r, pm->slots[2], "triangle id");
    t->alive = get_alive(r);
    for (int k = 0; k < 3; k++)
        t->t.w[k] = get_id(r, pm->slots[1], "triangle wedge");
    uint32_t n_mat = pm->tmpl->n_materials, n_parts = pm->tmpl->n_parts;
    t->t.material = get_u32(r, "triangle material");
    t->t.part = get_u32(r, "triangle part");
    if (t->t.material >= (n_mat ? n_mat : 1))
        bad(r, "triangle material", t->t.material, n_mat);
    if (t->t.part >= (n_parts ? n_parts : 1))
        bad(r, "triangle part", t->t.part, n_parts);
}

/* Three counts, then that many vertices, wedges and triangles. */
static void get_split(rd *r, const co_pm *pm, co_pm_split *s)
{
    uint32_t n[3];
    static const size_t bytes[3] = {CO_PM_VERT_BYTES, CO_PM_WEDGE_BYTES, CO_PM_TRI_BYTES};
    for (int k = 0; k < 3; k++) {
        n[k] = get_u32(r, "element count");
        if (!r->st && n[k] > (r->n - r->pos) / bytes[k])
            bad(r, "element count", n[k], (uint32_t)((r->n - r->pos) / bytes[k]));
    }
    if (r->st)
        return;
    s->verts = calloc((size_t)n[0] + 1, sizeof *s->verts);
    s->wedges = calloc((size_t)n[1] + 1, sizeof *s->wedges);
    s->tris = calloc((size_t)n[2] + 1, sizeof *s->tris);
    if (!s->verts || !s->wedges || !s->tris) {
        r->st = lm_fail(LM_E_NOMEM, "out of memory reading a progressive mesh");
        return;
    }
    s->n_verts = n[0], s->n_wedges = n[1], s->n_tris = n[2];
    for (uint32_t i = 0; i < n[0] && !r->st; i++)
        get_vert(r, pm, &s->verts[i]);
    for (uint32_t i = 0; i < n[1] && !r->st; i++)
        get_wedge(r, pm, &s->wedges[i]);
    for (uint32_t i = 0; i < n[2] && !r->st; i++)
        get_tri(r, pm, &s->tris[i]);
}

/* ---- header, materials, parts -------------------------------------------------------------- */

/* A PNG's size from its header, refused above the limits before anything is decoded. */
static lm_status check_png(const uint8_t *p, uint32_t n)
{
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (n < 24 || memcmp(p, sig, 8) || memcmp(p + 12, "IHDR", 4))
        return lm_fail(LM_E_FORMAT, "progressive mesh: a texture is not a PNG image");
    uint32_t w = (uint32_t)p[16] << 24 | (uint32_t)p[17] << 16 | (uint32_t)p[18] << 8 | p[19];
    uint32_t h = (uint32_t)p[20] << 24 | (uint32_t)p[21] << 16 | (uint32_t)p[22] << 8 | p[23];
    if (!w || !h || w > CO_PM_MAX_TEXTURE_SIDE || h > CO_PM_MAX_TEXTURE_SIDE ||
        (uint64_t)w * h > CO_PM_MAX_TEXTURE_PIXELS)
        return lm_fail(LM_E_FORMAT, "progressive mesh: a texture of %ux%u pixels is too large", w,
                       h);
    return LM_OK;
}

static void get_texture(rd *r, int decode, lm_image **tex)
{
    uint32_t n = get_u32(r, "texture");
    *tex = NULL;
    if (!n || !need(r, n, "texture"))
        return;
    const uint8_t *png = r->p + r->pos;
    r->pos += n;
    if (!decode)
        return;
    lm_status st = check_png(png, n);
    if (st == LM_OK)
        st = lm_image_read_memory(png, n, "png", tex);
    r->st = st;
}

static void get_materials(rd *r, co_pm *pm, uint32_t n_mat, uint32_t n_parts, int decode)
{
    for (uint32_t i = 0; i < n_mat && !r->st; i++) {
        char name[sizeof pm->tmpl->materials[0].name], path[CO_PM_MAX_STRING + 1];
        float diffuse[4];
        lm_image *tex = NULL;
        get_str(r, name, sizeof name, "material name");
        get_floats(r, diffuse, 4, "material");
        get_str(r, path, sizeof path, "texture path");
        get_texture(r, decode, &tex);
        if (!r->st)
            r->st = lm_mesh_add_material(pm->tmpl, name, diffuse, path[0] ? path : NULL, tex, NULL);
        else
            lm_image_destroy(tex);
    }
    for (uint32_t i = 0; i < n_parts && !r->st; i++) {
        char name[LM_PART_NAME_MAX];
        uint32_t id;
        get_str(r, name, sizeof name, "part name");
        if (!r->st && lm_mesh_find_part(pm->tmpl, name) != LM_NONE)
            r->st = lm_fail(LM_E_FORMAT, "progressive mesh: part '%s' comes twice", name);
        if (!r->st)
            r->st = lm_mesh_add_part(pm->tmpl, name, &id);
    }
}

/* Magic, version and the counts; slots are bounded by the file's size (every slot is named by
 * some element record, which takes more than 4 bytes). */
static void get_header(rd *r, co_pm *pm, uint32_t *n_mat, uint32_t *n_parts)
{
    if (!need(r, 4, "header") || memcmp(r->p, CO_PM_MAGIC, 4)) {
        r->st = r->st ? r->st : lm_fail(LM_E_FORMAT, "not a lumesh progressive mesh (no LMPM)");
        return;
    }
    r->pos = 4;
    uint32_t version = get_u32(r, "header");
    if (!r->st && version != CO_PM_VERSION)
        r->st = lm_fail(LM_E_FORMAT, "progressive mesh version %u (this lumesh reads %u)", version,
                        CO_PM_VERSION);
    pm->attrs = get_u32(r, "header") & (LM_ATTR_NORMAL | LM_ATTR_UV | LM_ATTR_COLOR);
    for (int k = 0; k < 3; k++) {
        pm->slots[k] = get_u32(r, "header");
        if (pm->slots[k] > r->n / 4 || pm->slots[k] > LM_MESH_MAX_VERTS)
            bad(r, "slot count", pm->slots[k], (uint32_t)(r->n / 4));
    }
    *n_mat = get_u32(r, "header");
    *n_parts = get_u32(r, "header");
    pm->n_splits = get_u32(r, "header");
    pm->base_verts = get_u32(r, "header");
    pm->full_verts = get_u32(r, "header");
    if (*n_mat > CO_PM_MAX_MATERIALS)
        bad(r, "material count", *n_mat, CO_PM_MAX_MATERIALS);
    if (*n_parts > r->n / 4)
        bad(r, "part count", *n_parts, (uint32_t)(r->n / 4));
    if (pm->n_splits > r->n / 12)
        bad(r, "split count", pm->n_splits, (uint32_t)(r->n / 12));
    if (!r->st && (uint64_t)pm->base_verts + pm->n_splits != pm->full_verts)
        r->st = lm_fail(LM_E_FORMAT, "progressive mesh: %u + %u splits is not %u vertices",
                        pm->base_verts, pm->n_splits, pm->full_verts);
}

/* ---- the mesh state: every slot, alive or not ---------------------------------------------- */

typedef struct state {
    co_pm_vert *v;
    co_pm_wedge *w;
    co_pm_tri *t;
    uint32_t live_verts;
} state;

static void state_free(state *s)
{
    free(s->v);
    free(s->w);
    free(s->t);
}

static lm_status state_init(const co_pm *pm, state *s)
{
    memset(s, 0, sizeof *s);
    s->v = calloc((size_t)pm->slots[0] + 1, sizeof *s->v);
    s->w = calloc((size_t)pm->slots[1] + 1, sizeof *s->w);
    s->t = calloc((size_t)pm->slots[2] + 1, sizeof *s->t);
    if (!s->v || !s->w || !s->t) {
        state_free(s);
        return lm_fail(LM_E_NOMEM, "out of memory for a progressive mesh of %u vertices",
                       pm->slots[0]);
    }
    return LM_OK;
}

/* Set every element the split names (ids were checked against the slots when read). */
static void state_apply(state *s, const co_pm_split *x)
{
    for (uint32_t i = 0; i < x->n_verts; i++) {
        const co_pm_vert *e = &x->verts[i];
        s->live_verts += e->alive - s->v[e->id].alive;
        s->v[e->id] = *e;
    }
    for (uint32_t i = 0; i < x->n_wedges; i++)
        s->w[x->wedges[i].id] = x->wedges[i];
    for (uint32_t i = 0; i < x->n_tris; i++)
        s->t[x->tris[i].id] = x->tris[i];
}

/* Apply the base and `k` splits, each of which must bring back one vertex. */
static lm_status state_run(const co_pm *pm, uint32_t k, state *s)
{
    lm_status st = state_init(pm, s);
    if (st)
        return st;
    state_apply(s, &pm->base);
    if (s->live_verts != pm->base_verts)
        st = lm_fail(LM_E_FORMAT, "progressive mesh: the base has %u vertices, not %u",
                     s->live_verts, pm->base_verts);
    for (uint32_t i = 0; i < k && st == LM_OK; i++) {
        uint32_t before = s->live_verts;
        state_apply(s, &pm->splits[i]);
        if (s->live_verts != before + 1)
            st = lm_fail(LM_E_FORMAT, "progressive mesh: split %u goes from %u to %u vertices", i,
                         before, s->live_verts);
    }
    if (st)
        state_free(s);
    return st;
}

static lm_status copy_template(const lm_mesh *tmpl, lm_mesh *m)
{
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < tmpl->n_materials && st == LM_OK; i++) {
        const lm_material *mat = &tmpl->materials[i];
        lm_image *tex = NULL;
        if (mat->texture)
            st = lm_image_clone(mat->texture, &tex);
        if (st == LM_OK)
            st = lm_mesh_add_material(m, mat->name, mat->diffuse, mat->texture_path, tex, NULL);
        if (st != LM_OK)
            lm_image_destroy(tex);
    }
    return st == LM_OK ? lm_mesh_copy_parts(tmpl, m) : st;
}

/* Live elements in id order (as lm_mesh_compact leaves the simplifier's mesh). */
static lm_status state_to_mesh(const co_pm *pm, const state *s, uint32_t *map, lm_mesh *m)
{
    lm_status st = copy_template(pm->tmpl, m);
    m->attrs = pm->attrs;
    uint32_t *vmap = map, *wmap = map + pm->slots[0];
    for (uint32_t v = 0; v < pm->slots[0] && st == LM_OK; v++)
        if (s->v[v].alive)
            st = lm_mesh_add_vertex(m, s->v[v].pos, &vmap[v]);
    for (uint32_t w = 0; w < pm->slots[1] && st == LM_OK; w++) {
        if (!s->w[w].alive)
            continue;
        lm_wedge x = s->w[w].w;
        x.vertex = s->v[x.vertex].alive ? vmap[x.vertex] : LM_NONE;
        st = lm_mesh_add_wedge(m, &x, &wmap[w]);
    }
    for (uint32_t t = 0; t < pm->slots[2] && st == LM_OK; t++) {
        if (!s->t[t].alive)
            continue;
        uint32_t w[3], id;
        for (int k = 0; k < 3; k++)
            w[k] = s->w[s->t[t].t.w[k]].alive ? wmap[s->t[t].t.w[k]] : LM_NONE;
        st = lm_mesh_add_tri(m, w, s->t[t].t.material, &id);
        if (st == LM_OK)
            m->tris[id].part = s->t[t].t.part;
    }
    if (st == LM_OK)
        st = lm_mesh_validate(m);
    return st == LM_OK ? lm_mesh_build_adjacency(m) : st;
}

lm_status co_pm_extract(const co_pm *pm, uint32_t verts, lm_mesh **out)
{
    *out = NULL;
    if (verts < pm->base_verts || verts > pm->full_verts)
        return lm_fail(LM_E_RANGE, "the progressive mesh has %u to %u vertices, not %u",
                       pm->base_verts, pm->full_verts, verts);
    state s;
    lm_status st = state_run(pm, verts - pm->base_verts, &s);
    if (st)
        return st;
    uint32_t *map = malloc(((size_t)pm->slots[0] + pm->slots[1] + 1) * sizeof *map);
    lm_mesh *m = NULL;
    st = map ? lm_mesh_create(&m) : lm_fail(LM_E_NOMEM, "out of memory extracting a mesh");
    if (st == LM_OK)
        st = state_to_mesh(pm, &s, map, m);
    if (st == LM_E_RANGE || st == LM_E_ILLEGAL) {
        char why[512];
        snprintf(why, sizeof why, "%s", lm_last_error());
        st = lm_fail(LM_E_FORMAT, "progressive mesh: %s", why);
    }
    free(map);
    state_free(&s);
    if (st) {
        lm_mesh_destroy(m);
        return st;
    }
    *out = m;
    return LM_OK;
}

/* ---- reading ------------------------------------------------------------------------------- */

void co_pm_destroy(co_pm *pm)
{
    if (!pm)
        return;
    co_pm_split_free(&pm->base);
    for (uint32_t i = 0; pm->splits && i < pm->n_splits; i++)
        co_pm_split_free(&pm->splits[i]);
    free(pm->splits);
    lm_mesh_destroy(pm->tmpl);
    free(pm);
}

void co_pm_range(const co_pm *pm, uint32_t *base_verts, uint32_t *full_verts)
{
    *base_verts = pm->base_verts;
    *full_verts = pm->full_verts;
}

static void get_body(rd *r, co_pm *pm, int decode)
{
    uint32_t n_mat = 0, n_parts = 0;
    get_header(r, pm, &n_mat, &n_parts);
    if (!r->st)
        get_materials(r, pm, n_mat, n_parts, decode);
    if (!r->st)
        get_split(r, pm, &pm->base);
    if (!r->st && !(pm->splits = calloc((size_t)pm->n_splits + 1, sizeof *pm->splits)))
        r->st = lm_fail(LM_E_NOMEM, "out of memory reading a progressive mesh");
    for (uint32_t i = 0; i < pm->n_splits && !r->st; i++)
        get_split(r, pm, &pm->splits[i]);
    if (!r->st && (!need(r, 4, "end mark") || memcmp(r->p + r->pos, CO_PM_END, 4)))
        r->st = r->st ? r->st : lm_fail(LM_E_FORMAT, "progressive mesh: no end mark");
    if (!r->st && r->pos + 4 != r->n)
        r->st = lm_fail(LM_E_FORMAT, "progressive mesh: %zu bytes after the end mark",
                        r->n - r->pos - 4);
}

lm_status co_pm_read_memory(const uint8_t *data, size_t size, int decode_textures, co_pm **out)
{
    *out = NULL;
    co_pm *pm = calloc(1, sizeof *pm);
    if (!pm)
        return lm_fail(LM_E_NOMEM, "out of memory reading a progressive mesh");
    rd r = {.p = data, .n = size};
    r.st = lm_mesh_create(&pm->tmpl);
    if (!r.st)
        get_body(&r, pm, decode_textures);
    state s;
    if (!r.st && !(r.st = state_run(pm, pm->n_splits, &s)))
        state_free(&s);
    if (r.st) {
        co_pm_destroy(pm);
        return r.st;
    }
    *out = pm;
    return LM_OK;
}

lm_status co_pm_read(const char *path, co_pm **out)
{
    *out = NULL;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return lm_fail(LM_E_IO, "cannot open '%s'", path);
    uint8_t *buf = NULL;
    size_t n = 0, cap = 0;
    lm_status st = LM_OK;
    for (;;) {
        if (n == cap && (cap >= (size_t)1 << 32 || !LM_GROW(&buf, &cap, n + 1, 1 << 16))) {
            st = lm_fail(LM_E_NOMEM, "'%s' is too large to read", path);
            break;
        }
        size_t k = fread(buf + n, 1, cap - n, fp);
        n += k;
        if (k == 0)
            break;
    }
    if (st == LM_OK && ferror(fp))
        st = lm_fail(LM_E_IO, "cannot read '%s'", path);
    fclose(fp);
    if (st == LM_OK) {
        st = co_pm_read_memory(buf, n, 1, out);
        if (st != LM_OK && st != LM_E_NOMEM) {
            char why[512];
            snprintf(why, sizeof why, "%s", lm_last_error());
            st = lm_fail(st, "%s: %s", path, why);
        }
    }
    free(buf);
    return st;
}
