/* tests/fuzz/fuzz_checkpoint.c — libFuzzer target for job checkpoints
 * (coordinator/job/checkpoint.h) and the optimizer state inside them (lm_optimizer_load) and a
 * validating job's state (co_validation_load). Every input is tried three ways, each for two jobs:
 * one without validation (checkpoint version 3) and one that validates (`optimize
 * --validate-every`: version 4, whose key holds the validation's options and whose payload holds
 * the training views' epoch and the validation state):
 *   1. as it is, as a checkpoint file: co_checkpoint_verify (frame, checksum, key);
 *   2. when it starts with the checkpoint magic, with its FNV-1a trailer recomputed so that
 *      mutations get past the checksum: co_checkpoint_read, the payload going to a loader like the
 *      job's (coordinator/job/job.c: u32 regrid draw, then lm_optimizer_load; validating: u32
 *      regrid draw, u32 epoch, lm_optimizer_load, then co_validation_load);
 *   3. as a bare payload, on a memory stream (fmemopen), to that loader.
 * The job keys, the optimizer and its views are the seeds': an octahedron optimised towards a
 * stretched one, seen by 2 views of 16x16 on the CPU rasteriser, made once. lm_optimizer_load
 * checks everything before it changes anything; past the checks it installs the loaded mesh and
 * state, and may still fail after that (adjacency, re-render). So whenever a load got that far (the
 * mesh's arrays were replaced) the optimizer and its views are made anew before the next input:
 * every input starts from the same state. A load that succeeds must be savable again. Any input
 * must give LM_OK or an error status with a one-line message; never a crash, a leak or a hang.
 * Seeds: tests/fuzz/corpus/checkpoint/: full checkpoints of the fresh optimizer and of one in the
 * middle of an iteration, and the latter's bare payload, for both jobs (v4_*: the validating one,
 * after a check that kept a best mesh), written by this target when run with
 * LUMESH_FUZZ_WRITE_SEEDS=DIR (it writes them into DIR and exits; so does the normal build's
 * tests/replay_checkpoint, which replays the corpus as the ctest fuzz_replay_checkpoint); v2_* are
 * the seeds an older lumesh wrote (version 2, still read); regress_*
 * are inputs that once failed (regress_touched_id_range: a touched vertex id of 2^28-1 made the
 * loader allocate 1 GiB; it shows with -malloc_limit_mb=64). */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/log.h"
#include "common/mesh_topology.h"
#include "common/optimizer/optimizer.h"
#include "common/view.h"
#include "coordinator/job/checkpoint.h"
#include "coordinator/job/validate.h"
#include "worker/render/views_local.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The frame's layout (checkpoint.h): magic, version, key size, 48-byte key, payload length. */
enum { HEADER_BYTES = 8 + 4 + 4 + 64 + 8, TRAILER_BYTES = 8 };

/* The job the seeds were written by (no regrid: the payload's draw must be 0). */
static const co_checkpoint_key g_key = {.original_hash = 0x6f63746168656472ull,
                                        .seed = 7,
                                        .target_verts = 6,
                                        .views = 2,
                                        .size = 16,
                                        .regrid_every = 0};
/* The same job validating every 100 evaluations on 2 views, new training views after 3 checks
 * without a new best: a key written as version 4. */
static const co_checkpoint_key g_key_v4 = {.original_hash = 0x6f63746168656472ull,
                                           .seed = 7,
                                           .target_verts = 6,
                                           .views = 2,
                                           .size = 16,
                                           .regrid_every = 0,
                                           .validate_every = 100,
                                           .validate_views = 2,
                                           .validate_patience = 3};

static lm_view_set g_vs;
static lm_mesh *g_orig;
static lm_views *g_views;
static lm_optimizer *g_opt;
static co_validation g_val; /* the validating job's state (no views: loads never render) */
static char g_path[512];

static void one_line_error(void)
{
    LM_ASSERT(lm_last_error()[0] != '\0' && !strchr(lm_last_error(), '\n'));
}

/* An octahedron of radius 1 whose +z apex is at `apex`, normals and UVs set, adjacency built. */
static lm_mesh *octahedron(float apex)
{
    static const float p[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                  {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    static const uint32_t f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                     {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    lm_mesh *m = NULL;
    LM_ASSERT(lm_mesh_create(&m) == LM_OK);
    LM_ASSERT(lm_mesh_add_material(m, "default", NULL, NULL, NULL, NULL) == LM_OK);
    m->attrs = LM_ATTR_NORMAL | LM_ATTR_UV;
    for (int i = 0; i < 6; i++) {
        float q[3] = {p[i][0], p[i][1], p[i][2] * (i == 4 ? apex : 1.0f)};
        uint32_t v;
        LM_ASSERT(lm_mesh_add_vertex(m, q, &v) == LM_OK);
        lm_wedge w = {.vertex = v,
                      .normal = {p[i][0], p[i][1], p[i][2]},
                      .uv = {0.5f + 0.1f * (float)i, 0.5f},
                      .color = {1, 1, 1, 1}};
        LM_ASSERT(lm_mesh_add_wedge(m, &w, NULL) == LM_OK);
    }
    for (int t = 0; t < 8; t++)
        LM_ASSERT(lm_mesh_add_tri(m, f[t], 0, NULL) == LM_OK);
    LM_ASSERT(lm_mesh_build_adjacency(m) == LM_OK);
    return m;
}

/* Views of the original and an optimizer on the regular octahedron, in a fresh state. */
static void make_optimizer(void)
{
    lm_optimizer_destroy(g_opt);
    lm_views_destroy(g_views);
    LM_ASSERT(wk_views_local_create(g_orig, &g_vs, 0, 0, "cpu", &g_views) == LM_OK);
    lm_params params = {.seed = g_key.seed, .attrs = g_key.attrs};
    LM_ASSERT(lm_optimizer_create(octahedron(1.0f), g_views, &params, &g_opt) == LM_OK);
}

static lm_status get_u32_le(FILE *fp, uint32_t *v, const char *what)
{
    uint8_t d[4];
    if (fread(d, 1, 4, fp) != 4)
        return lm_fail(LM_E_INVALID, "checkpoint is truncated (no %s)", what);
    *v = (uint32_t)d[0] | (uint32_t)d[1] << 8 | (uint32_t)d[2] << 16 | (uint32_t)d[3] << 24;
    return LM_OK;
}

static lm_status put_u32_le(FILE *fp, uint32_t v, const char *what)
{
    const uint8_t d[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    if (fwrite(d, 1, 4, fp) != 4)
        return lm_fail(LM_E_IO, "cannot write the checkpoint's %s", what);
    return LM_OK;
}

/* ctx of the loader and saver below: NULL the job without validation, this the validating one. */
static const char g_validating[] = "validating";

/* The job's payload loader, for a job without regrid draws; for the validating job the training
 * views' epoch follows the draw (any is taken, where the job would switch to that epoch's views)
 * and the validation state the optimizer. */
static lm_status load_like_job(void *ctx, FILE *fp)
{
    uint32_t draw = 0, epoch = 0;
    lm_status st = get_u32_le(fp, &draw, "regrid draw");
    if (st == LM_OK && ctx)
        st = get_u32_le(fp, &epoch, "training views");
    if (st != LM_OK)
        return st;
    if (draw)
        return lm_fail(LM_E_INVALID, "checkpoint names regrid draw %u of a job without one",
                       (unsigned)draw);
    st = lm_optimizer_load(g_opt, fp);
    if (st == LM_OK && ctx)
        st = co_validation_load(&g_val, lm_optimizer_mesh(g_opt), fp);
    return st;
}

static lm_status save_like_job(const void *ctx, FILE *fp)
{
    lm_status st = put_u32_le(fp, 0, "regrid draw");
    if (st == LM_OK && ctx)
        st = put_u32_le(fp, g_val.epoch, "training views");
    if (st == LM_OK)
        st = lm_optimizer_save(g_opt, fp);
    if (st == LM_OK && ctx)
        st = co_validation_save(&g_val, fp);
    return st;
}

/* The validating job's state as before any input: no checks, no best mesh. */
static void reset_validation(void)
{
    lm_mesh_destroy(g_val.best);
    memset(&g_val, 0, sizeof g_val);
}

/* After a load: a successful one must save again (the validating job's with its validation
 * state); one that replaced the state gets a fresh optimizer, and the validation state is reset,
 * for the next input. */
static void after_load(lm_status s, const float (*pos_before)[3], const void *ctx)
{
    if (s == LM_OK) {
        char *buf = NULL;
        size_t len = 0;
        FILE *ms = open_memstream(&buf, &len);
        LM_ASSERT(ms);
        LM_ASSERT(save_like_job(ctx, ms) == LM_OK);
        LM_ASSERT(fclose(ms) == 0);
        free(buf);
    } else {
        one_line_error();
    }
    if (lm_optimizer_mesh(g_opt)->pos != pos_before)
        make_optimizer();
    reset_validation();
}

static void write_file(const char *path, const void *data, size_t size)
{
    FILE *fp = fopen(path, "wb");
    LM_ASSERT(fp);
    LM_ASSERT(size == 0 || fwrite(data, 1, size, fp) == size);
    LM_ASSERT(fclose(fp) == 0);
}

static void write_payload(const char *dir, const char *name, const void *ctx)
{
    char path[4096], *buf = NULL;
    size_t len = 0;
    FILE *ms = open_memstream(&buf, &len);
    LM_ASSERT(ms && save_like_job(ctx, ms) == LM_OK && fclose(ms) == 0);
    snprintf(path, sizeof path, "%s/%s", dir, name);
    write_file(path, buf, len);
    free(buf);
}

static void write_checkpoint(const char *dir, const char *name, const void *ctx)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    LM_ASSERT(co_checkpoint_write(path, ctx ? &g_key_v4 : &g_key, save_like_job, ctx) == LM_OK);
}

/* The validating job's state after a check of the current mesh, on views of its own (the
 * optimizer's keep their mesh): a best mesh, one check, the next one 100 evaluations on. */
static void validate_once(uint64_t evals)
{
    LM_ASSERT(wk_views_local_create(g_orig, &g_vs, 0, 0, "cpu", &g_val.views) == LM_OK);
    LM_ASSERT(co_validation_check(&g_val, lm_optimizer_mesh(g_opt), evals, 1, NULL) == LM_OK);
    lm_views_destroy(g_val.views);
    g_val.views = NULL;
    g_val.next_evals = evals + g_key_v4.validate_every;
}

/* LUMESH_FUZZ_WRITE_SEEDS=DIR: the seed corpus, from the real optimizer. */
static void write_seeds(const char *dir)
{
    write_checkpoint(dir, "full_fresh", NULL);
    write_checkpoint(dir, "v4_full_fresh", g_validating);
    /* 300 evaluations end in the middle of an iteration, with moves accepted and tried. */
    lm_progress p;
    for (int guard = 0; guard < 1000; guard++) {
        lm_optimizer_progress(g_opt, &p);
        if (p.evals >= 300)
            break;
        LM_ASSERT(lm_optimizer_step(g_opt, 300) == LM_OK);
    }
    fprintf(stderr, "seeds at %llu evaluations, %llu iterations\n", (unsigned long long)p.evals,
            (unsigned long long)p.iterations);
    write_checkpoint(dir, "full_mid_iteration", NULL);
    write_payload(dir, "payload_mid_iteration", NULL);
    validate_once(p.evals);
    write_checkpoint(dir, "v4_full_mid_iteration", g_validating);
    write_payload(dir, "v4_payload_mid_iteration", g_validating);
    reset_validation();
}

static void cleanup(void)
{
    unlink(g_path);
    reset_validation();
    lm_optimizer_destroy(g_opt);
    lm_views_destroy(g_views);
    lm_mesh_destroy(g_orig);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    lm_log_set_level(LM_LOG_ERROR);
    g_orig = octahedron(1.6f);
    float c[3], r;
    lm_mesh_bounding_sphere(g_orig, c, &r);
    LM_ASSERT(lm_view_set_make(&g_vs, g_key.views, (int)g_key.size, c, r) == LM_OK);
    make_optimizer();
    const char *seeds = getenv("LUMESH_FUZZ_WRITE_SEEDS");
    if (seeds && *seeds) {
        write_seeds(seeds);
        cleanup();
        exit(0);
    }
    /* The checkpoint file is rewritten for every input: in memory (tmpfs) where there is one; on
       ext4 rewriting a file in place waits for the disk, some 20 times slower. */
    const char *tmp = getenv("TMPDIR");
    if (access("/dev/shm", W_OK) == 0)
        tmp = "/dev/shm";
    else if (!tmp || !*tmp)
        tmp = "/tmp";
    int len = snprintf(g_path, sizeof g_path, "%s/fuzz_checkpoint_XXXXXX", tmp);
    LM_ASSERT(len > 0 && (size_t)len < sizeof g_path);
    int fd = mkstemp(g_path);
    LM_ASSERT(fd >= 0);
    close(fd);
    atexit(cleanup);
    return 0;
}

static uint64_t get_u64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++)
        v |= (uint64_t)p[i] << (8 * i);
    return v;
}

/* The three ways, for one job (ctx: NULL, or g_validating with the version 4 key). */
static void try_job(const uint8_t *data, size_t size, const void *ctx)
{
    const co_checkpoint_key *key = ctx ? &g_key_v4 : &g_key;
    /* 1: the file as it is. */
    write_file(g_path, data, size);
    lm_status s = co_checkpoint_verify(g_path, key);
    if (s != LM_OK)
        one_line_error();

    /* 2: the file with a correct checksum. */
    if (size >= HEADER_BYTES + TRAILER_BYTES && memcmp(data, "LUMESHCK", 8) == 0) {
        uint8_t *copy = malloc(size);
        LM_ASSERT(copy);
        memcpy(copy, data, size);
        uint64_t sum = co_fnv1a(CO_FNV_OFFSET, copy, size - TRAILER_BYTES);
        for (int i = 0; i < 8; i++)
            copy[size - TRAILER_BYTES + i] = (uint8_t)(sum >> (8 * i));
        LM_ASSERT(s != LM_OK || get_u64(data + size - TRAILER_BYTES) == sum);
        write_file(g_path, copy, size);
        free(copy);
        const float(*pos)[3] = lm_optimizer_mesh(g_opt)->pos;
        after_load(co_checkpoint_read(g_path, key, load_like_job, (void *)ctx), pos, ctx);
    }

    /* 3: the bytes as a payload (fmemopen refuses a zero-size buffer). */
    if (size > 0) {
        FILE *ms = fmemopen((void *)data, size, "rb");
        LM_ASSERT(ms);
        const float(*pos)[3] = lm_optimizer_mesh(g_opt)->pos;
        after_load(load_like_job((void *)ctx, ms), pos, ctx);
        fclose(ms);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    try_job(data, size, NULL);
    try_job(data, size, g_validating);
    return 0;
}
