/* worker/render/gl/egl_internal.h — internals shared by egl_devices.c, egl_display.c and
 * gl_context.c: extension entry points, EGL error names, reference-counted device displays, raw
 * enumeration. Not a public header: the rest of lumesh uses worker/render/gl/gl_context.h. */
#ifndef LM_WORKER_EGL_INTERNAL_H
#define LM_WORKER_EGL_INTERNAL_H

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "common/error.h"

/* Entry points of EGL_EXT_device_enumeration / _device_query / _platform_base. */
typedef struct wk_egl_procs {
    PFNEGLQUERYDEVICESEXTPROC query_devices;
    PFNEGLQUERYDEVICESTRINGEXTPROC query_device_string;
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display;
} wk_egl_procs;

/* A device as EGL lists it, before any display is opened on it. */
typedef struct wk_egl_raw_device {
    EGLDeviceEXT handle;
    int index;       /* position in eglQueryDevicesEXT's list */
    int is_software; /* EGL_MESA_device_software */
    char node[128];  /* render node, else primary DRM node, else "" */
} wk_egl_raw_device;

/* A display, context and (only without EGL_KHR_surfaceless_context) a 1x1 pbuffer. */
typedef struct wk_egl_session {
    EGLDisplay display;
    EGLContext context;
    EGLSurface surface; /* EGL_NO_SURFACE when surfaceless */
} wk_egl_session;

/* Saved current-context state of the calling thread, to put back after a probe. */
typedef struct wk_egl_current {
    EGLenum api;
    EGLDisplay display;
    EGLSurface draw, read;
    EGLContext context;
} wk_egl_current;

/* "EGL_BAD_ALLOC" etc.; "unknown EGL error 0x...." is written into no buffer: returns a fixed
 * string for unknown codes. Never NULL. */
const char *wk_egl_error_name(EGLint code);
/* lm_fail(status, "<what>: <EGL error name of eglGetError()>"). */
lm_status wk_egl_fail(lm_status status, const char *what);

lm_status wk_egl_load_procs(wk_egl_procs *procs);
/* Devices in EGL order; *count <= cap. */
lm_status wk_egl_query_raw_devices(const wk_egl_procs *procs, wk_egl_raw_device *out, int cap,
                                   int *count);
/* 1 if the space-separated extension list `list` holds `name` exactly. */
int wk_egl_has_extension(const char *list, const char *name);

/* Display on a device, initialised; counted so that several contexts in one process can share
 * EGL's single display per device and only the last release calls eglTerminate. */
lm_status wk_egl_display_acquire(const wk_egl_procs *procs, EGLDeviceEXT dev, EGLDisplay *out);
void wk_egl_display_release(EGLDisplay display);

/* Open a GLES 3 context on the device (acquires the display). Does not make it current. */
lm_status wk_egl_session_open(const wk_egl_procs *procs, EGLDeviceEXT dev, wk_egl_session *out);
lm_status wk_egl_session_make_current(const wk_egl_session *s);
/* Destroys context/surface (releasing them first if current on this thread), releases display. */
void wk_egl_session_close(wk_egl_session *s);

/* Device spec: NULL or "auto", "host", "egl:N". */
typedef enum wk_spec_kind { WK_SPEC_AUTO, WK_SPEC_HOST, WK_SPEC_INDEX } wk_spec_kind;
lm_status wk_egl_parse_spec(const char *spec, wk_spec_kind *kind, int *index);

void wk_egl_current_save(wk_egl_current *saved);
void wk_egl_current_restore(const wk_egl_current *saved);

#endif
