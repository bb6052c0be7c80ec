/* common/optimizer/move_stats.h — statistics of the operations (connectivity move ×
 * optimisation level) and the paper's Inequality 3 that decides which operations to attempt on an
 * edge (§5.3).
 *
 * Per operation: exponentially attenuated sums (weights halve every `half_life` evaluations) of
 * the energy change ΔE of each attempt (0 when rejected), of ΔE², and of its time in evaluations.
 * The attenuated number of attempts is the operation's utilisation f. Time is the optimizer's
 * evaluation counter, so the statistics are reproducible and checkpointable (plain values). */
#ifndef LM_COMMON_OPTIMIZER_MOVE_STATS_H
#define LM_COMMON_OPTIMIZER_MOVE_STATS_H

#include <stdint.h>

#include "common/optimizer/binio.h"
#include "common/optimizer/optimizer.h"

#define LM_LEVELS 4

typedef struct lm_stat {
    double w;     /* attenuated number of samples */
    double sum_x; /* attenuated sums of the sample, its square, and its time */
    double sum_x2;
    double sum_t;
    uint64_t time;  /* clock (evaluations) of the last update */
    uint64_t count; /* samples ever added */
} lm_stat;

/* The attenuated view of one lm_stat at a given clock. */
typedef struct lm_stat_view {
    double f;     /* utilisation: attenuated sample count */
    double mean;  /* mean sample (ΔE) */
    double sigma; /* its standard deviation */
    double t;     /* mean time (evaluations) */
} lm_stat_view;

void lm_stat_add(lm_stat *s, double x, double t, uint64_t now, double half_life);
void lm_stat_get(const lm_stat *s, uint64_t now, double half_life, lm_stat_view *out);
/* A statistic in a saved state (the optimizer's checkpoint, the teleporter's), field by field. */
void lm_stat_save(lm_bin *b, const lm_stat *s);
void lm_stat_load(lm_bin *b, lm_stat *s);

typedef struct lm_move_stats {
    double half_life;  /* evaluations for a sample's weight to halve */
    double min_weight; /* an operation with less attenuated weight is always attempted */
    lm_stat op[LM_MOVE_KINDS][LM_LEVELS];
} lm_move_stats;

/* The whole statistics (constants, then every kind and level), as checkpoints and lane requests
 * carry them; the load checks nothing (its callers do). */
void lm_move_stats_save(lm_bin *b, const lm_move_stats *st);
void lm_move_stats_load(lm_bin *b, lm_move_stats *st);

void lm_move_stats_init(lm_move_stats *st, double half_life, double min_weight);

/* The operations that compete on an edge: no-op levels 1..3, swap and split (teleport) 0..3. */
int lm_move_is_edge_op(lm_move_kind kind, int level);

void lm_move_stats_add(lm_move_stats *st, lm_move_kind kind, int level, double delta_e,
                       double evals, uint64_t now);

/* The currently most efficient edge operation O* (lowest mean ΔE per evaluation among those with
 * at least min_weight). Returns 0 if none has enough data. */
int lm_move_stats_best(const lm_move_stats *st, uint64_t now, lm_move_kind *kind, int *level);

/* Inequality 3: attempt O if ΔE < min{ΔE' t/t' + √2 erf⁻¹(f'/(f + f')) σ, ΔE_total}, where the
 * primed values are those of the most efficient operation O* and de_total is the energy change
 * accumulated on the current edge so far. Choices the paper leaves open: utilisation f is the
 * attenuated time (evaluations) an operation used; σ is widened by σ*²/(samples + 1);
 * the ΔE_total term applies once de_total < 0 and not to operations
 * costing at most 4 evaluations on average; operations with less than min_weight attenuated
 * samples are always attempted. */
int lm_move_stats_should_try(const lm_move_stats *st, lm_move_kind kind, int level, double de_total,
                             uint64_t now);

/* Inverse error function on (-1, 1) (±inf at ±1, NaN outside): Giles' approximation refined by
 * Newton steps on erf() from <math.h>; accurate to a few ulp. */
double lm_erfinv(double x);

#endif
