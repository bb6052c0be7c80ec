/* proto/asset.c — content-addressed assets: hashing (libsodium's BLAKE2b), the asset set, and the
 * texture, material-table and mesh formats of asset.h with checked decoding. */
#include "proto/asset.h"

#include "common/bytes.h"
#include "common/grow.h"
#include "common/view.h"

#include <math.h>
#include <sodium.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char MAGIC_TEX[8] = "LMTEX1\0", MAGIC_MAT[8] = "LMMAT1\0", MAGIC_MESH[8] = "LMMSH1\0",
                  MAGIC_TGT[8] = "LMTGT1\0";
#define MAT_BYTES (64 + 16 + 1 + LM_ASSET_HASH_BYTES)

void lm_asset_hash_of(const void *data, size_t n, lm_asset_hash *out)
{
    crypto_generichash(out->b, sizeof out->b, data, n, NULL, 0);
}

const char *lm_asset_hash_short(const lm_asset_hash *h, char *buf)
{
    for (int i = 0; i < 8; i++)
        snprintf(buf + 2 * i, 3, "%02x", h->b[i]);
    return buf;
}

/* ---- the set --------------------------------------------------------------------------------- */

void lm_asset_set_init(lm_asset_set *s)
{
    memset(s, 0, sizeof *s);
}

void lm_asset_set_free(lm_asset_set *s)
{
    for (uint32_t i = 0; i < s->n; i++)
        free(s->items[i].data);
    free(s->items);
    memset(s, 0, sizeof *s);
}

const lm_asset *lm_asset_set_find(const lm_asset_set *s, const lm_asset_hash *h)
{
    for (uint32_t i = 0; i < s->n; i++)
        if (!memcmp(s->items[i].hash.b, h->b, sizeof h->b))
            return &s->items[i];
    return NULL;
}

void lm_asset_set_drop(lm_asset_set *s, const lm_asset_hash *h)
{
    const lm_asset *a = lm_asset_set_find(s, h);
    if (!a)
        return;
    uint32_t i = (uint32_t)(a - s->items);
    free(s->items[i].data);
    memmove(&s->items[i], &s->items[i + 1], (s->n - i - 1) * sizeof *s->items);
    s->n--;
}

lm_status lm_asset_set_copy(lm_asset_set *dst, const lm_asset_set *src)
{
    lm_asset *items = calloc(src->n ? src->n : 1, sizeof *items);
    for (uint32_t i = 0; items && i < src->n; i++) {
        items[i] = src->items[i];
        items[i].data = malloc(src->items[i].size ? src->items[i].size : 1);
        if (!items[i].data) {
            for (uint32_t k = 0; k < i; k++)
                free(items[k].data);
            free(items);
            items = NULL;
        } else if (src->items[i].size) {
            memcpy(items[i].data, src->items[i].data, src->items[i].size);
        }
    }
    if (!items)
        return lm_fail(LM_E_NOMEM, "out of memory copying %u assets", src->n);
    *dst = (lm_asset_set){items, src->n, src->n ? src->n : 1};
    return LM_OK;
}

lm_status lm_asset_set_put(lm_asset_set *s, uint8_t *data, size_t size, lm_asset_hash *out)
{
    lm_asset_hash h;
    lm_asset_hash_of(data, size, &h);
    if (out)
        *out = h;
    if (lm_asset_set_find(s, &h)) {
        free(data);
        return LM_OK;
    }
    if (s->n == s->cap && !LM_GROW32(&s->items, &s->cap, (size_t)s->n + 1, 8)) {
        free(data);
        return lm_fail(LM_E_NOMEM, "out of memory for %u assets",
                       (uint32_t)lm_grow_cap(s->cap, (size_t)s->n + 1, 8, UINT32_MAX));
    }
    s->items[s->n++] = (lm_asset){h, data, size};
    return LM_OK;
}

/* ---- writing --------------------------------------------------------------------------------- */

static void put_u32(lm_bytes *b, uint32_t v)
{
    uint8_t x[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    lm_bytes_put(b, x, 4);
}

static void put_f32(lm_bytes *b, float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    put_u32(b, v);
}

static void put_f32s(lm_bytes *b, const float *f, int n)
{
    for (int i = 0; i < n; i++)
        put_f32(b, f[i]);
}

/* The finished buffer into the set (its hash in *out). */
static lm_status finish(lm_bytes *b, lm_asset_set *s, lm_asset_hash *out)
{
    if (b->failed) {
        free(b->d);
        return lm_fail(LM_E_NOMEM, "out of memory packing an asset");
    }
    return lm_asset_set_put(s, b->d, b->n, out);
}

static lm_status pack_texture(const lm_image *img, lm_asset_set *s, lm_asset_hash *out)
{
    if (img->channels != 4)
        return lm_fail(LM_E_INVALID, "texture is not RGBA8");
    lm_bytes b = {0};
    lm_bytes_put(&b, MAGIC_TEX, 8);
    put_u32(&b, (uint32_t)img->width);
    put_u32(&b, (uint32_t)img->height);
    lm_bytes_put(&b, img->pixels, (size_t)img->width * (size_t)img->height * 4);
    return finish(&b, s, out);
}

/* The table's normal maps, after it: none at all where no material has one. */
static lm_status put_normal_maps(lm_bytes *b, const lm_material *mats, uint32_t n, lm_asset_set *s)
{
    uint32_t k = 0;
    for (uint32_t i = 0; i < n; i++)
        k += mats[i].normal_map != NULL;
    if (k)
        put_u32(b, k);
    for (uint32_t i = 0; i < n; i++) {
        lm_asset_hash h;
        if (!mats[i].normal_map)
            continue;
        lm_status st = pack_texture(mats[i].normal_map, s, &h);
        if (st != LM_OK)
            return st;
        put_u32(b, i);
        lm_bytes_put(b, h.b, sizeof h.b);
    }
    return LM_OK;
}

static lm_status put_materials(lm_bytes *b, const lm_material *mats, uint32_t n, lm_asset_set *s)
{
    put_u32(b, n);
    for (uint32_t i = 0; i < n; i++) {
        char name[64] = {0};
        snprintf(name, sizeof name, "%s", mats[i].name);
        lm_bytes_put(b, name, sizeof name);
        put_f32s(b, mats[i].diffuse, 4);
        lm_asset_hash h = {{0}};
        uint8_t has = mats[i].texture != NULL;
        if (has) {
            lm_status st = pack_texture(mats[i].texture, s, &h);
            if (st != LM_OK)
                return st;
        }
        lm_bytes_put(b, &has, 1);
        lm_bytes_put(b, h.b, sizeof h.b);
    }
    return put_normal_maps(b, mats, n, s);
}

lm_status lm_asset_pack_materials(const lm_material *mats, uint32_t n, lm_asset_set *s,
                                  lm_asset_hash *out)
{
    lm_bytes b = {0};
    lm_bytes_put(&b, MAGIC_MAT, 8);
    lm_status st = put_materials(&b, mats, n, s);
    if (st != LM_OK) {
        free(b.d);
        return st;
    }
    return finish(&b, s, out);
}

/* Alive elements renumbered densely: vertex and wedge maps (LM_NONE where dead). */
static void put_geometry(lm_bytes *b, const lm_mesh *m, uint32_t *vmap, uint32_t *wmap)
{
    uint32_t nv = 0, nw = 0, nt = 0;
    for (uint32_t v = 0; v < m->n_verts; v++)
        vmap[v] = m->vert_alive[v] ? nv++ : LM_NONE;
    for (uint32_t w = 0; w < m->n_wedges; w++)
        wmap[w] = m->wedge_alive[w] && vmap[m->wedges[w].vertex] != LM_NONE ? nw++ : LM_NONE;
    for (uint32_t t = 0; t < m->n_tris; t++)
        nt += m->tri_alive[t];
    put_u32(b, m->attrs);
    put_u32(b, nv);
    put_u32(b, nw);
    put_u32(b, nt);
    for (uint32_t v = 0; v < m->n_verts; v++)
        if (vmap[v] != LM_NONE)
            put_f32s(b, m->pos[v], 3);
    for (uint32_t w = 0; w < m->n_wedges; w++) {
        if (wmap[w] == LM_NONE)
            continue;
        const lm_wedge *x = &m->wedges[w];
        put_u32(b, vmap[x->vertex]);
        put_f32s(b, x->normal, 3);
        put_f32s(b, x->uv, 2);
        put_f32s(b, x->color, 4);
    }
    for (uint32_t t = 0; t < m->n_tris; t++) {
        if (!m->tri_alive[t])
            continue;
        for (int k = 0; k < 3; k++)
            put_u32(b, wmap[m->tris[t].w[k]]);
        put_u32(b, m->tris[t].material);
    }
}

lm_status lm_asset_pack_mesh(const lm_mesh *m, lm_asset_set *s, lm_asset_hash *out)
{
    uint32_t *vmap = malloc(((size_t)m->n_verts + 1) * sizeof *vmap);
    uint32_t *wmap = malloc(((size_t)m->n_wedges + 1) * sizeof *wmap);
    lm_bytes b = {0};
    lm_status st = vmap && wmap ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory packing a mesh");
    if (st == LM_OK) {
        lm_bytes_put(&b, MAGIC_MESH, 8);
        put_geometry(&b, m, vmap, wmap);
        st = put_materials(&b, m->materials, m->n_materials, s);
    }
    free(vmap);
    free(wmap);
    if (st != LM_OK) {
        free(b.d);
        return st;
    }
    return finish(&b, s, out);
}

/* ---- reading --------------------------------------------------------------------------------- */

typedef struct rbuf {
    const uint8_t *p;
    size_t n, at;
} rbuf;

static int has(const rbuf *r, size_t n)
{
    return r->n - r->at >= n;
}

static uint32_t get_u32(rbuf *r)
{
    const uint8_t *x = r->p + r->at;
    r->at += 4;
    return (uint32_t)x[0] | (uint32_t)x[1] << 8 | (uint32_t)x[2] << 16 | (uint32_t)x[3] << 24;
}

static float get_f32(rbuf *r)
{
    uint32_t v = get_u32(r);
    float f;
    memcpy(&f, &v, 4);
    return f;
}

/* n floats, all finite. */
static int get_f32s(rbuf *r, float *f, int n)
{
    int ok = 1;
    for (int i = 0; i < n; i++) {
        f[i] = get_f32(r);
        ok &= isfinite(f[i]) != 0;
    }
    return ok;
}

static lm_status check_magic(rbuf *r, const char magic[8], const char *what)
{
    if (!has(r, 8) || memcmp(r->p, magic, 8))
        return lm_fail(LM_E_FORMAT, "not a %s asset", what);
    r->at = 8;
    return LM_OK;
}

static lm_status unpack_texture(const lm_asset *a, lm_image **out)
{
    rbuf r = {a->data, a->size, 0};
    lm_status st = check_magic(&r, MAGIC_TEX, "texture");
    if (st != LM_OK)
        return st;
    if (!has(&r, 8))
        return lm_fail(LM_E_FORMAT, "texture asset truncated");
    uint32_t w = get_u32(&r), h = get_u32(&r);
    if (w < 1 || h < 1 || w > LM_IMAGE_MAX_SIDE || h > LM_IMAGE_MAX_SIDE)
        return lm_fail(LM_E_RANGE, "texture of %ux%u pixels", w, h);
    if (r.n - r.at != (size_t)w * h * 4)
        return lm_fail(LM_E_FORMAT, "texture asset of %ux%u pixels holds %zu bytes", w, h,
                       r.n - r.at);
    st = lm_image_create((int)w, (int)h, out);
    if (st == LM_OK)
        memcpy((*out)->pixels, r.p + r.at, (size_t)w * h * 4);
    return st;
}

/* One material record into m (its texture looked up in s). */
static lm_status get_material(rbuf *r, const lm_asset_set *s, lm_mesh *m)
{
    char name[65];
    memcpy(name, r->p + r->at, 64);
    name[64] = 0;
    r->at += 64;
    float diffuse[4];
    if (!get_f32s(r, diffuse, 4))
        return lm_fail(LM_E_RANGE, "a material's colour is not a finite number");
    uint8_t with = r->p[r->at++];
    lm_asset_hash h;
    memcpy(h.b, r->p + r->at, sizeof h.b);
    r->at += sizeof h.b;
    lm_image *tex = NULL;
    if (with) {
        const lm_asset *a = lm_asset_set_find(s, &h);
        char buf[17];
        if (!a)
            return lm_fail(LM_E_FORMAT, "texture %s is missing", lm_asset_hash_short(&h, buf));
        lm_status st = unpack_texture(a, &tex);
        if (st != LM_OK)
            return st;
    }
    lm_status st = lm_mesh_add_material(m, name, diffuse, NULL, tex, NULL);
    if (st != LM_OK)
        lm_image_destroy(tex);
    return st;
}

/* The count of the normal maps after a table of n materials, checked against the bytes left
 * (which they must fill exactly). */
static lm_status normal_count(rbuf *r, uint32_t n, uint32_t *k)
{
    *k = has(r, 4) ? get_u32(r) : 0;
    if (*k < 1 || *k > n || r->n - r->at != (size_t)*k * (4 + LM_ASSET_HASH_BYTES))
        return lm_fail(LM_E_FORMAT, "%zu bytes after the material table", r->n - r->at);
    return LM_OK;
}

static lm_status get_materials(rbuf *r, const lm_asset_set *s, lm_mesh *m)
{
    if (!has(r, 4))
        return lm_fail(LM_E_FORMAT, "material table truncated");
    uint32_t n = get_u32(r);
    if (n > (r->n - r->at) / MAT_BYTES)
        return lm_fail(LM_E_FORMAT, "material table of %u entries in %zu bytes", n, r->n - r->at);
    lm_status st = LM_OK;
    uint32_t base = m->n_materials;
    for (uint32_t i = 0; i < n && st == LM_OK; i++)
        st = get_material(r, s, m);
    uint32_t k;
    if (st == LM_OK && r->at != r->n && (st = normal_count(r, n, &k)) == LM_OK)
        for (uint32_t i = 0, last = 0; i < k && st == LM_OK; i++) {
            uint32_t mat = get_u32(r);
            lm_asset_hash h;
            memcpy(h.b, r->p + r->at, sizeof h.b);
            r->at += sizeof h.b;
            const lm_asset *a = lm_asset_set_find(s, &h);
            char buf[17];
            lm_image *img = NULL;
            if (mat >= n || (i && mat <= last))
                st = lm_fail(LM_E_FORMAT, "normal map of material %u of %u out of order", mat, n);
            else if (!a)
                st = lm_fail(LM_E_FORMAT, "normal map %s is missing", lm_asset_hash_short(&h, buf));
            else if ((st = unpack_texture(a, &img)) == LM_OK)
                st = lm_mesh_set_normal_map(m, base + mat, NULL, img);
            last = mat;
        }
    return st;
}

lm_status lm_asset_unpack_materials(const uint8_t *data, size_t size, const lm_asset_set *s,
                                    lm_mesh **out)
{
    *out = NULL;
    rbuf r = {data, size, 0};
    lm_status st = check_magic(&r, MAGIC_MAT, "material table");
    lm_mesh *m = NULL;
    if (st == LM_OK)
        st = lm_mesh_create(&m);
    if (st == LM_OK)
        st = get_materials(&r, s, m);
    if (st != LM_OK) {
        lm_mesh_destroy(m);
        return st;
    }
    *out = m;
    return LM_OK;
}

typedef struct counts {
    uint32_t attrs, nv, nw, nt;
} counts;

static lm_status get_counts(rbuf *r, counts *c)
{
    if (!has(r, 16))
        return lm_fail(LM_E_FORMAT, "mesh asset truncated");
    c->attrs = get_u32(r);
    c->nv = get_u32(r);
    c->nw = get_u32(r);
    c->nt = get_u32(r);
    if (c->nv > LM_MESH_MAX_VERTS || c->nw > LM_MESH_MAX_VERTS || c->nt > LM_MESH_MAX_TRIS ||
        c->attrs & ~7u)
        return lm_fail(LM_E_RANGE, "mesh asset of %u vertices, %u wedges, %u triangles", c->nv,
                       c->nw, c->nt);
    size_t need = (size_t)c->nv * 12 + (size_t)c->nw * 40 + (size_t)c->nt * 16;
    if (!has(r, need))
        return lm_fail(LM_E_FORMAT,
                       "mesh asset of %u vertices, %u wedges, %u triangles holds "
                       "%zu bytes, not at least %zu",
                       c->nv, c->nw, c->nt, r->n - r->at, need);
    return LM_OK;
}

static lm_status get_geometry(rbuf *r, const counts *c, lm_mesh *m)
{
    lm_status st = LM_OK;
    for (uint32_t v = 0; v < c->nv && st == LM_OK; v++) {
        float p[3];
        st = get_f32s(r, p, 3) ? lm_mesh_add_vertex(m, p, NULL)
                               : lm_fail(LM_E_RANGE, "vertex %u is not finite", v);
    }
    for (uint32_t w = 0; w < c->nw && st == LM_OK; w++) {
        lm_wedge x;
        x.vertex = get_u32(r);
        int ok = get_f32s(r, x.normal, 3) & get_f32s(r, x.uv, 2) & get_f32s(r, x.color, 4);
        st = ok ? lm_mesh_add_wedge(m, &x, NULL)
                : lm_fail(LM_E_RANGE, "wedge %u has a value that is not finite", w);
    }
    for (uint32_t t = 0; t < c->nt && st == LM_OK; t++) {
        uint32_t w[3] = {get_u32(r), get_u32(r), get_u32(r)}, mat = get_u32(r);
        st = lm_mesh_add_tri(m, w, mat, NULL);
    }
    return st;
}

/* Triangles' materials exist (the table comes after the geometry). */
static lm_status check_materials(const lm_mesh *m)
{
    for (uint32_t t = 0; t < m->n_tris; t++)
        if (m->tris[t].material >= m->n_materials)
            return lm_fail(LM_E_RANGE, "triangle %u uses material %u of %u", t, m->tris[t].material,
                           m->n_materials);
    return LM_OK;
}

lm_status lm_asset_unpack_mesh(const uint8_t *data, size_t size, const lm_asset_set *s,
                               lm_mesh **out)
{
    *out = NULL;
    rbuf r = {data, size, 0};
    counts c;
    lm_mesh *m = NULL;
    lm_status st = check_magic(&r, MAGIC_MESH, "mesh");
    if (st == LM_OK)
        st = get_counts(&r, &c);
    if (st == LM_OK)
        st = lm_mesh_create(&m);
    if (st == LM_OK)
        st = get_geometry(&r, &c, m);
    if (st == LM_OK)
        st = get_materials(&r, s, m);
    if (st == LM_OK)
        st = check_materials(m);
    if (st == LM_OK) {
        m->attrs = c.attrs;
        st = lm_mesh_validate(m);
    }
    if (st != LM_OK) {
        lm_mesh_destroy(m);
        return st;
    }
    *out = m;
    return LM_OK;
}

/* ---- references ------------------------------------------------------------------------------ */

/* The texture hashes of a material table at r. */
static lm_status table_refs(rbuf *r, lm_asset_hash **refs, uint32_t *n)
{
    if (!has(r, 4))
        return lm_fail(LM_E_FORMAT, "material table truncated");
    uint32_t k = get_u32(r);
    if (k > (r->n - r->at) / MAT_BYTES)
        return lm_fail(LM_E_FORMAT, "material table of %u entries in %zu bytes", k, r->n - r->at);
    *refs = malloc(((size_t)k + 1) * sizeof **refs);
    if (!*refs)
        return lm_fail(LM_E_NOMEM, "out of memory listing textures");
    *n = 0;
    for (uint32_t i = 0; i < k; i++) {
        const uint8_t *rec = r->p + r->at + (size_t)i * MAT_BYTES;
        if (rec[80])
            memcpy((*refs)[(*n)++].b, rec + 81, LM_ASSET_HASH_BYTES);
    }
    r->at += (size_t)k * MAT_BYTES;
    uint32_t kn;
    if (r->at == r->n)
        return LM_OK;
    lm_status st = normal_count(r, k, &kn);
    lm_asset_hash *more = st ? NULL : realloc(*refs, ((size_t)*n + kn + 1) * sizeof **refs);
    if (!st && !more)
        st = lm_fail(LM_E_NOMEM, "out of memory listing textures");
    if (st) {
        free(*refs);
        *refs = NULL;
        *n = 0;
        return st;
    }
    *refs = more;
    for (uint32_t i = 0; i < kn; i++)
        memcpy((*refs)[(*n)++].b, r->p + r->at + (size_t)i * (4 + LM_ASSET_HASH_BYTES) + 4,
               LM_ASSET_HASH_BYTES);
    return LM_OK;
}

lm_status lm_asset_refs(const uint8_t *data, size_t size, lm_asset_hash **refs, uint32_t *n)
{
    *refs = NULL;
    *n = 0;
    rbuf r = {data, size, 0};
    if (size >= 8 && (!memcmp(data, MAGIC_TEX, 8) || !memcmp(data, MAGIC_TGT, 8)))
        return LM_OK;
    if (size >= 8 && !memcmp(data, MAGIC_MAT, 8)) {
        r.at = 8;
        return table_refs(&r, refs, n);
    }
    counts c;
    lm_status st = check_magic(&r, MAGIC_MESH, "mesh");
    if (st == LM_OK)
        st = get_counts(&r, &c);
    if (st != LM_OK)
        return st;
    r.at += (size_t)c.nv * 12 + (size_t)c.nw * 40 + (size_t)c.nt * 16;
    return table_refs(&r, refs, n);
}

/* ---- targets --------------------------------------------------------------------------------- */

lm_status lm_asset_pack_targets(uint32_t width, uint32_t height, uint32_t n_views,
                                const uint8_t *luma, lm_asset_set *s, lm_asset_hash *out)
{
    if (width < 1 || height < 1 || width > LM_MAX_VIEW_SIZE || height > LM_MAX_VIEW_SIZE ||
        n_views < 1 || n_views > LM_MAX_VIEWS)
        return lm_fail(LM_E_RANGE, "targets of %u views of %ux%u", n_views, width, height);
    lm_bytes b = {0};
    lm_bytes_put(&b, MAGIC_TGT, 8);
    put_u32(&b, width);
    put_u32(&b, height);
    put_u32(&b, n_views);
    lm_bytes_put(&b, luma, (size_t)n_views * width * height);
    return finish(&b, s, out);
}

lm_status lm_asset_unpack_targets(const uint8_t *data, size_t size, lm_asset_targets *out)
{
    rbuf r = {data, size, 0};
    lm_status st = check_magic(&r, MAGIC_TGT, "targets");
    if (st != LM_OK)
        return st;
    if (!has(&r, 12))
        return lm_fail(LM_E_FORMAT, "targets asset truncated");
    uint32_t w = get_u32(&r), h = get_u32(&r), n = get_u32(&r);
    if (w < 1 || h < 1 || w > LM_MAX_VIEW_SIZE || h > LM_MAX_VIEW_SIZE)
        return lm_fail(LM_E_RANGE, "targets of %ux%u pixels", w, h);
    if (n < 1 || n > LM_MAX_VIEWS)
        return lm_fail(LM_E_RANGE, "targets of %u views", n);
    if (r.n - r.at != (size_t)n * w * h)
        return lm_fail(LM_E_FORMAT, "targets asset of %u views of %ux%u pixels holds %zu bytes", n,
                       w, h, r.n - r.at);
    *out = (lm_asset_targets){w, h, n, r.p + r.at};
    return LM_OK;
}
