/* tests/bench/scaling/meter.c — the measuring views: in-process views behind a wrapper that
 * records, for every evaluation batch, its patches, the bytes of the Evaluate message a worker
 * would receive (encoded exactly as the remote backend encodes it, against a replica of the
 * workers' records) and the views' time; and the views' other work (commits, meshes, energies,
 * the oracle's potentials) with the optimizer's planning around the potentials. The process CPU
 * outside the views is the coordinator's own work. */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "scaling.h"

double sc_wall(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

double sc_cpu(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The first request after an iteration's potentials: the planning around them is over. */
void sc_close_plan(meter *m)
{
    if (m->plan_open)
        m->plan_s += sc_cpu() - m->pot_end;
    m->plan_open = 0;
}

/* A state request (commit, mesh, energy, potentials) that took the views `w` seconds and `c` of
 * CPU from CPU time c0. */
static void state_done(meter *m, double w, double c0, double c1)
{
    m->state_cpu_s += c1 - c0;
    m->state_wall_s += w;
}

/* Bytes of an Evaluate (or, with n == 1 and commit, a Commit) message carrying these patches. */
static size_t message_bytes(meter *m, const lm_patch *p, uint32_t n, int commit)
{
    Lumesh__Patch *wp = lm_wire_arena_alloc(&m->arena, n * sizeof *wp);
    Lumesh__Patch **pp = lm_wire_arena_alloc(&m->arena, n * sizeof *pp);
    for (uint32_t i = 0; i < n; i++) {
        lm_wire_patch_encode_against(&p[i], lm_replica_current, &m->rep, &m->arena, &wp[i]);
        pp[i] = &wp[i];
    }
    Lumesh__Evaluate e = LUMESH__EVALUATE__INIT;
    Lumesh__Commit c = LUMESH__COMMIT__INIT;
    e.n_patches = n, e.patches = pp, c.patch = wp;
    lm_msg msg;
    lm_wire_msg_init(&msg, 1, 1, commit ? LUMESH__MSG__BODY_COMMIT : LUMESH__MSG__BODY_EVALUATE,
                     commit ? (void *)&c : (void *)&e);
    size_t bytes = lumesh__msg__get_packed_size(&msg);
    lm_wire_arena_reset(&m->arena);
    return bytes;
}

static lm_status me_evaluate(lm_views *v, const lm_patch *p, uint32_t n, int64_t *d)
{
    meter *m = (meter *)v;
    sc_close_plan(m);
    double c0 = sc_cpu(), t0 = sc_wall();
    lm_status st = m->in->ops->evaluate(m->in, p, n, d);
    m->views_s += sc_wall() - t0;
    double c1 = sc_cpu();
    m->views_cpu_s += c1 - c0;
    m->patches += n;
    if (m->light) {
        m->overlap_now = 0;
        return st;
    }
    if (m->batches == m->cap) {
        m->cap = m->cap ? 2 * m->cap : 4096;
        m->n = realloc(m->n, m->cap * sizeof *m->n);
        m->bytes = realloc(m->bytes, m->cap * sizeof *m->bytes);
        m->overlap = realloc(m->overlap, m->cap * sizeof *m->overlap);
    }
    m->overlap[m->batches] = (float)m->overlap_now;
    m->overlap_now = 0;
    m->n[m->batches] = n;
    m->bytes[m->batches++] = (uint32_t)message_bytes(m, p, n, 0);
    m->encode_cpu_s += sc_cpu() - c1;
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t j = 0; j < p[i].n_added; j++) {
            const lm_tri_data *cur = lm_replica_current(&m->rep, p[i].added[j].id);
            m->added++;
            m->kept_pos += cur && !memcmp(cur->c[0].pos, p[i].added[j].c[0].pos, 12) &&
                           !memcmp(cur->c[1].pos, p[i].added[j].c[1].pos, 12) &&
                           !memcmp(cur->c[2].pos, p[i].added[j].c[2].pos, 12);
        }
    return st;
}

/* As a remote backend: the caller's overlapped work (the geometric term), timed apart, then the
 * evaluation. */
static lm_status me_evaluate_overlapped(lm_views *v, const lm_patch *p, uint32_t n, int64_t *d,
                                        void (*overlap)(void *ctx), void *ctx)
{
    meter *m = (meter *)v;
    sc_close_plan(m);
    double c0 = sc_cpu();
    if (overlap)
        overlap(ctx);
    m->overlap_now = sc_cpu() - c0;
    m->overlap_cpu_s += m->overlap_now;
    return me_evaluate(v, p, n, d);
}

static lm_status me_commit(lm_views *v, const lm_patch *p)
{
    meter *m = (meter *)v;
    sc_close_plan(m);
    m->commits++;
    double e0 = sc_cpu();
    m->commit_bytes += message_bytes(m, p, 1, 1);
    double e1 = sc_cpu();
    lm_status st = lm_replica_apply(&m->rep, p);
    double c0 = sc_cpu();
    m->commit_enc_s += e1 - e0;
    m->replica_s += c0 - e1;
    double t0 = sc_wall();
    if (st == LM_OK)
        st = m->in->ops->commit(m->in, p);
    double w = sc_wall() - t0;
    state_done(m, w, c0, sc_cpu());
    m->commit_wall_s += w;
    return st;
}

static lm_status me_set_mesh(lm_views *v, const lm_tri_data *t, size_t n)
{
    meter *m = (meter *)v;
    sc_close_plan(m);
    double r0 = sc_cpu();
    lm_status st = lm_replica_set(&m->rep, t, n);
    double c0 = sc_cpu();
    m->replica_s += c0 - r0;
    double t0 = sc_wall();
    if (st == LM_OK)
        st = m->in->ops->set_mesh(m->in, t, n);
    state_done(m, sc_wall() - t0, c0, sc_cpu());
    return st;
}

static lm_status me_set_materials(lm_views *v, const lm_material *mat, uint32_t n)
{
    meter *m = (meter *)v;
    return m->in->ops->set_materials(m->in, mat, n);
}

static lm_status me_energy(lm_views *v, int64_t *t, int64_t *pv)
{
    meter *m = (meter *)v;
    sc_close_plan(m);
    double c0 = sc_cpu(), t0 = sc_wall();
    lm_status st = m->in->ops->energy(m->in, t, pv);
    state_done(m, sc_wall() - t0, c0, sc_cpu());
    m->round_trips++;
    return st;
}

static lm_status me_potentials(lm_views *v, const float (*pts)[3], size_t n, int64_t *out)
{
    meter *m = (meter *)v;
    sc_close_plan(m);
    double c0 = sc_cpu();
    if (m->light) /* the first request of a step: what came before it was planning */
        m->plan_s += c0 - m->step_c0;
    double t0 = sc_wall();
    lm_status st = m->in->ops->potentials(m->in, pts, n, out);
    double w = sc_wall() - t0, c1 = sc_cpu();
    state_done(m, w, c0, c1);
    m->pot_wall_s += w;
    m->pot_end = c1;
    m->plan_open = m->light;
    m->round_trips++;
    return st;
}

static lm_status me_read_image(lm_views *v, lm_image_kind k, uint32_t view, uint8_t *out)
{
    meter *m = (meter *)v;
    return m->in->ops->read_image(m->in, k, view, out);
}

static void me_info(lm_views *v, lm_views_info *out)
{
    meter *m = (meter *)v;
    m->in->ops->info(m->in, out);
}

static void me_destroy(lm_views *v)
{
    (void)v;
}

/* The geometric term where the views hold it (the workers' with --lanes remote, as in the job):
 * forwarded, so that the optimizer and the lanes price it as they do on the job's views. */
static lm_status me_surface_term(lm_views *v, const lm_mesh *surface, double k)
{
    meter *m = (meter *)v;
    return lm_views_surface_term(m->in, surface, k);
}

static lm_status me_evaluate_surface(lm_views *v, const lm_patch *p, uint32_t n, int64_t *d)
{
    meter *m = (meter *)v;
    sc_close_plan(m);
    double c0 = sc_cpu(), t0 = sc_wall();
    lm_status st = m->in->ops->evaluate_surface(m->in, p, n, d);
    m->views_s += sc_wall() - t0;
    m->views_cpu_s += sc_cpu() - c0;
    m->patches += n;
    return st;
}

static const lm_views_ops meter_ops = {
    .set_mesh = me_set_mesh,
    .set_materials = me_set_materials,
    .evaluate = me_evaluate,
    .evaluate_overlapped = me_evaluate_overlapped,
    .commit = me_commit,
    .energy = me_energy,
    .potentials = me_potentials,
    .read_image = me_read_image,
    .info = me_info,
    .destroy = me_destroy,
};

/* The lanes' runs' (sc_meter_start_on): the job's views, the geometric term with them. */
static const lm_views_ops meter_ops_surface = {
    .set_mesh = me_set_mesh,
    .set_materials = me_set_materials,
    .evaluate = me_evaluate,
    .evaluate_overlapped = me_evaluate_overlapped,
    .commit = me_commit,
    .energy = me_energy,
    .potentials = me_potentials,
    .read_image = me_read_image,
    .info = me_info,
    .destroy = me_destroy,
    .surface_term = me_surface_term,
    .evaluate_surface = me_evaluate_surface,
};

/* The meter over new in-process views, and *mesh a copy of the start for an optimizer. */
lm_status sc_meter_start(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                         const lm_view_set *vs, int light, meter *m, lm_mesh **mesh)
{
    lm_status st = sc_meter_start_on(o, orig, coarse, vs, light, NULL, NULL, m, mesh);
    m->base.ops = &meter_ops; /* the geometric term priced by the optimizer, as before */
    return st;
}

lm_status sc_meter_start_on(const opts *o, const lm_mesh *orig, const lm_mesh *coarse,
                            const lm_view_set *vs, int light, co_pool *pool,
                            const co_audit_rule *audit, meter *m, lm_mesh **mesh)
{
    co_views_desc d = {.kind = pool ? CO_VIEWS_REMOTE : CO_VIEWS_LOCAL,
                       .pool = pool,
                       .whole = pool != NULL,
                       .audit = audit ? *audit : (co_audit_rule){0, 0},
                       .original = orig,
                       .views = vs,
                       .materials = coarse->materials,
                       .n_materials = coarse->n_materials,
                       .device = o->device};
    memset(m, 0, sizeof *m);
    m->base.ops = &meter_ops_surface;
    m->light = light;
    lm_wire_arena_init(&m->arena);
    lm_status st = co_views_create(&d, &m->in);
    return st == LM_OK ? lm_mesh_clone(coarse, mesh) : st;
}
