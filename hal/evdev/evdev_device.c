/* SPDX-License-Identifier: MIT */
/*
 * evdev_device.c - one input device's event stream into HAL events.
 *
 * The kernel sends a device's changes in frames closed by SYN_REPORT (all
 * of a frame happened at once: two fingers moving, a key and the cursor).
 * Values are collected in the *_new state until SYN_REPORT, which compares
 * them with the *_now state, pushes the differences as events stamped with
 * the poll's time, and makes new the current state.
 *
 * SYN_DROPPED: the kernel's buffer overflowed and events were lost. What
 * was collected since the last SYN_REPORT is thrown away (new = now); the
 * backend then reads libevdev's resync (LIBEVDEV_READ_FLAG_SYNC): events
 * that take the device's state from what libevdev had to what the kernel has
 * now, ending in SYN_REPORT, which reports the difference like any frame. A
 * key released during the gap gives its UP; a finger lifted gives its UP.
 */
#include <string.h>

#include "evdev_internal.h"

/* The pad axes kept, by ABS code: index in pad_now/pad_new, or -1. */
static int device_pad_index(unsigned code)
{
    switch (code) {
    case ABS_X: return 0;
    case ABS_Y: return 1;
    case ABS_Z: return 2;
    case ABS_RX: return 3;
    case ABS_RY: return 4;
    case ABS_RZ: return 5;
    case ABS_HAT0X: return 6;
    case ABS_HAT0Y: return 7;
    default: return -1;
    }
}

int32_t psc_evdev_scale_pixel(int32_t raw, int32_t min, int32_t max, uint16_t size)
{
    int64_t range = (int64_t)max - min, v;

    if (raw < min)
        raw = min;
    if (raw > max)
        raw = max;
    if (size == 0 || range <= 0) {
        v = (int64_t)raw - min;
        return (int32_t)(v > INT16_MAX ? INT16_MAX : v);
    }
    /* min -> 0, max -> size - 1, to the nearest pixel (ties up) */
    v = ((int64_t)(raw - (int64_t)min) * (size - 1) * 2 + range) / (2 * range);
    return (int32_t)v;
}

int32_t psc_evdev_scale_q15(int32_t raw, int32_t min, int32_t max)
{
    int64_t range = (int64_t)max - min, num, q;

    if (range <= 0)
        return 0;
    if (raw < min)
        raw = min;
    if (raw > max)
        raw = max;
    /* centre (min + max) / 2 -> 0, ends -> +-32768, to nearest (ties away from 0) */
    num = (2 * ((int64_t)raw - min) - range) * 32768;
    q = (num >= 0 ? num + range / 2 : num - range / 2) / range;
    return (int32_t)(q < PSC_HAL_AXIS_MIN ? PSC_HAL_AXIS_MIN : q > PSC_HAL_AXIS_MAX ? PSC_HAL_AXIS_MAX : q);
}

void psc_evdev_push(psc_evdev_dev_t *d, psc_hal_input_type_t type, uint16_t code, int32_t value, int32_t x, int32_t y)
{
    psc_hal_input_event_t ev = { .type = type, .device = d->slot, .code = code, .value = value,
                                 .x = (int16_t)(x < INT16_MIN ? INT16_MIN : x > INT16_MAX ? INT16_MAX : x),
                                 .y = (int16_t)(y < INT16_MIN ? INT16_MIN : y > INT16_MAX ? INT16_MAX : y),
                                 .time_us = d->t_us };

    (void)psc_hal_event_queue_push(d->queue, &ev);   /* a full queue counts the loss itself */
}

void psc_evdev_dev_init(psc_evdev_dev_t *d, const psc_evdev_shared_t *shared, const psc_evdev_caps_t *caps,
                        unsigned kinds, uint8_t slot, uint64_t t_us)
{
    memset(d, 0, sizeof *d);
    d->shared = shared;
    d->slot = slot;
    d->kinds = kinds;
    d->t_us = t_us;
    memcpy(d->min, caps->abs_min, sizeof d->min);
    memcpy(d->max, caps->abs_max, sizeof d->max);
    d->mt = psc_evdev_bit(caps->abs, ABS_MT_SLOT) && psc_evdev_bit(caps->abs, ABS_MT_POSITION_X);
    d->pad_triggers = psc_evdev_bit(caps->abs, ABS_RX) && psc_evdev_bit(caps->abs, ABS_RY);
    for (unsigned a = 0; a < PSC_HAL_ACTION_COUNT; a++)
        psc_hal_button_init(&d->button[a], t_us);
    for (unsigned i = 0; i < PSC_HAL_POINTER_MAX; i++)
        d->mt_now[i] = d->mt_new[i] = (psc_evdev_contact_t){ -1, 0, 0 };
    d->st_now = d->st_new = (psc_evdev_contact_t){ -1, 0, 0 };
    d->cursor_x = shared->display_width / 2;
    d->cursor_y = shared->display_height / 2;
    /* sticks rest at their centre, triggers at their minimum: as read before any event */
    for (unsigned code = 0; code < ABS_CNT; code++) {
        int i = device_pad_index(code);
        if (i >= 0)
            d->pad_now[i] = d->pad_new[i] = (code == ABS_HAT0X || code == ABS_HAT0Y) ? 0
                                          : (d->pad_triggers && (code == ABS_Z || code == ABS_RZ))
                                              ? d->min[code]
                                              : d->min[code] + (d->max[code] - d->min[code]) / 2;
    }
}

static void device_report(psc_evdev_dev_t *d)
{
    if (d->kinds & PSC_EVDEV_TOUCH)
        psc_evdev_touch_report(d);
    if (d->kinds & PSC_EVDEV_MOUSE)
        psc_evdev_mouse_report(d);
    if (d->kinds & PSC_EVDEV_GAMEPAD)
        psc_evdev_pad_report(d);
    psc_evdev_keys_report(d);   /* last: the others read BTN_TOUCH and BTN_LEFT from key_new against key_now */
}

static void device_drop(psc_evdev_dev_t *d)
{
    memcpy(d->key_new, d->key_now, sizeof d->key_new);
    psc_evdev_touch_drop(d);
    d->rel_x = d->rel_y = d->wheel = 0;
    memcpy(d->pad_new, d->pad_now, sizeof d->pad_new);
}

void psc_evdev_dev_feed(psc_evdev_dev_t *d, const struct input_event *ev, uint64_t t_us, psc_hal_event_queue_t *q)
{
    int i;

    d->queue = q;
    d->t_us = t_us;
    switch (ev->type) {
    case EV_SYN:
        if (ev->code == SYN_REPORT)
            device_report(d);
        else if (ev->code == SYN_DROPPED)
            device_drop(d);
        break;
    case EV_KEY:
        if (ev->code < KEY_CNT && ev->value != 2)   /* 2: autorepeat */
            psc_evdev_set_bit(d->key_new, ev->code, ev->value != 0);
        break;
    case EV_REL:
        if (ev->code == REL_X)
            d->rel_x += ev->value;
        else if (ev->code == REL_Y)
            d->rel_y += ev->value;
        else if (ev->code == REL_WHEEL)
            d->wheel += ev->value;
        break;
    case EV_ABS:
        if (ev->code >= ABS_CNT)
            break;
        if (d->kinds & PSC_EVDEV_TOUCH)
            psc_evdev_touch_abs(d, ev->code, ev->value);
        else if ((d->kinds & PSC_EVDEV_GAMEPAD) && (i = device_pad_index(ev->code)) >= 0)
            d->pad_new[i] = ev->value;
        break;
    default:
        break;
    }
}
