/* common/folders.c — `mkdir -p` for output folders: walks the path one component at a time. */
#include "common/folders.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Make the folder `path` (its parents exist) unless it is one already. */
static lm_status make_one(const char *path)
{
    struct stat sb;
    if (mkdir(path, 0777) != 0 && errno != EEXIST)
        return lm_fail(LM_E_IO, "cannot create folder '%s': %s", path, strerror(errno));
    if (stat(path, &sb) != 0)
        return lm_fail(LM_E_IO, "cannot create folder '%s': %s", path, strerror(errno));
    if (!S_ISDIR(sb.st_mode))
        return lm_fail(LM_E_IO, "cannot create folder '%s': a file of that name is in the way",
                       path);
    return LM_OK;
}

lm_status lm_make_folders(const char *dir)
{
    if (!dir || !*dir)
        return lm_fail(LM_E_INVALID, "empty folder name");
    char *p = strdup(dir);
    if (!p)
        return lm_fail(LM_E_NOMEM, "out of memory");
    lm_status st = LM_OK;
    for (char *c = p + 1; st == LM_OK && *c; c++) {
        if (*c != '/' || c[-1] == '/')
            continue;
        *c = '\0';
        st = make_one(p);
        *c = '/';
    }
    if (st == LM_OK)
        st = make_one(p);
    free(p);
    return st;
}

lm_status lm_make_parent_folders(const char *path)
{
    const char *slash = path ? strrchr(path, '/') : NULL;
    if (!slash || slash == path)
        return LM_OK;
    char *dir = strndup(path, (size_t)(slash - path));
    if (!dir)
        return lm_fail(LM_E_NOMEM, "out of memory");
    lm_status st = lm_make_folders(dir);
    free(dir);
    return st;
}
