/* coordinator/cli/cli_args.h — what every `lumesh` subcommand parses its command line with: a
 * table of its options (co_opt: long name, one-letter form, kind, where the value goes; the shared
 * options — output, views, size, device, seed, evals, workers — written once below) that
 * co_cli_parse turns into getopt_long's arrays and loop, strict number parsing with ranges,
 * one-line error reporting, and the common exit-code rule (0 ok, 1 user error, 2 internal). */
#ifndef LM_COORDINATOR_CLI_ARGS_H
#define LM_COORDINATOR_CLI_ARGS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "common/error.h"
#include "common/view.h"

/* Parse a whole decimal string into [lo, hi]. On failure prints
 * "lumesh CMD: --FLAG expects an integer in [lo, hi], got 'VAL'" and returns LM_E_INVALID. */
lm_status co_arg_u64(const char *cmd, const char *flag, const char *val, uint64_t lo, uint64_t hi,
                     uint64_t *out);
lm_status co_arg_u32(const char *cmd, const char *flag, const char *val, uint32_t lo, uint32_t hi,
                     uint32_t *out);
lm_status co_arg_double(const char *cmd, const char *flag, const char *val, double lo, double hi,
                        double *out);

/* What an option's value is and where it goes (co_opt.to). */
typedef enum co_opt_kind {
    CO_OPT_KIND_STR,        /* const char *: the value as given */
    CO_OPT_KIND_FLAG,       /* int: set to 1; takes no value */
    CO_OPT_KIND_U32,        /* uint32_t: a whole number in [lo, hi] */
    CO_OPT_KIND_INT,        /* int: the same (an image side) */
    CO_OPT_KIND_U64,        /* uint64_t: a whole number in [lo, hi] */
    CO_OPT_KIND_DOUBLE,     /* double: a number in [dlo, dhi] */
    CO_OPT_KIND_CALL,       /* call(to, value) */
    CO_OPT_KIND_CALL_FLAG,  /* call(to, NULL); takes no value */
    CO_OPT_KIND_VIEWS,      /* lm_view_spec: --views N | upper | upper:N (co_cli_take_views) */
    CO_OPT_KIND_VIEWS_FROM, /* lm_view_spec: --views-from FILE, read at once */
} co_opt_kind;

/* --views and --views-from write an lm_view_spec. Commands preset its count to their default
 * number of views or to 0 for their options' own default (resolved in one place: `--views upper`
 * keeps it, `--views upper:N` and `--views N` set it); dist starts SPHERE. --views-from reads the
 * file as it is parsed (errors: one line, exit 1); its cameras live until the process ends (one
 * command a process; co_cli_reset_getopt forgets them). --views and --views-from exclude each
 * other. Returns -1 when taken, else the exit code (the reason said, "lumesh CMD: ..."). */
int co_cli_take_views(const char *cmd, lm_view_spec *v, const char *val, int from);
/* Forget the --views/--views-from given (co_cli_reset_getopt calls it). */
void co_cli_views_reset(void);

/* One option of a subcommand. Numbers out of range say so on one line (co_arg_u64). */
typedef struct co_opt {
    const char *name; /* the long name, without "--"; the messages call it --name */
    char letter;      /* its one-letter form (-o), or 0 */
    co_opt_kind kind;
    void *to;         /* where the value goes; the CALL kinds: the callback's context */
    uint64_t lo, hi;  /* whole numbers: the range */
    double dlo, dhi;  /* CO_OPT_KIND_DOUBLE: the range */
    const void *zero; /* numbers: what a 0 given stands for (of the type of *to); NULL: 0 */
    int (*call)(void *to, const char *val); /* -1 when taken, else the exit code (said) */
    const char *needed; /* the whole message when the option is not given; NULL: optional */
} co_opt;

/* Table rows; `to` must point to the type the kind writes (checked by the compiler). CO_OPT_ROW
 * starts a row of any kind: {CO_OPT_ROW(...), .lo = 1, .hi = 9, .needed = "missing --x N"}. */
#define CO_OPT_TO(type, p) ((void *)(1 ? (p) : (type *)0))
#define CO_OPT_ROW(n, l, k, type, p)                                                               \
    .name = (n), .letter = (l), .kind = (k), .to = CO_OPT_TO(type, p)
#define CO_OPT_STR(n, l, p)                                                                        \
    {                                                                                              \
        CO_OPT_ROW(n, l, CO_OPT_KIND_STR, const char *, p)                                         \
    }
#define CO_OPT_FLAG(n, l, p)                                                                       \
    {                                                                                              \
        CO_OPT_ROW(n, l, CO_OPT_KIND_FLAG, int, p)                                                 \
    }
#define CO_OPT_U32(n, l, p, a, b)                                                                  \
    {                                                                                              \
        CO_OPT_ROW(n, l, CO_OPT_KIND_U32, uint32_t, p), .lo = (a), .hi = (b)                       \
    }
#define CO_OPT_INT(n, l, p, a, b)                                                                  \
    {                                                                                              \
        CO_OPT_ROW(n, l, CO_OPT_KIND_INT, int, p), .lo = (a), .hi = (b)                            \
    }
#define CO_OPT_U64(n, l, p, a, b)                                                                  \
    {                                                                                              \
        CO_OPT_ROW(n, l, CO_OPT_KIND_U64, uint64_t, p), .lo = (a), .hi = (b)                       \
    }
#define CO_OPT_DOUBLE(n, p, a, b)                                                                  \
    {                                                                                              \
        CO_OPT_ROW(n, 0, CO_OPT_KIND_DOUBLE, double, p), .dlo = (a), .dhi = (b)                    \
    }
#define CO_OPT_CALL(n, l, f, ctx)                                                                  \
    {                                                                                              \
        CO_OPT_ROW(n, l, CO_OPT_KIND_CALL, void, ctx), .call = (f)                                 \
    }
#define CO_OPT_CALL_FLAG(n, f, ctx)                                                                \
    {                                                                                              \
        CO_OPT_ROW(n, 0, CO_OPT_KIND_CALL_FLAG, void, ctx), .call = (f)                            \
    }

/* The shared options, the same in every subcommand that has them. */
#define CO_OPT_OUTPUT(p) CO_OPT_STR("output", 'o', p)
#define CO_OPT_OUTPUT_NEEDED(p, msg)                                                               \
    {                                                                                              \
        CO_OPT_ROW("output", 'o', CO_OPT_KIND_STR, const char *, p), .needed = (msg)               \
    }
#define CO_OPT_DEVICE(p) CO_OPT_STR("device", 0, p)
/* --views and --views-from (an lm_view_spec *): two rows. */
#define CO_OPT_VIEWS(p)                                                                            \
    {CO_OPT_ROW("views", 0, CO_OPT_KIND_VIEWS, lm_view_spec, p)},                                  \
    {                                                                                              \
        CO_OPT_ROW("views-from", 0, CO_OPT_KIND_VIEWS_FROM, lm_view_spec, p)                       \
    }
#define CO_OPT_SIZE(p) CO_OPT_U32("size", 0, p, 16, LM_MAX_VIEW_SIZE)
#define CO_OPT_SIZE_INT(p) CO_OPT_INT("size", 0, p, 16, LM_MAX_VIEW_SIZE)
#define CO_OPT_SEED(p, lo) CO_OPT_U64("seed", 0, p, lo, UINT64_MAX)
#define CO_OPT_EVALS(p) CO_OPT_U64("evals", 0, p, 1, UINT64_MAX / 2)
/* --workers N of optimize and demo: up to 4096; 0 renders in this process (CO_JOB_NONE). */
extern const uint32_t co_opt_job_in_process;
#define CO_OPT_JOB_WORKERS(p)                                                                      \
    {                                                                                              \
        CO_OPT_ROW("workers", 0, CO_OPT_KIND_U32, uint32_t, p), .lo = 0, .hi = 4096,               \
                                                                .zero = &co_opt_job_in_process     \
    }
/* Where simplify and lod render (a co_simplify_workers *, coordinator/simplify/work.h): --workers
 * N (up to 256), --listen ADDR, --keys DIR, --renderer ID. Four rows. */
#define CO_OPT_SIMPLIFY_WORKERS(w)                                                                 \
    CO_OPT_U32("workers", 0, &(w)->local, 0, 256), CO_OPT_STR("listen", 0, &(w)->listen),          \
        CO_OPT_STR("keys", 0, &(w)->keys), CO_OPT_STR("renderer", 0, &(w)->renderer)

/* A subcommand's command line as a whole: its name (for the messages), its --help (-h) text, and
 * how many operands (words that are not options) it takes. */
typedef struct co_cli_spec {
    const char *cmd;
    void (*usage)(FILE *f); /* prints the help; called with stdout */
    int min, max;           /* operands; max -1: any number, unchecked */
    const char *missing;    /* the whole message when there are fewer than min */
    const char *too_many;   /* ... when there are more than max; NULL: "unexpected argument 'A'" */
    int see_help;           /* "unexpected argument 'A'" ends with " (see --help)" */
} co_cli_spec;

/* A number macro as text, for messages written as literals ("at most " CO_STR(MAX) " models"). */
#define CO_STR(x) CO_STR_(x)
#define CO_STR_(x) #x

/* The most options one table may have. */
#define CO_OPTS_MAX 48
#define CO_OPTS_N(t) (sizeof(t) / sizeof((t)[0]))

/* Parse argv's options from getopt_long's optind on (the caller resets it: co_cli_reset_getopt)
 * by the table opts[0..n) plus --help/-h, in order, the first wrong one said on one line ("option
 * --x needs a value (see --help)", "unknown option '--x' (see --help)", a number's range, a
 * callback's reason), then the operands' count, then the needed options not given (in the
 * table's order). Returns -1 to go on (the operands are argv[optind..argc)), 0 after --help, else
 * the exit code. */
int co_cli_parse(const co_cli_spec *s, const co_opt *opts, size_t n, int argc, char **argv);

typedef struct co_simplify_workers co_simplify_workers; /* coordinator/simplify/work.h */

/* Whether w asks for workers at all (any of those options given). */
int co_simplify_workers_given(const co_simplify_workers *w);
/* -1 when w makes sense, else 1 with the one-line reason on stderr (--keys or --renderer with
 * neither --workers nor --listen would be ignored). */
int co_cli_check_simplify_workers(const char *cmd, const co_simplify_workers *w);

/* Print "lumesh CMD: message" (one line) to stderr; returns 1 (the user-error exit code). */
int co_cli_usage_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Print "lumesh CMD: <lm_last_error() or lm_strerror(s)>" and return lm_exit_code(s). */
int co_cli_fail(const char *cmd, lm_status s);

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
