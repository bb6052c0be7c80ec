/* worker/render/gl/gl_context.c — a headless OpenGL ES 3 context on a chosen EGL device.
 * Opening a session (display + config + context, surfaceless or a 1x1 pbuffer), making it
 * current, the wk_gl_context object and its description. Device listing is in egl_devices.c,
 * display reference counting and EGL error names in egl_display.c. */
#include "worker/render/gl/gl_context.h"

#include <GLES3/gl3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/log.h"
#include "worker/render/gl/egl_internal.h"

struct wk_gl_context {
    wk_egl_session session;
    int device_index;
    char description[512];
};

static lm_status choose_config(EGLDisplay dpy, const char *exts, EGLConfig *out)
{
    EGLint attribs[] = {EGL_SURFACE_TYPE,
                        EGL_PBUFFER_BIT,
                        EGL_RENDERABLE_TYPE,
                        EGL_OPENGL_ES3_BIT,
                        EGL_RED_SIZE,
                        8,
                        EGL_GREEN_SIZE,
                        8,
                        EGL_BLUE_SIZE,
                        8,
                        EGL_ALPHA_SIZE,
                        8,
                        EGL_NONE};
    EGLint n = 0;
    for (int pass = 0; pass < 2; pass++) {
        attribs[1] = pass == 0 ? EGL_PBUFFER_BIT : EGL_DONT_CARE;
        if (!eglChooseConfig(dpy, attribs, out, 1, &n))
            return wk_egl_fail(LM_E_DEVICE, "eglChooseConfig");
        if (n > 0)
            return LM_OK;
    }
    if (wk_egl_has_extension(exts, "EGL_KHR_no_config_context")) {
        *out = EGL_NO_CONFIG_KHR;
        return LM_OK;
    }
    return lm_fail(LM_E_DEVICE, "no EGL config renders OpenGL ES 3 with RGBA8 on this device");
}

static lm_status create_objects(wk_egl_session *s, EGLConfig cfg, int surfaceless)
{
    static const EGLint ctx_attribs[] = {EGL_CONTEXT_MAJOR_VERSION_KHR, 3, EGL_NONE};
    static const EGLint pb_attribs[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
    s->context = eglCreateContext(s->display, cfg, EGL_NO_CONTEXT, ctx_attribs);
    if (s->context == EGL_NO_CONTEXT)
        return wk_egl_fail(LM_E_DEVICE, "eglCreateContext (OpenGL ES 3)");
    if (surfaceless)
        return LM_OK;
    if (cfg == EGL_NO_CONFIG_KHR)
        return lm_fail(LM_E_DEVICE, "device has neither EGL_KHR_surfaceless_context nor a "
                                    "pbuffer-capable config");
    s->surface = eglCreatePbufferSurface(s->display, cfg, pb_attribs);
    if (s->surface == EGL_NO_SURFACE)
        return wk_egl_fail(LM_E_DEVICE, "eglCreatePbufferSurface (1x1, no surfaceless support)");
    return LM_OK;
}

lm_status wk_egl_session_open(const wk_egl_procs *procs, EGLDeviceEXT dev, wk_egl_session *out)
{
    wk_egl_session s = {EGL_NO_DISPLAY, EGL_NO_CONTEXT, EGL_NO_SURFACE};
    EGLConfig cfg = EGL_NO_CONFIG_KHR;
    lm_status st = wk_egl_display_acquire(procs, dev, &s.display);
    if (st != LM_OK)
        return st;
    const char *exts = eglQueryString(s.display, EGL_EXTENSIONS);
    if (!eglBindAPI(EGL_OPENGL_ES_API))
        st = wk_egl_fail(LM_E_DEVICE, "eglBindAPI(EGL_OPENGL_ES_API)");
    if (st == LM_OK)
        st = choose_config(s.display, exts, &cfg);
    if (st == LM_OK)
        st = create_objects(&s, cfg, wk_egl_has_extension(exts, "EGL_KHR_surfaceless_context"));
    if (st != LM_OK) {
        wk_egl_session_close(&s);
        return st;
    }
    *out = s;
    return LM_OK;
}

lm_status wk_egl_session_make_current(const wk_egl_session *s)
{
    if (!eglBindAPI(EGL_OPENGL_ES_API))
        return wk_egl_fail(LM_E_DEVICE, "eglBindAPI(EGL_OPENGL_ES_API)");
    if (!eglMakeCurrent(s->display, s->surface, s->surface, s->context))
        return wk_egl_fail(LM_E_DEVICE, "eglMakeCurrent");
    return LM_OK;
}

void wk_egl_session_close(wk_egl_session *s)
{
    if (s->display == EGL_NO_DISPLAY)
        return;
    eglBindAPI(EGL_OPENGL_ES_API);
    if (s->context != EGL_NO_CONTEXT && eglGetCurrentContext() == s->context)
        eglMakeCurrent(s->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (s->surface != EGL_NO_SURFACE)
        eglDestroySurface(s->display, s->surface);
    if (s->context != EGL_NO_CONTEXT)
        eglDestroyContext(s->display, s->context);
    wk_egl_display_release(s->display);
    s->display = EGL_NO_DISPLAY;
    s->context = EGL_NO_CONTEXT;
    s->surface = EGL_NO_SURFACE;
}

void wk_egl_current_save(wk_egl_current *saved)
{
    saved->api = eglQueryAPI();
    eglBindAPI(EGL_OPENGL_ES_API);
    saved->display = eglGetCurrentDisplay();
    saved->draw = eglGetCurrentSurface(EGL_DRAW);
    saved->read = eglGetCurrentSurface(EGL_READ);
    saved->context = eglGetCurrentContext();
}

void wk_egl_current_restore(const wk_egl_current *saved)
{
    eglBindAPI(EGL_OPENGL_ES_API);
    if (saved->context != EGL_NO_CONTEXT) {
        eglMakeCurrent(saved->display, saved->draw, saved->read, saved->context);
    } else {
        EGLDisplay now = eglGetCurrentDisplay();
        if (now != EGL_NO_DISPLAY)
            eglMakeCurrent(now, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    }
    if (saved->api != EGL_NONE)
        eglBindAPI(saved->api);
}

/* ---- wk_gl_context ---- */

static lm_status describe(wk_gl_context *ctx)
{
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    const char *version = (const char *)glGetString(GL_VERSION);
    if (!renderer || !version)
        return lm_fail(LM_E_DEVICE,
                       "EGL device %d: glGetString(GL_RENDERER) failed (GL error "
                       "0x%04x)",
                       ctx->device_index, (unsigned)glGetError());
    snprintf(ctx->description, sizeof ctx->description, "EGL device %d: %s, %s", ctx->device_index,
             renderer, version);
    return LM_OK;
}

/* Open, make current and describe a context on one device; *out NULL on failure. */
static lm_status open_on(const wk_egl_procs *procs, const wk_egl_raw_device *dev,
                         wk_gl_context **out)
{
    wk_gl_context *ctx = calloc(1, sizeof *ctx);
    if (!ctx)
        return lm_fail(LM_E_NOMEM, "out of memory for a GL context");
    ctx->device_index = dev->index;
    lm_status st = wk_egl_session_open(procs, dev->handle, &ctx->session);
    if (st == LM_OK)
        st = wk_egl_session_make_current(&ctx->session);
    if (st == LM_OK)
        st = describe(ctx);
    if (st != LM_OK) {
        char msg[480];
        snprintf(msg, sizeof msg, "%s", lm_last_error());
        wk_gl_context_destroy(ctx);
        return lm_fail(st, "EGL device %d%s: %s", dev->index, dev->is_software ? " (software)" : "",
                       msg);
    }
    *out = ctx;
    return LM_OK;
}

/* "auto": the first GPU that yields a working context, else the software device. */
static lm_status open_auto(const wk_egl_procs *procs, const wk_egl_raw_device *devs, int n,
                           wk_gl_context **out)
{
    for (int pass = 0; pass < 2; pass++) {
        for (int i = 0; i < n; i++) {
            if (devs[i].is_software != pass)
                continue;
            if (open_on(procs, &devs[i], out) == LM_OK)
                return LM_OK;
            lm_info("device auto: skipping %s", lm_last_error());
        }
    }
    char last[480];
    snprintf(last, sizeof last, "%s", n > 0 ? lm_last_error() : "no devices");
    return lm_fail(LM_E_DEVICE,
                   "device auto: none of the %d EGL device(s) gave an OpenGL ES 3 "
                   "context (last: %s)",
                   n, last);
}

static lm_status open_spec(const wk_egl_procs *procs, const char *spec, wk_spec_kind kind,
                           int index, const wk_egl_raw_device *devs, int n, wk_gl_context **out)
{
    if (kind == WK_SPEC_AUTO)
        return open_auto(procs, devs, n, out);
    for (int i = 0; i < n; i++) {
        if ((kind == WK_SPEC_HOST && devs[i].is_software) ||
            (kind == WK_SPEC_INDEX && devs[i].index == index))
            return open_on(procs, &devs[i], out);
    }
    if (kind == WK_SPEC_HOST)
        return lm_fail(LM_E_UNSUPPORTED,
                       "device host: EGL lists no software device (Mesa "
                       "llvmpipe, EGL_MESA_device_software) among %d device(s)",
                       n);
    return lm_fail(LM_E_RANGE, "device %s: no such EGL device (%d found: egl:0..egl:%d)", spec, n,
                   n - 1);
}

lm_status wk_gl_context_create(const char *spec, wk_gl_context **out)
{
    wk_egl_procs procs;
    wk_egl_raw_device devs[WK_MAX_DEVICES];
    wk_spec_kind kind;
    int index = 0, n = 0;
    LM_ASSERT(out != NULL);
    *out = NULL;
    lm_status st = wk_egl_parse_spec(spec, &kind, &index);
    if (st == LM_OK)
        st = wk_egl_load_procs(&procs);
    if (st == LM_OK)
        st = wk_egl_query_raw_devices(&procs, devs, WK_MAX_DEVICES, &n);
    if (st != LM_OK)
        return st;
    return open_spec(&procs, spec ? spec : "auto", kind, index, devs, n, out);
}

lm_status wk_gl_context_create_gpu(wk_gl_context **out)
{
    wk_egl_procs procs;
    wk_egl_raw_device devs[WK_MAX_DEVICES];
    int n = 0;
    LM_ASSERT(out != NULL);
    *out = NULL;
    if (wk_egl_load_procs(&procs) != LM_OK ||
        wk_egl_query_raw_devices(&procs, devs, WK_MAX_DEVICES, &n) != LM_OK)
        return lm_fail(LM_E_UNSUPPORTED, "no EGL device enumeration (%s)", lm_last_error());
    for (int i = 0; i < n; i++) {
        if (devs[i].is_software)
            continue;
        if (open_on(&procs, &devs[i], out) == LM_OK)
            return LM_OK;
        lm_info("device auto: skipping %s", lm_last_error());
    }
    return lm_fail(LM_E_UNSUPPORTED,
                   "none of the %d EGL device(s) is a GPU with an OpenGL ES 3 "
                   "context",
                   n);
}

void wk_gl_context_destroy(wk_gl_context *ctx)
{
    if (!ctx)
        return;
    wk_egl_session_close(&ctx->session);
    free(ctx);
}

lm_status wk_gl_context_make_current(wk_gl_context *ctx)
{
    LM_ASSERT(ctx != NULL);
    lm_status st = wk_egl_session_make_current(&ctx->session);
    if (st != LM_OK) {
        char msg[480];
        snprintf(msg, sizeof msg, "%s", lm_last_error());
        return lm_fail(st, "EGL device %d: %s", ctx->device_index, msg);
    }
    return LM_OK;
}

const char *wk_gl_context_description(const wk_gl_context *ctx)
{
    return ctx ? ctx->description : "(no GL context)";
}
