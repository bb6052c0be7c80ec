/* worker/render/device_survey.c — the devices this machine can render with (device_survey.h). */
#include "worker/render/device_survey.h"

#include <string.h>

#include "worker/render/cpu/cpu_shade.h"
#include "worker/render/cpu/cpu_views.h"

lm_status wk_device_survey_take(wk_device_survey *s)
{
    memset(s, 0, sizeof *s);
    s->cpu_rasteriser = WK_CPU_RASTERISER;
    s->cpu_pixel_lanes = wk_cpu_shade_lanes();
    lm_status st = wk_egl_list_devices(s->egl, WK_MAX_DEVICES, &s->egl_count);
    if (st == LM_OK)
        st = wk_usb_list_devices(s->usb, WK_MAX_USB_DEVICES, &s->usb_count);
    return st;
}
