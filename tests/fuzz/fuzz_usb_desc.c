/* SPDX-License-Identifier: MIT */
/*
 * fuzz_usb_desc.c - a USB device's raw standard descriptors (what a usbfs
 * node reads: the device descriptor, then the configuration with its
 * interface, HID and endpoint descriptors) through
 * psc_usb_find_hid_interface (hal/usb/psc_usb_desc.h), which the USB
 * backend runs before it claims anything. A refusal returns -EINVAL or
 * -ENODEV with a reason; a found interface is HID with an interrupt IN
 * endpoint (bit 7 set) and a packet size of at most 11 bits.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_support.h"
#include "usb/psc_usb_desc.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *desc = fuzz_aligned_copy(data, size);
    psc_usb_hid_iface_t iface;
    char why[128] = "";

    int rc = psc_usb_find_hid_interface(desc, size, &iface, why, sizeof why);
    if (rc == 0) {
        FUZZ_REQUIRE((iface.ep_in & 0x80u) != 0);
        FUZZ_REQUIRE(iface.ep_in_max_packet <= 0x7FFu);
    } else {
        FUZZ_REQUIRE(rc == -EINVAL || rc == -ENODEV);
        FUZZ_REQUIRE(why[0] != '\0' && memchr(why, '\0', sizeof why) != NULL);
    }
    free(desc);
    return 0;
}
