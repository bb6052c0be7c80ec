/* coordinator/views/views_split.c — one lm_views over k children that each own a contiguous range
 * of the views: changes of state go to every child, int64 results are summed (per-view results
 * concatenated in range order), images are read from the child that owns the view. Because every
 * result is an exact integer sum, the split is bit-identical to a single backend over all views.
 * Children are called one after the other (in-process children share the process's time anyway;
 * worker processes overlap their work in the remote backend instead). */
#include <stdlib.h>
#include <string.h>

#include "coordinator/views/views.h"

typedef struct split {
    lm_views base;
    lm_views **kids;
    uint32_t n_kids;
    uint32_t *first; /* [n_kids + 1]: view offsets of the children */
    int64_t *scratch;
    uint32_t cap_scratch;
    uint64_t seq;
    uint64_t evaluations;
} split;

static split *as_split(lm_views *v)
{
    return (split *)v;
}

/* A change of state reached every child: the split's sequence number advances. */
static lm_status changed(split *s, lm_status st)
{
    s->seq += st == LM_OK;
    return st;
}

static lm_status sp_set_mesh(lm_views *v, const lm_tri_data *tris, size_t n)
{
    split *s = as_split(v);
    lm_status st = LM_OK;
    for (uint32_t k = 0; k < s->n_kids && st == LM_OK; k++)
        st = s->kids[k]->ops->set_mesh(s->kids[k], tris, n);
    return changed(s, st);
}

static lm_status sp_set_materials(lm_views *v, const lm_material *mats, uint32_t n)
{
    split *s = as_split(v);
    lm_status st = LM_OK;
    for (uint32_t k = 0; k < s->n_kids && st == LM_OK; k++)
        st = s->kids[k]->ops->set_materials(s->kids[k], mats, n);
    return changed(s, st);
}

static lm_status sp_commit(lm_views *v, const lm_patch *patch)
{
    split *s = as_split(v);
    lm_status st = LM_OK;
    for (uint32_t k = 0; k < s->n_kids && st == LM_OK; k++)
        st = s->kids[k]->ops->commit(s->kids[k], patch);
    return changed(s, st);
}

static lm_status sp_retarget(lm_views *v)
{
    split *s = as_split(v);
    lm_status st = LM_OK;
    for (uint32_t k = 0; k < s->n_kids && st == LM_OK; k++)
        st = lm_views_retarget(s->kids[k]);
    return changed(s, st);
}

static lm_status scratch_reserve(split *s, size_t n)
{
    if (n <= s->cap_scratch)
        return LM_OK;
    int64_t *p = realloc(s->scratch, n * sizeof *p);
    if (!p)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu partial results", n);
    s->scratch = p;
    s->cap_scratch = (uint32_t)n;
    return LM_OK;
}

static lm_status sp_evaluate(lm_views *v, const lm_patch *patches, uint32_t n, int64_t *delta)
{
    split *s = as_split(v);
    lm_status st = scratch_reserve(s, n);
    memset(delta, 0, (size_t)n * sizeof *delta);
    s->evaluations += n;
    for (uint32_t k = 0; k < s->n_kids && st == LM_OK; k++) {
        st = s->kids[k]->ops->evaluate(s->kids[k], patches, n, s->scratch);
        for (uint32_t i = 0; i < n && st == LM_OK; i++)
            delta[i] += s->scratch[i];
    }
    return st;
}

static lm_status sp_energy(lm_views *v, int64_t *total, int64_t *per_view)
{
    split *s = as_split(v);
    int64_t sum = 0;
    lm_status st = LM_OK;
    for (uint32_t k = 0; k < s->n_kids && st == LM_OK; k++) {
        int64_t t = 0;
        st = s->kids[k]->ops->energy(s->kids[k], &t, per_view ? per_view + s->first[k] : NULL);
        sum += t;
    }
    if (total && st == LM_OK)
        *total = sum;
    return st;
}

static lm_status sp_potentials(lm_views *v, const float (*points)[3], size_t n, int64_t *out)
{
    split *s = as_split(v);
    lm_status st = scratch_reserve(s, n);
    memset(out, 0, n * sizeof *out);
    for (uint32_t k = 0; k < s->n_kids && st == LM_OK; k++) {
        st = s->kids[k]->ops->potentials(s->kids[k], points, n, s->scratch);
        for (size_t i = 0; i < n && st == LM_OK; i++)
            out[i] += s->scratch[i];
    }
    return st;
}

static lm_status sp_read_image(lm_views *v, lm_image_kind kind, uint32_t view, uint8_t *out)
{
    split *s = as_split(v);
    if (view >= s->first[s->n_kids])
        return lm_fail(LM_E_RANGE, "view %u of %u", view, s->first[s->n_kids]);
    uint32_t k = 0;
    while (view >= s->first[k + 1])
        k++;
    return s->kids[k]->ops->read_image(s->kids[k], kind, view - s->first[k], out);
}

static void sp_info(lm_views *v, lm_views_info *out)
{
    split *s = as_split(v);
    s->kids[0]->ops->info(s->kids[0], out);
    out->n_views = s->first[s->n_kids];
    out->seq = s->seq;
    out->evaluations = s->evaluations; /* patches, not patches x children */
    out->regions = out->region_pixels = out->tris_drawn = 0;
    for (uint32_t k = 0; k < s->n_kids; k++) {
        lm_views_info i;
        s->kids[k]->ops->info(s->kids[k], &i);
        out->regions += i.regions;
        out->region_pixels += i.region_pixels;
        out->tris_drawn += i.tris_drawn;
    }
}

static void sp_destroy(lm_views *v)
{
    split *s = as_split(v);
    for (uint32_t k = 0; k < s->n_kids; k++)
        lm_views_destroy(s->kids[k]);
    free(s->kids);
    free(s->first);
    free(s->scratch);
    free(s);
}

static const lm_views_ops split_ops = {
    .set_mesh = sp_set_mesh,
    .set_materials = sp_set_materials,
    .evaluate = sp_evaluate,
    .commit = sp_commit,
    .energy = sp_energy,
    .potentials = sp_potentials,
    .read_image = sp_read_image,
    .info = sp_info,
    .destroy = sp_destroy,
    .retarget = sp_retarget,
};

/* Children agree on what a pixel is: same size and renderer. */
static lm_status check_children(lm_views **kids, uint32_t n, uint32_t *first)
{
    lm_views_info i0, ik;
    kids[0]->ops->info(kids[0], &i0);
    first[0] = 0;
    for (uint32_t k = 0; k < n; k++) {
        kids[k]->ops->info(kids[k], &ik);
        if (ik.width != i0.width || ik.height != i0.height || strcmp(ik.renderer, i0.renderer))
            return lm_fail(LM_E_INVALID,
                           "split views: child %u (%dx%d, %s) differs from child 0 "
                           "(%dx%d, %s)",
                           k, ik.width, ik.height, ik.renderer, i0.width, i0.height, i0.renderer);
        first[k + 1] = first[k] + ik.n_views;
    }
    return LM_OK;
}

lm_status co_views_split_create(lm_views **children, uint32_t n, lm_views **out)
{
    *out = NULL;
    split *s = calloc(1, sizeof *s);
    lm_status st = s ? LM_OK : lm_fail(LM_E_NOMEM, "out of memory creating split views");
    if (st == LM_OK && n == 0)
        st = lm_fail(LM_E_INVALID, "split views need at least one child");
    if (st == LM_OK) {
        s->base.ops = &split_ops;
        s->kids = malloc(n * sizeof *s->kids);
        s->first = malloc((n + 1) * sizeof *s->first);
        if (!s->kids || !s->first)
            st = lm_fail(LM_E_NOMEM, "out of memory creating split views");
    }
    if (st == LM_OK) {
        memcpy(s->kids, children, n * sizeof *s->kids);
        s->n_kids = n;
        st = check_children(children, n, s->first);
    }
    if (st == LM_OK) {
        *out = &s->base;
        return LM_OK;
    }
    if (s && s->kids) {
        sp_destroy(&s->base);
    } else {
        for (uint32_t k = 0; k < n; k++)
            lm_views_destroy(children[k]);
        if (s)
            free(s->first);
        free(s);
    }
    return st;
}
