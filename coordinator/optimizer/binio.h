/* coordinator/optimizer/binio.h — little-endian binary reading and writing for the optimizer's
 * state: integers in fixed widths, floating-point values as their raw IEEE-754 bits (so a resumed
 * run continues from bit-identical numbers). Errors are sticky: after the first failure every call
 * is a no-op and the status names the first problem. */
#ifndef LM_COORDINATOR_BINIO_H
#define LM_COORDINATOR_BINIO_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "common/error.h"

typedef struct co_bin {
    FILE *fp;
    lm_status status;
    const char *what; /* what is being read or written, for messages */
} co_bin;

void co_bin_init(co_bin *b, FILE *fp, const char *what);

void co_put_bytes(co_bin *b, const void *p, size_t n);
void co_put_u32(co_bin *b, uint32_t v);
void co_put_u64(co_bin *b, uint64_t v);
void co_put_i64(co_bin *b, int64_t v);
void co_put_f32(co_bin *b, float v);
void co_put_f64(co_bin *b, double v);

void co_get_bytes(co_bin *b, void *p, size_t n);
uint32_t co_get_u32(co_bin *b);
uint64_t co_get_u64(co_bin *b);
int64_t co_get_i64(co_bin *b);
float co_get_f32(co_bin *b);
double co_get_f64(co_bin *b);
/* Record a format error (first one wins) and return the status. */
lm_status co_bin_bad(co_bin *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
