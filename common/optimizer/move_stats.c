/* common/optimizer/move_stats.c — attenuated per-operation statistics, the inverse error
 * function and the paper's Inequality 3. */
#include "common/optimizer/move_stats.h"

#include <math.h>
#include <string.h>

#define LM_CHEAP_EVALS 4.0 /* mean evaluations per attempt below which an operation is cheap */

static double decay(uint64_t from, uint64_t to, double half_life)
{
    if (to <= from || !(half_life > 0))
        return 1.0;
    return exp2(-(double)(to - from) / half_life);
}

void lm_stat_add(lm_stat *s, double x, double t, uint64_t now, double half_life)
{
    double k = decay(s->time, now, half_life);
    s->w = s->w * k + 1.0;
    s->sum_x = s->sum_x * k + x;
    s->sum_x2 = s->sum_x2 * k + x * x;
    s->sum_t = s->sum_t * k + t;
    if (now > s->time)
        s->time = now;
    s->count++;
}

void lm_stat_get(const lm_stat *s, uint64_t now, double half_life, lm_stat_view *out)
{
    memset(out, 0, sizeof *out);
    if (!(s->w > 0))
        return;
    out->f = s->w * decay(s->time, now, half_life);
    out->mean = s->sum_x / s->w;
    double var = s->sum_x2 / s->w - out->mean * out->mean;
    out->sigma = var > 0 ? sqrt(var) : 0;
    out->t = s->sum_t / s->w;
}

void lm_move_stats_init(lm_move_stats *st, double half_life, double min_weight)
{
    memset(st, 0, sizeof *st);
    st->half_life = half_life;
    st->min_weight = min_weight;
}

int lm_move_is_edge_op(lm_move_kind kind, int level)
{
    if (level < 0 || level >= LM_LEVELS)
        return 0;
    switch (kind) {
    case LM_MOVE_NOOP:
        return level >= 1;
    case LM_MOVE_SWAP:
    case LM_MOVE_SPLIT:
        return 1;
    default:
        return 0;
    }
}

void lm_move_stats_add(lm_move_stats *st, lm_move_kind kind, int level, double delta_e,
                       double evals, uint64_t now)
{
    if ((unsigned)kind >= LM_MOVE_KINDS || level < 0 || level >= LM_LEVELS)
        return;
    lm_stat_add(&st->op[kind][level], delta_e, evals, now, st->half_life);
}

static void view(const lm_move_stats *st, lm_move_kind k, int l, uint64_t now, lm_stat_view *v)
{
    lm_stat_get(&st->op[k][l], now, st->half_life, v);
}

int lm_move_stats_best(const lm_move_stats *st, uint64_t now, lm_move_kind *kind, int *level)
{
    int found = 0;
    double best = 0;
    for (int k = 0; k < LM_MOVE_KINDS; k++)
        for (int l = 0; l < LM_LEVELS; l++) {
            if (!lm_move_is_edge_op((lm_move_kind)k, l))
                continue;
            lm_stat_view v;
            view(st, (lm_move_kind)k, l, now, &v);
            if (v.f < st->min_weight || v.f <= 0)
                continue;
            double eff = v.mean / fmax(v.t, 1e-9);
            if (!found || eff < best) {
                found = 1;
                best = eff;
                *kind = (lm_move_kind)k;
                *level = l;
            }
        }
    return found;
}

int lm_move_stats_should_try(const lm_move_stats *st, lm_move_kind kind, int level, double de_total,
                             uint64_t now)
{
    lm_stat_view o, b;
    view(st, kind, level, now, &o);
    if (o.f < st->min_weight || o.f <= 0)
        return 1;
    lm_move_kind bk;
    int bl;
    if (!lm_move_stats_best(st, now, &bk, &bl))
        return 1;
    view(st, bk, bl, now, &b);
    /* Utilisation is time (evaluations) spent, attenuated: a cheap operation is little used even
     * when attempted often. */
    double fo = o.f * o.t, fb = b.f * b.t;
    double q = fb / (fo + fb);
    /* σ widened by O*'s spread over the sample count: a few identical outcomes (σ = 0) do not
     * make an operation certain to lose for ever; the widening vanishes with more samples. */
    double sigma = sqrt(o.sigma * o.sigma + b.sigma * b.sigma / (o.f + 1.0));
    double bound = b.mean * (o.t / fmax(b.t, 1e-9)) + M_SQRT2 * lm_erfinv(q) * sigma;
    if (isnan(bound))
        return 1;
    /* "<=": O* itself passes even when its σ is 0. The ΔE_total term (do not start a possibly
     * expensive move once much was gained on this edge) applies once progress was made, and not
     * to operations that cost a few evaluations. */
    int cheap = o.t <= LM_CHEAP_EVALS;
    return o.mean <= bound && (cheap || de_total >= 0 || o.mean < de_total);
}

/* Giles, "Approximating the erfinv function" (GPU Computing Gems, 2011), single precision. */
static double erfinv_giles(double x)
{
    double w = -log((1.0 - x) * (1.0 + x)), p;
    if (w < 5.0) {
        w -= 2.5;
        p = 2.81022636e-08;
        p = 3.43273939e-07 + p * w;
        p = -3.5233877e-06 + p * w;
        p = -4.39150654e-06 + p * w;
        p = 0.00021858087 + p * w;
        p = -0.00125372503 + p * w;
        p = -0.00417768164 + p * w;
        p = 0.246640727 + p * w;
        p = 1.50140941 + p * w;
    } else {
        w = sqrt(w) - 3.0;
        p = -0.000200214257;
        p = 0.000100950558 + p * w;
        p = 0.00134934322 + p * w;
        p = -0.00367342844 + p * w;
        p = 0.00573950773 + p * w;
        p = -0.0076224613 + p * w;
        p = 0.00943887047 + p * w;
        p = 1.00167406 + p * w;
        p = 2.83297682 + p * w;
    }
    return p * x;
}

double lm_erfinv(double x)
{
    if (isnan(x) || x < -1.0 || x > 1.0)
        return NAN;
    if (x < 0)
        return -lm_erfinv(-x);
    if (x == 1.0)
        return INFINITY;
    if (x == 0.0)
        return 0.0;
    double r = erfinv_giles(x);
    /* Newton on erf(r) - x, written as (1 - x) - erfc(r) above 1/2 where 1 - x is exact; the
     * single-precision guess is poor in the far tails, so iterate until the step is negligible. */
    for (int i = 0; i < 32; i++) {
        double d = 2.0 / sqrt(M_PI) * exp(-r * r);
        if (!(d > 0))
            break;
        double res = x > 0.5 ? (1.0 - x) - erfc(r) : erf(r) - x;
        double step = res / d;
        r -= step;
        if (fabs(step) <= 1e-16 * fabs(r))
            break;
    }
    return r;
}

void lm_stat_save(lm_bin *b, const lm_stat *s)
{
    lm_put_f64(b, s->w);
    lm_put_f64(b, s->sum_x);
    lm_put_f64(b, s->sum_x2);
    lm_put_f64(b, s->sum_t);
    lm_put_u64(b, s->time);
    lm_put_u64(b, s->count);
}

void lm_stat_load(lm_bin *b, lm_stat *s)
{
    s->w = lm_get_f64(b);
    s->sum_x = lm_get_f64(b);
    s->sum_x2 = lm_get_f64(b);
    s->sum_t = lm_get_f64(b);
    s->time = lm_get_u64(b);
    s->count = lm_get_u64(b);
}

void lm_move_stats_save(lm_bin *b, const lm_move_stats *st)
{
    lm_put_f64(b, st->half_life);
    lm_put_f64(b, st->min_weight);
    for (int k = 0; k < LM_MOVE_KINDS; k++)
        for (int l = 0; l < LM_LEVELS; l++)
            lm_stat_save(b, &st->op[k][l]);
}

void lm_move_stats_load(lm_bin *b, lm_move_stats *st)
{
    st->half_life = lm_get_f64(b);
    st->min_weight = lm_get_f64(b);
    for (int k = 0; k < LM_MOVE_KINDS; k++)
        for (int l = 0; l < LM_LEVELS; l++)
            lm_stat_load(b, &st->op[k][l]);
}
