/* common/optimizer/lane_host.c — a lane run on its own from a request: mesh copy, views priced
 * at the group's start, the teleport state and statistics rebuilt from the request, the result
 * filled from the run (lane_host.h). */
#include "common/optimizer/lane_host.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/optimizer/edge.h"
#include "common/optimizer/lane_views.h"

struct lm_lane_host {
    lm_mesh *mesh;
    lm_moves *mv;
    lm_lane_views views;
    lm_teleport tp;
    lm_move_stats stats;
    lm_progress prog;
    uint64_t clock;
    lm_tri_data *start; /* the group's start as records, sorted by id */
    size_t n_start;
    uint64_t token;             /* names start and pristine (0: nothing kept) */
    lm_cq *pristine;            /* the queue as the requests of token give it */
    const lm_lane_request *req; /* during a run */
    lm_lane_result *res;
};

static void on_accepted(void *ctx, const lm_move_record *r)
{
    lm_lane_host *h = ctx;
    h->views.pending = r->delta;
    lm_status st = lm_lane_result_accepted(h->res, r, h->views.d_acc);
    LM_ASSERT(st == LM_OK);
}

static void on_reverted(void *ctx, size_t mark)
{
    lm_lane_host *h = ctx;
    h->views.d_acc = lm_lane_result_reverted(h->res, mark, h->views.d_acc);
}

/* The collapse search: not in another member's start neighbourhood, in the lane's share. */
static int host_veto(void *ctx, uint32_t a, uint32_t b)
{
    const lm_lane_request *q = ((const lm_lane_host *)ctx)->req;
    return lm_lane_request_vetoed(q, a) || lm_lane_request_vetoed(q, b) ||
           !lm_lane_share(a, b, q->n_group, q->index);
}

lm_status lm_lane_host_create(const lm_moves_config *cfg, lm_lane_host **out)
{
    *out = NULL;
    lm_lane_host *h = calloc(1, sizeof *h);
    if (!h)
        return lm_fail(LM_E_NOMEM, "out of memory for a lane host");
    lm_lane_views_init(&h->views, NULL, NULL);
    lm_status st = lm_mesh_create(&h->mesh);
    if (st == LM_OK)
        st = lm_moves_create(h->mesh, &h->views.base, cfg, &h->mv);
    if (st == LM_OK)
        st = lm_teleport_init(&h->tp, NULL, NULL);
    if (st != LM_OK) {
        lm_lane_host_destroy(h);
        return st;
    }
    lm_moves_observe(h->mv, &(lm_moves_observer){on_accepted, on_reverted, h});
    lm_moves_share_clock(h->mv, &h->clock);
    *out = h;
    return LM_OK;
}

void lm_lane_host_destroy(lm_lane_host *h)
{
    if (!h)
        return;
    lm_moves_destroy(h->mv);
    lm_mesh_destroy(h->mesh);
    lm_lane_views_free(&h->views);
    if (h->tp.queue)
        lm_teleport_free(&h->tp);
    free(h->start);
    lm_cq_destroy(h->pristine);
    free(h);
}

/* The teleport state of the request: its constants, threshold, improve[] and queue; the
 * counters from 0 (the result gives what the lane added). */
static lm_status load_teleport(lm_lane_host *h, const lm_lane_request *q, int kept,
                               lm_lane_result *res)
{
    lm_teleport *tp = &h->tp;
    lm_cq *queue = tp->queue;
    memset(tp, 0, sizeof *tp);
    tp->queue = queue;
    tp->cfg = q->tp_cfg;
    lm_teleport_config_defaults(&tp->cfg);
    tp->last_collapse = q->last_collapse;
    tp->last_time = q->last_time;
    memcpy(tp->improve, q->improve, sizeof tp->improve);
    tp->veto = host_veto;
    tp->veto_ctx = h;
    tp->log = &res->log;
    lm_cq_observe(queue, NULL, NULL);
    lm_status st = kept ? lm_cq_copy(queue, h->pristine) : LM_OK;
    if (!kept) {
        lm_cq_clear(queue);
        for (uint32_t i = 0; i < q->n_queue && st == LM_OK; i++) {
            const lm_cq_entry *e = &q->queue[i];
            st = lm_cq_set(queue, e->a, e->b, e->est, e->level, (int)e->in_heap);
        }
    }
    if (!kept && h->token && st == LM_OK) /* kept for the token's next lanes */
        st = h->pristine ? LM_OK : lm_cq_create(&h->pristine);
    if (!kept && h->token && st == LM_OK)
        st = lm_cq_copy(h->pristine, queue);
    lm_cq_observe(queue, lm_lane_log_queue, &res->log);
    return st;
}

/* The mesh, the views' start and the state of the group's start (what token names kept). */
static lm_status begin(lm_lane_host *h, const lm_mesh *start, lm_views *views,
                       const lm_lane_request *q, uint64_t token, lm_lane_result *res)
{
    lm_lane_result_clear(res);
    h->req = q;
    h->res = res;
    h->views.real = h->views.direct = views;
    int kept = token && token == h->token && h->start;
    if (!kept) {
        free(h->start);
        h->start = NULL;
        h->token = 0;
    }
    lm_status st = lm_mesh_copy_geometry(h->mesh, start);
    if (st == LM_OK && !kept)
        st = lm_mesh_export_tris(start, &h->start, &h->n_start);
    if (st != LM_OK)
        return st;
    h->token = token;
    lm_lane_views_reset(&h->views, h->start, h->n_start);
    lm_moves_forget(h->mv);
    h->stats = q->stats;
    h->clock = q->clock;
    memset(&h->prog, 0, sizeof h->prog);
    st = load_teleport(h, q, kept, res);
    if (st != LM_OK)
        h->token = 0; /* derived again next time */
    return st;
}

static void finish(lm_lane_host *h, const lm_edge_ctx *c, uint64_t evals0, lm_lane_result *res)
{
    res->d_acc = h->views.d_acc;
    res->mesh_hash = res->n_ops ? lm_mesh_hash(h->mesh) : 0;
    res->evals = lm_moves_evals(h->mv) - evals0;
    memcpy(res->attempted, h->prog.attempted, sizeof res->attempted);
    memcpy(res->accepted, c->accepted, sizeof res->accepted);
    res->searches = h->tp.searches;
    res->searches_failed = h->tp.searches_failed;
    res->collapses_tried = h->tp.collapses_tried;
    res->last_collapse = h->tp.last_collapse;
    res->last_time = h->tp.last_time;
}

lm_status lm_lane_host_run(lm_lane_host *h, const lm_mesh *start, lm_views *views,
                           const lm_lane_request *req, uint64_t token, lm_lane_result *res)
{
    lm_status st = begin(h, start, views, req, token, res);
    lm_edge_ctx c = {.mesh = h->mesh,
                     .mv = h->mv,
                     .stats = &h->stats,
                     .tp = &h->tp,
                     .touched = &res->touched,
                     .log = &res->log,
                     .prog = &h->prog,
                     .deferred = 1};
    uint64_t evals0 = lm_moves_evals(h->mv);
    if (st == LM_OK)
        st = lm_edge_optimise(&c, req->a, req->b, &res->total);
    finish(h, &c, evals0, res);
    lm_cq_observe(h->tp.queue, NULL, NULL);
    h->req = NULL;
    h->res = NULL;
    res->status = st;
    if (st != LM_OK)
        snprintf(res->msg, sizeof res->msg, "%s", lm_last_error());
    return st;
}
