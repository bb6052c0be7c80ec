/* coordinator/cli/cli_devices.c — `lumesh devices [--json] [--device SPEC]`: the EGL devices (GPUs
 * first, then Mesa's software renderer) with their node, renderer and whether a context works,
 * lumesh's CPU rasteriser ("cpu", always there), the USB devices with known accelerators flagged,
 * and the device a spec selects (worker/render/device_choice.h). */
#include <stdio.h>
#include <string.h>

#include "common/error.h"
#include "coordinator/cli/cli_args.h"
#include "worker/render/device_choice.h"
#include "worker/render/device_survey.h"

#define CMD "devices"

typedef struct devices_report {
    wk_device_survey dev;
    const char *spec;
    int selected; /* index into egl[], -1 for the CPU rasteriser (when select_status is LM_OK) */
    lm_status select_status;
    char select_error[512];
} devices_report;

/* Length of the valid UTF-8 sequence at s (1..4), or 0 if the bytes there are not one. */
static int utf8_len(const unsigned char *s)
{
    int n = s[0] >= 0xf0 && s[0] <= 0xf4 ? 4 : s[0] >= 0xe0 ? 3 : s[0] >= 0xc2 ? 2 : 0;
    if (s[0] >= 0xf8)
        return 0;
    for (int i = 1; i < n; i++) {
        if ((s[i] & 0xc0) != 0x80)
            return 0;
    }
    return n;
}

/* A JSON string literal: quotes, escapes, control characters as \u00XX, invalid UTF-8 as '?'. */
static void json_str(FILE *f, const char *str)
{
    const unsigned char *s = (const unsigned char *)(str ? str : "");
    fputc('"', f);
    while (*s) {
        if (*s == '"' || *s == '\\') {
            fprintf(f, "\\%c", *s++);
        } else if (*s < 0x20) {
            fprintf(f, "\\u%04x", *s++);
        } else if (*s < 0x80) {
            fputc(*s++, f);
        } else {
            int n = utf8_len(s);
            if (n == 0) {
                fputc('?', f);
                s++;
            } else {
                fwrite(s, 1, (size_t)n, f);
                s += n;
            }
        }
    }
    fputc('"', f);
}

static void print_json_egl(FILE *f, const devices_report *r)
{
    fputs("  \"egl_devices\": [", f);
    for (int i = 0; i < r->dev.egl_count; i++) {
        const wk_device_info *d = &r->dev.egl[i];
        fprintf(f, "%s\n    {\"index\": %d, \"spec\": \"egl:%d\", \"kind\": \"%s\", \"node\": ",
                i ? "," : "", d->index, d->index, d->is_software ? "software" : "gpu");
        json_str(f, d->node);
        fputs(", \"vendor\": ", f);
        json_str(f, d->vendor);
        fputs(", \"renderer\": ", f);
        json_str(f, d->renderer);
        fprintf(f, ", \"usable\": %s}", d->usable ? "true" : "false");
    }
    fputs(r->dev.egl_count ? "\n  ],\n" : "],\n", f);
}

static void print_json_usb(FILE *f, const devices_report *r)
{
    fputs("  \"usb_devices\": [", f);
    for (int i = 0; i < r->dev.usb_count; i++) {
        const wk_usb_device *u = &r->dev.usb[i];
        fprintf(f,
                "%s\n    {\"bus\": %u, \"address\": %u, \"id\": \"%04x:%04x\", \"class\": %u, "
                "\"product\": ",
                i ? "," : "", u->bus, u->address, u->vendor_id, u->product_id, u->device_class);
        json_str(f, u->product);
        fprintf(f, ", \"accelerator\": %s, \"accelerator_name\": ",
                u->is_accelerator ? "true" : "false");
        json_str(f, u->accelerator);
        fputc('}', f);
    }
    fputs(r->dev.usb_count ? "\n  ],\n" : "],\n", f);
}

static void print_json(FILE *f, const devices_report *r)
{
    fputs("{\n", f);
    print_json_egl(f, r);
    fputs("  \"cpu_device\": {\"spec\": \"cpu\", \"kind\": \"cpu\", \"renderer\": ", f);
    json_str(f, r->dev.cpu_rasteriser);
    fprintf(f, ", \"pixel_lanes\": %d, \"usable\": true},\n", r->dev.cpu_pixel_lanes);
    print_json_usb(f, r);
    fputs("  \"selection\": {\"spec\": ", f);
    json_str(f, r->spec);
    if (r->select_status == LM_OK && r->selected >= 0) {
        const wk_device_info *d = &r->dev.egl[r->selected];
        fprintf(f, ", \"selected\": \"egl:%d\", \"kind\": \"%s\", \"renderer\": ", d->index,
                d->is_software ? "software" : "gpu");
        json_str(f, d->renderer);
    } else if (r->select_status == LM_OK) {
        fputs(", \"selected\": \"cpu\", \"kind\": \"cpu\", \"renderer\": ", f);
        json_str(f, r->dev.cpu_rasteriser);
    } else {
        fputs(", \"selected\": null, \"error\": ", f);
        json_str(f, r->select_error);
    }
    fputs("}\n}\n", f);
}

static void print_text(FILE *f, const devices_report *r)
{
    fprintf(f, "EGL devices: %d (GPUs first)\n", r->dev.egl_count);
    if (r->dev.egl_count)
        fprintf(f, "  %-7s %-9s %-22s %-7s %s\n", "DEVICE", "KIND", "NODE", "USABLE", "RENDERER");
    for (int i = 0; i < r->dev.egl_count; i++) {
        const wk_device_info *d = &r->dev.egl[i];
        char spec[16];
        snprintf(spec, sizeof spec, "egl:%d", d->index);
        fprintf(f, "  %-7s %-9s %-22s %-7s %s\n", spec, d->is_software ? "software" : "gpu",
                d->node[0] ? d->node : "-", d->usable ? "yes" : "no",
                d->renderer[0] ? d->renderer : "(no context)");
    }
    fprintf(f, "CPU renderer: cpu (%s), always usable; pixels %d at a time\n",
            r->dev.cpu_rasteriser, r->dev.cpu_pixel_lanes);
    fprintf(f, "USB devices: %d\n", r->dev.usb_count);
    for (int i = 0; i < r->dev.usb_count; i++) {
        const wk_usb_device *u = &r->dev.usb[i];
        fprintf(f, "  bus %03u addr %03u  %04x:%04x  %s%s%s%s%s\n", u->bus, u->address,
                u->vendor_id, u->product_id, u->is_accelerator ? "ACCELERATOR: " : "",
                u->accelerator, u->is_accelerator && u->product[0] ? " — " : "", u->product,
                !u->is_accelerator && !u->product[0] ? "(unrecognised)" : "");
    }
    if (r->select_status == LM_OK && r->selected >= 0) {
        const wk_device_info *d = &r->dev.egl[r->selected];
        fprintf(f, "selected: egl:%d (%s, %s) for --device %s\n", d->index,
                d->is_software ? "software" : "gpu", d->renderer, r->spec);
    } else if (r->select_status == LM_OK) {
        fprintf(f, "selected: cpu (cpu, %s) for --device %s\n", r->dev.cpu_rasteriser, r->spec);
    } else {
        fprintf(f, "selected: none for --device %s (%s)\n", r->spec, r->select_error);
    }
}

static void usage(FILE *f)
{
    fputs("usage: lumesh devices [--json] [--device auto|cpu|host|egl:N]\n"
          "Lists EGL rendering devices (GPUs first, then Mesa's software renderer), probing each\n"
          "with an OpenGL ES 3 context, lumesh's CPU rasteriser (cpu) and USB devices with known\n"
          "accelerators flagged; then the device that --device (default auto: the first working\n"
          "GPU, else cpu) selects, as lumesh-worker would choose it.\n"
          "The CPU rasteriser shades 8 pixels at a time where the processor has AVX2, else 4\n"
          "(LUMESH_CPU_LANES=4 forces 4); both give the same bits.\n",
          f);
}

static const co_cli_spec spec = {CMD, usage, 0, 0, NULL, NULL, 1};

/* Returns -1 to go on, else the exit code. */
static int parse(int argc, char **argv, int *json, const char **device)
{
    const co_opt opts[] = {CO_OPT_FLAG("json", 'j', json), CO_OPT_STR("device", 'd', device)};
    return co_cli_parse(&spec, opts, CO_OPTS_N(opts), argc, argv);
}

int co_cli_devices(int argc, char **argv)
{
    devices_report r; /* ~40 KiB */
    int json = 0, rc;
    memset(&r, 0, sizeof r);
    r.spec = "auto";
    if ((rc = parse(argc, argv, &json, &r.spec)) >= 0)
        return rc;
    lm_status st = wk_device_check_spec(r.spec);
    if (st != LM_OK) /* a malformed spec is a usage error before any probing */
        return co_cli_fail(CMD, st);
    st = wk_device_survey_take(&r.dev);
    if (st != LM_OK)
        return co_cli_fail(CMD, st);
    r.selected = -1;
    r.select_status = wk_device_choose(r.spec, r.dev.egl, r.dev.egl_count, &r.selected);
    if (r.select_status != LM_OK)
        snprintf(r.select_error, sizeof r.select_error, "%s", lm_last_error());
    if (json)
        print_json(stdout, &r);
    else
        print_text(stdout, &r);
    if (r.select_status != LM_OK)
        return co_cli_fail(CMD, r.select_status);
    return 0;
}
