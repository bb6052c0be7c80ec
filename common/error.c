/* common/error.c — status names, the thread-local last-error message, asserts. */
#include "common/error.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static _Thread_local char last_message[512];

const char *lm_strerror(lm_status s)
{
    static const char *const names[LM_E_COUNT_] = {
        [LM_OK] = "ok",
        [LM_E_INVALID] = "invalid argument",
        [LM_E_IO] = "input/output error",
        [LM_E_FORMAT] = "malformed or unsupported file",
        [LM_E_RANGE] = "value out of range",
        [LM_E_NOMEM] = "out of memory",
        [LM_E_ILLEGAL] = "illegal mesh operation",
        [LM_E_DEVICE] = "rendering device error",
        [LM_E_INTERNAL] = "internal error",
        [LM_E_UNSUPPORTED] = "unsupported",
        [LM_E_POISON] = "poison batch",
    };
    if ((int)s < 0 || s >= LM_E_COUNT_)
        return "unknown error";
    return names[s];
}

lm_status lm_failv(lm_status s, const char *fmt, va_list ap)
{
    vsnprintf(last_message, sizeof last_message, fmt, ap);
    for (char *c = last_message; *c; c++) /* one line, whatever a file's bytes put in it */
        if ((unsigned char)*c < 0x20 || *c == 0x7f)
            *c = '?';
    return s;
}

lm_status lm_fail(lm_status s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    lm_failv(s, fmt, ap);
    va_end(ap);
    return s;
}

const char *lm_last_error(void)
{
    return last_message;
}

void lm_clear_error(void)
{
    last_message[0] = '\0';
}

int lm_exit_code(lm_status s)
{
    switch (s) {
    case LM_OK:
        return 0;
    case LM_E_INVALID:
    case LM_E_IO:
    case LM_E_FORMAT:
    case LM_E_RANGE:
    case LM_E_ILLEGAL:
    case LM_E_UNSUPPORTED:
        return 1;
    default:
        return 2;
    }
}

void lm_assert_fail(const char *expr, const char *file, int line)
{
    fprintf(stderr, "lumesh: assertion failed: %s (%s:%d)\n", expr, file, line);
    abort();
}
