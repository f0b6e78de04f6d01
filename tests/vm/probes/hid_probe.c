/* SPDX-License-Identifier: MIT */
/*
 * hid_probe - read a USB HID gamepad through libusb the way the USB joystick
 * backend will: find the device, take the interface from a kernel driver
 * if one holds it, fetch the HID report descriptor with a control transfer,
 * and read reports with interrupt-IN transfers, counting zero-length packets
 * (a gadget may send one after every report that fills its packet).
 *
 *   hid_probe list                  every device: VID:PID and interface classes
 *   hid_probe read VID:PID N        print "descriptor HEX", "ready", then the
 *                                   first N non-empty reports as "report HEX"
 *                                   and "zlp COUNT"; fails when a transfer
 *                                   times out or the device goes away
 *   hid_probe wait-gone VID:PID     wait until the device has left the bus
 *
 * A "ready" line tells the case script it may start writing reports.
 */
/* vm-pkg-config: libusb-1.0 */
#include <libusb.h>

#include "probe_util.h"

#define HID_PROBE_TIMEOUT_MS 15000
#define HID_CLASS 3
#define HID_DESCRIPTOR_HID 0x21
#define HID_DESCRIPTOR_REPORT 0x22

static void hid_list(libusb_context *ctx)
{
    libusb_device **list;
    ssize_t n = libusb_get_device_list(ctx, &list);

    if (n < 0)
        probe_fail(0, "libusb_get_device_list: %s", libusb_strerror((int)n));
    for (ssize_t i = 0; i < n; i++) {
        struct libusb_device_descriptor dd;
        struct libusb_config_descriptor *cfg;

        if (libusb_get_device_descriptor(list[i], &dd) != 0)
            continue;
        printf("device %04x:%04x bus %u address %u", dd.idVendor, dd.idProduct, libusb_get_bus_number(list[i]),
               libusb_get_device_address(list[i]));
        if (libusb_get_active_config_descriptor(list[i], &cfg) == 0) {
            for (int k = 0; k < cfg->bNumInterfaces; k++)
                if (cfg->interface[k].num_altsetting > 0)
                    printf(" interface-class %u", cfg->interface[k].altsetting[0].bInterfaceClass);
            libusb_free_config_descriptor(cfg);
        }
        printf("\n");
    }
    libusb_free_device_list(list, 1);
}

static void parse_vid_pid(const char *s, uint16_t *vid, uint16_t *pid)
{
    unsigned v, p;
    char tail;

    if (sscanf(s, "%4x:%4x%c", &v, &p, &tail) != 2)
        probe_fail(0, "'%s' is not VID:PID in hex", s);
    *vid = (uint16_t)v;
    *pid = (uint16_t)p;
}

static void print_hex(const char *label, const uint8_t *b, int n)
{
    printf("%s", label);
    for (int i = 0; i < n; i++)
        printf(" %02x", b[i]);
    printf("\n");
}

/* The HID interface of an open device: its number, IN endpoint, packet size and report descriptor length. */
static void hid_find_interface(libusb_device_handle *h, int *iface, uint8_t *ep, uint16_t *packet, uint16_t *desc_len)
{
    struct libusb_config_descriptor *cfg;

    if (libusb_get_active_config_descriptor(libusb_get_device(h), &cfg) != 0)
        probe_fail(0, "no active configuration");
    *iface = -1;
    for (int k = 0; k < cfg->bNumInterfaces && *iface < 0; k++) {
        const struct libusb_interface_descriptor *alt;

        if (cfg->interface[k].num_altsetting < 1)
            continue;
        alt = &cfg->interface[k].altsetting[0];
        if (alt->bInterfaceClass != HID_CLASS)
            continue;
        /* the HID class descriptor follows the interface: bLength, 0x21, bcdHID, country, count, then type+length pairs */
        for (int off = 0; off + 9 <= alt->extra_length; off += alt->extra[off] ? alt->extra[off] : 1) {
            const uint8_t *d = alt->extra + off;

            if (d[1] == HID_DESCRIPTOR_HID && d[6] == HID_DESCRIPTOR_REPORT)
                *desc_len = (uint16_t)(d[7] | d[8] << 8);
        }
        for (int e = 0; e < alt->bNumEndpoints; e++) {
            const struct libusb_endpoint_descriptor *epd = &alt->endpoint[e];

            if ((epd->bEndpointAddress & LIBUSB_ENDPOINT_IN) &&
                (epd->bmAttributes & LIBUSB_TRANSFER_TYPE_MASK) == LIBUSB_TRANSFER_TYPE_INTERRUPT) {
                *ep = epd->bEndpointAddress;
                *packet = epd->wMaxPacketSize;
                *iface = alt->bInterfaceNumber;
            }
        }
    }
    libusb_free_config_descriptor(cfg);
    if (*iface < 0)
        probe_fail(0, "the device has no HID interface with an interrupt-IN endpoint");
}

static void hid_read(libusb_context *ctx, const char *id, int reports)
{
    uint16_t vid, pid, packet = 0, desc_len = 0;
    libusb_device_handle *h;
    uint8_t desc[1024], buf[1024], ep = 0;
    int iface, r, got = 0, zlp = 0, n;

    parse_vid_pid(id, &vid, &pid);
    h = libusb_open_device_with_vid_pid(ctx, vid, pid);
    if (h == NULL)
        probe_fail(0, "no device %s (or no permission)", id);
    hid_find_interface(h, &iface, &ep, &packet, &desc_len);
    printf("interface %d endpoint 0x%02x packet %u\n", iface, ep, packet);
    r = libusb_kernel_driver_active(h, iface);
    printf("kernel driver %s\n", r == 1 ? "attached" : "none");
    libusb_set_auto_detach_kernel_driver(h, 1);
    r = libusb_claim_interface(h, iface);
    if (r != 0)
        probe_fail(0, "claim interface %d: %s", iface, libusb_strerror(r));
    if (desc_len == 0 || desc_len > sizeof desc)
        probe_fail(0, "report descriptor length %u out of range", desc_len);
    n = libusb_control_transfer(h, LIBUSB_ENDPOINT_IN | LIBUSB_RECIPIENT_INTERFACE, LIBUSB_REQUEST_GET_DESCRIPTOR,
                                HID_DESCRIPTOR_REPORT << 8, (uint16_t)iface, desc, desc_len, HID_PROBE_TIMEOUT_MS);
    if (n < 0)
        probe_fail(0, "GET_DESCRIPTOR(report): %s", libusb_strerror(n));
    print_hex("descriptor", desc, n);
    printf("ready\n");
    fflush(stdout);
    if (packet == 0 || packet > sizeof buf)
        probe_fail(0, "packet size %u out of range", packet);
    while (got < reports) {
        int len = 0;

        /* one packet per transfer: a full-size packet ends the transfer without needing a ZLP */
        r = libusb_interrupt_transfer(h, ep, buf, packet, &len, HID_PROBE_TIMEOUT_MS);
        if (r != 0)
            probe_fail(0, "interrupt IN after %d reports: %s", got, libusb_strerror(r));
        if (len == 0) {
            zlp++;
            continue;
        }
        print_hex("report", buf, len);
        fflush(stdout);
        got++;
    }
    printf("zlp %d\n", zlp);
    libusb_release_interface(h, iface);
    libusb_close(h);
}

static void hid_wait_gone(libusb_context *ctx, const char *id)
{
    uint16_t vid, pid;

    parse_vid_pid(id, &vid, &pid);
    for (int i = 0; i < 200; i++) {
        libusb_device_handle *h = libusb_open_device_with_vid_pid(ctx, vid, pid);

        if (h == NULL) {
            printf("gone %s\n", id);
            return;
        }
        libusb_close(h);
        usleep(50000);
    }
    probe_fail(0, "%s is still there", id);
}

int main(int argc, char **argv)
{
    libusb_context *ctx;
    int r = libusb_init(&ctx);

    if (r != 0)
        probe_fail(0, "libusb_init: %s", libusb_strerror(r));
    if (argc == 2 && strcmp(argv[1], "list") == 0) {
        hid_list(ctx);
    } else if (argc == 4 && strcmp(argv[1], "read") == 0) {
        hid_read(ctx, argv[2], (int)probe_number("reports", argv[3]));
    } else if (argc == 3 && strcmp(argv[1], "wait-gone") == 0) {
        hid_wait_gone(ctx, argv[2]);
    } else {
        fprintf(stderr, "usage: hid_probe list | read VID:PID N | wait-gone VID:PID\n");
        return 2;
    }
    libusb_exit(ctx);
    return 0;
}
