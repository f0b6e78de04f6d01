/* SPDX-License-Identifier: MIT */
/*
 * test_hid.c - the HID report descriptor parser and report decoder
 * (hal/usb/psc_hid_parse.h) on real descriptors written byte by byte from
 * public sources, each cited where it is defined:
 *
 *  - the joystick example of the HID 1.11 specification (Device Class
 *    Definition for HID 1.11, USB-IF 2001, Appendix D "Example Report
 *    Descriptors"): push/pop, a 4-position hat with a null state, buttons on
 *    both sides of an End Collection, a throttle after Pop;
 *  - the example game pad of the HID Usage Tables 1.1 (USB-IF 1999, the
 *    Generic Desktop "Game Pad" example, Figure 16 "Example Game Pad Input
 *    Device Report"): 2-bit signed axes and padding;
 *  - an Xbox One S controller's descriptor (335 bytes) as captured from
 *    /sys/.../report_descriptor and published in the xpadneo project's
 *    docs/descriptors/xb1s_linux.md: report IDs 1-4, 16-bit axes with a
 *    4-byte logical maximum, simulation-page triggers, an 8-way hat 1..8
 *    with a null state, a consumer collection nested in the game pad, output
 *    reports, and a stray 0x00 byte at the end;
 *  - the keyboard descriptor and the joystick report layout of Linux's USB
 *    HID gadget documentation (Documentation/usb/gadget_hid.rst: the
 *    keyboard's report_desc, and hid_gadget_test's 4-byte joystick report:
 *    three signed axes, hat in the low nibble with 4 = neutral, buttons 1-4
 *    in the high nibble); the joystick descriptor here is written for that
 *    layout.
 * Decoded sample reports are asserted bit-exactly. Then: every truncation,
 * tens of thousands of random mutations (parse or fail with a reason and an
 * offset inside the descriptor; whatever parses is internally consistent and
 * decodes any report without reading past it), several report IDs, every
 * documented cap and error, and report-level errors.
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

#include "usb/psc_hid_parse.h"

/* ---- the descriptors ------------------------------------------------------ */

/* HID 1.11, Appendix D, the joystick. Two corrections, both noted: the spec's
 * listing says "Usage Minimum (Button 4)" where it means Usage Maximum, and
 * writes "Usage (Throttle)" with the Generic Desktop page still in effect,
 * while Throttle is on the Simulation Controls page: written here as an
 * extended usage that carries its page (0x000200BB). */
static const uint8_t joystick_hid111[] = {
    0x05, 0x01,             /* Usage Page (Generic Desktop) */
    0x09, 0x04,             /* Usage (Joystick) */
    0xA1, 0x01,             /* Collection (Application) */
    0x05, 0x01,             /*   Usage Page (Generic Desktop) */
    0x09, 0x01,             /*   Usage (Pointer) */
    0xA1, 0x00,             /*   Collection (Physical) */
    0x15, 0x81,             /*     Logical Minimum (-127) */
    0x25, 0x7F,             /*     Logical Maximum (127) */
    0x75, 0x08,             /*     Report Size (8) */
    0x95, 0x02,             /*     Report Count (2) */
    0xA4,                   /*     Push */
    0x09, 0x30,             /*     Usage (X) */
    0x09, 0x31,             /*     Usage (Y) */
    0x81, 0x02,             /*     Input (Data, Variable, Absolute) */
    0x09, 0x39,             /*     Usage (Hat switch) */
    0x15, 0x00,             /*     Logical Minimum (0) */
    0x25, 0x03,             /*     Logical Maximum (3) */
    0x35, 0x00,             /*     Physical Minimum (0) */
    0x46, 0x0E, 0x01,       /*     Physical Maximum (270) */
    0x65, 0x14,             /*     Unit (Degrees) */
    0x95, 0x01,             /*     Report Count (1) */
    0x75, 0x04,             /*     Report Size (4) */
    0x81, 0x42,             /*     Input (Data, Variable, Absolute, Null State) */
    0x15, 0x00,             /*     Logical Minimum (0) */
    0x25, 0x01,             /*     Logical Maximum (1) */
    0x95, 0x02,             /*     Report Count (2) */
    0x75, 0x01,             /*     Report Size (1) */
    0x05, 0x09,             /*     Usage Page (Buttons) */
    0x19, 0x01,             /*     Usage Minimum (Button 1) */
    0x29, 0x02,             /*     Usage Maximum (Button 2) */
    0x65, 0x00,             /*     Unit (None) */
    0x81, 0x02,             /*     Input (Data, Variable, Absolute) */
    0xC0,                   /*   End Collection */
    0x19, 0x03,             /*   Usage Minimum (Button 3) */
    0x29, 0x04,             /*   Usage Maximum (Button 4) */
    0x81, 0x02,             /*   Input (Data, Variable, Absolute) */
    0xB4,                   /*   Pop */
    0x0B, 0xBB, 0x00, 0x02, 0x00, /* Usage (Simulation Controls: Throttle) */
    0x95, 0x01,             /*   Report Count (1) */
    0x81, 0x02,             /*   Input (Data, Variable, Absolute) */
    0xC0,                   /* End Collection */
};

/* HID Usage Tables 1.1, the example game pad; the report (Figure 16) is
 * byte 0: X bits 0-1, Y bits 2-3, pad; byte 1: buttons 1-6, pad. */
static const uint8_t gamepad_hut11[] = {
    0x05, 0x01,             /* Usage Page (Generic Desktop) */
    0x09, 0x05,             /* Usage (Game Pad) */
    0xA1, 0x01,             /* Collection (Application) */
    0x09, 0x01,             /*   Usage (Pointer) */
    0xA1, 0x00,             /*   Collection (Physical) */
    0x09, 0x30,             /*     Usage (X) */
    0x09, 0x31,             /*     Usage (Y) */
    0x15, 0xFF,             /*     Logical Minimum (-1) */
    0x25, 0x01,             /*     Logical Maximum (1) */
    0x95, 0x02,             /*     Report Count (2) */
    0x75, 0x02,             /*     Report Size (2) */
    0x81, 0x02,             /*     Input (Data, Variable, Absolute, No Null) */
    0xC0,                   /*   End Collection */
    0x95, 0x02,             /*   Report Count (2) */
    0x81, 0x03,             /*   Input (Constant, Variable, Absolute): 4-bit pad */
    0x05, 0x09,             /*   Usage Page (Buttons) */
    0x19, 0x01,             /*   Usage Minimum (Button 1) */
    0x29, 0x06,             /*   Usage Maximum (Button 6) */
    0x15, 0x00,             /*   Logical Minimum (0) */
    0x25, 0x01,             /*   Logical Maximum (1) */
    0x95, 0x06,             /*   Report Count (6) */
    0x75, 0x01,             /*   Report Size (1) */
    0x81, 0x02,             /*   Input (Data, Variable, Absolute) */
    0x95, 0x02,             /*   Report Count (2) */
    0x81, 0x03,             /*   Input (Constant, Variable, Absolute): 2-bit pad */
    0xC0,                   /* End Collection */
};

/* Xbox One S (045e:02fd), Linux mode, from xpadneo's docs/descriptors/xb1s_linux.md
 * (hex dump of the 335-byte report_descriptor). */
static const uint8_t xbox_one_s[] = {
    0x05, 0x01, 0x09, 0x05, 0xa1, 0x01, 0x85, 0x01, 0x09, 0x01, 0xa1, 0x00, 0x09, 0x30, 0x09, 0x31, 0x15, 0x00, 0x27, 0xff,
    0xff, 0x00, 0x00, 0x95, 0x02, 0x75, 0x10, 0x81, 0x02, 0xc0, 0x09, 0x01, 0xa1, 0x00, 0x09, 0x32, 0x09, 0x35, 0x15, 0x00,
    0x27, 0xff, 0xff, 0x00, 0x00, 0x95, 0x02, 0x75, 0x10, 0x81, 0x02, 0xc0, 0x05, 0x02, 0x09, 0xc5, 0x15, 0x00, 0x26, 0xff,
    0x03, 0x95, 0x01, 0x75, 0x0a, 0x81, 0x02, 0x15, 0x00, 0x25, 0x00, 0x75, 0x06, 0x95, 0x01, 0x81, 0x03, 0x05, 0x02, 0x09,
    0xc4, 0x15, 0x00, 0x26, 0xff, 0x03, 0x95, 0x01, 0x75, 0x0a, 0x81, 0x02, 0x15, 0x00, 0x25, 0x00, 0x75, 0x06, 0x95, 0x01,
    0x81, 0x03, 0x05, 0x01, 0x09, 0x39, 0x15, 0x01, 0x25, 0x08, 0x35, 0x00, 0x46, 0x3b, 0x01, 0x66, 0x14, 0x00, 0x75, 0x04,
    0x95, 0x01, 0x81, 0x42, 0x75, 0x04, 0x95, 0x01, 0x15, 0x00, 0x25, 0x00, 0x35, 0x00, 0x45, 0x00, 0x65, 0x00, 0x81, 0x03,
    0x05, 0x09, 0x19, 0x01, 0x29, 0x0f, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x0f, 0x81, 0x02, 0x15, 0x00, 0x25, 0x00,
    0x75, 0x01, 0x95, 0x01, 0x81, 0x03, 0x05, 0x0c, 0x0a, 0x24, 0x02, 0x15, 0x00, 0x25, 0x01, 0x95, 0x01, 0x75, 0x01, 0x81,
    0x02, 0x15, 0x00, 0x25, 0x00, 0x75, 0x07, 0x95, 0x01, 0x81, 0x03, 0x05, 0x0c, 0x09, 0x01, 0x85, 0x02, 0xa1, 0x01, 0x05,
    0x0c, 0x0a, 0x23, 0x02, 0x15, 0x00, 0x25, 0x01, 0x95, 0x01, 0x75, 0x01, 0x81, 0x02, 0x15, 0x00, 0x25, 0x00, 0x75, 0x07,
    0x95, 0x01, 0x81, 0x03, 0xc0, 0x05, 0x0f, 0x09, 0x21, 0x85, 0x03, 0xa1, 0x02, 0x09, 0x97, 0x15, 0x00, 0x25, 0x01, 0x75,
    0x04, 0x95, 0x01, 0x91, 0x02, 0x15, 0x00, 0x25, 0x00, 0x75, 0x04, 0x95, 0x01, 0x91, 0x03, 0x09, 0x70, 0x15, 0x00, 0x25,
    0x64, 0x75, 0x08, 0x95, 0x04, 0x91, 0x02, 0x09, 0x50, 0x66, 0x01, 0x10, 0x55, 0x0e, 0x15, 0x00, 0x26, 0xff, 0x00, 0x75,
    0x08, 0x95, 0x01, 0x91, 0x02, 0x09, 0xa7, 0x15, 0x00, 0x26, 0xff, 0x00, 0x75, 0x08, 0x95, 0x01, 0x91, 0x02, 0x65, 0x00,
    0x55, 0x00, 0x09, 0x7c, 0x15, 0x00, 0x26, 0xff, 0x00, 0x75, 0x08, 0x95, 0x01, 0x91, 0x02, 0xc0, 0x05, 0x06, 0x09, 0x20,
    0x85, 0x04, 0x15, 0x00, 0x26, 0xff, 0x00, 0x75, 0x08, 0x95, 0x01, 0x81, 0x02, 0xc0, 0x00,
};

/* Linux Documentation/usb/gadget_hid.rst: the keyboard's report_desc (63 bytes). */
static const uint8_t keyboard_gadget_doc[] = {
    0x05, 0x01, 0x09, 0x06, 0xa1, 0x01, 0x05, 0x07, 0x19, 0xe0, 0x29, 0xe7, 0x15, 0x00, 0x25, 0x01,
    0x75, 0x01, 0x95, 0x08, 0x81, 0x02, 0x95, 0x01, 0x75, 0x08, 0x81, 0x03, 0x95, 0x05, 0x75, 0x01,
    0x05, 0x08, 0x19, 0x01, 0x29, 0x05, 0x91, 0x02, 0x95, 0x01, 0x75, 0x03, 0x91, 0x03, 0x95, 0x06,
    0x75, 0x08, 0x15, 0x00, 0x25, 0x65, 0x05, 0x07, 0x19, 0x00, 0x29, 0x65, 0x81, 0x00, 0xc0,
};

/* A joystick for the report hid_gadget_test (gadget_hid.rst) writes: bytes
 * 0-2 signed X, Y, Z; byte 3 low nibble the hat (0..3, 4 = neutral), high
 * nibble buttons 1-4. Also the descriptor a dummy_hcd test gadget can use. */
static const uint8_t joystick_gadget[] = {
    0x05, 0x01,             /* Usage Page (Generic Desktop) */
    0x09, 0x04,             /* Usage (Joystick) */
    0xA1, 0x01,             /* Collection (Application) */
    0x15, 0x81,             /*   Logical Minimum (-127) */
    0x25, 0x7F,             /*   Logical Maximum (127) */
    0x75, 0x08,             /*   Report Size (8) */
    0x95, 0x03,             /*   Report Count (3) */
    0x09, 0x30,             /*   Usage (X) */
    0x09, 0x31,             /*   Usage (Y) */
    0x09, 0x32,             /*   Usage (Z) */
    0x81, 0x02,             /*   Input (Data, Variable, Absolute) */
    0x15, 0x00,             /*   Logical Minimum (0) */
    0x25, 0x03,             /*   Logical Maximum (3) */
    0x35, 0x00,             /*   Physical Minimum (0) */
    0x46, 0x0E, 0x01,       /*   Physical Maximum (270) */
    0x65, 0x14,             /*   Unit (Degrees) */
    0x75, 0x04,             /*   Report Size (4) */
    0x95, 0x01,             /*   Report Count (1) */
    0x09, 0x39,             /*   Usage (Hat switch) */
    0x81, 0x42,             /*   Input (Data, Variable, Absolute, Null State) */
    0x65, 0x00,             /*   Unit (None) */
    0x15, 0x00,             /*   Logical Minimum (0) */
    0x25, 0x01,             /*   Logical Maximum (1) */
    0x75, 0x01,             /*   Report Size (1) */
    0x95, 0x04,             /*   Report Count (4) */
    0x05, 0x09,             /*   Usage Page (Button) */
    0x19, 0x01,             /*   Usage Minimum (1) */
    0x29, 0x04,             /*   Usage Maximum (4) */
    0x81, 0x02,             /*   Input (Data, Variable, Absolute) */
    0xC0,                   /* End Collection */
};

/* A device with several report IDs: the game pad's sticks in report 1, its
 * buttons in report 2 (an array of two 8-bit slots), and a mouse in report 3
 * whose relative X/Y must not be taken for sticks. */
static const uint8_t multi_report[] = {
    0x05, 0x01, 0x09, 0x05, 0xA1, 0x01,             /* Game Pad application */
    0x85, 0x01,                                     /*   Report ID (1) */
    0x16, 0x00, 0x80, 0x26, 0xFF, 0x7F,             /*   Logical -32768..32767 */
    0x75, 0x10, 0x95, 0x02, 0x09, 0x30, 0x09, 0x35, /*   16-bit X, Rz */
    0x81, 0x02,
    0x85, 0x02,                                     /*   Report ID (2) */
    0x05, 0x09, 0x19, 0x01, 0x29, 0x20,             /*   Buttons 1..32 */
    0x15, 0x01, 0x25, 0x20, 0x75, 0x08, 0x95, 0x02, /*   logical 1..32 (0 = none), 2 slots */
    0x81, 0x00,                                     /*   Input (Data, Array, Absolute) */
    0xC0,
    0x05, 0x01, 0x09, 0x02, 0xA1, 0x01,             /* Mouse application */
    0x85, 0x03, 0x09, 0x01, 0xA1, 0x00,
    0x05, 0x09, 0x19, 0x01, 0x29, 0x03, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x03, 0x81, 0x02,
    0x75, 0x05, 0x95, 0x01, 0x81, 0x03,
    0x05, 0x01, 0x09, 0x30, 0x09, 0x31, 0x15, 0x81, 0x25, 0x7F, 0x75, 0x08, 0x95, 0x02, 0x81, 0x06,
    0xC0, 0xC0,
};

typedef struct {
    const char *name;
    const uint8_t *bytes;
    size_t len;
} descriptor_t;

static const descriptor_t real_descriptors[] = {
    { "HID 1.11 joystick", joystick_hid111, sizeof joystick_hid111 },
    { "HUT 1.1 game pad", gamepad_hut11, sizeof gamepad_hut11 },
    { "Xbox One S", xbox_one_s, sizeof xbox_one_s },
    { "gadget joystick", joystick_gadget, sizeof joystick_gadget },
    { "multi-report pad", multi_report, sizeof multi_report },
};
#define REAL_COUNT (sizeof real_descriptors / sizeof real_descriptors[0])

/* ---- helpers ----------------------------------------------------------------- */

/* A compound literal and its length, so no byte count is written by hand. */
#define BYTES(...) (const uint8_t[]){ __VA_ARGS__ }, sizeof((const uint8_t[]){ __VA_ARGS__ })

/* Parse from a heap copy of exactly len bytes, so a sanitizer catches overreads. */
static int parse_copy(const uint8_t *bytes, size_t len, psc_hid_gamepad_t *g, psc_hid_error_t *err)
{
    uint8_t *copy = malloc(len ? len : 1);
    int rc;

    assert_non_null(copy);
    if (len)
        memcpy(copy, bytes, len);
    rc = psc_hid_parse(copy, len, g, err);
    free(copy);
    return rc;
}

static int decode_copy(const psc_hid_gamepad_t *g, const uint8_t *bytes, size_t len, psc_hid_state_t *st)
{
    uint8_t *copy = malloc(len ? len : 1);
    int rc;

    assert_non_null(copy);
    if (len)
        memcpy(copy, bytes, len);
    rc = psc_hid_decode(g, len ? copy : NULL, len, st);
    free(copy);
    return rc;
}

static const psc_hid_report_t *report_of(const psc_hid_gamepad_t *g, uint8_t id)
{
    for (unsigned i = 0; i < g->report_count; i++)
        if (g->reports[i].id == id)
            return &g->reports[i];
    return NULL;
}

static void check_field(const psc_hid_gamepad_t *g, const psc_hid_field_t *f, unsigned extra_bits)
{
    const psc_hid_report_t *r = report_of(g, f->report_id);

    assert_non_null(r);
    assert_true(f->bit_size >= 1 && f->bit_size <= 32);
    assert_true(f->logical_min <= f->logical_max);
    assert_true((unsigned)f->bit_offset + f->bit_size + extra_bits <= r->bits);
    assert_true(f->is_signed == (f->logical_min < 0));
}

/* Everything a successful parse promises. */
static void check_sane(const psc_hid_gamepad_t *g)
{
    assert_true(g->report_count >= 1 && g->report_count <= PSC_HID_MAX_REPORTS);
    assert_true(g->axis_count <= PSC_HID_MAX_AXES && g->hat_count <= PSC_HID_MAX_HATS);
    assert_true(g->button_count <= PSC_HID_MAX_BUTTONS && g->button_array_count <= PSC_HID_MAX_BUTTON_ARRAYS);
    assert_true(g->axis_count + g->hat_count + g->button_count + g->button_array_count > 0);
    assert_true(g->max_report_bytes >= 1 && g->max_report_bytes <= PSC_HID_MAX_REPORT_BYTES + 1u);
    for (unsigned i = 0; i < g->report_count; i++) {
        assert_true(g->reports[i].bits <= PSC_HID_MAX_REPORT_BYTES * 8u);
        assert_true(g->uses_report_ids || g->reports[i].id == 0);
        for (unsigned k = 0; k < i; k++)
            assert_int_not_equal(g->reports[k].id, g->reports[i].id);
    }
    for (unsigned i = 0; i < g->axis_count; i++) {
        check_field(g, &g->axes[i].field, 0);
        assert_true(g->axes[i].kind < PSC_HID_AXIS_KIND_COUNT);
        assert_true(g->axes[i].field.logical_min < g->axes[i].field.logical_max);
    }
    for (unsigned i = 0; i < g->hat_count; i++)
        check_field(g, &g->hats[i].field, 0);
    for (unsigned i = 0; i < g->button_count; i++) {
        check_field(g, &g->buttons[i].field, 0);
        assert_true(g->buttons[i].number >= 1 && g->buttons[i].number <= 32);
    }
    for (unsigned i = 0; i < g->button_array_count; i++) {
        const psc_hid_button_array_t *a = &g->button_arrays[i];
        assert_true(a->count >= 1);
        check_field(g, &a->field, (unsigned)(a->count - 1u) * a->field.bit_size);
        assert_true(a->usage_min <= a->usage_max);
    }
}

/* ---- the real descriptors, decoded bit-exactly ---------------------------------- */

static void test_hid111_joystick(void **state)
{
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    psc_hid_state_t st;
    char text[160];
    (void)state;

    assert_int_equal(parse_copy(joystick_hid111, sizeof joystick_hid111, &g, &err), 0);
    check_sane(&g);
    assert_int_equal(g.application, 0x04);
    assert_false(g.uses_report_ids);
    assert_int_equal(g.report_count, 1);
    assert_int_equal(g.reports[0].bits, 32);
    assert_int_equal(g.max_report_bytes, 4);
    assert_int_equal(g.axis_count, 3);
    assert_int_equal(g.axes[0].kind, PSC_HID_AXIS_X);
    assert_int_equal(g.axes[1].kind, PSC_HID_AXIS_Y);
    assert_int_equal(g.axes[2].kind, PSC_HID_AXIS_THROTTLE);
    /* Pop brought back the -127..127, 8-bit state pushed before X and Y */
    assert_int_equal(g.axes[2].field.bit_offset, 24);
    assert_int_equal(g.axes[2].field.bit_size, 8);
    assert_int_equal(g.axes[2].field.logical_min, -127);
    assert_int_equal(g.axes[2].field.logical_max, 127);
    assert_int_equal(g.hat_count, 1);
    assert_int_equal(g.hats[0].field.bit_offset, 16);
    assert_int_equal(g.hats[0].field.bit_size, 4);
    assert_int_equal(g.button_count, 4);
    for (unsigned i = 0; i < 4; i++) {
        assert_int_equal(g.buttons[i].number, i + 1);
        assert_int_equal(g.buttons[i].field.bit_offset, 20 + i);
    }
    psc_hid_describe(&g, text, sizeof text);
    assert_string_equal(text, "3 axes (x y throttle), 1 hat, 4 buttons");

    /* X -127, Y +127, hat 1 (east), buttons 1 and 4, throttle 0 */
    psc_hid_state_clear(&st);
    assert_int_equal(decode_copy(&g, BYTES(0x81, 0x7F, 0x91, 0x00), &st), 0);
    assert_int_equal(st.axis[0], -32768);
    assert_int_equal(st.axis[1], 32767);
    assert_int_equal(st.axis[2], 0);
    assert_int_equal(st.hat[0], PSC_HID_HAT_RIGHT);
    assert_int_equal(st.buttons, 0x9u);
    /* X 0, Y -1, hat 4 (the null state: centred), buttons 2 and 3, throttle 64 */
    assert_int_equal(decode_copy(&g, BYTES(0x00, 0xFF, 0x64, 0x40), &st), 0);
    assert_int_equal(st.axis[0], 0);
    assert_int_equal(st.axis[1], -258);      /* -2/254 of full scale: -258.02 */
    assert_int_equal(st.axis[2], 16513);     /* 128/254: 16513.26 */
    assert_int_equal(st.hat[0], 0);
    assert_int_equal(st.buttons, 0x6u);
    /* the four hat positions clockwise from up */
    for (unsigned v = 0; v < 4; v++) {
        static const uint8_t dir[4] = { PSC_HID_HAT_UP, PSC_HID_HAT_RIGHT, PSC_HID_HAT_DOWN, PSC_HID_HAT_LEFT };
        assert_int_equal(decode_copy(&g, BYTES(0, 0, (uint8_t)v, 0), &st), 0);
        assert_int_equal(st.hat[0], dir[v]);
    }
}

static void test_hut11_gamepad(void **state)
{
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    psc_hid_state_t st;
    (void)state;

    assert_int_equal(parse_copy(gamepad_hut11, sizeof gamepad_hut11, &g, &err), 0);
    check_sane(&g);
    assert_int_equal(g.application, 0x05);
    assert_int_equal(g.reports[0].bits, 16);
    assert_int_equal(g.axis_count, 2);
    assert_int_equal(g.axes[0].field.bit_offset, 0);
    assert_int_equal(g.axes[1].field.bit_offset, 2);
    assert_true(g.axes[0].field.is_signed);
    assert_int_equal(g.button_count, 6);
    assert_int_equal(g.buttons[0].field.bit_offset, 8);
    assert_int_equal(g.buttons[5].field.bit_offset, 13);
    assert_int_equal(g.hat_count, 0);

    psc_hid_state_clear(&st);
    /* X = -1 (0b11), Y = +1 (0b01); buttons 1 and 6 */
    assert_int_equal(decode_copy(&g, BYTES(0x07, 0x21), &st), 0);
    assert_int_equal(st.axis[0], -32768);
    assert_int_equal(st.axis[1], 32767);
    assert_int_equal(st.buttons, 0x21u);
    /* both centred; the pad bits set (ignored); no buttons */
    assert_int_equal(decode_copy(&g, BYTES(0xF0, 0xC0), &st), 0);
    assert_int_equal(st.axis[0], 0);
    assert_int_equal(st.axis[1], 0);
    assert_int_equal(st.buttons, 0u);
    /* -2 is outside the logical range -1..1: clamped to full deflection */
    assert_int_equal(decode_copy(&g, BYTES(0x02, 0x00), &st), 0);
    assert_int_equal(st.axis[0], -32768);
}

/* Xbox report 1, little-endian fields: see the layout table in xpadneo's doc. */
static void xbox_report(uint8_t *r, uint16_t x, uint16_t y, uint16_t z, uint16_t rz, uint16_t brake, uint16_t accel,
                        uint8_t hat, uint16_t buttons, uint8_t back)
{
    r[0] = 1;
    r[1] = (uint8_t)x, r[2] = (uint8_t)(x >> 8);
    r[3] = (uint8_t)y, r[4] = (uint8_t)(y >> 8);
    r[5] = (uint8_t)z, r[6] = (uint8_t)(z >> 8);
    r[7] = (uint8_t)rz, r[8] = (uint8_t)(rz >> 8);
    r[9] = (uint8_t)brake, r[10] = (uint8_t)(brake >> 8);   /* 10 bits + 6 pad */
    r[11] = (uint8_t)accel, r[12] = (uint8_t)(accel >> 8);
    r[13] = hat;                                            /* 4 bits + 4 pad */
    r[14] = (uint8_t)buttons, r[15] = (uint8_t)(buttons >> 8);   /* 15 bits + 1 pad */
    r[16] = back;                                           /* AC Back (consumer page) + 7 pad */
}

static void test_xbox_one_s(void **state)
{
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    psc_hid_state_t st, before;
    uint8_t r[17];
    char text[160];
    (void)state;

    assert_int_equal(sizeof xbox_one_s, 335);
    assert_int_equal(parse_copy(xbox_one_s, sizeof xbox_one_s, &g, &err), 0);
    check_sane(&g);
    assert_int_equal(g.application, 0x05);
    assert_true(g.uses_report_ids);
    /* input reports 1 (128 bits), 2 (AC Home, 8) and 4 (battery, 8); 3 is output only */
    assert_int_equal(g.report_count, 3);
    assert_non_null(report_of(&g, 1));
    assert_int_equal(report_of(&g, 1)->bits, 128);
    assert_int_equal(report_of(&g, 2)->bits, 8);
    assert_int_equal(report_of(&g, 4)->bits, 8);
    assert_null(report_of(&g, 3));
    assert_int_equal(g.max_report_bytes, 17);
    psc_hid_describe(&g, text, sizeof text);
    assert_string_equal(text, "6 axes (x y z rz brake accelerator), 1 hat, 15 buttons, report IDs 1 2 4");
    assert_int_equal(g.axes[0].field.logical_max, 65535);   /* 4-byte logical maximum, unsigned */
    assert_false(g.axes[0].field.is_signed);
    assert_int_equal(g.axes[4].field.bit_offset, 64);
    assert_int_equal(g.axes[4].field.bit_size, 10);
    assert_int_equal(g.hats[0].field.logical_min, 1);
    assert_int_equal(g.hats[0].field.bit_offset, 96);
    assert_int_equal(g.buttons[14].number, 15);
    assert_int_equal(g.buttons[14].field.bit_offset, 118);

    psc_hid_state_clear(&st);
    xbox_report(r, 0x0000, 0xFFFF, 0x8000, 0x7FFF, 1023, 0, 3, 0x4001, 1);
    assert_int_equal(decode_copy(&g, r, sizeof r, &st), 1);
    assert_int_equal(st.axis[0], -32768);
    assert_int_equal(st.axis[1], 32767);
    assert_int_equal(st.axis[2], 1);         /* 32768 of 0..65535: +0.5, rounded away from zero */
    assert_int_equal(st.axis[3], -1);
    assert_int_equal(st.axis[4], 32767);     /* brake 1023 */
    assert_int_equal(st.axis[5], -32768);    /* accelerator 0 */
    assert_int_equal(st.hat[0], PSC_HID_HAT_RIGHT);   /* 3 of 1..8: east */
    assert_int_equal(st.buttons, 0x4001u);   /* A and the right stick click (button 15) */
    /* the eight hat positions and the null state 0 */
    for (unsigned v = 0; v <= 8; v++) {
        static const uint8_t dir[9] = { 0, PSC_HID_HAT_UP, PSC_HID_HAT_UP | PSC_HID_HAT_RIGHT, PSC_HID_HAT_RIGHT,
                                        PSC_HID_HAT_DOWN | PSC_HID_HAT_RIGHT, PSC_HID_HAT_DOWN,
                                        PSC_HID_HAT_DOWN | PSC_HID_HAT_LEFT, PSC_HID_HAT_LEFT,
                                        PSC_HID_HAT_UP | PSC_HID_HAT_LEFT };
        xbox_report(r, 0, 0, 0, 0, 0, 0, (uint8_t)(v | 0xF0), 0, 0);
        assert_int_equal(decode_copy(&g, r, sizeof r, &st), 1);
        assert_int_equal(st.hat[0], dir[v]);
    }
    /* report 2 (the Xbox button, a consumer control) and 4 (battery) change nothing here */
    before = st;
    assert_int_equal(decode_copy(&g, BYTES(2, 0x01), &st), 2);
    assert_int_equal(decode_copy(&g, BYTES(4, 0x80), &st), 4);
    assert_memory_equal(&before, &st, sizeof st);
    /* output report 3 is not an input report */
    assert_int_equal(decode_copy(&g, BYTES(3, 0, 0, 0, 0, 0, 0, 0, 0), &st), -ENOENT);
    /* a report one byte short */
    assert_int_equal(decode_copy(&g, r, sizeof r - 1, &st), -EMSGSIZE);
    assert_memory_equal(&before, &st, sizeof st);
}

static void test_gadget_joystick(void **state)
{
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    psc_hid_state_t st;
    (void)state;

    assert_int_equal(parse_copy(joystick_gadget, sizeof joystick_gadget, &g, &err), 0);
    check_sane(&g);
    assert_int_equal(g.max_report_bytes, 4);
    assert_int_equal(g.axis_count, 3);
    psc_hid_state_clear(&st);
    /* hid_gadget_test: "--b1 --hat2 10 -20 30" */
    assert_int_equal(decode_copy(&g, BYTES(10, 0xEC, 30, 0x11), &st), 0);
    assert_int_equal(st.axis[0], 2580);      /* 20/254 of full scale: 2580.16 */
    assert_int_equal(st.axis[1], -5160);
    assert_int_equal(st.axis[2], 7740);
    assert_int_equal(st.hat[0], PSC_HID_HAT_RIGHT);
    assert_int_equal(st.buttons, 0x1u);
    /* "--b4 --hatneutral 127 -127 0" */
    assert_int_equal(decode_copy(&g, BYTES(127, 0x81, 0, 0x84), &st), 0);
    assert_int_equal(st.axis[0], 32767);
    assert_int_equal(st.axis[1], -32768);
    assert_int_equal(st.axis[2], 0);
    assert_int_equal(st.hat[0], 0);
    assert_int_equal(st.buttons, 0x8u);
    /* -128 is below the logical minimum: still full deflection, never wrapped */
    assert_int_equal(decode_copy(&g, BYTES(0x80, 0, 0, 4), &st), 0);
    assert_int_equal(st.axis[0], -32768);
}

static void test_keyboard_is_not_a_joystick(void **state)
{
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    (void)state;

    assert_int_equal(parse_copy(keyboard_gadget_doc, sizeof keyboard_gadget_doc, &g, &err), -ENODEV);
    assert_non_null(strstr(err.reason, "no joystick or gamepad controls"));
    assert_int_equal(g.report_count, 0);   /* zeroed on failure */
}

static void test_multiple_report_ids(void **state)
{
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    psc_hid_state_t st;
    (void)state;

    assert_int_equal(parse_copy(multi_report, sizeof multi_report, &g, &err), 0);
    check_sane(&g);
    assert_true(g.uses_report_ids);
    assert_int_equal(g.report_count, 3);
    assert_int_equal(report_of(&g, 1)->bits, 32);
    assert_int_equal(report_of(&g, 2)->bits, 16);
    assert_int_equal(report_of(&g, 3)->bits, 24);
    assert_int_equal(g.max_report_bytes, 5);
    assert_int_equal(g.axis_count, 2);   /* the mouse's relative X/Y are not sticks */
    assert_int_equal(g.axes[1].kind, PSC_HID_AXIS_RZ);
    assert_int_equal(g.button_count, 0);   /* the mouse's buttons are not the pad's */
    assert_int_equal(g.button_array_count, 1);
    assert_int_equal(g.button_arrays[0].count, 2);
    assert_int_equal(g.button_arrays[0].usage_max, 32);

    psc_hid_state_clear(&st);
    assert_int_equal(decode_copy(&g, BYTES(1, 0x00, 0x80, 0xFF, 0x7F), &st), 1);
    assert_int_equal(st.axis[0], -32768);
    assert_int_equal(st.axis[1], 32767);
    assert_int_equal(st.buttons, 0u);
    /* report 2: slots hold button numbers 3 and 17; report 1's axes stay */
    assert_int_equal(decode_copy(&g, BYTES(2, 3, 17), &st), 2);
    assert_int_equal(st.buttons, (1u << 2) | (1u << 16));
    assert_int_equal(st.axis[0], -32768);
    /* 0 is outside 1..32: an empty slot; 32 is the last button */
    assert_int_equal(decode_copy(&g, BYTES(2, 0, 32), &st), 2);
    assert_int_equal(st.buttons, 1u << 31);
    /* the mouse report is described (its bits counted) but changes nothing */
    assert_int_equal(decode_copy(&g, BYTES(3, 7, 5, 5), &st), 3);
    assert_int_equal(st.buttons, 1u << 31);
    /* unknown ID, empty report */
    assert_int_equal(decode_copy(&g, BYTES(9, 0, 0, 0, 0), &st), -ENOENT);
    assert_int_equal(decode_copy(&g, NULL, 0, &st), -ENODATA);
}

/* ---- errors and limits ---------------------------------------------------------- */

static void expect_error(const uint8_t *bytes, size_t len, int rc, size_t offset, const char *words)
{
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    int got = parse_copy(bytes, len, &g, &err);

    if (got != rc || err.offset != offset || strstr(err.reason, words) == NULL)
        fail_msg("expected %d at %zu with '%s', got %d at %zu: %s", rc, offset, words, got, err.offset, err.reason);
}

#define JOY_HEAD 0x05, 0x01, 0x09, 0x04, 0xA1, 0x01
#define ONE_AXIS 0x15, 0x00, 0x25, 0x7F, 0x75, 0x08, 0x95, 0x01, 0x09, 0x30, 0x81, 0x02

static void test_errors(void **state)
{
    (void)state;
    expect_error(NULL, 0, -EINVAL, 0, "empty");
    expect_error(BYTES(JOY_HEAD, 0xB4, ONE_AXIS, 0xC0), -EINVAL, 6, "pop without a push");
    expect_error(BYTES(0xC0), -EINVAL, 0, "end collection without");
    expect_error(BYTES(JOY_HEAD, 0x85, 0x00, ONE_AXIS, 0xC0), -EINVAL, 6, "report ID 0");
    expect_error(BYTES(JOY_HEAD, 0x86, 0x00, 0x01, ONE_AXIS, 0xC0), -EINVAL, 6, "report ID 256");
    expect_error(BYTES(JOY_HEAD, ONE_AXIS), -EINVAL, 18, "1 collection not closed");
    expect_error(BYTES(JOY_HEAD, 0x26, 0xFF), -EINVAL, 6, "needs 2 data bytes, only 1 remain");
    expect_error(BYTES(JOY_HEAD, 0x19, 0x05, 0x29, 0x02, 0xC0), -EINVAL, 8, "above usage maximum");
    expect_error(BYTES(JOY_HEAD, 0x19, 0x01, 0x19, 0x02, 0xC0), -EINVAL, 8, "usage minimum twice");
    expect_error(BYTES(JOY_HEAD, 0xFE, 0x04, 0x10, 0x00), -EINVAL, 6, "long item of 4 data bytes");
    expect_error(BYTES(JOY_HEAD, 0xFE, 0x04), -EINVAL, 6, "long item header");
    /* a relative X (a mouse's) is not a stick */
    expect_error(BYTES(JOY_HEAD, 0x15, 0x81, 0x25, 0x7F, 0x75, 0x08, 0x95, 0x01, 0x09, 0x30, 0x81, 0x06,
                                    0xC0), -ENODEV, 0, "no joystick");
    /* a Generic Desktop X outside any joystick collection (a mouse) */
    expect_error(BYTES(0x05, 0x01, 0x09, 0x02, 0xA1, 0x01, ONE_AXIS, 0xC0), -ENODEV, 0,
                 "no joystick");
}

static void test_limits(void **state)
{
    uint8_t d[5000];
    size_t n = 0;
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    (void)state;

    /* push nested past PSC_HID_PUSH_DEPTH */
    memcpy(d, (const uint8_t[]){ JOY_HEAD }, 6);
    n = 6;
    for (unsigned i = 0; i <= PSC_HID_PUSH_DEPTH; i++)
        d[n++] = 0xA4;
    expect_error(d, n, -E2BIG, 6 + PSC_HID_PUSH_DEPTH, "push nested deeper");
    /* collections nested past PSC_HID_COLLECTION_DEPTH */
    n = 0;
    for (unsigned i = 0; i <= PSC_HID_COLLECTION_DEPTH; i++)
        d[n++] = 0xA1, d[n++] = 0x00;
    expect_error(d, n, -E2BIG, 2 * PSC_HID_COLLECTION_DEPTH, "nested deeper");
    /* an input report longer than PSC_HID_MAX_REPORT_BYTES */
    expect_error(BYTES(JOY_HEAD, 0x75, 0x08, 0x96, 0x01, 0x02, 0x81, 0x03, 0xC0), -E2BIG, 11,
                 "grows past 512 bytes");
    /* exactly PSC_HID_MAX_REPORT_BYTES is fine */
    assert_int_equal(parse_copy(BYTES(JOY_HEAD, 0x75, 0x08, 0x96, 0xFF, 0x01, 0x81, 0x03, ONE_AXIS, 0xC0), &g, &err), 0);
    assert_int_equal(g.max_report_bytes, 512);
    /* more than PSC_HID_MAX_REPORTS report IDs */
    memcpy(d, (const uint8_t[]){ JOY_HEAD, ONE_AXIS }, 18);
    n = 18;
    for (unsigned id = 1; id <= PSC_HID_MAX_REPORTS + 1; id++) {
        d[n++] = 0x85, d[n++] = (uint8_t)id;
        d[n++] = 0x09, d[n++] = 0x31, d[n++] = 0x81, d[n++] = 0x02;
    }
    d[n++] = 0xC0;
    /* the axis before the first Report ID is report 0: the 16th ID's input is one too many */
    expect_error(d, n, -E2BIG, 18 + 15 * 6 + 4, "more than 16 input report IDs");
    /* a descriptor longer than PSC_HID_MAX_DESCRIPTOR */
    memset(d, 0, sizeof d);
    expect_error(d, PSC_HID_MAX_DESCRIPTOR + 1, -E2BIG, 0, "more than the 4096 accepted");
    /* more controls than the caps: kept up to the cap, the rest counted */
    n = 0;
    assert_int_equal(parse_copy(BYTES(JOY_HEAD, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x96, 0x30, 0x00, 0x05, 0x09, 0x19,
                                      0x01, 0x29, 0x30, 0x81, 0x02, 0x05, 0x01, 0x15, 0x00, 0x25, 0x7F, 0x75, 0x08,
                                      0x95, 0x14, 0x09, 0x36, 0x81, 0x02, 0xC0), &g, &err), 0);
    check_sane(&g);
    assert_int_equal(g.button_count, 32);
    assert_int_equal(g.axis_count, PSC_HID_MAX_AXES);
    assert_int_equal(g.ignored_controls, 16 + 20 - PSC_HID_MAX_AXES);
}

static void test_long_items_and_reserved(void **state)
{
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    /* a long item (skipped whole, its data looks like items), a reserved-type
     * item (0xFC: type 3) and an unknown main tag (0xD0) are all skipped */
    static const uint8_t d[] = { JOY_HEAD, 0xFE, 0x03, 0x20, 0xC0, 0xC0, 0xC0, 0xFC, 0x01, 0x02, 0x03, 0x04,
                                 0xD0, ONE_AXIS, 0xC0 };
    (void)state;

    assert_int_equal(parse_copy(d, sizeof d, &g, &err), 0);
    assert_int_equal(g.axis_count, 1);
    assert_int_equal(g.reports[0].bits, 8);
}

static void test_usage_page_rules(void **state)
{
    psc_hid_gamepad_t g;
    psc_hid_error_t err;
    /* Usage (0x30) declared, then Usage Page (Button) before the Input: the
     * page in effect at the main item wins (HID 1.11 6.2.2.8), so this is
     * button 0x30 (beyond 32: ignored), not an X axis. A 32-bit usage keeps
     * its own page. Fewer usages than report count: the last repeats. */
    static const uint8_t d[] = { JOY_HEAD, 0x09, 0x30, 0x05, 0x09, 0x15, 0x00, 0x25, 0x7F, 0x75, 0x08, 0x95, 0x01,
                                 0x81, 0x02,
                                 0x0B, 0x31, 0x00, 0x01, 0x00, 0x81, 0x02,
                                 0x09, 0x02, 0x09, 0x03, 0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x04, 0x81, 0x02,
                                 0x95, 0x04, 0x81, 0x03, 0xC0 };
    (void)state;

    assert_int_equal(parse_copy(d, sizeof d, &g, &err), 0);
    check_sane(&g);
    assert_int_equal(g.ignored_controls, 1);
    assert_int_equal(g.axis_count, 1);
    assert_int_equal(g.axes[0].kind, PSC_HID_AXIS_Y);
    assert_int_equal(g.axes[0].field.bit_offset, 8);
    assert_int_equal(g.button_count, 4);
    assert_int_equal(g.buttons[0].number, 2);
    assert_int_equal(g.buttons[1].number, 3);
    assert_int_equal(g.buttons[2].number, 3);
    assert_int_equal(g.buttons[3].number, 3);
}

/* ---- truncation and mutation ------------------------------------------------------- */

/* Whether a prefix of n bytes ends at an item boundary with every
 * collection closed: only such a prefix may parse. */
static bool closed_boundary(const uint8_t *d, size_t len, size_t n)
{
    size_t pos = 0;
    int depth = 0;

    while (pos < n && pos < len) {
        size_t size = (d[pos] & 3u) == 3u ? 4u : (d[pos] & 3u);
        if (d[pos] == 0xFE)
            size = 2u + d[pos + 1];
        depth += d[pos] == 0xA1 ? 1 : d[pos] == 0xC0 ? -1 : 0;
        pos += 1 + size;
    }
    return pos == n && depth == 0;
}

static void test_truncation(void **state)
{
    (void)state;
    for (size_t k = 0; k < REAL_COUNT; k++) {
        const descriptor_t *r = &real_descriptors[k];
        unsigned parsed = 0;

        for (size_t n = 0; n <= r->len; n++) {
            psc_hid_gamepad_t g;
            psc_hid_error_t err;
            int rc = parse_copy(r->bytes, n, &g, &err);

            if (rc == 0) {
                if (!closed_boundary(r->bytes, r->len, n))
                    fail_msg("%s cut to %zu bytes, inside an item or a collection, parsed", r->name, n);
                check_sane(&g);
                parsed++;
            } else {
                assert_true(err.reason[0] != '\0');
                assert_true(err.offset <= n);
            }
        }
        assert_true(parsed >= 1);   /* at least the whole descriptor */
    }
}

/* splitmix64: deterministic, so a failure reproduces. */
static uint64_t rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static unsigned rng_below(uint64_t *s, unsigned n)
{
    return (unsigned)(rng_next(s) % n);
}

/* One random change: flip a bit, set a byte, insert or delete bytes, copy a
 * run of the descriptor elsewhere, or put an interesting item value in. */
static size_t mutate(uint8_t *d, size_t len, size_t cap, uint64_t *rng)
{
    static const uint8_t interesting[] = { 0x00, 0x01, 0x7F, 0x80, 0xFF, 0xFE, 0xC0, 0xA1, 0xA4, 0xB4, 0x85, 0x95,
                                           0x75, 0x81, 0x27, 0x17, 0x0B, 0x19, 0x29 };
    unsigned op = rng_below(rng, 7), at = len ? rng_below(rng, (unsigned)len) : 0;

    switch (op) {
    case 0:
        if (len)
            d[at] ^= (uint8_t)(1u << rng_below(rng, 8));
        break;
    case 1:
        if (len)
            d[at] = (uint8_t)rng_next(rng);
        break;
    case 2:
        if (len)
            d[at] = interesting[rng_below(rng, sizeof interesting)];
        break;
    case 3: { /* insert 1..8 random bytes */
        unsigned n = 1 + rng_below(rng, 8);
        if (len + n > cap)
            break;
        memmove(d + at + n, d + at, len - at);
        for (unsigned i = 0; i < n; i++)
            d[at + i] = (uint8_t)rng_next(rng);
        len += n;
        break;
    }
    case 4: { /* delete 1..8 bytes */
        unsigned n = 1 + rng_below(rng, 8);
        if (at + n > len)
            n = (unsigned)(len - at);
        memmove(d + at, d + at + n, len - at - n);
        len -= n;
        break;
    }
    case 5: { /* duplicate a run */
        unsigned from = len ? rng_below(rng, (unsigned)len) : 0, n = 1 + rng_below(rng, 24);
        if (from + n > len)
            n = (unsigned)(len - from);
        if (len + n > cap)
            break;
        memmove(d + at + n, d + at, len - at);
        memmove(d + at, d + (from >= at ? from + n : from), n);
        len += n;
        break;
    }
    default: /* a big report count or size */
        if (len + 3 <= cap) {
            memmove(d + at + 3, d + at, len - at);
            d[at] = rng_below(rng, 2) ? 0x96 : 0x76;
            d[at + 1] = (uint8_t)rng_next(rng);
            d[at + 2] = (uint8_t)rng_next(rng);
            len += 3;
        }
        break;
    }
    return len;
}

static void test_fuzz_mutations(void **state)
{
    enum { ROUNDS = 12000, CAP = 1024 };
    uint64_t rng = 0x5eed0005ull;
    unsigned parsed = 0, refused = 0, by_rc[5] = { 0 };
    (void)state;

    for (size_t k = 0; k < REAL_COUNT; k++) {
        const descriptor_t *r = &real_descriptors[k];

        for (unsigned round = 0; round < ROUNDS; round++) {
            uint8_t d[CAP], report[PSC_HID_MAX_REPORT_BYTES + 2];
            size_t len = r->len;
            unsigned changes = 1 + rng_below(&rng, 4);
            psc_hid_gamepad_t g;
            psc_hid_error_t err;
            int rc;

            memcpy(d, r->bytes, r->len);
            for (unsigned c = 0; c < changes; c++)
                len = mutate(d, len, CAP, &rng);
            rc = parse_copy(d, len, &g, &err);
            if (rc != 0) {
                refused++;
                by_rc[rc == -EINVAL ? 0 : rc == -E2BIG ? 1 : rc == -ENODEV ? 2 : 3]++;
                assert_true(rc == -EINVAL || rc == -E2BIG || rc == -ENODEV);
                assert_true(err.reason[0] != '\0');
                assert_true(err.offset <= len);
                continue;
            }
            parsed++;
            check_sane(&g);
            /* decode every report ID at full length, a random length and one short */
            for (unsigned i = 0; i < g.report_count; i++) {
                psc_hid_state_t st;
                size_t full = (g.reports[i].bits + 7u) / 8u + (g.uses_report_ids ? 1u : 0u);
                size_t rnd = rng_below(&rng, (unsigned)full + 3u);

                psc_hid_state_clear(&st);
                for (size_t b = 0; b < sizeof report; b++)
                    report[b] = (uint8_t)rng_next(&rng);
                report[0] = g.uses_report_ids ? g.reports[i].id : report[0];
                if (full > 0) {
                    assert_int_equal(decode_copy(&g, report, full, &st), g.reports[i].id);
                    for (unsigned a = 0; a < g.axis_count; a++)
                        assert_true(st.axis[a] >= -32768 && st.axis[a] <= 32767);
                    for (unsigned h = 0; h < g.hat_count; h++)
                        assert_true(st.hat[h] <= 15);
                }
                rc = decode_copy(&g, report, rnd, &st);
                assert_true(rc == g.reports[i].id || rc == -ENODATA || rc == -EMSGSIZE || rc == -ENOENT);
            }
        }
    }
    print_message("hid fuzz: %u mutated descriptors parsed, %u refused (EINVAL %u, E2BIG %u, ENODEV %u)\n", parsed,
                  refused, by_rc[0], by_rc[1], by_rc[2]);
    assert_true(parsed > 1000);
    assert_true(refused > 1000);
}

/* Random bytes, not mutations of anything: the parser never trusts a length. */
static void test_fuzz_random(void **state)
{
    uint64_t rng = 0xB17E5ull;
    (void)state;

    for (unsigned round = 0; round < 20000; round++) {
        uint8_t d[256];
        size_t len = rng_below(&rng, sizeof d + 1);
        psc_hid_gamepad_t g;
        psc_hid_error_t err;

        for (size_t i = 0; i < len; i++)
            d[i] = (uint8_t)rng_next(&rng);
        if (parse_copy(d, len, &g, &err) == 0)
            check_sane(&g);
        else
            assert_true(err.offset <= len && err.reason[0] != '\0');
    }
}

static void test_axis_names(void **state)
{
    (void)state;
    for (int k = 0; k < PSC_HID_AXIS_KIND_COUNT; k++)
        assert_int_equal(psc_hid_axis_kind_parse(psc_hid_axis_kind_name((psc_hid_axis_kind_t)k)), k);
    assert_int_equal(psc_hid_axis_kind_parse("rz"), PSC_HID_AXIS_RZ);
    assert_int_equal(psc_hid_axis_kind_parse("Rz"), -1);
    assert_string_equal(psc_hid_axis_kind_name(PSC_HID_AXIS_KIND_COUNT), "?");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hid111_joystick),
        cmocka_unit_test(test_hut11_gamepad),
        cmocka_unit_test(test_xbox_one_s),
        cmocka_unit_test(test_gadget_joystick),
        cmocka_unit_test(test_keyboard_is_not_a_joystick),
        cmocka_unit_test(test_multiple_report_ids),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_long_items_and_reserved),
        cmocka_unit_test(test_usage_page_rules),
        cmocka_unit_test(test_truncation),
        cmocka_unit_test(test_fuzz_mutations),
        cmocka_unit_test(test_fuzz_random),
        cmocka_unit_test(test_axis_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
