/* worker/render/gl/egl_display.c — the EGL boundary: extension entry points, EGL error names, and
 * reference-counted device displays.
 *
 * EGL keeps one EGLDisplay per device per process, and eglTerminate ends it for every user. So
 * that two wk_gl_context objects (or a context and a device probe) can coexist, displays are
 * counted here and only the last release terminates. This table mirrors EGL's own per-process
 * display table; it is the one piece of process-wide state in the worker, guarded by a mutex.
 * (EGL_KHR_display_reference would do the same inside EGL, but Mesa 22 lacks it.) */
#include "worker/render/gl/egl_internal.h"

#include <pthread.h>
#include <string.h>

#include "worker/render/gl/gl_context.h"

const char *wk_egl_error_name(EGLint code)
{
    switch (code) {
    case EGL_SUCCESS:
        return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE:
        return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP:
        return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW:
        return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
        return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST:
        return "EGL_CONTEXT_LOST";
    case EGL_BAD_DEVICE_EXT:
        return "EGL_BAD_DEVICE_EXT";
    default:
        return "unknown EGL error";
    }
}

lm_status wk_egl_fail(lm_status status, const char *what)
{
    EGLint code = eglGetError();
    return lm_fail(status, "%s failed: %s (0x%04x)", what, wk_egl_error_name(code), (unsigned)code);
}

int wk_egl_has_extension(const char *list, const char *name)
{
    size_t len = strlen(name);
    const char *p = list;
    if (!list || len == 0)
        return 0;
    while ((p = strstr(p, name)) != NULL) {
        int starts = (p == list || p[-1] == ' ');
        int ends = (p[len] == '\0' || p[len] == ' ');
        if (starts && ends)
            return 1;
        p += len;
    }
    return 0;
}

lm_status wk_egl_load_procs(wk_egl_procs *procs)
{
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    static const char *const needed[] = {"EGL_EXT_device_enumeration", "EGL_EXT_device_query",
                                         "EGL_EXT_platform_device"};
    if (!client)
        return wk_egl_fail(LM_E_UNSUPPORTED, "eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS)");
    for (size_t i = 0; i < sizeof needed / sizeof needed[0]; i++) {
        if (!wk_egl_has_extension(client, needed[i]) &&
            !(i < 2 && wk_egl_has_extension(client, "EGL_EXT_device_base")))
            return lm_fail(LM_E_UNSUPPORTED, "EGL client lacks %s (needed to choose a device)",
                           needed[i]);
    }
    procs->query_devices = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
    procs->query_device_string =
        (PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
    procs->get_platform_display =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    if (!procs->query_devices || !procs->query_device_string || !procs->get_platform_display)
        return lm_fail(LM_E_UNSUPPORTED, "eglGetProcAddress found no eglQueryDevicesEXT / "
                                         "eglQueryDeviceStringEXT / eglGetPlatformDisplayEXT");
    return LM_OK;
}

/* ---- reference-counted displays ---- */

typedef struct display_ref {
    EGLDisplay display;
    int refs;
} display_ref;

static pthread_mutex_t display_lock = PTHREAD_MUTEX_INITIALIZER;
static display_ref display_refs[WK_MAX_DEVICES * 2];

static display_ref *find_ref(EGLDisplay display)
{
    for (size_t i = 0; i < sizeof display_refs / sizeof display_refs[0]; i++) {
        if (display_refs[i].refs > 0 && display_refs[i].display == display)
            return &display_refs[i];
    }
    return NULL;
}

static lm_status add_ref(EGLDisplay display)
{
    display_ref *ref = find_ref(display);
    if (ref) {
        ref->refs++;
        return LM_OK;
    }
    if (!eglInitialize(display, NULL, NULL))
        return wk_egl_fail(LM_E_DEVICE, "eglInitialize on the device's display");
    for (size_t i = 0; !ref && i < sizeof display_refs / sizeof display_refs[0]; i++) {
        if (display_refs[i].refs == 0)
            ref = &display_refs[i];
    }
    if (!ref) {
        eglTerminate(display);
        return lm_fail(LM_E_RANGE, "more than %d EGL displays open at once",
                       (int)(sizeof display_refs / sizeof display_refs[0]));
    }
    ref->display = display;
    ref->refs = 1;
    return LM_OK;
}

lm_status wk_egl_display_acquire(const wk_egl_procs *procs, EGLDeviceEXT dev, EGLDisplay *out)
{
    EGLDisplay display = procs->get_platform_display(EGL_PLATFORM_DEVICE_EXT, dev, NULL);
    if (display == EGL_NO_DISPLAY)
        return wk_egl_fail(LM_E_DEVICE, "eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT)");
    pthread_mutex_lock(&display_lock);
    lm_status st = add_ref(display);
    pthread_mutex_unlock(&display_lock);
    if (st == LM_OK)
        *out = display;
    return st;
}

void wk_egl_display_release(EGLDisplay display)
{
    pthread_mutex_lock(&display_lock);
    display_ref *ref = find_ref(display);
    LM_ASSERT(ref != NULL);
    if (--ref->refs == 0) {
        ref->display = EGL_NO_DISPLAY;
        eglTerminate(display);
    }
    pthread_mutex_unlock(&display_lock);
}
