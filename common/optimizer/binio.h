/* common/optimizer/binio.h — little-endian binary reading and writing for the optimizer's
 * state: integers in fixed widths, floating-point values as their raw IEEE-754 bits (so a resumed
 * run continues from bit-identical numbers). Errors are sticky: after the first failure every call
 * is a no-op and the status names the first problem. */
#ifndef LM_COMMON_OPTIMIZER_BINIO_H
#define LM_COMMON_OPTIMIZER_BINIO_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "common/error.h"

typedef struct lm_bin {
    FILE *fp; /* NULL: the bytes are in memory (lm_bin_init_writer, lm_bin_init_reader) */
    lm_status status;
    const char *what;  /* what is being read or written, for messages */
    uint8_t *out;      /* a writer's bytes so far (malloc'd, grown; lm_bin_take hands them over) */
    const uint8_t *in; /* a reader's bytes (borrowed) */
    size_t pos, cap;   /* a writer: bytes written, allocated; a reader: bytes read, in all */
} lm_bin;

/* 1 where the host's integers and floats are the streams' little-endian layout, so an array of
 * them (with no padding) may be written as its raw bytes: the same bytes, one call. */
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define LM_BIN_HOST_LE 1
#else
#define LM_BIN_HOST_LE 0
#endif

/* A stream over fp (not owned). */
void lm_bin_init(lm_bin *b, FILE *fp, const char *what);
/* A stream into memory: the same bytes a FILE stream would get, without stdio's cost per call.
 * Never blocks; out of memory is the stream's status. Finish it with lm_bin_take. */
void lm_bin_init_writer(lm_bin *b, const char *what);
/* A writer's bytes: *buf (malloc'd, caller frees; non-NULL even when empty) and *len, and its
 * status; on a failure nothing is handed over (*buf NULL, *len 0) and the bytes are freed. */
lm_status lm_bin_take(lm_bin *b, uint8_t **buf, size_t *len);
/* A stream reading buf[0..len) (borrowed, must outlive b). Reading past the end is "truncated". */
void lm_bin_init_reader(lm_bin *b, const uint8_t *buf, size_t len, const char *what);
/* Bytes a reader has left; UINT64_MAX for a FILE stream that cannot tell (not seekable). */
uint64_t lm_bin_left(lm_bin *b);

void lm_put_bytes(lm_bin *b, const void *p, size_t n);
void lm_put_u32(lm_bin *b, uint32_t v);
void lm_put_u64(lm_bin *b, uint64_t v);
void lm_put_i64(lm_bin *b, int64_t v);
void lm_put_f32(lm_bin *b, float v);
void lm_put_f64(lm_bin *b, double v);

void lm_get_bytes(lm_bin *b, void *p, size_t n);
uint32_t lm_get_u32(lm_bin *b);
uint64_t lm_get_u64(lm_bin *b);
int64_t lm_get_i64(lm_bin *b);
float lm_get_f32(lm_bin *b);
double lm_get_f64(lm_bin *b);
/* Record a format error (first one wins) and return the status. */
lm_status lm_bin_bad(lm_bin *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
