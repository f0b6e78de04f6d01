/* SPDX-License-Identifier: MIT */
/*
 * test_input.c - the input backends' logic that needs no hardware:
 *
 *  - button debounce and long press (hal/psc_hal_button.h) at explicit
 *    times: bounces swallowed, edges at last change + debounce, a press read
 *    late in one batch is not lost, one LONG per press;
 *  - the time-ordered event queue (hal/psc_hal_event_queue.h);
 *  - finding a gamepad interface in raw USB descriptors
 *    (hal/usb/psc_usb_desc.h), on a real joystick's descriptors, boot
 *    keyboards and composites, every truncation and random mutations;
 *  - the USB gamepad's report path (hal/usb/psc_usb_pad.h) fed with made-up
 *    interrupt transfers: reports, zero-length packets, stalls, errors,
 *    unplug, cancellation, the board's axis/button/hat map and its errors;
 *  - the usb and gpio backends with no device present (they open, poll
 *    nothing, name themselves, reject bad options with file:line);
 *  - several backends as one input ("sim,usb,gpio"): same events as the
 *    backend alone, slots renumbered, options routed;
 *  - the firmware's stick dead zone and response curve, and the board keys
 *    that set them and the input list.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "board_config.h"
#include "controls.h"
#include "psc_hal_button.h"
#include "psc_hal_clock.h"
#include "psc_hal_event_queue.h"
#include "psc_hal_input.h"
#include "psc_hal_input_multi.h"
#include "tsup_files.h"
#include "usb/psc_hid_parse.h"
#include "usb/psc_usb_desc.h"
#include "usb/psc_usb_pad.h"

#define BYTES(...) (const uint8_t[]){ __VA_ARGS__ }, sizeof((const uint8_t[]){ __VA_ARGS__ })
#define MS 1000u

/* ---- button: debounce and long press ----------------------------------------- */

typedef struct {
    psc_hal_button_edge_t e[16];
    unsigned n;
} edges_t;

static void advance(psc_hal_button_t *b, const psc_hal_button_timing_t *t, uint64_t at, edges_t *out)
{
    psc_hal_button_edge_t e[2];
    unsigned n = psc_hal_button_advance(b, t, at, e);

    for (unsigned i = 0; i < n; i++) {
        assert_true(out->n < 16);
        if (out->n > 0)
            assert_true(e[i].time_us >= out->e[out->n - 1].time_us);
        out->e[out->n++] = e[i];
    }
}

/* Feed a raw change the way backends do: advance to its time, then set. */
static void feed(psc_hal_button_t *b, const psc_hal_button_timing_t *t, bool level, uint64_t at, edges_t *out)
{
    advance(b, t, at, out);
    psc_hal_button_set(b, level, at);
}

static void expect_edge(const edges_t *ed, unsigned i, psc_hal_input_type_t type, uint64_t at)
{
    assert_true(i < ed->n);
    assert_int_equal(ed->e[i].type, type);
    assert_int_equal(ed->e[i].time_us, at);
}

static void test_button_no_debounce(void **state)
{
    psc_hal_button_timing_t t = { 0, 800 * MS };
    psc_hal_button_t b;
    edges_t ed = { .n = 0 };
    (void)state;

    psc_hal_button_init(&b, 0);
    feed(&b, &t, true, 100, &ed);
    advance(&b, &t, 100, &ed);
    expect_edge(&ed, 0, PSC_HAL_INPUT_BUTTON_DOWN, 100);
    advance(&b, &t, 100 + 800 * MS - 1, &ed);
    assert_int_equal(ed.n, 1);
    advance(&b, &t, 100 + 800 * MS, &ed);
    expect_edge(&ed, 1, PSC_HAL_INPUT_BUTTON_LONG, 100 + 800 * MS);
    advance(&b, &t, 5000 * MS, &ed);   /* one LONG per press */
    assert_int_equal(ed.n, 2);
    feed(&b, &t, false, 5000 * MS, &ed);
    advance(&b, &t, 5000 * MS, &ed);
    expect_edge(&ed, 2, PSC_HAL_INPUT_BUTTON_UP, 5000 * MS);
    /* a short press: no LONG */
    feed(&b, &t, true, 6000 * MS, &ed);
    feed(&b, &t, false, 6500 * MS, &ed);
    advance(&b, &t, 9000 * MS, &ed);
    assert_int_equal(ed.n, 5);
    expect_edge(&ed, 3, PSC_HAL_INPUT_BUTTON_DOWN, 6000 * MS);
    expect_edge(&ed, 4, PSC_HAL_INPUT_BUTTON_UP, 6500 * MS);
    /* the same level again changes nothing */
    feed(&b, &t, false, 9100 * MS, &ed);
    advance(&b, &t, 9200 * MS, &ed);
    assert_int_equal(ed.n, 5);
}

static void test_button_debounce(void **state)
{
    psc_hal_button_timing_t t = { 10 * MS, 800 * MS };
    psc_hal_button_t b;
    edges_t ed = { .n = 0 };
    (void)state;

    psc_hal_button_init(&b, 0);
    /* a bouncing press: 1 at 1 ms, 0 at 3 ms, 1 at 4 ms, then steady */
    feed(&b, &t, true, 1 * MS, &ed);
    feed(&b, &t, false, 3 * MS, &ed);
    feed(&b, &t, true, 4 * MS, &ed);
    advance(&b, &t, 14 * MS - 1, &ed);
    assert_int_equal(ed.n, 0);
    advance(&b, &t, 14 * MS, &ed);
    expect_edge(&ed, 0, PSC_HAL_INPUT_BUTTON_DOWN, 14 * MS);
    /* a 5 ms blip while held is swallowed and does not restart the long press */
    feed(&b, &t, false, 300 * MS, &ed);
    feed(&b, &t, true, 305 * MS, &ed);
    advance(&b, &t, 814 * MS - 1, &ed);
    assert_int_equal(ed.n, 1);
    advance(&b, &t, 814 * MS, &ed);
    expect_edge(&ed, 1, PSC_HAL_INPUT_BUTTON_LONG, 814 * MS);
    /* a bouncing release */
    feed(&b, &t, false, 900 * MS, &ed);
    feed(&b, &t, true, 902 * MS, &ed);
    feed(&b, &t, false, 903 * MS, &ed);
    advance(&b, &t, 2000 * MS, &ed);
    expect_edge(&ed, 2, PSC_HAL_INPUT_BUTTON_UP, 913 * MS);
    assert_int_equal(ed.n, 3);
    /* a blip shorter than the debounce time while released: nothing */
    feed(&b, &t, true, 3000 * MS, &ed);
    feed(&b, &t, false, 3009 * MS, &ed);
    advance(&b, &t, 4000 * MS, &ed);
    assert_int_equal(ed.n, 3);
}

/* A press and its release both read in one late batch: the press is kept. */
static void test_button_late_batch(void **state)
{
    psc_hal_button_timing_t t = { 10 * MS, 0 };
    psc_hal_button_t b;
    edges_t ed = { .n = 0 };
    (void)state;

    psc_hal_button_init(&b, 0);
    feed(&b, &t, true, 0, &ed);
    feed(&b, &t, false, 50 * MS, &ed);
    advance(&b, &t, 100 * MS, &ed);
    assert_int_equal(ed.n, 2);
    expect_edge(&ed, 0, PSC_HAL_INPUT_BUTTON_DOWN, 10 * MS);
    expect_edge(&ed, 1, PSC_HAL_INPUT_BUTTON_UP, 60 * MS);
    /* long_press_us = 0: never LONG */
    feed(&b, &t, true, 200 * MS, &ed);
    advance(&b, &t, 100000 * MS, &ed);
    assert_int_equal(ed.n, 3);
}

/* ---- event queue ---------------------------------------------------------------------- */

static int push_ev(psc_hal_event_queue_t *q, psc_hal_input_type_t type, uint8_t dev, uint16_t code, int32_t value,
                   uint64_t t)
{
    psc_hal_input_event_t ev = { .type = type, .device = dev, .code = code, .value = value, .time_us = t };
    return psc_hal_event_queue_push(q, &ev);
}

static void test_event_queue(void **state)
{
    psc_hal_input_event_t store[4], ev;
    psc_hal_event_queue_t q;
    (void)state;

    psc_hal_event_queue_init(&q, store, 4);
    assert_null(psc_hal_event_queue_peek(&q));
    assert_int_equal(push_ev(&q, PSC_HAL_INPUT_BUTTON_DOWN, 0, 1, 1, 30), 0);
    assert_int_equal(push_ev(&q, PSC_HAL_INPUT_BUTTON_DOWN, 0, 2, 1, 10), 0);
    assert_int_equal(push_ev(&q, PSC_HAL_INPUT_BUTTON_DOWN, 0, 3, 1, 30), 0);
    assert_int_equal(push_ev(&q, PSC_HAL_INPUT_AXIS, 1, 0, 100, 20), 0);
    /* full: refused and counted; but a newer position of a queued axis replaces it */
    assert_int_equal(push_ev(&q, PSC_HAL_INPUT_BUTTON_UP, 0, 1, 0, 40), -ENOSPC);
    assert_int_equal(q.dropped, 1);
    assert_int_equal(push_ev(&q, PSC_HAL_INPUT_AXIS, 1, 0, 200, 35), 0);
    assert_int_equal(q.count, 4);
    assert_int_equal(psc_hal_event_queue_peek(&q)->time_us, 10);
    /* nothing due before 10; then oldest first, equal times in push order */
    assert_int_equal(psc_hal_event_queue_pop(&q, 9, &ev), 0);
    assert_int_equal(psc_hal_event_queue_pop(&q, 100, &ev), 1);
    assert_int_equal(ev.code, 2);
    assert_int_equal(psc_hal_event_queue_pop(&q, 100, &ev), 1);
    assert_int_equal(ev.code, 1);
    assert_int_equal(psc_hal_event_queue_pop(&q, 100, &ev), 1);
    assert_int_equal(ev.code, 3);
    assert_int_equal(psc_hal_event_queue_pop(&q, 34, &ev), 0);
    assert_int_equal(psc_hal_event_queue_pop(&q, 35, &ev), 1);
    assert_int_equal(ev.type, PSC_HAL_INPUT_AXIS);
    assert_int_equal(ev.value, 200);
    assert_int_equal(psc_hal_event_queue_pop(&q, 1000, &ev), 0);
}

/* ---- USB descriptors -------------------------------------------------------------------- */

/* "Generic USB Joystick" by DragonRise (0079:0006), as USBlyzer/USB Device
 * Tree Viewer listed it in the PJRC forum thread "USB Joystick rumble/force
 * feedback on Teensy 3.1": device descriptor, then the 41-byte configuration
 * with one HID interface (subclass 0, protocol 0), a HID descriptor naming a
 * 101-byte report descriptor, interrupt IN 0x81 (8 bytes, 10 ms) and
 * interrupt OUT 0x01. */
static const uint8_t dragonrise[] = {
    0x12, 0x01, 0x00, 0x01, 0x00, 0x00, 0x00, 0x08, 0x79, 0x00, 0x06, 0x00, 0x07, 0x01, 0x01, 0x02, 0x00, 0x01,
    0x09, 0x02, 0x29, 0x00, 0x01, 0x01, 0x00, 0x80, 0xFA,
    0x09, 0x04, 0x00, 0x00, 0x02, 0x03, 0x00, 0x00, 0x00,
    0x09, 0x21, 0x10, 0x01, 0x21, 0x01, 0x22, 0x65, 0x00,
    0x07, 0x05, 0x81, 0x03, 0x08, 0x00, 0x0A,
    0x07, 0x05, 0x01, 0x03, 0x08, 0x00, 0x0A,
};

/* A composite: interface 0 a boot keyboard, interface 1 a HID gamepad whose
 * HID descriptor lists a physical descriptor before the report one. */
static const uint8_t composite[] = {
    0x12, 0x01, 0x00, 0x02, 0x00, 0x00, 0x00, 0x40, 0x6D, 0x04, 0x16, 0xC2, 0x00, 0x01, 0x01, 0x02, 0x00, 0x01,
    0x09, 0x02, 0x3E, 0x00, 0x02, 0x01, 0x00, 0x80, 0x32,
    0x09, 0x04, 0x00, 0x00, 0x01, 0x03, 0x01, 0x01, 0x00,
    0x09, 0x21, 0x11, 0x01, 0x00, 0x01, 0x22, 0x3F, 0x00,
    0x07, 0x05, 0x81, 0x03, 0x08, 0x00, 0x0A,
    0x09, 0x04, 0x01, 0x00, 0x01, 0x03, 0x00, 0x00, 0x00,
    0x0C, 0x21, 0x11, 0x01, 0x00, 0x02, 0x23, 0x10, 0x00, 0x22, 0x7A, 0x00,
    0x07, 0x05, 0x82, 0x03, 0x40, 0x00, 0x04,
};

static void test_usb_desc_real(void **state)
{
    psc_usb_hid_iface_t i;
    char why[96];
    (void)state;

    assert_int_equal(sizeof dragonrise, 18 + 41);
    assert_int_equal(psc_usb_find_hid_interface(dragonrise, sizeof dragonrise, &i, why, sizeof why), 0);
    assert_int_equal(i.vendor_id, 0x0079);
    assert_int_equal(i.product_id, 0x0006);
    assert_int_equal(i.interface_number, 0);
    assert_int_equal(i.ep_in, 0x81);
    assert_int_equal(i.ep_in_max_packet, 8);
    assert_int_equal(i.ep_in_interval, 10);
    assert_int_equal(i.report_desc_len, 101);

    assert_int_equal(sizeof composite, 18 + 0x3E);
    assert_int_equal(psc_usb_find_hid_interface(composite, sizeof composite, &i, why, sizeof why), 0);
    assert_int_equal(i.interface_number, 1);   /* the boot keyboard is skipped */
    assert_int_equal(i.ep_in, 0x82);
    assert_int_equal(i.ep_in_max_packet, 64);
    assert_int_equal(i.report_desc_len, 0x7A);

    /* only the boot keyboard */
    assert_int_equal(psc_usb_find_hid_interface(composite, 18 + 34, &i, why, sizeof why), -EINVAL);
    uint8_t kb[18 + 34];
    memcpy(kb, composite, sizeof kb);
    kb[20] = 34;
    kb[22] = 1;
    assert_int_equal(psc_usb_find_hid_interface(kb, sizeof kb, &i, why, sizeof why), -ENODEV);
    assert_string_equal(why, "only a boot keyboard or mouse");
    /* no HID at all: the same joystick with a vendor-specific class */
    uint8_t vendor[sizeof dragonrise];
    memcpy(vendor, dragonrise, sizeof vendor);
    vendor[18 + 9 + 5] = 0xFF;
    assert_int_equal(psc_usb_find_hid_interface(vendor, sizeof vendor, &i, why, sizeof why), -ENODEV);
    assert_string_equal(why, "no HID interface");
    /* a HID interface without an interrupt IN endpoint */
    memcpy(vendor, dragonrise, sizeof vendor);
    vendor[18 + 9 + 9 + 9 + 2] = 0x02;   /* 0x81 -> OUT 0x02 */
    assert_int_equal(psc_usb_find_hid_interface(vendor, sizeof vendor, &i, why, sizeof why), -ENODEV);
}

static uint64_t rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static int find_copy(const uint8_t *d, size_t len, psc_usb_hid_iface_t *i)
{
    uint8_t *copy = malloc(len ? len : 1);
    char why[96];
    int rc;

    assert_non_null(copy);
    memcpy(copy, d, len);
    rc = psc_usb_find_hid_interface(copy, len, i, why, sizeof why);
    free(copy);
    if (rc == 0) {
        assert_true(i->ep_in & 0x80);
        assert_true(i->ep_in_max_packet >= 1 && i->ep_in_max_packet <= 2047);
        assert_true(i->report_desc_len > 0);
    } else {
        assert_true(rc == -EINVAL || rc == -ENODEV);
        assert_true(why[0] != '\0');
    }
    return rc;
}

static void test_usb_desc_truncation_and_fuzz(void **state)
{
    psc_usb_hid_iface_t i;
    uint64_t rng = 77;
    unsigned ok = 0, bad = 0;
    (void)state;

    for (size_t n = 0; n < sizeof dragonrise; n++)
        assert_int_not_equal(find_copy(dragonrise, n, &i), 0);
    for (size_t n = 0; n < sizeof composite; n++)
        assert_int_not_equal(find_copy(composite, n, &i), 0);
    for (unsigned round = 0; round < 20000; round++) {
        uint8_t d[sizeof composite + 8];
        size_t len = sizeof composite;
        memcpy(d, round & 1 ? composite : dragonrise, round & 1 ? sizeof composite : sizeof dragonrise);
        if (!(round & 1))
            len = sizeof dragonrise;
        for (unsigned c = 1 + (unsigned)(rng_next(&rng) % 3); c > 0; c--)
            d[rng_next(&rng) % len] = (uint8_t)rng_next(&rng);
        if (find_copy(d, len, &i) == 0)
            ok++;
        else
            bad++;
    }
    assert_true(ok > 100 && bad > 100);
}

/* ---- USB gamepad report path, fed made-up transfers ----------------------------------- */

/* The joystick of test_hid.c's gadget_hid.rst layout: X Y Z signed bytes,
 * hat nibble (4 = neutral), buttons 1-4 in the high nibble. */
static const uint8_t joystick_gadget[] = {
    0x05, 0x01, 0x09, 0x04, 0xA1, 0x01, 0x15, 0x81, 0x25, 0x7F, 0x75, 0x08, 0x95, 0x03, 0x09, 0x30, 0x09, 0x31,
    0x09, 0x32, 0x81, 0x02, 0x15, 0x00, 0x25, 0x03, 0x35, 0x00, 0x46, 0x0E, 0x01, 0x65, 0x14, 0x75, 0x04, 0x95,
    0x01, 0x09, 0x39, 0x81, 0x42, 0x65, 0x00, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x04, 0x05, 0x09, 0x19,
    0x01, 0x29, 0x04, 0x81, 0x02, 0xC0,
};

typedef struct {
    psc_usb_pad_t pad;
    psc_usb_map_t map;
    psc_hal_button_timing_t timing;
    psc_hal_input_event_t store[64];
    psc_hal_event_queue_t queue;
} pad_rig_t;

static void rig_init(pad_rig_t *r, const psc_hal_option_t *opts, size_t n)
{
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    char msg[256];

    assert_int_equal(psc_hid_parse(joystick_gadget, sizeof joystick_gadget, &g, &err), 0);
    psc_usb_map_default(&r->map);
    assert_int_equal(psc_usb_map_parse(&r->map, &(psc_hal_options_t){ opts, n }, msg, sizeof msg), 0);
    r->timing = (psc_hal_button_timing_t){ 0, 800 * MS };
    psc_hal_event_queue_init(&r->queue, r->store, 64);
    psc_usb_pad_init(&r->pad, &g, &r->map, 2, 0);
}

static psc_usb_next_t rig_feed(pad_rig_t *r, psc_usb_xfer_status_t st, const uint8_t *d, size_t len, uint64_t t)
{
    return psc_usb_pad_transfer_done(&r->pad, &r->map, &r->timing, st, d, len, t, &r->queue);
}

static void expect_event(pad_rig_t *r, psc_hal_input_type_t type, uint16_t code, int32_t value, uint64_t t)
{
    psc_hal_input_event_t ev;

    if (psc_hal_event_queue_pop(&r->queue, UINT64_MAX, &ev) != 1)
        fail_msg("expected event type %d code %u, the queue is empty", type, code);
    if (ev.type != type || ev.code != code || ev.value != value || ev.time_us != t || ev.device != 2)
        fail_msg("expected type %d code %u value %d at %llu, got type %d code %u value %d at %llu dev %u", type,
                 code, value, (unsigned long long)t, ev.type, ev.code, ev.value, (unsigned long long)ev.time_us,
                 ev.device);
}

static void expect_no_event(pad_rig_t *r)
{
    assert_null(psc_hal_event_queue_peek(&r->queue));
}

static void test_usb_pad_feed(void **state)
{
    static const psc_hal_option_t opts[] = {
        { "axis.yaw", "x", "b.conf:1" }, { "axis.pitch", "-y", "b.conf:2" }, { "axis.zoom", "-z", "b.conf:3" },
    };
    pad_rig_t r;
    (void)state;

    rig_init(&r, opts, 3);
    /* stick right and forward (HID Y negative), button 1 (home by default), hat neutral */
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_COMPLETED, BYTES(127, 0x81, 0, 0x14), 1000), PSC_USB_NEXT_RESUBMIT);
    expect_event(&r, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_YAW, 32767, 1000);
    expect_event(&r, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_PITCH, 32767, 1000);   /* -(-32768), kept full */
    expect_event(&r, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_HOME, 1, 1000);
    expect_no_event(&r);
    /* a zero-length packet after it: counted, nothing else */
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_COMPLETED, NULL, 0, 2000), PSC_USB_NEXT_RESUBMIT);
    assert_int_equal(r.pad.empty_reports, 1);
    expect_no_event(&r);
    /* the same report again: no change, no event */
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_COMPLETED, BYTES(127, 0x81, 0, 0x14), 3000), PSC_USB_NEXT_RESUBMIT);
    expect_no_event(&r);
    /* held 800 ms: a long press, once */
    psc_usb_pad_tick(&r.pad, &r.timing, 800 * MS + 999, &r.queue);
    expect_no_event(&r);
    psc_usb_pad_tick(&r.pad, &r.timing, 801 * MS, &r.queue);
    expect_event(&r, PSC_HAL_INPUT_BUTTON_LONG, PSC_HAL_ACTION_HOME, 1, 801 * MS);
    psc_usb_pad_tick(&r.pad, &r.timing, 5000 * MS, &r.queue);
    expect_no_event(&r);
    /* released; hat up (0) looks up; Z half back zooms in (inverted) */
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_COMPLETED, BYTES(0, 0, 0xC1, 0x00), 6000 * MS), PSC_USB_NEXT_RESUBMIT);
    expect_event(&r, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_YAW, 0, 6000 * MS);
    expect_event(&r, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_PITCH, 0, 6000 * MS);
    expect_event(&r, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_ZOOM, 16255, 6000 * MS);   /* -(-63/127 of full): 16255.5 */
    expect_event(&r, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_LOOK_UP, 1, 6000 * MS);
    expect_event(&r, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_HOME, 0, 6000 * MS);
    expect_no_event(&r);
    /* hat down-right is impossible with 4 positions; hat 1 = right */
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_COMPLETED, BYTES(0, 0, 0xC1, 0x01), 6100 * MS), PSC_USB_NEXT_RESUBMIT);
    expect_event(&r, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_PAN_RIGHT, 1, 6100 * MS);
    expect_event(&r, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_LOOK_UP, 0, 6100 * MS);
    expect_no_event(&r);
    /* a report too short is counted and changes nothing */
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_COMPLETED, BYTES(9, 9), 6200 * MS), PSC_USB_NEXT_RESUBMIT);
    assert_int_equal(r.pad.bad_reports, 1);
    expect_no_event(&r);
    assert_int_equal(r.pad.reports, 4);
}

static void test_usb_pad_transfer_status(void **state)
{
    pad_rig_t r;
    (void)state;

    rig_init(&r, NULL, 0);
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_TIMED_OUT, NULL, 0, 1), PSC_USB_NEXT_RESUBMIT);
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_STALL, NULL, 0, 2), PSC_USB_NEXT_CLEAR_HALT);
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_OVERFLOW, NULL, 0, 3), PSC_USB_NEXT_RESUBMIT);
    assert_int_equal(r.pad.bad_reports, 1);
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_CANCELLED, NULL, 0, 4), PSC_USB_NEXT_IDLE);
    /* a good transfer resets the error run */
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_COMPLETED, BYTES(0, 0, 0, 4), 5), PSC_USB_NEXT_RESUBMIT);
    for (unsigned i = 1; i < PSC_USB_PAD_MAX_ERRORS; i++)
        assert_int_equal(rig_feed(&r, PSC_USB_XFER_ERROR, NULL, 0, 6), PSC_USB_NEXT_RESUBMIT);
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_ERROR, NULL, 0, 7), PSC_USB_NEXT_GONE);
    rig_init(&r, NULL, 0);
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_NO_DEVICE, NULL, 0, 1), PSC_USB_NEXT_GONE);
}

static void test_usb_pad_map(void **state)
{
    static const psc_hal_option_t two_buttons[] = {
        { "button.1", "next_scene", "b:1" }, { "button.3", "next_scene", "b:2" }, { "hat", "none", "b:3" },
    };
    pad_rig_t r;
    (void)state;

    /* default map: yaw x, pitch -y, zoom -rz (absent on this pad), buttons 1 2 3 5 6, hat pans */
    rig_init(&r, NULL, 0);
    assert_int_equal(r.pad.axis_index[PSC_HAL_AXIS_YAW], 0);
    assert_int_equal(r.pad.axis_index[PSC_HAL_AXIS_PITCH], 1);
    assert_int_equal(r.pad.axis_index[PSC_HAL_AXIS_ZOOM], -1);
    assert_int_equal(r.map.button_action[1], PSC_HAL_ACTION_NEXT_SCENE);
    assert_int_equal(r.map.button_action[5], PSC_HAL_ACTION_ZOOM_IN);
    /* two buttons on one action: held while either is; the hat does nothing */
    rig_init(&r, two_buttons, 3);
    assert_int_equal(r.map.button_action[1], PSC_HAL_ACTION_NONE);   /* any button line drops the defaults */
    assert_int_equal(r.pad.axis_index[PSC_HAL_AXIS_YAW], 0);          /* axis defaults kept */
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_COMPLETED, BYTES(0, 0, 0, 0x10), 10), PSC_USB_NEXT_RESUBMIT);
    expect_event(&r, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_NEXT_SCENE, 1, 10);
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_COMPLETED, BYTES(0, 0, 0, 0x40), 20), PSC_USB_NEXT_RESUBMIT);
    expect_no_event(&r);   /* 1 released, 3 pressed: still held */
    assert_int_equal(rig_feed(&r, PSC_USB_XFER_COMPLETED, BYTES(0, 0, 0, 0x04), 30), PSC_USB_NEXT_RESUBMIT);
    expect_event(&r, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_NEXT_SCENE, 0, 30);
    assert_true(psc_usb_map_knows("axis.yaw") && psc_usb_map_knows("button.7") && psc_usb_map_knows("hat"));
    assert_false(psc_usb_map_knows("match") || psc_usb_map_knows("axisyaw"));
}

static void expect_map_error(const char *key, const char *value, const char *words)
{
    psc_usb_map_t map;
    psc_hal_option_t o = { key, value, "boards/k/board.conf:7" };
    char err[300] = "";

    psc_usb_map_default(&map);
    assert_int_equal(psc_usb_map_parse(&map, &(psc_hal_options_t){ &o, 1 }, err, sizeof err), -EINVAL);
    if (strncmp(err, "boards/k/board.conf:7: ", 23) != 0 || strstr(err, words) == NULL)
        fail_msg("%s = %s: expected '%s' in '%s'", key, value, words, err);
}

static void test_usb_pad_map_errors(void **state)
{
    (void)state;
    expect_map_error("axis.roll", "x", "no logical axis 'roll'");
    expect_map_error("axis.yaw", "q", "must be a HID axis");
    expect_map_error("axis.yaw", "--x", "must be a HID axis");
    expect_map_error("button.0", "home", "1 to 32");
    expect_map_error("button.33", "home", "1 to 32");
    expect_map_error("button.x", "home", "1 to 32");
    expect_map_error("button.2", "fly", "must be an action");
    expect_map_error("hat", "up", "pan or none");
}

/* ---- backends with nothing plugged in --------------------------------------------------- */

/* A clock the tests move by hand. */
typedef struct {
    psc_hal_clock_t base;
    uint64_t now;
} test_clock_t;

static uint64_t test_clock_now(psc_hal_clock_t *c)
{
    return ((test_clock_t *)c)->now;
}

static int test_clock_sleep(psc_hal_clock_t *c, uint64_t t)
{
    test_clock_t *tc = (test_clock_t *)c;
    if (t > tc->now)
        tc->now = t;
    return 0;
}

static void test_clock_close(psc_hal_clock_t *c)
{
    (void)c;
}

static const psc_hal_clock_ops_t test_clock_ops = { test_clock_now, test_clock_sleep, test_clock_close };

static void empty_dir(char *path, size_t n, const char *name)
{
    tsup_tmp_path(path, n, "input", name);
    mkdir(path, 0755);
}

static int open_input(const char *backend, const psc_hal_option_t *opts, size_t n, test_clock_t *clk,
                      psc_hal_input_t **in, char *err, size_t errlen)
{
    psc_hal_input_config_t cfg = { .clock = &clk->base, .long_press_ms = 800, .options = { opts, n } };

    clk->base.ops = &test_clock_ops;
    clk->base.backend = "test";
    return psc_hal_input_open(backend, &cfg, in, err, errlen);
}

static void test_usb_backend_absent(void **state)
{
    char dir[256], err[512], name[64];
    test_clock_t clk = { .now = 0 };
    psc_hal_input_t *in;
    psc_hal_input_event_t ev;
    (void)state;

    empty_dir(dir, sizeof dir, "usb");
    psc_hal_option_t opts[] = { { "dev_dir", dir, "t:1" }, { "rescan_ms", "50", "t:2" },
                                { "match", "046d:c216,045E:02FD", "t:3" }, { "axis.zoom", "-ry", "t:4" } };
    assert_int_equal(open_input("usb", opts, 4, &clk, &in, err, sizeof err), 0);
    for (unsigned i = 0; i < 5; i++, clk.now += 60 * MS)
        assert_int_equal(psc_hal_input_poll(in, clk.now, &ev), 0);
    assert_int_equal(psc_hal_input_get_device_name(in, 0, name, sizeof name), -ENODEV);
    psc_hal_input_close(in);

    psc_hal_option_t bad[] = { { "rescan", "5", "boards/x/board.conf:9" } };
    assert_int_not_equal(open_input("usb", bad, 1, &clk, &in, err, sizeof err), 0);
    assert_null(in);
    assert_non_null(strstr(err, "boards/x/board.conf:9: input option 'rescan' is not known to the usb backend"));
    psc_hal_option_t bad_match[] = { { "match", "046d-c216", "boards/x/board.conf:3" } };
    assert_int_equal(open_input("usb", bad_match, 1, &clk, &in, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "boards/x/board.conf:3: usb input option 'match'"));
    psc_hal_option_t bad_rescan[] = { { "rescan_ms", "10", "boards/x/board.conf:4" } };
    assert_int_equal(open_input("usb", bad_rescan, 1, &clk, &in, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "boards/x/board.conf:4:"));
}

static void test_gpio_backend_absent(void **state)
{
    char dir[256], err[512], name[96];
    test_clock_t clk = { .now = 0 };
    psc_hal_input_t *in;
    psc_hal_input_event_t ev;
    (void)state;

    empty_dir(dir, sizeof dir, "gpio");
    psc_hal_option_t opts[] = { { "line.home", "BTN_HOME", "t:1" }, { "line.next_scene", "BTN_NEXT", "t:2" },
                                { "dev_dir", dir, "t:3" }, { "debounce_ms", "20", "t:4" },
                                { "bias", "pull-down", "t:5" }, { "active_low", "no", "t:6" },
                                { "rescan_ms", "100", "t:7" } };
    /* the lines are nowhere: not an error (a kiosk runs without its buttons) */
    assert_int_equal(open_input("gpio", opts, 7, &clk, &in, err, sizeof err), 0);
    for (unsigned i = 0; i < 5; i++, clk.now += 150 * MS)
        assert_int_equal(psc_hal_input_poll(in, clk.now, &ev), 0);
    assert_int_equal(psc_hal_input_get_device_name(in, 0, name, sizeof name), 0);
    assert_string_equal(name, "GPIO buttons");
    psc_hal_input_close(in);

    static const struct {
        const char *key, *value, *words;
    } bad[] = {
        { "line.fly", "X", "'fly' is not an action" },
        { "bias", "up", "must be pull-up, pull-down, disabled or as-is" },
        { "active_low", "maybe", "must be yes or no" },
        { "debounce_ms", "5000", "from 0 to 1000" },
        { "chip", "gpiochip0", "not known to the gpio backend" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        psc_hal_option_t o[] = { { "line.home", "BTN_HOME", "boards/g/board.conf:1" },
                                 { bad[i].key, bad[i].value, "boards/g/board.conf:2" } };
        assert_int_equal(open_input("gpio", o, 2, &clk, &in, err, sizeof err), -EINVAL);
        if (strstr(err, "boards/g/board.conf:2:") == NULL || strstr(err, bad[i].words) == NULL)
            fail_msg("%s = %s: got '%s'", bad[i].key, bad[i].value, err);
    }
    psc_hal_option_t twice[] = { { "line.home", "A", "b:1" }, { "line.home", "B", "b:2" } };
    assert_int_equal(open_input("gpio", twice, 2, &clk, &in, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "that action already has a line"));
    psc_hal_option_t shared[] = { { "line.home", "A", "b:1" }, { "line.back", "A", "b:2" } };
    assert_int_equal(open_input("gpio", shared, 2, &clk, &in, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "that line already serves another action"));
    assert_int_equal(open_input("gpio", NULL, 0, &clk, &in, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "no buttons"));
}

/* ---- several backends as one input ------------------------------------------------------ */

static const char tour_text[] =
    "wait 100ms\n"
    "press home\n"
    "hold 200ms axis yaw 0.5\n"
    "plug 1\n"
    "device 1\n"
    "hold 300ms axis pitch -1.0\n"
    "unplug 1\n"
    "plug 1\n"
    "press next_scene\n"
    "end\n";

static size_t collect(psc_hal_input_t *in, test_clock_t *clk, psc_hal_input_event_t *out, size_t max)
{
    size_t n = 0;

    for (clk->now = 0; clk->now <= 2000 * MS; clk->now += 10 * MS) {
        psc_hal_input_event_t ev;
        while (n < max && psc_hal_input_poll(in, clk->now, &ev) == 1)
            out[n++] = ev;
    }
    return n;
}

static void test_multi_input(void **state)
{
    char tour[256], dir[256], err[512], name[64];
    psc_hal_input_event_t alone[64], merged[64];
    test_clock_t clk = { .now = 0 };
    psc_hal_input_t *in;
    size_t n_alone, n_merged;
    (void)state;

    tsup_tmp_path(tour, sizeof tour, "input", "tour.txt");
    assert_int_equal(tsup_write_bytes(tour, tour_text, strlen(tour_text)), 0);
    empty_dir(dir, sizeof dir, "multi_usb");

    psc_hal_option_t sim_opts[] = { { "script", tour, "t" } };
    assert_int_equal(open_input("sim", sim_opts, 1, &clk, &in, err, sizeof err), 0);
    n_alone = collect(in, &clk, alone, 64);
    psc_hal_input_close(in);

    /* unprefixed options go to the first backend; "usb.X" and "gpio.X" to those */
    psc_hal_option_t opts[] = { { "script", tour, "t:1" }, { "usb.dev_dir", dir, "t:2" },
                                { "usb.rescan_ms", "0", "t:3" }, { "gpio.line.home", "NOWHERE", "t:4" },
                                { "gpio.dev_dir", dir, "t:5" } };
    clk.now = 0;
    assert_int_equal(open_input(" sim , usb,gpio ", opts, 5, &clk, &in, err, sizeof err), 0);
    assert_string_equal(in->backend, "multi");
    n_merged = collect(in, &clk, merged, 64);
    assert_int_equal(psc_hal_input_get_device_name(in, 0, name, sizeof name), 0);
    assert_string_equal(name, "sim keypad");
    psc_hal_input_close(in);

    assert_true(n_alone >= 8);
    assert_int_equal(n_merged, n_alone);
    for (size_t i = 0; i < n_alone; i++) {
        assert_int_equal(merged[i].type, alone[i].type);
        assert_int_equal(merged[i].code, alone[i].code);
        assert_int_equal(merged[i].value, alone[i].value);
        assert_int_equal(merged[i].time_us, alone[i].time_us);
        /* device 0 speaks first and keeps slot 0; device 1 gets the next free slot, also after a replug */
        if (alone[i].type != PSC_HAL_INPUT_QUIT)
            assert_int_equal(merged[i].device, alone[i].device);
    }
    assert_int_equal(merged[n_merged - 1].type, PSC_HAL_INPUT_QUIT);

    /* a usb option the usb backend does not know, routed to it */
    psc_hal_option_t typo[] = { { "script", tour, "t:1" }, { "usb.rescan", "0", "boards/m/board.conf:6" } };
    assert_int_not_equal(open_input("sim,usb", typo, 2, &clk, &in, err, sizeof err), 0);
    assert_non_null(strstr(err, "boards/m/board.conf:6: input option 'rescan' is not known to the usb backend"));
    /* malformed lists */
    assert_int_equal(open_input("sim,sim", sim_opts, 1, &clk, &in, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "listed twice"));
    assert_int_equal(open_input("sim,", sim_opts, 1, &clk, &in, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "empty backend name"));
    assert_int_equal(open_input("sim,warp", sim_opts, 1, &clk, &in, err, sizeof err), -ENODEV);
    assert_non_null(strstr(err, "input backend 'warp' is not in this build"));
    remove(tour);
}

/* ---- the firmware's stick shaping and board keys ------------------------------------------ */

static void test_stick_shape(void **state)
{
    psc_controls_t c;
    int32_t prev = PSC_HAL_AXIS_MIN;
    (void)state;

    psc_controls_init(&c);
    for (int32_t v = PSC_HAL_AXIS_MIN; v <= PSC_HAL_AXIS_MAX; v++)
        assert_int_equal(psc_controls_shape_axis(&c, v), v);   /* off: exactly the identity */

    psc_controls_set_stick_shape(&c, 100, 0);   /* 10 % dead zone */
    assert_int_equal(c.dead_zone_q15, 3277);
    assert_int_equal(psc_controls_shape_axis(&c, 3277), 0);
    assert_int_equal(psc_controls_shape_axis(&c, -3277), 0);
    assert_int_equal(psc_controls_shape_axis(&c, 3278), 1);
    assert_int_equal(psc_controls_shape_axis(&c, PSC_HAL_AXIS_MAX), PSC_HAL_AXIS_MAX);
    assert_int_equal(psc_controls_shape_axis(&c, PSC_HAL_AXIS_MIN), PSC_HAL_AXIS_MIN);
    assert_int_equal(psc_controls_shape_axis(&c, 18022), 16383);   /* (18022 - 3277) / 29491 of full: 16383.4 */

    psc_controls_set_stick_shape(&c, 0, 1000);  /* fully cubic */
    assert_int_equal(psc_controls_shape_axis(&c, 16384), 4096);      /* 0.5^3 */
    assert_int_equal(psc_controls_shape_axis(&c, -16384), -4096);
    psc_controls_set_stick_shape(&c, 120, 400);
    for (int32_t v = PSC_HAL_AXIS_MIN; v <= PSC_HAL_AXIS_MAX; v++) {
        int32_t s = psc_controls_shape_axis(&c, v);
        assert_true(s >= prev);                    /* monotonic: no jumps back */
        assert_true(s - prev <= 4);                /* and no jumps: slope <= 1/0.88 * 1.8, twice rounded */
        if (v > PSC_HAL_AXIS_MIN)
            assert_int_equal(psc_controls_shape_axis(&c, -v), -s);   /* odd */
        prev = s;
    }
    psc_controls_set_stick_shape(&c, 5000, 5000);   /* clamped to 0.9 and 1.0 */
    assert_int_equal(c.dead_zone_q15, 29491);
    assert_int_equal(c.expo_q15, 32768);

    /* AXIS events go through it */
    psc_controls_set_stick_shape(&c, 100, 0);
    psc_controls_apply(&c, &(psc_hal_input_event_t){ .type = PSC_HAL_INPUT_AXIS, .device = 1,
                                                     .code = PSC_HAL_AXIS_YAW, .value = 2000 });
    assert_int_equal(c.axis[1][PSC_HAL_AXIS_YAW], 0);
}

static int parse_board(const char *extra, psc_board_config_t *cfg, char *err, size_t errlen)
{
    char text[1024];

    snprintf(text, sizeof text, "display = sim\ndisplay_size = 64x48\nclock = sim\n%s", extra);
    psc_board_config_defaults(cfg);
    return psc_board_config_parse(text, strlen(text), "b.conf", cfg, err, errlen);
}

static void test_board_keys(void **state)
{
    psc_board_config_t cfg;
    char err[512];
    (void)state;

    assert_int_equal(parse_board("input = sim\n", &cfg, err, sizeof err), 0);
    assert_int_equal(cfg.stick_dead_zone_milli, 0);
    assert_int_equal(cfg.stick_expo_milli, 0);
    assert_int_equal(parse_board("input = gpio,usb\nstick_dead_zone = 0.12\nstick_expo = 0.3\n", &cfg, err,
                                 sizeof err), 0);
    assert_string_equal(cfg.input_backend, "gpio,usb");
    assert_int_equal(cfg.stick_dead_zone_milli, 120);
    assert_int_equal(cfg.stick_expo_milli, 300);
    assert_int_equal(parse_board("input = sim, usb\n", &cfg, err, sizeof err), 0);
    assert_int_equal(parse_board("input = sim,warp\n", &cfg, err, sizeof err), -1);
    assert_non_null(strstr(err, "b.conf:4: input backend 'warp' is not in this build"));
    assert_int_equal(parse_board("input = usb,usb\n", &cfg, err, sizeof err), -1);
    assert_non_null(strstr(err, "b.conf:4: input list 'usb,usb' has an empty or repeated name"));
    assert_int_equal(parse_board("input = usb,\n", &cfg, err, sizeof err), -1);
    assert_non_null(strstr(err, "b.conf:4:"));
    assert_int_equal(parse_board("input = sim\nstick_dead_zone = 0.95\n", &cfg, err, sizeof err), -1);
    assert_non_null(strstr(err, "b.conf:5: stick_dead_zone must be a number from 0 to 0.9"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_button_no_debounce),
        cmocka_unit_test(test_button_debounce),
        cmocka_unit_test(test_button_late_batch),
        cmocka_unit_test(test_event_queue),
        cmocka_unit_test(test_usb_desc_real),
        cmocka_unit_test(test_usb_desc_truncation_and_fuzz),
        cmocka_unit_test(test_usb_pad_feed),
        cmocka_unit_test(test_usb_pad_transfer_status),
        cmocka_unit_test(test_usb_pad_map),
        cmocka_unit_test(test_usb_pad_map_errors),
        cmocka_unit_test(test_usb_backend_absent),
        cmocka_unit_test(test_gpio_backend_absent),
        cmocka_unit_test(test_multi_input),
        cmocka_unit_test(test_stick_shape),
        cmocka_unit_test(test_board_keys),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
