/* SPDX-License-Identifier: MIT */
/*
 * evdev_pad.c - the axes of a gamepad the kernel drives (xpad, hid-generic,
 * hid-playstation, ...), in the kernel's gamepad layout
 * (Documentation/input/gamepad.rst):
 *
 *   yaw    left stick ABS_X (right positive)
 *   pitch  left stick ABS_Y, inverted (the kernel's Y grows downwards)
 *   zoom   right stick ABS_RY pushed up, plus the right trigger ABS_RZ,
 *          minus the left trigger ABS_Z; a pad without ABS_RX/ABS_RY (a
 *          plain HID joystick, whose right stick is ABS_Z/ABS_RZ) zooms by
 *          ABS_RZ pushed up instead
 *   hat    ABS_HAT0X/Y as pan_left/pan_right, look_up/look_down buttons
 *
 * Sticks are scaled from their absinfo min..max to Q1.15 (min -> -32768, the
 * centre (min + max) / 2 -> 0, max -> 32767), raw, with no dead zone: the
 * firmware's stick_dead_zone and stick_expo shape every device alike.
 * Triggers rest at their minimum: min..max -> 0..32767. The buttons are in
 * the key map (evdev_keys.c).
 */
#include "evdev_internal.h"

enum { PAD_X, PAD_Y, PAD_Z, PAD_RX, PAD_RY, PAD_RZ, PAD_HX, PAD_HY };

static int32_t pad_neg(int32_t v)
{
    return v <= -PSC_HAL_AXIS_MAX ? PSC_HAL_AXIS_MAX : -v;
}

/* A trigger: min..max onto 0..32767, rounded. */
static int32_t pad_trigger(int32_t raw, int32_t min, int32_t max)
{
    int64_t range = (int64_t)max - min;

    if (range <= 0)
        return 0;
    if (raw < min)
        raw = min;
    if (raw > max)
        raw = max;
    return (int32_t)((((int64_t)raw - min) * PSC_HAL_AXIS_MAX * 2 + range) / (2 * range));
}

static void pad_axis(psc_evdev_dev_t *d, psc_hal_axis_t axis, int64_t v)
{
    int32_t q = (int32_t)(v < PSC_HAL_AXIS_MIN ? PSC_HAL_AXIS_MIN : v > PSC_HAL_AXIS_MAX ? PSC_HAL_AXIS_MAX : v);

    if (d->axis[axis] == q)
        return;
    d->axis[axis] = q;
    psc_evdev_push(d, PSC_HAL_INPUT_AXIS, (uint16_t)axis, q, 0, 0);
}

/* A hat direction: -1, 0 or +1 on one of its axes, as two buttons. */
static void pad_hat(psc_evdev_dev_t *d, int32_t was, int32_t is, unsigned neg, unsigned pos)
{
    int32_t w = was < 0 ? -1 : was > 0, i = is < 0 ? -1 : is > 0;

    if (w == i)
        return;
    if (w != 0)
        psc_evdev_press(d, w < 0 ? neg : pos, false);
    if (i != 0)
        psc_evdev_press(d, i < 0 ? neg : pos, true);
}

void psc_evdev_pad_report(psc_evdev_dev_t *d)
{
    const int32_t *v = d->pad_new;
    int64_t zoom;

    pad_axis(d, PSC_HAL_AXIS_YAW, psc_evdev_scale_q15(v[PAD_X], d->min[ABS_X], d->max[ABS_X]));
    pad_axis(d, PSC_HAL_AXIS_PITCH, pad_neg(psc_evdev_scale_q15(v[PAD_Y], d->min[ABS_Y], d->max[ABS_Y])));
    if (d->pad_triggers) {
        zoom = (int64_t)pad_neg(psc_evdev_scale_q15(v[PAD_RY], d->min[ABS_RY], d->max[ABS_RY])) +
               pad_trigger(v[PAD_RZ], d->min[ABS_RZ], d->max[ABS_RZ]) -
               pad_trigger(v[PAD_Z], d->min[ABS_Z], d->max[ABS_Z]);
    } else {
        zoom = d->max[ABS_RZ] > d->min[ABS_RZ]
                   ? pad_neg(psc_evdev_scale_q15(v[PAD_RZ], d->min[ABS_RZ], d->max[ABS_RZ]))
                   : 0;
    }
    pad_axis(d, PSC_HAL_AXIS_ZOOM, zoom);
    pad_hat(d, d->pad_now[PAD_HX], v[PAD_HX], PSC_HAL_ACTION_PAN_LEFT, PSC_HAL_ACTION_PAN_RIGHT);
    pad_hat(d, d->pad_now[PAD_HY], v[PAD_HY], PSC_HAL_ACTION_LOOK_UP, PSC_HAL_ACTION_LOOK_DOWN);
    for (unsigned i = 0; i < PSC_EVDEV_PAD_AXES; i++)
        d->pad_now[i] = d->pad_new[i];
}
