/* common/optimizer/lane_delta.c — a start mesh record or a collapse queue as a delta against an
 * earlier one (lane_delta.h): the encoder (section by section) and the hostile-input-safe apply. */
#include "common/optimizer/lane_delta.h"

#include <stdlib.h>
#include <string.h>

#define DELTA_MAGIC 0x4c444e4cu /* "LNDL" */
#define HEAD_BYTES 16u
#define OP_BYTES 12u
#define GAP 16u     /* equal bytes fewer than this stay inside a literal (an op costs 12) */
#define SECTIONS 7u /* of a mesh record (optimizer_state.c's save_mesh) */
#define BLOCK 64u   /* equal bytes skipped a block at a time */

static uint32_t u32_at(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static void u32_to(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

/* ---- encoding ----------------------------------------------------------------------------------
 */

typedef struct builder {
    uint8_t *p;
    size_t n, cap;
    int oom;
    size_t op_at; /* the open op's header in p (0: none open) */
    uint32_t n_ops;
    uint32_t copy, lit; /* the open op's */
    size_t cursor;      /* the base cursor after the open op's copy */
} builder;

static uint8_t *grow(builder *b, size_t n)
{
    if (b->oom)
        return NULL;
    if (b->n + n > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->n + n)
            cap *= 2;
        uint8_t *p = realloc(b->p, cap);
        if (!p) {
            b->oom = 1;
            return NULL;
        }
        b->p = p;
        b->cap = cap;
    }
    uint8_t *at = b->p + b->n;
    b->n += n;
    return at;
}

static void close_op(builder *b)
{
    if (!b->op_at || b->oom)
        return;
    u32_to(b->p + b->op_at + 4, b->copy);
    u32_to(b->p + b->op_at + 8, b->lit);
    b->op_at = 0;
}

/* A new op whose copy starts at base offset `from` (>= the cursor). */
static void open_op(builder *b, size_t from)
{
    close_op(b);
    uint8_t *h = grow(b, OP_BYTES);
    if (!h)
        return;
    b->op_at = (size_t)(h - b->p);
    u32_to(h, (uint32_t)(from - b->cursor));
    b->cursor = from;
    b->copy = b->lit = 0;
    b->n_ops++;
}

static void copy(builder *b, size_t from, size_t len)
{
    if (!len)
        return;
    if (!b->op_at || b->lit || from != b->cursor)
        open_op(b, from);
    b->copy += (uint32_t)len;
    b->cursor += len;
}

static void literal(builder *b, const uint8_t *src, size_t len)
{
    if (!len)
        return;
    if (!b->op_at)
        open_op(b, b->cursor);
    uint8_t *at = grow(b, len);
    if (!at)
        return;
    memcpy(at, src, len);
    b->lit += (uint32_t)len;
}

/* Equal bytes of x and y from i, at most m. */
static size_t equal_run(const uint8_t *x, const uint8_t *y, size_t i, size_t m)
{
    size_t j = i;
    while (j + BLOCK <= m && !memcmp(x + j, y + j, BLOCK))
        j += BLOCK;
    while (j < m && x[j] == y[j])
        j++;
    return j - i;
}

/* cur's section [cs, cs + cl) against base's [bs, bs + bl): copies of equal runs, literals of
 * the rest (and of cur's bytes beyond the base's section). */
static void diff_section(builder *b, const uint8_t *base, size_t bs, size_t bl, const uint8_t *cur,
                         size_t cs, size_t cl)
{
    size_t m = bl < cl ? bl : cl, i = 0, lit_from = 0;
    while (i < m) {
        if (base[bs + i] != cur[cs + i]) {
            i++;
            continue;
        }
        size_t run = equal_run(base + bs, cur + cs, i, m);
        if (run >= GAP) {
            literal(b, cur + cs + lit_from, i - lit_from);
            copy(b, bs + i, run);
            lit_from = i + run;
        }
        i += run;
    }
    literal(b, cur + cs + lit_from, cl - lit_from);
}

/* The starts of a mesh record's sections (at[SECTIONS] = its end); 0 when r is not one. */
static int sections(const uint8_t *r, size_t n, size_t at[SECTIONS + 1])
{
    if (n < 32)
        return 0;
    uint64_t nv = u32_at(r), nw = u32_at(r + 4), nt = u32_at(r + 8);
    const uint64_t size[SECTIONS] = {32, 12 * nv, nv, 40 * nw, nw, 20 * nt, nt};
    uint64_t end = 0;
    for (uint32_t i = 0; i < SECTIONS; i++) {
        at[i] = (size_t)end;
        end += size[i];
    }
    at[SECTIONS] = (size_t)end;
    return end == n;
}

/* The delta's header written, handed out (or freed when memory ran out). */
static lm_status finish(builder *b, size_t n_base, size_t n_cur, uint8_t **out, size_t *n_out)
{
    close_op(b);
    if (b->oom) {
        free(b->p);
        return lm_fail(LM_E_NOMEM, "out of memory for a delta");
    }
    u32_to(b->p, DELTA_MAGIC);
    u32_to(b->p + 4, (uint32_t)n_base);
    u32_to(b->p + 8, (uint32_t)n_cur);
    u32_to(b->p + 12, b->n_ops);
    *out = b->p;
    *n_out = b->n;
    return LM_OK;
}

lm_status lm_lane_delta_encode(const uint8_t *base, size_t n_base, const uint8_t *cur, size_t n_cur,
                               uint8_t **out, size_t *n_out)
{
    *out = NULL;
    *n_out = 0;
    if (n_base > UINT32_MAX || n_cur > UINT32_MAX)
        return lm_fail(LM_E_INVALID, "a start mesh of more than 4 GiB");
    builder b = {.n = 0};
    grow(&b, HEAD_BYTES);
    size_t ba[SECTIONS + 1], ca[SECTIONS + 1];
    if (sections(base, n_base, ba) && sections(cur, n_cur, ca)) {
        for (uint32_t s = 0; s < SECTIONS; s++)
            diff_section(&b, base, ba[s], ba[s + 1] - ba[s], cur, ca[s], ca[s + 1] - ca[s]);
    } else {
        diff_section(&b, base, 0, n_base, cur, 0, n_cur);
    }
    return finish(&b, n_base, n_cur, out, n_out);
}

/* ---- a collapse queue's section (lane_wire.h) ---------------------------------------------- */

#define ENTRY_BYTES 24u

/* A queue's section: a count and that many entries. */
static int queue_section(const uint8_t *r, size_t n)
{
    return n >= 4 && (n - 4) % ENTRY_BYTES == 0 && u32_at(r) == (n - 4) / ENTRY_BYTES;
}

/* The order of two entries' edges (a, then b). */
static int edge_cmp(const uint8_t *x, const uint8_t *y)
{
    uint32_t xa = u32_at(x), ya = u32_at(y), xb = u32_at(x + 4), yb = u32_at(y + 4);
    return xa != ya ? (xa < ya ? -1 : 1) : xb != yb ? (xb < yb ? -1 : 1) : 0;
}

/* The two sections walked in edge order: an entry of both, unchanged, is copied; one only the
 * base has is skipped; one new or changed is a literal. An unsorted section costs bytes, never
 * correctness (the apply rebuilds cur exactly either way). */
static void diff_queue(builder *b, const uint8_t *base, size_t n_base, const uint8_t *cur,
                       size_t n_cur)
{
    if (memcmp(base, cur, 4))
        literal(b, cur, 4);
    else
        copy(b, 0, 4);
    size_t i = 4, j = 4;
    while (j < n_cur) {
        int c = i < n_base ? edge_cmp(base + i, cur + j) : 1;
        if (c < 0) {
            i += ENTRY_BYTES; /* gone */
            continue;
        }
        if (c == 0 && !memcmp(base + i, cur + j, ENTRY_BYTES))
            copy(b, i, ENTRY_BYTES);
        else
            literal(b, cur + j, ENTRY_BYTES);
        i += c == 0 ? ENTRY_BYTES : 0;
        j += ENTRY_BYTES;
    }
}

lm_status lm_lane_queue_delta_encode(const uint8_t *base, size_t n_base, const uint8_t *cur,
                                     size_t n_cur, uint8_t **out, size_t *n_out)
{
    if (!queue_section(base, n_base) || !queue_section(cur, n_cur))
        return lm_lane_delta_encode(base, n_base, cur, n_cur, out, n_out);
    *out = NULL;
    *n_out = 0;
    if (n_base > UINT32_MAX || n_cur > UINT32_MAX)
        return lm_fail(LM_E_INVALID, "a collapse queue of more than 4 GiB");
    builder b = {.n = 0};
    grow(&b, HEAD_BYTES);
    diff_queue(&b, base, n_base, cur, n_cur);
    return finish(&b, n_base, n_cur, out, n_out);
}

/* ---- applying ----------------------------------------------------------------------------------
 */

static lm_status bad(uint8_t *buf, const char *why)
{
    free(buf);
    return lm_fail(LM_E_FORMAT, "a delta %s", why);
}

lm_status lm_lane_delta_apply(const uint8_t *base, size_t n_base, const uint8_t *delta,
                              size_t n_delta, uint8_t **out, size_t *n_out)
{
    *out = NULL;
    *n_out = 0;
    if (n_delta < HEAD_BYTES || u32_at(delta) != DELTA_MAGIC)
        return bad(NULL, "without its header");
    size_t named_base = u32_at(delta + 4), len = u32_at(delta + 8);
    uint32_t n_ops = u32_at(delta + 12);
    if (named_base != n_base)
        return bad(NULL, "made for a base of another length");
    if (len > n_base + n_delta || n_ops > (n_delta - HEAD_BYTES) / OP_BYTES)
        return bad(NULL, "whose counts do not fit its bytes");
    uint8_t *buf = malloc(len ? len : 1);
    if (!buf)
        return lm_fail(LM_E_NOMEM, "out of memory for a delta's result");
    size_t at = HEAD_BYTES, cursor = 0, w = 0;
    for (uint32_t i = 0; i < n_ops; i++) {
        if (n_delta - at < OP_BYTES)
            return bad(buf, "cut short");
        size_t skip = u32_at(delta + at), cp = u32_at(delta + at + 4), lit = u32_at(delta + at + 8);
        at += OP_BYTES;
        if (skip > n_base - cursor || cp > n_base - cursor - skip || cp > len - w)
            return bad(buf, "that copies past its base or result");
        cursor += skip;
        if (cp)
            memcpy(buf + w, base + cursor, cp);
        cursor += cp;
        w += cp;
        if (lit > n_delta - at || lit > len - w)
            return bad(buf, "whose literal runs past its bytes or result");
        if (lit)
            memcpy(buf + w, delta + at, lit);
        at += lit;
        w += lit;
    }
    if (at != n_delta)
        return bad(buf, "with trailing bytes");
    if (w != len)
        return bad(buf, "shorter than the result it names");
    *out = buf;
    *n_out = len;
    return LM_OK;
}
