/* coordinator/simplify/lod.c — the level-of-detail chain: the defaults, targets from the spec, one
 * set of views of the original, per level simplify (image / shard / QEM) → optimise → next, and the
 * output (one file per level or one GLB), measured into the manifest (lod_manifest.h). */
#include "coordinator/simplify/lod.h"
#include "coordinator/quality/cull_unseen.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/folders.h"
#include "common/mesh_topology.h"
#include "common/optimizer/optimizer.h"
#include "coordinator/pool/pool.h"
#include "coordinator/quality/view_setup.h"
#include "coordinator/simplify/isimp.h"
#include "coordinator/simplify/lod_manifest.h"
#include "coordinator/simplify/simplify.h"
#include "coordinator/simplify/work.h"

#define CO_LOD_MAX_IDLE_STEPS 16

typedef struct lod {
    const co_lod_options *o;
    co_lod_summary *sum;
    lm_mesh *orig;
    lm_view_set *vs;
    co_pool *pool;
    lm_views *views, *shard_views;
    lm_mesh *levels[LM_MESH_MAX_LODS];
    uint32_t target[LM_MESH_MAX_LODS];
} lod;

co_lod_options co_lod_resolve(const co_lod_options *in)
{
    co_lod_options o = *in;
    o.evals = o.evals ? o.evals : CO_LOD_DEFAULT_EVALS;
    if (o.views.dist != LM_VIEW_DIST_CAMERAS && !o.views.count)
        o.views.count = LM_DEFAULT_VIEWS;
    o.size = o.size ? o.size : LM_DEFAULT_VIEW_SIZE;
    o.seed = o.seed ? o.seed : CO_LOD_DEFAULT_SEED;
    o.screen_height = o.screen_height ? o.screen_height : CO_LOD_DEFAULT_SCREEN_HEIGHT;
    o.fov_deg = o.fov_deg > 0 ? o.fov_deg : CO_LOD_DEFAULT_FOV;
    o.pixel_error = o.pixel_error > 0 ? o.pixel_error : CO_LOD_DEFAULT_PIXEL_ERROR;
    return o;
}

lm_status co_lod_parse_levels(const char *spec, co_lod_options *o)
{
    o->n_levels = 0;
    for (const char *p = spec; p && *p;) {
        size_t n = strcspn(p, ",");
        char item[64];
        if (n == 0 || n >= sizeof item || o->n_levels == LM_MESH_MAX_LODS)
            return lm_fail(LM_E_INVALID,
                           "--levels: '%s' is not a list of up to %u levels such "
                           "as 50%%,25%%,10%%",
                           spec, LM_MESH_MAX_LODS);
        memcpy(item, p, n);
        item[n] = 0;
        char *end;
        double x = strtod(item, &end);
        co_lod_spec *l = &o->levels[o->n_levels++];
        *l = (co_lod_spec){0};
        if (*end == '%' && end[1] == 0 && x > 0 && x <= 100)
            l->fraction = x / 100.0;
        else if (*end == 0 && x >= 4 && x <= LM_MESH_MAX_VERTS && x == floor(x))
            l->verts = (uint32_t)x;
        else
            return lm_fail(LM_E_INVALID,
                           "--levels: '%s' is neither a percentage (0-100%%] nor a "
                           "vertex count (at least 4)",
                           item);
        p += n + (p[n] == ',');
    }
    return o->n_levels ? LM_OK : lm_fail(LM_E_INVALID, "--levels needs at least one level");
}

void co_lod_level_path(const char *out, uint32_t k, char *buf, size_t cap)
{
    const char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
    if (!dot || (slash && dot < slash))
        dot = out + strlen(out);
    snprintf(buf, cap, "%.*s.lod%u%s", (int)(dot - out), out, k, dot);
}

/* Targets in vertices, strictly decreasing. */
static lm_status resolve_targets(lod *L)
{
    uint32_t live = L->orig->live_verts;
    for (uint32_t k = 0; k < L->o->n_levels; k++) {
        const co_lod_spec *s = &L->o->levels[k];
        uint32_t t = s->fraction > 0 ? (uint32_t)floor(s->fraction * live + 0.5) : s->verts;
        t = t < 4 ? 4 : t > live ? live : t;
        if (k && t >= L->target[k - 1])
            return lm_fail(LM_E_INVALID,
                           "--levels: level %u (%u vertices) is not below level %u "
                           "(%u vertices)",
                           k, t, k - 1, L->target[k - 1]);
        L->target[k] = t;
    }
    return LM_OK;
}

static lm_status make_views(lod *L)
{
    const co_lod_options *o = L->o;
    lm_status st = co_view_set_of(L->orig, &o->views, o->size, 0, &L->vs);
    if (st == LM_OK)
        st = co_simplify_pool_start(&o->workers, o->device, &L->pool);
    if (st == LM_OK)
        st = co_simplify_make_views(CO_PRICE_IMAGE, L->orig, L->orig, L->vs, o->device, L->pool,
                                    &L->views);
    if (st == LM_OK && !o->qem && o->method == CO_PRICE_SHARD)
        st = co_simplify_make_views(CO_PRICE_SHARD, L->orig, L->orig, L->vs, o->device, NULL,
                                    &L->shard_views);
    if (st == LM_OK) {
        lm_views_info info;
        L->views->ops->info(L->views, &info);
        snprintf(L->sum->renderer, sizeof L->sum->renderer, "%s", info.renderer);
    }
    return st;
}

/* QEM or the shape-adaptive method when asked (or QEM to 10 x the target first), then
 * image-driven or shard collapses. */
static lm_status simplify_level(lod *L, uint32_t k, lm_mesh **out)
{
    const lm_mesh *prev = k ? L->levels[k - 1] : L->orig;
    uint32_t t = L->target[k];
    int geometric = L->o->qem || L->o->adaptive;
    uint32_t start = geometric ? t : co_simplify_start_verts(prev->live_verts, t, 0);
    int short_of = 0;
    co_simplify_method how = L->o->adaptive ? CO_SIMPLIFY_ADAPTIVE : CO_SIMPLIFY_QEM;
    lm_status st = start < prev->live_verts ? co_simplify_best(prev, how, start, out, &short_of)
                                            : lm_mesh_clone(prev, out);
    if (short_of)
        lm_clear_error();
    int derived;
    if (st == LM_OK)
        st = co_simplify_prepare(*out, &derived);
    if (st != LM_OK || geometric || (*out)->live_verts <= t)
        return st;
    int shard = L->o->method == CO_PRICE_SHARD;
    co_isimp_config cfg = {
        .method = L->o->method, .target_verts = t, .views = L->vs, .derived_normals = derived};
    co_isimp_stats s = {0};
    if (!shard)
        st = lm_views_set_mesh_from(L->views, *out);
    if (st == LM_OK)
        st = co_isimp_run(*out, shard ? L->shard_views : L->views, &cfg, &s);
    L->sum->level[k].collapses = s.collapses;
    L->sum->level[k].simplify_evals = s.evaluations;
    return st;
}

/* The optimizer's attributes, as `lumesh optimize` chooses them: uv when textured, colour when
 * coloured; normals derived. */
static uint32_t optimizer_attrs(const lm_mesh *orig)
{
    int textured = 0;
    for (uint32_t i = 0; i < orig->n_materials; i++)
        textured |= orig->materials[i].texture != NULL;
    return ((orig->attrs & LM_ATTR_UV) && textured ? LM_ATTR_UV : 0) |
           (orig->attrs & LM_ATTR_COLOR);
}

/* Optimise m (taken) against the original's images for the level's budget; the result in *out. */
static lm_status optimize_level(lod *L, uint32_t k, lm_mesh *m, lm_mesh **out)
{
    uint64_t budget = L->o->evals;
    lm_mesh_merge_wedges(m, LM_ATTR_UV | LM_ATTR_COLOR);
    lm_mesh_compute_normals(m);
    lm_params params = {.seed = L->o->seed, .attrs = optimizer_attrs(L->orig)};
    lm_optimizer *opt = NULL;
    lm_status st = lm_mesh_compact(m);
    if (st == LM_OK)
        st = lm_mesh_build_adjacency(m);
    if (st == LM_OK)
        st = lm_optimizer_create(m, L->views, &params, &opt);
    else
        lm_mesh_destroy(m);
    lm_progress p = {0};
    for (int idle = 0; st == LM_OK && idle < CO_LOD_MAX_IDLE_STEPS;) {
        lm_optimizer_progress(opt, &p);
        if (p.evals >= budget)
            break;
        uint64_t before = p.evals;
        st = lm_optimizer_step(opt, budget);
        lm_optimizer_progress(opt, &p);
        idle = p.evals == before ? idle + 1 : 0;
    }
    if (st == LM_OK) {
        L->sum->level[k].optimize_evals = p.evals;
        L->sum->level[k].energy_optimized = p.energy;
        st = co_simplify_output_copy(lm_optimizer_mesh(opt), out);
    }
    lm_optimizer_destroy(opt);
    return st;
}

static lm_status energy_of(lod *L, const lm_mesh *m, int64_t *e)
{
    lm_status st = lm_views_set_mesh_from(L->views, m);
    return st == LM_OK ? L->views->ops->energy(L->views, e, NULL) : st;
}

static lm_status make_level(lod *L, uint32_t k)
{
    co_lod_level_result *r = &L->sum->level[k];
    double t0 = co_now_s();
    r->target = L->target[k];
    lm_mesh *m = NULL;
    lm_status st;
    if (L->target[k] >= L->orig->live_verts) /* 100%: the original as it is */
        st = co_simplify_output_copy(L->orig, &L->levels[k]);
    else if ((st = simplify_level(L, k, &m)) == LM_OK &&
             (st = energy_of(L, m, &r->energy_simplified)) == LM_OK) {
        lm_mesh *simplified = NULL;
        st = co_simplify_output_copy(m, &simplified);
        if (st == LM_OK && !L->o->no_optimize)
            st = optimize_level(L, k, m, &L->levels[k]);
        else
            lm_mesh_destroy(m);
        m = NULL;
        /* the optimiser derives normals; where that loses to the level as simplified (a model
           with normals of its own, a small budget), the simplified level is kept */
        if (st == LM_OK && (L->o->no_optimize || r->energy_optimized > r->energy_simplified)) {
            lm_mesh_destroy(L->levels[k]);
            L->levels[k] = simplified;
            r->kept_simplified = !L->o->no_optimize;
            r->energy_optimized = r->energy_simplified;
            simplified = NULL;
        }
        lm_mesh_destroy(simplified);
    }
    lm_mesh_destroy(m);
    if (st == LM_OK) {
        r->verts = L->levels[k]->live_verts;
        r->tris = L->levels[k]->live_tris;
        r->parts = lm_mesh_count_parts(L->levels[k]);
        if (L->target[k] >= L->orig->live_verts)
            st = energy_of(L, L->levels[k], &r->energy_optimized);
    }
    r->seconds = co_now_s() - t0;
    if (st == LM_OK && L->o->progress)
        fprintf(stderr, "lumesh lod: level %u: %u vertices, %u triangles (%.1f s)\n", k, r->verts,
                r->tris, r->seconds);
    if (st == LM_OK)
        co_simplify_warn_lost_parts("lod", L->orig, L->levels[k]);
    return st;
}

static lm_status write_levels(const co_lod_options *o, co_lod_summary *sum, lm_mesh **levels)
{
    uint32_t n = o->n_levels;
    lm_status st = lm_make_parent_folders(o->output_path);
    if (o->msft_lod) {
        float coverage[LM_MESH_MAX_LODS];
        for (uint32_t k = 0; k < n; k++) /* halving screen coverages: 0.5, 0.25, ... */
            coverage[k] = (float)ldexp(1.0, -(int)k - 1);
        return st ? st
                  : lm_mesh_save_glb_lods(o->output_path, (const lm_mesh *const *)levels, n,
                                          coverage);
    }
    for (uint32_t k = 0; k < n && st == LM_OK; k++) {
        co_lod_level_path(o->output_path, k, sum->level[k].path, sizeof sum->level[k].path);
        st = lm_mesh_save(sum->level[k].path, levels[k]);
    }
    return st;
}

lm_status co_lod_build(const co_lod_options *given, co_lod_summary *sum, lm_mesh **levels)
{
    memset(sum, 0, sizeof *sum);
    double t0 = co_now_s();
    co_lod_options resolved = co_lod_resolve(given), *o = &resolved;
    lod L = {.o = o, .sum = sum};
    lm_status st = lm_mesh_load(o->input_path, NULL, &L.orig);
    if (st == LM_OK) {
        sum->in_verts = L.orig->live_verts;
        sum->in_tris = L.orig->live_tris;
        sum->in_parts = lm_mesh_count_parts(L.orig);
        sum->n_levels = o->n_levels;
        st = resolve_targets(&L);
    }
    if (st == LM_OK)
        st = make_views(&L);
    for (uint32_t k = 0; k < o->n_levels && st == LM_OK; k++)
        st = make_level(&L, k);
    for (uint32_t k = 0; o->cull_unseen && k < o->n_levels && st == LM_OK; k++) {
        st = co_cull_unseen(L.levels[k], L.orig, &o->views, o->size, &sum->level[k].culled_tris);
        sum->level[k].verts = L.levels[k]->live_verts;
        sum->level[k].tris = L.levels[k]->live_tris;
    }
    for (uint32_t k = 0; k < o->n_levels; k++) {
        levels[k] = st == LM_OK ? L.levels[k] : NULL;
        if (st != LM_OK)
            lm_mesh_destroy(L.levels[k]);
    }
    lm_views_destroy(L.shard_views);
    lm_views_destroy(L.views);
    co_pool_destroy(L.pool);
    free(L.vs);
    lm_mesh_destroy(L.orig);
    sum->seconds = co_now_s() - t0;
    return st;
}

lm_status co_lod_run(const co_lod_options *given, co_lod_summary *sum)
{
    co_lod_options o_resolved = co_lod_resolve(given), *o = &o_resolved;
    lm_mesh *levels[LM_MESH_MAX_LODS] = {0};
    lm_status st = co_lod_build(o, sum, levels);
    if (st == LM_OK)
        st = write_levels(o, sum, levels);
    if (st == LM_OK)
        st = co_lod_measure_levels(o, sum, (const lm_mesh *const *)levels);
    if (st == LM_OK)
        st = co_lod_manifest_write(o, sum);
    for (uint32_t k = 0; k < o->n_levels; k++)
        lm_mesh_destroy(levels[k]);
    return st;
}
