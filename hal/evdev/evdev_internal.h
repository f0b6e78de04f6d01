/* SPDX-License-Identifier: MIT */
/*
 * evdev_internal.h - the pieces of the "evdev" input backend (the kernel's
 * input devices: keyboards, mice, touch screens, gamepads), split so that
 * everything between a struct input_event and a psc_hal_input_event_t can be
 * driven without a device node (tests/test_evdev.c):
 *
 *   evdev_caps.c    what a device is (touch screen, keyboard, mouse, gamepad),
 *                   from its capability bits, and the kinds a board accepts;
 *   evdev_keys.c    key codes -> actions (the default map, quit keys, the
 *                   board's key.NAME = ACTION lines), held keys through the
 *                   HAL's long-press logic;
 *   evdev_touch.c   multitouch protocol B slots and single-touch screens ->
 *                   POINTER_DOWN/MOVE/UP in display pixels;
 *   evdev_mouse.c   a virtual cursor moved by REL_X/REL_Y, POINTER_* while
 *                   the left button is held, WHEEL notches;
 *   evdev_pad.c     the kernel's gamepad layout -> yaw, pitch, zoom axes in
 *                   Q1.15 and the hat as pan/look buttons;
 *   evdev_device.c  one device's event stream: changes collected until
 *                   SYN_REPORT, then turned into HAL events; SYN_DROPPED;
 *   evdev_input.c   the backend: options, finding and opening nodes (inotify
 *                   and a rescan), libevdev reading and resync, device slots.
 *
 * Nothing here allocates: a device's whole state is one psc_evdev_dev_t,
 * part of the backend's slot table allocated at open.
 */
#ifndef PSC_EVDEV_INTERNAL_H
#define PSC_EVDEV_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>
#include <linux/input.h>

#include "psc_hal_button.h"
#include "psc_hal_event_queue.h"
#include "psc_hal_input.h"

/* ---- device kinds (evdev_caps.c) ---------------------------------------------- */

#define PSC_EVDEV_TOUCH 0x1u      /* a touch screen: MT protocol B, or ABS_X/ABS_Y + BTN_TOUCH */
#define PSC_EVDEV_KEYBOARD 0x2u   /* keys the key map maps (a keyboard, a keypad, a remote) */
#define PSC_EVDEV_MOUSE 0x4u      /* REL_X, REL_Y and BTN_LEFT */
#define PSC_EVDEV_GAMEPAD 0x8u    /* BTN_SOUTH or BTN_TRIGGER, with ABS_X */
/* a gamepad on a bus other than USB (Bluetooth, a console's own port): the kiosks' usb backend
 * takes USB pads from the kernel, so "wireless_gamepad" lets evdev have just the others */
#define PSC_EVDEV_WIRELESS_GAMEPAD 0x10u
#define PSC_EVDEV_ALL_KINDS 0x1Fu

#define PSC_EVDEV_BITS(n) (((n) + 7u) / 8u)
#define PSC_EVDEV_NAME_MAX 128u

/** What a device can report, as the kernel tells it (EVIOCGBIT, EVIOCGABS, EVIOCGPROP). */
typedef struct {
    char name[PSC_EVDEV_NAME_MAX];
    uint16_t bustype;              /* BUS_USB, BUS_BLUETOOTH, ... (EVIOCGID); 0 unknown */
    uint8_t ev[PSC_EVDEV_BITS(EV_CNT)];
    uint8_t key[PSC_EVDEV_BITS(KEY_CNT)];
    uint8_t abs[PSC_EVDEV_BITS(ABS_CNT)];
    uint8_t rel[PSC_EVDEV_BITS(REL_CNT)];
    uint8_t prop[PSC_EVDEV_BITS(INPUT_PROP_CNT)];
    int32_t abs_min[ABS_CNT], abs_max[ABS_CNT];
} psc_evdev_caps_t;

static inline bool psc_evdev_bit(const uint8_t *bits, unsigned n)
{
    return (bits[n / 8u] >> (n % 8u)) & 1u;
}

static inline void psc_evdev_set_bit(uint8_t *bits, unsigned n, bool on)
{
    if (on)
        bits[n / 8u] = (uint8_t)(bits[n / 8u] | (1u << (n % 8u)));
    else
        bits[n / 8u] = (uint8_t)(bits[n / 8u] & ~(1u << (n % 8u)));
}

/** Mark an absolute axis with its range (tests build devices this way). */
void psc_evdev_caps_abs(psc_evdev_caps_t *c, unsigned code, int32_t min, int32_t max);
/** Mark a key, relative axis or property. */
void psc_evdev_caps_key(psc_evdev_caps_t *c, unsigned code);
void psc_evdev_caps_rel(psc_evdev_caps_t *c, unsigned code);
void psc_evdev_caps_prop(psc_evdev_caps_t *c, unsigned prop);

/* ---- key map (evdev_keys.c) ------------------------------------------------------ */

#define PSC_EVDEV_QUIT 0xFEu       /* a key map entry: the key asks the program to end */

typedef struct {
    uint8_t action[KEY_CNT];       /* psc_hal_action_t, PSC_EVDEV_QUIT, or 0 */
} psc_evdev_map_t;

/** The built-in map: arrows, + - (and keypad), Home, Page Up/Down, Enter, Backspace, the gamepad buttons;
 *  q and Escape quit only with quit_keys. */
void psc_evdev_map_default(psc_evdev_map_t *m, bool quit_keys);

/** One board line "key.NAME = ACTION" (ACTION: an action, quit or none). origin/board_key name it in errors. */
int psc_evdev_map_set(psc_evdev_map_t *m, const char *name, const char *action, const char *origin,
                      const char *board_key, char *err, size_t errlen);

/** The kind of device a key code belongs to: PSC_EVDEV_GAMEPAD, _MOUSE or _KEYBOARD. */
unsigned psc_evdev_key_kind(unsigned code);

/* ---- what a device is (evdev_caps.c) ---------------------------------------------- */

/** The kinds (PSC_EVDEV_*) the device is, with map deciding what counts as a keyboard. */
unsigned psc_evdev_classify(const psc_evdev_caps_t *c, const psc_evdev_map_t *m);

/** What of a device of kinds is translated for a board taking board_kinds (a wireless pad taken is a pad). */
static inline unsigned psc_evdev_taken_kinds(unsigned kinds, unsigned board_kinds)
{
    unsigned taken = kinds & board_kinds;

    return taken & PSC_EVDEV_WIRELESS_GAMEPAD ? (taken | PSC_EVDEV_GAMEPAD) & ~PSC_EVDEV_WIRELESS_GAMEPAD : taken;
}

/** "touch,keyboard" -> kinds; 0 and err for an unknown word. */
int psc_evdev_parse_kinds(const char *list, unsigned *kinds, const char *origin, const char *board_key, char *err,
                          size_t errlen);

/** "touch screen, keyboard" for logs. */
void psc_evdev_describe_kinds(unsigned kinds, char *buf, size_t len);

/* ---- one device's translation (evdev_device.c and friends) ------------------------------ */

#define PSC_EVDEV_PAD_AXES 8u      /* X Y Z RX RY RZ HAT0X HAT0Y */

typedef struct {
    int32_t id;                    /* tracking id, -1: no contact */
    int32_t x, y;                  /* raw */
} psc_evdev_contact_t;

/** The settings every device of a backend shares. */
typedef struct {
    const psc_evdev_map_t *map;
    psc_hal_button_timing_t timing;
    uint16_t display_width, display_height;   /* 0: unknown (pointer coordinates then raw) */
} psc_evdev_shared_t;

typedef struct {
    const psc_evdev_shared_t *shared;
    uint8_t slot;                  /* device slot of its events */
    unsigned kinds;                /* what is translated (the device's kinds the board accepts) */
    bool mt;                       /* touch by MT protocol B (else single touch) */
    int32_t min[ABS_CNT], max[ABS_CNT];
    bool pad_triggers;             /* ABS_Z/ABS_RZ are triggers (a right stick on RX/RY) */
    /* keys: the state after the last SYN_REPORT, and the one being collected */
    uint8_t key_now[PSC_EVDEV_BITS(KEY_CNT)], key_new[PSC_EVDEV_BITS(KEY_CNT)];
    uint8_t held[PSC_HAL_ACTION_COUNT];
    psc_hal_button_t button[PSC_HAL_ACTION_COUNT];
    /* touch */
    int32_t mt_slot;
    psc_evdev_contact_t mt_now[PSC_HAL_POINTER_MAX], mt_new[PSC_HAL_POINTER_MAX];
    psc_evdev_contact_t st_now, st_new;        /* single touch: id 0 while touching */
    int16_t px[PSC_HAL_POINTER_MAX], py[PSC_HAL_POINTER_MAX];   /* last reported, display pixels */
    /* mouse */
    int32_t cursor_x, cursor_y, rel_x, rel_y, wheel;
    /* gamepad: raw axis values, reported axes, hat */
    int32_t pad_now[PSC_EVDEV_PAD_AXES], pad_new[PSC_EVDEV_PAD_AXES];
    int32_t axis[PSC_HAL_AXIS_COUNT];
    uint64_t t_us;                 /* time of the events being translated */
    psc_hal_event_queue_t *queue;
} psc_evdev_dev_t;

/**
 * Start translating a device of caps, as kinds (already narrowed to the board's), into device slot slot,
 * at time t_us. Everything starts released; the mouse cursor at the display's centre.
 */
void psc_evdev_dev_init(psc_evdev_dev_t *d, const psc_evdev_shared_t *shared, const psc_evdev_caps_t *caps,
                        unsigned kinds, uint8_t slot, uint64_t t_us);

/**
 * One event of the device at t_us: collected, and at SYN_REPORT turned into HAL events pushed to q.
 * SYN_DROPPED throws away what was collected since the last SYN_REPORT; the events that follow (libevdev's
 * resync: the device's true state, ending in SYN_REPORT) bring the state up to date.
 */
void psc_evdev_dev_feed(psc_evdev_dev_t *d, const struct input_event *ev, uint64_t t_us, psc_hal_event_queue_t *q);

/** Long presses due by t_us. */
void psc_evdev_dev_tick(psc_evdev_dev_t *d, uint64_t t_us, psc_hal_event_queue_t *q);

/** Events one SYN_REPORT may produce at most: keep that much room in the queue before reading one. */
#define PSC_EVDEV_EVENTS_PER_REPORT (2u * PSC_HAL_POINTER_MAX + 3u * PSC_HAL_ACTION_COUNT + PSC_HAL_AXIS_COUNT + 4u)

/* internal to the translation files */
void psc_evdev_push(psc_evdev_dev_t *d, psc_hal_input_type_t type, uint16_t code, int32_t value, int32_t x,
                    int32_t y);
void psc_evdev_press(psc_evdev_dev_t *d, unsigned action, bool down);
void psc_evdev_keys_report(psc_evdev_dev_t *d);
void psc_evdev_touch_report(psc_evdev_dev_t *d);
void psc_evdev_touch_abs(psc_evdev_dev_t *d, unsigned code, int32_t value);
void psc_evdev_touch_drop(psc_evdev_dev_t *d);
void psc_evdev_mouse_report(psc_evdev_dev_t *d);
void psc_evdev_pad_report(psc_evdev_dev_t *d);
/** raw in min..max onto 0..size-1 (rounded, clamped); size 0: raw - min. */
int32_t psc_evdev_scale_pixel(int32_t raw, int32_t min, int32_t max, uint16_t size);
/** raw in min..max onto Q1.15: min -> -32768, centre -> 0, max -> 32767, rounded. */
int32_t psc_evdev_scale_q15(int32_t raw, int32_t min, int32_t max);

#endif
