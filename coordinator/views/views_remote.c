/* coordinator/views/views_remote.c — the lm_views ops over lumesh-worker processes: changes of
 * state sent to every worker (packed once) with their sequence numbers and kept for resending;
 * requests fanned out over the layout (a batch divided between the replicas of a range), partial
 * int64 results summed; an operation redone when a worker was lost or stale meanwhile. */
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "coordinator/views/views_remote_internal.h"

static co_remote *as_remote(lm_views *v)
{
    return (co_remote *)v;
}

/* ---- changes of state ------------------------------------------------------------------------ */

/* The packed change to every worker of the layout (no reply: a worker that fails it answers the
 * next request Stale and is sent the state again). */
static lm_status broadcast(co_remote *r, Lumesh__Msg__BodyCase c, void *body)
{
    size_t n;
    lm_status st = co_remote_pack(r, 0, r->seq, c, body, &n);
    for (uint32_t i = 0; i < r->n_live && st == LM_OK; i++)
        st = co_pool_send_packed(r->pool, r->live[i], r->pack, n);
    lm_wire_arena_reset(&r->arena);
    return st;
}

static lm_status rm_set_mesh(lm_views *v, const lm_tri_data *tris, size_t n)
{
    co_remote *r = as_remote(v);
    r->mesh_set = 0;
    lm_status st = lm_replica_set(&r->rep, tris, n);
    if (st == LM_OK)
        st = co_remote_layout(r);
    if (st != LM_OK)
        return st;
    r->mesh_set = 1;
    r->seq++;
    Lumesh__SetMesh m = LUMESH__SET_MESH__INIT;
    m.n_tris = n;
    st = lm_wire_tris_encode(tris, n, &r->arena, &m.tris);
    return st == LM_OK ? broadcast(r, LUMESH__MSG__BODY_SET_MESH, &m) : st;
}

/* The geometric term on the workers (views_api.h, surface_term): each group of views prices the
 * triangle ids of its share; the first time, the mesh goes again with it (the workers keep e(t)
 * per triangle from it). */
static lm_status rm_surface_term(lm_views *v, const lm_mesh *surface, double k)
{
    co_remote *r = as_remote(v);
    if (surface != r->original_mesh)
        return lm_fail(LM_E_UNSUPPORTED, "the workers hold another original than this surface");
    if (!(k > 0 && k <= DBL_MAX))
        return lm_fail(LM_E_INVALID, "a geometric term of scale %g", k);
    int first = !(r->surface_k > 0);
    r->surface_k = k;
    r->seq++;
    Lumesh__SetSurface g;
    co_remote_surface_msg(r, &g);
    lm_status st = broadcast(r, LUMESH__MSG__BODY_SET_SURFACE, &g);
    if (st != LM_OK || !first || !r->mesh_set)
        return st;
    lm_tri_data *tris = NULL;
    Lumesh__SetMesh sm;
    r->seq++;
    st = co_remote_mesh_msg(r, &sm, &tris);
    if (st == LM_OK)
        st = broadcast(r, LUMESH__MSG__BODY_SET_MESH, &sm);
    lm_wire_arena_reset(&r->arena);
    free(tris);
    return st;
}

static lm_status rm_set_materials(lm_views *v, const lm_material *mats, uint32_t n)
{
    co_remote *r = as_remote(v);
    lm_asset_hash h;
    lm_status st = lm_asset_pack_materials(mats, n, &r->assets, &h);
    if (st == LM_OK)
        st = co_remote_layout(r);
    if (st == LM_OK)
        st = co_remote_ship(r, r->live, r->n_live);
    for (uint32_t i = 0; i < r->n_live; i++)
        co_pool_disarm(r->live[i]);
    if (st != LM_OK)
        return st;
    r->materials = h;
    r->has_materials = 1;
    r->seq++;
    Lumesh__SetMaterials m = LUMESH__SET_MATERIALS__INIT;
    m.materials = (ProtobufCBinaryData){LM_ASSET_HASH_BYTES, r->materials.b};
    return broadcast(r, LUMESH__MSG__BODY_SET_MATERIALS, &m);
}

/* The patch goes against the replica as it was (the workers' current records), which then
 * follows it. */
static lm_status rm_commit(lm_views *v, const lm_patch *patch)
{
    co_remote *r = as_remote(v);
    if (!r->mesh_set)
        return lm_fail(LM_E_INVALID, "no mesh set: call set_mesh before commit");
    Lumesh__Commit c = LUMESH__COMMIT__INIT;
    Lumesh__Patch p;
    lm_status st = lm_wire_patch_encode_against(patch, lm_replica_current, &r->rep, &r->arena, &p);
    c.patch = &p;
    if (st == LM_OK)
        st = lm_replica_apply(&r->rep, patch);
    if (st != LM_OK) {
        lm_wire_arena_reset(&r->arena);
        r->mesh_set = 0; /* half-applied: the caller sets the mesh again */
        return st;
    }
    r->seq++;
    return broadcast(r, LUMESH__MSG__BODY_COMMIT, &c);
}

/* ---- requests -------------------------------------------------------------------------------- */

/* One request round over some workers: each gets its body from make(), then all are awaited and
 * their replies taken by take(). *again is set when the round must be redone (a worker lost or
 * stale; stale ones were sent the state). */
typedef struct round {
    co_remote *r;
    Lumesh__Msg__BodyCase want;
    lm_status (*send)(struct round *rd, uint32_t i, uint64_t req);
    lm_status (*take)(struct round *rd, uint32_t i);
    void *ctx;
    co_worker **ws;
    uint32_t n;
    void (*overlap)(void *ctx); /* the caller's work while the first try is out (then NULL) */
    void *overlap_ctx;
} round;

/* How a round went: done, to redo (a worker lost or stale: the state was sent again), or struck
 * (workers holding the request were lost or failed it: to redo too, and each one counts). */
enum { ROUND_DONE, ROUND_AGAIN, ROUND_STRUCK };

/* One worker's answer: taken, or why the round goes again. */
static lm_status judge(round *rd, uint32_t i, int *outcome, int *strikes)
{
    co_remote *r = rd->r;
    co_worker *w = rd->ws[i];
    if (w->lost) {
        *outcome = ROUND_STRUCK;
        ++*strikes;
        return LM_OK;
    }
    int stale = 0;
    lm_status st = co_remote_check_reply(r, w, rd->want, &stale);
    if (st == LM_OK && stale) {
        *outcome = *outcome > ROUND_AGAIN ? *outcome : ROUND_AGAIN;
        return co_remote_send_state(r, w);
    }
    if (st != LM_OK && w->reply.msg->body_case == LUMESH__MSG__BODY_FAILURE) {
        co_pool_failed(r->pool, w, lm_last_error()); /* the third blocklists it */
        lm_clear_error();
        *outcome = ROUND_STRUCK;
        ++*strikes;
        return w->lost ? LM_OK : co_remote_send_state(r, w);
    }
    if (st == LM_OK && *outcome == ROUND_DONE)
        st = rd->take(rd, i);
    return st;
}

static lm_status run_round(round *rd, int *outcome, int *strikes)
{
    co_remote *r = rd->r;
    uint64_t req = co_pool_next_req(r->pool);
    lm_status st = LM_OK;
    *outcome = ROUND_DONE;
    for (uint32_t i = 0; i < rd->n && st == LM_OK; i++)
        if (rd->ws[i]) {
            co_pool_arm_req(rd->ws[i], req);
            st = rd->send(rd, i, req);
        }
    if (st == LM_OK && rd->overlap) {
        rd->overlap(rd->overlap_ctx);
        rd->overlap = NULL;
    }
    if (st == LM_OK)
        st = co_remote_await(r, rd->ws, rd->n);
    for (uint32_t i = 0; i < rd->n && st == LM_OK; i++)
        if (rd->ws[i])
            st = judge(rd, i, outcome, strikes);
    for (uint32_t i = 0; i < rd->n; i++)
        if (rd->ws[i])
            co_pool_disarm(rd->ws[i]);
    return st;
}

/* Redo a round (made afresh by plan() on the current layout) until it is done: workers may be lost
 * or stale meanwhile. A request that CO_REMOTE_STRIKES workers holding it died or failed on is
 * poison (LM_E_POISON); one that keeps finding workers out of step gives up (LM_E_IO). */
static lm_status with_retries(co_remote *r, lm_status (*plan)(round *rd), round *rd)
{
    int strikes = 0;
    for (int t = 0; t < CO_REMOTE_TRIES; t++) {
        int outcome = ROUND_DONE;
        lm_status st = co_remote_layout(r);
        if (st == LM_OK)
            st = plan(rd);
        if (st == LM_OK)
            st = run_round(rd, &outcome, &strikes);
        free(rd->ws);
        rd->ws = NULL;
        if (st != LM_OK || outcome == ROUND_DONE)
            return st;
        if (strikes >= CO_REMOTE_STRIKES)
            return lm_fail(LM_E_POISON, "a request failed on %d workers, every one it went to",
                           strikes);
    }
    return lm_fail(LM_E_IO, "workers were lost or out of step %d times in a row", CO_REMOTE_TRIES);
}

/* One worker per range (the first of its replicas), in range order. */
static lm_status plan_one_per_range(round *rd)
{
    co_remote *r = rd->r;
    rd->n = r->n_ranges;
    rd->ws = calloc(r->n_ranges + 1, sizeof *rd->ws);
    if (!rd->ws)
        return lm_fail(LM_E_NOMEM, "out of memory planning a request");
    for (uint32_t i = r->n_live; i-- > 0;)
        rd->ws[r->group[i]] = r->live[i];
    return LM_OK;
}

/* -- evaluate -- */

typedef struct eval_ctx {
    const lm_patch *patches;
    uint32_t n;
    int surface; /* the workers add the geometric term (surface_term) */
    int64_t *delta;
    uint32_t *lo, *hi; /* slice of worker i */
    size_t packed;     /* bytes of the message in r->pack (0 = none) */
    uint32_t packed_lo, packed_hi;
    uint64_t packed_req;
} eval_ctx;

/* Every worker of the layout, with its slice of the batch (replicas of a range share it). */
static lm_status plan_evaluate(round *rd)
{
    co_remote *r = rd->r;
    eval_ctx *e = rd->ctx;
    rd->n = r->n_live;
    rd->ws = calloc(r->n_live + 1, sizeof *rd->ws);
    free(e->lo);
    e->lo = calloc(r->n_live + 1, sizeof *e->lo);
    free(e->hi);
    e->hi = calloc(r->n_live + 1, sizeof *e->hi);
    if (!rd->ws || !e->lo || !e->hi)
        return lm_fail(LM_E_NOMEM, "out of memory planning an evaluation");
    for (uint32_t i = 0; i < r->n_live; i++) {
        uint32_t reps = 0, me = 0;
        for (uint32_t k = 0; k < r->n_live; k++)
            if (r->group[k] == r->group[i])
                me += k < i, reps++;
        e->lo[i] = (uint32_t)((uint64_t)e->n * me / reps);
        e->hi[i] = (uint32_t)((uint64_t)e->n * (me + 1) / reps);
        rd->ws[i] = e->hi[i] > e->lo[i] ? r->live[i] : NULL;
    }
    memset(e->delta, 0, (size_t)e->n * sizeof *e->delta);
    return LM_OK;
}

/* Worker i's slice, packed once for every worker that has the same one (every worker when no
 * range has replicas). */
static lm_status send_evaluate(round *rd, uint32_t i, uint64_t req)
{
    co_remote *r = rd->r;
    eval_ctx *e = rd->ctx;
    uint32_t lo = e->lo[i], n = e->hi[i] - lo;
    lm_status st = LM_OK;
    if (!e->packed || e->packed_lo != lo || e->packed_hi != e->hi[i] || e->packed_req != req) {
        Lumesh__Patch *p = lm_wire_arena_alloc(&r->arena, n * sizeof *p);
        Lumesh__Patch **pp = lm_wire_arena_alloc(&r->arena, n * sizeof *pp);
        st = p && pp ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory encoding patches");
        for (uint32_t k = 0; k < n && st == LM_OK; k++) {
            st = lm_wire_patch_encode_against(&e->patches[lo + k], lm_replica_current, &r->rep,
                                              &r->arena, &p[k]);
            pp[k] = &p[k];
        }
        Lumesh__Evaluate m = LUMESH__EVALUATE__INIT;
        m.n_patches = n;
        m.patches = pp;
        m.surface = e->surface;
        if (st == LM_OK)
            st = co_remote_pack(r, req, r->seq, LUMESH__MSG__BODY_EVALUATE, &m, &e->packed);
        lm_wire_arena_reset(&r->arena);
        e->packed_lo = lo, e->packed_hi = e->hi[i], e->packed_req = req;
        if (st != LM_OK)
            e->packed = 0;
    }
    return st == LM_OK ? co_pool_send_packed(r->pool, rd->ws[i], r->pack, e->packed) : st;
}

static lm_status take_deltas(round *rd, uint32_t i)
{
    eval_ctx *e = rd->ctx;
    co_worker *w = rd->ws[i];
    const Lumesh__Deltas *d = w->reply.msg->deltas;
    uint32_t lo = e->lo[i], n = e->hi[i] - lo;
    if (d->n_delta != n)
        return lm_fail(LM_E_FORMAT, "worker %u answered %zu results for %u patches", w->id,
                       d->n_delta, n);
    for (uint32_t k = 0; k < n; k++)
        e->delta[lo + k] += d->delta[k];
    w->evals += n;
    w->busy_s += 1e-6 * (double)d->busy_us;
    return LM_OK;
}

/* A batch over the layout; with `surface`, the workers add the geometric term. */
static lm_status evaluate_batch(co_remote *r, const lm_patch *patches, uint32_t n, int64_t *delta,
                                int surface, void (*overlap)(void *ctx), void *ctx)
{
    if (!r->mesh_set)
        return lm_fail(LM_E_INVALID, "no mesh set: call set_mesh before evaluate");
    if (surface && !(r->surface_k > 0))
        return lm_fail(LM_E_INVALID, "the geometric term asked of workers that were not given it");
    if (n == 0) {
        if (overlap)
            overlap(ctx);
        return LM_OK;
    }
    eval_ctx e = {.patches = patches, .n = n, .delta = delta, .surface = surface};
    round rd = {.r = r,
                .want = LUMESH__MSG__BODY_DELTAS,
                .send = send_evaluate,
                .take = take_deltas,
                .ctx = &e,
                .overlap = overlap,
                .overlap_ctx = ctx};
    lm_status st = with_retries(r, plan_evaluate, &rd);
    free(e.lo);
    free(e.hi);
    r->evaluations += st == LM_OK ? n : 0;
    co_pool_set_job_evals(r->pool, r->evaluations);
    return st;
}

static lm_status rm_evaluate_overlapped(lm_views *v, const lm_patch *patches, uint32_t n,
                                        int64_t *delta, void (*overlap)(void *ctx), void *ctx)
{
    return evaluate_batch(as_remote(v), patches, n, delta, 0, overlap, ctx);
}

static lm_status rm_evaluate(lm_views *v, const lm_patch *patches, uint32_t n, int64_t *delta)
{
    return evaluate_batch(as_remote(v), patches, n, delta, 0, NULL, NULL);
}

static lm_status rm_evaluate_surface(lm_views *v, const lm_patch *patches, uint32_t n,
                                     int64_t *delta)
{
    return evaluate_batch(as_remote(v), patches, n, delta, 1, NULL, NULL);
}

/* -- energy -- */

static lm_status send_energy(round *rd, uint32_t i, uint64_t req)
{
    Lumesh__Energy m = LUMESH__ENERGY__INIT;
    return co_pool_send(rd->r->pool, rd->ws[i], req, rd->r->seq, LUMESH__MSG__BODY_ENERGY, &m);
}

static lm_status take_energy(round *rd, uint32_t i)
{
    co_remote *r = rd->r;
    const co_range *g = &r->ranges[i];
    const Lumesh__EnergyResult *e = rd->ws[i]->reply.msg->energy_result;
    if (e->n_per_view != g->count)
        return lm_fail(LM_E_FORMAT, "worker %u answered %zu energies for %u views", rd->ws[i]->id,
                       e->n_per_view, g->count);
    for (uint32_t j = 0; j < g->count; j++)
        ((int64_t *)rd->ctx)[lm_view_deal_view(*g, j) - r->first] = e->per_view[j];
    return LM_OK;
}

static lm_status rm_energy(lm_views *v, int64_t *total, int64_t *per_view)
{
    co_remote *r = as_remote(v);
    if (!r->mesh_set)
        return lm_fail(LM_E_INVALID, "energy asked before a mesh was set");
    int64_t per[LM_MAX_VIEWS];
    round rd = {.r = r,
                .want = LUMESH__MSG__BODY_ENERGY_RESULT,
                .send = send_energy,
                .take = take_energy,
                .ctx = per};
    lm_status st = with_retries(r, plan_one_per_range, &rd);
    if (st != LM_OK)
        return st;
    int64_t sum = 0;
    for (uint32_t h = 0; h < r->count; h++)
        sum += per[h];
    if (total)
        *total = sum;
    if (per_view)
        memcpy(per_view, per, r->count * sizeof *per);
    return LM_OK;
}

/* -- potentials -- */

typedef struct pot_ctx {
    const float (*points)[3];
    size_t n;
    int64_t *out;
} pot_ctx;

static lm_status send_potentials(round *rd, uint32_t i, uint64_t req)
{
    pot_ctx *c = rd->ctx;
    if (i == 0)
        memset(c->out, 0, c->n * sizeof *c->out);
    Lumesh__Potentials m = LUMESH__POTENTIALS__INIT;
    m.n_points = 3 * c->n;
    m.points = (float *)(void *)c->points;
    return co_pool_send(rd->r->pool, rd->ws[i], req, rd->r->seq, LUMESH__MSG__BODY_POTENTIALS, &m);
}

static lm_status take_potentials(round *rd, uint32_t i)
{
    pot_ctx *c = rd->ctx;
    const Lumesh__PotentialsResult *p = rd->ws[i]->reply.msg->potentials_result;
    if (p->n_sums != c->n)
        return lm_fail(LM_E_FORMAT, "worker %u answered %zu potentials for %zu points",
                       rd->ws[i]->id, p->n_sums, c->n);
    for (size_t k = 0; k < c->n; k++)
        c->out[k] += p->sums[k];
    return LM_OK;
}

static lm_status rm_potentials(lm_views *v, const float (*points)[3], size_t n, int64_t *out)
{
    co_remote *r = as_remote(v);
    if (!r->mesh_set)
        return lm_fail(LM_E_INVALID, "potentials asked before a mesh was set");
    if (3 * n > LM_WIRE_MAX_FRAME / 8)
        return lm_fail(LM_E_RANGE, "%zu points exceed what one message carries", n);
    pot_ctx c = {points, n, out};
    round rd = {.r = r,
                .want = LUMESH__MSG__BODY_POTENTIALS_RESULT,
                .send = send_potentials,
                .take = take_potentials,
                .ctx = &c};
    memset(out, 0, n * sizeof *out);
    return with_retries(r, plan_one_per_range, &rd);
}

/* -- images -- */

typedef struct image_ctx {
    lm_image_kind kind;
    uint32_t view; /* job index */
    uint8_t *out;
    size_t bytes;
} image_ctx;

static lm_status plan_image(round *rd)
{
    co_remote *r = rd->r;
    image_ctx *c = rd->ctx;
    rd->n = 1;
    rd->ws = calloc(1, sizeof *rd->ws);
    if (!rd->ws)
        return lm_fail(LM_E_NOMEM, "out of memory planning a request");
    uint32_t place;
    for (uint32_t i = 0; i < r->n_live && !rd->ws[0]; i++) {
        const co_worker *w = r->live[i];
        if (lm_view_deal_place((lm_view_deal){w->first, w->count, w->stride}, c->view, &place))
            rd->ws[0] = r->live[i];
    }
    return LM_OK;
}

static lm_status send_image(round *rd, uint32_t i, uint64_t req)
{
    image_ctx *c = rd->ctx;
    Lumesh__ReadImage m = LUMESH__READ_IMAGE__INIT;
    m.kind = (uint32_t)c->kind;
    m.view = c->view;
    return co_pool_send(rd->r->pool, rd->ws[i], req, rd->r->seq, LUMESH__MSG__BODY_READ_IMAGE, &m);
}

static lm_status take_image(round *rd, uint32_t i)
{
    image_ctx *c = rd->ctx;
    const Lumesh__Image *img = rd->ws[i]->reply.msg->image;
    if (img->pixels.len != c->bytes)
        return lm_fail(LM_E_FORMAT, "worker %u answered an image of %zu bytes, not %zu",
                       rd->ws[i]->id, img->pixels.len, c->bytes);
    memcpy(c->out, img->pixels.data, c->bytes);
    return LM_OK;
}

static lm_status rm_read_image(lm_views *v, lm_image_kind kind, uint32_t view, uint8_t *out)
{
    co_remote *r = as_remote(v);
    if (view >= r->count)
        return lm_fail(LM_E_RANGE, "view %u of %u", view, r->count);
    if (kind == LM_IMAGE_TRIANGLE)
        return lm_fail(LM_E_UNSUPPORTED, "triangle ids are not read from workers");
    image_ctx c = {kind, r->first + view, out,
                   (size_t)r->width * (size_t)r->height * lm_image_kind_bpp(kind)};
    round rd = {
        .r = r, .want = LUMESH__MSG__BODY_IMAGE, .send = send_image, .take = take_image, .ctx = &c};
    return with_retries(r, plan_image, &rd);
}

/* ---- the rest -------------------------------------------------------------------------------- */

static void rm_info(lm_views *v, lm_views_info *out)
{
    co_remote *r = as_remote(v);
    memset(out, 0, sizeof *out);
    out->n_views = r->count;
    out->width = r->width;
    out->height = r->height;
    out->seq = r->seq;
    out->evaluations = r->evaluations;
    out->overlap_costs = co_pool_cores_full(r->pool);
    snprintf(out->renderer, sizeof out->renderer, "%s", r->renderer);
}

static void rm_destroy(lm_views *v)
{
    co_remote *r = as_remote(v);
    co_remote_layout_free(r);
    lm_asset_set_free(&r->assets);
    lm_replica_free(&r->rep);
    lm_wire_arena_free(&r->arena);
    free(r->pack);
    free(r->views);
    free(r->lane_base);
    free(r->lane_queue_base);
    free(r);
}

static const lm_views_ops remote_ops = {
    .set_mesh = rm_set_mesh,
    .set_materials = rm_set_materials,
    .evaluate = rm_evaluate,
    .evaluate_overlapped = rm_evaluate_overlapped,
    .commit = rm_commit,
    .energy = rm_energy,
    .potentials = rm_potentials,
    .read_image = rm_read_image,
    .info = rm_info,
    .destroy = rm_destroy,
    .surface_term = rm_surface_term,
    .evaluate_surface = rm_evaluate_surface,
};

co_remote *co_remote_of(lm_views *v)
{
    return v && v->ops == &remote_ops ? (co_remote *)v : NULL;
}

void co_original_pack_free(co_original_pack *p)
{
    lm_asset_set_free(&p->assets);
    memset(p, 0, sizeof *p);
}

/* r's assets: the original packed, or copied from d->pack when that holds this original (and
 * filled from these when it holds none). */
static lm_status pack_original(const co_views_desc *d, co_remote *r)
{
    co_original_pack *p = d->pack;
    if (p && p->mesh == d->original) {
        r->original = p->hash;
        return lm_asset_set_copy(&r->assets, &p->assets);
    }
    lm_status st = lm_asset_pack_mesh(d->original, &r->assets, &r->original);
    if (st != LM_OK || !p)
        return st;
    co_original_pack_free(p);
    if (lm_asset_set_copy(&p->assets, &r->assets) == LM_OK) {
        p->mesh = d->original;
        p->hash = r->original;
    }
    lm_clear_error(); /* no pack: the next views pack again */
    return LM_OK;
}

lm_status co_views_remote_create(const co_views_desc *d, lm_views **out)
{
    static uint32_t jobs;
    *out = NULL;
    co_remote *r = calloc(1, sizeof *r);
    lm_status st = r ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory creating remote views");
    if (st == LM_OK) {
        r->base.ops = &remote_ops;
        r->pool = d->pool;
        r->job = (uint64_t)getpid() << 32 | ++jobs;
        r->first = d->first;
        r->count = d->count;
        r->whole = d->whole;
        r->audit = d->audit;
        r->original_mesh = d->original;
        r->width = d->views->views[0].width;
        r->height = d->views->views[0].height;
        lm_asset_set_init(&r->assets);
        lm_replica_init(&r->rep);
        lm_wire_arena_init(&r->arena);
        r->views = malloc(sizeof *r->views);
        st = r->views ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory for the view set");
    }
    if (st == LM_OK) {
        memcpy(r->views, d->views, sizeof *r->views);
        st = pack_original(d, r);
    }
    if (st == LM_OK)
        st = co_remote_layout(r);
    if (st != LM_OK) {
        if (r)
            rm_destroy(&r->base);
        return st;
    }
    *out = &r->base;
    return LM_OK;
}
