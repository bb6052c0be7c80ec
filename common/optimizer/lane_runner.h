/* common/optimizer/lane_runner.h — where the isolated lanes of a group run, when not in this
 * process: a runner that the optimizer's owner sets (lm_optimizer_set_lane_runner; the
 * coordinator's remote views give one that sends the lanes to workers). The default (no runner)
 * runs them in process. The runner gets the group's lanes as encoded requests (lane_wire.h: each
 * lane's head and the group's queue, which every lane shares), runs each against the group's start
 * mesh and views committed to it (lane_host.h, elsewhere), and hands back each lane's decoded
 * result; the optimizer merges them in lane order as it merges lanes run in process, so the output
 * bytes do not depend on where or in what order they ran. */
#ifndef LM_COMMON_OPTIMIZER_LANE_RUNNER_H
#define LM_COMMON_OPTIMIZER_LANE_RUNNER_H

#include <stddef.h>
#include <stdint.h>

#include "common/mesh.h"
#include "common/optimizer/lane_work.h"
#include "common/optimizer/moves.h"

typedef struct lm_lane_batch {
    const lm_mesh *start;       /* the group's start: the optimizer's mesh (borrowed, unchanged
                                   until the runner returns); the views are committed to it */
    const lm_moves_config *cfg; /* the job's moves config (lane_host.h) */
    uint32_t n;                 /* lanes, in lane order (lane i has request index i) */
    uint32_t n_verts;           /* the start's vertex slots: what results are decoded with */
    const uint8_t *const *req;  /* [n] encoded requests' heads (borrowed): lane i's request is
                                   req[i] followed by queue (lane_wire.h) */
    const size_t *req_len;      /* [n] */
    const uint8_t *queue;       /* the group's collapse queue, encoded once (borrowed) */
    size_t queue_len;
    lm_lane_result *const *res; /* [n] initialised results: each filled by lm_lane_result_decode
                                   with a status of LM_OK when run returns LM_OK */
    uint64_t *result_bytes;     /* out: the encoded results' bytes, in all (for traffic) */
} lm_lane_batch;

/* run: BLOCKING until every lane of b has its result, or fails (then the run of the optimizer
 * fails with its one-line message). A runner retries lanes lost with a process itself: the same
 * request gives the same result bytes wherever it runs. */
typedef struct lm_lane_runner {
    lm_status (*run)(void *ctx, const lm_lane_batch *b);
    void *ctx;
} lm_lane_runner;

#endif
