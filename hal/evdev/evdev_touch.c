/* SPDX-License-Identifier: MIT */
/*
 * evdev_touch.c - touch screens: contacts as POINTER_DOWN / MOVE / UP.
 *
 * Multitouch protocol B (Documentation/input/multi-touch-protocol.rst): the
 * device keeps one slot per contact; ABS_MT_SLOT selects the slot the
 * following values are for, ABS_MT_TRACKING_ID >= 0 puts a new contact in it
 * and -1 lifts it, ABS_MT_POSITION_X/Y move it; only changed values are
 * sent. The slot number is the contact number (code) of the events: a
 * contact keeps its slot while it lasts. Slots beyond PSC_HAL_POINTER_MAX are
 * not reported. The kernel's single-touch emulation (ABS_X, ABS_Y,
 * BTN_TOUCH) of such a device is ignored.
 *
 * Single-touch screens (ABS_X, ABS_Y, BTN_TOUCH, no slots): contact 0, down
 * while BTN_TOUCH is.
 *
 * At SYN_REPORT, per contact: lifted (or replaced by a new tracking id in
 * the same frame) -> UP at its last reported position; new -> DOWN;
 * moved -> MOVE (only when its pixel changed). Positions are scaled from the
 * axis's min..max (absinfo) to 0..display size - 1, rounded to the nearest
 * pixel: min is pixel 0, max the last pixel.
 */
#include "evdev_internal.h"

void psc_evdev_touch_abs(psc_evdev_dev_t *d, unsigned code, int32_t value)
{
    if (d->mt) {
        psc_evdev_contact_t *c;

        if (code == ABS_MT_SLOT) {
            d->mt_slot = value;
            return;
        }
        if (d->mt_slot < 0 || d->mt_slot >= (int32_t)PSC_HAL_POINTER_MAX)
            return;
        c = &d->mt_new[d->mt_slot];
        if (code == ABS_MT_TRACKING_ID)
            c->id = value < 0 ? -1 : value;
        else if (code == ABS_MT_POSITION_X)
            c->x = value;
        else if (code == ABS_MT_POSITION_Y)
            c->y = value;
        return;
    }
    if (code == ABS_X)
        d->st_new.x = value;
    else if (code == ABS_Y)
        d->st_new.y = value;
}

void psc_evdev_touch_drop(psc_evdev_dev_t *d)
{
    for (unsigned i = 0; i < PSC_HAL_POINTER_MAX; i++)
        d->mt_new[i] = d->mt_now[i];
    d->st_new = d->st_now;
}

/* One contact's change between the last report and this one. */
static void touch_contact(psc_evdev_dev_t *d, unsigned n, const psc_evdev_contact_t *was, const psc_evdev_contact_t *is,
                          unsigned cx, unsigned cy)
{
    int32_t x = psc_evdev_scale_pixel(is->x, d->min[cx], d->max[cx], d->shared->display_width);
    int32_t y = psc_evdev_scale_pixel(is->y, d->min[cy], d->max[cy], d->shared->display_height);

    if (was->id >= 0 && is->id != was->id)
        psc_evdev_push(d, PSC_HAL_INPUT_POINTER_UP, (uint16_t)n, 0, d->px[n], d->py[n]);
    if (is->id < 0)
        return;
    if (is->id != was->id)
        psc_evdev_push(d, PSC_HAL_INPUT_POINTER_DOWN, (uint16_t)n, 0, x, y);
    else if (x != d->px[n] || y != d->py[n])
        psc_evdev_push(d, PSC_HAL_INPUT_POINTER_MOVE, (uint16_t)n, 0, x, y);
    else
        return;
    d->px[n] = (int16_t)x;
    d->py[n] = (int16_t)y;
}

void psc_evdev_touch_report(psc_evdev_dev_t *d)
{
    if (d->mt) {
        for (unsigned i = 0; i < PSC_HAL_POINTER_MAX; i++) {
            touch_contact(d, i, &d->mt_now[i], &d->mt_new[i], ABS_MT_POSITION_X, ABS_MT_POSITION_Y);
            d->mt_now[i] = d->mt_new[i];
        }
        return;
    }
    /* single touch: a contact while BTN_TOUCH is down (id 0) */
    d->st_new.id = psc_evdev_bit(d->key_new, BTN_TOUCH) ? 0 : -1;
    touch_contact(d, 0, &d->st_now, &d->st_new, ABS_X, ABS_Y);
    d->st_now = d->st_new;
}
