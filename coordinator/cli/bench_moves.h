/* coordinator/cli/bench_moves.h — the benchmark's typical optimizer moves as patches. */
#ifndef LM_COORDINATOR_BENCH_MOVES_H
#define LM_COORDINATOR_BENCH_MOVES_H

#include <stdint.h>

#include "common/mesh.h"
#include "common/patch.h"

/* n patches (initialised by the caller), each moving one random vertex of m (adjacency built) by
 * a random displacement of at most a third of the mean edge length per axis: removed = its 1-ring,
 * added = the 1-ring with the vertex moved. Deterministic in seed. */
lm_status co_bench_vertex_moves(const lm_mesh *m, uint64_t seed, lm_patch *out, uint32_t n);

#endif
