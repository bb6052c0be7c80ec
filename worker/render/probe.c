/* worker/render/probe.c — the renderer fingerprint: an integer-made probe scene rendered through
 * the local views backend (targets, then a textured current mesh), its images hashed (BLAKE2b). */
#include "worker/render/probe.h"

#include <sodium.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/patch.h"
#include "common/view.h"
#include "worker/render/views_local.h"

#define PROBE_TRIS 240
#define PROBE_VIEWS 4
#define PROBE_SIZE 48
#define PROBE_TEX 32

static uint32_t lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

/* A value in [-1, 1) with 10 fractional bits: exact in a float, the same everywhere. */
static float unit(uint32_t *s)
{
    return (float)((int)(lcg(s) % 2048u) - 1024) / 1024.0f;
}

/* A checker texture with a gradient, so that every mipmap level differs. */
static lm_status probe_texture(lm_image **out)
{
    lm_status st = lm_image_create(PROBE_TEX, PROBE_TEX, out);
    for (int y = 0; st == LM_OK && y < PROBE_TEX; y++)
        for (int x = 0; x < PROBE_TEX; x++) {
            uint8_t *p = (*out)->pixels + 4 * (y * PROBE_TEX + x);
            int on = ((x >> 2) ^ (y >> 2)) & 1;
            p[0] = (uint8_t)(on ? 230 : 20 + 6 * x);
            p[1] = (uint8_t)(on ? 40 + 6 * y : 200);
            p[2] = (uint8_t)((x * y) & 255);
            p[3] = 255;
        }
    return st;
}

static lm_status add_probe_tri(lm_mesh *m, uint32_t *s)
{
    uint32_t w[3];
    for (int k = 0; k < 3; k++) {
        float p[3] = {unit(s), unit(s), unit(s)};
        lm_wedge x = {.normal = {unit(s), unit(s), 1.0f},
                      .uv = {2.0f * unit(s), 2.0f * unit(s)},
                      .color = {0.5f + 0.5f * unit(s), 0.75f, 0.5f - 0.25f * unit(s), 1.0f}};
        lm_status st = lm_mesh_add_vertex(m, p, &x.vertex);
        if (st == LM_OK)
            st = lm_mesh_add_wedge(m, &x, &w[k]);
        if (st != LM_OK)
            return st;
    }
    return lm_mesh_add_tri(m, w, lcg(s) % 2u, NULL);
}

/* Two materials: a plain one and a textured one. */
static lm_status probe_mesh(lm_mesh **out)
{
    lm_image *tex = NULL;
    lm_status st = lm_mesh_create(out);
    float grey[4] = {0.8f, 0.8f, 0.8f, 1.0f}, white[4] = {1, 1, 1, 1};
    if (st == LM_OK)
        st = lm_mesh_add_material(*out, "plain", grey, NULL, NULL, NULL);
    if (st == LM_OK)
        st = probe_texture(&tex);
    if (st == LM_OK && (st = lm_mesh_add_material(*out, "textured", white, NULL, tex, NULL)))
        lm_image_destroy(tex);
    uint32_t seed = 12345u;
    for (int i = 0; i < PROBE_TRIS && st == LM_OK; i++)
        st = add_probe_tri(*out, &seed);
    (*out)->attrs = LM_ATTR_NORMAL | LM_ATTR_UV | LM_ATTR_COLOR;
    return st;
}

/* Hash every view's target and current luminance and colour image. */
static lm_status hash_images(lm_views *v, crypto_generichash_state *h)
{
    static uint8_t buf[PROBE_SIZE * PROBE_SIZE * 4];
    lm_image_kind kinds[] = {LM_IMAGE_TARGET_LUMA, LM_IMAGE_CURRENT_LUMA, LM_IMAGE_RGBA};
    for (uint32_t view = 0; view < PROBE_VIEWS; view++)
        for (int k = 0; k < 3; k++) {
            lm_status st = v->ops->read_image(v, kinds[k], view, buf);
            if (st != LM_OK)
                return st;
            crypto_generichash_update(h, buf,
                                      PROBE_SIZE * PROBE_SIZE * lm_image_kind_bpp(kinds[k]));
        }
    return LM_OK;
}

/* The current mesh: the probe's triangles moved by a 1/4096 shift (sub-pixel edges again). */
static lm_status set_shifted(lm_views *v, const lm_mesh *m)
{
    lm_tri_data *tris;
    size_t n;
    lm_status st = lm_mesh_export_tris(m, &tris, &n);
    for (size_t i = 0; st == LM_OK && i < n; i++)
        for (int k = 0; k < 3; k++)
            tris[i].c[k].pos[0] += 1.0f / 4096.0f;
    if (st == LM_OK)
        st = v->ops->set_mesh(v, tris, n);
    free(tris);
    return st;
}

lm_status wk_probe_renderer(const char *device, char *id, char *desc)
{
    lm_mesh *m = NULL;
    lm_views *v = NULL;
    lm_view_set *vs = malloc(sizeof *vs);
    float centre[3] = {0, 0, 0};
    lm_status st = vs ? probe_mesh(&m) : lm_fail(LM_E_NOMEM, "out of memory for the probe");
    if (st == LM_OK)
        st = lm_view_set_make(vs, PROBE_VIEWS, PROBE_SIZE, centre, 1.75f);
    if (st == LM_OK)
        st = wk_views_local_create(m, vs, 0, 0, device, &v);
    if (st == LM_OK)
        st = set_shifted(v, m);
    crypto_generichash_state h;
    crypto_generichash_init(&h, NULL, 0, LM_WIRE_RENDERER_ID_CHARS / 2);
    if (st == LM_OK)
        st = hash_images(v, &h);
    if (st == LM_OK) {
        uint8_t out[LM_WIRE_RENDERER_ID_CHARS / 2];
        crypto_generichash_final(&h, out, sizeof out);
        for (int i = 0; i < LM_WIRE_RENDERER_ID_CHARS / 2; i++)
            snprintf(id + 2 * i, 3, "%02x", out[i]);
        if (desc) {
            lm_views_info info;
            v->ops->info(v, &info);
            snprintf(desc, 128, "%s", info.renderer);
        }
    }
    lm_views_destroy(v);
    lm_mesh_destroy(m);
    free(vs);
    return st;
}
