/* common/log.c — leveled logging to stderr. */
#include "common/log.h"

#include <stdarg.h>
#include <stdio.h>

static lm_log_level current_level = LM_LOG_WARN;

void lm_log_set_level(lm_log_level level)
{
    current_level = level;
}

lm_log_level lm_log_get_level(void)
{
    return current_level;
}

void lm_log(lm_log_level level, const char *fmt, ...)
{
    static const char *const tags[] = {"error", "warning", "info", "debug"};
    if (level > current_level)
        return;
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "lumesh: %s: ", tags[level]);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}
