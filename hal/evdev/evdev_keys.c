/* SPDX-License-Identifier: MIT */
/*
 * evdev_keys.c - key codes to actions, and held keys to BUTTON events.
 *
 * The default map is the desktop's (hal/sdl/sdl_input.c) in kernel key codes,
 * plus the gamepad buttons of the kernel's gamepad layout mapped as SDL maps
 * a game controller's. q and Escape quit only when the board says
 * quit_keys = yes: a visitor's keyboard must not end a kiosk. A board line
 * key.NAME = ACTION (NAME as libevdev names it: KEY_F5, BTN_SOUTH) adds to or
 * overrides the map; ACTION none takes a key out, quit makes it a quit key.
 *
 * Several keys may hold one action (Enter and keypad Enter): the action is
 * down while any of them is, and its edges go through psc_hal_button.h, so a
 * key held for long_press_ms gives one BUTTON_LONG as a GPIO button does.
 */
#include <stdio.h>
#include <string.h>

#include <libevdev/libevdev.h>

#include "evdev_internal.h"

void psc_evdev_map_default(psc_evdev_map_t *m, bool quit_keys)
{
    static const struct {
        uint16_t code;
        uint8_t action;
    } def[] = {
        { KEY_LEFT, PSC_HAL_ACTION_PAN_LEFT },      { KEY_RIGHT, PSC_HAL_ACTION_PAN_RIGHT },
        { KEY_UP, PSC_HAL_ACTION_LOOK_UP },         { KEY_DOWN, PSC_HAL_ACTION_LOOK_DOWN },
        { KEY_EQUAL, PSC_HAL_ACTION_ZOOM_IN },      { KEY_KPPLUS, PSC_HAL_ACTION_ZOOM_IN },
        { KEY_MINUS, PSC_HAL_ACTION_ZOOM_OUT },     { KEY_KPMINUS, PSC_HAL_ACTION_ZOOM_OUT },
        { KEY_HOME, PSC_HAL_ACTION_HOME },          { KEY_PAGEUP, PSC_HAL_ACTION_PREV_SCENE },
        { KEY_PAGEDOWN, PSC_HAL_ACTION_NEXT_SCENE }, { KEY_ENTER, PSC_HAL_ACTION_SELECT },
        { KEY_KPENTER, PSC_HAL_ACTION_SELECT },     { KEY_BACKSPACE, PSC_HAL_ACTION_BACK },
        /* gamepads (Documentation/input/gamepad.rst): as SDL's controller map */
        { BTN_SOUTH, PSC_HAL_ACTION_SELECT },       { BTN_EAST, PSC_HAL_ACTION_BACK },
        { BTN_WEST, PSC_HAL_ACTION_ZOOM_OUT },      { BTN_NORTH, PSC_HAL_ACTION_ZOOM_IN },
        { BTN_START, PSC_HAL_ACTION_HOME },         { BTN_TL, PSC_HAL_ACTION_PREV_SCENE },
        { BTN_TR, PSC_HAL_ACTION_NEXT_SCENE },      { BTN_DPAD_LEFT, PSC_HAL_ACTION_PAN_LEFT },
        { BTN_DPAD_RIGHT, PSC_HAL_ACTION_PAN_RIGHT }, { BTN_DPAD_UP, PSC_HAL_ACTION_LOOK_UP },
        { BTN_DPAD_DOWN, PSC_HAL_ACTION_LOOK_DOWN },
        /* a plain joystick's first buttons */
        { BTN_TRIGGER, PSC_HAL_ACTION_SELECT },     { BTN_THUMB, PSC_HAL_ACTION_BACK },
    };

    memset(m, 0, sizeof *m);
    for (size_t i = 0; i < sizeof def / sizeof def[0]; i++)
        m->action[def[i].code] = def[i].action;
    if (quit_keys) {
        m->action[KEY_Q] = PSC_EVDEV_QUIT;
        m->action[KEY_ESC] = PSC_EVDEV_QUIT;
    }
}

int psc_evdev_map_set(psc_evdev_map_t *m, const char *name, const char *action, const char *origin,
                      const char *board_key, char *err, size_t errlen)
{
    int code = libevdev_event_code_from_name(EV_KEY, name);
    psc_hal_action_t a;

    if (code < 0 || code >= KEY_CNT) {
        psc_hal_error_set(err, errlen, "%s: %s: '%s' is not a kernel key name (write it as libevdev and "
                          "linux/input-event-codes.h do: KEY_F5, KEY_SPACE, BTN_SOUTH)", origin, board_key, name);
        return -EINVAL;
    }
    if (strcmp(action, "none") == 0) {
        m->action[code] = 0;
        return 0;
    }
    if (strcmp(action, "quit") == 0) {
        m->action[code] = PSC_EVDEV_QUIT;
        return 0;
    }
    a = psc_hal_action_parse(action);
    if (a == PSC_HAL_ACTION_NONE) {
        psc_hal_error_set(err, errlen, "%s: %s: '%s' is not an action (pan_left pan_right look_up look_down "
                          "zoom_in zoom_out home next_scene prev_scene select back, or quit, none)",
                          origin, board_key, action);
        return -EINVAL;
    }
    m->action[code] = (uint8_t)a;
    return 0;
}

unsigned psc_evdev_key_kind(unsigned code)
{
    if ((code >= BTN_JOYSTICK && code < BTN_DIGI) || (code >= BTN_DPAD_UP && code <= BTN_DPAD_RIGHT) ||
        (code >= BTN_TRIGGER_HAPPY && code <= BTN_TRIGGER_HAPPY40))
        return PSC_EVDEV_GAMEPAD;
    if (code >= BTN_MOUSE && code < BTN_JOYSTICK)
        return PSC_EVDEV_MOUSE;
    return PSC_EVDEV_KEYBOARD;
}

/* An action's button moved to t: its due edges as events. */
static void keys_advance(psc_evdev_dev_t *d, unsigned action)
{
    psc_hal_button_edge_t e[2];
    unsigned n = psc_hal_button_advance(&d->button[action], &d->shared->timing, d->t_us, e);

    for (unsigned i = 0; i < n; i++) {
        psc_hal_input_event_t ev = { .type = e[i].type, .device = d->slot, .code = (uint16_t)action,
                                     .value = e[i].type == PSC_HAL_INPUT_BUTTON_UP ? 0 : 1, .time_us = e[i].time_us };
        (void)psc_hal_event_queue_push(d->queue, &ev);
    }
}

void psc_evdev_press(psc_evdev_dev_t *d, unsigned action, bool down)
{
    if (action == PSC_HAL_ACTION_NONE || action >= PSC_HAL_ACTION_COUNT)
        return;
    if (down)
        d->held[action]++;
    else if (d->held[action] > 0)
        d->held[action]--;
    else
        return;   /* a key held before the device was opened */
    keys_advance(d, action);
    psc_hal_button_set(&d->button[action], d->held[action] > 0, d->t_us);
    keys_advance(d, action);
}

/* The keys that changed in this report, in code order. */
void psc_evdev_keys_report(psc_evdev_dev_t *d)
{
    const psc_evdev_map_t *m = d->shared->map;

    for (unsigned byte = 0; byte < sizeof d->key_now; byte++) {
        unsigned diff = (unsigned)(d->key_now[byte] ^ d->key_new[byte]);

        for (unsigned bit = 0; diff != 0; bit++, diff >>= 1) {
            unsigned code = byte * 8u + bit;
            bool down = psc_evdev_bit(d->key_new, code);

            if (!(diff & 1u) || (psc_evdev_key_kind(code) & d->kinds) == 0)
                continue;
            if (m->action[code] == PSC_EVDEV_QUIT) {
                if (down)
                    psc_evdev_push(d, PSC_HAL_INPUT_QUIT, 0, 0, 0, 0);
            } else {
                psc_evdev_press(d, m->action[code], down);
            }
        }
        d->key_now[byte] = d->key_new[byte];
    }
}

void psc_evdev_dev_tick(psc_evdev_dev_t *d, uint64_t t_us, psc_hal_event_queue_t *q)
{
    d->queue = q;
    d->t_us = t_us;
    for (unsigned a = 1; a < PSC_HAL_ACTION_COUNT; a++)
        if (d->held[a] > 0 || d->button[a].stable)
            keys_advance(d, a);
}
