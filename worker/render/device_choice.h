/* worker/render/device_choice.h — what a --device spec means, in one place:
 *   "cpu"    lumesh's own exact CPU rasteriser (worker/render/cpu/cpu_views.h), on every machine;
 *   "auto"   the first GPU that gives an OpenGL ES 3 context, else "cpu" (the default);
 *   "host"   Mesa's software renderer llvmpipe through EGL;
 *   "egl:N"  EGL device N as `lumesh devices` lists it.
 * Why "auto" falls back to the CPU rasteriser rather than llvmpipe: worker/RENDERING.md. */
#ifndef LM_WORKER_DEVICE_CHOICE_H
#define LM_WORKER_DEVICE_CHOICE_H

#include "common/error.h"
#include "worker/render/gl/gl_context.h"

/* LM_OK when spec (NULL = "auto") is well formed; LM_E_INVALID names the accepted forms. */
lm_status wk_device_check_spec(const char *spec);
/* Whether spec is exactly "cpu". */
int wk_device_is_cpu(const char *spec);

/* Open what spec names: *ctx a current GL context on its EGL device, or NULL for the CPU
 * rasteriser ("cpu", or "auto" where no GPU gives a context). */
lm_status wk_device_open(const char *spec, wk_gl_context **ctx);

/* What spec selects among probed EGL devices (as wk_egl_list_devices lists them): *index into
 * devs, or -1 for the CPU rasteriser. Errors as wk_egl_choose_device. */
lm_status wk_device_choose(const char *spec, const wk_device_info *devs, int count, int *index);

#endif
