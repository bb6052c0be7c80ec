/* common/optimizer/lane_start.h — what a process that runs isolated lanes for another (a worker,
 * lane_host.h) needs besides the lane's request: the job's moves config and the group's start mesh,
 * as bytes (little-endian, floating-point values as their raw bits). Decoding takes hostile input:
 * truncation, trailing bytes, counts beyond what the bytes hold, non-finite constants and meshes
 * whose arrays do not fit together are refused with LM_E_FORMAT and one line (lm_last_error). */
#ifndef LM_COMMON_OPTIMIZER_LANE_START_H
#define LM_COMMON_OPTIMIZER_LANE_START_H

#include <stddef.h>
#include <stdint.h>

#include "common/mesh.h"
#include "common/optimizer/moves.h"

/* *buf (malloc'd, caller frees) and *len. */
lm_status lm_lane_config_encode(const lm_moves_config *cfg, uint8_t **buf, size_t *len);
lm_status lm_lane_config_decode(const uint8_t *buf, size_t len, lm_moves_config *cfg);

/* The mesh as the optimizer's state records it (dead slots included, so vertex ids stay). */
lm_status lm_lane_mesh_encode(const lm_mesh *m, uint8_t **buf, size_t *len);
/* Into m (created, with no materials or parts beyond the encoded mesh's): its arrays replaced,
 * adjacency built; m gets placeholder materials and parts up to the encoded counts (a lane's moves
 * read only their ids). A failure may leave m without adjacency: the
 * caller decodes again or drops it. */
lm_status lm_lane_mesh_decode(const uint8_t *buf, size_t len, lm_mesh *m);

#endif
