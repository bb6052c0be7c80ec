/* worker/render/usb_devices.h — attached USB devices, with known render / AI accelerators
 * recognised. Enumeration through libusb with a private context. A machine without a USB bus
 * (libusb_init fails, no /dev/bus/usb, container) has zero devices; that is not an error. */
#ifndef LM_WORKER_USB_DEVICES_H
#define LM_WORKER_USB_DEVICES_H

#include <stdint.h>

#include "common/error.h"

#define WK_MAX_USB_DEVICES 128

typedef struct wk_usb_device {
    uint8_t bus, address;
    uint16_t vendor_id, product_id;
    uint8_t device_class; /* bDeviceClass (0 = defined per interface) */
    char product[128];    /* iProduct string if the device could be opened, else "" */
    int is_accelerator;   /* found in the table of known accelerators */
    char accelerator[96]; /* the table's name for it, "" if not recognised */
} wk_usb_device;

/* The devices on all buses, at most cap (WK_MAX_USB_DEVICES suffices on ordinary machines);
 * *count <= cap. LM_OK with *count = 0 when there is no USB. */
lm_status wk_usb_list_devices(wk_usb_device *out, int cap, int *count);

/* The table's name for vendor:product, or NULL if it is not a known accelerator. */
const char *wk_usb_accelerator_name(uint16_t vendor_id, uint16_t product_id);

#endif
