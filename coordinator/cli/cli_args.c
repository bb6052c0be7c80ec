/* coordinator/cli/cli_args.c — number parsing, one-line errors and the worker options shared by
 * the subcommands. */
#include "coordinator/cli/cli_args.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "common/view.h"
#include "coordinator/simplify/work.h"

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

int co_cli_bad_option(const char *cmd, int c, char **argv)
{
    if (c == ':')
        return co_cli_usage_error(cmd, "option %s needs a value (see --help)", argv[optind - 1]);
    return co_cli_usage_error(cmd, "unknown option '%s' (see --help)", argv[optind - 1]);
}

lm_status co_arg_views(const char *cmd, const char *val, uint32_t *out)
{
    return co_arg_u32(cmd, "--views", val, 1, LM_MAX_VIEWS, out);
}

lm_status co_arg_size(const char *cmd, const char *val, uint32_t *out)
{
    return co_arg_u32(cmd, "--size", val, 16, LM_MAX_VIEW_SIZE, out);
}

void co_cli_reset_getopt(void)
{
    optind = 0; /* glibc: 0 forces a full re-initialisation */
    opterr = 1;
}

int co_arg_simplify_workers(const char *cmd, int c, const char *val, co_simplify_workers *w)
{
    switch (c) {
    case 'w':
        return co_arg_u32(cmd, "--workers", val, 0, 256, &w->local) ? 1 : -1;
    case 'L':
        w->listen = val;
        return -1;
    case 'K':
        w->keys = val;
        return -1;
    case 'I':
        w->renderer = val;
        return -1;
    default:
        return -2;
    }
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
