/* SPDX-License-Identifier: MIT */
/*
 * psc_usb_input.c - the "usb" input backend: USB joysticks and gamepads
 * through libusb-1.0, read by their HID report descriptors (no built-in
 * layouts), plugged and unplugged at any time.
 *
 * Finding devices. The backend lists /dev/bus/usb/BBB/DDD itself (with
 * getdents64 on directory descriptors opened once, so a rescan allocates
 * nothing) and reads each new node's standard descriptors (a plain read() of
 * a usbfs node returns them without claiming anything); psc_usb_desc.h
 * decides whether it has a gamepad interface. A candidate is opened O_RDWR
 * and handed to libusb with libusb_wrap_sys_device. Why not libusb's device
 * list: on Linux it is refreshed only by udev events, and a kiosk (or a test
 * VM) without a running udevd would never see a device plugged in after
 * start-up. libusb hotplug is still registered where libusb supports it,
 * but only to trigger an immediate rescan; the periodic rescan
 * (option rescan_ms) works everywhere.
 *
 * Opening a gamepad: detach the kernel driver from the interface (usbhid;
 * re-attached at close), claim it, fetch the HID report descriptor with an
 * asynchronous GET_DESCRIPTOR control transfer, parse it (psc_hid_parse.h);
 * a device without joystick controls is released and its driver re-attached.
 * Then two interrupt-IN transfers stay in flight; psc_usb_pad.h decodes what
 * they bring. Zero-length packets (sent after a report that fills its last
 * packet) are counted and skipped. Everything is polled from the input's
 * poll with libusb_handle_events_timeout_completed(0), so poll never blocks.
 *
 * Unplugging: a transfer ending with LIBUSB_TRANSFER_NO_DEVICE (or the
 * node disappearing, or PSC_USB_PAD_MAX_ERRORS failures in a row) closes the
 * pad: DEVICE_LEAVE, slot freed. A replug is a new node, found by the next
 * scan: DEVICE_ARRIVE. If libusb itself cannot start (no USB host
 * controller), the backend still opens, reports no device and retries at
 * every rescan: a kiosk without its gamepad keeps running.
 *
 * Memory: transfers and their buffers for USB_MAX_PADS pads are allocated at
 * open. libusb allocates internally per submitted transfer (usbfs URBs);
 * that is the library's business and bounded by the two transfers per pad.
 *
 * Options (board lines "input.KEY = VALUE"): the map of psc_usb_pad.h
 * (axis.*, button.*, hat), match = VID:PID[,VID:PID...] to accept only those
 * devices, rescan_ms = 50..60000 (default 1000) or 0 for no periodic rescan,
 * dev_dir = the usbfs directory (default /dev/bus/usb; tests point it
 * elsewhere).
 */
#define _GNU_SOURCE   /* getdents64 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <libusb.h>

#include "psc_hal_backends.h"
#include "psc_hal_clock.h"
#include "psc_hal_event_queue.h"
#include "psc_hal_input.h"
#include "psc_usb_desc.h"
#include "psc_usb_pad.h"
#include "psc_io_log.h"

#define USB_MAX_PADS 4u                   /* gamepads at once (device slots 0..3) */
#define USB_XFERS_PER_PAD 2u              /* interrupt transfers in flight per pad */
#define USB_XFER_BYTES 1024u              /* >= PSC_HID_MAX_REPORT_BYTES + 1 */
#define USB_SEEN_MAX 64u                  /* usbfs nodes remembered between scans */
#define USB_QUEUE_LEN 128u
#define USB_DESC_READ_MAX 4096u           /* standard descriptors read from a node */
#define USB_CTRL_TIMEOUT_MS 1000u
#define USB_CLOSE_WAIT_ROUNDS 20          /* x 50 ms waiting for cancelled transfers at close */
#define USB_DEFAULT_RESCAN_MS 1000u
#define USB_MAX_MATCH 8u

typedef enum { PAD_FREE = 0, PAD_DESCRIBING, PAD_RUNNING, PAD_CLOSING } usb_pad_phase_t;

/* What a scan remembers about a usbfs node, so it is probed once. */
typedef enum { NODE_IGNORED = 0, NODE_OPEN, NODE_RETRY } usb_node_state_t;

typedef struct usb_input usb_input_t;

typedef struct {
    usb_input_t *owner;
    usb_pad_phase_t phase;
    uint8_t slot;
    int fd;
    uint16_t bus, addr;
    libusb_device_handle *handle;
    psc_usb_hid_iface_t iface;
    bool detached, claimed, gone, announced, clear_halt;
    struct libusb_transfer *ctrl;
    uint8_t *ctrl_buf;
    bool ctrl_busy;
    struct libusb_transfer *xfer[USB_XFERS_PER_PAD];
    uint8_t *xfer_buf[USB_XFERS_PER_PAD];
    bool xfer_busy[USB_XFERS_PER_PAD];
    uint16_t xfer_len;
    psc_usb_pad_t pad;
    char name[96];
} usb_pad_t;

typedef struct {
    uint16_t bus, addr;
    uint8_t state;          /* usb_node_state_t */
    bool alive;             /* seen by the current scan */
} usb_node_t;

struct usb_input {
    psc_hal_input_t base;              /* first: the HAL hands this pointer back */
    psc_hal_clock_t *clock;
    libusb_context *ctx;
    bool ctx_failed_reported;
    libusb_hotplug_callback_handle hotplug;
    bool hotplug_registered;
    bool scan_pending;
    uint64_t next_scan_us;
    uint32_t rescan_us;
    uint64_t now_us;                   /* the time of the poll being served, for callbacks */
    char dev_dir[128];
    int root_fd;
    psc_usb_map_t map;
    psc_hal_button_timing_t timing;
    uint16_t match_vid[USB_MAX_MATCH], match_pid[USB_MAX_MATCH];
    unsigned match_count;
    usb_pad_t pads[USB_MAX_PADS];
    usb_node_t nodes[USB_SEEN_MAX];
    unsigned node_count;
    psc_hal_input_event_t queue_store[USB_QUEUE_LEN];
    psc_hal_event_queue_t queue;
    uint8_t desc_buf[USB_DESC_READ_MAX];
    char dirent_buf[4096];
    char dirent_buf2[4096];
};

static const char *const usb_known_options[] = { "match", "rescan_ms", "dev_dir", NULL };

static void usb_log(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Device events worth a line on stderr: the firmware's log shows arrivals
 * and departures; this says why a plugged-in device was not used. */
static void usb_log(const char *fmt, ...)
{
    char line[PSC_LOG_LINE_MAX];
    va_list ap;

    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    psc_io_log(PSC_LOG_NOTICE, "periscope: usb input: %s", line);
}

static void usb_queue_device_event(usb_input_t *s, usb_pad_t *p, psc_hal_input_type_t type)
{
    psc_hal_input_event_t ev = { .type = type, .device = p->slot, .time_us = s->now_us };

    (void)psc_hal_event_queue_push(&s->queue, &ev);
}

static bool usb_pad_busy(const usb_pad_t *p)
{
    if (p->ctrl_busy)
        return true;
    for (unsigned i = 0; i < USB_XFERS_PER_PAD; i++)
        if (p->xfer_busy[i])
            return true;
    return false;
}

/* Begin closing: cancel what is in flight; usb_pad_finish completes it once
 * libusb has handed every transfer back. */
static void usb_pad_start_close(usb_pad_t *p, bool gone)
{
    if (p->phase == PAD_FREE)
        return;
    p->phase = PAD_CLOSING;
    p->gone = p->gone || gone;
    if (p->ctrl_busy)
        libusb_cancel_transfer(p->ctrl);
    for (unsigned i = 0; i < USB_XFERS_PER_PAD; i++)
        if (p->xfer_busy[i])
            libusb_cancel_transfer(p->xfer[i]);
}

static usb_node_t *usb_node_find(usb_input_t *s, uint16_t bus, uint16_t addr)
{
    for (unsigned i = 0; i < s->node_count; i++)
        if (s->nodes[i].bus == bus && s->nodes[i].addr == addr)
            return &s->nodes[i];
    return NULL;
}

/* Release the interface, give it back to its kernel driver, close. */
static void usb_pad_finish(usb_input_t *s, usb_pad_t *p)
{
    usb_node_t *n = usb_node_find(s, p->bus, p->addr);

    if (p->handle != NULL) {
        if (p->claimed)
            libusb_release_interface(p->handle, p->iface.interface_number);
        if (p->detached && !p->gone)
            libusb_attach_kernel_driver(p->handle, p->iface.interface_number);
        libusb_close(p->handle);
    }
    if (p->fd >= 0)
        close(p->fd);
    if (p->announced)
        usb_queue_device_event(s, p, PSC_HAL_INPUT_DEVICE_LEAVE);
    /* a device that vanished may come back at the same address; one that
     * failed while plugged in (not a joystick, errors) stays ignored until
     * it is unplugged, so its kernel driver is not detached again and again */
    if (n != NULL && n->state == NODE_OPEN)
        n->state = p->gone ? NODE_RETRY : NODE_IGNORED;
    p->phase = PAD_FREE;
    p->handle = NULL;
    p->fd = -1;
    p->claimed = p->detached = p->gone = p->announced = p->clear_halt = false;
}

static psc_usb_xfer_status_t usb_status(enum libusb_transfer_status st)
{
    switch (st) {
    case LIBUSB_TRANSFER_COMPLETED: return PSC_USB_XFER_COMPLETED;
    case LIBUSB_TRANSFER_TIMED_OUT: return PSC_USB_XFER_TIMED_OUT;
    case LIBUSB_TRANSFER_STALL: return PSC_USB_XFER_STALL;
    case LIBUSB_TRANSFER_OVERFLOW: return PSC_USB_XFER_OVERFLOW;
    case LIBUSB_TRANSFER_NO_DEVICE: return PSC_USB_XFER_NO_DEVICE;
    case LIBUSB_TRANSFER_CANCELLED: return PSC_USB_XFER_CANCELLED;
    case LIBUSB_TRANSFER_ERROR:
    default: return PSC_USB_XFER_ERROR;
    }
}

static void LIBUSB_CALL usb_interrupt_done(struct libusb_transfer *t)
{
    usb_pad_t *p = t->user_data;
    usb_input_t *s = p->owner;
    unsigned i = t->buffer == p->xfer_buf[0] ? 0u : 1u;
    psc_usb_next_t next;

    p->xfer_busy[i] = false;
    if (p->phase != PAD_RUNNING)
        return;
    next = psc_usb_pad_transfer_done(&p->pad, &s->map, &s->timing, usb_status(t->status), t->buffer,
                                     (size_t)(t->actual_length > 0 ? t->actual_length : 0), s->now_us, &s->queue);
    switch (next) {
    case PSC_USB_NEXT_RESUBMIT:
        if (libusb_submit_transfer(t) == 0)
            p->xfer_busy[i] = true;
        else
            usb_pad_start_close(p, true);
        break;
    case PSC_USB_NEXT_CLEAR_HALT:
        p->clear_halt = true;   /* done from poll: libusb_clear_halt is synchronous */
        break;
    case PSC_USB_NEXT_GONE:
        if (t->status != LIBUSB_TRANSFER_NO_DEVICE)
            usb_log("%s: %u transfers failed in a row; closing it", p->name, (unsigned)PSC_USB_PAD_MAX_ERRORS);
        usb_pad_start_close(p, t->status == LIBUSB_TRANSFER_NO_DEVICE);
        break;
    case PSC_USB_NEXT_IDLE:
        break;
    }
}

static int usb_pad_submit_all(usb_pad_t *p)
{
    for (unsigned i = 0; i < USB_XFERS_PER_PAD; i++) {
        if (p->xfer_busy[i])
            continue;
        libusb_fill_interrupt_transfer(p->xfer[i], p->handle, p->iface.ep_in, p->xfer_buf[i], p->xfer_len,
                                       usb_interrupt_done, p, 0);
        if (libusb_submit_transfer(p->xfer[i]) != 0)
            return -EIO;
        p->xfer_busy[i] = true;
    }
    return 0;
}

/* The report descriptor arrived: parse it, start reading reports. */
static void LIBUSB_CALL usb_descriptor_done(struct libusb_transfer *t)
{
    usb_pad_t *p = t->user_data;
    usb_input_t *s = p->owner;
    psc_hid_gamepad_t g;
    psc_hid_error_t herr;
    char summary[96];
    unsigned mps = p->iface.ep_in_max_packet, len;

    p->ctrl_busy = false;
    if (p->phase != PAD_DESCRIBING)
        return;
    if (t->status != LIBUSB_TRANSFER_COMPLETED || t->actual_length <= 0) {
        if (t->status != LIBUSB_TRANSFER_NO_DEVICE)
            usb_log("%s: reading its HID report descriptor failed (%s)", p->name,
                    libusb_error_name(t->status == LIBUSB_TRANSFER_STALL ? LIBUSB_ERROR_PIPE : LIBUSB_ERROR_IO));
        usb_pad_start_close(p, t->status == LIBUSB_TRANSFER_NO_DEVICE);
        return;
    }
    if (psc_hid_parse(libusb_control_transfer_get_data(t), (size_t)t->actual_length, &g, &herr) != 0) {
        usb_log("%s: not used: its HID report descriptor (%d bytes) %s at byte %zu: %s", p->name,
                t->actual_length, herr.reason[0] ? "was refused" : "is unusable", herr.offset, herr.reason);
        usb_pad_start_close(p, false);
        return;
    }
    /* ask for whole packets: a report of k full packets ends with a ZLP */
    len = g.max_report_bytes > mps ? (g.max_report_bytes + mps - 1u) / mps * mps : mps;
    p->xfer_len = (uint16_t)(len > USB_XFER_BYTES ? USB_XFER_BYTES : len);
    psc_usb_pad_init(&p->pad, &g, &s->map, p->slot, s->now_us);
    p->phase = PAD_RUNNING;
    if (usb_pad_submit_all(p) != 0) {
        usb_log("%s: could not start reading its reports", p->name);
        usb_pad_start_close(p, false);
        return;
    }
    psc_hid_describe(&g, summary, sizeof summary);
    snprintf(p->name + strlen(p->name), sizeof p->name - strlen(p->name), ": %s", summary);
    p->announced = true;
    usb_queue_device_event(s, p, PSC_HAL_INPUT_DEVICE_ARRIVE);
}

/* Open a usbfs node that has a gamepad interface (fd is O_RDWR). Takes fd. */
static void usb_pad_open(usb_input_t *s, usb_pad_t *p, int fd, uint16_t bus, uint16_t addr,
                         const psc_usb_hid_iface_t *iface)
{
    int rc;
    unsigned dlen = iface->report_desc_len > PSC_HID_MAX_DESCRIPTOR ? PSC_HID_MAX_DESCRIPTOR
                                                                     : iface->report_desc_len;

    p->fd = fd;
    p->bus = bus;
    p->addr = addr;
    p->iface = *iface;
    snprintf(p->name, sizeof p->name, "%04x:%04x at usb %u-%u", (unsigned)iface->vendor_id,
             (unsigned)iface->product_id, (unsigned)bus, (unsigned)addr);
    rc = libusb_wrap_sys_device(s->ctx, (intptr_t)fd, &p->handle);
    if (rc != 0) {
        usb_log("%s: libusb cannot use it: %s", p->name, libusb_error_name(rc));
        p->handle = NULL;
        goto fail;
    }
    p->phase = PAD_DESCRIBING;
    if (libusb_kernel_driver_active(p->handle, iface->interface_number) == 1) {
        rc = libusb_detach_kernel_driver(p->handle, iface->interface_number);
        if (rc != 0) {
            usb_log("%s: cannot detach the kernel driver from interface %u: %s", p->name,
                    (unsigned)iface->interface_number, libusb_error_name(rc));
            goto fail;
        }
        p->detached = true;
    }
    rc = libusb_claim_interface(p->handle, iface->interface_number);
    if (rc != 0) {
        usb_log("%s: cannot claim interface %u: %s", p->name, (unsigned)iface->interface_number,
                libusb_error_name(rc));
        goto fail;
    }
    p->claimed = true;
    libusb_fill_control_setup(p->ctrl_buf, LIBUSB_ENDPOINT_IN | LIBUSB_REQUEST_TYPE_STANDARD |
                                               LIBUSB_RECIPIENT_INTERFACE,
                              LIBUSB_REQUEST_GET_DESCRIPTOR, (uint16_t)(LIBUSB_DT_REPORT << 8),
                              iface->interface_number, (uint16_t)dlen);
    libusb_fill_control_transfer(p->ctrl, p->handle, p->ctrl_buf, usb_descriptor_done, p, USB_CTRL_TIMEOUT_MS);
    rc = libusb_submit_transfer(p->ctrl);
    if (rc != 0) {
        usb_log("%s: cannot ask for its report descriptor: %s", p->name, libusb_error_name(rc));
        goto fail;
    }
    p->ctrl_busy = true;
    return;
fail:
    p->phase = PAD_CLOSING;
    usb_pad_finish(s, p);
}

static bool usb_matches(const usb_input_t *s, const psc_usb_hid_iface_t *iface)
{
    if (s->match_count == 0)
        return true;
    for (unsigned i = 0; i < s->match_count; i++)
        if (s->match_vid[i] == iface->vendor_id && s->match_pid[i] == iface->product_id)
            return true;
    return false;
}

static usb_pad_t *usb_free_pad(usb_input_t *s)
{
    for (unsigned i = 0; i < USB_MAX_PADS; i++)
        if (s->pads[i].phase == PAD_FREE)
            return &s->pads[i];
    return NULL;
}

/* A node this scan has not seen before (or one to retry): probe it. */
static usb_node_state_t usb_probe(usb_input_t *s, int bus_fd, const char *name, uint16_t bus, uint16_t addr)
{
    psc_usb_hid_iface_t iface;
    usb_pad_t *p;
    char why[96];
    ssize_t n;
    int fd;

    fd = openat(bus_fd, name, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return NODE_RETRY;   /* it may be half-created: try at the next scan */
    n = read(fd, s->desc_buf, sizeof s->desc_buf);
    close(fd);
    if (n <= 0)
        return NODE_RETRY;
    if (psc_usb_find_hid_interface(s->desc_buf, (size_t)n, &iface, why, sizeof why) != 0 || !usb_matches(s, &iface))
        return NODE_IGNORED;
    p = usb_free_pad(s);
    if (p == NULL)
        return NODE_RETRY;   /* every slot in use: try again when one frees */
    fd = openat(bus_fd, name, O_RDWR | O_CLOEXEC);
    if (fd < 0) {
        usb_log("%04x:%04x at %s/%03u/%s: cannot open it for reading and writing (%s); run as root or give "
                "the kiosk user access with a udev rule (boards/README.md)", (unsigned)iface.vendor_id,
                (unsigned)iface.product_id, s->dev_dir, (unsigned)bus, name, strerror(errno));
        return NODE_IGNORED;
    }
    usb_pad_open(s, p, fd, bus, addr, &iface);
    return p->phase == PAD_FREE ? NODE_IGNORED : NODE_OPEN;
}

/* "001" -> 1; anything but three digits -> 0 (not a bus or device node). */
static uint16_t usb_three_digits(const char *n)
{
    if (n[0] < '0' || n[0] > '9' || n[1] < '0' || n[1] > '9' || n[2] < '0' || n[2] > '9' || n[3] != '\0')
        return 0;
    return (uint16_t)((n[0] - '0') * 100 + (n[1] - '0') * 10 + (n[2] - '0'));
}

/* Every directory entry of fd, by name, without allocating. */
typedef void (*usb_dirent_fn)(usb_input_t *s, int dir_fd, const char *name, uint16_t number, uint16_t ctx);

static void usb_list_dir(usb_input_t *s, int fd, char *buf, size_t buflen, usb_dirent_fn fn, uint16_t ctx)
{
    ssize_t n;

    if (lseek(fd, 0, SEEK_SET) < 0)
        return;
    while ((n = getdents64(fd, buf, buflen)) > 0) {
        for (ssize_t off = 0; off < n;) {
            const struct dirent64 *d = (const struct dirent64 *)(const void *)(buf + off);
            uint16_t number = usb_three_digits(d->d_name);

            if (number != 0)
                fn(s, fd, d->d_name, number, ctx);
            off += d->d_reclen;
        }
    }
}

static void usb_scan_device(usb_input_t *s, int bus_fd, const char *name, uint16_t addr, uint16_t bus)
{
    usb_node_t *node = usb_node_find(s, bus, addr);

    if (node != NULL && node->state != NODE_RETRY) {
        node->alive = true;
        return;
    }
    if (node == NULL) {
        if (s->node_count == USB_SEEN_MAX)
            return;   /* more devices than remembered: the rest wait for a slot in the table */
        node = &s->nodes[s->node_count++];
        *node = (usb_node_t){ bus, addr, NODE_RETRY, true };
    }
    node->alive = true;
    node->state = (uint8_t)usb_probe(s, bus_fd, name, bus, addr);
}

static void usb_scan_bus(usb_input_t *s, int root_fd, const char *name, uint16_t bus, uint16_t ctx)
{
    int fd = openat(root_fd, name, O_RDONLY | O_DIRECTORY | O_CLOEXEC);

    (void)ctx;
    if (fd < 0)
        return;
    usb_list_dir(s, fd, s->dirent_buf2, sizeof s->dirent_buf2, usb_scan_device, bus);
    close(fd);
}

static void usb_scan(usb_input_t *s)
{
    unsigned kept = 0;

    s->scan_pending = false;
    if (s->ctx == NULL) {
        int rc = libusb_init(&s->ctx);
        if (rc != 0) {
            s->ctx = NULL;
            if (!s->ctx_failed_reported)
                usb_log("libusb cannot start (%s); no gamepad until it can (retrying every rescan)",
                        libusb_error_name(rc));
            s->ctx_failed_reported = true;
            return;
        }
    }
    if (s->root_fd < 0)
        s->root_fd = open(s->dev_dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    for (unsigned i = 0; i < s->node_count; i++)
        s->nodes[i].alive = false;
    if (s->root_fd >= 0)
        usb_list_dir(s, s->root_fd, s->dirent_buf, sizeof s->dirent_buf, usb_scan_bus, 0);
    /* nodes that disappeared: their pads are unplugged; forget them */
    for (unsigned i = 0; i < s->node_count; i++) {
        usb_node_t *n = &s->nodes[i];
        if (!n->alive) {
            for (unsigned k = 0; k < USB_MAX_PADS; k++)
                if (s->pads[k].phase != PAD_FREE && s->pads[k].bus == n->bus && s->pads[k].addr == n->addr)
                    usb_pad_start_close(&s->pads[k], true);
            continue;
        }
        s->nodes[kept++] = *n;
    }
    s->node_count = kept;
}

static int LIBUSB_CALL usb_hotplug(libusb_context *ctx, libusb_device *dev, libusb_hotplug_event event,
                                   void *user)
{
    usb_input_t *s = user;

    (void)ctx;
    (void)dev;
    (void)event;
    s->scan_pending = true;   /* the scan decides what changed */
    return 0;
}

static void usb_register_hotplug(usb_input_t *s)
{
    if (s->ctx == NULL || s->hotplug_registered || !libusb_has_capability(LIBUSB_CAP_HAS_HOTPLUG))
        return;
    if (libusb_hotplug_register_callback(s->ctx, LIBUSB_HOTPLUG_EVENT_DEVICE_ARRIVED |
                                                     LIBUSB_HOTPLUG_EVENT_DEVICE_LEFT,
                                         0, LIBUSB_HOTPLUG_MATCH_ANY, LIBUSB_HOTPLUG_MATCH_ANY,
                                         LIBUSB_HOTPLUG_MATCH_ANY, usb_hotplug, s, &s->hotplug) == 0)
        s->hotplug_registered = true;
}

static int usb_poll(psc_hal_input_t *in, uint64_t now_us, psc_hal_input_event_t *ev)
{
    usb_input_t *s = (usb_input_t *)in;
    struct timeval zero = { 0, 0 };

    s->now_us = now_us;
    if (s->scan_pending || (s->rescan_us != 0 && now_us >= s->next_scan_us)) {
        usb_scan(s);
        usb_register_hotplug(s);
        s->next_scan_us = now_us + s->rescan_us;
    }
    if (s->ctx != NULL)
        libusb_handle_events_timeout_completed(s->ctx, &zero, NULL);
    for (unsigned i = 0; i < USB_MAX_PADS; i++) {
        usb_pad_t *p = &s->pads[i];

        if (p->phase == PAD_RUNNING) {
            if (p->clear_halt) {
                p->clear_halt = false;
                libusb_clear_halt(p->handle, p->iface.ep_in);
                if (usb_pad_submit_all(p) != 0)
                    usb_pad_start_close(p, false);
            }
            psc_usb_pad_tick(&p->pad, &s->timing, now_us, &s->queue);
        }
        if (p->phase == PAD_CLOSING && !usb_pad_busy(p))
            usb_pad_finish(s, p);
    }
    return psc_hal_event_queue_pop(&s->queue, now_us, ev);
}

static int usb_get_device_name(psc_hal_input_t *in, uint8_t device, char *buf, size_t len)
{
    usb_input_t *s = (usb_input_t *)in;

    if (device >= USB_MAX_PADS || s->pads[device].phase == PAD_FREE)
        return -ENODEV;
    snprintf(buf, len, "gamepad %s", s->pads[device].name);
    return 0;
}

static void usb_close(psc_hal_input_t *in)
{
    usb_input_t *s = (usb_input_t *)in;
    struct timeval tick = { 0, 50000 };

    for (unsigned i = 0; i < USB_MAX_PADS; i++)
        usb_pad_start_close(&s->pads[i], false);
    for (int round = 0; s->ctx != NULL && round < USB_CLOSE_WAIT_ROUNDS; round++) {
        bool busy = false;
        for (unsigned i = 0; i < USB_MAX_PADS; i++)
            busy = busy || usb_pad_busy(&s->pads[i]);
        if (!busy)
            break;
        libusb_handle_events_timeout_completed(s->ctx, &tick, NULL);
    }
    for (unsigned i = 0; i < USB_MAX_PADS; i++) {
        usb_pad_t *p = &s->pads[i];
        if (p->phase != PAD_FREE)
            usb_pad_finish(s, p);
        /* a transfer libusb never handed back cannot be freed safely: leak it */
        if (!p->ctrl_busy)
            libusb_free_transfer(p->ctrl);
        for (unsigned k = 0; k < USB_XFERS_PER_PAD; k++)
            if (!p->xfer_busy[k])
                libusb_free_transfer(p->xfer[k]);
        if (!usb_pad_busy(p)) {
            free(p->ctrl_buf);
            for (unsigned k = 0; k < USB_XFERS_PER_PAD; k++)
                free(p->xfer_buf[k]);
        }
    }
    if (s->hotplug_registered)
        libusb_hotplug_deregister_callback(s->ctx, s->hotplug);
    if (s->ctx != NULL)
        libusb_exit(s->ctx);
    if (s->root_fd >= 0)
        close(s->root_fd);
    free(s);
}

static const psc_hal_input_ops_t usb_input_ops = {
    .poll = usb_poll,
    .get_device_name = usb_get_device_name,
    .close = usb_close,
};

/* "046d:c216,045e:02fd" into the match table. */
static int usb_parse_match(usb_input_t *s, const psc_hal_option_t *o, char *err, size_t errlen)
{
    const char *p = o->value != NULL ? o->value : "";

    while (*p) {
        unsigned vid = 0, pid = 0, digits = 0;

        for (; *p && *p != ':'; p++, digits++) {
            int d = (*p >= '0' && *p <= '9') ? *p - '0' : (*p >= 'a' && *p <= 'f') ? *p - 'a' + 10
                  : (*p >= 'A' && *p <= 'F') ? *p - 'A' + 10 : -1;
            if (d < 0 || digits >= 4)
                goto bad;
            vid = vid * 16u + (unsigned)d;
        }
        if (*p++ != ':' || digits == 0)
            goto bad;
        for (digits = 0; *p && *p != ','; p++, digits++) {
            int d = (*p >= '0' && *p <= '9') ? *p - '0' : (*p >= 'a' && *p <= 'f') ? *p - 'a' + 10
                  : (*p >= 'A' && *p <= 'F') ? *p - 'A' + 10 : -1;
            if (d < 0 || digits >= 4)
                goto bad;
            pid = pid * 16u + (unsigned)d;
        }
        if (digits == 0 || s->match_count == USB_MAX_MATCH)
            goto bad;
        s->match_vid[s->match_count] = (uint16_t)vid;
        s->match_pid[s->match_count++] = (uint16_t)pid;
        if (*p == ',')
            p++;
    }
    if (s->match_count > 0)
        return 0;
bad:
    psc_hal_error_set(err, errlen, "%s: usb input option 'match' must be VENDOR:PRODUCT in hex, like 046d:c216, "
                      "up to %u separated by commas; got '%s'", o->origin ? o->origin : "(built-in)",
                      (unsigned)USB_MAX_MATCH, o->value ? o->value : "");
    return -EINVAL;
}

static int usb_check_options(const psc_hal_options_t *opts, char *err, size_t errlen)
{
    for (size_t i = 0; opts->items != NULL && i < opts->count; i++) {
        const psc_hal_option_t *o = &opts->items[i];
        bool known = psc_usb_map_knows(o->key);

        for (unsigned k = 0; !known && usb_known_options[k] != NULL; k++)
            known = o->key != NULL && strcmp(o->key, usb_known_options[k]) == 0;
        if (!known) {
            psc_hal_error_set(err, errlen, "%s: input option '%s' is not known to the usb backend (it knows: "
                              "axis.yaw, axis.pitch, axis.zoom, button.N, hat, match, rescan_ms, dev_dir)",
                              o->origin ? o->origin : "(built-in)", o->key ? o->key : "");
            return -EINVAL;
        }
    }
    return 0;
}

static int usb_input_open(const psc_hal_input_config_t *cfg, psc_hal_input_t **out, char *err, size_t errlen)
{
    const psc_hal_option_t *o;
    usb_input_t *s;
    uint32_t rescan_ms = 0;
    int rc;

    *out = NULL;
    rc = usb_check_options(&cfg->options, err, errlen);
    if (rc != 0)
        return rc;
    s = calloc(1, sizeof *s);
    if (s == NULL) {
        psc_hal_error_set(err, errlen, "usb input: out of memory");
        return -ENOMEM;
    }
    s->base.ops = &usb_input_ops;
    s->base.backend = "usb";
    s->clock = cfg->clock;
    s->root_fd = -1;
    psc_hal_event_queue_init(&s->queue, s->queue_store, USB_QUEUE_LEN);
    s->timing = (psc_hal_button_timing_t){ 0, (cfg->long_press_ms ? cfg->long_press_ms : 800u) * 1000u };
    for (unsigned i = 0; i < USB_MAX_PADS; i++) {
        usb_pad_t *p = &s->pads[i];
        p->owner = s;
        p->slot = (uint8_t)i;
        p->fd = -1;
        p->ctrl = libusb_alloc_transfer(0);
        p->ctrl_buf = calloc(1, LIBUSB_CONTROL_SETUP_SIZE + PSC_HID_MAX_DESCRIPTOR);
        for (unsigned k = 0; k < USB_XFERS_PER_PAD; k++) {
            p->xfer[k] = libusb_alloc_transfer(0);
            p->xfer_buf[k] = calloc(1, USB_XFER_BYTES);
            if (p->xfer[k] == NULL || p->xfer_buf[k] == NULL)
                rc = -ENOMEM;
        }
        if (p->ctrl == NULL || p->ctrl_buf == NULL)
            rc = -ENOMEM;
    }
    if (rc != 0) {
        psc_hal_error_set(err, errlen, "usb input: out of memory for transfers");
        usb_close(&s->base);
        return rc;
    }
    psc_usb_map_default(&s->map);
    rc = psc_usb_map_parse(&s->map, &cfg->options, err, errlen);
    if (rc == 0 && (o = psc_hal_options_find(&cfg->options, "match")) != NULL)
        rc = usb_parse_match(s, o, err, errlen);
    if (rc == 0)
        rc = psc_hal_options_get_u32(&cfg->options, "rescan_ms", 0, 60000, USB_DEFAULT_RESCAN_MS, &rescan_ms,
                                     err, errlen);
    if (rc == 0 && rescan_ms != 0 && rescan_ms < 50) {
        psc_hal_error_set(err, errlen, "%s: usb input option 'rescan_ms' must be 0 (off) or 50 to 60000",
                          psc_hal_options_find(&cfg->options, "rescan_ms")->origin);
        rc = -EINVAL;
    }
    o = psc_hal_options_find(&cfg->options, "dev_dir");
    snprintf(s->dev_dir, sizeof s->dev_dir, "%s", o != NULL && o->value != NULL ? o->value : "/dev/bus/usb");
    if (rc != 0) {
        usb_close(&s->base);
        return rc;
    }
    s->rescan_us = rescan_ms * 1000u;
    s->scan_pending = true;   /* the first poll scans */
    *out = &s->base;
    return 0;
}

const psc_hal_backend_t psc_hal_usb_backend = {
    .name = "usb",
    .description = "USB joysticks and gamepads through libusb-1.0: HID report descriptors, hotplug",
    .input_open = usb_input_open,
};
