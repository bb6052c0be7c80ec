/* common/optimizer/lane_work.c — a lane's request and result: lifetime, the vetoed list, the
 * accepted operations as the lane's moves report them (lane_work.h). */
#include "common/optimizer/lane_work.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

void lm_lane_request_init(lm_lane_request *q)
{
    memset(q, 0, sizeof *q);
}

void lm_lane_request_free(lm_lane_request *q)
{
    free(q->vetoed);
    free(q->queue);
    lm_lane_request_init(q);
}

lm_status lm_lane_request_veto(lm_lane_request *q, uint32_t v)
{
    if (!LM_GROW32(&q->vetoed, &q->cap_vetoed, (size_t)q->n_vetoed + 1, 256))
        return lm_fail(LM_E_NOMEM, "out of memory for a lane's request");
    q->vetoed[q->n_vetoed++] = v;
    return LM_OK;
}

int lm_lane_request_vetoed(const lm_lane_request *q, uint32_t v)
{
    uint32_t lo = 0, hi = q->n_vetoed;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (q->vetoed[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < q->n_vetoed && q->vetoed[lo] == v;
}

int lm_lane_share(uint32_t a, uint32_t b, uint32_t n, uint32_t index)
{
    uint64_t k = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    return n <= 1 || k % n == index;
}

void lm_lane_result_init(lm_lane_result *r)
{
    memset(r, 0, sizeof *r);
    lm_lane_log_init(&r->log);
    lm_idset_init(&r->touched);
}

void lm_lane_result_free(lm_lane_result *r)
{
    free(r->ops);
    free(r->xs);
    lm_lane_log_free(&r->log);
    lm_idset_free(&r->touched);
    lm_lane_result_init(r);
}

void lm_lane_result_clear(lm_lane_result *r)
{
    lm_lane_result keep = *r;
    memset(r, 0, sizeof *r);
    r->ops = keep.ops, r->cap_ops = keep.cap_ops;
    r->xs = keep.xs, r->cap_xs = keep.cap_xs;
    r->log = keep.log;
    r->touched = keep.touched;
    lm_lane_log_clear(&r->log);
    lm_idset_clear(&r->touched);
}

lm_status lm_lane_result_accepted(lm_lane_result *res, const lm_move_record *r, int64_t d_acc)
{
    if (!LM_GROW32(&res->ops, &res->cap_ops, (size_t)res->n_ops + 1, 16) ||
        !LM_GROW32(&res->xs, &res->cap_xs, (size_t)res->n_xs + r->dim, 1024))
        return lm_fail(LM_E_NOMEM, "out of memory for a lane's operations");
    memcpy(res->xs + res->n_xs, r->x, (size_t)r->dim * sizeof *r->x);
    res->ops[res->n_ops] = (lm_lane_op){*r, res->n_xs, d_acc};
    res->ops[res->n_ops++].r.x = NULL;
    res->n_xs += r->dim;
    return LM_OK;
}

int64_t lm_lane_result_reverted(lm_lane_result *res, size_t mark, int64_t d_acc)
{
    while (res->n_ops && res->ops[res->n_ops - 1].r.mark >= mark) {
        lm_lane_op *op = &res->ops[--res->n_ops];
        d_acc = op->d_acc_0;
        res->n_xs = op->x_at;
    }
    return d_acc;
}
