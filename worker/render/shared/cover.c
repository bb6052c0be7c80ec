/* worker/render/shared/cover.c — whether a patch's added triangles certainly cover the pixels of
 * its removed ones in a view (see cover.h for the argument): the boundary chain comparison and the
 * per-view orientation and clipping checks. */
#include "worker/render/shared/cover.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A directed edge between two corner positions, stored with its ends in bitwise order and the
 * sign of its direction. */
typedef struct chain_edge {
    float a[3], b[3];
    int sign;
} chain_edge;

static int edge_cmp(const void *x, const void *y)
{
    const chain_edge *e = x, *f = y;
    int c = memcmp(e->a, f->a, sizeof e->a);
    return c ? c : memcmp(e->b, f->b, sizeof e->b);
}

static void edges_of(const lm_tri_data *t, int sign, chain_edge *out)
{
    for (int k = 0; k < 3; k++) {
        const float *p = t->c[k].pos, *q = t->c[(k + 1) % 3].pos;
        int swap = memcmp(p, q, 3 * sizeof *p) > 0;
        memcpy(out[k].a, swap ? q : p, sizeof out[k].a);
        memcpy(out[k].b, swap ? p : q, sizeof out[k].b);
        out[k].sign = swap ? -sign : sign;
    }
}

/* A triangle's corner positions rotated to start at the bitwise least corner (the same cyclic
 * order, so twins compare equal), with where it came from. */
typedef struct tri_key {
    float p[3][3];
    uint32_t index; /* into the twin array */
    int added;
} tri_key;

static int key_cmp(const void *x, const void *y)
{
    const tri_key *a = x, *b = y;
    int c = memcmp(a->p, b->p, sizeof a->p);
    return c ? c : a->added - b->added;
}

static void key_of(const lm_tri_data *t, uint32_t index, int added, tri_key *out)
{
    int first = 0;
    for (int k = 1; k < 3; k++)
        if (memcmp(t->c[k].pos, t->c[first].pos, sizeof t->c[k].pos) < 0)
            first = k;
    for (int k = 0; k < 3; k++)
        memcpy(out->p[k], t->c[(first + k) % 3].pos, sizeof out->p[k]);
    out->index = index;
    out->added = added;
}

static lm_status reserve(void **buf, size_t *cap, size_t need)
{
    if (need <= *cap)
        return LM_OK;
    void *b = realloc(*buf, need);
    if (!b)
        return lm_fail(LM_E_NOMEM, "out of memory for %zu bytes of patch geometry", need);
    *buf = b;
    *cap = need;
    return LM_OK;
}

/* Marks twin pairs: keys sorted, in each run of equal positions the removed ones pair with the
 * added ones. */
static void mark_twins(tri_key *k, size_t n, uint8_t *twin)
{
    qsort(k, n, sizeof *k, key_cmp);
    for (size_t i = 0; i < n;) {
        size_t j = i, n_rem = 0;
        while (j < n && !memcmp(k[i].p, k[j].p, sizeof k[i].p))
            n_rem += !k[j++].added;
        size_t pairs = n_rem < j - i - n_rem ? n_rem : j - i - n_rem;
        for (size_t a = 0; a < pairs; a++) {
            twin[k[i + a].index] = 1;         /* removed ones sort first */
            twin[k[i + n_rem + a].index] = 1; /* then the added ones */
        }
        i = j;
    }
}

static int boundary_cancels(chain_edge *e, size_t n)
{
    if (n > 1)
        qsort(e, n, sizeof *e, edge_cmp);
    for (size_t i = 0; i < n;) {
        size_t j = i;
        int sum = 0;
        while (j < n && !edge_cmp(&e[i], &e[j]))
            sum += e[j++].sign;
        if (sum != 0)
            return 0;
        i = j;
    }
    return 1;
}

lm_status wk_cover_patch_prepare(wk_cover_patch *cp, const lm_tri_data *const *removed,
                                 uint32_t n_removed, const lm_tri_data *added, uint32_t n_added)
{
    size_t n = (size_t)n_removed + n_added;
    size_t bytes =
        n * (sizeof(tri_key) > 3 * sizeof(chain_edge) ? sizeof(tri_key) : 3 * sizeof(chain_edge));
    lm_status st = reserve((void **)&cp->twin, &cp->cap_twin, n + 1);
    if (st == LM_OK)
        st = reserve(&cp->scratch, &cp->cap_scratch, bytes + 1);
    if (st != LM_OK)
        return st;
    memset(cp->twin, 0, n);
    tri_key *k = cp->scratch;
    for (uint32_t i = 0; i < n_removed; i++)
        key_of(removed[i], i, 0, &k[i]);
    for (uint32_t i = 0; i < n_added; i++)
        key_of(&added[i], n_removed + i, 1, &k[n_removed + i]);
    mark_twins(k, n, cp->twin);
    chain_edge *e = cp->scratch;
    size_t m = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (cp->twin[i])
            continue;
        if (i < n_removed)
            edges_of(removed[i], 1, e + m);
        else
            edges_of(&added[i - n_removed], -1, e + m);
        m += 3;
    }
    cp->same_boundary = boundary_cancels(e, m);
    return LM_OK;
}

void wk_cover_patch_free(wk_cover_patch *cp)
{
    free(cp->twin);
    free(cp->scratch);
    *cp = (wk_cover_patch){0};
}

/* Far more than the rasteriser's snapping (1/256 px) and the difference of its float projection
 * from ours: an orientation decided with this margin is the rasteriser's too. */
#define WK_COVER_SNAP 0.01f
/* Corners this far inside the depth range and within a view's size of the view are not clipped. */
#define WK_COVER_DEPTH_MARGIN 1e-4f

static int corner_unclipped(const wk_cover *c, const float win[2])
{
    return win[0] > -(float)c->width && win[0] < 2.0f * (float)c->width &&
           win[1] > -(float)c->height && win[1] < 2.0f * (float)c->height;
}

lm_status wk_cover_begin(wk_cover *c, const wk_cover_patch *cp, size_t n_tris, int width,
                         int height)
{
    c->same_boundary = cp->same_boundary;
    c->n = 0;
    c->width = width;
    c->height = height;
    return reserve((void **)&c->tris, &c->cap_bytes, n_tris * sizeof *c->tris);
}

void wk_cover_free(wk_cover *c)
{
    free(c->tris);
    *c = (wk_cover){0};
}

/* The orientation of footprint f as the rasteriser sees it: +1 or -1, 0 when clipping may touch
 * it or the margin does not decide. */
static int footprint_sign(const wk_cover *c, const wk_footprint *f)
{
    if (!f->projected || !(f->zmin > WK_COVER_DEPTH_MARGIN) ||
        !(f->zmax < 1.0f - WK_COVER_DEPTH_MARGIN) || !corner_unclipped(c, f->win[0]) ||
        !corner_unclipped(c, f->win[1]) || !corner_unclipped(c, f->win[2]))
        return 0;
    const float(*w)[2] = f->win;
    double e1x = w[1][0] - w[0][0], e1y = w[1][1] - w[0][1];
    double e2x = w[2][0] - w[0][0], e2y = w[2][1] - w[0][1];
    double cross = e1x * e2y - e1y * e2x;
    double perim =
        fabs(e1x) + fabs(e1y) + fabs(e2x) + fabs(e2y) + fabs(e2x - e1x) + fabs(e2y - e1y);
    /* moving each corner by up to WK_COVER_SNAP per axis changes cross by less than this */
    double slack = 4.0 * WK_COVER_SNAP * perim + 16.0 * WK_COVER_SNAP * WK_COVER_SNAP;
    return cross > slack ? 1 : cross < -slack ? -1 : 0;
}

void wk_cover_feed(wk_cover *c, const wk_footprint *f, int added)
{
    if (!c->same_boundary || wk_rect_empty(&f->rect))
        return; /* an empty rectangle: the triangle covers no pixel of the view */
    LM_ASSERT((c->n + 1) * sizeof *c->tris <= c->cap_bytes);
    c->tris[c->n++] = (wk_cover_tri){f->rect, f->zmax, footprint_sign(c, f), added};
}

int wk_cover_front_of(const wk_cover *c, const wk_rect *r, float z)
{
    if (!c->same_boundary)
        return 0;
    int sign = 0;
    for (size_t i = 0; i < c->n; i++) {
        const wk_cover_tri *t = &c->tris[i];
        if (!wk_rects_meet(&t->rect, r))
            continue;
        if (t->sign == 0 || (sign && t->sign != sign) || (t->added && !(t->zmax < z)))
            return 0;
        sign = t->sign;
    }
    return 1;
}
