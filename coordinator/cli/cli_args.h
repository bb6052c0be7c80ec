/* coordinator/cli/cli_args.h — small helpers every `lumesh` subcommand uses: strict number parsing
 * with ranges, one-line error reporting, and the common exit-code rule (0 ok, 1 user error,
 * 2 internal). Subcommands parse flags with getopt_long and call these for values and errors. */
#ifndef LM_COORDINATOR_CLI_ARGS_H
#define LM_COORDINATOR_CLI_ARGS_H

#include <stdint.h>

#include "common/error.h"

typedef struct co_simplify_workers co_simplify_workers; /* coordinator/simplify/work.h */

/* Parse a whole decimal string into [lo, hi]. On failure prints
 * "lumesh CMD: --FLAG expects an integer in [lo, hi], got 'VAL'" and returns LM_E_INVALID. */
lm_status co_arg_u64(const char *cmd, const char *flag, const char *val, uint64_t lo, uint64_t hi,
                     uint64_t *out);
lm_status co_arg_u32(const char *cmd, const char *flag, const char *val, uint32_t lo, uint32_t hi,
                     uint32_t *out);
lm_status co_arg_double(const char *cmd, const char *flag, const char *val, double lo, double hi,
                        double *out);

/* --views N and --size PIXELS, with the same ranges in every subcommand that renders views. */
lm_status co_arg_views(const char *cmd, const char *val, uint32_t *out);
lm_status co_arg_size(const char *cmd, const char *val, uint32_t *out);

/* Where simplify and lod render: getopt code c with value val if it is one of their worker
 * options ('w' --workers N, 'L' --listen, 'K' --keys, 'I' --renderer). Returns -1 when taken,
 * 1 when val was wrong (said on stderr), -2 when c is none of them. */
int co_arg_simplify_workers(const char *cmd, int c, const char *val, co_simplify_workers *w);
/* Whether w asks for workers at all (any of those options given). */
int co_simplify_workers_given(const co_simplify_workers *w);
/* -1 when w makes sense, else 1 with the one-line reason on stderr (--keys or --renderer with
 * neither --workers nor --listen would be ignored). */
int co_cli_check_simplify_workers(const char *cmd, const co_simplify_workers *w);

/* Print "lumesh CMD: message" (one line) to stderr; returns 1 (the user-error exit code). */
int co_cli_usage_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Print "lumesh CMD: <lm_last_error() or lm_strerror(s)>" and return lm_exit_code(s). */
int co_cli_fail(const char *cmd, lm_status s);

/* What getopt_long's ':' (a flag without its value) or '?' (an unknown flag) means for the user:
 * one line on stderr; returns 1. */
int co_cli_bad_option(const char *cmd, int c, char **argv);

/* getopt_long state is global in libc: call before each subcommand's parse (resets optind). */
void co_cli_reset_getopt(void);

/* Subcommands: each takes argv with argv[0] = the subcommand name; returns the exit code. */
int co_cli_optimize(int argc, char **argv);
int co_cli_simplify(int argc, char **argv);
int co_cli_energy(int argc, char **argv);
int co_cli_compare(int argc, char **argv);
int co_cli_report(int argc, char **argv);
int co_cli_render(int argc, char **argv);
int co_cli_devices(int argc, char **argv);
int co_cli_gen_frog(int argc, char **argv);
int co_cli_demo(int argc, char **argv);
int co_cli_bench(int argc, char **argv);
int co_cli_lod(int argc, char **argv);
int co_cli_pm_extract(int argc, char **argv);
int co_cli_workers(int argc, char **argv);
int co_cli_keygen(int argc, char **argv);

#endif
