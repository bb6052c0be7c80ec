/* coordinator/views/views_remote_layout.c — which worker serves which views, bringing workers
 * into the job (assets they lack, the job, their views, the current state), and waiting for
 * replies. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "coordinator/views/lane_audit.h"
#include "coordinator/views/views_remote_internal.h"

lm_status co_remote_pack(co_remote *r, uint64_t req, uint64_t seq, Lumesh__Msg__BodyCase c,
                         void *body, size_t *size)
{
    lm_msg m;
    lm_wire_msg_init(&m, req, seq, c, body);
    size_t n = lumesh__msg__get_packed_size(&m);
    if (n > LM_WIRE_MAX_FRAME)
        return lm_fail(LM_E_RANGE, "a %s message of %zu bytes exceeds the frame limit of %u",
                       lm_wire_body_name(&m), n, LM_WIRE_MAX_FRAME);
    if (n > r->cap_pack) {
        uint8_t *p = realloc(r->pack, n);
        if (!p)
            return lm_fail(LM_E_NOMEM, "out of memory for a %zu-byte message", n);
        r->pack = p;
        r->cap_pack = n;
    }
    lumesh__msg__pack(&m, r->pack);
    *size = n;
    return LM_OK;
}

lm_status co_remote_await(co_remote *r, co_worker **ws, uint32_t n)
{
    double t0 = co_pool_now();
    for (;;) {
        uint32_t waiting = 0;
        for (uint32_t i = 0; i < n; i++)
            waiting += ws[i] && !ws[i]->lost && ws[i]->want && !ws[i]->replied;
        if (!waiting)
            return LM_OK;
        /* a signal ends the run at the optimizer's next step; a wait that outlasts that is
         * given up (workers that never answer must not make SIGINT/SIGTERM useless) */
        if (co_pool_interrupted() && co_pool_now() - t0 > CO_REMOTE_INTERRUPT_GRACE_S)
            return lm_fail(LM_E_INVALID, "interrupted while waiting for workers");
        lm_status st = co_pool_pump(r->pool, 200);
        if (st != LM_OK)
            return st;
    }
}

lm_status co_remote_check_reply(co_remote *r, co_worker *w, Lumesh__Msg__BodyCase want, int *stale)
{
    (void)r;
    *stale = 0;
    const lm_msg *m = w->reply.msg;
    if (m->body_case == want)
        return LM_OK;
    if (m->body_case == LUMESH__MSG__BODY_STALE) {
        *stale = 1;
        return LM_OK;
    }
    if (m->body_case == LUMESH__MSG__BODY_FAILURE)
        return lm_fail((lm_status)(m->failure->code && m->failure->code < LM_E_COUNT_
                                       ? m->failure->code
                                       : LM_E_INTERNAL),
                       "worker %u (%s): %s", w->id, w->host,
                       m->failure->message ? m->failure->message : "failed");
    return lm_fail(LM_E_INTERNAL, "worker %u (%s) answered %s where %s was due", w->id, w->host,
                   lm_wire_body_name(m), lm_wire_case_name(want));
}

/* ---- one step of bringing workers up, on all of them at once --------------------------------- */

typedef lm_status (*step_fn)(co_remote *r, co_worker *w, uint64_t req);

/* Send a request to each worker (step), wait for all, and check each reply is `want` (a worker
 * lost meanwhile is left out: the layout will change). */
static lm_status step_all(co_remote *r, co_worker **ws, uint32_t n, step_fn step,
                          Lumesh__Msg__BodyCase want)
{
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < n && st == LM_OK; i++)
        if (!ws[i]->lost) {
            co_pool_arm_load(ws[i], co_pool_next_req(r->pool)); /* the set-up's limits */
            st = step(r, ws[i], ws[i]->want);
        }
    if (st == LM_OK)
        st = co_remote_await(r, ws, n);
    for (uint32_t i = 0; i < n && st == LM_OK; i++) {
        int stale;
        if (!ws[i]->lost && ws[i]->replied)
            st = co_remote_check_reply(r, ws[i], want, &stale);
    }
    return st;
}

static lm_status offer(co_remote *r, co_worker *w, uint64_t req)
{
    ProtobufCBinaryData *h = lm_wire_arena_alloc(&r->arena, (r->assets.n + 1) * sizeof *h);
    if (!h)
        return lm_fail(LM_E_NOMEM, "out of memory offering assets");
    for (uint32_t i = 0; i < r->assets.n; i++)
        h[i] = (ProtobufCBinaryData){LM_ASSET_HASH_BYTES, r->assets.items[i].hash.b};
    Lumesh__Offer o = LUMESH__OFFER__INIT;
    o.n_assets = r->assets.n;
    o.assets = h;
    lm_status st = co_pool_send(r->pool, w, req, r->seq, LUMESH__MSG__BODY_OFFER, &o);
    lm_wire_arena_reset(&r->arena);
    return st;
}

static lm_status send_asset(co_remote *r, co_worker *w, const lm_asset *a, uint64_t req)
{
    lm_status st = LM_OK;
    for (size_t off = 0; off < a->size && st == LM_OK; off += LM_WIRE_CHUNK) {
        size_t len = a->size - off < LM_WIRE_CHUNK ? a->size - off : LM_WIRE_CHUNK;
        Lumesh__Asset m = LUMESH__ASSET__INIT;
        m.hash = (ProtobufCBinaryData){LM_ASSET_HASH_BYTES, (uint8_t *)a->hash.b};
        m.size = a->size;
        m.offset = off;
        m.data = (ProtobufCBinaryData){len, a->data + off};
        st = co_pool_send(r->pool, w, req, r->seq, LUMESH__MSG__BODY_ASSET, &m);
    }
    return st;
}

/* A Need answered with the assets; the slot is re-armed for the Ready that follows. */
static lm_status send_needed(co_remote *r, co_worker *w)
{
    const Lumesh__Need *need = w->reply.msg->need;
    uint64_t req = w->want;
    lm_status st = LM_OK;
    for (size_t i = 0; i < need->n_assets && st == LM_OK; i++) {
        lm_asset_hash h;
        if (need->assets[i].len != LM_ASSET_HASH_BYTES)
            return lm_fail(LM_E_FORMAT, "worker %u asked for a malformed asset hash", w->id);
        memcpy(h.b, need->assets[i].data, sizeof h.b);
        const lm_asset *a = lm_asset_set_find(&r->assets, &h);
        if (!a)
            return lm_fail(LM_E_INVALID, "worker %u asked for an asset that was not offered",
                           w->id);
        st = send_asset(r, w, a, req);
    }
    co_pool_arm_load(w, req);
    return st;
}

lm_status co_remote_ship(co_remote *r, co_worker **ws, uint32_t n)
{
    lm_status st = LM_OK;
    for (uint32_t i = 0; i < n && st == LM_OK; i++)
        if (!ws[i]->lost) {
            co_pool_arm_load(ws[i], co_pool_next_req(r->pool));
            st = offer(r, ws[i], ws[i]->want);
        }
    for (int round = 0; round < 2 && st == LM_OK; round++) {
        st = co_remote_await(r, ws, n);
        for (uint32_t i = 0; i < n && st == LM_OK; i++) {
            co_worker *w = ws[i];
            if (w->lost || !w->replied)
                continue;
            if (w->reply.msg->body_case == LUMESH__MSG__BODY_NEED && round == 0)
                st = send_needed(r, w);
            else if (w->reply.msg->body_case != LUMESH__MSG__BODY_READY) {
                int stale;
                st = co_remote_check_reply(r, w, LUMESH__MSG__BODY_READY, &stale);
                if (st == LM_OK)
                    st = lm_fail(LM_E_INTERNAL, "worker %u did not take the job's assets", w->id);
            }
        }
    }
    return st;
}

static lm_status send_job(co_remote *r, co_worker *w, uint64_t req)
{
    Lumesh__View *views = lm_wire_arena_alloc(&r->arena, r->views->count * sizeof *views);
    Lumesh__View **ptrs = lm_wire_arena_alloc(&r->arena, r->views->count * sizeof *ptrs);
    lm_status st = views && ptrs ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory sending the job");
    for (uint32_t i = 0; i < r->views->count && st == LM_OK; i++) {
        st = lm_wire_view_encode(&r->views->views[i], &r->arena, &views[i]);
        ptrs[i] = &views[i];
    }
    Lumesh__Job j = LUMESH__JOB__INIT;
    j.job = r->job;
    j.original = (ProtobufCBinaryData){LM_ASSET_HASH_BYTES, r->original.b};
    j.width = (uint32_t)r->width;
    j.height = (uint32_t)r->height;
    j.n_views = r->views->count;
    j.views = ptrs;
    if (st == LM_OK)
        st = co_pool_send(r->pool, w, req, r->seq, LUMESH__MSG__BODY_JOB, &j);
    lm_wire_arena_reset(&r->arena);
    return st;
}

static lm_status send_assign(co_remote *r, co_worker *w, uint64_t req)
{
    Lumesh__Assign a = LUMESH__ASSIGN__INIT;
    a.job = r->job;
    a.first = w->first;
    a.count = w->count;
    a.stride = w->stride;
    if (r->has_targets && w->first == r->first && w->count == r->count && w->stride <= 1)
        a.targets = (ProtobufCBinaryData){LM_ASSET_HASH_BYTES, r->targets.b};
    return co_pool_send(r->pool, w, req, r->seq, LUMESH__MSG__BODY_ASSIGN, &a);
}

/* ---- the targets rendered split (whole views, several workers to bring up) ------------------- */

/* Target j of w's share (w->first + j * w->stride) asked of w: state 0, that of its Assign. */
static lm_status ask_target(co_remote *r, co_worker *w, uint32_t j)
{
    Lumesh__ReadImage q = LUMESH__READ_IMAGE__INIT;
    q.kind = LM_IMAGE_TARGET_LUMA;
    q.view = w->first + j * w->stride;
    return co_pool_send(r->pool, w, co_pool_arm(r->pool, w), 0, LUMESH__MSG__BODY_READ_IMAGE, &q);
}

/* Every worker of ws (k) asked for its shares' targets, round after round, into y (the whole
 * view set's, view after view). A worker lost: LM_E_IO. */
static lm_status read_targets(co_remote *r, co_worker **ws, uint32_t k, uint8_t *y, size_t plane)
{
    lm_status st = LM_OK;
    for (uint32_t j = 0; j < ws[0]->count && st == LM_OK; j++) { /* ws[0] has the most */
        for (uint32_t i = 0; i < k && st == LM_OK; i++)
            if (j < ws[i]->count)
                st = ask_target(r, ws[i], j);
        if (st == LM_OK)
            st = co_remote_await(r, ws, k);
        for (uint32_t i = 0; i < k && st == LM_OK; i++) {
            co_worker *w = ws[i];
            int stale = 0;
            if (w->lost)
                return lm_fail(LM_E_IO, "worker %u was lost rendering targets", w->id);
            if (j >= w->count)
                continue;
            st = co_remote_check_reply(r, w, LUMESH__MSG__BODY_IMAGE, &stale);
            const Lumesh__Image *im = w->reply.msg->image;
            if (st == LM_OK && (stale || im->pixels.len != plane))
                st = lm_fail(LM_E_INVALID, "worker %u sent no target image of view %u", w->id,
                             w->first + j * w->stride);
            if (st == LM_OK)
                memcpy(y + (size_t)(w->first + j * w->stride) * plane, im->pixels.data, plane);
            co_pool_disarm(w);
        }
    }
    return st;
}

/* The split's spot check, with the lanes' audits on (lane_audit.h): worker (i + 1) % k renders
 * again one view of ws[i]'s share (which one turns with the job's number) and the two images must
 * be the same bytes, as a renderer's targets are whoever draws them. A mismatch fails the split
 * (split_targets: every worker then renders its own targets, and the lanes' audits find a worker
 * gone wrong as before), so one worker's wrong targets never reach every worker. */
static lm_status check_targets(co_remote *r, co_worker **ws, uint32_t k, const uint8_t *y,
                               size_t plane)
{
    if (k < 2 || co_audit_off(r->audit))
        return LM_OK;
    uint32_t *v = malloc(k * sizeof *v);
    uint8_t *again = malloc(r->count * plane);
    lm_status st = v && again ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory checking targets");
    for (uint32_t i = 0; i < k && st == LM_OK; i++) /* ws[i]'s view, before the deals change */
        v[i] = ws[i]->first + (uint32_t)(r->job % ws[i]->count) * ws[i]->stride;
    for (uint32_t i = 0; i < k && st == LM_OK; i++) {
        co_worker *c = ws[(i + 1) % k]; /* checks v[i] */
        c->first = v[i];
        c->count = 1;
        c->stride = 1;
    }
    if (st == LM_OK)
        st = step_all(r, ws, k, send_assign, LUMESH__MSG__BODY_ASSIGNED);
    for (uint32_t i = 0; i < k && st == LM_OK; i++)
        if (ws[i]->lost)
            st = lm_fail(LM_E_IO, "worker %u was lost checking targets", ws[i]->id);
    if (st == LM_OK)
        st = read_targets(r, ws, k, again, plane);
    for (uint32_t i = 0; i < k && st == LM_OK; i++)
        if (memcmp(again + (size_t)v[i] * plane, y + (size_t)v[i] * plane, plane))
            st = lm_fail(LM_E_INVALID, "workers %u and %u rendered different targets of view %u",
                         ws[i]->id, ws[(i + 1) % k]->id, v[i]);
    free(again);
    free(v);
    return st;
}

/* The split's steps (a)-(b): ws[i] (i < k) renders views i, i + k, ...; their targets are read
 * back, spot-checked (check_targets) and packed into r->targets, among r->assets (bring_up ships
 * it). */
static lm_status render_split(co_remote *r, co_worker **ws, uint32_t k)
{
    size_t plane = (size_t)r->width * (size_t)r->height;
    for (uint32_t i = 0; i < k; i++) {
        ws[i]->first = i;
        ws[i]->count = r->count / k + (i < r->count % k);
        ws[i]->stride = k;
    }
    lm_status st = step_all(r, ws, k, send_assign, LUMESH__MSG__BODY_ASSIGNED);
    for (uint32_t i = 0; i < k && st == LM_OK; i++)
        if (ws[i]->lost)
            st = lm_fail(LM_E_IO, "worker %u was lost rendering targets", ws[i]->id);
    uint8_t *y = st == LM_OK ? malloc(r->count * plane) : NULL;
    if (st == LM_OK && !y)
        st = lm_fail(LM_E_NOMEM, "out of memory for %u target images", r->count);
    if (st == LM_OK)
        st = read_targets(r, ws, k, y, plane);
    if (st == LM_OK)
        st = check_targets(r, ws, k, y, plane);
    if (st == LM_OK)
        st = lm_asset_pack_targets((uint32_t)r->width, (uint32_t)r->height, r->count, y, &r->assets,
                                   &r->targets);
    free(y);
    return st;
}

/* Whole views brought up on n >= 2 workers (ws): their targets rendered once, split over them,
 * so that the Assign that follows names them (r->has_targets) and no worker renders all. Any
 * loss or failure: a warning, and every worker renders its targets itself, as before (the deals
 * of ws are restored either way). Interruption is not hidden. */
static lm_status split_targets(co_remote *r, co_worker **ws, uint32_t n)
{
    if (!r->whole || r->has_targets || n < 2 || r->first != 0 || r->count != r->views->count)
        return LM_OK;
    double t0 = co_pool_now();
    uint32_t k = n < r->count ? n : r->count;
    lm_status st = render_split(r, ws, k);
    for (uint32_t i = 0; i < n; i++) {
        co_pool_disarm(ws[i]);
        ws[i]->first = r->first;
        ws[i]->count = r->count;
        ws[i]->stride = 1;
    }
    if (st == LM_OK) {
        r->has_targets = 1;
        lm_info("targets: %u views rendered split over %u workers (at most %u each) in %.2f s",
                r->count, k, (r->count + k - 1) / k, co_pool_now() - t0);
        return LM_OK;
    }
    if (co_pool_interrupted())
        return st;
    lm_warn("rendering the targets split failed (%s): every worker renders them", lm_last_error());
    return LM_OK;
}

void co_remote_surface_msg(const co_remote *r, Lumesh__SetSurface *out)
{
    Lumesh__SetSurface m = LUMESH__SET_SURFACE__INIT;
    m.k = r->surface_k;
    m.views_first = r->first;
    *out = m;
}

lm_status co_remote_mesh_msg(co_remote *r, Lumesh__SetMesh *out, lm_tri_data **tris)
{
    *tris = malloc((r->rep.n_alive + 1) * sizeof **tris);
    if (!*tris)
        return lm_fail(LM_E_NOMEM, "out of memory re-sending the mesh");
    size_t n = 0;
    for (size_t id = 0; id < r->rep.cap; id++)
        if (r->rep.alive[id])
            (*tris)[n++] = r->rep.tris[id];
    Lumesh__SetMesh sm = LUMESH__SET_MESH__INIT;
    sm.n_tris = n;
    lm_status st = lm_wire_tris_encode(*tris, n, &r->arena, &sm.tris);
    *out = sm;
    return st;
}

lm_status co_remote_send_state(co_remote *r, co_worker *w)
{
    lm_status st = LM_OK;
    if (r->has_materials) {
        Lumesh__SetMaterials m = LUMESH__SET_MATERIALS__INIT;
        m.materials = (ProtobufCBinaryData){LM_ASSET_HASH_BYTES, r->materials.b};
        st = co_pool_send(r->pool, w, 0, r->seq, LUMESH__MSG__BODY_SET_MATERIALS, &m);
    }
    if (st == LM_OK && r->surface_k > 0) {
        Lumesh__SetSurface g;
        co_remote_surface_msg(r, &g);
        st = co_pool_send(r->pool, w, 0, r->seq, LUMESH__MSG__BODY_SET_SURFACE, &g);
    }
    if (st != LM_OK || !r->mesh_set)
        return st;
    lm_tri_data *tris = NULL;
    Lumesh__SetMesh sm;
    st = co_remote_mesh_msg(r, &sm, &tris);
    if (st == LM_OK)
        st = co_pool_send(r->pool, w, 0, r->seq, LUMESH__MSG__BODY_SET_MESH, &sm);
    lm_wire_arena_reset(&r->arena);
    free(tris);
    return st;
}

/* ---- the layout ------------------------------------------------------------------------------ */

int co_remote_layout_stale(co_remote *r)
{
    for (uint32_t i = 0; i < r->n_live; i++)
        if (r->live[i]->lost)
            return 1;
    return co_pool_alive(r->pool) != r->n_live;
}

/* Every alive worker, in the order they joined. */
static lm_status gather_live(co_remote *r)
{
    uint32_t n = co_pool_size(r->pool);
    if (n > r->cap_live) {
        co_worker **l = realloc(r->live, n * sizeof *l);
        uint32_t *g = realloc(r->group, n * sizeof *g);
        if (l)
            r->live = l;
        if (g)
            r->group = g;
        if (!l || !g)
            return lm_fail(LM_E_NOMEM, "out of memory for the layout");
        r->cap_live = n;
    }
    r->n_live = 0;
    for (uint32_t i = 0; i < n; i++) {
        co_worker *w = co_pool_worker(r->pool, i);
        if (!w->lost)
            r->live[r->n_live++] = w;
    }
    return LM_OK;
}

/* G shares of near-equal size (the first ones a view longer), the views dealt out: share k holds
 * every G-th view from the k-th, so each sees the model from all sides and a patch's work splits
 * evenly (contiguous shares would each look from one side). Worker i serves share i mod G. */
static void plan(co_remote *r)
{
    uint32_t g = r->whole ? 1 : r->n_live < r->count ? r->n_live : r->count;
    r->n_ranges = g;
    for (uint32_t k = 0; k < g; k++)
        r->ranges[k] = (co_range){r->first + k, r->count / g + (k < r->count % g), g};
    for (uint32_t i = 0; i < r->n_live; i++)
        r->group[i] = i % g;
}

/* Workers new to the job get the assets and the job; workers whose views change get them. */
static lm_status bring_up(co_remote *r)
{
    co_worker **fresh = malloc((r->n_live + 1) * sizeof *fresh);
    co_worker **moved = malloc((r->n_live + 1) * sizeof *moved);
    uint32_t nf = 0, nm = 0;
    lm_status st = fresh && moved ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for the layout");
    for (uint32_t i = 0; i < r->n_live && st == LM_OK; i++) {
        co_worker *w = r->live[i];
        const co_range *g = &r->ranges[r->group[i]];
        int in_job = w->job == r->job;
        if (!in_job)
            fresh[nf++] = w;
        if (!in_job || w->first != g->first || w->count != g->count || w->stride != g->stride) {
            w->first = g->first;
            w->count = g->count;
            w->stride = g->stride;
            moved[nm++] = w;
        }
    }
    if (st == LM_OK && nf)
        st = co_remote_ship(r, fresh, nf);
    if (st == LM_OK && nf)
        st = step_all(r, fresh, nf, send_job, LUMESH__MSG__BODY_READY);
    for (uint32_t i = 0; i < nf && st == LM_OK; i++)
        fresh[i]->job = fresh[i]->lost ? 0 : r->job;
    if (st == LM_OK && nm)
        st = split_targets(r, moved, nm);
    if (st == LM_OK && nm && r->has_targets) /* a worker drops the targets once it used them */
        st = co_remote_ship(r, moved, nm);
    if (st == LM_OK && nm)
        st = step_all(r, moved, nm, send_assign, LUMESH__MSG__BODY_ASSIGNED);
    for (uint32_t i = 0; i < nm && st == LM_OK; i++) {
        co_pool_disarm(moved[i]);
        st = co_remote_send_state(r, moved[i]);
    }
    free(fresh);
    free(moved);
    return st;
}

/* The renderer's description, from the first worker of the layout. */
static void take_renderer(co_remote *r)
{
    if (r->n_live && !r->renderer[0])
        snprintf(r->renderer, sizeof r->renderer, "%.100s [%.16s]", r->live[0]->renderer,
                 r->live[0]->renderer_id);
}

lm_status co_remote_layout(co_remote *r)
{
    for (int tries = 0; tries < 64; tries++) {
        lm_status st = co_pool_pump(r->pool, 0);
        if (st == LM_OK && co_pool_alive(r->pool) == 0)
            st = co_pool_wait(r->pool, 1, 0);
        if (st != LM_OK)
            return st;
        if (r->n_live && !co_remote_layout_stale(r))
            return LM_OK;
        if ((st = gather_live(r)) != LM_OK)
            return st;
        plan(r);
        take_renderer(r);
        if ((st = bring_up(r)) != LM_OK)
            return st;
        if (!co_remote_layout_stale(r))
            return LM_OK;
    }
    return lm_fail(LM_E_IO, "workers keep coming and going: no stable set to serve the views");
}

void co_remote_layout_free(co_remote *r)
{
    for (uint32_t i = 0; i < r->n_live; i++)
        if (r->live[i]->job == r->job)
            r->live[i]->job = 0;
    free(r->live);
    free(r->group);
    r->live = NULL;
    r->group = NULL;
    r->n_live = r->cap_live = 0;
}
