/* common/bytes.c — the growable byte buffer (common/bytes.h). */
#include "common/bytes.h"

#include <stdlib.h>
#include <string.h>

#include "common/grow.h"

void lm_bytes_put(lm_bytes *b, const void *src, size_t n)
{
    if (b->failed || n == 0)
        return;
    if (b->n + n > b->cap && !LM_GROW(&b->d, &b->cap, b->n + n, 4096)) {
        b->failed = 1;
        return;
    }
    memcpy(b->d + b->n, src, n);
    b->n += n;
}
