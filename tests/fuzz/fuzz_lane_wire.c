/* tests/fuzz/fuzz_lane_wire.c — libFuzzer target for a lane's wire messages (lane_wire.h), what a
 * worker would send back to the coordinator and the coordinator to a worker. The first input
 * byte picks the message (mod 4: 0 a request, 2 a request's head, 3 a group's collapse queue, 1 a
 * result; all of a lane whose group started with FUZZ_VERTS vertex slots), the rest is the
 * message. Any input must be refused with LM_E_FORMAT
 * (or LM_E_NOMEM) and one line, or decode to a message that encodes to exactly the input bytes;
 * never a crash, a read past the input or an allocation beyond O(input).
 * LUMESH_FUZZ_WRITE_SEEDS=DIR writes the seeds (so does tests/replay_lane_wire, which replays the
 * corpus as the ctest fuzz_replay_lane_wire). */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "common/optimizer/lane_wire.h"
#include "common/optimizer/optimizer.h" /* LM_MAX_EDGES_IN_FLIGHT */

#define FUZZ_VERTS 1000u

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

/* A request of lane 1 of 3 with vetoed vertices and a queue (and its head as the last lane of a
 * group of LM_MAX_EDGES_IN_FLIGHT, and of one above it: refused); a result with two operations
 * (one split making vertex FUZZ_VERTS), logs and touched vertices. */
static void write_seeds(const char *dir)
{
    lm_lane_request q;
    lm_lane_request_init(&q);
    q.index = 1, q.n_group = 3, q.a = 4, q.b = 9, q.n_verts = FUZZ_VERTS, q.clock = 5000;
    for (uint32_t v = 100; v < 110; v++)
        LM_ASSERT(lm_lane_request_veto(&q, v) == LM_OK);
    q.stats.half_life = 100000, q.stats.min_weight = 1;
    q.stats.op[1][2] = (lm_stat){1.5, -30, 900, 40, 4000, 3};
    q.tp_cfg = (lm_teleport_config){20000, 50000, 3000};
    q.improve[1] = (lm_stat){0.5, -3, 9, 4, 300, 1};
    lm_cq_entry e[4] = {{0, 1, -5, 0, 1}, {0, 2, 0, -1, 1}, {3, 4, 77, 2, 0}, {5, 999, 1, 3, 1}};
    q.queue = e, q.n_queue = 4;
    uint8_t *buf;
    size_t len;
    LM_ASSERT(lm_lane_request_encode(&q, &buf, &len) == LM_OK);
    write_seed(dir, "request", 0, buf, len);
    free(buf);
    LM_ASSERT(lm_lane_request_encode_head(&q, &buf, &len) == LM_OK);
    write_seed(dir, "head", 2, buf, len);
    free(buf);
    q.index = LM_MAX_EDGES_IN_FLIGHT - 1, q.n_group = LM_MAX_EDGES_IN_FLIGHT; /* the last lane */
    LM_ASSERT(lm_lane_request_encode_head(&q, &buf, &len) == LM_OK);
    write_seed(dir, "head_group_at_cap", 2, buf, len);
    free(buf);
    q.n_group = LM_MAX_EDGES_IN_FLIGHT + 1; /* refused: a group above the cap */
    LM_ASSERT(lm_lane_request_encode_head(&q, &buf, &len) == LM_OK);
    write_seed(dir, "head_group_above_cap", 2, buf, len);
    free(buf);
    q.index = 1, q.n_group = 3;
    LM_ASSERT(lm_lane_queue_encode(e, 4, &buf, &len) == LM_OK);
    write_seed(dir, "queue", 3, buf, len);
    free(buf);
    q.queue = NULL;
    lm_lane_request_free(&q);

    lm_lane_result r;
    lm_lane_result_init(&r);
    const double x[4] = {0.5, 0.25, -2, 8};
    lm_move_record m0 = {LM_MOVE_NOOP, 1, 4, 9, LM_NONE, 0, 3, x, -40};
    lm_move_record m1 = {LM_MOVE_SPLIT, 0, 4, 9, FUZZ_VERTS, 0, 1, x + 3, -7};
    LM_ASSERT(lm_lane_result_accepted(&r, &m0, 0) == LM_OK);
    LM_ASSERT(lm_lane_result_accepted(&r, &m1, -40) == LM_OK);
    r.d_acc = -47, r.mesh_hash = 42, r.total = -47, r.evals = 120;
    r.attempted[0] = 3, r.accepted[0] = 1, r.accepted[2] = 1;
    LM_ASSERT(lm_lane_log_add(&r.log, LM_MOVE_NOOP, 1, -40, 60, 5060) == LM_OK);
    LM_ASSERT(lm_lane_log_add(&r.log, LM_LANE_LOG_IMPROVE, 2, -3, 0, 5100) == LM_OK);
    lm_lane_log_queue(&r.log, &(lm_cq_entry){4, FUZZ_VERTS, 0, -1, 1}, 1);
    lm_lane_log_queue(&r.log, &(lm_cq_entry){4, 9, 0, -1, 0}, 0);
    for (uint32_t v = 3; v < 12; v += 2)
        LM_ASSERT(lm_idset_add(&r.touched, v) == LM_OK);
    LM_ASSERT(lm_lane_result_encode(&r, &buf, &len) == LM_OK);
    write_seed(dir, "result", 1, buf, len);
    free(buf);
    lm_lane_result_free(&r);
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

/* The decoded message, encoded again, must be the input. */
static void check_same(const uint8_t *data, size_t size, uint8_t *buf, size_t len)
{
    LM_ASSERT(len == size && memcmp(buf, data, size) == 0);
    free(buf);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    uint8_t *buf = NULL;
    size_t len = 0;
    lm_status st;
    if (data[0] % 4 == 0 || data[0] % 4 == 2) {
        int head = data[0] % 4 == 2;
        lm_lane_request q;
        lm_lane_request_init(&q);
        st = head ? lm_lane_request_decode_head(data + 1, size - 1, &q)
                  : lm_lane_request_decode(data + 1, size - 1, &q);
        if (st == LM_OK) {
            LM_ASSERT((head ? lm_lane_request_encode_head(&q, &buf, &len)
                            : lm_lane_request_encode(&q, &buf, &len)) == LM_OK);
            check_same(data + 1, size - 1, buf, len);
        }
        lm_lane_request_free(&q);
    } else if (data[0] % 4 == 3) {
        lm_cq_entry *e = NULL;
        uint32_t n = 0;
        st = lm_lane_queue_decode(data + 1, size - 1, FUZZ_VERTS, &e, &n);
        if (st == LM_OK) {
            LM_ASSERT(lm_lane_queue_encode(e, n, &buf, &len) == LM_OK);
            check_same(data + 1, size - 1, buf, len);
        }
        free(e);
    } else {
        lm_lane_result r;
        lm_lane_result_init(&r);
        st = lm_lane_result_decode(data + 1, size - 1, FUZZ_VERTS, &r);
        if (st == LM_OK) {
            LM_ASSERT(lm_lane_result_encode(&r, &buf, &len) == LM_OK);
            check_same(data + 1, size - 1, buf, len);
        }
        lm_lane_result_free(&r);
    }
    LM_ASSERT(st == LM_OK || st == LM_E_FORMAT || st == LM_E_NOMEM);
    lm_clear_error();
    return 0;
}
