/* coordinator/job/bake.c — the result's bakes from files to files (see bake.h). */
#include "coordinator/job/bake.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/bake_color.h"
#include "common/bake_normal.h"
#include "common/io/image_io.h"
#include "common/io/mesh_io.h"
#include "common/uv_atlas.h"
#include "coordinator/quality/json_text.h"

/* One name of --bake's list: its bit, 0 when unknown. */
static unsigned kind_bit(const char *name, size_t len)
{
    if (len == 6 && strncmp(name, "normal", len) == 0)
        return CO_BAKE_NORMAL;
    if (len == 5 && strncmp(name, "color", len) == 0)
        return CO_BAKE_COLOR;
    return 0;
}

lm_status co_bake_parse_kind(const char *val, unsigned *kinds)
{
    *kinds = 0;
    for (const char *p = val;; p++) {
        const char *end = strchr(p, ',');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        unsigned bit = kind_bit(p, len);
        if (!bit || (*kinds & bit))
            return lm_fail(LM_E_INVALID,
                           "--bake expects normal, color or both (normal,color), "
                           "got '%s'",
                           val);
        *kinds |= bit;
        if (!end)
            return LM_OK;
        p = end;
    }
}

/* OUT without its extension + suffix (e.g. "_normal.png"). */
static lm_status map_path(const char *output, const char *suffix, char *out, size_t cap)
{
    const char *dot = strrchr(output, '.'), *slash = strrchr(output, '/');
    size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - output) : strlen(output);
    int n = snprintf(out, cap, "%.*s%s", (int)stem, output, suffix);
    if (n < 0 || (size_t)n >= cap)
        return lm_fail(LM_E_INVALID, "--bake: output name '%s' is too long", output);
    return LM_OK;
}

/* The mesh to bake onto: *res itself when its coordinates pass, else its atlas (*res becomes
 * the atlas and *from the mesh it was made of). */
static lm_status bake_target(lm_mesh **res, lm_mesh **from, int size, co_bake_result *r)
{
    *from = NULL;
    lm_status st = lm_bake_uv_check(*res, size, &r->stats);
    if (st == LM_OK)
        return LM_OK;
    lm_mesh *a;
    st = lm_atlas_packed(*res, size, &a, &r->charts);
    if (st == LM_E_INVALID) { /* charts that do not pack: one triangle a cell */
        r->charts = 0;
        st = lm_atlas_per_triangle(*res, size, &a);
    }
    if (st != LM_OK)
        return st;
    *from = *res;
    *res = a;
    r->atlas = 1;
    return LM_OK;
}

static lm_status attach_normal(lm_mesh *res, const char *path, const lm_image *img)
{
    for (uint32_t i = 0; i < res->n_materials; i++) {
        lm_image *copy;
        lm_status st = lm_image_clone(img, &copy);
        if (st == LM_OK)
            st = lm_mesh_set_normal_map(res, i, path, copy);
        if (st != LM_OK)
            return st;
    }
    return LM_OK;
}

/* Every material takes the baked colour map as its texture, its factor's RGB 1; the vertex
 * colours, which the map holds, become white. */
static lm_status attach_color(lm_mesh *res, const char *path, const lm_image *img)
{
    for (uint32_t i = 0; i < res->n_materials; i++) {
        lm_material *mat = &res->materials[i];
        lm_image *copy;
        char *name = path ? malloc(strlen(path) + 1) : NULL;
        lm_status st = name || !path ? lm_image_clone(img, &copy) : LM_E_NOMEM;
        if (st != LM_OK) {
            free(name);
            return st == LM_E_NOMEM ? lm_fail(st, "out of memory attaching a colour map") : st;
        }
        if (name)
            memcpy(name, path, strlen(path) + 1);
        lm_image_destroy(mat->texture);
        free(mat->texture_path);
        mat->texture = copy, mat->texture_path = name;
        mat->diffuse[0] = mat->diffuse[1] = mat->diffuse[2] = 1.0f;
    }
    for (uint32_t w = 0; w < res->n_wedges; w++)
        for (int ch = 0; ch < 4; ch++)
            res->wedges[w].color[ch] = 1.0f;
    res->attrs &= ~(uint32_t)LM_ATTR_COLOR;
    return LM_OK;
}

/* The atlas's materials take the resampled textures (ownership moves; NULL entries skipped). */
static void attach_resampled(lm_mesh *res, lm_image **colour, co_bake_result *r)
{
    for (uint32_t i = 0; i < res->n_materials; i++) {
        if (!colour[i])
            continue;
        lm_image_destroy(res->materials[i].texture);
        res->materials[i].texture = colour[i];
        colour[i] = NULL;
        r->resampled++;
    }
}

/* The maps of one bake and the sinks that fill them (imgs[0] normal, imgs[1] colour, then the
 * transfer's resampled textures). */
typedef struct bake_maps {
    lm_image **imgs; /* [2 + res->n_materials] */
    lm_bake_sink sinks[3];
    int n_sinks;
    lm_bake_colour transfer;
} bake_maps;

static void maps_free(bake_maps *b, uint32_t n_materials)
{
    for (uint32_t i = 0; b->imgs && i < 2 + n_materials; i++)
        lm_image_destroy(b->imgs[i]);
    free(b->imgs);
    lm_bake_transfer_end(&b->transfer);
}

/* The images and sinks for `kinds` on res; with an atlas (from) and no colour bake, the transfer
 * of from's textures. */
static lm_status maps_make(bake_maps *b, const lm_mesh *res, const lm_mesh *from, unsigned kinds,
                           int size)
{
    memset(b, 0, sizeof *b);
    b->imgs = calloc(2 + (size_t)res->n_materials, sizeof *b->imgs);
    if (!b->imgs)
        return lm_fail(LM_E_NOMEM, "out of memory for a bake");
    lm_status st = LM_OK;
    if ((kinds & CO_BAKE_NORMAL) && (st = lm_image_create(size, size, &b->imgs[0])) == LM_OK)
        lm_bake_normal_sink(b->imgs[0], &b->sinks[b->n_sinks++]);
    if (st == LM_OK && (kinds & CO_BAKE_COLOR) &&
        (st = lm_image_create(size, size, &b->imgs[1])) == LM_OK)
        lm_bake_color_sink(b->imgs[1], &b->sinks[b->n_sinks++]);
    if (st == LM_OK && from && !(kinds & CO_BAKE_COLOR)) {
        b->transfer.from = from, b->transfer.out = b->imgs + 2;
        st = lm_bake_transfer_begin(res, size, &b->transfer, &b->sinks[b->n_sinks++]);
    }
    return st;
}

static lm_status write_maps(lm_mesh *res, bake_maps *b, co_bake_result *r)
{
    lm_status st = LM_OK;
    if (b->imgs[0] && (st = lm_image_write(r->map_path, b->imgs[0])) == LM_OK)
        st = attach_normal(res, r->map_path, b->imgs[0]);
    if (st == LM_OK && b->imgs[1] && (st = lm_image_write(r->color_path, b->imgs[1])) == LM_OK)
        st = attach_color(res, r->color_path, b->imgs[1]);
    if (st == LM_OK && b->transfer.from)
        attach_resampled(res, b->imgs + 2, r);
    return st;
}

lm_status co_bake_attach(const lm_mesh *orig, lm_mesh *res, const lm_mesh *from, unsigned kinds,
                         int size, lm_bake_stats *stats, unsigned *resampled)
{
    bake_maps b;
    uint32_t n_materials = res->n_materials;
    lm_status st = maps_make(&b, res, from, kinds, size);
    if (st == LM_OK)
        st = lm_bake_walk(orig, res, size, b.sinks, b.n_sinks, b.imgs, 2 + (int)n_materials, stats);
    if (st == LM_OK && b.imgs[0])
        st = attach_normal(res, NULL, b.imgs[0]);
    if (st == LM_OK && b.imgs[1])
        st = attach_color(res, NULL, b.imgs[1]);
    co_bake_result r = {0};
    if (st == LM_OK && b.transfer.from)
        attach_resampled(res, b.imgs + 2, &r);
    if (resampled)
        *resampled = r.resampled;
    maps_free(&b, n_materials);
    return st;
}

static lm_status bake_meshes(const lm_mesh *orig, lm_mesh **res, const char *output, unsigned kinds,
                             int size, co_bake_result *r)
{
    /* A result without normals holds the derived ones (lm_mesh_compute_normals, as the renderers
     * derive them): the bake's frame, written with the map since TANGENT needs them. */
    (*res)->attrs |= LM_ATTR_NORMAL;
    lm_mesh *from = NULL;
    lm_status st = bake_target(res, &from, size, r);
    if (st != LM_OK)
        return st;
    bake_maps b;
    uint32_t n_materials = (*res)->n_materials;
    st = maps_make(&b, *res, from, kinds, size);
    if (st == LM_OK)
        st = lm_bake_walk(orig, *res, size, b.sinks, b.n_sinks, b.imgs, 2 + (int)n_materials,
                          &r->stats);
    if (st == LM_OK)
        st = write_maps(*res, &b, r);
    maps_free(&b, n_materials);
    lm_mesh_destroy(from);
    if (st == LM_OK)
        st = lm_mesh_save(output, *res);
    return st;
}

lm_status co_bake_file(const char *original, const char *output, unsigned kinds, int size,
                       co_bake_result *r)
{
    memset(r, 0, sizeof *r);
    r->kinds = kinds;
    lm_status st = LM_OK;
    if (kinds & CO_BAKE_NORMAL)
        st = map_path(output, "_normal.png", r->map_path, sizeof r->map_path);
    if (st == LM_OK && (kinds & CO_BAKE_COLOR))
        st = map_path(output, "_color.png", r->color_path, sizeof r->color_path);
    lm_mesh *orig = NULL, *res = NULL;
    if (st == LM_OK)
        st = lm_mesh_load(original, NULL, &orig);
    if (st == LM_OK)
        st = lm_mesh_load(output, NULL, &res);
    if (st == LM_OK)
        st = bake_meshes(orig, &res, output, kinds, size, r);
    lm_mesh_destroy(orig);
    lm_mesh_destroy(res);
    return st;
}

/* What the bake went through, into buf. */
static const char *how(const co_bake_result *r, char *buf, size_t cap)
{
    if (!r->atlas)
        return "the result's own texture coordinates";
    if (r->charts)
        snprintf(buf, cap, "a packed atlas of %u charts", r->charts);
    else
        snprintf(buf, cap, "a per-triangle atlas");
    if (r->resampled)
        snprintf(buf + strlen(buf), cap - strlen(buf), ", the colour textures resampled into it");
    return buf;
}

void co_bake_print(const co_bake_result *r, int json)
{
    const lm_bake_stats *s = &r->stats;
    char buf[160];
    if (!json) {
        if (r->kinds & CO_BAKE_NORMAL)
            printf("baked normal map: %s (%s; %llu texels, %llu met the original along the "
                   "normal)\n",
                   r->map_path, how(r, buf, sizeof buf), (unsigned long long)s->texels,
                   (unsigned long long)s->hits);
        if (r->kinds & CO_BAKE_COLOR)
            printf("baked colour map: %s (%s; %llu texels, %llu met the original along the "
                   "normal)\n",
                   r->color_path, how(r, buf, sizeof buf), (unsigned long long)s->texels,
                   (unsigned long long)s->hits);
        return;
    }
    fputs("{\"type\":\"bake\"", stdout);
    if (r->kinds & CO_BAKE_NORMAL) {
        fputs(",\"map\":", stdout);
        co_json_string(stdout, r->map_path);
    }
    if (r->kinds & CO_BAKE_COLOR) {
        fputs(",\"color_map\":", stdout);
        co_json_string(stdout, r->color_path);
    }
    printf(",\"atlas\":%s,\"resampled_textures\":%u,\"texels\":%llu,\"hits\":%llu,"
           "\"charts\":%u}\n",
           r->atlas ? "true" : "false", r->resampled, (unsigned long long)s->texels,
           (unsigned long long)s->hits, r->charts);
}
