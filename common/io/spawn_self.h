/* common/io/spawn_self.h — this program run afresh as a helper process (fork, then exec of
 * /proc/self/exe), for work whose crash must not take the caller down: decoding an image, reading
 * a model. A fork alone is not enough: the child would inherit locks and thread pools of threads
 * it does not have (OpenImageIO's TIFF reader spun forever in such a child). The helper is told
 * what to do by environment variables that a constructor of the helper's code reads before main
 * runs; it talks to the caller on its stdin and stdout. */
#ifndef LM_COMMON_SPAWN_SELF_H
#define LM_COMMON_SPAWN_SELF_H

#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#include "common/error.h"

/* The names of the variables that tell a helper what to do begin with this; a helper starts with
 * only the ones its spawn sets (a model reader that decodes a texture in a helper of its own
 * passes none of its own settings on). */
#define LM_SPAWN_ENV_PREFIX "LUMESH_HELPER_"

/* Start this program with `env` (NULL-terminated "NAME=VALUE" strings) added to the caller's
 * environment less its LM_SPAWN_ENV_PREFIX variables (and with ASan's signal handlers off, so that
 * a crash in a sanitizer build is the signal its caller reports); every descriptor of the caller
 * is closed in it. Everything is prepared before the fork: the child only calls dup2, close_range
 * and execve (async-signal-safe), so a caller with threads is safe. Its stdin gets `size` bytes of
 * `data` (none when data is NULL), then end of file; a helper that dies before reading them costs
 * the caller nothing (SIGPIPE is ignored while they are written). Blocks until they are written.
 * On success *pid is the helper and *answer_fd the read end of its stdout: the caller reads the
 * answer, closes it, then reaps the helper (waitpid); an exec that fails ends the child with
 * status 127. Errors: LM_E_NOMEM, LM_E_IO (no pipe, fork failed); one line naming `what`. */
lm_status lm_spawn_self(const char *what, const char *const *env, const void *data, size_t size,
                        pid_t *pid, int *answer_fd);

/* In a helper, first thing: its stdout becomes the answer's alone (the descriptor returned, or -1;
 * whatever a library prints goes to stderr from now on), and a CPU limit of `cpu_seconds`, so a
 * helper that loops forever is killed (SIGXCPU) and reported like one that crashed. */
int lm_spawn_helper_begin(unsigned cpu_seconds);

/* Write (read) all n bytes on fd, retrying EINTR: 1, or 0 when the other end is gone (or the
 * bytes ran out). Blocking. */
int lm_fd_write_all(int fd, const void *p, size_t n);
int lm_fd_read_all(int fd, void *p, size_t n);

/* In a helper: all the bytes on stdin (*n of them, at most `max`) in a malloc'ed buffer with a NUL
 * after them; NULL when out of memory or over `max`. */
uint8_t *lm_spawn_read_stdin(size_t max, size_t *n);

#endif
