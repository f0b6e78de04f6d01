/* SPDX-License-Identifier: MIT */
/*
 * psc_usb_desc.h - find the gamepad interface of a USB device from its raw
 * standard descriptors: what reading a usbfs node (/dev/bus/usb/BBB/DDD)
 * returns, i.e. the 18-byte device descriptor followed by the configuration
 * descriptors with their interface, class and endpoint descriptors (USB 2.0
 * chapter 9.6, HID 1.11 section 6.2.1). Pure C, no libusb, so the USB
 * backend can decide whether to open a device before claiming anything, and
 * the decision is unit-tested and fuzzed.
 *
 * A gamepad interface is: interface class 3 (HID), alternate setting 0, not
 * a boot keyboard or boot mouse (subclass 1 with protocol 1 or 2), with a HID
 * class descriptor naming a report descriptor and an interrupt IN endpoint.
 * Whether it really is a joystick is decided later from its report
 * descriptor (psc_hid_parse.h). Only the first configuration is read
 * (gamepads have one).
 */
#ifndef PSC_USB_DESC_H
#define PSC_USB_DESC_H

#include <stddef.h>
#include <stdint.h>

/** What the backend needs to open one HID interface. */
typedef struct {
    uint16_t vendor_id, product_id;
    uint8_t interface_number;
    uint8_t subclass, protocol;
    uint8_t ep_in;                 /* interrupt IN endpoint address (bit 7 set) */
    uint16_t ep_in_max_packet;     /* wMaxPacketSize bits 0..10 */
    uint8_t ep_in_interval;
    uint16_t report_desc_len;      /* wDescriptorLength of the report descriptor */
} psc_usb_hid_iface_t;

/**
 * Look through desc[0..len) for the first gamepad interface (see above).
 * Returns 0 with *out filled; -EINVAL when the descriptors are malformed
 * (lengths running past the end or shorter than their type needs); -ENODEV
 * when they are fine but hold no such interface. why[whylen] (may be NULL)
 * gets a short reason on failure ("no HID interface", "boot keyboard", ...).
 */
int psc_usb_find_hid_interface(const uint8_t *desc, size_t len, psc_usb_hid_iface_t *out, char *why,
                               size_t whylen);

#endif
