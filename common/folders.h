/* common/folders.h — output folders made on demand: every command that writes into a folder (or a
 * file inside one) creates the folders that are missing, as `mkdir -p` does. */
#ifndef LM_COMMON_FOLDERS_H
#define LM_COMMON_FOLDERS_H

#include "common/error.h"

/* Create `dir` and every missing folder above it (mode 0777, less the umask). LM_OK when it exists
 * as a folder afterwards; LM_E_IO naming the component that could not be made, or that exists and
 * is not a folder. */
lm_status lm_make_folders(const char *dir);

/* The same for the folder that holds the file `path` (nothing to do for a bare file name). */
lm_status lm_make_parent_folders(const char *path);

#endif
