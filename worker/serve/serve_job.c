/* worker/serve/serve_job.c — the worker's job: the original and the view set (Job), the views it is
 * assigned (Assign: targets rendered, or taken from a targets asset), the replica's changes of
 * state in sequence (SetMaterials, SetSurface, SetMesh, Commit) and the requests priced against it
 * (Evaluate, Energy, Potentials, ReadImage); with SetSurface, its share of the geometric term added
 * to every Evaluate. Everything decoded is checked (proto/wire_records.h; the views backend checks
 * patches against the replica) and a failure is answered, never fatal. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "worker/render/views_local.h"
#include "worker/serve/serve_internal.h"

static void drop_views(wk_server *s)
{
    lm_surface_table_destroy(s->geo);
    s->geo = NULL;
    s->mesh_set = 0;
    lm_replica_clear(&s->rep);
    lm_views_destroy(s->v);
    s->v = NULL;
    s->seq = 0;
    s->stale = 0;
    s->n_materials = 0;
}

void wk_serve_end_job(wk_server *s)
{
    wk_serve_lanes_free(s);
    drop_views(s);
    lm_mesh_destroy(s->original);
    s->original = NULL;
    free(s->views);
    s->views = NULL;
    s->job = 0;
}

static lm_status hash_from(const ProtobufCBinaryData *b, lm_asset_hash *h)
{
    if (b->len != LM_ASSET_HASH_BYTES)
        return lm_fail(LM_E_FORMAT, "an asset hash of %zu bytes", b->len);
    memcpy(h->b, b->data, sizeof h->b);
    return LM_OK;
}

/* The asset named by b, from the cache. */
static lm_status cached(wk_server *s, const ProtobufCBinaryData *b, const lm_asset **out)
{
    lm_asset_hash h;
    lm_status st = hash_from(b, &h);
    char buf[17];
    if (st == LM_OK && !(*out = lm_asset_set_find(&s->cache, &h)))
        st = lm_fail(LM_E_INVALID, "asset %s was never sent", lm_asset_hash_short(&h, buf));
    return st;
}

static lm_status take_views(wk_server *s, const Lumesh__Job *j)
{
    if (j->n_views < 1 || j->n_views > LM_MAX_VIEWS)
        return lm_fail(LM_E_RANGE, "a job of %zu views", j->n_views);
    s->views = malloc(sizeof *s->views);
    if (!s->views)
        return lm_fail(LM_E_NOMEM, "out of memory for the view set");
    s->views->count = (uint32_t)j->n_views;
    lm_status st = LM_OK;
    for (size_t i = 0; i < j->n_views && st == LM_OK; i++)
        st = lm_wire_view_decode(j->views[i], (int)j->width, (int)j->height, &s->views->views[i]);
    return st;
}

/* Fault injection for tests (LUMESH_WORKER_FAULT, read only by builds with LUMESH_TEST_HOOKS):
 * "slow-load=S" makes loading the job's original (Job) and rendering its targets (Assign) take S
 * more seconds, silent: no heartbeats meanwhile (a worker whose load outlasts the liveness limit,
 * on a loaded machine). From its first load on, the worker's own limit on the coordinator's
 * silence is also cut to S - 1 s (S > 2), so that the time spent loading must not count as the
 * coordinator's silence (serve.c); the set-up before it (a start made, a sanitizer build) keeps
 * the usual limit. */
double wk_serve_slow_load_s(const wk_server *s)
{
    static const char kind[] = "slow-load=";
    if (!s->fault || strncmp(s->fault, kind, sizeof kind - 1))
        return 0.0;
    double v = strtod(s->fault + sizeof kind - 1, NULL);
    return v > 0 && v < 3600 ? v : 0.0;
}

static void slow_load(wk_server *s)
{
    double d = wk_serve_slow_load_s(s);
    if (!(d > 0))
        return;
    if (d > 2.0)
        s->o.silence_s = d - 1.0;
    wk_beat_pause(s, 1);
    struct timespec ts = {(time_t)d, (long)((d - (double)(time_t)d) * 1e9)};
    while (nanosleep(&ts, &ts) != 0)
        ;
    wk_beat_pause(s, 0);
}

lm_status wk_serve_job(wk_server *s, const lm_msg *m)
{
    wk_serve_end_job(s);
    slow_load(s);
    const lm_asset *a = NULL;
    lm_status st = take_views(s, m->job);
    if (st == LM_OK)
        st = cached(s, &m->job->original, &a);
    if (st == LM_OK)
        st = lm_asset_unpack_mesh(a->data, a->size, &s->cache, &s->original);
    if (st == LM_OK) {
        s->original_hash = a->hash;
        if (s->bvh && memcmp(s->bvh_of.b, a->hash.b, sizeof a->hash.b)) {
            lm_bvh_destroy(s->bvh); /* made for another original */
            s->bvh = NULL;
        }
    }
    if (st != LM_OK) {
        lm_status code = st;
        char msg[512];
        snprintf(msg, sizeof msg, "%s", lm_last_error());
        wk_serve_end_job(s);
        return wk_serve_fail(s, m->req, code, msg);
    }
    s->job = m->job->job;
    Lumesh__Ready r = LUMESH__READY__INIT;
    r.job = s->job;
    return wk_serve_send(s, m->req, LUMESH__MSG__BODY_READY, &r);
}

/* The views of deal with the targets of the asset named by b (Assign.targets), which must be of
 * the job's view set: its count and size. The asset leaves the cache once used (a coordinator
 * that assigns it again offers it again). */
static lm_status create_given(wk_server *s, lm_view_deal deal, const ProtobufCBinaryData *b)
{
    const lm_asset *a = NULL;
    lm_asset_targets t;
    lm_status st = cached(s, b, &a);
    if (st == LM_OK)
        st = lm_asset_unpack_targets(a->data, a->size, &t);
    const lm_view *v0 = &s->views->views[0];
    if (st == LM_OK &&
        (t.n_views != s->views->count || (int)t.width != v0->width || (int)t.height != v0->height))
        st = lm_fail(LM_E_INVALID, "targets of %u views of %ux%u given for %u views of %dx%d",
                     t.n_views, t.width, t.height, s->views->count, v0->width, v0->height);
    if (st == LM_OK)
        st = wk_views_local_create_given(s->original, s->views, deal, s->o.device, t.luma, &s->v);
    if (st == LM_OK) /* each bring-up has targets of its own: the cache must not keep them all */
        lm_asset_set_drop(&s->cache, &a->hash);
    return st;
}

lm_status wk_serve_assign(wk_server *s, const lm_msg *m)
{
    const Lumesh__Assign *a = m->assign;
    drop_views(s);
    slow_load(s);
    lm_status st = LM_OK;
    if (!s->original || a->job != s->job)
        st = lm_fail(LM_E_INVALID, "views of job %llu assigned, but the job is %llu",
                     (unsigned long long)a->job, (unsigned long long)s->job);
    lm_view_deal deal = {a->first, a->count, a->stride ? a->stride : 1};
    if (st == LM_OK && !lm_view_deal_fits(deal, s->views->count))
        st = lm_fail(LM_E_RANGE, "%u views from view %u, %u apart, assigned of %u", a->count,
                     a->first, deal.stride, s->views->count);
    if (st == LM_OK && a->targets.len)
        st = create_given(s, deal, &a->targets);
    else if (st == LM_OK)
        st = wk_views_local_create_dealt(s->original, s->views, deal, s->o.device, &s->v);
    if (st != LM_OK)
        return wk_serve_fail(s, m->req, st, lm_last_error());
    s->deal = deal;
    s->n_materials = s->original->n_materials;
    Lumesh__Assigned r = LUMESH__ASSIGNED__INIT;
    r.job = s->job;
    r.first = deal.first;
    r.count = deal.count;
    r.stride = deal.stride;
    return wk_serve_send(s, m->req, LUMESH__MSG__BODY_ASSIGNED, &r);
}

/* ---- changes of state ------------------------------------------------------------------------ */

static lm_status set_materials(wk_server *s, const Lumesh__SetMaterials *b)
{
    const lm_asset *a = NULL;
    lm_mesh *mats = NULL;
    lm_status st = cached(s, &b->materials, &a);
    if (st == LM_OK)
        st = lm_asset_unpack_materials(a->data, a->size, &s->cache, &mats);
    if (st == LM_OK)
        st = s->v->ops->set_materials(s->v, mats->materials, mats->n_materials);
    if (st == LM_OK)
        s->n_materials = mats->n_materials;
    lm_mesh_destroy(mats);
    return st;
}

static lm_status set_mesh(wk_server *s, const Lumesh__SetMesh *b)
{
    if (b->n_tris > LM_MESH_MAX_TRIS)
        return lm_fail(LM_E_RANGE, "a mesh of %zu triangles", b->n_tris);
    lm_tri_data *tris = malloc((b->n_tris + 1) * sizeof *tris);
    if (!tris)
        return lm_fail(LM_E_NOMEM, "out of memory for a mesh of %zu triangles", b->n_tris);
    lm_status st = LM_OK;
    for (size_t i = 0; i < b->n_tris && st == LM_OK; i++)
        st = lm_wire_tri_decode(b->tris[i], s->n_materials, &tris[i]);
    s->mesh_set = 0;
    if (st == LM_OK)
        st = s->v->ops->set_mesh(s->v, tris, b->n_tris);
    if (st == LM_OK && s->geo)
        st = lm_surface_table_set_mesh(s->geo, tris, b->n_tris);
    if (st == LM_OK)
        st = lm_replica_set(&s->rep, tris, b->n_tris);
    s->mesh_set = st == LM_OK;
    free(tris);
    return st;
}

/* The geometric term of this worker's share (proto/lumesh.proto, SetSurface): a new scale for
 * the table there is, or a table made empty, to be filled by the mesh that follows (*stale: until
 * then the replica is stale). */
static lm_status set_surface(wk_server *s, const Lumesh__SetSurface *b, int *stale)
{
    if (!(b->k > 0) || !isfinite(b->k))
        return lm_fail(LM_E_FORMAT, "a geometric term of scale %g", b->k);
    if (b->views_first > s->deal.first || s->deal.first - b->views_first >= s->deal.stride)
        return lm_fail(LM_E_RANGE,
                       "a geometric term for views from %u, served from view %u, %u "
                       "apart",
                       b->views_first, s->deal.first, s->deal.stride);
    if (s->geo) {
        lm_surface_table_set_k(s->geo, b->k);
        return LM_OK;
    }
    lm_status st = LM_OK;
    if (!s->bvh) {
        st = lm_bvh_create(s->original, &s->bvh);
        s->bvh_of = s->original_hash;
    }
    if (st == LM_OK)
        st = lm_surface_table_create(s->bvh, b->k, s->deal.first - b->views_first, s->deal.stride,
                                     &s->geo);
    *stale = st == LM_OK && s->mesh_set; /* the table lacks the mesh until it is set again */
    return st;
}

static lm_status reserve_patches(wk_server *s, size_t n)
{
    if (n <= s->cap_patches)
        return LM_OK;
    if (n > LM_WIRE_MAX_PATCHES)
        return lm_fail(LM_E_RANGE, "%zu patches in one request (limit %u)", n, LM_WIRE_MAX_PATCHES);
    lm_patch *p = realloc(s->patches, n * sizeof *p);
    int64_t *d = realloc(s->deltas, n * sizeof *d);
    if (p)
        s->patches = p;
    if (d)
        s->deltas = d;
    if (!p || !d)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu patches", n);
    for (size_t i = s->cap_patches; i < n; i++)
        lm_patch_init(&s->patches[i]);
    s->cap_patches = (uint32_t)n;
    return LM_OK;
}

static lm_status commit(wk_server *s, const lm_msg *m)
{
    if (s->stale || s->seq + 1 != m->seq)
        return LM_E_UNSUPPORTED; /* missed a change: stale until the state is sent again */
    if (!m->commit->patch)
        return lm_fail(LM_E_FORMAT, "a commit without a patch");
    lm_status st = reserve_patches(s, 1);
    if (st == LM_OK)
        st = lm_wire_patch_decode_against(m->commit->patch, s->n_materials, lm_replica_current,
                                          &s->rep, &s->patches[0]);
    if (st == LM_OK)
        st = s->v->ops->commit(s->v, &s->patches[0]);
    if (st == LM_OK && s->geo)
        st = lm_surface_table_commit(s->geo, &s->patches[0]);
    if (st == LM_OK)
        st = lm_replica_apply(&s->rep, &s->patches[0]);
    return st;
}

/* A change's result is the coordinator's sequence number; a failed one leaves no state (every
 * later request is answered Stale until the state is sent again) and is reported. */
lm_status wk_serve_change(wk_server *s, const lm_msg *m)
{
    lm_status st;
    int stale = 0;
    if (!s->v)
        return wk_serve_fail(s, m->req, LM_E_INVALID,
                             "a change of state before views were assigned");
    switch (m->body_case) {
    case LUMESH__MSG__BODY_SET_MATERIALS:
        st = set_materials(s, m->set_materials);
        break;
    case LUMESH__MSG__BODY_SET_MESH:
        st = set_mesh(s, m->set_mesh);
        break;
    case LUMESH__MSG__BODY_SET_SURFACE:
        st = set_surface(s, m->set_surface, &stale);
        break;
    default:
        st = commit(s, m);
        if (st == LM_E_UNSUPPORTED) {
            s->stale = 1;
            return LM_OK;
        }
    }
    if (st == LM_OK) {
        s->seq = m->seq;
        s->stale = stale;
        return LM_OK;
    }
    s->stale = 1;
    return wk_serve_fail(s, m->req, st, lm_last_error());
}

/* ---- requests -------------------------------------------------------------------------------- */

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Fault injection for tests (LUMESH_WORKER_FAULT, read only by builds with LUMESH_TEST_HOOKS):
 * "crash-on-tris=N" aborts the process, and "fail-on-tris=N" answers a Failure, on any batch with a
 * patch adding more than N triangles — a poison batch, the same on every worker and every retry. */
static int faulty(const wk_server *s, const Lumesh__Evaluate *e, const char *kind)
{
    size_t n = strlen(kind);
    if (!s->fault || strncmp(s->fault, kind, n) || s->fault[n] != '=')
        return 0;
    size_t limit = (size_t)strtoul(s->fault + n + 1, NULL, 10);
    for (size_t i = 0; i < e->n_patches; i++)
        if (e->patches[i]->n_added > limit)
            return 1;
    return 0;
}

static lm_status evaluate(wk_server *s, const lm_msg *m)
{
    const Lumesh__Evaluate *e = m->evaluate;
    if (e->surface && !s->geo) { /* the term asked of a replica that lacks it: send the state */
        Lumesh__Stale r = LUMESH__STALE__INIT;
        return wk_serve_send(s, m->req, LUMESH__MSG__BODY_STALE, &r);
    }
    if (s->fault && faulty(s, e, "crash-on-tris"))
        abort();
    if (s->fault && faulty(s, e, "fail-on-tris"))
        return wk_serve_fail(s, m->req, LM_E_INTERNAL, "injected failure (LUMESH_WORKER_FAULT)");
    double t0 = cpu_now();
    lm_status st = reserve_patches(s, e->n_patches);
    for (size_t i = 0; i < e->n_patches && st == LM_OK; i++)
        st = lm_wire_patch_decode_against(e->patches[i], s->n_materials, lm_replica_current,
                                          &s->rep, &s->patches[i]);
    if (st == LM_OK && e->n_patches)
        st = s->v->ops->evaluate(s->v, s->patches, (uint32_t)e->n_patches, s->deltas);
    for (size_t i = 0; i < e->n_patches && st == LM_OK && e->surface; i++)
        s->deltas[i] += lm_surface_table_delta(s->geo, &s->patches[i]);
    if (st != LM_OK)
        return wk_serve_fail(s, m->req, st, lm_last_error());
    Lumesh__Deltas d = LUMESH__DELTAS__INIT;
    d.n_delta = e->n_patches;
    d.delta = s->deltas;
    d.busy_us = (uint64_t)((cpu_now() - t0) * 1e6);
    return wk_serve_send(s, m->req, LUMESH__MSG__BODY_DELTAS, &d);
}

static lm_status energy(wk_server *s, const lm_msg *m)
{
    int64_t per[LM_MAX_VIEWS];
    lm_status st = s->v->ops->energy(s->v, NULL, per);
    if (st != LM_OK)
        return wk_serve_fail(s, m->req, st, lm_last_error());
    Lumesh__EnergyResult r = LUMESH__ENERGY_RESULT__INIT;
    r.n_per_view = s->deal.count;
    r.per_view = per;
    return wk_serve_send(s, m->req, LUMESH__MSG__BODY_ENERGY_RESULT, &r);
}

static lm_status potentials(wk_server *s, const lm_msg *m)
{
    const Lumesh__Potentials *p = m->potentials;
    size_t n = p->n_points / 3;
    lm_status st =
        p->n_points % 3 ? lm_fail(LM_E_FORMAT, "%zu point coordinates", p->n_points) : LM_OK;
    int64_t *out = st == LM_OK ? malloc((n + 1) * sizeof *out) : NULL;
    if (st == LM_OK && !out)
        st = lm_fail(LM_E_NOMEM, "out of memory for %zu potentials", n);
    if (st == LM_OK)
        st = s->v->ops->potentials(s->v, (const float(*)[3])(void *)p->points, n, out);
    if (st == LM_OK) {
        Lumesh__PotentialsResult r = LUMESH__POTENTIALS_RESULT__INIT;
        r.n_sums = n;
        r.sums = out;
        st = wk_serve_send(s, m->req, LUMESH__MSG__BODY_POTENTIALS_RESULT, &r);
    } else {
        st = wk_serve_fail(s, m->req, st, lm_last_error());
    }
    free(out);
    return st;
}

/* Fault injection for tests (LUMESH_WORKER_FAULT, read only by builds with LUMESH_TEST_HOOKS):
 * "fail-targets" answers a Failure to every read of a target image (the coordinator's split render
 * of the targets must fall back to every worker rendering them); "lie-targets=W" makes the worker
 * welcomed as W send every target image it is asked for with its first pixel changed (a worker
 * gone wrong: the coordinator's spot check must catch it before any other worker uses them). */
static void maybe_lie_target(const wk_server *s, const Lumesh__ReadImage *q, uint8_t *px)
{
    static const char kind[] = "lie-targets=";
    if (s->fault && !strncmp(s->fault, kind, sizeof kind - 1) &&
        strtoul(s->fault + sizeof kind - 1, NULL, 10) == s->worker_id &&
        q->kind == LM_IMAGE_TARGET_LUMA)
        px[0] ^= 0x5a;
}

static lm_status read_image(wk_server *s, const lm_msg *m)
{
    const Lumesh__ReadImage *q = m->read_image;
    if (s->fault && !strcmp(s->fault, "fail-targets") && q->kind == LM_IMAGE_TARGET_LUMA)
        return wk_serve_fail(s, m->req, LM_E_INTERNAL, "injected failure (LUMESH_WORKER_FAULT)");
    lm_views_info info;
    s->v->ops->info(s->v, &info);
    lm_status st = LM_OK;
    uint32_t place = 0;
    if (q->kind > LM_IMAGE_COVERAGE || !lm_view_deal_place(s->deal, q->view, &place))
        st = lm_fail(LM_E_RANGE, "image %u of view %u asked of %u views from view %u, %u apart",
                     q->kind, q->view, s->deal.count, s->deal.first, s->deal.stride);
    size_t bytes = (size_t)info.width * info.height * lm_image_kind_bpp((lm_image_kind)q->kind);
    uint8_t *px = st == LM_OK ? malloc(bytes) : NULL;
    if (st == LM_OK && !px)
        st = lm_fail(LM_E_NOMEM, "out of memory for an image");
    if (st == LM_OK)
        st = s->v->ops->read_image(s->v, (lm_image_kind)q->kind, place, px);
    if (st == LM_OK && s->fault)
        maybe_lie_target(s, q, px);
    if (st == LM_OK) {
        Lumesh__Image r = LUMESH__IMAGE__INIT;
        r.pixels = (ProtobufCBinaryData){bytes, px};
        st = wk_serve_send(s, m->req, LUMESH__MSG__BODY_IMAGE, &r);
    } else {
        st = wk_serve_fail(s, m->req, st, lm_last_error());
    }
    free(px);
    return st;
}

lm_status wk_serve_request(wk_server *s, const lm_msg *m)
{
    if (!s->v || s->stale || m->seq != s->seq) {
        Lumesh__Stale r = LUMESH__STALE__INIT;
        return wk_serve_send(s, m->req, LUMESH__MSG__BODY_STALE, &r);
    }
    switch (m->body_case) {
    case LUMESH__MSG__BODY_EVALUATE:
        return evaluate(s, m);
    case LUMESH__MSG__BODY_ENERGY:
        return energy(s, m);
    case LUMESH__MSG__BODY_POTENTIALS:
        return potentials(s, m);
    default:
        return read_image(s, m);
    }
}
