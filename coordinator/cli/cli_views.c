/* coordinator/cli/cli_views.c — the shared --views and --views-from options (an lm_view_spec): a
 * count, the upper hemisphere with or without a count, or a camera file read as it is parsed and
 * kept here (one command a process). */
#include <ctype.h>
#include <string.h>

#include "common/io/camera_file.h"
#include "coordinator/cli/cli_args.h"

static lm_camera cameras[LM_MAX_VIEWS];
static int views_given, from_given;

void co_cli_views_reset(void)
{
    views_given = from_given = 0;
}

static int take_count(const char *cmd, lm_view_spec *v, const char *val)
{
    static const char upper[] = "upper";
    size_t k = sizeof upper - 1;
    if (!strncmp(val, upper, k) && (val[k] == 0 || val[k] == ':')) {
        v->dist = LM_VIEW_DIST_UPPER;
        if (val[k] == ':' &&
            co_arg_u32(cmd, "--views upper:N", val + k + 1, 1, LM_MAX_VIEWS, &v->count) != LM_OK)
            return 1;
        return -1;
    }
    if (isalpha((unsigned char)val[0]))
        return co_cli_usage_error(cmd, "--views expects N, upper or upper:N, got '%s'", val);
    v->dist = LM_VIEW_DIST_SPHERE;
    return co_arg_u32(cmd, "--views", val, 1, LM_MAX_VIEWS, &v->count) == LM_OK ? -1 : 1;
}

static int take_file(const char *cmd, lm_view_spec *v, const char *path)
{
    uint32_t n = 0;
    lm_status st = lm_cameras_read(path, cameras, &n);
    if (st != LM_OK)
        return co_cli_fail(cmd, st);
    *v = (lm_view_spec){.dist = LM_VIEW_DIST_CAMERAS, .count = n, .cameras = cameras};
    return -1;
}

int co_cli_take_views(const char *cmd, lm_view_spec *v, const char *val, int from)
{
    if (from ? views_given : from_given)
        return co_cli_usage_error(cmd, "--views and --views-from exclude each other");
    if (from) {
        from_given = 1;
        return take_file(cmd, v, val);
    }
    views_given = 1;
    return take_count(cmd, v, val);
}
