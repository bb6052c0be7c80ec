/* worker/render/device_survey.h — what this machine can render with, for `lumesh devices`: the EGL
 * devices (GPUs first, then Mesa's software renderer), lumesh's CPU rasteriser (always there) and
 * the USB devices. The one header through which the coordinator sees the devices; what a --device
 * spec selects among them is device_choice.h. */
#ifndef LM_WORKER_DEVICE_SURVEY_H
#define LM_WORKER_DEVICE_SURVEY_H

#include "common/error.h"
#include "worker/render/gl/gl_context.h"
#include "worker/render/usb_devices.h"

typedef struct wk_device_survey {
    wk_device_info egl[WK_MAX_DEVICES]; /* as wk_egl_list_devices lists them */
    int egl_count;
    wk_usb_device usb[WK_MAX_USB_DEVICES];
    int usb_count;
    const char *cpu_rasteriser; /* the CPU rasteriser's name and version (static) */
    int cpu_pixel_lanes;        /* pixels it shades at a time on this processor */
} wk_device_survey;

/* Fill *s (about 40 KiB: callers keep it off small stacks at will). Blocking: opens and closes an
 * EGL display per device and walks the USB buses. Errors as wk_egl_list_devices and
 * wk_usb_list_devices; *s is then partly filled. */
lm_status wk_device_survey_take(wk_device_survey *s);

#endif
