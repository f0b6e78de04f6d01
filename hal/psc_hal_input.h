/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_input.h - buttons, joysticks and their hot-plugging, delivered as a
 * queue of logical events.
 *
 * The firmware never sees GPIO line numbers or HID usages: a backend maps
 * each physical control to a logical action (psc_hal_action_t: "home",
 * "zoom_in", ...) or axis (psc_hal_axis_t: "yaw", "pitch", "zoom") using its
 * board options, and reports
 *   BUTTON_DOWN / BUTTON_UP   a debounced edge of an action's button;
 *   BUTTON_LONG               the button has been held for the long-press
 *                             time (sent once per press, before its UP);
 *   AXIS                      an axis moved: value is Q1.15, -32768..32767
 *                             (-1.0 .. just under +1.0), the raw position:
 *                             the firmware applies the board's dead zone
 *                             and response curve (firmware/controls.h);
 *   DEVICE_ARRIVE / _LEAVE    a device was plugged in or removed; after a
 *                             LEAVE the firmware releases everything that
 *                             device held (no UP events follow);
 *   QUIT                      the input source asks the program to end (the
 *                             simulated tour reached its end; a real board
 *                             may map a service key to it; q or Escape on a
 *                             keyboard);
 *   POINTER_DOWN / _MOVE / _UP
 *                             a contact on the picture: a finger on a touch
 *                             screen (code = its contact number, 0..
 *                             PSC_HAL_POINTER_MAX - 1) or a mouse with its
 *                             left button held (code 0); x, y in display
 *                             pixels (the frame's own, whatever the window's
 *                             size), may lie off the display while a drag
 *                             goes on. The firmware makes the gestures
 *                             (grab-drag, pinch, tap: firmware/gestures.h);
 *                             a backend only reports contacts. After a
 *                             LEAVE no UP follows;
 *   WHEEL                     a scroll wheel turned: value notches, > 0 away
 *                             from the user (zoom in), at the pointer (x, y).
 * Backends behind this interface:
 *   gpio    libgpiod 1.6 or 2.x, lines by name ("input.line.home =
 *           BTN_HOME"), edge events, kernel or software debounce, long press
 *           (hal/gpio/);
 *   usb     libusb: each gamepad's HID report descriptor parsed for its axes,
 *           hat and buttons, hotplug arrive/leave, axes scaled from the
 *           logical min..max to Q1.15 (hal/usb/);
 *   sdl     the SDL2 window's keyboard and mouse and SDL game controllers,
 *           for the desktop (hal/sdl/);
 *   evdev   the kernel's input devices (libevdev): keyboards, mice, touch
 *           screens and the gamepads the kernel drives, hot-plugged
 *           (hal/evdev/);
 *   sim     a tour script (hal/sim/psc_sim_tour.h) replayed on the sim clock;
 *   a list  "gpio,usb" merges backends into one input (psc_hal_input_multi.h).
 * Each event carries the device slot it came from (0..PSC_HAL_INPUT_MAX_DEVICES-1).
 */
#ifndef PSC_HAL_INPUT_H
#define PSC_HAL_INPUT_H

#include "psc_hal.h"

#define PSC_HAL_INPUT_MAX_DEVICES 8u

/** Q1.15 axis value of full deflection in the positive direction. */
#define PSC_HAL_AXIS_MAX 32767
/** Q1.15 axis value of full deflection in the negative direction. */
#define PSC_HAL_AXIS_MIN (-32768)
/** Contacts a touch screen may report at once (code of POINTER_* events). */
#define PSC_HAL_POINTER_MAX 10u

/** Kind of an input event. */
typedef enum {
    PSC_HAL_INPUT_BUTTON_DOWN = 1,
    PSC_HAL_INPUT_BUTTON_UP,
    PSC_HAL_INPUT_BUTTON_LONG,
    PSC_HAL_INPUT_AXIS,
    PSC_HAL_INPUT_DEVICE_ARRIVE,
    PSC_HAL_INPUT_DEVICE_LEAVE,
    PSC_HAL_INPUT_QUIT,
    PSC_HAL_INPUT_POINTER_DOWN,
    PSC_HAL_INPUT_POINTER_MOVE,
    PSC_HAL_INPUT_POINTER_UP,
    PSC_HAL_INPUT_WHEEL
} psc_hal_input_type_t;

/** Logical buttons. Names (psc_hal_action_name) are what board files and tours use. */
typedef enum {
    PSC_HAL_ACTION_NONE = 0,
    PSC_HAL_ACTION_PAN_LEFT,
    PSC_HAL_ACTION_PAN_RIGHT,
    PSC_HAL_ACTION_LOOK_UP,
    PSC_HAL_ACTION_LOOK_DOWN,
    PSC_HAL_ACTION_ZOOM_IN,
    PSC_HAL_ACTION_ZOOM_OUT,
    PSC_HAL_ACTION_HOME,
    PSC_HAL_ACTION_NEXT_SCENE,
    PSC_HAL_ACTION_PREV_SCENE,
    PSC_HAL_ACTION_SELECT,
    PSC_HAL_ACTION_BACK,
    PSC_HAL_ACTION_COUNT
} psc_hal_action_t;

/** Logical axes. Positive yaw turns right, positive pitch looks up, positive zoom zooms in. */
typedef enum {
    PSC_HAL_AXIS_YAW = 0,
    PSC_HAL_AXIS_PITCH,
    PSC_HAL_AXIS_ZOOM,
    PSC_HAL_AXIS_COUNT
} psc_hal_axis_t;

/** One input event. */
typedef struct {
    psc_hal_input_type_t type;
    uint8_t device;       /* device slot, < PSC_HAL_INPUT_MAX_DEVICES */
    uint16_t code;        /* psc_hal_action_t for buttons, psc_hal_axis_t for AXIS, contact for POINTER_*, else 0 */
    int32_t value;        /* AXIS: Q1.15 position; BUTTON_*: 1 down/long, 0 up; WHEEL: notches; else 0 */
    int16_t x, y;         /* POINTER_*, WHEEL: display pixels from the top left; else 0 */
    uint64_t time_us;     /* when it happened, on the input's clock */
} psc_hal_input_event_t;

/** Configuration of an input source. */
typedef struct psc_hal_input_config {
    psc_hal_clock_t *clock;       /* timestamps, debounce and script time; must outlive the input */
    uint32_t long_press_ms;       /* held this long = BUTTON_LONG; 0 = the backend's default */
    uint16_t display_width;       /* the display mode, for pointer coordinates (touch screens */
    uint16_t display_height;      /* scale their own range to it); 0 = unknown */
    psc_hal_options_t options;    /* backend-specific (sim: script) */
} psc_hal_input_config_t;

typedef struct {
    /* Mandatory. Take the oldest pending event whose time is <= now_us into *ev
     * and return 1; return 0 when there is none. Never blocks. */
    int (*poll)(psc_hal_input_t *in, uint64_t now_us, psc_hal_input_event_t *ev);
    /* Optional. A human-readable name of the device in a slot ("Logitech F310",
     * "gpiochip0"), for logs. -ENODEV for an empty slot. */
    int (*get_device_name)(psc_hal_input_t *in, uint8_t device, char *buf, size_t len);
    /* Mandatory. Release the devices and free everything. */
    void (*close)(psc_hal_input_t *in);
} psc_hal_input_ops_t;

/** The public part of an input source; backends embed it first in their state. */
struct psc_hal_input {
    const psc_hal_input_ops_t *ops;
    const char *backend;
};

/**
 * Open an input source of the named backend (board key "input"). 0 and *out
 * set, or a negative errno (psc_hal.h) with err naming the problem (for a
 * tour script: its file, line and what is wrong with it).
 */
int psc_hal_input_open(const char *backend, const psc_hal_input_config_t *cfg,
                       psc_hal_input_t **out, char *err, size_t errlen);

/** Close an input source opened with psc_hal_input_open (NULL is ignored). */
void psc_hal_input_close(psc_hal_input_t *in);

/** Take the next due event: 1 with *ev filled, 0 when none, negative errno on failure. */
static inline int psc_hal_input_poll(psc_hal_input_t *in, uint64_t now_us, psc_hal_input_event_t *ev)
{
    return in->ops->poll(in, now_us, ev);
}

/** Name of the device in a slot; -ENOSYS when the backend cannot tell. */
static inline int psc_hal_input_get_device_name(psc_hal_input_t *in, uint8_t device, char *buf, size_t len)
{
    return in->ops->get_device_name ? in->ops->get_device_name(in, device, buf, len) : -ENOSYS;
}

/** Board-file name of an action ("pan_left"...), or "?" for an unknown value. */
const char *psc_hal_action_name(psc_hal_action_t action);

/** The action with board-file name name, or PSC_HAL_ACTION_NONE if there is none. */
psc_hal_action_t psc_hal_action_parse(const char *name);

/** Board-file name of an axis ("yaw", "pitch", "zoom"), or "?". */
const char *psc_hal_axis_name(psc_hal_axis_t axis);

/** The axis named name; -1 if there is none (so the caller can report it). */
int psc_hal_axis_parse(const char *name);

#endif
