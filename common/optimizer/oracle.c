/* common/optimizer/oracle.c — edge potentials from the views' blurred difference images,
 * ranking, iteration planning (oracle ∪ random, interleaved) and the progress balance between the
 * two. */
#include "common/optimizer/oracle.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

void lm_oracle_init(lm_oracle *o)
{
    memset(o, 0, sizeof *o);
    o->share = 0.5;
    o->min_share = 0.125;
    o->max_share = 0.875;
    o->max_age = 16;
}

void lm_oracle_free(lm_oracle *o)
{
    free(o->stale);
    o->stale = NULL;
    o->n_stale = o->cap_stale = 0;
}

static int cmp_ranked(const void *x, const void *y)
{
    const lm_ranked_edge *a = x, *b = y;
    if (a->potential != b->potential)
        return a->potential > b->potential ? -1 : 1;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    return (a->b > b->b) - (a->b < b->b);
}

/* Points: every vertex slot (dead ones too, harmless) then every edge midpoint. */
static lm_status make_points(const lm_mesh *m, const uint32_t (*edges)[2], size_t n,
                             float (**pts)[3])
{
    size_t np = (size_t)m->n_verts + n;
    float(*p)[3] = malloc((np + 1) * sizeof *p);
    if (!p)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu oracle points", np);
    memcpy(p, m->pos, (size_t)m->n_verts * sizeof *p);
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            p[m->n_verts + i][k] = 0.5f * (m->pos[edges[i][0]][k] + m->pos[edges[i][1]][k]);
    *pts = p;
    return LM_OK;
}

lm_status lm_oracle_rank(lm_views *views, const lm_mesh *m, const uint32_t (*edges)[2], size_t n,
                         lm_ranked_edge **out)
{
    *out = NULL;
    for (size_t i = 0; i < n; i++)
        if (edges[i][0] >= m->n_verts || edges[i][1] >= m->n_verts)
            return lm_fail(LM_E_RANGE, "oracle: edge (%u, %u) outside %u vertices", edges[i][0],
                           edges[i][1], m->n_verts);
    float(*pts)[3] = NULL;
    lm_status st = make_points(m, edges, n, &pts);
    if (st)
        return st;
    size_t np = (size_t)m->n_verts + n;
    int64_t *pot = malloc((np + 1) * sizeof *pot);
    lm_ranked_edge *r = malloc((n + 1) * sizeof *r);
    if (!pot || !r)
        st = lm_fail(LM_E_NOMEM, "out of memory ranking %zu edges", n);
    if (!st)
        st = views->ops->potentials(views, (const float(*)[3])pts, np, pot);
    for (size_t i = 0; i < n && !st; i++) {
        uint32_t a = edges[i][0], b = edges[i][1];
        r[i].a = a < b ? a : b;
        r[i].b = a < b ? b : a;
        r[i].potential = pot[a] + pot[b] + pot[m->n_verts + i];
    }
    free(pts);
    free(pot);
    if (st) {
        free(r);
        return st;
    }
    qsort(r, n, sizeof *r, cmp_ranked);
    *out = r;
    return LM_OK;
}

static int is_stale(const lm_oracle *o, uint64_t key)
{
    size_t lo = 0, hi = o->n_stale;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (o->stale[mid].key < key)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < o->n_stale && o->stale[lo].key == key;
}

static int planned(const lm_planned_edge *p, uint32_t n, uint32_t a, uint32_t b)
{
    for (uint32_t i = 0; i < n; i++)
        if (p[i].a == a && p[i].b == b)
            return 1;
    return 0;
}

static int touches(const lm_planned_edge *p, uint32_t n, uint32_t a, uint32_t b)
{
    for (uint32_t i = 0; i < n; i++)
        if (p[i].a == a || p[i].b == a || p[i].a == b || p[i].b == b)
            return 1;
    return 0;
}

/* What pick has taken so far, for its two questions in O(1): the edges (open addressing over
 * their keys) and their vertices (a mark per vertex id). Without its memory, pick asks the list
 * (planned, touches): the same answers. */
typedef struct taken {
    uint64_t *keys; /* [cap] edge key + 1, 0 empty */
    uint32_t cap;   /* a power of two, at least twice what is taken */
    uint8_t *mark;  /* [n_marks] 1: a taken edge's vertex */
    uint32_t n_marks;
} taken;

static int taken_init(taken *t, const lm_ranked_edge *r, size_t n, uint32_t count)
{
    uint32_t max_v = 0;
    for (size_t i = 0; i < n; i++)
        max_v = r[i].b > max_v ? r[i].b : max_v, max_v = r[i].a > max_v ? r[i].a : max_v;
    t->cap = 16;
    while (t->cap < 2u * count && t->cap < (1u << 30))
        t->cap *= 2;
    t->n_marks = max_v + 1;
    t->keys = calloc(t->cap, sizeof *t->keys);
    t->mark = calloc(t->n_marks, 1);
    return t->keys && t->mark && t->cap >= 2u * count;
}

static void taken_free(taken *t)
{
    free(t->keys);
    free(t->mark);
}

static uint32_t taken_slot(const taken *t, uint64_t key)
{
    uint32_t i = (uint32_t)((key * 0x9e3779b97f4a7c15ull) >> 32) & (t->cap - 1);
    while (t->keys[i] && t->keys[i] != key + 1)
        i = (i + 1) & (t->cap - 1);
    return i;
}

static int taken_has(const taken *t, uint32_t a, uint32_t b)
{
    return t->keys[taken_slot(t, lm_edge_key(a, b))] != 0;
}

static int taken_touches(const taken *t, uint32_t a, uint32_t b)
{
    return t->mark[a] || t->mark[b];
}

static void taken_add(taken *t, uint32_t a, uint32_t b)
{
    uint64_t key = lm_edge_key(a, b);
    t->keys[taken_slot(t, key)] = key + 1;
    t->mark[a] = t->mark[b] = 1;
}

/* Best non-stale edges first, spread out: an edge sharing a vertex with an edge already taken is
 * passed over (neighbouring edges are optimised together by the vertex sets anyway); then random
 * distinct edges. fast: t answers what the list would (the same edges taken). */
static uint32_t pick_with(const lm_oracle *o, const lm_ranked_edge *r, size_t n, lm_rng *rng,
                          uint32_t k_oracle, uint32_t count, lm_planned_edge *tmp, taken *t,
                          int fast)
{
    uint32_t k = 0;
    for (int pass = 0; pass < 2 && k < k_oracle; pass++)
        for (size_t i = 0; i < n && k < k_oracle; i++) {
            uint32_t a = r[i].a, b = r[i].b;
            if (is_stale(o, lm_edge_key(a, b)) ||
                (fast ? taken_has(t, a, b) : planned(tmp, k, a, b)))
                continue;
            if (pass == 0 && (fast ? taken_touches(t, a, b) : touches(tmp, k, a, b)))
                continue;
            tmp[k++] = (lm_planned_edge){a, b, 1};
            if (fast)
                taken_add(t, a, b);
        }
    uint32_t want = count < n ? count : (uint32_t)n;
    for (uint32_t tries = 0; k < want && tries < 16 * count; tries++) {
        const lm_ranked_edge *e = &r[lm_rng_below(rng, n)];
        if (fast ? taken_has(t, e->a, e->b) : planned(tmp, k, e->a, e->b))
            continue;
        tmp[k++] = (lm_planned_edge){e->a, e->b, 0};
        if (fast)
            taken_add(t, e->a, e->b);
    }
    return k;
}

static uint32_t pick(const lm_oracle *o, const lm_ranked_edge *r, size_t n, lm_rng *rng,
                     uint32_t k_oracle, uint32_t count, lm_planned_edge *tmp)
{
    taken t;
    int fast = taken_init(&t, r, n, count);
    uint32_t k = pick_with(o, r, n, rng, k_oracle, count, tmp, &t, fast);
    taken_free(&t);
    return k;
}

lm_status lm_oracle_plan(const lm_oracle *o, const lm_ranked_edge *ranked, size_t n_ranked,
                         lm_rng *rng, uint32_t count, lm_planned_edge *out, uint32_t *n_out)
{
    *n_out = 0;
    if (!n_ranked || !count)
        return LM_OK;
    lm_planned_edge *tmp = malloc((size_t)count * sizeof *tmp);
    if (!tmp)
        return lm_fail(LM_E_NOMEM, "out of memory planning %u edges", count);
    uint32_t k_oracle = (uint32_t)lround(o->share * count);
    uint32_t k = pick(o, ranked, n_ranked, rng, k_oracle, count, tmp);
    uint32_t n_or = 0;
    while (n_or < k && tmp[n_or].from_oracle)
        n_or++;
    /* Interleave evenly (Bresenham): oracle edge i goes out at about i * k / n_or. */
    uint32_t io = 0, ir = n_or;
    for (uint32_t i = 0; i < k; i++) {
        int take_oracle = io < n_or && (ir >= k || (uint64_t)io * k <= (uint64_t)i * n_or);
        out[i] = take_oracle ? tmp[io++] : tmp[ir++];
    }
    free(tmp);
    *n_out = k;
    return LM_OK;
}

void lm_oracle_balance(lm_oracle *o, double gain_oracle, uint32_t n_oracle, double gain_random,
                       uint32_t n_random)
{
    double go = n_oracle ? fmax(gain_oracle, 0) / n_oracle : 0;
    double gr = n_random ? fmax(gain_random, 0) / n_random : 0;
    double target = go + gr > 0 ? go / (go + gr) : 0.5;
    double s = 0.5 * o->share + 0.5 * target;
    o->share = fmin(fmax(s, o->min_share), o->max_share);
}

static int cmp_stale(const void *x, const void *y)
{
    const lm_stale_edge *a = x, *b = y;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return (a->iteration < b->iteration) - (a->iteration > b->iteration); /* newest first */
}

static lm_status reserve_stale(lm_oracle *o, uint32_t n)
{
    if (!LM_GROW32(&o->stale, &o->cap_stale, n, 256))
        return lm_fail(LM_E_NOMEM, "out of memory in the oracle");
    return LM_OK;
}

/* Sort by key and keep the newest entry per key. */
static void normalise(lm_oracle *o)
{
    if (o->n_stale == 0)
        return; /* o->stale may be NULL: qsort's argument must not be */
    qsort(o->stale, o->n_stale, sizeof *o->stale, cmp_stale);
    uint32_t k = 0;
    for (uint32_t i = 0; i < o->n_stale; i++)
        if (k == 0 || o->stale[k - 1].key != o->stale[i].key)
            o->stale[k++] = o->stale[i];
    o->n_stale = k;
}

lm_status lm_oracle_update_stale(lm_oracle *o, uint64_t iteration, const uint64_t *no_progress,
                                 uint32_t n, int (*touched)(const void *ctx, uint32_t v),
                                 const void *ctx)
{
    uint32_t k = 0;
    for (uint32_t i = 0; i < o->n_stale; i++) {
        const lm_stale_edge *e = &o->stale[i];
        uint32_t a = (uint32_t)(e->key >> 32), b = (uint32_t)e->key;
        if (iteration - e->iteration > o->max_age ||
            (touched && (touched(ctx, a) || touched(ctx, b))))
            continue;
        o->stale[k++] = *e;
    }
    o->n_stale = k;
    lm_status st = reserve_stale(o, k + n);
    if (st)
        return st;
    for (uint32_t i = 0; i < n; i++)
        o->stale[o->n_stale++] = (lm_stale_edge){no_progress[i], iteration};
    normalise(o);
    return LM_OK;
}

lm_status lm_oracle_set_stale(lm_oracle *o, const lm_stale_edge *e, uint32_t n)
{
    lm_status st = reserve_stale(o, n);
    if (st)
        return st;
    if (n)
        memcpy(o->stale, e, (size_t)n * sizeof *e);
    o->n_stale = n;
    normalise(o);
    return LM_OK;
}
