/* tests/bench/scaling/visits.c — the window's plan order as visits: an edge's optimisation cut
 * into visits of at most N evaluations (--cap N; 0: no cap, one visit an edge).
 *
 * The measured edges, cycled, are the pass's edges (at least one pass over the start's edges).
 * A visit to an edge stops after N evaluations; what the edge still had to do is a continuation
 * visit placed later in plan order, at position p + D of the visit before it (p: that visit's
 * position, D: the window's lag), so that it starts from a state where that visit is merged;
 * continuations due at a position go first, in the order they were made, and if several are due
 * the later ones slide on (a continuation is never earlier than p + D). A position with no
 * continuation due takes the next edge. The visits are made until every visit of the pass's edges
 * is placed; the positions between are filled with the next edges of the cycle (the next pass, as
 * in a run that goes on), and what is placed is what is modelled (the in-process time included):
 * with long edges and a large D many passes' worth (a 1,500-evaluation edge at N 16, D 4096 spans
 * 94 visits, 94 x 4096 positions).
 *
 * An edge of n evaluations and cost c becomes ceil(n / N) visits, each of cost
 * c (its evaluations) / n, the views' time likewise; the planning before the edge (plans, plan_s,
 * pot_s) goes with its first visit. Operations are committed by the visit that accepts them; the
 * accepted operations, their commits (apply_s, bytes) and the merge are all charged to the last
 * visit (conservative for re-validation: the commit comes as late as possible). The last visit's
 * re-validation distance (near) is recomputed between last visits; where the edge it meets commits
 * after it, it is re-validated (near 1). Not charged: a continuation re-evaluating its starting
 * state against the merged mesh (restarts counts them: at most one evaluation each). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "common/error.h"
#include "scaling.h"

typedef struct pending {
    size_t edge;   /* the cycle's index of the edge */
    uint32_t done; /* its evaluations before this visit */
    size_t due;    /* the earliest position */
} pending;

typedef struct builder {
    const edges_run *er;
    uint32_t cap;
    visits *out;
    pending *q; /* FIFO: dues only grow, in the order made */
    size_t head, tail, qcap;
    size_t *last_at; /* per edge of the cycle placed: the position of its last visit */
    size_t edges, cap_last;
    uint64_t placed; /* evaluations placed of the pass's edges */
} builder;

static uint32_t visits_of(uint32_t n, uint32_t cap)
{
    return !cap || n <= cap ? 1 : (n + cap - 1) / cap;
}

static void push_visit(builder *b, const edge_rec *v)
{
    visits *o = b->out;
    if (o->n == o->cap) {
        o->cap = o->cap ? 2 * o->cap : 1024;
        o->v = realloc(o->v, o->cap * sizeof *o->v);
        LM_ASSERT(o->v);
    }
    o->v[o->n++] = *v;
}

static void push_pending(builder *b, pending p)
{
    if (b->tail == b->qcap) { /* the live ones to the front; room for as many again */
        size_t live = b->tail - b->head;
        memmove(b->q, b->q + b->head, live * sizeof *b->q);
        b->head = 0, b->tail = live;
        if (2 * live >= b->qcap) {
            b->qcap = b->qcap ? 2 * b->qcap : 256;
            b->q = realloc(b->q, b->qcap * sizeof *b->q);
            LM_ASSERT(b->q);
        }
    }
    b->q[b->tail++] = p;
}

/* A new edge of the cycle: its last visit's position unknown yet. */
static size_t new_edge(builder *b)
{
    if (b->edges == b->cap_last) {
        b->cap_last = b->cap_last ? 2 * b->cap_last : 1024;
        b->last_at = realloc(b->last_at, b->cap_last * sizeof *b->last_at);
        LM_ASSERT(b->last_at);
    }
    b->last_at[b->edges] = SIZE_MAX;
    return b->edges++;
}

/* Place the visit of edge j (cycle index) after `done` of its evaluations at the next position. */
static void place(builder *b, size_t j, uint32_t done, uint32_t d)
{
    const edge_rec *e = sc_pass_edge(b->er, j);
    uint32_t n = e->evals, m = b->cap && n - done > b->cap ? b->cap : n - done;
    int first = done == 0, last = done + m >= n;
    double f = n ? (double)m / n : 1;
    edge_rec v = {.evals = m,
                  .edges = first ? e->edges : 0,
                  .plans = first ? e->plans : 0,
                  .plan_s = first ? e->plan_s : 0,
                  .pot_s = first ? e->pot_s : 0,
                  .cost_s = (float)(e->cost_s * f),
                  .views_s = (float)(e->views_s * f)};
    if (last) {
        v.ops = e->ops, v.near = e->near, v.apply_s = e->apply_s, v.merge_s = e->merge_s;
        v.bytes = e->bytes;
        b->last_at[j] = b->out->n;
    } else
        push_pending(b, (pending){j, done + m, b->out->n + d});
    push_visit(b, &v);
}

/* The last visits' near, from the edges they meet to the last visits of those. */
static void renear(builder *b)
{
    for (size_t j = 0; j < b->edges; j++) {
        size_t at = b->last_at[j];
        if (at == SIZE_MAX)
            continue;
        edge_rec *v = &b->out->v[at];
        if (!v->ops || !v->near || v->near > j)
            continue;
        size_t other = b->last_at[j - v->near];
        v->near = other < at ? (uint32_t)(at - other > UINT32_MAX ? UINT32_MAX : at - other) : 1;
    }
}

void sc_visits_make(const edges_run *er, uint32_t cap, uint32_t d, visits *out)
{
    memset(out, 0, sizeof *out);
    builder b = {.er = er, .cap = cap, .out = out};
    size_t pass = er->n > er->mesh_edges ? er->n : er->mesh_edges, left = 0;
    uint64_t evals = 0;
    for (size_t j = 0; j < pass; j++) {
        left += visits_of(sc_pass_edge(er, j)->evals, cap);
        evals += sc_pass_edge(er, j)->evals;
    }
    out->edges = pass;
    while (left) {
        size_t j;
        uint32_t done = 0;
        if (b.head < b.tail && b.q[b.head].due <= out->n) {
            j = b.q[b.head].edge, done = b.q[b.head].done;
            b.head++;
        } else
            j = new_edge(&b);
        place(&b, j, done, d ? d : 1);
        if (j < pass)
            left--, b.placed += out->v[out->n - 1].evals;
    }
    LM_ASSERT(b.placed == evals);
    out->started = b.edges;
    out->restarts = (double)(out->n - b.edges);
    renear(&b);
    free(b.q);
    free(b.last_at);
}

void sc_visits_free(visits *v)
{
    free(v->v);
    memset(v, 0, sizeof *v);
}
