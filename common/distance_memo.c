/* common/distance_memo.c — the memo of distances (distance_memo.h): a direct-mapped
 * table keyed by a point's exact bits. */
#include "common/distance_memo.h"

#include <stdlib.h>
#include <string.h>

typedef struct slot {
    uint64_t key[3]; /* the point's bits */
    double sq;
    int used;
} slot;

struct lm_distance_memo {
    const lm_bvh *bvh;
    slot *slots;
    uint64_t mask;
};

lm_status lm_distance_memo_create(const lm_bvh *bvh, uint32_t log2_slots, lm_distance_memo **out)
{
    *out = NULL;
    if (!bvh || log2_slots > 24)
        return lm_fail(LM_E_INVALID, "a distance memo needs a surface and at most 2^24 slots");
    lm_distance_memo *m = calloc(1, sizeof *m);
    slot *s = calloc((size_t)1 << log2_slots, sizeof *s);
    if (!m || !s) {
        free(m);
        free(s);
        return lm_fail(LM_E_NOMEM, "out of memory for the distance memo");
    }
    m->bvh = bvh;
    m->slots = s;
    m->mask = ((uint64_t)1 << log2_slots) - 1;
    *out = m;
    return LM_OK;
}

void lm_distance_memo_destroy(lm_distance_memo *m)
{
    if (!m)
        return;
    free(m->slots);
    free(m);
}

/* A 64-bit mix of the three words (splitmix64's finaliser on a running sum). */
static uint64_t hash_of(const uint64_t k[3])
{
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < 3; i++) {
        h ^= k[i] + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        h ^= h >> 30;
        h *= 0xBF58476D1CE4E5B9ull;
        h ^= h >> 27;
        h *= 0x94D049BB133111EBull;
        h ^= h >> 31;
    }
    return h;
}

double lm_distance_memo_sq(lm_distance_memo *m, const double q[3])
{
    uint64_t k[3];
    memcpy(k, q, sizeof k);
    slot *s = &m->slots[hash_of(k) & m->mask];
    if (s->used && !memcmp(s->key, k, sizeof k))
        return s->sq;
    memcpy(s->key, k, sizeof k);
    s->sq = lm_bvh_closest_sq(m->bvh, q);
    s->used = 1;
    return s->sq;
}
