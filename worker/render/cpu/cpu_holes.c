/* worker/render/cpu/cpu_holes.c — a view's step A remembered for the next pass with the same
 * removed triangles (cpu_holes.h). */
#include "worker/render/cpu/cpu_holes.h"

#include <stdlib.h>
#include <string.h>

int wk_cpu_holes_match(const wk_cpu_holes *c, uint64_t seq, int occlusion, const uint32_t *removed,
                       const uint8_t *twin, uint32_t n_removed)
{
    return c->valid && c->seq == seq && c->occlusion == occlusion && c->n_removed == n_removed &&
           (n_removed == 0 || (!memcmp(c->removed, removed, n_removed * sizeof *removed) &&
                               !memcmp(c->twin, twin, n_removed)));
}

/* Room for n elements of size `elem` in *a, which holds `cap` of them now. */
static int grow(void **a, size_t elem, size_t n, size_t cap)
{
    if (n <= cap && *a)
        return 1;
    void *b = realloc(*a, (n ? n : 1) * elem);
    if (!b)
        return 0;
    *a = b;
    return 1;
}

static int reserve(wk_cpu_holes *c, uint32_t n_removed, size_t n, size_t n_tiles)
{
    size_t cr = n_removed > c->cap_removed ? n_removed : c->cap_removed;
    size_t cp = n > c->cap ? n + n / 2 : c->cap;
    size_t ct = n_tiles > c->cap_tiles ? n_tiles + n_tiles / 2 : c->cap_tiles;
    int ok = grow((void **)&c->removed, sizeof *c->removed, cr, c->cap_removed) &&
             grow((void **)&c->twin, 1, cr, c->cap_removed);
    if (ok)
        c->cap_removed = (uint32_t)cr;
    int ok_px = ok && grow((void **)&c->idx, sizeof *c->idx, cp, c->cap) &&
                grow((void **)&c->xy, sizeof *c->xy, cp, c->cap) &&
                grow((void **)&c->old, sizeof *c->old, cp, c->cap) &&
                grow((void **)&c->flag, 1, cp, c->cap);
    if (ok_px)
        c->cap = cp;
    int ok_t = ok_px && grow((void **)&c->tiles, sizeof *c->tiles, ct, c->cap_tiles);
    if (ok_t)
        c->cap_tiles = ct;
    return ok_t;
}

void wk_cpu_holes_keep(wk_cpu_holes *c, uint64_t seq, int occlusion, const uint32_t *removed,
                       const uint8_t *twin, uint32_t n_removed, const wk_cpu_log *log, size_t n,
                       const uint32_t *tiles, size_t n_tiles)
{
    c->valid = 0;
    if (n > WK_CPU_HOLES_MAX_PIXELS || !reserve(c, n_removed, n, n_tiles))
        return;
    c->seq = seq;
    c->occlusion = occlusion;
    c->n_removed = n_removed;
    if (n_removed) {
        memcpy(c->removed, removed, n_removed * sizeof *removed);
        memcpy(c->twin, twin, n_removed);
    }
    c->n = n;
    if (n) {
        memcpy(c->idx, log->idx, n * sizeof *c->idx);
        memcpy(c->xy, log->xy, n * sizeof *c->xy);
        memcpy(c->old, log->old, n * sizeof *c->old);
        memcpy(c->flag, log->flag, n);
    }
    c->n_tiles = n_tiles;
    if (n_tiles)
        memcpy(c->tiles, tiles, n_tiles * sizeof *tiles);
    c->valid = 1;
}

void wk_cpu_holes_free(wk_cpu_holes *c)
{
    void *p[] = {c->removed, c->twin, c->idx, c->xy, c->old, c->flag, c->tiles};
    for (size_t i = 0; i < sizeof p / sizeof *p; i++)
        free(p[i]);
    memset(c, 0, sizeof *c);
}
