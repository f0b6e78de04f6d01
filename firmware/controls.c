/* SPDX-License-Identifier: MIT */
/*
 * controls.c - input events to held buttons, stick positions and one-shot
 * requests (see controls.h).
 */
#include <string.h>

#include "controls.h"

void psc_controls_init(psc_controls_t *c)
{
    memset(c, 0, sizeof *c);
}

void psc_controls_set_stick_shape(psc_controls_t *c, uint32_t dead_zone_milli, uint32_t expo_milli)
{
    if (dead_zone_milli > 900u)
        dead_zone_milli = 900u;
    if (expo_milli > 1000u)
        expo_milli = 1000u;
    c->dead_zone_q15 = (int32_t)((dead_zone_milli * 32768u + 500u) / 1000u);
    c->expo_q15 = (int32_t)((expo_milli * 32768u + 500u) / 1000u);
}

int32_t psc_controls_shape_axis(const psc_controls_t *c, int32_t value)
{
    int64_t x = value < 0 ? -(int64_t)value : value, dz = c->dead_zone_q15, e = c->expo_q15, out;

    if (x > 32768)
        x = 32768;
    if (x <= dz)
        return 0;
    /* rescale (dz, 32768] onto (0, 32768]: continuous at the zone's edge */
    x = ((x - dz) * 32768 + (32768 - dz) / 2) / (32768 - dz);
    /* (1 - e) x + e x^3, all in Q15; exact identity when e = 0 */
    out = (x * (32768 - e) + ((x * x * x) >> 30) * e + 16384) >> 15;
    out = value < 0 ? -out : out;
    return (int32_t)(out < PSC_HAL_AXIS_MIN ? PSC_HAL_AXIS_MIN : out > PSC_HAL_AXIS_MAX ? PSC_HAL_AXIS_MAX : out);
}

static void controls_release_device(psc_controls_t *c, uint8_t dev)
{
    memset(c->held[dev], 0, sizeof c->held[dev]);
    memset(c->axis[dev], 0, sizeof c->axis[dev]);
}

void psc_controls_apply(psc_controls_t *c, const psc_hal_input_event_t *ev)
{
    uint8_t dev = ev->device;

    if (ev->type == PSC_HAL_INPUT_QUIT) {
        c->quit = true;
        return;
    }
    if (dev >= PSC_HAL_INPUT_MAX_DEVICES)
        return;
    switch (ev->type) {
    case PSC_HAL_INPUT_DEVICE_ARRIVE:
        c->present[dev] = true;
        controls_release_device(c, dev);
        break;
    case PSC_HAL_INPUT_DEVICE_LEAVE:
        c->present[dev] = false;
        controls_release_device(c, dev);
        break;
    case PSC_HAL_INPUT_BUTTON_DOWN:
    case PSC_HAL_INPUT_BUTTON_UP:
    case PSC_HAL_INPUT_BUTTON_LONG:
        if (ev->code == PSC_HAL_ACTION_NONE || ev->code >= PSC_HAL_ACTION_COUNT)
            break;
        if (ev->type == PSC_HAL_INPUT_BUTTON_DOWN) {
            /* count a press only on the edge, not a repeated DOWN */
            if (!c->held[dev][ev->code])
                c->pressed[ev->code]++;
            c->held[dev][ev->code] = true;
        } else if (ev->type == PSC_HAL_INPUT_BUTTON_UP) {
            c->held[dev][ev->code] = false;
        } else {
            c->long_pressed[ev->code]++;
        }
        break;
    case PSC_HAL_INPUT_AXIS:
        if (ev->code >= PSC_HAL_AXIS_COUNT)
            break;
        c->axis[dev][ev->code] = psc_controls_shape_axis(c, ev->value < PSC_HAL_AXIS_MIN ? PSC_HAL_AXIS_MIN
                                                        : ev->value > PSC_HAL_AXIS_MAX ? PSC_HAL_AXIS_MAX
                                                                                       : ev->value);
        break;
    case PSC_HAL_INPUT_QUIT:
    case PSC_HAL_INPUT_POINTER_DOWN:   /* gestures (gestures.c) take the pointer's events */
    case PSC_HAL_INPUT_POINTER_MOVE:
    case PSC_HAL_INPUT_POINTER_UP:
    case PSC_HAL_INPUT_WHEEL:
        break;
    }
}

static int32_t controls_saturate(int64_t v)
{
    return (int32_t)(v < PSC_HAL_AXIS_MIN ? PSC_HAL_AXIS_MIN : v > PSC_HAL_AXIS_MAX ? PSC_HAL_AXIS_MAX : v);
}

void psc_controls_motion_input(const psc_controls_t *c, psc_motion_input_t *out)
{
    int64_t yaw = 0, pitch = 0, zoom = 0;

    for (unsigned d = 0; d < PSC_HAL_INPUT_MAX_DEVICES; d++) {
        const bool *h = c->held[d];

        yaw += c->axis[d][PSC_HAL_AXIS_YAW];
        pitch += c->axis[d][PSC_HAL_AXIS_PITCH];
        zoom += c->axis[d][PSC_HAL_AXIS_ZOOM];
        yaw += (h[PSC_HAL_ACTION_PAN_RIGHT] - h[PSC_HAL_ACTION_PAN_LEFT]) * (int64_t)PSC_HAL_AXIS_MAX;
        pitch += (h[PSC_HAL_ACTION_LOOK_UP] - h[PSC_HAL_ACTION_LOOK_DOWN]) * (int64_t)PSC_HAL_AXIS_MAX;
        zoom += (h[PSC_HAL_ACTION_ZOOM_IN] - h[PSC_HAL_ACTION_ZOOM_OUT]) * (int64_t)PSC_HAL_AXIS_MAX;
    }
    out->yaw = controls_saturate(yaw);
    out->pitch = controls_saturate(pitch);
    out->zoom = controls_saturate(zoom);
}

bool psc_controls_take_press(psc_controls_t *c, psc_hal_action_t action)
{
    if ((unsigned)action >= PSC_HAL_ACTION_COUNT || c->pressed[action] == 0)
        return false;
    c->pressed[action]--;
    return true;
}

bool psc_controls_take_long_press(psc_controls_t *c, psc_hal_action_t action)
{
    if ((unsigned)action >= PSC_HAL_ACTION_COUNT || c->long_pressed[action] == 0)
        return false;
    c->long_pressed[action]--;
    return true;
}
