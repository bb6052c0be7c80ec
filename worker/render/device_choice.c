/* worker/render/device_choice.c — the --device policy (see device_choice.h): spec syntax, opening
 * the device for a views object or a self-test, and the choice `lumesh devices` reports. */
#include "worker/render/device_choice.h"

#include <string.h>

#include "common/log.h"
#include "worker/render/gl/egl_internal.h"

int wk_device_is_cpu(const char *spec)
{
    return spec && strcmp(spec, "cpu") == 0;
}

static int is_auto(const char *spec)
{
    return !spec || strcmp(spec, "auto") == 0;
}

lm_status wk_device_check_spec(const char *spec)
{
    wk_spec_kind kind;
    int index;
    if (wk_device_is_cpu(spec) || wk_egl_parse_spec(spec, &kind, &index) == LM_OK)
        return LM_OK;
    return lm_fail(LM_E_INVALID, "bad device '%s': expected auto, cpu, host or egl:N",
                   spec ? spec : "");
}

lm_status wk_device_open(const char *spec, wk_gl_context **ctx)
{
    *ctx = NULL;
    lm_status st = wk_device_check_spec(spec);
    if (st != LM_OK || wk_device_is_cpu(spec))
        return st;
    if (!is_auto(spec))
        return wk_gl_context_create(spec, ctx);
    st = wk_gl_context_create_gpu(ctx);
    if (st == LM_E_UNSUPPORTED) {
        lm_info("device auto: %s; using the CPU rasteriser", lm_last_error());
        return LM_OK;
    }
    return st;
}

lm_status wk_device_choose(const char *spec, const wk_device_info *devs, int count, int *index)
{
    lm_status st = wk_device_check_spec(spec);
    *index = -1;
    if (st != LM_OK || wk_device_is_cpu(spec))
        return st;
    if (!is_auto(spec))
        return wk_egl_choose_device(spec, devs, count, index);
    for (int i = 0; i < count; i++)
        if (!devs[i].is_software && devs[i].usable) {
            *index = i;
            break;
        }
    return LM_OK;
}
