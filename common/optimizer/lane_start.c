/* common/optimizer/lane_start.c — the moves config and a group's start mesh to bytes and back
 * (lane_start.h). */
#include "common/optimizer/lane_start.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "common/mesh_topology.h"
#include "common/optimizer/binio.h"
#include "common/optimizer/optimizer.h"

#define CONFIG_MAGIC 0x46434e4cu /* "LNCF" */
#define MAX_SLOTS 4096u          /* materials or parts of a start mesh (also at most its bytes) */
#define CONFIG_BYTES (4u + 4u * 4u + 6u * 8u + 4u * 4u)

/* x written by put into memory: *buf (malloc'd) and *len, or nothing on a failure. */
static lm_status write_bytes(lm_status (*put)(const void *x, lm_bin *b), const void *x,
                             uint8_t **buf, size_t *len, const char *what)
{
    lm_bin b;
    lm_bin_init_writer(&b, what);
    put(x, &b);
    return lm_bin_take(&b, buf, len);
}

static lm_status put_config(const void *x, lm_bin *bp)
{
    const lm_moves_config *c = x;
    lm_bin b = *bp;
    lm_put_u32(&b, CONFIG_MAGIC);
    lm_put_u32(&b, c->attrs);
    lm_put_u32(&b, c->evals_per_dim);
    lm_put_u32(&b, c->max_set_verts);
    lm_put_u32(&b, c->max_dim);
    const double d[6] = {c->pos_step,   c->normal_step, c->uv_step,
                         c->color_step, c->size_tol,    c->f_rtol};
    for (int i = 0; i < 6; i++)
        lm_put_f64(&b, d[i]);
    for (int i = 0; i < 3; i++)
        lm_put_f32(&b, c->centre[i]);
    lm_put_f32(&b, c->bound_radius);
    *bp = b;
    return b.status;
}

lm_status lm_lane_config_encode(const lm_moves_config *cfg, uint8_t **buf, size_t *len)
{
    return write_bytes(put_config, cfg, buf, len, "a moves config");
}

lm_status lm_lane_config_decode(const uint8_t *buf, size_t len, lm_moves_config *cfg)
{
    if (len != CONFIG_BYTES)
        return lm_fail(LM_E_FORMAT, "a moves config of %zu bytes (%u expected)", len, CONFIG_BYTES);
    lm_bin b;
    lm_bin_init_reader(&b, buf, len, "a moves config");
    lm_moves_config c;
    uint32_t magic = lm_get_u32(&b);
    c.attrs = lm_get_u32(&b);
    c.evals_per_dim = lm_get_u32(&b);
    c.max_set_verts = lm_get_u32(&b);
    c.max_dim = lm_get_u32(&b);
    double *d[6] = {&c.pos_step, &c.normal_step, &c.uv_step, &c.color_step, &c.size_tol, &c.f_rtol};
    int finite = 1;
    for (int i = 0; i < 6; i++) {
        *d[i] = lm_get_f64(&b);
        finite = finite && isfinite(*d[i]) && *d[i] >= 0;
    }
    for (int i = 0; i < 3; i++) {
        c.centre[i] = lm_get_f32(&b);
        finite = finite && isfinite(c.centre[i]);
    }
    c.bound_radius = lm_get_f32(&b);
    finite = finite && isfinite(c.bound_radius) && c.bound_radius >= 0;
    if (b.status != LM_OK)
        return b.status;
    if (magic != CONFIG_MAGIC)
        return lm_fail(LM_E_FORMAT, "not a moves config (magic %08x)", magic);
    if (!finite || c.attrs >> 16)
        return lm_fail(LM_E_FORMAT, "a moves config with constants out of range");
    *cfg = c;
    return LM_OK;
}

static lm_status put_mesh(const void *x, lm_bin *b)
{
    return lm_optimizer_save_mesh_bin(x, b);
}

lm_status lm_lane_mesh_encode(const lm_mesh *m, uint8_t **buf, size_t *len)
{
    return write_bytes(put_mesh, m, buf, len, "a start mesh");
}

/* Little-endian u32 at byte i of buf. */
static uint32_t u32_at(const uint8_t *buf, size_t i)
{
    return (uint32_t)buf[i] | (uint32_t)buf[i + 1] << 8 | (uint32_t)buf[i + 2] << 16 |
           (uint32_t)buf[i + 3] << 24;
}

/* m gets the material and part slots the record names (placeholders: a lane's moves read only
 * their ids): at most MAX_SLOTS, and no more than the record has bytes. */
static lm_status slots(const uint8_t *buf, size_t len, lm_mesh *m)
{
    if (len < 32)
        return lm_fail(LM_E_FORMAT, "a start mesh of %zu bytes", len);
    uint32_t n_materials = u32_at(buf, 24), n_parts = u32_at(buf, 28);
    if (n_materials > MAX_SLOTS || n_parts > MAX_SLOTS || n_materials > len || n_parts > len)
        return lm_fail(LM_E_FORMAT, "a start mesh of %u materials and %u parts", n_materials,
                       n_parts);
    static const float grey[4] = {0.5f, 0.5f, 0.5f, 1.0f};
    lm_status st = LM_OK;
    uint32_t id;
    while (st == LM_OK && m->n_materials < n_materials)
        st = lm_mesh_add_material(m, "", grey, NULL, NULL, &id);
    while (st == LM_OK && m->n_parts < n_parts) {
        char name[32];
        snprintf(name, sizeof name, "part%u", m->n_parts);
        st = lm_mesh_add_part(m, name, &id);
    }
    return st;
}

lm_status lm_lane_mesh_decode(const uint8_t *buf, size_t len, lm_mesh *m)
{
    lm_status st = slots(buf, len, m);
    if (st != LM_OK)
        return st;
    lm_bin b;
    lm_bin_init_reader(&b, buf, len, "mesh");
    st = lm_optimizer_load_mesh_bin(m, &b);
    if (st == LM_OK && lm_bin_left(&b))
        st = lm_fail(LM_E_FORMAT, "a start mesh with trailing bytes");
    if (st == LM_OK && lm_mesh_validate(m) != LM_OK)
        st = lm_fail(LM_E_FORMAT, "a start mesh that is not valid: %s", lm_last_error());
    return st == LM_OK ? lm_mesh_build_adjacency(m) : st;
}
