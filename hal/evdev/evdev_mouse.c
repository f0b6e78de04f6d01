/* SPDX-License-Identifier: MIT */
/*
 * evdev_mouse.c - a mouse as a pointer: a virtual cursor that starts at the
 * display's centre and moves by REL_X/REL_Y counts (one count one pixel),
 * kept on the display. While BTN_LEFT is held the cursor is contact 0:
 * POINTER_DOWN where the button went down, POINTER_MOVE as it moves,
 * POINTER_UP where it was let go (the firmware makes grab-drag of it).
 * REL_WHEEL notches are WHEEL events at the cursor (> 0: away from the user).
 * The kernel sends REL_WHEEL_HI_RES beside REL_WHEEL; only whole notches are
 * used.
 */
#include "evdev_internal.h"

static int32_t mouse_clamp(int64_t v, uint16_t size)
{
    int64_t hi = size > 0 ? (int64_t)size - 1 : INT16_MAX;

    return (int32_t)(v < 0 ? 0 : v > hi ? hi : v);
}

void psc_evdev_mouse_report(psc_evdev_dev_t *d)
{
    bool was = psc_evdev_bit(d->key_now, BTN_LEFT), is = psc_evdev_bit(d->key_new, BTN_LEFT);
    int32_t x = mouse_clamp((int64_t)d->cursor_x + d->rel_x, d->shared->display_width);
    int32_t y = mouse_clamp((int64_t)d->cursor_y + d->rel_y, d->shared->display_height);
    bool moved = x != d->cursor_x || y != d->cursor_y;

    d->cursor_x = x;
    d->cursor_y = y;
    d->rel_x = d->rel_y = 0;
    if (is && !was)
        psc_evdev_push(d, PSC_HAL_INPUT_POINTER_DOWN, 0, 0, x, y);
    else if (is && moved)
        psc_evdev_push(d, PSC_HAL_INPUT_POINTER_MOVE, 0, 0, x, y);
    else if (!is && was)
        psc_evdev_push(d, PSC_HAL_INPUT_POINTER_UP, 0, 0, x, y);
    if (d->wheel != 0)
        psc_evdev_push(d, PSC_HAL_INPUT_WHEEL, 0, d->wheel, x, y);
    d->wheel = 0;
}
