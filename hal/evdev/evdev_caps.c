/* SPDX-License-Identifier: MIT */
/*
 * evdev_caps.c - what an input device is, from what it says it can report.
 *
 *   touch screen  ABS_MT_SLOT with ABS_MT_POSITION_X/Y (multitouch protocol
 *                 B), or ABS_X/ABS_Y with BTN_TOUCH (single touch); not a
 *                 touchpad (INPUT_PROP_POINTER: its positions are not the
 *                 display's)
 *   keyboard      at least one key the key map maps (a keyboard, a keypad,
 *                 a remote control); a power button, lid switch or the PC
 *                 speaker has none and is not used
 *   mouse         REL_X, REL_Y and BTN_LEFT
 *   gamepad       BTN_SOUTH (the kernel's gamepad layout) or BTN_TRIGGER (a
 *                 joystick), with ABS_X, and not a touch screen
 * One device may be several (a keyboard with a pointing stick).
 */
#include <stdio.h>
#include <string.h>

#include "evdev_internal.h"

void psc_evdev_caps_abs(psc_evdev_caps_t *c, unsigned code, int32_t min, int32_t max)
{
    psc_evdev_set_bit(c->ev, EV_ABS, true);
    psc_evdev_set_bit(c->abs, code, true);
    c->abs_min[code] = min;
    c->abs_max[code] = max;
}

void psc_evdev_caps_key(psc_evdev_caps_t *c, unsigned code)
{
    psc_evdev_set_bit(c->ev, EV_KEY, true);
    psc_evdev_set_bit(c->key, code, true);
}

void psc_evdev_caps_rel(psc_evdev_caps_t *c, unsigned code)
{
    psc_evdev_set_bit(c->ev, EV_REL, true);
    psc_evdev_set_bit(c->rel, code, true);
}

void psc_evdev_caps_prop(psc_evdev_caps_t *c, unsigned prop)
{
    psc_evdev_set_bit(c->prop, prop, true);
}

static bool caps_has_abs(const psc_evdev_caps_t *c, unsigned code)
{
    return psc_evdev_bit(c->ev, EV_ABS) && psc_evdev_bit(c->abs, code) && c->abs_max[code] > c->abs_min[code];
}

static bool caps_has_key(const psc_evdev_caps_t *c, unsigned code)
{
    return psc_evdev_bit(c->ev, EV_KEY) && psc_evdev_bit(c->key, code);
}

unsigned psc_evdev_classify(const psc_evdev_caps_t *c, const psc_evdev_map_t *m)
{
    unsigned kinds = 0;
    bool mt = caps_has_abs(c, ABS_MT_SLOT) && caps_has_abs(c, ABS_MT_POSITION_X) &&
              caps_has_abs(c, ABS_MT_POSITION_Y);
    bool st = caps_has_abs(c, ABS_X) && caps_has_abs(c, ABS_Y) && caps_has_key(c, BTN_TOUCH);

    if ((mt || st) && !psc_evdev_bit(c->prop, INPUT_PROP_POINTER))
        kinds |= PSC_EVDEV_TOUCH;
    if (psc_evdev_bit(c->ev, EV_REL) && psc_evdev_bit(c->rel, REL_X) && psc_evdev_bit(c->rel, REL_Y) &&
        caps_has_key(c, BTN_LEFT))
        kinds |= PSC_EVDEV_MOUSE;
    if (!mt && !st && caps_has_abs(c, ABS_X) &&
        (caps_has_key(c, BTN_SOUTH) || caps_has_key(c, BTN_TRIGGER)))
        kinds |= PSC_EVDEV_GAMEPAD | (c->bustype != BUS_USB ? PSC_EVDEV_WIRELESS_GAMEPAD : 0u);
    if (psc_evdev_bit(c->ev, EV_KEY)) {
        for (unsigned code = 1; code < KEY_CNT; code++) {
            if (m->action[code] != 0 && psc_evdev_key_kind(code) == PSC_EVDEV_KEYBOARD && psc_evdev_bit(c->key, code)) {
                kinds |= PSC_EVDEV_KEYBOARD;
                break;
            }
        }
    }
    return kinds;
}

static const struct {
    const char *word;
    unsigned kind;
    const char *text;
} kind_names[] = {
    { "touch", PSC_EVDEV_TOUCH, "touch screen" },
    { "keyboard", PSC_EVDEV_KEYBOARD, "keyboard" },
    { "mouse", PSC_EVDEV_MOUSE, "mouse" },
    { "gamepad", PSC_EVDEV_GAMEPAD, "gamepad" },
    { "wireless_gamepad", PSC_EVDEV_WIRELESS_GAMEPAD, "gamepad not on USB" },
};

int psc_evdev_parse_kinds(const char *list, unsigned *kinds, const char *origin, const char *board_key, char *err,
                          size_t errlen)
{
    const char *p = list;

    *kinds = 0;
    for (;;) {
        const char *start, *end;
        size_t n, k;

        while (*p == ' ' || *p == '\t')
            p++;
        start = p;
        while (*p && *p != ',')
            p++;
        end = p;
        while (end > start && (end[-1] == ' ' || end[-1] == '\t'))
            end--;
        n = (size_t)(end - start);
        for (k = 0; k < sizeof kind_names / sizeof kind_names[0]; k++)
            if (strlen(kind_names[k].word) == n && strncmp(start, kind_names[k].word, n) == 0)
                break;
        if (k == sizeof kind_names / sizeof kind_names[0]) {
            psc_hal_error_set(err, errlen, "%s: %s: '%.*s' is not a kind of device (touch, keyboard, mouse, gamepad, "
                              "wireless_gamepad, separated by commas)", origin, board_key, (int)(n > 40 ? 40 : n), start);
            return -EINVAL;
        }
        *kinds |= kind_names[k].kind;
        if (*p == '\0')
            return 0;
        p++;
    }
}

void psc_evdev_describe_kinds(unsigned kinds, char *buf, size_t len)
{
    size_t used = 0;

    if (len == 0)
        return;
    buf[0] = '\0';
    for (size_t k = 0; k < sizeof kind_names / sizeof kind_names[0] && used < len; k++) {
        if (kinds & kind_names[k].kind) {
            int n = snprintf(buf + used, len - used, "%s%s", used ? ", " : "", kind_names[k].text);
            if (n < 0)
                break;
            used += (size_t)n;
        }
    }
}
