/* SPDX-License-Identifier: MIT */
/*
 * psc_usb_pad.h - one gamepad's reports turned into HAL input events: the
 * part of the USB backend that needs no USB. The backend (psc_usb_input.c)
 * feeds it every finished interrupt transfer; tests feed it made-up
 * transfers. Nothing here allocates or blocks.
 *
 * The map from HID controls to logical axes and actions comes from the
 * board's "input.*" options of the usb backend (boards/README.md):
 *   axis.yaw = x         axis.pitch = -y        axis.zoom = -rz
 *     an axis kind (psc_hid_axis_kind_name: x y z rx ry rz slider dial wheel
 *     throttle rudder accelerator brake), '-' in front to invert, or none;
 *   button.N = ACTION    HID button N (1..32) acts as ACTION;
 *   hat = pan | none     hat switch directions act as pan_left/pan_right/
 *                        look_up/look_down (default pan).
 * Without any axis.* line the defaults above hold (HID's Y grows downwards,
 * hence -y: stick forward looks up); without any button.* line:
 * 1 home, 2 next_scene, 3 prev_scene, 5 zoom_out, 6 zoom_in.
 *
 * Events: AXIS when a mapped axis's Q1.15 value changes (the raw position:
 * the firmware applies the dead zone and response curve); BUTTON_DOWN/UP/LONG
 * per action, an action being held while any of its buttons or hat
 * directions is (psc_hal_button.h does the long press).
 */
#ifndef PSC_USB_PAD_H
#define PSC_USB_PAD_H

#include <stdbool.h>
#include <stdint.h>
#include "psc_hal_button.h"
#include "psc_hal_event_queue.h"
#include "psc_hal_input.h"
#include "psc_hid_parse.h"

/** HID controls to logical axes and actions. */
typedef struct {
    int8_t axis_kind[PSC_HAL_AXIS_COUNT];           /* psc_hid_axis_kind_t, -1 = not mapped */
    bool axis_invert[PSC_HAL_AXIS_COUNT];
    uint8_t button_action[PSC_HID_MAX_BUTTONS];     /* psc_hal_action_t of HID button n at [n-1] */
    bool hat_pans;
} psc_usb_map_t;

/** The defaults listed in the header comment. */
void psc_usb_map_default(psc_usb_map_t *map);

/**
 * Read the axis.*, button.* and hat options of opts into *map (on top of the
 * defaults; see the header for when defaults are dropped). Other keys are
 * left for the caller. 0, or -EINVAL with err naming the option's origin
 * (board file and line), the key and what it accepts.
 */
int psc_usb_map_parse(psc_usb_map_t *map, const psc_hal_options_t *opts, char *err, size_t errlen);

/** True when key is one psc_usb_map_parse reads (axis.NAME, button.N, hat). */
bool psc_usb_map_knows(const char *key);

/** A gamepad in use: its description, control state and what was last reported. */
typedef struct {
    psc_hid_gamepad_t desc;
    psc_hid_state_t state;
    uint8_t device;                                 /* HAL device slot of its events */
    int8_t axis_index[PSC_HAL_AXIS_COUNT];          /* into desc.axes, -1 = not on this device */
    int32_t axis_value[PSC_HAL_AXIS_COUNT];         /* last reported, Q1.15 */
    psc_hal_button_t action[PSC_HAL_ACTION_COUNT];
    uint32_t reports;                               /* reports decoded */
    uint32_t empty_reports;                         /* zero-length packets seen */
    uint32_t bad_reports;                           /* unknown ID, too short, overflow */
    uint32_t errors_in_row;                         /* failed transfers since the last good one */
} psc_usb_pad_t;

/**
 * Start a pad for a parsed descriptor, reporting as device slot device:
 * everything at rest, no event. now_us starts the long-press clocks.
 */
void psc_usb_pad_init(psc_usb_pad_t *pad, const psc_hid_gamepad_t *desc, const psc_usb_map_t *map,
                      uint8_t device, uint64_t now_us);

/**
 * One input report (as read, ID byte first when the device uses IDs): decode
 * it and queue the AXIS and BUTTON events it causes at now_us. Returns 0, or
 * the psc_hid_decode error (-ENODATA for a zero-length packet, which is
 * normal after a report that fills its last packet), counted and otherwise
 * ignored.
 */
int psc_usb_pad_report(psc_usb_pad_t *pad, const psc_usb_map_t *map, const psc_hal_button_timing_t *timing,
                       const uint8_t *data, size_t len, uint64_t now_us, psc_hal_event_queue_t *queue);

/** Queue the long presses that became due by now_us (call once per poll). */
void psc_usb_pad_tick(psc_usb_pad_t *pad, const psc_hal_button_timing_t *timing, uint64_t now_us,
                      psc_hal_event_queue_t *queue);

/** How an interrupt transfer ended (the backend maps libusb's status onto this). */
typedef enum {
    PSC_USB_XFER_COMPLETED = 0,
    PSC_USB_XFER_TIMED_OUT,
    PSC_USB_XFER_STALL,
    PSC_USB_XFER_OVERFLOW,
    PSC_USB_XFER_ERROR,
    PSC_USB_XFER_NO_DEVICE,
    PSC_USB_XFER_CANCELLED
} psc_usb_xfer_status_t;

/** What the backend does with the transfer next. */
typedef enum {
    PSC_USB_NEXT_RESUBMIT = 0,   /* read the next report */
    PSC_USB_NEXT_CLEAR_HALT,     /* clear the endpoint's halt, then resubmit */
    PSC_USB_NEXT_GONE,           /* the device is gone (unplugged, or failing every transfer): close it */
    PSC_USB_NEXT_IDLE            /* cancelled by us: leave it */
} psc_usb_next_t;

/** Consecutive failed transfers after which a device counts as gone. */
#define PSC_USB_PAD_MAX_ERRORS 8u

/**
 * A finished interrupt transfer: decode data[0..len) if it completed
 * (zero-length completions are counted and skipped), and say what to do next.
 */
psc_usb_next_t psc_usb_pad_transfer_done(psc_usb_pad_t *pad, const psc_usb_map_t *map,
                                         const psc_hal_button_timing_t *timing, psc_usb_xfer_status_t status,
                                         const uint8_t *data, size_t len, uint64_t now_us,
                                         psc_hal_event_queue_t *queue);

#endif
