/* tests/fuzz/fuzz_lane_start.c — libFuzzer target for what a worker decodes besides a lane's
 * request when it runs lanes (--lanes remote): the moves config and the group's start mesh
 * (common/optimizer/lane_start.h) and collapse queue, whole or as a delta against the last group's
 * (lane_delta.h).
 * The first input byte picks the message (mod 4: 0 a config, 1 a mesh, 2 a mesh's delta: a u32
 * base length, that many base bytes, the delta; 3 a collapse queue's delta the same way, the
 * result a queue of FUZZ_VERTS vertex slots, lane_wire.h), the rest is the message. Any input must
 * be refused with a status and one line, or decode (a config to one that encodes to exactly the
 * input bytes; a mesh that validates; a delta to a record that then decodes or is refused); never a
 * crash, a read past the input or an allocation beyond O(input). LUMESH_FUZZ_WRITE_SEEDS=DIR writes
 * the seeds (so does tests/replay_lane_start, which replays the corpus as the ctest
 * fuzz_replay_lane_start). */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "common/optimizer/lane_delta.h"
#include "common/optimizer/lane_start.h"
#include "common/optimizer/lane_wire.h"

#define FUZZ_VERTS 1000u /* a queue's vertex slots */

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void write_seed(const char *dir, const char *name, uint8_t kind, const uint8_t *buf,
                       size_t len)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *fp = fopen(path, "wb");
    LM_ASSERT(fp && fwrite(&kind, 1, 1, fp) == 1 && fwrite(buf, 1, len, fp) == len);
    fclose(fp);
}

/* An octahedron with one material and one part. */
static lm_mesh *octahedron(void)
{
    lm_mesh *m;
    LM_ASSERT(lm_mesh_create(&m) == LM_OK);
    const float grey[4] = {0.5f, 0.5f, 0.5f, 1};
    uint32_t id;
    LM_ASSERT(lm_mesh_add_material(m, "skin", grey, NULL, NULL, &id) == LM_OK);
    LM_ASSERT(lm_mesh_add_part(m, "body", &id) == LM_OK);
    const float p[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int i = 0; i < 6; i++) {
        uint32_t v;
        LM_ASSERT(lm_mesh_add_vertex(m, p[i], &v) == LM_OK);
        lm_wedge w = {.vertex = v, .normal = {p[i][0], p[i][1], p[i][2]}, .color = {1, 1, 1, 1}};
        LM_ASSERT(lm_mesh_add_wedge(m, &w, NULL) == LM_OK);
    }
    const uint32_t f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                              {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int i = 0; i < 8; i++)
        LM_ASSERT(lm_mesh_add_tri(m, f[i], 0, NULL) == LM_OK);
    return m;
}

/* A group's collapse queue as a delta against the last group's (an entry changed, one gone, one
 * new). */
static void write_queue_seed(const char *dir)
{
    lm_cq_entry e[4] = {{0, 1, -5, 0, 1}, {0, 2, 0, -1, 1}, {3, 4, 77, 2, 0}, {5, 999, 1, 3, 1}};
    uint8_t *base, *cur, *d;
    size_t n_base, n_cur, n_d;
    LM_ASSERT(lm_lane_queue_encode(e, 4, &base, &n_base) == LM_OK);
    e[1] = e[2], e[2] = (lm_cq_entry){4, 7, 3, 1, 1}, e[0].est = -9;
    LM_ASSERT(lm_lane_queue_encode(e, 4, &cur, &n_cur) == LM_OK);
    LM_ASSERT(lm_lane_queue_delta_encode(base, n_base, cur, n_cur, &d, &n_d) == LM_OK);
    uint8_t *seed = malloc(4 + n_base + n_d);
    LM_ASSERT(seed);
    for (int i = 0; i < 4; i++)
        seed[i] = (uint8_t)(n_base >> (8 * i));
    memcpy(seed + 4, base, n_base);
    memcpy(seed + 4 + n_base, d, n_d);
    write_seed(dir, "queue_delta", 3, seed, 4 + n_base + n_d);
    free(seed);
    free(d);
    free(cur);
    free(base);
}

static void write_seeds(const char *dir)
{
    lm_moves_config c = {.attrs = 1,
                         .evals_per_dim = 32,
                         .max_set_verts = 8,
                         .max_dim = 160,
                         .pos_step = 0.2,
                         .normal_step = 0.15,
                         .uv_step = 0.2,
                         .color_step = 0.05,
                         .size_tol = 0.25,
                         .centre = {0.5f, 1, -2},
                         .bound_radius = 3};
    uint8_t *buf;
    size_t len;
    LM_ASSERT(lm_lane_config_encode(&c, &buf, &len) == LM_OK);
    write_seed(dir, "config", 0, buf, len);
    free(buf);
    lm_mesh *m = octahedron();
    LM_ASSERT(lm_lane_mesh_encode(m, &buf, &len) == LM_OK);
    write_seed(dir, "mesh", 1, buf, len);
    m->pos[2][1] = 1.25f; /* the next group's start: a vertex moved */
    uint8_t *cur, *d;
    size_t n_cur, n_d;
    LM_ASSERT(lm_lane_mesh_encode(m, &cur, &n_cur) == LM_OK);
    LM_ASSERT(lm_lane_delta_encode(buf, len, cur, n_cur, &d, &n_d) == LM_OK);
    uint8_t *seed = malloc(4 + len + n_d);
    LM_ASSERT(seed);
    for (int i = 0; i < 4; i++)
        seed[i] = (uint8_t)(len >> (8 * i));
    memcpy(seed + 4, buf, len);
    memcpy(seed + 4 + len, d, n_d);
    write_seed(dir, "delta", 2, seed, 4 + len + n_d);
    free(seed);
    write_queue_seed(dir);
    free(d);
    free(cur);
    free(buf);
    lm_mesh_destroy(m);
}

/* data: a u32 base length, the base, the delta (a short base length is what there is). */
static lm_status try_delta(const uint8_t *data, size_t size, int queue)
{
    if (size < 4)
        return lm_fail(LM_E_FORMAT, "no base length");
    size_t n_base =
        (size_t)data[0] | (size_t)data[1] << 8 | (size_t)data[2] << 16 | (size_t)data[3] << 24;
    n_base = n_base < size - 4 ? n_base : size - 4;
    uint8_t *rec = NULL;
    size_t n_rec = 0;
    lm_status st =
        lm_lane_delta_apply(data + 4, n_base, data + 4 + n_base, size - 4 - n_base, &rec, &n_rec);
    LM_ASSERT(st != LM_OK || n_rec <= size);
    if (st == LM_OK && queue) {
        lm_cq_entry *e = NULL;
        uint32_t n = 0;
        st = lm_lane_queue_decode(rec, n_rec, FUZZ_VERTS, &e, &n);
        free(e);
    } else if (st == LM_OK) {
        lm_mesh *m = NULL;
        LM_ASSERT(lm_mesh_create(&m) == LM_OK);
        st = lm_lane_mesh_decode(rec, n_rec, m);
        lm_mesh_destroy(m);
    }
    free(rec);
    return st;
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    lm_log_set_level(LM_LOG_ERROR);
    const char *dir = getenv("LUMESH_FUZZ_WRITE_SEEDS");
    if (dir) {
        write_seeds(dir);
        exit(0);
    }
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    lm_status st;
    if (data[0] % 4 >= 2) {
        st = try_delta(data + 1, size - 1, data[0] % 4 == 3);
    } else if (data[0] % 4 == 0) {
        lm_moves_config c;
        st = lm_lane_config_decode(data + 1, size - 1, &c);
        if (st == LM_OK) {
            uint8_t *buf = NULL;
            size_t len = 0;
            LM_ASSERT(lm_lane_config_encode(&c, &buf, &len) == LM_OK);
            LM_ASSERT(len == size - 1 && memcmp(buf, data + 1, len) == 0);
            free(buf);
        }
    } else {
        lm_mesh *m = NULL;
        LM_ASSERT(lm_mesh_create(&m) == LM_OK);
        st = lm_lane_mesh_decode(data + 1, size - 1, m);
        if (st == LM_OK)
            LM_ASSERT(lm_mesh_validate(m) == LM_OK);
        lm_mesh_destroy(m);
    }
    LM_ASSERT(st == LM_OK || lm_last_error()[0]);
    lm_clear_error();
    return 0;
}
