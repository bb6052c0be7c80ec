/* coordinator/cli/cli_args.c — the subcommands' command lines: an option table made into
 * getopt_long's arrays and read in one loop (co_cli_parse), number parsing with ranges, one-line
 * errors, and the checks of the simplifiers' worker options. */
#include "coordinator/cli/cli_args.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/view.h"
#include "coordinator/job/job.h"
#include "coordinator/simplify/work.h"

const uint32_t co_opt_job_in_process = CO_JOB_NONE;

lm_status co_arg_u64(const char *cmd, const char *flag, const char *val, uint64_t lo, uint64_t hi,
                     uint64_t *out)
{
    char *end = NULL;
    errno = 0;
    unsigned long long x = val && *val && *val != '-' ? strtoull(val, &end, 10) : 0;
    if (!val || !*val || *val == '-' || errno || *end || x < lo || x > hi) {
        fprintf(stderr, "lumesh %s: %s expects an integer in [%llu, %llu], got '%s'\n", cmd, flag,
                (unsigned long long)lo, (unsigned long long)hi, val ? val : "");
        return LM_E_INVALID;
    }
    *out = x;
    return LM_OK;
}

lm_status co_arg_u32(const char *cmd, const char *flag, const char *val, uint32_t lo, uint32_t hi,
                     uint32_t *out)
{
    uint64_t x;
    lm_status s = co_arg_u64(cmd, flag, val, lo, hi, &x);
    if (!s)
        *out = (uint32_t)x;
    return s;
}

lm_status co_arg_double(const char *cmd, const char *flag, const char *val, double lo, double hi,
                        double *out)
{
    char *end = NULL;
    errno = 0;
    double x = val && *val ? strtod(val, &end) : NAN;
    if (!val || !*val || errno || *end || !isfinite(x) || x < lo || x > hi) {
        fprintf(stderr, "lumesh %s: %s expects a number in [%g, %g], got '%s'\n", cmd, flag, lo, hi,
                val ? val : "");
        return LM_E_INVALID;
    }
    *out = x;
    return LM_OK;
}

int co_cli_usage_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "lumesh %s: ", cmd);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return 1;
}

int co_cli_fail(const char *cmd, lm_status s)
{
    const char *msg = lm_last_error();
    fprintf(stderr, "lumesh %s: %s\n", cmd, msg && *msg ? msg : lm_strerror(s));
    return lm_exit_code(s);
}

/* What getopt_long's ':' (a flag without its value) or '?' (an unknown flag) means for the user:
 * one line on stderr; returns 1. */
static int bad_option(const char *cmd, int c, char **argv)
{
    if (c == ':')
        return co_cli_usage_error(cmd, "option %s needs a value (see --help)", argv[optind - 1]);
    return co_cli_usage_error(cmd, "unknown option '%s' (see --help)", argv[optind - 1]);
}

void co_cli_reset_getopt(void)
{
    optind = 0; /* glibc: 0 forces a full re-initialisation */
    opterr = 1;
    co_cli_views_reset();
}

int co_simplify_workers_given(const co_simplify_workers *w)
{
    return w->local || w->listen || w->keys || w->renderer;
}

int co_cli_check_simplify_workers(const char *cmd, const co_simplify_workers *w)
{
    if ((w->keys || w->renderer) && !w->local && !w->listen)
        return co_cli_usage_error(cmd, "--keys and --renderer go with --workers N or --listen");
    return -1;
}

/* A whole number x taken for o: stored in o's type, a 0 as o->zero says. */
static void store_whole(const co_opt *o, uint64_t x)
{
    if (o->kind == CO_OPT_KIND_U64)
        *(uint64_t *)o->to = x || !o->zero ? x : *(const uint64_t *)o->zero;
    else if (o->kind == CO_OPT_KIND_U32)
        *(uint32_t *)o->to = x || !o->zero ? (uint32_t)x : *(const uint32_t *)o->zero;
    else
        *(int *)o->to = (int)x;
}

/* The value val of o: -1 when taken, else the exit code (the reason said). */
static int take(const char *cmd, const co_opt *o, const char *val)
{
    char flag[64];
    snprintf(flag, sizeof flag, "--%s", o->name);
    uint64_t x;
    double d;
    switch (o->kind) {
    case CO_OPT_KIND_STR:
        *(const char **)o->to = val;
        return -1;
    case CO_OPT_KIND_FLAG:
        *(int *)o->to = 1;
        return -1;
    case CO_OPT_KIND_CALL:
    case CO_OPT_KIND_CALL_FLAG:
        return o->call(o->to, val);
    case CO_OPT_KIND_VIEWS:
    case CO_OPT_KIND_VIEWS_FROM:
        return co_cli_take_views(cmd, o->to, val, o->kind == CO_OPT_KIND_VIEWS_FROM);
    case CO_OPT_KIND_DOUBLE:
        if (co_arg_double(cmd, flag, val, o->dlo, o->dhi, &d))
            return 1;
        *(double *)o->to = d != 0 || !o->zero ? d : *(const double *)o->zero;
        return -1;
    default:
        if (co_arg_u64(cmd, flag, val, o->lo, o->hi, &x))
            return 1;
        store_whole(o, x);
        return -1;
    }
}

static int takes_value(const co_opt *o)
{
    return o->kind != CO_OPT_KIND_FLAG && o->kind != CO_OPT_KIND_CALL_FLAG;
}

/* getopt_long's arrays for opts[0..n) and --help/-h: option i answers 256 + i, its letter itself.
 */
static void make_getopt(const co_opt *opts, size_t n, struct option *longs, char *letters)
{
    size_t k = 0;
    letters[k++] = ':';
    for (size_t i = 0; i < n; i++) {
        longs[i] =
            (struct option){opts[i].name, takes_value(&opts[i]) ? required_argument : no_argument,
                            NULL, 256 + (int)i};
        if (opts[i].letter) {
            letters[k++] = opts[i].letter;
            if (takes_value(&opts[i]))
                letters[k++] = ':';
        }
    }
    longs[n] = (struct option){"help", no_argument, NULL, 'h'};
    longs[n + 1] = (struct option){NULL, 0, NULL, 0};
    letters[k++] = 'h';
    letters[k] = '\0';
}

/* The option getopt_long answered c for, or NULL when c is none of the table's. */
static const co_opt *find(const co_opt *opts, size_t n, int c)
{
    if (c >= 256 && (size_t)(c - 256) < n)
        return &opts[c - 256];
    for (size_t i = 0; c > 0 && i < n; i++)
        if (opts[i].letter == c)
            return &opts[i];
    return NULL;
}

/* The count of the operands argv[optind..argc) against s: -1 when fine, else 1 (said). */
static int check_operands(const co_cli_spec *s, int argc, char **argv)
{
    int n = argc - optind;
    if (n < s->min)
        return co_cli_usage_error(s->cmd, "%s", s->missing);
    if (s->max >= 0 && n > s->max && s->too_many)
        return co_cli_usage_error(s->cmd, "%s", s->too_many);
    if (s->max >= 0 && n > s->max)
        return co_cli_usage_error(s->cmd, "unexpected argument '%s'%s", argv[optind + s->max],
                                  s->see_help ? " (see --help)" : "");
    return -1;
}

/* The first needed option of opts[0..n) not given (seen[i] 0), said; -1 when none. */
static int check_needed(const char *cmd, const co_opt *opts, size_t n, const unsigned char *seen)
{
    for (size_t i = 0; i < n; i++)
        if (opts[i].needed && !seen[i])
            return co_cli_usage_error(cmd, "%s", opts[i].needed);
    return -1;
}

int co_cli_parse(const co_cli_spec *s, const co_opt *opts, size_t n, int argc, char **argv)
{
    struct option longs[CO_OPTS_MAX + 2];
    char letters[2 * CO_OPTS_MAX + 3];
    unsigned char seen[CO_OPTS_MAX] = {0};
    if (n > CO_OPTS_MAX)
        return co_cli_fail(s->cmd,
                           lm_fail(LM_E_INTERNAL, "%zu options, more than %d", n, CO_OPTS_MAX));
    make_getopt(opts, n, longs, letters);
    opterr = 0;
    int c, rc;
    while ((c = getopt_long(argc, argv, letters, longs, NULL)) != -1) {
        const co_opt *o = find(opts, n, c);
        if (c == 'h' && !o) {
            s->usage(stdout);
            return 0;
        }
        rc = o ? take(s->cmd, o, optarg) : bad_option(s->cmd, c, argv);
        if (rc >= 0)
            return rc;
        seen[o - opts] = 1;
    }
    rc = check_operands(s, argc, argv);
    return rc >= 0 ? rc : check_needed(s->cmd, opts, n, seen);
}
