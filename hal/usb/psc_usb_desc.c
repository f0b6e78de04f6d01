/* SPDX-License-Identifier: MIT */
/*
 * psc_usb_desc.c - the gamepad interface in raw USB descriptors
 * (psc_usb_desc.h). Each descriptor starts with bLength and bDescriptorType;
 * every field is read only after checking that bLength covers it and that
 * bLength stays inside the buffer.
 */
#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "psc_usb_desc.h"

#define DT_DEVICE 0x01u
#define DT_CONFIG 0x02u
#define DT_INTERFACE 0x04u
#define DT_ENDPOINT 0x05u
#define DT_HID 0x21u
#define DT_REPORT 0x22u
#define CLASS_HID 0x03u
#define SUBCLASS_BOOT 0x01u

static uint16_t desc_le16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (p[1] << 8));
}

static int desc_fail(char *why, size_t whylen, int rc, const char *reason)
{
    if (why != NULL && whylen > 0)
        snprintf(why, whylen, "%s", reason);
    return rc;
}

int psc_usb_find_hid_interface(const uint8_t *desc, size_t len, psc_usb_hid_iface_t *out, char *why,
                               size_t whylen)
{
    psc_usb_hid_iface_t cur;
    bool in_candidate = false, saw_hid = false, saw_boot = false;
    size_t pos, end;

    memset(out, 0, sizeof *out);
    if (desc == NULL || len < 18 || desc[0] < 18 || desc[1] != DT_DEVICE)
        return desc_fail(why, whylen, -EINVAL, "no device descriptor");
    memset(&cur, 0, sizeof cur);
    cur.vendor_id = desc_le16(desc + 8);
    cur.product_id = desc_le16(desc + 10);
    pos = desc[0];
    if (pos > len || len - pos < 9 || desc[pos] < 9 || desc[pos + 1] != DT_CONFIG)
        return desc_fail(why, whylen, -EINVAL, "no configuration descriptor");
    end = pos + desc_le16(desc + pos + 2);   /* wTotalLength of the first configuration */
    if (end > len || end < pos + 9)
        return desc_fail(why, whylen, -EINVAL, "configuration longer than the descriptors read");
    pos += desc[pos];
    while (pos < end) {
        const uint8_t *d = desc + pos;
        uint8_t dlen = d[0];

        if (end - pos < 2 || dlen < 2 || dlen > end - pos)
            return desc_fail(why, whylen, -EINVAL, "a descriptor runs past the configuration");
        switch (d[1]) {
        case DT_INTERFACE:
            if (dlen < 9)
                return desc_fail(why, whylen, -EINVAL, "short interface descriptor");
            if (in_candidate && cur.ep_in != 0 && cur.report_desc_len != 0)
                goto found;
            in_candidate = false;
            if (d[5] != CLASS_HID || d[3] != 0)
                break;
            saw_hid = true;
            if (d[6] == SUBCLASS_BOOT && (d[7] == 1 || d[7] == 2)) {
                saw_boot = true;
                break;
            }
            in_candidate = true;
            cur.interface_number = d[2];
            cur.subclass = d[6];
            cur.protocol = d[7];
            cur.ep_in = 0;
            cur.report_desc_len = 0;
            break;
        case DT_HID:
            /* bLength, type, bcdHID(2), country, bNumDescriptors, then (type, length) pairs */
            if (!in_candidate)
                break;
            if (dlen < 6)
                return desc_fail(why, whylen, -EINVAL, "short HID descriptor");
            for (unsigned i = 0; i < d[5] && 6u + 3u * i + 3u <= dlen; i++) {
                if (d[6 + 3 * i] == DT_REPORT) {
                    cur.report_desc_len = desc_le16(d + 7 + 3 * i);
                    break;
                }
            }
            break;
        case DT_ENDPOINT:
            if (!in_candidate)
                break;
            if (dlen < 7)
                return desc_fail(why, whylen, -EINVAL, "short endpoint descriptor");
            if ((d[2] & 0x80u) && (d[3] & 3u) == 3u && cur.ep_in == 0) {
                cur.ep_in = d[2];
                cur.ep_in_max_packet = (uint16_t)(desc_le16(d + 4) & 0x7FFu);
                cur.ep_in_interval = d[6];
            }
            break;
        default:
            break;
        }
        pos += dlen;
    }
    if (in_candidate && cur.ep_in != 0 && cur.report_desc_len != 0)
        goto found;
    if (in_candidate)
        return desc_fail(why, whylen, -ENODEV, "HID interface without an interrupt IN endpoint or report descriptor");
    return desc_fail(why, whylen, -ENODEV, saw_boot ? "only a boot keyboard or mouse"
                                           : saw_hid ? "no usable HID interface" : "no HID interface");
found:
    if (cur.ep_in_max_packet == 0)
        return desc_fail(why, whylen, -EINVAL, "interrupt endpoint with a zero packet size");
    *out = cur;
    return 0;
}
