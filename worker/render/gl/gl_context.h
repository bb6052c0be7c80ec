/* worker/render/gl/gl_context.h — EGL device choice and a headless OpenGL ES 3 context on it.
 * Devices come from EGL_EXT_device_enumeration: GPU devices (those with a DRM render node) first,
 * Mesa's software device (llvmpipe) as the host fallback. A spec chooses: "auto" (first GPU that
 * yields a working context, else host), "egl:N" (device N of the list), "host" (software device).
 * The context is surfaceless (EGL_KHR_surfaceless_context); rendering goes to framebuffer objects.
 * One context per object, no globals: several may exist in one process (one current per thread). */
#ifndef LM_WORKER_GL_CONTEXT_H
#define LM_WORKER_GL_CONTEXT_H

#include "common/error.h"

#define WK_MAX_DEVICES 16

typedef struct wk_device_info {
    int index;          /* position in EGL's device list (the N of "egl:N") */
    int is_software;    /* 1 for Mesa's software rasteriser */
    char node[128];     /* DRM render node path, "" if none */
    char vendor[128];   /* EGL_VENDOR of a display on it, if it could be initialised */
    char renderer[256]; /* GL_RENDERER / version string if a context could be made, else "" */
    int usable;         /* a context could be created on it */
} wk_device_info;

/* Enumerate EGL devices (probes each: creating a context briefly). *count <= cap. */
lm_status wk_egl_list_devices(wk_device_info *out, int cap, int *count);

/* Index into the list that `spec` selects (after probing), or an error naming the spec. */
lm_status wk_egl_choose_device(const char *spec, const wk_device_info *devs, int count, int *index);

typedef struct wk_gl_context wk_gl_context;

/* spec NULL means "auto". On success the new context is current on the calling thread. */
lm_status wk_gl_context_create(const char *spec, wk_gl_context **out);
/* The first GPU (not a software device) that yields a working context, current on return;
 * LM_E_UNSUPPORTED when there is none (no EGL device enumeration, no GPU, none working). */
lm_status wk_gl_context_create_gpu(wk_gl_context **out);
void wk_gl_context_destroy(wk_gl_context *ctx);
lm_status wk_gl_context_make_current(wk_gl_context *ctx);
/* "EGL device N: <GL_RENDERER>, <GL_VERSION>" — recorded with every image and energy. */
const char *wk_gl_context_description(const wk_gl_context *ctx);

#endif
