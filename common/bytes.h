/* common/bytes.h — a growable byte buffer for writers that build a file or a message in memory
 * (GLB files, wire assets), and the little-endian reader of binary headers. A failed allocation is
 * remembered, not reported at once: the writer appends freely and checks `failed` once at the end.
 * The caller owns `d` (free it). */
#ifndef LUMESH_COMMON_BYTES_H
#define LUMESH_COMMON_BYTES_H

#include <stddef.h>
#include <stdint.h>

typedef struct lm_bytes {
    uint8_t *d;
    size_t n, cap;
    int failed; /* an allocation failed: d holds what came before, later puts do nothing */
} lm_bytes;

/* Append n bytes of src (doubling the capacity from 4 KiB as needed). */
void lm_bytes_put(lm_bytes *b, const void *src, size_t n);

/* The little-endian 32-bit number at p (GLB and STL headers). */
static inline uint32_t lm_le32(const void *p)
{
    const uint8_t *u = (const uint8_t *)p;
    return (uint32_t)u[0] | (uint32_t)u[1] << 8 | (uint32_t)u[2] << 16 | (uint32_t)u[3] << 24;
}

#endif
