/* SPDX-License-Identifier: MIT */
/*
 * test_evdev.c - the evdev input backend (hal/evdev/) without a device node:
 * its translation of struct input_event sequences into HAL events, fed
 * directly (evdev_internal.h), and its options through psc_hal_input_open:
 *
 *  - what a device is from its capability bits (touch screen, touchpad,
 *    keyboard, mouse, gamepad, power button, lid switch, PC speaker);
 *  - the key map: arrows, + - and keypad, Home, Page Up/Down, Enter and
 *    keypad Enter on one action, Backspace; autorepeat ignored; long press;
 *    q and Escape quit only with quit_keys; key.NAME = ACTION remaps;
 *  - multitouch protocol B: two fingers down, moving, lifted, a slot reused
 *    in one frame, positions at the range's limits (min -> 0, max -> size-1)
 *    and rounding between; the kernel's single-touch emulation ignored;
 *  - a single-touch screen (ABS_X/ABS_Y + BTN_TOUCH);
 *  - a mouse: the virtual cursor, clamped to the display, drag as contact 0,
 *    wheel notches at the cursor;
 *  - a gamepad: sticks at min, centre and max in Q1.15, Y inverted, triggers
 *    and right stick as zoom, the hat and buttons as actions;
 *  - SYN_DROPPED: what was collected before it is thrown away, the resync's
 *    state is reported;
 *  - the backend's options: accepted forms, and errors naming the board key.
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

#include "evdev/evdev_internal.h"
#include "psc_hal_clock.h"
#include "psc_hal_input.h"
#include "tsup_files.h"

#define MS 1000u
#define QLEN 256u

static psc_hal_input_event_t q_store[QLEN];
static psc_hal_event_queue_t q;
static uint64_t now_us;

typedef struct {
    psc_hal_input_event_t e[QLEN];
    size_t n;
} got_t;

static void feed(psc_evdev_dev_t *d, unsigned type, unsigned code, int32_t value)
{
    struct input_event ie;

    memset(&ie, 0, sizeof ie);
    ie.type = (uint16_t)type;
    ie.code = (uint16_t)code;
    ie.value = value;
    psc_evdev_dev_feed(d, &ie, now_us, &q);
}

static void syn(psc_evdev_dev_t *d)
{
    feed(d, EV_SYN, SYN_REPORT, 0);
}

static void key(psc_evdev_dev_t *d, unsigned code, int32_t value)
{
    feed(d, EV_KEY, code, value);
    syn(d);
}

/* Everything pushed so far, oldest first. */
static void drain(got_t *g)
{
    g->n = 0;
    while (g->n < QLEN && psc_hal_event_queue_pop(&q, UINT64_MAX, &g->e[g->n]) == 1)
        g->n++;
}

static void expect_n(const got_t *g, size_t n)
{
    if (g->n != n) {
        for (size_t i = 0; i < g->n; i++)
            print_message("  event %zu: type %d code %u value %d at %d,%d\n", i, (int)g->e[i].type,
                          (unsigned)g->e[i].code, (int)g->e[i].value, g->e[i].x, g->e[i].y);
        fail_msg("%zu events, expected %zu", g->n, n);
    }
}

static void expect_ev(const got_t *g, size_t i, psc_hal_input_type_t type, unsigned code, int32_t value)
{
    assert_true(i < g->n);
    if (g->e[i].type != type || g->e[i].code != code || g->e[i].value != value)
        fail_msg("event %zu: type %d code %u value %d, expected type %d code %u value %d", i, (int)g->e[i].type,
                 (unsigned)g->e[i].code, (int)g->e[i].value, (int)type, code, (int)value);
}

static void expect_ptr(const got_t *g, size_t i, psc_hal_input_type_t type, unsigned contact, int x, int y)
{
    expect_ev(g, i, type, contact, 0);
    if (g->e[i].x != x || g->e[i].y != y)
        fail_msg("event %zu (type %d, contact %u) at %d,%d, expected %d,%d", i, (int)type, contact, g->e[i].x,
                 g->e[i].y, x, y);
}

typedef struct {
    psc_evdev_map_t map;
    psc_evdev_shared_t shared;
    psc_evdev_caps_t caps;
    psc_evdev_dev_t dev;
} rig_t;

/* A device of caps, translated as kinds (0: what it is), on an 800x480 display. */
static void rig_start(rig_t *r, bool quit_keys, unsigned kinds)
{
    psc_evdev_map_default(&r->map, quit_keys);
    r->shared = (psc_evdev_shared_t){ &r->map, { 0, 800 * MS }, 800, 480 };
    if (kinds == 0)
        kinds = psc_evdev_classify(&r->caps, &r->map);
    psc_hal_event_queue_init(&q, q_store, QLEN);
    now_us = 1000 * MS;
    psc_evdev_dev_init(&r->dev, &r->shared, &r->caps, kinds, 3, now_us);
}

static void caps_keyboard(psc_evdev_caps_t *c)
{
    static const unsigned keys[] = { KEY_ESC, KEY_Q, KEY_A, KEY_ENTER, KEY_KPENTER, KEY_LEFT, KEY_RIGHT, KEY_UP,
                                     KEY_DOWN, KEY_HOME, KEY_PAGEUP, KEY_PAGEDOWN, KEY_EQUAL, KEY_MINUS, KEY_KPPLUS,
                                     KEY_KPMINUS, KEY_BACKSPACE, KEY_F5, KEY_SPACE };
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "AT Translated Set 2 keyboard");
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        psc_evdev_caps_key(c, keys[i]);
    psc_evdev_set_bit(c->ev, EV_LED, true);
    psc_evdev_set_bit(c->ev, EV_REP, true);
}

static void caps_touch(psc_evdev_caps_t *c)
{
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "FT5406 memory based driver");
    psc_evdev_caps_key(c, BTN_TOUCH);
    psc_evdev_caps_abs(c, ABS_X, 0, 4095);
    psc_evdev_caps_abs(c, ABS_Y, 0, 2047);
    psc_evdev_caps_abs(c, ABS_MT_SLOT, 0, 9);
    psc_evdev_caps_abs(c, ABS_MT_TRACKING_ID, 0, 65535);
    psc_evdev_caps_abs(c, ABS_MT_POSITION_X, 0, 4095);
    psc_evdev_caps_abs(c, ABS_MT_POSITION_Y, 0, 2047);
    psc_evdev_caps_prop(c, INPUT_PROP_DIRECT);
}

static void caps_mouse(psc_evdev_caps_t *c)
{
    memset(c, 0, sizeof *c);
    psc_evdev_caps_key(c, BTN_LEFT);
    psc_evdev_caps_key(c, BTN_RIGHT);
    psc_evdev_caps_key(c, BTN_MIDDLE);
    psc_evdev_caps_rel(c, REL_X);
    psc_evdev_caps_rel(c, REL_Y);
    psc_evdev_caps_rel(c, REL_WHEEL);
    psc_evdev_caps_rel(c, REL_WHEEL_HI_RES);
}

static void caps_pad(psc_evdev_caps_t *c)
{
    static const unsigned keys[] = { BTN_SOUTH, BTN_EAST, BTN_NORTH, BTN_WEST, BTN_TL, BTN_TR, BTN_SELECT,
                                     BTN_START, BTN_MODE, BTN_THUMBL, BTN_THUMBR };
    memset(c, 0, sizeof *c);
    snprintf(c->name, sizeof c->name, "Microsoft X-Box 360 pad");
    c->bustype = BUS_USB;
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        psc_evdev_caps_key(c, keys[i]);
    psc_evdev_caps_abs(c, ABS_X, -32768, 32767);
    psc_evdev_caps_abs(c, ABS_Y, -32768, 32767);
    psc_evdev_caps_abs(c, ABS_RX, -32768, 32767);
    psc_evdev_caps_abs(c, ABS_RY, -32768, 32767);
    psc_evdev_caps_abs(c, ABS_Z, 0, 255);
    psc_evdev_caps_abs(c, ABS_RZ, 0, 255);
    psc_evdev_caps_abs(c, ABS_HAT0X, -1, 1);
    psc_evdev_caps_abs(c, ABS_HAT0Y, -1, 1);
}

/* ---- what a device is ------------------------------------------------------------------- */

static void test_classify(void **state)
{
    psc_evdev_map_t map;
    psc_evdev_caps_t c;
    char text[64];
    (void)state;

    psc_evdev_map_default(&map, false);
    caps_keyboard(&c);
    assert_int_equal(psc_evdev_classify(&c, &map), PSC_EVDEV_KEYBOARD);
    caps_touch(&c);
    assert_int_equal(psc_evdev_classify(&c, &map), PSC_EVDEV_TOUCH);
    /* a touchpad: positions on the pad, not on the display */
    psc_evdev_caps_prop(&c, INPUT_PROP_POINTER);
    assert_int_equal(psc_evdev_classify(&c, &map), 0);
    /* a single-touch screen */
    memset(&c, 0, sizeof c);
    psc_evdev_caps_key(&c, BTN_TOUCH);
    psc_evdev_caps_abs(&c, ABS_X, 100, 3900);
    psc_evdev_caps_abs(&c, ABS_Y, 200, 3800);
    assert_int_equal(psc_evdev_classify(&c, &map), PSC_EVDEV_TOUCH);
    caps_mouse(&c);
    assert_int_equal(psc_evdev_classify(&c, &map), PSC_EVDEV_MOUSE);
    caps_pad(&c);
    assert_int_equal(psc_evdev_classify(&c, &map), PSC_EVDEV_GAMEPAD);
    /* the same pad over Bluetooth: also a wireless one, which kiosks take beside the usb backend */
    c.bustype = BUS_BLUETOOTH;
    assert_int_equal(psc_evdev_classify(&c, &map), PSC_EVDEV_GAMEPAD | PSC_EVDEV_WIRELESS_GAMEPAD);
    unsigned kiosk;
    assert_int_equal(psc_evdev_parse_kinds("touch,keyboard,mouse,wireless_gamepad", &kiosk, "b:1", "devices", text,
                                           sizeof text), 0);
    assert_int_equal(psc_evdev_taken_kinds(PSC_EVDEV_GAMEPAD | PSC_EVDEV_WIRELESS_GAMEPAD, kiosk), PSC_EVDEV_GAMEPAD);
    assert_int_equal(psc_evdev_taken_kinds(PSC_EVDEV_GAMEPAD, kiosk), 0);   /* a USB pad: the usb backend's */
    c.bustype = BUS_USB;
    /* a plain (USB) joystick */
    memset(&c, 0, sizeof c);
    c.bustype = BUS_USB;
    psc_evdev_caps_key(&c, BTN_TRIGGER);
    psc_evdev_caps_abs(&c, ABS_X, 0, 1023);
    psc_evdev_caps_abs(&c, ABS_Y, 0, 1023);
    assert_int_equal(psc_evdev_classify(&c, &map), PSC_EVDEV_GAMEPAD);
    /* the power button, the lid switch, the PC speaker: nothing */
    memset(&c, 0, sizeof c);
    psc_evdev_caps_key(&c, KEY_POWER);
    assert_int_equal(psc_evdev_classify(&c, &map), 0);
    memset(&c, 0, sizeof c);
    psc_evdev_set_bit(c.ev, EV_SW, true);
    assert_int_equal(psc_evdev_classify(&c, &map), 0);
    memset(&c, 0, sizeof c);
    psc_evdev_set_bit(c.ev, EV_SND, true);
    assert_int_equal(psc_evdev_classify(&c, &map), 0);
    /* ... unless the board maps the power button's key */
    memset(&c, 0, sizeof c);
    psc_evdev_caps_key(&c, KEY_POWER);
    assert_int_equal(psc_evdev_map_set(&map, "KEY_POWER", "home", "t", "k", text, sizeof text), 0);
    assert_int_equal(psc_evdev_classify(&c, &map), PSC_EVDEV_KEYBOARD);
    /* a keyboard with a pointing stick is both */
    caps_keyboard(&c);
    psc_evdev_caps_key(&c, BTN_LEFT);
    psc_evdev_caps_rel(&c, REL_X);
    psc_evdev_caps_rel(&c, REL_Y);
    assert_int_equal(psc_evdev_classify(&c, &map), PSC_EVDEV_KEYBOARD | PSC_EVDEV_MOUSE);
    psc_evdev_describe_kinds(PSC_EVDEV_KEYBOARD | PSC_EVDEV_MOUSE, text, sizeof text);
    assert_string_equal(text, "keyboard, mouse");
}

/* ---- keys ------------------------------------------------------------------------------- */

static void test_keys_default_map(void **state)
{
    static const struct {
        unsigned code;
        psc_hal_action_t action;
    } keys[] = {
        { KEY_LEFT, PSC_HAL_ACTION_PAN_LEFT },    { KEY_RIGHT, PSC_HAL_ACTION_PAN_RIGHT },
        { KEY_UP, PSC_HAL_ACTION_LOOK_UP },       { KEY_DOWN, PSC_HAL_ACTION_LOOK_DOWN },
        { KEY_EQUAL, PSC_HAL_ACTION_ZOOM_IN },    { KEY_KPPLUS, PSC_HAL_ACTION_ZOOM_IN },
        { KEY_MINUS, PSC_HAL_ACTION_ZOOM_OUT },   { KEY_KPMINUS, PSC_HAL_ACTION_ZOOM_OUT },
        { KEY_HOME, PSC_HAL_ACTION_HOME },        { KEY_PAGEUP, PSC_HAL_ACTION_PREV_SCENE },
        { KEY_PAGEDOWN, PSC_HAL_ACTION_NEXT_SCENE }, { KEY_ENTER, PSC_HAL_ACTION_SELECT },
        { KEY_KPENTER, PSC_HAL_ACTION_SELECT },   { KEY_BACKSPACE, PSC_HAL_ACTION_BACK },
    };
    rig_t *r = calloc(1, sizeof *r);
    got_t *g = calloc(1, sizeof *g);
    (void)state;

    caps_keyboard(&r->caps);
    rig_start(r, false, 0);
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        now_us += 10 * MS;
        key(&r->dev, keys[i].code, 1);
        key(&r->dev, keys[i].code, 2);   /* autorepeat: nothing */
        now_us += 10 * MS;
        key(&r->dev, keys[i].code, 0);
        drain(g);
        expect_n(g, 2);
        expect_ev(g, 0, PSC_HAL_INPUT_BUTTON_DOWN, keys[i].action, 1);
        expect_ev(g, 1, PSC_HAL_INPUT_BUTTON_UP, keys[i].action, 0);
        assert_int_equal(g->e[0].device, 3);
        assert_int_equal(g->e[1].time_us, g->e[0].time_us + 10 * MS);
    }
    /* unmapped keys, and a key already held when the device was opened: nothing */
    key(&r->dev, KEY_A, 1);
    key(&r->dev, KEY_A, 0);
    key(&r->dev, KEY_SPACE, 0);
    key(&r->dev, KEY_LEFT, 0);
    drain(g);
    expect_n(g, 0);
    /* Enter and keypad Enter hold one action: down with the first, up with the last */
    key(&r->dev, KEY_ENTER, 1);
    key(&r->dev, KEY_KPENTER, 1);
    key(&r->dev, KEY_ENTER, 0);
    drain(g);
    expect_n(g, 1);
    expect_ev(g, 0, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_SELECT, 1);
    /* held for the long-press time: one LONG, at down + 800 ms */
    uint64_t down = g->e[0].time_us;
    psc_evdev_dev_tick(&r->dev, down + 799 * MS, &q);
    drain(g);
    expect_n(g, 0);
    psc_evdev_dev_tick(&r->dev, down + 2000 * MS, &q);
    now_us = down + 2000 * MS;
    key(&r->dev, KEY_KPENTER, 0);
    drain(g);
    expect_n(g, 2);
    expect_ev(g, 0, PSC_HAL_INPUT_BUTTON_LONG, PSC_HAL_ACTION_SELECT, 1);
    assert_int_equal(g->e[0].time_us, down + 800 * MS);
    expect_ev(g, 1, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_SELECT, 0);
    /* two keys in one report */
    feed(&r->dev, EV_KEY, KEY_HOME, 1);
    feed(&r->dev, EV_KEY, KEY_RIGHT, 1);
    drain(g);
    expect_n(g, 0);   /* nothing before SYN_REPORT */
    syn(&r->dev);
    drain(g);
    expect_n(g, 2);
    expect_ev(g, 0, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_HOME, 1);   /* code order: KEY_HOME 102, KEY_RIGHT 106 */
    expect_ev(g, 1, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_PAN_RIGHT, 1);
    free(g);
    free(r);
}

static void test_keys_quit(void **state)
{
    rig_t *r = calloc(1, sizeof *r);
    got_t *g = calloc(1, sizeof *g);
    (void)state;

    /* a kiosk: q and Escape do nothing */
    caps_keyboard(&r->caps);
    rig_start(r, false, 0);
    key(&r->dev, KEY_ESC, 1);
    key(&r->dev, KEY_ESC, 0);
    key(&r->dev, KEY_Q, 1);
    key(&r->dev, KEY_Q, 0);
    drain(g);
    expect_n(g, 0);
    /* quit_keys = yes: each quits when pressed */
    rig_start(r, true, 0);
    key(&r->dev, KEY_ESC, 1);
    key(&r->dev, KEY_ESC, 0);
    key(&r->dev, KEY_Q, 1);
    drain(g);
    expect_n(g, 2);
    expect_ev(g, 0, PSC_HAL_INPUT_QUIT, 0, 0);
    expect_ev(g, 1, PSC_HAL_INPUT_QUIT, 0, 0);
    free(g);
    free(r);
}

static void test_keys_remap(void **state)
{
    rig_t *r = calloc(1, sizeof *r);
    got_t *g = calloc(1, sizeof *g);
    char err[512];
    (void)state;

    caps_keyboard(&r->caps);
    rig_start(r, false, 0);
    assert_int_equal(psc_evdev_map_set(&r->map, "KEY_F5", "home", "b:1", "input.evdev.key.KEY_F5", err, sizeof err), 0);
    assert_int_equal(psc_evdev_map_set(&r->map, "KEY_LEFT", "none", "b:2", "x", err, sizeof err), 0);
    assert_int_equal(psc_evdev_map_set(&r->map, "KEY_HOME", "next_scene", "b:3", "x", err, sizeof err), 0);
    assert_int_equal(psc_evdev_map_set(&r->map, "KEY_SPACE", "quit", "b:4", "x", err, sizeof err), 0);
    key(&r->dev, KEY_F5, 1);
    key(&r->dev, KEY_F5, 0);
    key(&r->dev, KEY_LEFT, 1);
    key(&r->dev, KEY_LEFT, 0);
    key(&r->dev, KEY_HOME, 1);
    key(&r->dev, KEY_SPACE, 1);
    drain(g);
    expect_n(g, 4);
    expect_ev(g, 0, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_HOME, 1);
    expect_ev(g, 1, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_HOME, 0);
    expect_ev(g, 2, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_NEXT_SCENE, 1);
    expect_ev(g, 3, PSC_HAL_INPUT_QUIT, 0, 0);
    /* errors name the board line and key */
    assert_int_equal(psc_evdev_map_set(&r->map, "KEY_F55", "home", "boards/k/board.conf:7",
                                       "input.evdev.key.KEY_F55", err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "boards/k/board.conf:7: input.evdev.key.KEY_F55: 'KEY_F55' is not a kernel key name"));
    assert_int_equal(psc_evdev_map_set(&r->map, "KEY_F5", "jump", "boards/k/board.conf:8", "input.evdev.key.KEY_F5",
                                       err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "boards/k/board.conf:8: input.evdev.key.KEY_F5: 'jump' is not an action"));
    assert_int_equal(psc_evdev_map_set(&r->map, "REL_X", "home", "b", "k", err, sizeof err), -EINVAL);
    free(g);
    free(r);
}

/* ---- touch ------------------------------------------------------------------------------- */

static void mt(psc_evdev_dev_t *d, int slot, int id, int x, int y)
{
    feed(d, EV_ABS, ABS_MT_SLOT, slot);
    if (id != -2)
        feed(d, EV_ABS, ABS_MT_TRACKING_ID, id);
    if (x >= 0)
        feed(d, EV_ABS, ABS_MT_POSITION_X, x);
    if (y >= 0)
        feed(d, EV_ABS, ABS_MT_POSITION_Y, y);
}

static void test_touch_multitouch(void **state)
{
    rig_t *r = calloc(1, sizeof *r);
    got_t *g = calloc(1, sizeof *g);
    (void)state;

    caps_touch(&r->caps);   /* 0..4095 x 0..2047 onto 800 x 480 */
    rig_start(r, false, 0);
    /* two fingers at the range's two corners in one frame, with the kernel's single-touch emulation */
    mt(&r->dev, 0, 100, 0, 0);
    mt(&r->dev, 1, 101, 4095, 2047);
    feed(&r->dev, EV_KEY, BTN_TOUCH, 1);
    feed(&r->dev, EV_ABS, ABS_X, 0);
    feed(&r->dev, EV_ABS, ABS_Y, 0);
    syn(&r->dev);
    drain(g);
    expect_n(g, 2);
    expect_ptr(g, 0, PSC_HAL_INPUT_POINTER_DOWN, 0, 0, 0);
    expect_ptr(g, 1, PSC_HAL_INPUT_POINTER_DOWN, 1, 799, 479);
    assert_int_equal(g->e[0].device, 3);
    /* the slot stays selected: only X of slot 1 changes; rounding: 2048/4095*799 = 399.6 -> 400,
     * 1023/2047*479 = 239.38 -> 239 */
    feed(&r->dev, EV_ABS, ABS_MT_POSITION_X, 2048);
    feed(&r->dev, EV_ABS, ABS_MT_POSITION_Y, 1023);
    syn(&r->dev);
    /* a change too small for a pixel: no event */
    feed(&r->dev, EV_ABS, ABS_MT_POSITION_X, 2049);
    syn(&r->dev);
    /* slot 0 moves, slot 1 lifts, in one frame */
    mt(&r->dev, 0, -2, 4095, -1);
    mt(&r->dev, 1, -1, -1, -1);
    syn(&r->dev);
    drain(g);
    expect_n(g, 3);
    expect_ptr(g, 0, PSC_HAL_INPUT_POINTER_MOVE, 1, 400, 239);
    expect_ptr(g, 1, PSC_HAL_INPUT_POINTER_MOVE, 0, 799, 0);
    expect_ptr(g, 2, PSC_HAL_INPUT_POINTER_UP, 1, 400, 239);
    /* slot 0 lifted and a new finger in it within one frame: UP then DOWN */
    mt(&r->dev, 0, 102, 10, 2047);
    syn(&r->dev);
    drain(g);
    expect_n(g, 2);
    expect_ptr(g, 0, PSC_HAL_INPUT_POINTER_UP, 0, 799, 0);
    expect_ptr(g, 1, PSC_HAL_INPUT_POINTER_DOWN, 0, 2, 479);
    /* a slot beyond the contacts reported: ignored */
    mt(&r->dev, 12, 200, 5, 5);
    syn(&r->dev);
    mt(&r->dev, 0, -1, -1, -1);
    feed(&r->dev, EV_KEY, BTN_TOUCH, 0);
    syn(&r->dev);
    drain(g);
    expect_n(g, 1);
    expect_ptr(g, 0, PSC_HAL_INPUT_POINTER_UP, 0, 2, 479);
    free(g);
    free(r);
}

static void test_touch_single(void **state)
{
    rig_t *r = calloc(1, sizeof *r);
    got_t *g = calloc(1, sizeof *g);
    (void)state;

    memset(&r->caps, 0, sizeof r->caps);
    psc_evdev_caps_key(&r->caps, BTN_TOUCH);
    psc_evdev_caps_abs(&r->caps, ABS_X, -100, 100);   /* 800 px */
    psc_evdev_caps_abs(&r->caps, ABS_Y, 300, 3800);
    rig_start(r, false, 0);
    assert_int_equal(r->dev.kinds, PSC_EVDEV_TOUCH);
    /* moving without touching: nothing */
    feed(&r->dev, EV_ABS, ABS_X, 50);
    syn(&r->dev);
    feed(&r->dev, EV_ABS, ABS_X, -100);
    feed(&r->dev, EV_ABS, ABS_Y, 3800);
    feed(&r->dev, EV_KEY, BTN_TOUCH, 1);
    syn(&r->dev);
    feed(&r->dev, EV_ABS, ABS_X, 100);
    feed(&r->dev, EV_ABS, ABS_Y, 300);
    syn(&r->dev);
    feed(&r->dev, EV_ABS, ABS_X, 0);
    feed(&r->dev, EV_ABS, ABS_Y, 99999);   /* beyond the range: the last pixel */
    syn(&r->dev);
    feed(&r->dev, EV_KEY, BTN_TOUCH, 0);
    syn(&r->dev);
    drain(g);
    expect_n(g, 4);
    expect_ptr(g, 0, PSC_HAL_INPUT_POINTER_DOWN, 0, 0, 479);
    expect_ptr(g, 1, PSC_HAL_INPUT_POINTER_MOVE, 0, 799, 0);
    expect_ptr(g, 2, PSC_HAL_INPUT_POINTER_MOVE, 0, 400, 479);   /* 100/200 * 799 = 399.5 -> 400 */
    expect_ptr(g, 3, PSC_HAL_INPUT_POINTER_UP, 0, 400, 479);
    free(g);
    free(r);
}

static void test_scale(void **state)
{
    (void)state;
    assert_int_equal(psc_evdev_scale_pixel(0, 0, 4095, 800), 0);
    assert_int_equal(psc_evdev_scale_pixel(4095, 0, 4095, 800), 799);
    assert_int_equal(psc_evdev_scale_pixel(-5, 0, 4095, 800), 0);
    assert_int_equal(psc_evdev_scale_pixel(5000, 0, 4095, 800), 799);
    assert_int_equal(psc_evdev_scale_pixel(-1000, -1000, 1000, 1), 0);
    assert_int_equal(psc_evdev_scale_pixel(1000, -1000, 1000, 1), 0);
    assert_int_equal(psc_evdev_scale_pixel(77, 10, 1000, 0), 67);   /* display size unknown: raw */
    assert_int_equal(psc_evdev_scale_q15(0, 0, 255), PSC_HAL_AXIS_MIN);
    assert_int_equal(psc_evdev_scale_q15(255, 0, 255), PSC_HAL_AXIS_MAX);
    assert_int_equal(psc_evdev_scale_q15(512, 0, 1024), 0);
    assert_int_equal(psc_evdev_scale_q15(-32768, -32768, 32767), PSC_HAL_AXIS_MIN);
    assert_int_equal(psc_evdev_scale_q15(32767, -32768, 32767), PSC_HAL_AXIS_MAX);
    assert_int_equal(psc_evdev_scale_q15(0, -32768, 32767), 1);   /* 0.5 above the centre, rounded */
    assert_int_equal(psc_evdev_scale_q15(5, 5, 5), 0);
}

/* ---- mouse ------------------------------------------------------------------------------- */

static void rel(psc_evdev_dev_t *d, int dx, int dy)
{
    if (dx != 0)
        feed(d, EV_REL, REL_X, dx);
    if (dy != 0)
        feed(d, EV_REL, REL_Y, dy);
    syn(d);
}

static void test_mouse(void **state)
{
    rig_t *r = calloc(1, sizeof *r);
    got_t *g = calloc(1, sizeof *g);
    (void)state;

    caps_mouse(&r->caps);
    rig_start(r, false, 0);
    /* the cursor starts at the centre (400, 240); moving without the button: no pointer */
    rel(&r->dev, 10, -20);
    drain(g);
    expect_n(g, 0);
    key(&r->dev, BTN_LEFT, 1);
    rel(&r->dev, -100000, 0);   /* clamped to the left edge */
    rel(&r->dev, -5, 0);        /* at the edge already: no move */
    rel(&r->dev, 0, 100000);    /* the bottom edge */
    key(&r->dev, BTN_RIGHT, 1); /* no action */
    feed(&r->dev, EV_REL, REL_X, 3);
    feed(&r->dev, EV_KEY, BTN_LEFT, 0);
    syn(&r->dev);
    drain(g);
    expect_n(g, 4);
    expect_ptr(g, 0, PSC_HAL_INPUT_POINTER_DOWN, 0, 410, 220);
    expect_ptr(g, 1, PSC_HAL_INPUT_POINTER_MOVE, 0, 0, 220);
    expect_ptr(g, 2, PSC_HAL_INPUT_POINTER_MOVE, 0, 0, 479);
    expect_ptr(g, 3, PSC_HAL_INPUT_POINTER_UP, 0, 3, 479);
    /* the wheel: notches at the cursor, both ways; the high-resolution counts are not notches */
    rel(&r->dev, 100000, -100000);   /* top right corner */
    feed(&r->dev, EV_REL, REL_WHEEL, 1);
    feed(&r->dev, EV_REL, REL_WHEEL_HI_RES, 120);
    syn(&r->dev);
    feed(&r->dev, EV_REL, REL_WHEEL, -2);
    syn(&r->dev);
    drain(g);
    expect_n(g, 2);
    assert_int_equal(g->e[0].type, PSC_HAL_INPUT_WHEEL);
    assert_int_equal(g->e[0].value, 1);
    assert_int_equal(g->e[0].x, 799);
    assert_int_equal(g->e[0].y, 0);
    assert_int_equal(g->e[1].value, -2);
    free(g);
    free(r);
}

/* ---- gamepad ----------------------------------------------------------------------------- */

static void test_gamepad(void **state)
{
    rig_t *r = calloc(1, sizeof *r);
    got_t *g = calloc(1, sizeof *g);
    (void)state;

    caps_pad(&r->caps);
    rig_start(r, false, 0);
    assert_int_equal(r->dev.kinds, PSC_EVDEV_GAMEPAD);
    /* left stick at its limits and centre */
    feed(&r->dev, EV_ABS, ABS_X, 32767);
    feed(&r->dev, EV_ABS, ABS_Y, -32768);   /* up */
    syn(&r->dev);
    drain(g);
    expect_n(g, 3);   /* yaw, pitch, and the first report's zoom: the sticks' centre 0 and -1 read +1 */
    expect_ev(g, 0, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_YAW, PSC_HAL_AXIS_MAX);
    expect_ev(g, 1, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_PITCH, PSC_HAL_AXIS_MAX);
    feed(&r->dev, EV_ABS, ABS_X, -32768);
    feed(&r->dev, EV_ABS, ABS_Y, 32767);
    syn(&r->dev);
    drain(g);
    expect_n(g, 2);
    expect_ev(g, 0, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_YAW, PSC_HAL_AXIS_MIN);
    expect_ev(g, 1, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_PITCH, -PSC_HAL_AXIS_MAX);
    /* zoom: right stick up, plus right trigger, minus left trigger (0..255, resting at 0); the queue keeps
     * only an axis's latest value, so each report is taken before the next */
    static const struct {
        unsigned code;
        int32_t value, zoom;
    } zoom[] = {
        { ABS_RY, 0, -1 },                          /* 0.5 below the centre */
        { ABS_RY, -32768, PSC_HAL_AXIS_MAX },       /* up */
        { ABS_RY, 0, -1 },
        { ABS_RZ, 255, PSC_HAL_AXIS_MAX - 1 },      /* the stick's -1 and the trigger's full 32767 */
        { ABS_Z, 255, -1 },                         /* both triggers: they cancel */
        { ABS_RY, 32767, -PSC_HAL_AXIS_MAX },       /* down: 32767 negated */
    };
    for (size_t i = 0; i < sizeof zoom / sizeof zoom[0]; i++) {
        feed(&r->dev, EV_ABS, zoom[i].code, zoom[i].value);
        syn(&r->dev);
        drain(g);
        expect_n(g, 1);
        expect_ev(g, 0, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_ZOOM, zoom[i].zoom);
    }
    /* the hat and the buttons */
    feed(&r->dev, EV_ABS, ABS_HAT0X, -1);
    syn(&r->dev);
    feed(&r->dev, EV_ABS, ABS_HAT0X, 1);
    syn(&r->dev);
    feed(&r->dev, EV_ABS, ABS_HAT0X, 0);
    feed(&r->dev, EV_ABS, ABS_HAT0Y, -1);
    syn(&r->dev);
    key(&r->dev, BTN_SOUTH, 1);
    key(&r->dev, BTN_SOUTH, 0);
    key(&r->dev, BTN_NORTH, 1);
    key(&r->dev, BTN_MODE, 1);   /* no action */
    drain(g);
    expect_n(g, 8);
    expect_ev(g, 0, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_PAN_LEFT, 1);
    expect_ev(g, 1, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_PAN_LEFT, 0);
    expect_ev(g, 2, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_PAN_RIGHT, 1);
    expect_ev(g, 3, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_PAN_RIGHT, 0);
    expect_ev(g, 4, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_LOOK_UP, 1);
    expect_ev(g, 5, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_SELECT, 1);
    expect_ev(g, 6, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_SELECT, 0);
    expect_ev(g, 7, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_ZOOM_IN, 1);
    free(g);
    free(r);
}

static void test_gamepad_centre(void **state)
{
    rig_t *r = calloc(1, sizeof *r);
    got_t *g = calloc(1, sizeof *g);
    (void)state;

    /* a joystick whose axes start at 0 (centre (0 + 1024) / 2), right stick on Z/RZ */
    memset(&r->caps, 0, sizeof r->caps);
    psc_evdev_caps_key(&r->caps, BTN_TRIGGER);
    psc_evdev_caps_abs(&r->caps, ABS_X, 0, 1024);
    psc_evdev_caps_abs(&r->caps, ABS_Y, 0, 1024);
    psc_evdev_caps_abs(&r->caps, ABS_Z, 0, 1024);
    psc_evdev_caps_abs(&r->caps, ABS_RZ, 0, 1024);
    rig_start(r, false, 0);
    feed(&r->dev, EV_ABS, ABS_X, 1024);
    syn(&r->dev);
    drain(g);
    expect_n(g, 1);
    expect_ev(g, 0, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_YAW, PSC_HAL_AXIS_MAX);
    feed(&r->dev, EV_ABS, ABS_X, 512);
    syn(&r->dev);
    drain(g);
    expect_n(g, 1);
    expect_ev(g, 0, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_YAW, 0);
    feed(&r->dev, EV_ABS, ABS_X, 0);
    feed(&r->dev, EV_ABS, ABS_Z, 0);     /* the right stick's X: not an axis here */
    feed(&r->dev, EV_ABS, ABS_RZ, 0);    /* up: zoom in */
    syn(&r->dev);
    key(&r->dev, BTN_TRIGGER, 1);
    drain(g);
    expect_n(g, 3);
    expect_ev(g, 0, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_YAW, PSC_HAL_AXIS_MIN);
    expect_ev(g, 1, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_ZOOM, PSC_HAL_AXIS_MAX);
    expect_ev(g, 2, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_SELECT, 1);
    free(g);
    free(r);
}

/* ---- SYN_DROPPED ------------------------------------------------------------------------- */

static void test_syn_dropped(void **state)
{
    rig_t *r = calloc(1, sizeof *r);
    got_t *g = calloc(1, sizeof *g);
    (void)state;

    /* a touch screen that is also a keyboard (some kiosk panels have keys) */
    caps_touch(&r->caps);
    psc_evdev_caps_key(&r->caps, KEY_HOME);
    rig_start(r, false, 0);
    assert_int_equal(r->dev.kinds, PSC_EVDEV_TOUCH | PSC_EVDEV_KEYBOARD);
    mt(&r->dev, 0, 7, 0, 0);
    syn(&r->dev);
    key(&r->dev, KEY_HOME, 1);
    drain(g);
    expect_n(g, 2);
    /* a frame cut by the overflow: its values never count */
    mt(&r->dev, 0, -2, 4095, 2047);
    mt(&r->dev, 1, 8, 100, 100);
    feed(&r->dev, EV_SYN, SYN_DROPPED, 0);
    /* libevdev's resync: the device's state now (finger 0 lifted, home released, slot 1 never seen) */
    feed(&r->dev, EV_ABS, ABS_MT_SLOT, 0);
    feed(&r->dev, EV_ABS, ABS_MT_TRACKING_ID, -1);
    feed(&r->dev, EV_KEY, KEY_HOME, 0);
    syn(&r->dev);
    drain(g);
    expect_n(g, 2);
    expect_ptr(g, 0, PSC_HAL_INPUT_POINTER_UP, 0, 0, 0);   /* where it was last reported */
    expect_ev(g, 1, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_HOME, 0);
    /* a key pressed and dropped with its frame: the resync says it is up, nothing happened */
    feed(&r->dev, EV_KEY, KEY_HOME, 1);
    feed(&r->dev, EV_SYN, SYN_DROPPED, 0);
    syn(&r->dev);
    drain(g);
    expect_n(g, 0);
    free(g);
    free(r);
}

/* Kinds the board does not take are not translated. */
static void test_kinds_narrowed(void **state)
{
    rig_t *r = calloc(1, sizeof *r);
    got_t *g = calloc(1, sizeof *g);
    (void)state;

    caps_touch(&r->caps);
    psc_evdev_caps_key(&r->caps, KEY_HOME);
    rig_start(r, false, PSC_EVDEV_KEYBOARD);
    mt(&r->dev, 0, 7, 0, 0);
    syn(&r->dev);
    key(&r->dev, KEY_HOME, 1);
    drain(g);
    expect_n(g, 1);
    expect_ev(g, 0, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_HOME, 1);
    free(g);
    free(r);
}

/* ---- the backend's options --------------------------------------------------------------- */

typedef struct {
    psc_hal_clock_t base;
    uint64_t now;
} test_clock_t;

static uint64_t tclock_now(psc_hal_clock_t *c)
{
    return ((test_clock_t *)c)->now;
}

static int tclock_sleep(psc_hal_clock_t *c, uint64_t t)
{
    test_clock_t *tc = (test_clock_t *)c;
    if (t > tc->now)
        tc->now = t;
    return 0;
}

static void tclock_close(psc_hal_clock_t *c)
{
    (void)c;
}

static const psc_hal_clock_ops_t tclock_ops = { tclock_now, tclock_sleep, tclock_close };

static int open_evdev(const psc_hal_option_t *opts, size_t n, test_clock_t *clk, psc_hal_input_t **in, char *err,
                      size_t errlen)
{
    psc_hal_input_config_t cfg = { .clock = &clk->base, .long_press_ms = 800, .display_width = 800,
                                   .display_height = 480, .options = { opts, n } };

    clk->base.ops = &tclock_ops;
    clk->base.backend = "test";
    return psc_hal_input_open("evdev", &cfg, in, err, errlen);
}

static void test_backend_options(void **state)
{
    char dir[256], missing[300], err[512], name[64];
    test_clock_t clk = { .now = 0 };
    psc_hal_input_t *in = NULL;
    psc_hal_input_event_t ev;
    (void)state;

    tsup_tmp_path(dir, sizeof dir, "evdev", "empty");
    mkdir(dir, 0755);
    /* every option, bare and with the evdev. prefix input = evdev alone passes on */
    psc_hal_option_t opts[] = { { "dir", dir, "t:1" }, { "evdev.devices", "touch, keyboard", "t:2" },
                                { "evdev.name", "FT5406*", "t:3" }, { "grab", "yes", "t:4" },
                                { "evdev.quit_keys", "no", "t:5" }, { "evdev.key.KEY_F5", "home", "t:6" },
                                { "key.BTN_SOUTH", "none", "t:7" }, { "rescan_ms", "100", "t:8" } };
    assert_int_equal(open_evdev(opts, 8, &clk, &in, err, sizeof err), 0);
    assert_string_equal(in->backend, "evdev");
    for (unsigned i = 0; i < 5; i++, clk.now += 150 * MS)
        assert_int_equal(psc_hal_input_poll(in, clk.now, &ev), 0);
    assert_int_equal(psc_hal_input_get_device_name(in, 0, name, sizeof name), -ENODEV);
    psc_hal_input_close(in);
    /* a directory that is not there yet: not an error (devtmpfs makes /dev/input with the first device) */
    snprintf(missing, sizeof missing, "%s/not-yet", dir);
    psc_hal_option_t later[] = { { "dir", missing, "t:1" } };
    assert_int_equal(open_evdev(later, 1, &clk, &in, err, sizeof err), 0);
    assert_int_equal(psc_hal_input_poll(in, clk.now + 2000 * MS, &ev), 0);
    psc_hal_input_close(in);

    static const struct {
        const char *key, *value, *words;
    } bad[] = {
        { "devices", "touch,pen", "boards/e/board.conf:4: input.evdev.devices: 'pen' is not a kind of device" },
        { "evdev.devices", "", "input.evdev.devices: '' is not a kind of device" },
        { "evdev.key.KEY_NOPE", "home",
          "boards/e/board.conf:4: input.evdev.key.KEY_NOPE: 'KEY_NOPE' is not a kernel key name" },
        { "key.KEY_F5", "fly", "input.evdev.key.KEY_F5: 'fly' is not an action" },
        { "grab", "maybe", "boards/e/board.conf:4: input.evdev.grab must be yes or no, got 'maybe'" },
        { "evdev.quit_keys", "sometimes", "input.evdev.quit_keys must be yes or no" },
        { "rescan_ms", "10", "input.evdev.rescan_ms must be 0 (only inotify) or 50 to 60000, got '10'" },
        { "rescan_ms", "1s", "input.evdev.rescan_ms must be" },
        { "name", "", "input.evdev.name must be 1 to" },
        { "evdev.speed", "3", "boards/e/board.conf:4: input.evdev.speed is not known to the evdev input backend" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        psc_hal_option_t o[] = { { "dir", dir, "boards/e/board.conf:3" },
                                 { bad[i].key, bad[i].value, "boards/e/board.conf:4" } };
        in = (psc_hal_input_t *)1;
        assert_int_equal(open_evdev(o, 2, &clk, &in, err, sizeof err), -EINVAL);
        assert_null(in);
        if (strstr(err, bad[i].words) == NULL)
            fail_msg("%s = %s: got '%s', expected '%s'", bad[i].key, bad[i].value, err, bad[i].words);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_classify),
        cmocka_unit_test(test_keys_default_map),
        cmocka_unit_test(test_keys_quit),
        cmocka_unit_test(test_keys_remap),
        cmocka_unit_test(test_touch_multitouch),
        cmocka_unit_test(test_touch_single),
        cmocka_unit_test(test_scale),
        cmocka_unit_test(test_mouse),
        cmocka_unit_test(test_gamepad),
        cmocka_unit_test(test_gamepad_centre),
        cmocka_unit_test(test_syn_dropped),
        cmocka_unit_test(test_kinds_narrowed),
        cmocka_unit_test(test_backend_options),
    };

    return cmocka_run_group_tests(tests, NULL, NULL);
}
