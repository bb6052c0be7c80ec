/* coordinator/optimizer/optimizer_tuning.h — the numbers the paper leaves open (step sizes,
 * tolerances, attenuation, oracle share bounds, collapse search limits), for benchmarks and
 * experiments. co_optimizer_create uses co_tuning_defaults(); a checkpoint records the tuning and
 * is only loaded by an optimizer with the same one. Zero means default for every field (for
 * surface_weight the default is no geometric term; a negative one means none too). */
#ifndef LM_COORDINATOR_OPTIMIZER_TUNING_H
#define LM_COORDINATOR_OPTIMIZER_TUNING_H

#include "coordinator/optimizer/moves.h"
#include "coordinator/optimizer/optimizer.h"
#include "coordinator/optimizer/teleport.h"

/* The geometric term's weight where co_tuning leaves it 0: none. Measured with scripts/fidelity.sh
 * (coordinator/OPTIMIZER.md) it helps scanned and CAD models and costs textured ones, so it is
 * an option (`optimize --surface-weight W`), not a default. */
#define CO_SURFACE_WEIGHT 0.0

/* Where co_tuning leaves the weight 0: the geometric term's share of the image energy at the start
 * (the weight is chosen so that E_geo(start) = share · E_image(start)); 0 = none. 0.1 with the
 * job's default views (CO_JOB_DEFAULT_VIEWS): measured in coordinator/OPTIMIZER.md, third round. */
#define CO_SURFACE_SHARE 0.1

/* The most a relative weight may be (a start almost on the surface). */
#define CO_SURFACE_MAX_WEIGHT 1e9

typedef struct co_tuning {
    co_moves_config moves;       /* steps, set limits, simplex tolerances (attrs, bounds ignored) */
    co_teleport_config teleport; /* threshold attenuation, collapse search limit */
    double stats_half_life;      /* evaluations for a statistic's weight to halve */
    double stats_min_weight;     /* operations with less attenuated weight are always tried */
    double oracle_share, oracle_min_share, oracle_max_share;
    uint32_t oracle_max_age; /* iterations an edge tried without progress is skipped at most */
    double surface_weight;   /* weight of the geometric term (surface_term.h) where co_params has
                                a surface; negative = none (and surface_share ignored) */
    double surface_share;    /* without a surface_weight: E_geo(start) / E_image(start), from
                                which the optimizer sets the weight; negative = none */
} co_tuning;

/* Fill every field with the value used when it is zero. */
void co_tuning_defaults(co_tuning *t);

/* co_optimizer_create with explicit tuning (NULL = defaults). */
lm_status co_optimizer_create_tuned(lm_mesh *mesh, lm_views *views, const co_params *params,
                                    const co_tuning *tuning, co_optimizer **out);

#endif
