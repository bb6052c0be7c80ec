/* coordinator/simplify/simplify_qem.c — QEM simplification through meshoptimizer 0.18
 * (meshopt_simplify: Garland– Heckbert quadrics, edge collapses onto existing vertices, topology
 * preserving, no attribute metric in this version).
 *
 * meshoptimizer sees one vertex per (wedge, material, part). Its seam detection treats vertices
 * that share a position as one point with several attribute sets and keeps the seam edges they
 * form, so UV/normal seams, material and part boundaries survive. It aims at an index count; we
 * want a number of live vertices, so the index budget is searched (secant steps inside a bracket)
 * until the vertex count is within CO_SIMPLIFY_TOLERANCE. No error limit is used. For large inputs
 * a first pass cuts the mesh to about three times the target, and the search runs on that. A part
 * the search's result lost altogether (a small open part collapses to nothing) comes back at its
 * smallest non-empty form, simplified alone: no part disappears silently. */
#include <float.h>
#include <meshoptimizer.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/grow.h"
#include "coordinator/simplify/simplify_internal.h"

#define QEM_NO_ERROR_LIMIT 1e10f /* relative error; anything above ~2 means "no limit" */
#define QEM_MAX_PASSES 14

/* The vertex buffer handed to meshoptimizer: one entry per (wedge, material, part). */
typedef struct qem_input {
    float (*pos)[3]; /* [n_entries] position of the entry's vertex */
    uint32_t *wedge; /* [n_entries] input wedge id */
    uint32_t *mat;   /* [n_entries] material */
    uint32_t *part;  /* [n_entries] part */
    uint32_t n_entries, cap;
    uint32_t *indices; /* [n_indices] entries, 3 per alive input triangle */
    size_t n_indices;
} qem_input;

typedef struct qem_search {
    const lm_mesh *in;
    const qem_input *qi;
    uint32_t target;
    uint32_t *stamp; /* [in->n_verts] pass number that last counted the vertex */
    uint32_t pass;
    uint32_t runs;     /* simplifier runs */
    uint32_t *scratch; /* [n_indices] result of the current pass */
    uint32_t *best;    /* [n_indices] best result so far */
    size_t best_count;
    uint32_t best_verts;
} qem_search;

static void qem_input_free(qem_input *q)
{
    free(q->pos);
    free(q->wedge);
    free(q->mat);
    free(q->part);
    free(q->indices);
    memset(q, 0, sizeof *q);
}

static lm_status entry_add(qem_input *q, const lm_mesh *in, uint32_t w, const lm_tri *t)
{
    if (q->n_entries == q->cap) {
        size_t cap = lm_grow_cap(q->cap, (size_t)q->n_entries + 1, 1024, UINT32_MAX);
        if (!cap || !LM_RESIZE(&q->pos, cap) || !LM_RESIZE(&q->wedge, cap) ||
            !LM_RESIZE(&q->mat, cap) || !LM_RESIZE(&q->part, cap))
            return lm_fail(LM_E_NOMEM, "out of memory preparing QEM input");
        q->cap = (uint32_t)cap;
    }
    memcpy(q->pos[q->n_entries], in->pos[in->wedges[w].vertex], sizeof q->pos[0]);
    q->wedge[q->n_entries] = w;
    q->mat[q->n_entries] = t->material;
    q->part[q->n_entries] = t->part;
    q->n_entries++;
    return LM_OK;
}

/* Entry of (w, t's material and part): first[w] starts a chain through next[] of entries of the
 * same wedge. */
static lm_status entry_of(qem_input *q, const lm_mesh *in, uint32_t *first, uint32_t **next,
                          uint32_t w, const lm_tri *t, uint32_t *out)
{
    uint32_t e = first[w], prev = LM_NONE;
    for (; e != LM_NONE; prev = e, e = (*next)[e])
        if (q->mat[e] == t->material && q->part[e] == t->part) {
            *out = e;
            return LM_OK;
        }
    e = q->n_entries;
    lm_status s = entry_add(q, in, w, t);
    if (s)
        return s;
    uint32_t *nx = realloc(*next, (size_t)q->cap * sizeof *nx);
    if (!nx)
        return lm_fail(LM_E_NOMEM, "out of memory preparing QEM input");
    *next = nx;
    nx[e] = LM_NONE;
    if (prev == LM_NONE)
        first[w] = e;
    else
        nx[prev] = e;
    *out = e;
    return LM_OK;
}

static lm_status qem_input_build(const lm_mesh *in, qem_input *q)
{
    memset(q, 0, sizeof *q);
    uint32_t *first = malloc(((size_t)in->n_wedges + 1) * sizeof *first);
    uint32_t *next = NULL;
    q->indices = malloc(((size_t)in->live_tris * 3 + 3) * sizeof *q->indices);
    lm_status s = first && q->indices ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory preparing QEM");
    for (uint32_t w = 0; w < in->n_wedges && first; w++)
        first[w] = LM_NONE;
    for (uint32_t t = 0; t < in->n_tris && !s; t++) {
        if (!in->tri_alive[t])
            continue;
        for (int k = 0; k < 3 && !s; k++)
            s = entry_of(q, in, first, &next, in->tris[t].w[k], &in->tris[t],
                         &q->indices[q->n_indices++]);
    }
    free(first);
    free(next);
    if (s)
        qem_input_free(q);
    return s;
}

/* Live vertices of an index buffer (triangles repeating a vertex do not count). */
static uint32_t count_verts(qem_search *S, const uint32_t *idx, size_t n)
{
    const lm_mesh *in = S->in;
    uint32_t stamp = ++S->pass, count = 0;
    for (size_t i = 0; i + 2 < n; i += 3) {
        uint32_t v[3];
        for (int k = 0; k < 3; k++)
            v[k] = in->wedges[S->qi->wedge[idx[i + k]]].vertex;
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
            continue;
        for (int k = 0; k < 3; k++)
            if (S->stamp[v[k]] != stamp) {
                S->stamp[v[k]] = stamp;
                count++;
            }
    }
    return count;
}

/* One simplifier run from `src` to an index budget; returns the result's size and vertices. */
static size_t run_pass(qem_search *S, const uint32_t *src, size_t n_src, size_t budget,
                       uint32_t *verts)
{
    size_t n = meshopt_simplify(S->scratch, src, n_src, &S->qi->pos[0][0], S->qi->n_entries,
                                sizeof S->qi->pos[0], budget, QEM_NO_ERROR_LIMIT, 0, NULL);
    S->runs++;
    *verts = count_verts(S, S->scratch, n);
    uint64_t d_new = *verts > S->target ? *verts - S->target : S->target - *verts;
    uint64_t d_old =
        S->best_verts > S->target ? S->best_verts - S->target : S->target - S->best_verts;
    if (S->best_count == 0 || d_new < d_old) {
        memcpy(S->best, S->scratch, n * sizeof *S->best);
        S->best_count = n;
        S->best_verts = *verts;
    }
    return n;
}

static int close_enough(uint32_t v, uint32_t target, uint32_t pass)
{
    double d = (double)v - (double)target;
    d = d < 0 ? -d : d;
    return d <= 1.0 || d <= 0.015 * target || (pass >= 5 && co_simplify_within(v, target));
}

/* Next budget: secant step inside the bracket, kept away from its ends so the bracket shrinks. */
static size_t next_budget(size_t lo, uint32_t v_lo, size_t hi, uint32_t v_hi, uint32_t target)
{
    double f = v_hi > v_lo ? ((double)target - v_lo) / ((double)v_hi - v_lo) : 0.5;
    f = f < 0.05 ? 0.05 : f > 0.95 ? 0.95 : f;
    size_t b = lo + (size_t)(f * (double)(hi - lo));
    b -= b % 3;
    return b <= lo ? lo + 3 : b;
}

/* Search the index budget on `src` (v_src vertices). Sets *stuck when the simplifier cannot go
 * below the target (topology). The best result is in S->best. */
static void search(qem_search *S, const uint32_t *src, size_t n_src, uint32_t v_src, size_t guess,
                   int *stuck)
{
    size_t lo = 0, hi = n_src;
    uint32_t v_lo = 0, v_hi = v_src;
    size_t budget = guess < 3 ? 3 : guess > n_src ? n_src : guess;
    budget -= budget % 3;
    *stuck = 0;
    for (uint32_t pass = 0; pass < QEM_MAX_PASSES; pass++) {
        uint32_t v;
        size_t n = run_pass(S, src, n_src, budget, &v);
        if (close_enough(v, S->target, pass))
            return;
        if (v > S->target) {
            if (n > budget) { /* stopped short: nothing smaller is reachable */
                *stuck = 1;
                return;
            }
            hi = budget;
            v_hi = v;
        } else {
            lo = budget;
            v_lo = v;
        }
        if (hi <= lo + 3)
            return;
        budget = next_budget(lo, v_lo, hi, v_hi, S->target);
    }
}

/* 1 when idx[i..i+3) is a triangle of three distinct vertices (what the output keeps). */
static int proper(const qem_search *S, const uint32_t *idx, size_t i)
{
    uint32_t v[3];
    for (int k = 0; k < 3; k++)
        v[k] = S->in->wedges[S->qi->wedge[idx[i + k]]].vertex;
    return v[0] != v[1] && v[1] != v[2] && v[0] != v[2];
}

/* parts[p] = 1 where triangles of idx[0..n) put part p on the output. */
static void mark_parts(const qem_search *S, const uint32_t *idx, size_t n, uint8_t *parts)
{
    for (size_t i = 0; i + 2 < n; i += 3)
        if (proper(S, idx, i) && S->qi->part[idx[i]] < S->in->n_parts)
            parts[S->qi->part[idx[i]]] = 1;
}

/* One part alone (its triangles in sub[0..n_sub)) at the smallest index budget whose result keeps
 * a triangle: the result appended to dst at *n_dst. */
static void smallest_part(const qem_search *S, const uint32_t *sub, size_t n_sub, uint32_t *dst,
                          size_t *n_dst)
{
    const qem_input *q = S->qi;
    for (size_t budget = 3;; budget += 3 * (budget / 12 + 1)) {
        budget = budget > n_sub ? n_sub : budget;
        size_t n = meshopt_simplify(dst + *n_dst, sub, n_sub, &q->pos[0][0], q->n_entries,
                                    sizeof q->pos[0], budget, QEM_NO_ERROR_LIMIT, 0, NULL);
        int kept = 0;
        for (size_t i = 0; i + 2 < n && !kept; i += 3)
            kept = proper(S, dst + *n_dst, i);
        if (kept || budget >= n_sub) {
            *n_dst += n;
            return;
        }
    }
}

/* Every part of the input that S->best lost comes back at its smallest form (appended to
 * S->best, which is reallocated); *kept counts them. */
static lm_status keep_parts(qem_search *S, uint32_t *kept)
{
    const lm_mesh *in = S->in;
    const qem_input *q = S->qi;
    *kept = 0;
    if (in->n_parts < 2)
        return LM_OK;
    uint8_t *had = calloc(in->n_parts, 1), *has = calloc(in->n_parts, 1);
    uint32_t *sub = malloc((q->n_indices + 3) * sizeof *sub);
    uint32_t *best = realloc(S->best, (S->best_count + q->n_indices + 3) * sizeof *best);
    if (best)
        S->best = best;
    lm_status s = had && has && sub && best ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory");
    if (s == LM_OK) {
        mark_parts(S, q->indices, q->n_indices, had);
        mark_parts(S, S->best, S->best_count, has);
    }
    for (uint32_t p = 0; s == LM_OK && p < in->n_parts; p++) {
        if (!had[p] || has[p])
            continue;
        size_t n_sub = 0;
        for (size_t i = 0; i + 2 < q->n_indices; i += 3)
            if (q->part[q->indices[i]] == p) {
                memcpy(sub + n_sub, q->indices + i, 3 * sizeof *sub);
                n_sub += 3;
            }
        smallest_part(S, sub, n_sub, S->best, &S->best_count);
        (*kept)++;
    }
    free(had);
    free(has);
    free(sub);
    return s;
}

/* Turn the best index buffer into the output mesh. */
static lm_status emit(const lm_mesh *in, const qem_input *q, const uint32_t *idx, size_t n,
                      uint32_t *dropped, lm_mesh **out)
{
    lm_tri *tris = malloc((n / 3 + 1) * sizeof *tris);
    if (!tris)
        return lm_fail(LM_E_NOMEM, "out of memory building the simplified mesh");
    for (size_t t = 0; t < n / 3; t++) {
        for (int k = 0; k < 3; k++)
            tris[t].w[k] = q->wedge[idx[3 * t + k]];
        tris[t].material = q->mat[idx[3 * t]];
        tris[t].part = q->part[idx[3 * t]];
    }
    lm_status s = co_simplify_build_from_tris(in, tris, n / 3, dropped, out);
    free(tris);
    if (!s && !(in->attrs & LM_ATTR_NORMAL))
        lm_mesh_compute_normals(*out);
    return s;
}

static lm_status search_all(qem_search *S, size_t n_full, int *stuck)
{
    const qem_input *q = S->qi;
    uint32_t v_full = count_verts(S, q->indices, n_full);
    size_t guess = (size_t)((double)n_full * S->target / (v_full ? v_full : 1));
    if (n_full > 8 * guess) {
        /* Cut to about 3x the target first; the search then runs on the smaller buffer. */
        uint32_t *pre = malloc(n_full * sizeof *pre);
        if (!pre)
            return lm_fail(LM_E_NOMEM, "out of memory in the QEM search");
        size_t n_pre = meshopt_simplify(pre, q->indices, n_full, &q->pos[0][0], q->n_entries,
                                        sizeof q->pos[0], 3 * guess, QEM_NO_ERROR_LIMIT, 0, NULL);
        uint32_t v_pre = count_verts(S, pre, n_pre);
        S->runs++;
        if (v_pre > S->target)
            search(S, pre, n_pre, v_pre, guess, stuck);
        free(pre);
        if (v_pre > S->target)
            return LM_OK;
    }
    search(S, q->indices, n_full, v_full, guess, stuck);
    return LM_OK;
}

lm_status co_simplify_qem(const lm_mesh *in, uint32_t target_verts, co_simplify_stats *stats,
                          lm_mesh **out)
{
    *out = NULL;
    qem_input q;
    lm_status s = qem_input_build(in, &q);
    if (s)
        return s;
    qem_search S = {.in = in, .qi = &q, .target = target_verts};
    S.stamp = calloc((size_t)in->n_verts + 1, sizeof *S.stamp);
    S.scratch = malloc((q.n_indices + 3) * sizeof *S.scratch);
    S.best = malloc((q.n_indices + 3) * sizeof *S.best);
    int stuck = 0;
    uint32_t dropped = 0, kept = 0;
    if (!S.stamp || !S.scratch || !S.best)
        s = lm_fail(LM_E_NOMEM, "out of memory in the QEM search (%zu indices)", q.n_indices);
    if (!s)
        s = search_all(&S, q.n_indices, &stuck);
    if (!s)
        s = keep_parts(&S, &kept);
    if (!s)
        s = emit(in, &q, S.best, S.best_count, &dropped, out);
    if (stats) {
        memset(stats, 0, sizeof *stats);
        stats->passes = S.runs;
        stats->degenerate_removed = dropped;
    }
    free(S.stamp);
    free(S.scratch);
    free(S.best);
    qem_input_free(&q);
    if (s || co_simplify_reached((*out)->live_verts, target_verts))
        return s;
    char also[128] = ""; /* the parts kept, when any */
    if (kept)
        snprintf(also, sizeof also, " (with %u part%s QEM would have removed, kept at %s smallest)",
                 kept, kept == 1 ? "" : "s", kept == 1 ? "its" : "their");
    if (stuck)
        return lm_fail(LM_E_RANGE,
                       "QEM stopped at %u vertices%s (target %u): the topology (closed small "
                       "parts, seams) allows no further edge collapses; --method cluster goes "
                       "further",
                       (*out)->live_verts, also, target_verts);
    if (kept)
        return lm_fail(LM_E_RANGE, "QEM reached %u vertices at best%s, above the target %u",
                       (*out)->live_verts, also, target_verts);
    return lm_fail(LM_E_RANGE, "QEM reached %u vertices at best, above the target %u",
                   (*out)->live_verts, target_verts);
}
