/* coordinator/job/checkpoint.c — checkpoint file format, atomic write and verified read. */
#include "coordinator/job/checkpoint.h"

#include <errno.h>
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "common/io/atomic_file.h"
#include "common/io/mesh_io.h"
#include "common/view.h"
#include "coordinator/job/schedule.h"

static const char co_magic[8] = {'L', 'U', 'M', 'E', 'S', 'H', 'C', 'K'};

enum {
    CO_KEY_BYTES_V3 = 64,
    CO_KEY_BYTES_V2 = 48, /* version 2: no view distribution, no camera hash (sphere views) */
    CO_KEY_BYTES_V4 = 80, /* version 4: the validation's options after version 3's key */
    CO_KEY_BYTES = 96,    /* version 5: the view schedule after version 4's key */
    CO_HEADER_BYTES = 8 + 4 + 4 + CO_KEY_BYTES + 8,
    CO_TRAILER_BYTES = 8,
};

/* Bytes before the payload for a key of key_bytes. */
static size_t header_bytes(uint32_t key_bytes)
{
    return 8 + 4 + 4 + (size_t)key_bytes + 8;
}

uint64_t co_fnv1a(uint64_t h, const void *data, size_t n)
{
    const uint8_t *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

lm_status co_checkpoint_hash_file(const char *path, uint64_t *out)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return lm_fail(LM_E_IO, "cannot read '%s': %s", path, strerror(errno));
    uint8_t buf[1 << 16];
    uint64_t h = CO_FNV_OFFSET;
    size_t n = 0;
    while ((n = fread(buf, 1, sizeof buf, fp)) > 0)
        h = co_fnv1a(h, buf, n);
    int bad = ferror(fp);
    fclose(fp);
    if (bad)
        return lm_fail(LM_E_IO, "error reading '%s'", path);
    *out = h;
    return LM_OK;
}

static void put_u32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static void put_u64(uint8_t *p, uint64_t v)
{
    for (int i = 0; i < 8; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t get_u32(const uint8_t *p)
{
    uint32_t v = 0;
    for (int i = 0; i < 4; i++)
        v |= (uint32_t)p[i] << (8 * i);
    return v;
}

static uint64_t get_u64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++)
        v |= (uint64_t)p[i] << (8 * i);
    return v;
}

/* The version a key is written in: 3 (its bytes as ever) unless the job validates (4) or grows
 * its views (5). */
static uint32_t key_version(const co_checkpoint_key *key)
{
    return key->view_schedule ? CO_CHECKPOINT_VERSION : key->validate_every ? 4u : 3u;
}

static uint32_t version_key_bytes(uint32_t version)
{
    return version == 2   ? CO_KEY_BYTES_V2
           : version == 3 ? CO_KEY_BYTES_V3
           : version == 4 ? CO_KEY_BYTES_V4
                          : CO_KEY_BYTES;
}

/* Writes the header; returns its size. */
static size_t encode_header(uint8_t *h, const co_checkpoint_key *key, uint64_t payload_len)
{
    uint32_t version = key_version(key), kb = version_key_bytes(version);
    memcpy(h, co_magic, 8);
    put_u32(h + 8, version);
    put_u32(h + 12, kb);
    uint8_t *k = h + 16;
    put_u64(k, key->original_hash);
    put_u64(k + 8, key->initial_hash);
    put_u64(k + 16, key->seed);
    put_u32(k + 24, key->target_verts);
    put_u32(k + 28, key->views);
    put_u32(k + 32, key->size);
    put_u32(k + 36, key->attrs);
    put_u64(k + 40, key->regrid_every);
    put_u32(k + 48, key->view_dist);
    put_u32(k + 52, 0);
    put_u64(k + 56, key->cameras_hash);
    if (kb > CO_KEY_BYTES_V3) {
        put_u64(k + 64, key->validate_every);
        put_u32(k + 72, key->validate_views);
        put_u32(k + 76, key->validate_patience);
    }
    if (kb > CO_KEY_BYTES_V4) {
        put_u32(k + 80, key->view_schedule);
        put_u32(k + 84, 0);
        put_u64(k + 88, key->schedule_evals);
    }
    put_u64(h + 16 + kb, payload_len);
    return header_bytes(kb);
}

static void decode_key(const uint8_t *k, uint32_t key_bytes, co_checkpoint_key *key)
{
    key->original_hash = get_u64(k);
    key->initial_hash = get_u64(k + 8);
    key->seed = get_u64(k + 16);
    key->target_verts = get_u32(k + 24);
    key->views = get_u32(k + 28);
    key->size = get_u32(k + 32);
    key->attrs = get_u32(k + 36);
    key->regrid_every = get_u64(k + 40);
    key->view_dist = key_bytes > CO_KEY_BYTES_V2 ? get_u32(k + 48) : LM_VIEW_DIST_SPHERE;
    key->cameras_hash = key_bytes > CO_KEY_BYTES_V2 ? get_u64(k + 56) : 0;
    key->validate_every = key_bytes > CO_KEY_BYTES_V3 ? get_u64(k + 64) : 0;
    key->validate_views = key_bytes > CO_KEY_BYTES_V3 ? get_u32(k + 72) : 0;
    key->validate_patience = key_bytes > CO_KEY_BYTES_V3 ? get_u32(k + 76) : 0;
    key->view_schedule = key_bytes > CO_KEY_BYTES_V4 ? get_u32(k + 80) : 0;
    key->schedule_evals = key_bytes > CO_KEY_BYTES_V4 ? get_u64(k + 88) : 0;
}

uint64_t co_checkpoint_hash_cameras(const lm_view_spec *views)
{
    if (views->dist != LM_VIEW_DIST_CAMERAS)
        return 0;
    uint64_t h = CO_FNV_OFFSET;
    for (uint32_t i = 0; i < views->count; i++) {
        const lm_camera *c = &views->cameras[i];
        const float *f[4] = {c->position, c->target, c->up, &c->fov_deg};
        for (int k = 0; k < 10; k++) {
            uint32_t bits;
            uint8_t b[4];
            memcpy(&bits, k < 9 ? &f[k / 3][k % 3] : f[3], 4);
            put_u32(b, bits);
            h = co_fnv1a(h, b, 4);
        }
    }
    return h;
}

/* Run the payload writer into memory. */
static lm_status render_payload(co_checkpoint_save_fn save, const void *ctx, char **buf,
                                size_t *len)
{
    *buf = NULL;
    *len = 0;
    FILE *ms = open_memstream(buf, len);
    if (!ms)
        return lm_fail(LM_E_NOMEM, "cannot allocate the checkpoint buffer");
    lm_status st = save(ctx, ms);
    if (fclose(ms) != 0 && st == LM_OK)
        st = lm_fail(LM_E_NOMEM, "cannot allocate the checkpoint buffer");
    if (st != LM_OK) {
        free(*buf);
        *buf = NULL;
    }
    return st;
}

static lm_status write_all(lm_atomic_file *af, const char *path, const void *data, size_t n)
{
    if (n && fwrite(data, 1, n, (FILE *)af->fp) != n)
        return lm_fail(LM_E_IO, "cannot write checkpoint '%s': %s", path, strerror(errno));
    return LM_OK;
}

lm_status co_checkpoint_write(const char *path, const co_checkpoint_key *key,
                              co_checkpoint_save_fn save, const void *ctx)
{
    char *payload;
    size_t len;
    lm_status st = render_payload(save, ctx, &payload, &len);
    if (st != LM_OK)
        return st;
    uint8_t header[CO_HEADER_BYTES], trailer[CO_TRAILER_BYTES];
    size_t head = encode_header(header, key, len);
    uint64_t sum = co_fnv1a(co_fnv1a(CO_FNV_OFFSET, header, head), payload, len);
    put_u64(trailer, sum);

    lm_atomic_file af;
    st = lm_atomic_open(&af, path);
    if (st == LM_OK) {
        st = write_all(&af, path, header, head);
        if (st == LM_OK)
            st = write_all(&af, path, payload, len);
        if (st == LM_OK)
            st = write_all(&af, path, trailer, sizeof trailer);
        if (st == LM_OK)
            st = lm_atomic_commit(&af);
        else
            lm_atomic_abort(&af);
    }
    free(payload);
    return st;
}

/* Read the whole file (bounded). */
static lm_status slurp(const char *path, uint8_t **data, size_t *len)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return lm_fail(LM_E_IO, "cannot open checkpoint '%s': %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fileno(fp), &sb) != 0 || !S_ISREG(sb.st_mode)) {
        fclose(fp);
        return lm_fail(LM_E_IO, "checkpoint '%s' is not a regular file", path);
    }
    if ((uint64_t)sb.st_size > CO_CHECKPOINT_MAX_BYTES) {
        fclose(fp);
        return lm_fail(LM_E_FORMAT, "checkpoint '%s' is implausibly large (%lld bytes)", path,
                       (long long)sb.st_size);
    }
    size_t n = (size_t)sb.st_size;
    uint8_t *buf = malloc(n ? n : 1);
    if (!buf) {
        fclose(fp);
        return lm_fail(LM_E_NOMEM, "cannot allocate %zu bytes to read checkpoint '%s'", n, path);
    }
    size_t got = fread(buf, 1, n, fp);
    fclose(fp);
    if (got != n) {
        free(buf);
        return lm_fail(LM_E_IO, "error reading checkpoint '%s'", path);
    }
    *data = buf;
    *len = n;
    return LM_OK;
}

/* Magic, version, length and checksum; *key_bytes the key's size (version 2's is shorter). */
static lm_status verify_frame(const char *path, const uint8_t *d, size_t n, uint32_t *key_bytes,
                              uint64_t *payload_len)
{
    if (n < sizeof co_magic || memcmp(d, co_magic, sizeof co_magic) != 0)
        return lm_fail(LM_E_FORMAT, "'%s' is not a lumesh checkpoint (bad magic)", path);
    if (n < header_bytes(CO_KEY_BYTES_V2) + CO_TRAILER_BYTES)
        return lm_fail(LM_E_FORMAT, "checkpoint '%s' is truncated (%zu bytes)", path, n);
    uint32_t version = get_u32(d + 8);
    if (version < 2 || version > CO_CHECKPOINT_VERSION)
        return lm_fail(LM_E_FORMAT,
                       "checkpoint '%s' has version %" PRIu32 ", expected %u (%s lumesh wrote it)",
                       path, version, CO_CHECKPOINT_VERSION,
                       version < CO_CHECKPOINT_VERSION ? "an older" : "a newer");
    uint32_t kb = version_key_bytes(version);
    size_t head = header_bytes(kb);
    if (get_u32(d + 12) != kb)
        return lm_fail(LM_E_FORMAT, "checkpoint '%s' is corrupted (bad header)", path);
    if (n < head + CO_TRAILER_BYTES)
        return lm_fail(LM_E_FORMAT, "checkpoint '%s' is truncated (%zu bytes)", path, n);
    uint64_t plen = get_u64(d + 16 + kb);
    uint64_t body = (uint64_t)n - head - CO_TRAILER_BYTES;
    if (plen > body)
        return lm_fail(LM_E_FORMAT,
                       "checkpoint '%s' is truncated (%zu bytes, expected %" PRIu64 ")", path, n,
                       plen + head + CO_TRAILER_BYTES);
    if (plen < body)
        return lm_fail(LM_E_FORMAT, "checkpoint '%s' is corrupted (%" PRIu64 " trailing bytes)",
                       path, body - plen);
    uint64_t sum = co_fnv1a(CO_FNV_OFFSET, d, n - CO_TRAILER_BYTES);
    if (sum != get_u64(d + n - CO_TRAILER_BYTES))
        return lm_fail(LM_E_FORMAT, "checkpoint '%s' is corrupted (checksum mismatch)", path);
    *key_bytes = kb;
    *payload_len = plen;
    return LM_OK;
}

/* The flag that made a start (initial_hash). */
static const char *start_flag(uint64_t initial_hash)
{
    return initial_hash == 0                              ? "--start qem"
           : initial_hash == CO_CHECKPOINT_IMAGE_START    ? "--start image"
           : initial_hash == CO_CHECKPOINT_ADAPTIVE_START ? "--start adaptive"
                                                          : "--initial";
}

static lm_status verify_key(const char *path, const co_checkpoint_key *got,
                            const co_checkpoint_key *want)
{
    if (got->original_hash != want->original_hash)
        return lm_fail(LM_E_INVALID, "checkpoint '%s' was written for a different original model",
                       path);
    const char *was = start_flag(got->initial_hash), *is = start_flag(want->initial_hash);
    if (got->initial_hash != want->initial_hash && strcmp(was, is))
        return lm_fail(LM_E_INVALID, "checkpoint '%s' was written with %s, this run uses %s", path,
                       was, is);
    if (got->initial_hash != want->initial_hash)
        return lm_fail(LM_E_INVALID, "checkpoint '%s' was written for a different initial mesh",
                       path);
#define CO_KEY_CHECK(field, flag, fmt)                                                             \
    if (got->field != want->field)                                                                 \
        return lm_fail(LM_E_INVALID,                                                               \
                       "checkpoint '%s' was written with " flag " %" fmt ", this run uses " flag   \
                       " %" fmt,                                                                   \
                       path, got->field, want->field);
    if (got->view_dist != want->view_dist)
        return lm_fail(LM_E_INVALID,
                       "checkpoint '%s' was written for %s views, this run uses %s views", path,
                       lm_view_dist_name((lm_view_dist)got->view_dist),
                       lm_view_dist_name((lm_view_dist)want->view_dist));
    if (got->cameras_hash != want->cameras_hash)
        return lm_fail(LM_E_INVALID,
                       "checkpoint '%s' was written for other cameras than this --views-from",
                       path);
    CO_KEY_CHECK(seed, "--seed", PRIu64)
    CO_KEY_CHECK(target_verts, "--target-verts", PRIu32)
    CO_KEY_CHECK(views, "--views", PRIu32)
    CO_KEY_CHECK(size, "--size", PRIu32)
    CO_KEY_CHECK(attrs, "--attrs mask", PRIu32)
    CO_KEY_CHECK(regrid_every, "--regrid-every", PRIu64)
    CO_KEY_CHECK(validate_every, "--validate-every", PRIu64)
    CO_KEY_CHECK(validate_views, "--validate-views", PRIu32)
    CO_KEY_CHECK(validate_patience, "--validate-patience", PRIu32)
    if (got->view_schedule != want->view_schedule)
        return lm_fail(LM_E_INVALID,
                       "checkpoint '%s' was written with --view-schedule %s, this run uses %s",
                       path, co_schedule_name((co_view_schedule)got->view_schedule),
                       co_schedule_name((co_view_schedule)want->view_schedule));
    CO_KEY_CHECK(schedule_evals, "--view-schedule grow over --evals", PRIu64)
#undef CO_KEY_CHECK
    return LM_OK;
}

static lm_status load_payload(const char *path, uint8_t *payload, uint64_t len,
                              co_checkpoint_load_fn load, void *ctx)
{
    /* fmemopen refuses a zero-size buffer; give it one spare byte it will never reach. */
    FILE *ms = fmemopen(payload, len ? (size_t)len : 1, "rb");
    if (!ms)
        return lm_fail(LM_E_NOMEM, "cannot open the payload of checkpoint '%s'", path);
    lm_status st = len ? load(ctx, ms) : lm_fail(LM_E_FORMAT, "checkpoint '%s' is empty", path);
    if (st == LM_OK) {
        long pos = ftell(ms);
        if (pos < 0 || (uint64_t)pos != len)
            st = lm_fail(LM_E_FORMAT,
                         "checkpoint '%s': optimizer state has %" PRIu64
                         " unread bytes (written by another build?)",
                         path, len - (uint64_t)(pos < 0 ? 0 : pos));
    }
    fclose(ms);
    return st;
}

static lm_status ignore_payload(void *ctx, FILE *fp)
{
    (void)ctx;
    return fseek(fp, 0, SEEK_END) == 0 ? LM_OK : lm_fail(LM_E_IO, "cannot skip the payload");
}

lm_status co_checkpoint_verify(const char *path, const co_checkpoint_key *expect)
{
    return co_checkpoint_read(path, expect, ignore_payload, NULL);
}

lm_status co_checkpoint_read(const char *path, const co_checkpoint_key *expect,
                             co_checkpoint_load_fn load, void *ctx)
{
    uint8_t *d = NULL;
    size_t n = 0;
    lm_status st = slurp(path, &d, &n);
    if (st != LM_OK)
        return st;
    uint64_t plen = 0;
    uint32_t kb = 0;
    st = verify_frame(path, d, n, &kb, &plen);
    if (st == LM_OK) {
        co_checkpoint_key got;
        decode_key(d + 16, kb, &got);
        st = verify_key(path, &got, expect);
    }
    if (st == LM_OK)
        st = load_payload(path, d + header_bytes(kb), plen, load, ctx);
    free(d);
    return st;
}
