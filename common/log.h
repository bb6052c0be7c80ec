/* common/log.h — leveled logging to stderr. The level is per process, set once by the CLI. */
#ifndef LM_COMMON_LOG_H
#define LM_COMMON_LOG_H

typedef enum lm_log_level { LM_LOG_ERROR, LM_LOG_WARN, LM_LOG_INFO, LM_LOG_DEBUG } lm_log_level;

void lm_log_set_level(lm_log_level level);
lm_log_level lm_log_get_level(void);
void lm_log(lm_log_level level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#define lm_warn(...) lm_log(LM_LOG_WARN, __VA_ARGS__)
#define lm_info(...) lm_log(LM_LOG_INFO, __VA_ARGS__)
#define lm_debug(...) lm_log(LM_LOG_DEBUG, __VA_ARGS__)

#endif
