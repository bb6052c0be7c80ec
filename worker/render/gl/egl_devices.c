/* worker/render/gl/egl_devices.c — which EGL devices exist, what they are, and which one a spec
 * picks. Enumeration via EGL_EXT_device_enumeration; a device is "software" when it carries
 * EGL_MESA_device_software (llvmpipe), otherwise a GPU; its node comes from
 * EGL_EXT_device_drm_render_node (render node) or EGL_EXT_device_drm (primary node).
 * The list is ordered GPUs first; each entry is probed by briefly creating a context. */
#include "worker/render/gl/gl_context.h"

#include <GLES3/gl3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "worker/render/gl/egl_internal.h"

static void copy_str(char *dst, size_t cap, const char *src)
{
    snprintf(dst, cap, "%s", src ? src : "");
}

static void describe_raw(const wk_egl_procs *procs, EGLDeviceEXT h, int index,
                         wk_egl_raw_device *out)
{
    const char *exts = procs->query_device_string(h, EGL_EXTENSIONS);
    const char *node = NULL;
    memset(out, 0, sizeof *out);
    out->handle = h;
    out->index = index;
    out->is_software = wk_egl_has_extension(exts, "EGL_MESA_device_software");
    if (wk_egl_has_extension(exts, "EGL_EXT_device_drm_render_node"))
        node = procs->query_device_string(h, EGL_DRM_RENDER_NODE_FILE_EXT);
    if (!node && wk_egl_has_extension(exts, "EGL_EXT_device_drm"))
        node = procs->query_device_string(h, EGL_DRM_DEVICE_FILE_EXT);
    eglGetError(); /* a device without a node answers NULL + an error; neither is a failure */
    copy_str(out->node, sizeof out->node, node);
}

lm_status wk_egl_query_raw_devices(const wk_egl_procs *procs, wk_egl_raw_device *out, int cap,
                                   int *count)
{
    EGLDeviceEXT handles[WK_MAX_DEVICES];
    EGLint n = 0;
    LM_ASSERT(cap >= 0 && count != NULL);
    if (cap > WK_MAX_DEVICES)
        cap = WK_MAX_DEVICES;
    *count = 0;
    if (cap == 0)
        return LM_OK;
    if (!procs->query_devices(cap, handles, &n))
        return wk_egl_fail(LM_E_DEVICE, "eglQueryDevicesEXT");
    for (EGLint i = 0; i < n && i < cap; i++)
        describe_raw(procs, handles[i], (int)i, &out[i]);
    *count = n < cap ? (int)n : cap;
    return LM_OK;
}

lm_status wk_egl_parse_spec(const char *spec, wk_spec_kind *kind, int *index)
{
    *index = -1;
    if (!spec || strcmp(spec, "auto") == 0) {
        *kind = WK_SPEC_AUTO;
        return LM_OK;
    }
    if (strcmp(spec, "host") == 0) {
        *kind = WK_SPEC_HOST;
        return LM_OK;
    }
    if (strncmp(spec, "egl:", 4) == 0 && spec[4] >= '0' && spec[4] <= '9') {
        char *end = NULL;
        long v = strtol(spec + 4, &end, 10);
        if (*end == '\0' && v >= 0 && v < 1000000) {
            *kind = WK_SPEC_INDEX;
            *index = (int)v;
            return LM_OK;
        }
    }
    return lm_fail(LM_E_INVALID, "bad device '%s': expected auto, host or egl:N", spec);
}

/* Fill vendor / renderer / usable by opening a context briefly. Restores the caller's context. */
static void probe(const wk_egl_procs *procs, const wk_egl_raw_device *raw, wk_device_info *info)
{
    wk_egl_current saved;
    wk_egl_session s;
    EGLDisplay dpy;
    if (wk_egl_display_acquire(procs, raw->handle, &dpy) != LM_OK)
        return;
    copy_str(info->vendor, sizeof info->vendor, eglQueryString(dpy, EGL_VENDOR));
    wk_egl_current_save(&saved);
    if (wk_egl_session_open(procs, raw->handle, &s) == LM_OK) {
        if (wk_egl_session_make_current(&s) == LM_OK) {
            const char *r = (const char *)glGetString(GL_RENDERER);
            const char *v = (const char *)glGetString(GL_VERSION);
            if (r && v) {
                snprintf(info->renderer, sizeof info->renderer, "%s, %s", r, v);
                info->usable = 1;
            }
        }
        wk_egl_session_close(&s);
    }
    wk_egl_current_restore(&saved);
    wk_egl_display_release(dpy);
}

lm_status wk_egl_list_devices(wk_device_info *out, int cap, int *count)
{
    wk_egl_procs procs;
    wk_egl_raw_device raw[WK_MAX_DEVICES];
    int n = 0, k = 0;
    LM_ASSERT(out != NULL && count != NULL && cap >= 0);
    *count = 0;
    lm_status st = wk_egl_load_procs(&procs);
    if (st == LM_OK)
        st = wk_egl_query_raw_devices(&procs, raw, cap, &n);
    if (st != LM_OK)
        return st;
    for (int pass = 0; pass < 2; pass++) { /* GPUs first, then software devices */
        for (int i = 0; i < n; i++) {
            if (raw[i].is_software != pass)
                continue;
            wk_device_info *info = &out[k++];
            memset(info, 0, sizeof *info);
            info->index = raw[i].index;
            info->is_software = raw[i].is_software;
            copy_str(info->node, sizeof info->node, raw[i].node);
            probe(&procs, &raw[i], info);
        }
    }
    *count = k;
    return LM_OK;
}

static lm_status choose_auto(const wk_device_info *devs, int count, int *index)
{
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < count; i++) {
            if (devs[i].is_software == pass && devs[i].usable) {
                *index = i;
                return LM_OK;
            }
        }
    }
    return lm_fail(LM_E_DEVICE,
                   "device auto: none of the %d EGL device(s) gave an OpenGL ES 3 "
                   "context",
                   count);
}

lm_status wk_egl_choose_device(const char *spec, const wk_device_info *devs, int count, int *index)
{
    wk_spec_kind kind;
    int want = -1;
    lm_status st = wk_egl_parse_spec(spec, &kind, &want);
    if (st != LM_OK)
        return st;
    if (kind == WK_SPEC_AUTO)
        return choose_auto(devs, count, index);
    for (int i = 0; i < count; i++) {
        if ((kind == WK_SPEC_HOST && devs[i].is_software) ||
            (kind == WK_SPEC_INDEX && devs[i].index == want)) {
            if (!devs[i].usable)
                return lm_fail(LM_E_DEVICE,
                               "device %s: EGL device %d gave no OpenGL ES 3 "
                               "context",
                               spec, devs[i].index);
            *index = i;
            return LM_OK;
        }
    }
    if (kind == WK_SPEC_HOST)
        return lm_fail(LM_E_UNSUPPORTED,
                       "device host: EGL lists no software device (Mesa "
                       "llvmpipe) among %d device(s)",
                       count);
    return lm_fail(LM_E_RANGE, "device %s: no such EGL device (%d found)", spec, count);
}
