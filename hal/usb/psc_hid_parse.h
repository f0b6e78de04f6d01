/* SPDX-License-Identifier: MIT */
/*
 * psc_hid_parse.h - USB HID report descriptors of joysticks and gamepads,
 * reduced to what a panorama kiosk needs, and the decoding of their input
 * reports. Pure C (no libusb, no allocation, no I/O), so it is unit-tested
 * and fuzzed on descriptors written from public specifications.
 *
 * What is understood (HID 1.11, section 6.2.2 "Report Descriptor"):
 *  - short items of every type and size (0, 1, 2, 4 data bytes); long items
 *    (prefix 0xFE) are skipped whole;
 *  - globals: usage page, logical and physical minimum/maximum, unit and
 *    exponent (read, not used), report size, report count, report ID,
 *    push/pop (PSC_HID_PUSH_DEPTH deep);
 *  - locals: usage, usage minimum/maximum (ranges), 32-bit "extended" usages
 *    that carry their own page; designators, strings and delimiters are
 *    read and ignored;
 *  - mains: input (constant = padding; variable; array), output and feature
 *    (skipped: they do not move input bits), collection/end collection
 *    (PSC_HID_COLLECTION_DEPTH deep), unknown main tags are ignored as
 *    Linux's hid-core does.
 * Only input controls inside an *application* collection whose usage is
 * Generic Desktop Joystick (0x04), Game Pad (0x05) or Multi-axis Controller
 * (0x08) are recorded (the innermost application collection decides, so the
 * consumer-control collection a gamepad nests inside itself is not taken for
 * its buttons); bit offsets are counted over every input item of a report ID,
 * whatever collection it sits in.
 *
 * Interpretation choices (spelled out because devices disagree):
 *  - logical minimum is signed; logical maximum is read unsigned when the
 *    minimum is >= 0 (a 1-byte "Logical Maximum (255)" is 0xFF, not -1), as
 *    Linux and Windows read it; likewise physical;
 *  - a field is signed when its logical minimum is negative;
 *  - a usage without its own page takes the usage page in effect when the
 *    main item is reached (HID 1.11 6.2.2.8: "the last declared Usage Page");
 *  - with fewer usages than report count, the last usage repeats;
 *  - relative axes, controls wider than 32 bits and ranges with minimum above
 *    maximum are left out (counted in ignored_controls), not errors.
 *
 * Bounded memory: every cap below is a fixed array in psc_hid_gamepad_t
 * (about 1.2 KiB); controls beyond a cap are counted and left out, a report
 * longer than PSC_HID_MAX_REPORT_BYTES or more than PSC_HID_MAX_REPORTS
 * report IDs is an error. The parser reads only desc[0..len).
 *
 * Decoded values: axes Q1.15 (logical minimum -> -32768, maximum -> 32767,
 * the middle of the range -> 0, rounded to nearest); hats as a bitmask of
 * PSC_HID_HAT_UP/RIGHT/DOWN/LEFT (0 = centred or null); buttons as a bitmask,
 * bit n-1 for HID button n (1..32).
 */
#ifndef PSC_HID_PARSE_H
#define PSC_HID_PARSE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define PSC_HID_MAX_AXES 16u           /* axis controls kept */
#define PSC_HID_MAX_HATS 2u            /* hat switches kept */
#define PSC_HID_MAX_BUTTONS 32u        /* buttons numbered 1..32 kept */
#define PSC_HID_MAX_BUTTON_ARRAYS 4u   /* array (index-list) button items kept */
#define PSC_HID_MAX_REPORTS 16u        /* distinct input report IDs (an error beyond) */
#define PSC_HID_MAX_REPORT_BYTES 512u  /* one input report, without its ID byte (an error beyond) */
#define PSC_HID_COLLECTION_DEPTH 16u   /* nested collections (an error beyond) */
#define PSC_HID_PUSH_DEPTH 8u          /* push without pop (an error beyond) */
#define PSC_HID_MAX_USAGES 64u         /* usage items and ranges before one main item (more are dropped) */
#define PSC_HID_MAX_DESCRIPTOR 4096u   /* longest descriptor accepted (USB allows 65535; gamepads use < 1 KiB) */

/** Hat directions, combined for diagonals (UP | RIGHT = north-east). */
#define PSC_HID_HAT_UP 1u
#define PSC_HID_HAT_RIGHT 2u
#define PSC_HID_HAT_DOWN 4u
#define PSC_HID_HAT_LEFT 8u

/** Which control an axis is: Generic Desktop X..Wheel and four Simulation Controls. */
typedef enum {
    PSC_HID_AXIS_X = 0,
    PSC_HID_AXIS_Y,
    PSC_HID_AXIS_Z,
    PSC_HID_AXIS_RX,
    PSC_HID_AXIS_RY,
    PSC_HID_AXIS_RZ,
    PSC_HID_AXIS_SLIDER,
    PSC_HID_AXIS_DIAL,
    PSC_HID_AXIS_WHEEL,
    PSC_HID_AXIS_THROTTLE,
    PSC_HID_AXIS_RUDDER,
    PSC_HID_AXIS_ACCELERATOR,
    PSC_HID_AXIS_BRAKE,
    PSC_HID_AXIS_KIND_COUNT
} psc_hid_axis_kind_t;

/** Where one control lives in its input report. */
typedef struct {
    uint8_t report_id;      /* 0 when the device uses no report IDs */
    uint8_t bit_size;       /* 1..32 */
    uint16_t bit_offset;    /* from the first bit after the report ID byte */
    bool is_signed;         /* logical minimum < 0: sign-extend */
    int32_t logical_min, logical_max;
} psc_hid_field_t;

typedef struct {
    psc_hid_field_t field;
    uint8_t kind;           /* psc_hid_axis_kind_t */
} psc_hid_axis_t;

typedef struct {
    psc_hid_field_t field;  /* logical_min..logical_max are the positions, clockwise from up */
} psc_hid_hat_t;

typedef struct {
    psc_hid_field_t field;  /* pressed when the raw value is not 0 */
    uint8_t number;         /* HID button number, 1..32 */
} psc_hid_button_t;

/** An array item: count slots, each holding the index of a pressed button. */
typedef struct {
    psc_hid_field_t field;  /* the first slot; the others follow every bit_size bits */
    uint16_t count;
    uint16_t usage_min, usage_max;   /* button numbers the slots can name (usage_min at logical_min) */
} psc_hid_button_array_t;

/** Bit length of one input report ID. */
typedef struct {
    uint8_t id;
    uint16_t bits;
} psc_hid_report_t;

/** A parsed joystick/gamepad: plain data, safe to copy. */
typedef struct {
    uint16_t application;               /* Generic Desktop usage of the first joystick/gamepad collection */
    bool uses_report_ids;               /* every input report starts with its ID byte */
    uint8_t report_count;
    psc_hid_report_t reports[PSC_HID_MAX_REPORTS];
    uint8_t axis_count;
    psc_hid_axis_t axes[PSC_HID_MAX_AXES];
    uint8_t hat_count;
    psc_hid_hat_t hats[PSC_HID_MAX_HATS];
    uint8_t button_count;
    psc_hid_button_t buttons[PSC_HID_MAX_BUTTONS];
    uint8_t button_array_count;
    psc_hid_button_array_t button_arrays[PSC_HID_MAX_BUTTON_ARRAYS];
    uint16_t max_report_bytes;          /* longest input report with its ID byte: the transfer size */
    uint16_t ignored_controls;          /* joystick controls left out (caps, relative, unusable) */
} psc_hid_gamepad_t;

/** Where and why a descriptor was refused. */
typedef struct {
    size_t offset;          /* byte offset of the offending item */
    char reason[112];
} psc_hid_error_t;

/** The state of a gamepad's controls, as psc_hid_decode leaves it. */
typedef struct {
    int32_t axis[PSC_HID_MAX_AXES];     /* Q1.15, indexed like psc_hid_gamepad_t.axes */
    uint8_t hat[PSC_HID_MAX_HATS];      /* PSC_HID_HAT_* bits, 0 = centred */
    uint32_t buttons;                   /* bit n-1 = button n */
} psc_hid_state_t;

/**
 * Parse a HID report descriptor desc[0..len) into *out. Returns 0; -EINVAL
 * for a malformed descriptor (an item running past the end, unbalanced
 * collections, pop without push, report ID 0 or above 255, usage minimum
 * without maximum and so on); -E2BIG when it is larger than a documented cap
 * (descriptor, report length, report IDs, nesting); -ENODEV when it is well
 * formed but describes no joystick or gamepad control. On failure err (may be
 * NULL) gives the byte offset and the reason, and *out is zeroed.
 */
int psc_hid_parse(const uint8_t *desc, size_t len, psc_hid_gamepad_t *out, psc_hid_error_t *err);

/**
 * Decode one input report (as read from the interrupt endpoint: with its ID
 * byte first when the device uses report IDs) into *state, updating only the
 * controls that report carries. Returns the report ID (0 without IDs);
 * -ENODATA for an empty report (a zero-length packet); -ENOENT for a report
 * ID the descriptor did not describe; -EMSGSIZE when the report is shorter
 * than described. On error *state is untouched.
 */
int psc_hid_decode(const psc_hid_gamepad_t *g, const uint8_t *report, size_t len, psc_hid_state_t *state);

/** All axes at rest (0), hats centred, no button pressed. */
void psc_hid_state_clear(psc_hid_state_t *state);

/** The index of the first axis of a kind in g->axes, or -1 if the device has none. */
int psc_hid_find_axis(const psc_hid_gamepad_t *g, psc_hid_axis_kind_t kind);

/** Board-file name of an axis kind ("x", "rz", "slider", "throttle"...), or "?". */
const char *psc_hid_axis_kind_name(psc_hid_axis_kind_t kind);

/** The axis kind named name, or -1. */
int psc_hid_axis_kind_parse(const char *name);

/**
 * A one-line summary for logs: "4 axes (x y z rz), 1 hat, 12 buttons,
 * report IDs 1 3" (always NUL-terminated, truncated to len).
 */
void psc_hid_describe(const psc_hid_gamepad_t *g, char *buf, size_t len);

#endif
