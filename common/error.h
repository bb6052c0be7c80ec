/* common/error.h — the one error rule of lumesh.
 * Every fallible function returns lm_status (0 = LM_OK); objects come back through out-parameters.
 * A failing function also records a one-line human message (thread-local) that the CLI prints.
 * Errors from EGL, libusb, assimp and OpenImageIO are converted to these codes at the boundary. */
#ifndef LM_COMMON_ERROR_H
#define LM_COMMON_ERROR_H

#include <stdarg.h>

typedef enum lm_status {
    LM_OK = 0,
    LM_E_INVALID,     /* bad argument or flag from the user */
    LM_E_IO,          /* file missing, unreadable, unwritable */
    LM_E_FORMAT,      /* malformed or unsupported file content */
    LM_E_RANGE,       /* count or value out of the accepted range (absurd sizes, NaN, bad index) */
    LM_E_NOMEM,       /* allocation failed */
    LM_E_ILLEGAL,     /* a mesh operation that would break legality (link condition, boundary...) */
    LM_E_DEVICE,      /* rendering device / EGL / GL failure */
    LM_E_INTERNAL,    /* a bug or an unexpected library failure */
    LM_E_UNSUPPORTED, /* valid request this build or device cannot serve */
    LM_E_POISON,      /* a batch the workers it was sent to failed on: its moves are refused */
    LM_E_COUNT_
} lm_status;

/* Name of a status code ("invalid argument", ...). Never NULL. */
const char *lm_strerror(lm_status s);

/* Record the message for the current thread and return `s` (for `return lm_fail(...)`). */
lm_status lm_fail(lm_status s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
lm_status lm_failv(lm_status s, const char *fmt, va_list ap);

/* The last message recorded on this thread ("" if none). */
const char *lm_last_error(void);
void lm_clear_error(void);

/* Exit code for the CLI: 0 ok, 1 user error (invalid/io/format/range/illegal), 2 internal. */
int lm_exit_code(lm_status s);

/* Programmer errors: asserts stay on in every build. */
#define LM_ASSERT(cond)                                                                            \
    do {                                                                                           \
        if (!(cond))                                                                               \
            lm_assert_fail(#cond, __FILE__, __LINE__);                                             \
    } while (0)
_Noreturn void lm_assert_fail(const char *expr, const char *file, int line);

#endif
