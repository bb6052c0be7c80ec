/* worker/render/usb_devices.c — libusb enumeration of attached USB devices and the table of known
 * render / AI accelerators.
 *
 * The table (vendor:product, "*" = any product of the vendor):
 *   03e7:2150  Intel Movidius Myriad 2 VPU (Neural Compute Stick, before firmware boot)
 *   03e7:2485  Intel Movidius Myriad X VPU (Neural Compute Stick 2, before firmware boot)
 *   03e7:f63b  Intel Movidius Myriad VPU (booted, running firmware)
 *   1a6e:089a  Google Coral Edge TPU USB Accelerator (Global Unichip, before firmware load)
 *   18d1:9302  Google Coral Edge TPU USB Accelerator (firmware loaded)
 *   17e9:*     DisplayLink USB graphics adapter
 * These are reported so that an operator sees what is attached; lumesh itself renders through
 * EGL only (none of these is an EGL device), so recognising one changes no device choice.
 * USB has no device class for GPUs or NPUs, so recognition is by vendor/product only.
 * libusb errors stay inside: no USB bus is zero devices, not an error. */
#include "worker/render/usb_devices.h"

#include <libusb-1.0/libusb.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "common/log.h"

#define ANY_PRODUCT 0xffffffffu

typedef struct accel_entry {
    uint16_t vendor;
    uint32_t product; /* ANY_PRODUCT = every product of the vendor */
    const char *name;
} accel_entry;

static const accel_entry accel_table[] = {
    {0x03e7, 0x2150, "Intel Movidius Myriad 2 VPU (unbooted)"},
    {0x03e7, 0x2485, "Intel Movidius Myriad X VPU (unbooted)"},
    {0x03e7, 0xf63b, "Intel Movidius Myriad VPU (booted)"},
    {0x1a6e, 0x089a, "Google Coral Edge TPU (before firmware load)"},
    {0x18d1, 0x9302, "Google Coral Edge TPU"},
    {0x17e9, ANY_PRODUCT, "DisplayLink USB graphics adapter"},
};

const char *wk_usb_accelerator_name(uint16_t vendor_id, uint16_t product_id)
{
    for (size_t i = 0; i < sizeof accel_table / sizeof accel_table[0]; i++) {
        const accel_entry *e = &accel_table[i];
        if (e->vendor == vendor_id && (e->product == ANY_PRODUCT || e->product == product_id))
            return e->name;
    }
    return NULL;
}

/* iProduct string, best effort: devices we may not open (permissions) keep "". */
static void read_product(libusb_device *dev, uint8_t index, char *dst, size_t cap)
{
    libusb_device_handle *h = NULL;
    dst[0] = '\0';
    if (index == 0 || libusb_open(dev, &h) != 0)
        return;
    int n = libusb_get_string_descriptor_ascii(h, index, (unsigned char *)dst, (int)cap - 1);
    dst[n > 0 ? n : 0] = '\0';
    for (int i = 0; i < n; i++) { /* keep it printable: it goes to terminals and JSON */
        if ((unsigned char)dst[i] < 0x20 || (unsigned char)dst[i] > 0x7e)
            dst[i] = '?';
    }
    libusb_close(h);
}

static int describe(libusb_device *dev, wk_usb_device *out)
{
    struct libusb_device_descriptor d;
    int rc = libusb_get_device_descriptor(dev, &d);
    if (rc != 0) {
        lm_debug("usb: skipping a device: %s", libusb_error_name(rc));
        return 0;
    }
    memset(out, 0, sizeof *out);
    out->bus = libusb_get_bus_number(dev);
    out->address = libusb_get_device_address(dev);
    out->vendor_id = d.idVendor;
    out->product_id = d.idProduct;
    out->device_class = d.bDeviceClass;
    const char *name = wk_usb_accelerator_name(d.idVendor, d.idProduct);
    if (name) {
        out->is_accelerator = 1;
        snprintf(out->accelerator, sizeof out->accelerator, "%s", name);
    }
    read_product(dev, d.iProduct, out->product, sizeof out->product);
    return 1;
}

lm_status wk_usb_list_devices(wk_usb_device *out, int cap, int *count)
{
    libusb_context *ctx = NULL;
    libusb_device **list = NULL;
    LM_ASSERT(count != NULL && cap >= 0 && (out != NULL || cap == 0));
    *count = 0;
    int rc = libusb_init(&ctx);
    if (rc != 0) {
        lm_debug("usb: no USB bus (libusb_init: %s)", libusb_error_name(rc));
        return LM_OK;
    }
    ssize_t n = libusb_get_device_list(ctx, &list);
    if (n < 0) {
        libusb_exit(ctx);
        if (n == LIBUSB_ERROR_NO_MEM)
            return lm_fail(LM_E_NOMEM, "libusb_get_device_list: %s", libusb_error_name((int)n));
        lm_debug("usb: no device list (%s)", libusb_error_name((int)n));
        return LM_OK;
    }
    int k = 0;
    for (ssize_t i = 0; i < n && k < cap; i++)
        k += describe(list[i], &out[k]);
    libusb_free_device_list(list, 1);
    libusb_exit(ctx);
    *count = k;
    return LM_OK;
}
