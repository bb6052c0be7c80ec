/* common/io/atomic_file.h — files written atomically: a temporary file beside the target, renamed
 * over it on commit, so a reader never sees half a file (outputs, checkpoints, reports). */
#ifndef LM_COMMON_IO_ATOMIC_FILE_H
#define LM_COMMON_IO_ATOMIC_FILE_H

#include <stdio.h>

#include "common/error.h"

/* Atomic file helpers shared by every writer: open "<path>.tmp.XXXXXX" beside path, then commit
 * (fflush, fsync, rename) or abort (unlink). A writer that must write tmp_path by name
 * (OpenImageIO) closes fp and sets it to NULL before writing; commit then syncs the file by name.
 */
typedef struct lm_atomic_file {
    char *final_path;
    char *tmp_path;
    void *fp; /* FILE* */
} lm_atomic_file;
lm_status lm_atomic_open(lm_atomic_file *f, const char *path);
lm_status lm_atomic_commit(lm_atomic_file *f);
void lm_atomic_abort(lm_atomic_file *f);

#endif
