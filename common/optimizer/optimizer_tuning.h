/* common/optimizer/optimizer_tuning.h — the numbers the paper leaves open (step sizes,
 * tolerances, attenuation, oracle share bounds, collapse search limits), for benchmarks and
 * experiments. lm_optimizer_create uses lm_tuning_defaults(); a checkpoint records the tuning and
 * is only loaded by an optimizer with the same one. Zero means default for every field (for
 * surface_weight the default is no geometric term; a negative one means none too). */
#ifndef LM_COMMON_OPTIMIZER_OPTIMIZER_TUNING_H
#define LM_COMMON_OPTIMIZER_OPTIMIZER_TUNING_H

#include "common/optimizer/moves.h"
#include "common/optimizer/optimizer.h"
#include "common/optimizer/teleport.h"

/* The geometric term's weight where lm_tuning leaves it 0: none. Measured with scripts/fidelity.sh
 * (coordinator/OPTIMIZER.md) it helps scanned and CAD models and costs textured ones, so it is
 * an option (`optimize --surface-weight W`), not a default. */
#define LM_SURFACE_WEIGHT 0.0

/* Where lm_tuning leaves the weight 0: the geometric term's share of the image energy at the start
 * (the weight is chosen so that E_geo(start) = share · E_image(start)); 0 = none. 0.1 with the
 * job's default views (CO_JOB_DEFAULT_VIEWS): measured in coordinator/OPTIMIZER.md, third round. */
#define LM_SURFACE_SHARE 0.1

/* The most a relative weight may be (a start almost on the surface). */
#define LM_SURFACE_MAX_WEIGHT 1e9

typedef struct lm_tuning {
    lm_moves_config moves;       /* steps, set limits, simplex tolerances (attrs, bounds ignored) */
    lm_teleport_config teleport; /* threshold attenuation, collapse search limit */
    double stats_half_life;      /* evaluations for a statistic's weight to halve */
    double stats_min_weight;     /* operations with less attenuated weight are always tried */
    double oracle_share, oracle_min_share, oracle_max_share;
    uint32_t oracle_max_age; /* iterations an edge tried without progress is skipped at most */
    double surface_weight;   /* weight of the geometric term (surface_term.h) where lm_params has
                                a surface; negative = none (and surface_share ignored) */
    double surface_share;    /* without a surface_weight: E_geo(start) / E_image(start), from
                                which the optimizer sets the weight; negative = none */
} lm_tuning;

/* Fill every field with the value used when it is zero. */
void lm_tuning_defaults(lm_tuning *t);

/* lm_optimizer_create with explicit tuning (NULL = defaults). */
lm_status lm_optimizer_create_tuned(lm_mesh *mesh, lm_views *views, const lm_params *params,
                                    const lm_tuning *tuning, lm_optimizer **out);

#endif
