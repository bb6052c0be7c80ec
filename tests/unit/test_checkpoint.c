/* tests/unit/test_checkpoint.c — checkpoint files: round trip, every single-byte corruption and
 * every truncation detected, foreign files and other options refused with one line, and atomicity
 * (a failed write leaves the previous checkpoint intact and no temporary file behind). */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "coordinator/job/checkpoint.h"
#include "test_support.h"

typedef struct payload {
    size_t n;
    uint8_t bytes[1500];
    size_t fail_after; /* save: fail after writing this many bytes (0 = never) */
} payload;

static lm_status save_fn(const void *ctx, FILE *fp)
{
    const payload *p = ctx;
    size_t n = p->fail_after ? p->fail_after : p->n;
    if (fwrite(p->bytes, 1, n, fp) != n)
        return lm_fail(LM_E_IO, "test payload write failed");
    if (p->fail_after)
        return lm_fail(LM_E_INTERNAL, "optimizer state could not be serialised (test)");
    return LM_OK;
}

static lm_status load_fn(void *ctx, FILE *fp)
{
    payload *p = ctx;
    p->n = fread(p->bytes, 1, sizeof p->bytes, fp);
    return LM_OK;
}

/* A loader that reads only half: the reader must notice the unread rest. */
static lm_status load_half_fn(void *ctx, FILE *fp)
{
    payload *p = ctx;
    p->n = fread(p->bytes, 1, 10, fp);
    return LM_OK;
}

static const co_checkpoint_key key0 = {
    .original_hash = 0x1234567890abcdefull,
    .initial_hash = 0,
    .seed = 7,
    .target_verts = 350,
    .views = 20,
    .size = 256,
    .attrs = LM_ATTR_UV,
};

static void make_payload(payload *p, size_t n, uint8_t salt)
{
    memset(p, 0, sizeof *p);
    p->n = n;
    for (size_t i = 0; i < n; i++)
        p->bytes[i] = (uint8_t)(i * 31u + salt);
}

static char *path_in(const char *dir, const char *name)
{
    char *s = malloc(strlen(dir) + strlen(name) + 2);
    sprintf(s, "%s/%s", dir, name);
    return s;
}

static uint8_t *read_file(const char *path, size_t *n)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    fseek(fp, 0, SEEK_END);
    *n = (size_t)ftell(fp);
    fseek(fp, 0, SEEK_SET);
    uint8_t *d = malloc(*n + 1);
    assert_int_equal(fread(d, 1, *n, fp), *n);
    fclose(fp);
    return d;
}

static void write_file(const char *path, const uint8_t *d, size_t n)
{
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(d, 1, n, fp), n);
    fclose(fp);
}

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
            n++;
    closedir(d);
    return n;
}

static void test_round_trip(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char *path = path_in(dir, "job.ckpt");
    payload in, out;
    make_payload(&in, 1000, 3);
    assert_int_equal(co_checkpoint_write(path, &key0, save_fn, &in), LM_OK);
    memset(&out, 0, sizeof out);
    assert_int_equal(co_checkpoint_read(path, &key0, load_fn, &out), LM_OK);
    assert_int_equal(out.n, in.n);
    assert_memory_equal(out.bytes, in.bytes, in.n);
    /* Overwriting replaces the content and leaves only the checkpoint in the folder. */
    make_payload(&in, 700, 99);
    assert_int_equal(co_checkpoint_write(path, &key0, save_fn, &in), LM_OK);
    assert_int_equal(co_checkpoint_read(path, &key0, load_fn, &out), LM_OK);
    assert_int_equal(out.n, 700);
    assert_memory_equal(out.bytes, in.bytes, in.n);
    assert_int_equal(count_entries(dir), 1);
    /* verify: same checks without a loader. */
    assert_int_equal(co_checkpoint_verify(path, &key0), LM_OK);
    co_checkpoint_key other = key0;
    other.views = 8;
    assert_int_equal(co_checkpoint_verify(path, &other), LM_E_INVALID);
    free(path);
    lmt_rmdir(dir);
}

static void test_every_byte_flip_detected(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char *path = path_in(dir, "c.ckpt");
    payload in, out;
    make_payload(&in, 300, 11);
    assert_int_equal(co_checkpoint_write(path, &key0, save_fn, &in), LM_OK);
    size_t n;
    uint8_t *good = read_file(path, &n);
    assert_true(n > 300);
    for (size_t i = 0; i < n; i++) {
        for (int bit = 0; bit < 8; bit += 3) {
            good[i] ^= (uint8_t)(1u << bit);
            write_file(path, good, n);
            good[i] ^= (uint8_t)(1u << bit);
            lm_clear_error();
            lm_status st = co_checkpoint_read(path, &key0, load_fn, &out);
            if (st != LM_E_FORMAT)
                fail_msg("flip of byte %zu bit %d: status %d (%s)", i, bit, st, lm_last_error());
            assert_non_null(strstr(lm_last_error(), path));
            assert_null(strchr(lm_last_error(), '\n'));
            assert_int_equal(co_checkpoint_verify(path, &key0), LM_E_FORMAT);
        }
    }
    free(good);
    free(path);
    lmt_rmdir(dir);
}

static void test_every_truncation_detected(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char *path = path_in(dir, "c.ckpt");
    payload in, out;
    make_payload(&in, 200, 5);
    assert_int_equal(co_checkpoint_write(path, &key0, save_fn, &in), LM_OK);
    size_t n;
    uint8_t *good = read_file(path, &n);
    for (size_t len = 0; len < n; len++) {
        write_file(path, good, len);
        lm_status st = co_checkpoint_read(path, &key0, load_fn, &out);
        if (st != LM_E_FORMAT)
            fail_msg("truncated to %zu of %zu bytes: status %d", len, n, st);
        if (len >= 8)
            assert_true(strstr(lm_last_error(), "truncated") ||
                        strstr(lm_last_error(), "corrupted"));
    }
    /* Appended garbage is refused too. */
    uint8_t *longer = malloc(n + 5);
    memcpy(longer, good, n);
    memset(longer + n, 0xAB, 5);
    write_file(path, longer, n + 5);
    assert_int_equal(co_checkpoint_read(path, &key0, load_fn, &out), LM_E_FORMAT);
    free(longer);
    free(good);
    free(path);
    lmt_rmdir(dir);
}

static void test_foreign_and_missing(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char *path = path_in(dir, "notes.txt");
    const char *text = "# Wavefront OBJ\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    write_file(path, (const uint8_t *)text, strlen(text));
    payload out;
    assert_int_equal(co_checkpoint_read(path, &key0, load_fn, &out), LM_E_FORMAT);
    assert_non_null(strstr(lm_last_error(), "not a lumesh checkpoint"));
    char *missing = path_in(dir, "missing.ckpt");
    assert_int_equal(co_checkpoint_read(missing, &key0, load_fn, &out), LM_E_IO);
    assert_non_null(strstr(lm_last_error(), "missing.ckpt"));
    /* A folder is not a checkpoint. */
    assert_int_equal(co_checkpoint_read(dir, &key0, load_fn, &out), LM_E_IO);
    free(missing);
    free(path);
    lmt_rmdir(dir);
}

static void expect_key_refused(const char *path, const co_checkpoint_key *k, const char *word)
{
    payload out;
    lm_status st = co_checkpoint_read(path, k, load_fn, &out);
    assert_int_equal(st, LM_E_INVALID);
    if (!strstr(lm_last_error(), word))
        fail_msg("message '%s' does not name '%s'", lm_last_error(), word);
}

static void test_other_options_refused(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char *path = path_in(dir, "c.ckpt");
    payload in;
    make_payload(&in, 64, 1);
    assert_int_equal(co_checkpoint_write(path, &key0, save_fn, &in), LM_OK);
    co_checkpoint_key k = key0;
    k.original_hash ^= 1;
    expect_key_refused(path, &k, "different original");
    k = key0;
    k.initial_hash = 42;
    expect_key_refused(path, &k, "written with --start qem, this run uses --initial");
    k.initial_hash = CO_CHECKPOINT_IMAGE_START;
    expect_key_refused(path, &k, "written with --start qem, this run uses --start image");
    char *other = path_in(dir, "initial.ckpt");
    k = key0;
    k.initial_hash = 42;
    assert_int_equal(co_checkpoint_write(other, &k, save_fn, &in), LM_OK);
    k.initial_hash = 43;
    expect_key_refused(other, &k, "different initial mesh");
    free(other);
    k = key0;
    k.seed = 8;
    expect_key_refused(path, &k, "--seed");
    k = key0;
    k.views = 12;
    expect_key_refused(path, &k, "--views 20, this run uses --views 12");
    k = key0;
    k.view_dist = LM_VIEW_DIST_UPPER;
    expect_key_refused(path, &k, "written for sphere views, this run uses upper views");
    k = key0;
    k.cameras_hash = 5;
    expect_key_refused(path, &k, "other cameras than this --views-from");
    k = key0;
    k.size = 128;
    expect_key_refused(path, &k, "--size");
    k = key0;
    k.target_verts = 351;
    expect_key_refused(path, &k, "--target-verts");
    k = key0;
    k.attrs = 0;
    expect_key_refused(path, &k, "--attrs");
    free(path);
    lmt_rmdir(dir);
}

static void test_failed_write_keeps_old(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char *path = path_in(dir, "c.ckpt");
    payload a, b, out;
    make_payload(&a, 500, 1);
    assert_int_equal(co_checkpoint_write(path, &key0, save_fn, &a), LM_OK);
    size_t n0;
    uint8_t *before = read_file(path, &n0);
    make_payload(&b, 900, 2);
    b.fail_after = 450;
    assert_int_equal(co_checkpoint_write(path, &key0, save_fn, &b), LM_E_INTERNAL);
    assert_non_null(strstr(lm_last_error(), "serialised"));
    size_t n1;
    uint8_t *after = read_file(path, &n1);
    assert_int_equal(n0, n1);
    assert_memory_equal(before, after, n0);
    assert_int_equal(co_checkpoint_read(path, &key0, load_fn, &out), LM_OK);
    assert_int_equal(out.n, 500);
    assert_memory_equal(out.bytes, a.bytes, 500);
    assert_int_equal(count_entries(dir), 1); /* no temporary file left behind */
    /* A folder that does not exist: refused, nothing created. */
    char *bad = path_in(dir, "no/such/folder/c.ckpt");
    assert_int_not_equal(co_checkpoint_write(bad, &key0, save_fn, &a), LM_OK);
    assert_int_equal(count_entries(dir), 1);
    free(bad);
    free(before);
    free(after);
    free(path);
    lmt_rmdir(dir);
}

static void test_unread_payload_refused(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char *path = path_in(dir, "c.ckpt");
    payload in, out;
    make_payload(&in, 100, 4);
    assert_int_equal(co_checkpoint_write(path, &key0, save_fn, &in), LM_OK);
    assert_int_equal(co_checkpoint_read(path, &key0, load_half_fn, &out), LM_E_FORMAT);
    assert_non_null(strstr(lm_last_error(), "unread"));
    free(path);
    lmt_rmdir(dir);
}

static void test_hash_file(void **state)
{
    (void)state;
    /* FNV-1a 64 reference values: "" and "a". */
    assert_true(co_fnv1a(CO_FNV_OFFSET, "", 0) == 0xcbf29ce484222325ull);
    assert_true(co_fnv1a(CO_FNV_OFFSET, "a", 1) == 0xaf63dc4c8601ec8cull);
    char *dir = lmt_mkdtemp();
    char *path = path_in(dir, "f.bin");
    uint8_t big[200000];
    for (size_t i = 0; i < sizeof big; i++)
        big[i] = (uint8_t)(i ^ (i >> 8));
    write_file(path, big, sizeof big);
    uint64_t h = 0;
    assert_int_equal(co_checkpoint_hash_file(path, &h), LM_OK);
    assert_true(h == co_fnv1a(CO_FNV_OFFSET, big, sizeof big)); /* streaming = one shot */
    char *missing = path_in(dir, "nope.obj");
    assert_int_equal(co_checkpoint_hash_file(missing, &h), LM_E_IO);
    free(missing);
    free(path);
    lmt_rmdir(dir);
}

/* A version-2 checkpoint (its key without the views' distribution and camera hash) is still read,
 * as sphere views: a job checkpointed before --views upper existed resumes. */
static void test_version2_read_as_sphere(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char *path = path_in(dir, "job.ckpt");
    payload in, out;
    make_payload(&in, 600, 5);
    assert_int_equal(co_checkpoint_write(path, &key0, save_fn, &in), LM_OK);
    size_t n;
    uint8_t *d = read_file(path, &n);
    /* 8 magic, 4 version, 4 key size, then the key: drop its last 16 bytes (48..63). */
    size_t k = 16, cut = 16;
    memmove(d + k + 48, d + k + 64, n - (k + 64));
    n -= cut;
    d[8] = 2, d[9] = d[10] = d[11] = 0;
    d[12] = 48, d[13] = d[14] = d[15] = 0;
    uint64_t sum = co_fnv1a(CO_FNV_OFFSET, d, n - 8);
    for (int i = 0; i < 8; i++)
        d[n - 8 + i] = (uint8_t)(sum >> (8 * i));
    write_file(path, d, n);
    memset(&out, 0, sizeof out);
    assert_int_equal(co_checkpoint_read(path, &key0, load_fn, &out), LM_OK);
    assert_int_equal(out.n, in.n);
    assert_memory_equal(out.bytes, in.bytes, in.n);
    co_checkpoint_key upper = key0;
    upper.view_dist = LM_VIEW_DIST_UPPER;
    assert_int_equal(co_checkpoint_verify(path, &upper), LM_E_INVALID);
    free(d);
    free(path);
    lmt_rmdir(dir);
}

/* A validating job writes version 4 (an 80-byte key); every other job version 3 as before. Each
 * validation option is part of the key, and a version-3 file is a job without validation. */
static void test_version4_validation(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char *p3 = path_in(dir, "v3.ckpt"), *p4 = path_in(dir, "v4.ckpt");
    payload in, out;
    make_payload(&in, 300, 9);
    co_checkpoint_key kv = key0;
    kv.validate_every = 2000;
    kv.validate_views = 30;
    kv.validate_patience = 4;
    assert_int_equal(co_checkpoint_write(p3, &key0, save_fn, &in), LM_OK);
    assert_int_equal(co_checkpoint_write(p4, &kv, save_fn, &in), LM_OK);
    size_t n3, n4;
    uint8_t *d3 = read_file(p3, &n3), *d4 = read_file(p4, &n4);
    assert_int_equal(d3[8], 3);
    assert_int_equal(d3[12], 64);
    assert_int_equal(d4[8], 4);
    assert_int_equal(d4[12], 80);
    assert_int_equal(n4, n3 + 16);
    memset(&out, 0, sizeof out);
    assert_int_equal(co_checkpoint_read(p4, &kv, load_fn, &out), LM_OK);
    assert_int_equal(out.n, in.n);
    assert_memory_equal(out.bytes, in.bytes, in.n);
    expect_key_refused(p3, &kv, "--validate-every 0, this run uses --validate-every 2000");
    expect_key_refused(p4, &key0, "--validate-every 2000, this run uses --validate-every 0");
    co_checkpoint_key k = kv;
    k.validate_views = 12;
    expect_key_refused(p4, &k, "--validate-views 30, this run uses --validate-views 12");
    k = kv;
    k.validate_patience = 0;
    expect_key_refused(p4, &k, "--validate-patience 4, this run uses --validate-patience 0");
    free(d3);
    free(d4);
    free(p3);
    free(p4);
    lmt_rmdir(dir);
}

/* A job with the grow view schedule writes version 5 (a 96-byte key: version 4's, then the
 * schedule and the evaluations its stages are fractions of); both are part of the key, and a
 * version 3 or 4 file is a job with fixed views. */
static void test_version5_schedule(void **state)
{
    (void)state;
    char *dir = lmt_mkdtemp();
    char *p3 = path_in(dir, "v3.ckpt"), *p5 = path_in(dir, "v5.ckpt");
    payload in, out;
    make_payload(&in, 300, 9);
    co_checkpoint_key kg = key0;
    kg.view_schedule = 2;
    kg.schedule_evals = 100000;
    assert_int_equal(co_checkpoint_write(p3, &key0, save_fn, &in), LM_OK);
    assert_int_equal(co_checkpoint_write(p5, &kg, save_fn, &in), LM_OK);
    size_t n3, n5;
    uint8_t *d3 = read_file(p3, &n3), *d5 = read_file(p5, &n5);
    assert_int_equal(d5[8], CO_CHECKPOINT_VERSION);
    assert_int_equal(CO_CHECKPOINT_VERSION, 5);
    assert_int_equal(d5[12], 96);
    assert_int_equal(n5, n3 + 32);
    memset(&out, 0, sizeof out);
    assert_int_equal(co_checkpoint_read(p5, &kg, load_fn, &out), LM_OK);
    assert_int_equal(out.n, in.n);
    assert_memory_equal(out.bytes, in.bytes, in.n);
    expect_key_refused(p3, &kg, "--view-schedule fixed, this run uses grow");
    expect_key_refused(p5, &key0, "--view-schedule grow, this run uses fixed");
    co_checkpoint_key k = kg;
    k.schedule_evals = 200000;
    expect_key_refused(p5, &k, "over --evals 100000, this run uses");
    free(d3);
    free(d5);
    free(p3);
    free(p5);
    lmt_rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_every_byte_flip_detected),
        cmocka_unit_test(test_every_truncation_detected),
        cmocka_unit_test(test_foreign_and_missing),
        cmocka_unit_test(test_other_options_refused),
        cmocka_unit_test(test_failed_write_keeps_old),
        cmocka_unit_test(test_unread_payload_refused),
        cmocka_unit_test(test_hash_file),
        cmocka_unit_test(test_version2_read_as_sphere),
        cmocka_unit_test(test_version4_validation),
        cmocka_unit_test(test_version5_schedule),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
