/* common/optimizer/optimizer_state.c — the optimizer's checkpoint: a versioned binary record
 * of everything a run needs to continue exactly as if uninterrupted: parameters (checked), PRNG,
 * counters, the mesh in full (dead slots included, so ids stay identical), move statistics,
 * teleport state and collapse queue, oracle state and the iteration in progress. Floating-point
 * values are stored as raw bits. Loading parses and checks everything before replacing anything
 * it can (the mesh is replaced last), and re-sends the mesh to the views. */
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "common/mesh_topology.h"
#include "common/optimizer/binio.h"
#include "common/optimizer/optimizer_internal.h"

#define OPT_MAGIC "LMOPTST1"
#define OPT_VERSION 3u      /* 2: triangles carry their part; 3: the geometric term */
#define OPT_END 0x444e4521u /* "!END" */

/* ---- mesh --------------------------------------------------------------------------------------
 */

static void save_mesh(lm_bin *bp, const lm_mesh *m)
{
    lm_bin b = *bp;
    uint32_t head[8] = {m->n_verts,   m->n_wedges, m->n_tris,      m->live_verts,
                        m->live_tris, m->attrs,    m->n_materials, m->n_parts};
    for (int i = 0; i < 8; i++)
        lm_put_u32(&b, head[i]);
    if (LM_BIN_HOST_LE && sizeof *m->pos == 12 && sizeof *m->wedges == 40 &&
        sizeof *m->tris == 20) { /* the records' layout: their bytes at once */
        lm_put_bytes(&b, m->pos, (size_t)m->n_verts * 12);
        lm_put_bytes(&b, m->vert_alive, m->n_verts);
        lm_put_bytes(&b, m->wedges, (size_t)m->n_wedges * 40);
        lm_put_bytes(&b, m->wedge_alive, m->n_wedges);
        lm_put_bytes(&b, m->tris, (size_t)m->n_tris * 20);
        lm_put_bytes(&b, m->tri_alive, m->n_tris);
        *bp = b;
        return;
    }
    for (uint32_t v = 0; v < m->n_verts; v++)
        for (int k = 0; k < 3; k++)
            lm_put_f32(&b, m->pos[v][k]);
    lm_put_bytes(&b, m->vert_alive, m->n_verts);
    for (uint32_t i = 0; i < m->n_wedges; i++) {
        const lm_wedge *w = &m->wedges[i];
        lm_put_u32(&b, w->vertex);
        const float *f[3] = {w->normal, w->uv, w->color};
        const int nf[3] = {3, 2, 4};
        for (int g = 0; g < 3; g++)
            for (int k = 0; k < nf[g]; k++)
                lm_put_f32(&b, f[g][k]);
    }
    lm_put_bytes(&b, m->wedge_alive, m->n_wedges);
    for (uint32_t t = 0; t < m->n_tris; t++) {
        for (int k = 0; k < 3; k++)
            lm_put_u32(&b, m->tris[t].w[k]);
        lm_put_u32(&b, m->tris[t].material);
        lm_put_u32(&b, m->tris[t].part);
    }
    lm_put_bytes(&b, m->tri_alive, m->n_tris);
    *bp = b;
}

typedef struct mesh_arrays {
    uint32_t n_verts, n_wedges, n_tris, live_verts, live_tris, attrs;
    float (*pos)[3];
    uint8_t *vert_alive;
    lm_wedge *wedges;
    uint8_t *wedge_alive;
    lm_tri *tris;
    uint8_t *tri_alive;
} mesh_arrays;

static void arrays_free(mesh_arrays *a)
{
    free(a->pos);
    free(a->vert_alive);
    free(a->wedges);
    free(a->wedge_alive);
    free(a->tris);
    free(a->tri_alive);
}

static lm_status read_arrays(lm_bin *b, mesh_arrays *a)
{
    a->pos = malloc(((size_t)a->n_verts + 1) * sizeof *a->pos);
    a->vert_alive = malloc((size_t)a->n_verts + 1);
    a->wedges = malloc(((size_t)a->n_wedges + 1) * sizeof *a->wedges);
    a->wedge_alive = malloc((size_t)a->n_wedges + 1);
    a->tris = malloc(((size_t)a->n_tris + 1) * sizeof *a->tris);
    a->tri_alive = malloc((size_t)a->n_tris + 1);
    if (!a->pos || !a->vert_alive || !a->wedges || !a->wedge_alive || !a->tris || !a->tri_alive)
        return lm_fail(LM_E_NOMEM, "out of memory reading a checkpointed mesh");
    for (uint32_t v = 0; v < a->n_verts; v++)
        for (int k = 0; k < 3; k++)
            a->pos[v][k] = lm_get_f32(b);
    lm_get_bytes(b, a->vert_alive, a->n_verts);
    for (uint32_t i = 0; i < a->n_wedges && !b->status; i++) {
        lm_wedge *w = &a->wedges[i];
        w->vertex = lm_get_u32(b);
        float *f[3] = {w->normal, w->uv, w->color};
        const int nf[3] = {3, 2, 4};
        for (int g = 0; g < 3; g++)
            for (int k = 0; k < nf[g]; k++)
                f[g][k] = lm_get_f32(b);
    }
    lm_get_bytes(b, a->wedge_alive, a->n_wedges);
    for (uint32_t t = 0; t < a->n_tris && !b->status; t++) {
        for (int k = 0; k < 3; k++)
            a->tris[t].w[k] = lm_get_u32(b);
        a->tris[t].material = lm_get_u32(b);
        a->tris[t].part = lm_get_u32(b);
    }
    lm_get_bytes(b, a->tri_alive, a->n_tris);
    return b->status;
}

/* References and counts must be consistent: alive wedges on alive vertices, alive triangles on
 * alive wedges and existing materials. */
static lm_status check_arrays(lm_bin *b, const mesh_arrays *a, uint32_t n_materials,
                              uint32_t n_parts)
{
    uint32_t lv = 0, lt = 0;
    for (uint32_t v = 0; v < a->n_verts; v++) {
        if (a->vert_alive[v] > 1)
            return lm_bin_bad(b, "vertex %u has a bad alive flag", v);
        lv += a->vert_alive[v];
    }
    for (uint32_t i = 0; i < a->n_wedges; i++) {
        uint32_t v = a->wedges[i].vertex;
        if (a->wedge_alive[i] > 1 || (a->wedge_alive[i] && (v >= a->n_verts || !a->vert_alive[v])))
            return lm_bin_bad(b, "wedge %u refers to a missing vertex", i);
    }
    for (uint32_t t = 0; t < a->n_tris; t++) {
        if (a->tri_alive[t] > 1)
            return lm_bin_bad(b, "triangle %u has a bad alive flag", t);
        if (!a->tri_alive[t])
            continue;
        lt++;
        for (int k = 0; k < 3; k++) {
            uint32_t w = a->tris[t].w[k];
            if (w >= a->n_wedges || !a->wedge_alive[w])
                return lm_bin_bad(b, "triangle %u refers to a missing wedge", t);
        }
        if (a->tris[t].material >= (n_materials ? n_materials : 1))
            return lm_bin_bad(b, "triangle %u refers to a missing material", t);
        if (a->tris[t].part >= (n_parts ? n_parts : 1))
            return lm_bin_bad(b, "triangle %u refers to a missing part", t);
    }
    if (lv != a->live_verts || lt != a->live_tris)
        return lm_bin_bad(b, "live counts do not match the alive flags");
    return LM_OK;
}

static void install(lm_mesh *m, mesh_arrays *a)
{
    free(m->pos);
    free(m->vert_alive);
    free(m->wedges);
    free(m->wedge_alive);
    free(m->tris);
    free(m->tri_alive);
    m->pos = a->pos;
    m->vert_alive = a->vert_alive;
    m->wedges = a->wedges;
    m->wedge_alive = a->wedge_alive;
    m->tris = a->tris;
    m->tri_alive = a->tri_alive;
    m->n_verts = m->cap_verts = a->n_verts;
    m->n_wedges = m->cap_wedges = a->n_wedges;
    m->n_tris = m->cap_tris = a->n_tris;
    m->live_verts = a->live_verts;
    m->live_tris = a->live_tris;
    m->attrs = a->attrs;
    memset(a, 0, sizeof *a);
}

static lm_status load_mesh(lm_bin *b, const lm_mesh *m, mesh_arrays *a)
{
    uint32_t *h[6] = {&a->n_verts,    &a->n_wedges,  &a->n_tris,
                      &a->live_verts, &a->live_tris, &a->attrs};
    for (int i = 0; i < 6; i++)
        *h[i] = lm_get_u32(b);
    uint32_t n_materials = lm_get_u32(b), n_parts = lm_get_u32(b);
    if (b->status)
        return b->status;
    if (n_materials != m->n_materials)
        return lm_bin_bad(b, "%u materials, the mesh has %u", n_materials, m->n_materials);
    if (n_parts != m->n_parts)
        return lm_bin_bad(b, "%u parts, the mesh has %u", n_parts, m->n_parts);
    uint64_t need =
        (uint64_t)a->n_verts * 13 + (uint64_t)a->n_wedges * 41 + (uint64_t)a->n_tris * 21;
    if (a->n_verts > LM_MESH_MAX_VERTS || a->n_tris > LM_MESH_MAX_TRIS ||
        a->n_wedges > LM_MESH_MAX_VERTS * 4u || a->live_verts > a->n_verts ||
        a->live_tris > a->n_tris || need > lm_bin_left(b))
        return lm_bin_bad(b, "element counts out of range or truncated");
    lm_status st = read_arrays(b, a);
    return st ? st : check_arrays(b, a, n_materials, n_parts);
}

/* ---- statistics, oracle, iteration ---------------------------------------------------------- */

static void save_counters(lm_bin *b, const lm_optimizer *o)
{
    lm_put_u64(b, lm_moves_evals(o->mv));
    lm_put_u64(b, o->prog.iterations);
    lm_put_i64(b, o->prog.energy_start);
    lm_put_i64(b, o->prog.energy);
    lm_put_i64(b, o->prog.geometric_start);
    for (int k = 0; k < LM_MOVE_KINDS; k++) {
        lm_put_u64(b, o->prog.accepted[k]);
        lm_put_u64(b, o->prog.attempted[k]);
    }
}

static void load_counters(lm_bin *b, lm_progress *p)
{
    p->evals = lm_get_u64(b);
    p->iterations = lm_get_u64(b);
    p->energy_start = lm_get_i64(b);
    p->energy = lm_get_i64(b);
    p->geometric_start = lm_get_i64(b);
    for (int k = 0; k < LM_MOVE_KINDS; k++) {
        p->accepted[k] = lm_get_u64(b);
        p->attempted[k] = lm_get_u64(b);
    }
}

static void save_oracle(lm_bin *b, const lm_oracle *o)
{
    lm_put_f64(b, o->share);
    lm_put_f64(b, o->min_share);
    lm_put_f64(b, o->max_share);
    lm_put_u32(b, o->max_age);
    lm_put_u32(b, o->n_stale);
    for (uint32_t i = 0; i < o->n_stale; i++) {
        lm_put_u64(b, o->stale[i].key);
        lm_put_u64(b, o->stale[i].iteration);
    }
}

static lm_status load_oracle(lm_bin *b, lm_oracle *o)
{
    o->share = lm_get_f64(b);
    o->min_share = lm_get_f64(b);
    o->max_share = lm_get_f64(b);
    o->max_age = lm_get_u32(b);
    uint32_t n = lm_get_u32(b);
    if (b->status)
        return b->status;
    if (!(o->share >= 0 && o->share <= 1) || (uint64_t)n * 16 > lm_bin_left(b))
        return lm_bin_bad(b, "bad oracle state");
    lm_stale_edge *e = malloc(((size_t)n + 1) * sizeof *e);
    if (!e)
        return lm_fail(LM_E_NOMEM, "out of memory reading the oracle state");
    for (uint32_t i = 0; i < n; i++) {
        e[i].key = lm_get_u64(b);
        e[i].iteration = lm_get_u64(b);
    }
    lm_status st = b->status ? b->status : lm_oracle_set_stale(o, e, n);
    free(e);
    return st;
}

static void save_iteration(lm_bin *b, const lm_iteration *it)
{
    lm_put_u32(b, (uint32_t)it->active);
    lm_put_u32(b, it->pos);
    lm_put_u32(b, it->n_plan);
    for (uint32_t i = 0; i < it->n_plan; i++) {
        lm_put_u32(b, it->plan[i].a);
        lm_put_u32(b, it->plan[i].b);
        lm_put_u32(b, it->plan[i].from_oracle);
    }
    for (int s = 0; s < 2; s++) {
        lm_put_f64(b, it->gain[s]);
        lm_put_u32(b, it->count[s]);
    }
    lm_put_u32(b, it->n_no_progress);
    for (uint32_t i = 0; i < it->n_no_progress; i++)
        lm_put_u64(b, it->no_progress[i]);
    lm_put_u32(b, it->touched.n);
    for (uint32_t i = 0; i < it->touched.n; i++)
        lm_put_u32(b, it->touched.ids[i]);
}

/* Into `it`, whose arrays hold `cap` entries; touched vertices are ids below n_verts (the set is
 * sized by the largest id). */
static lm_status load_iteration(lm_bin *b, lm_iteration *it, uint32_t cap, uint32_t n_verts)
{
    it->active = (int)lm_get_u32(b);
    it->pos = lm_get_u32(b);
    it->n_plan = lm_get_u32(b);
    if (b->status)
        return b->status;
    if (it->n_plan > cap || it->pos > it->n_plan || (unsigned)it->active > 1)
        return lm_bin_bad(b, "bad iteration state");
    for (uint32_t i = 0; i < it->n_plan; i++) {
        it->plan[i].a = lm_get_u32(b);
        it->plan[i].b = lm_get_u32(b);
        it->plan[i].from_oracle = lm_get_u32(b);
    }
    for (int s = 0; s < 2; s++) {
        it->gain[s] = lm_get_f64(b);
        it->count[s] = lm_get_u32(b);
    }
    it->n_no_progress = lm_get_u32(b);
    if (!b->status && it->n_no_progress > cap)
        return lm_bin_bad(b, "bad iteration state");
    for (uint32_t i = 0; i < it->n_no_progress; i++)
        it->no_progress[i] = lm_get_u64(b);
    uint32_t n = lm_get_u32(b);
    if (!b->status && (uint64_t)n * 4 > lm_bin_left(b))
        return lm_bin_bad(b, "bad iteration state");
    for (uint32_t i = 0; i < n && !b->status; i++) {
        uint32_t v = lm_get_u32(b);
        if (v >= n_verts)
            return lm_bin_bad(b, "bad iteration state");
        lm_status st = lm_idset_add(&it->touched, v);
        if (st)
            return st;
    }
    return b->status;
}

/* ---- whole optimizer --------------------------------------------------------------------------
 */

/* Every tuning number, in a fixed order (they decide the run as much as the seed does); the
 * geometric term's weight last (check_params names it). */
static uint32_t tuning_values(const lm_tuning *t, double *v)
{
    const lm_moves_config *m = &t->moves;
    const lm_teleport_config *p = &t->teleport;
    double x[] = {m->max_set_verts,    m->max_dim,          m->pos_step,
                  m->normal_step,      m->uv_step,          m->color_step,
                  m->size_tol,         m->f_rtol,           p->threshold_half_life,
                  p->stats_half_life,  p->max_search_evals, t->stats_half_life,
                  t->stats_min_weight, t->oracle_share,     t->oracle_min_share,
                  t->oracle_max_share, t->oracle_max_age,   t->surface_weight};
    uint32_t n = sizeof x / sizeof *x;
    if (v)
        memcpy(v, x, sizeof x);
    return n;
}

/* Edges in flight as saved: their count, the top bit set with isolated lanes (a state without
 * them keeps its bytes). */
static uint32_t in_flight_word(const lm_optimizer *o)
{
    return o->params.edges_in_flight | (o->params.lane_isolation ? 1u << 31 : 0);
}

static void save_params(lm_bin *b, const lm_optimizer *o)
{
    lm_put_bytes(b, OPT_MAGIC, 8);
    lm_put_u32(b, OPT_VERSION);
    lm_put_u64(b, o->params.seed);
    lm_put_u32(b, o->params.attrs);
    lm_put_u32(b, o->attrs);
    lm_put_u32(b, o->params.edges_per_iteration);
    lm_put_u32(b, o->params.simplex_evals_per_dim);
    lm_put_u32(b, in_flight_word(o));
    double v[32];
    uint32_t n = tuning_values(&o->tuning, v);
    lm_put_u32(b, n);
    for (uint32_t i = 0; i < n; i++)
        lm_put_f64(b, v[i]);
}

static lm_status check_params(lm_bin *b, const lm_optimizer *o)
{
    char magic[8];
    lm_get_bytes(b, magic, 8);
    if (!b->status && memcmp(magic, OPT_MAGIC, 8) != 0)
        return lm_bin_bad(b, "not an optimizer state");
    uint32_t version = lm_get_u32(b);
    if (!b->status && version != OPT_VERSION)
        return lm_bin_bad(b, "version %u, this build reads %u", version, OPT_VERSION);
    uint64_t seed = lm_get_u64(b);
    uint32_t p[5];
    for (int i = 0; i < 5; i++)
        p[i] = lm_get_u32(b);
    if (b->status)
        return b->status;
    if (seed != o->params.seed || p[0] != o->params.attrs || p[1] != o->attrs ||
        p[2] != o->params.edges_per_iteration || p[3] != o->params.simplex_evals_per_dim ||
        p[4] != in_flight_word(o))
        return lm_bin_bad(b, "written with other optimizer parameters (seed, attrs, edges per "
                             "iteration, simplex limit or edges in flight)");
    double v[32];
    uint32_t n = tuning_values(&o->tuning, v), got = lm_get_u32(b);
    if (!b->status && got != n)
        return lm_bin_bad(b, "written with another set of tuning values");
    for (uint32_t i = 0; i < n && !b->status; i++) {
        double got_v = lm_get_f64(b);
        if (!b->status && got_v != v[i] && i == n - 1) /* the last: the geometric term's weight */
            return lm_bin_bad(b,
                              "written with another geometric term (weight %g, here %g; -1 = "
                              "none): give the run's --surface-weight or --surface-share",
                              got_v, v[i]);
        if (!b->status && got_v != v[i])
            return lm_bin_bad(b, "written with other tuning values");
    }
    return b->status;
}

lm_status lm_optimizer_save(const lm_optimizer *opt, FILE *fp)
{
    lm_bin b;
    lm_bin_init(&b, fp, "optimizer state");
    save_params(&b, opt);
    for (int i = 0; i < 4; i++)
        lm_put_u64(&b, opt->rng.s[i]);
    save_counters(&b, opt);
    save_mesh(&b, opt->mesh);
    lm_move_stats_save(&b, &opt->stats);
    if (b.status)
        return b.status;
    lm_status st = lm_teleport_save(&opt->tp, fp);
    if (st)
        return st;
    save_oracle(&b, &opt->oracle);
    save_iteration(&b, &opt->it);
    lm_put_u32(&b, OPT_END);
    return b.status;
}

typedef struct loaded {
    lm_rng rng;
    lm_progress prog;
    mesh_arrays mesh;
    lm_move_stats stats;
    lm_teleport tp;
    int tp_made;
    lm_oracle oracle;
    lm_iteration it;
} loaded;

static void loaded_free(loaded *l)
{
    arrays_free(&l->mesh);
    if (l->tp_made)
        lm_teleport_free(&l->tp);
    lm_oracle_free(&l->oracle);
    free(l->it.plan);
    free(l->it.no_progress);
    lm_idset_free(&l->it.touched);
}

static lm_status parse(lm_bin *b, const lm_optimizer *o, loaded *l)
{
    uint32_t cap = o->params.edges_per_iteration;
    lm_status st = check_params(b, o);
    for (int i = 0; i < 4 && !st; i++)
        l->rng.s[i] = lm_get_u64(b);
    if (!st)
        load_counters(b, &l->prog);
    if (!st && !(st = b->status))
        st = load_mesh(b, o->mesh, &l->mesh);
    if (!st)
        lm_move_stats_load(b, &l->stats);
    if (!st && !(st = b->status) && !(st = lm_teleport_init(&l->tp, &o->tp.cfg, NULL))) {
        l->tp_made = 1;
        st = lm_teleport_load(&l->tp, b->fp);
    }
    lm_oracle_init(&l->oracle);
    lm_idset_init(&l->it.touched);
    if (!st)
        st = load_oracle(b, &l->oracle);
    l->it.plan = calloc(cap, sizeof *l->it.plan);
    l->it.no_progress = calloc(cap, sizeof *l->it.no_progress);
    if (!st && (!l->it.plan || !l->it.no_progress))
        st = lm_fail(LM_E_NOMEM, "out of memory reading the optimizer state");
    if (!st)
        st = load_iteration(b, &l->it, cap, l->mesh.n_verts);
    if (!st && lm_get_u32(b) != OPT_END)
        st = lm_bin_bad(b, "missing end marker");
    for (uint32_t i = 0; i < l->it.n_plan && !st; i++)
        if (l->it.plan[i].a >= l->mesh.n_verts || l->it.plan[i].b >= l->mesh.n_verts)
            st = lm_bin_bad(b, "planned edge %u is outside the mesh", i);
    return st ? st : b->status;
}

static lm_status resend_mesh(lm_optimizer *o)
{
    lm_status st = lm_views_set_mesh_from(o->views, o->mesh);
    int64_t e = 0;
    if (!st)
        st = o->views->ops->energy(o->views, &e, NULL);
    if (!st && e != o->prog.energy)
        lm_warn("resumed mesh renders to energy %lld, the checkpoint recorded %lld", (long long)e,
                (long long)o->prog.energy);
    return st;
}

static void swap_in(lm_optimizer *o, loaded *l)
{
    o->rng = l->rng;
    o->prog = l->prog;
    lm_moves_set_evals(o->mv, l->prog.evals);
    lm_moves_forget(o->mv);
    o->stats = l->stats;
    lm_teleport t = o->tp;
    o->tp = l->tp;
    l->tp = t;
    lm_oracle oc = o->oracle;
    o->oracle = l->oracle;
    l->oracle = oc;
    lm_iteration it = o->it;
    o->it = l->it;
    l->it = it;
}

lm_status lm_optimizer_load(lm_optimizer *opt, FILE *fp)
{
    lm_bin b;
    lm_bin_init(&b, fp, "optimizer state");
    loaded l;
    memset(&l, 0, sizeof l);
    lm_status st = parse(&b, opt, &l);
    if (!st) {
        install(opt->mesh, &l.mesh);
        swap_in(opt, &l);
        st = lm_mesh_build_adjacency(opt->mesh);
        if (!st)
            st = resend_mesh(opt);
    }
    loaded_free(&l);
    return st;
}

lm_status lm_optimizer_save_mesh_bin(const lm_mesh *m, lm_bin *b)
{
    save_mesh(b, m);
    return b->status;
}

lm_status lm_optimizer_load_mesh_bin(lm_mesh *m, lm_bin *b)
{
    mesh_arrays a;
    memset(&a, 0, sizeof a);
    lm_status st = load_mesh(b, m, &a);
    if (!st)
        install(m, &a);
    arrays_free(&a);
    return st;
}

lm_status lm_optimizer_save_mesh(const lm_mesh *m, FILE *fp)
{
    lm_bin b;
    lm_bin_init(&b, fp, "mesh");
    return lm_optimizer_save_mesh_bin(m, &b);
}

lm_status lm_optimizer_load_mesh(lm_mesh *m, FILE *fp)
{
    lm_bin b;
    lm_bin_init(&b, fp, "mesh");
    return lm_optimizer_load_mesh_bin(m, &b);
}
