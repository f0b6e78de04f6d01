/* SPDX-License-Identifier: MIT */
/*
 * psc_usb_pad.c - gamepad reports to HAL input events (psc_usb_pad.h).
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "psc_usb_pad.h"

void psc_usb_map_default(psc_usb_map_t *map)
{
    memset(map, 0, sizeof *map);
    map->axis_kind[PSC_HAL_AXIS_YAW] = PSC_HID_AXIS_X;
    map->axis_kind[PSC_HAL_AXIS_PITCH] = PSC_HID_AXIS_Y;
    map->axis_invert[PSC_HAL_AXIS_PITCH] = true;
    map->axis_kind[PSC_HAL_AXIS_ZOOM] = PSC_HID_AXIS_RZ;
    map->axis_invert[PSC_HAL_AXIS_ZOOM] = true;
    map->button_action[0] = PSC_HAL_ACTION_HOME;
    map->button_action[1] = PSC_HAL_ACTION_NEXT_SCENE;
    map->button_action[2] = PSC_HAL_ACTION_PREV_SCENE;
    map->button_action[4] = PSC_HAL_ACTION_ZOOM_OUT;
    map->button_action[5] = PSC_HAL_ACTION_ZOOM_IN;
    map->hat_pans = true;
}

static const char *map_origin(const psc_hal_option_t *o)
{
    return o->origin != NULL ? o->origin : "(built-in)";
}

/* "12" -> 12 within 1..PSC_HID_MAX_BUTTONS, else 0. */
static unsigned map_button_number(const char *s)
{
    unsigned v = 0;

    if (*s == '\0' || *s == '0')
        return 0;
    for (; *s; s++) {
        if (*s < '0' || *s > '9')
            return 0;
        v = v * 10u + (unsigned)(*s - '0');
        if (v > PSC_HID_MAX_BUTTONS)
            return 0;
    }
    return v;
}

bool psc_usb_map_knows(const char *key)
{
    return key != NULL && (strncmp(key, "axis.", 5) == 0 || strncmp(key, "button.", 7) == 0 ||
                           strcmp(key, "hat") == 0);
}

int psc_usb_map_parse(psc_usb_map_t *map, const psc_hal_options_t *opts, char *err, size_t errlen)
{
    bool axes_cleared = false, buttons_cleared = false;

    for (size_t i = 0; opts != NULL && opts->items != NULL && i < opts->count; i++) {
        const psc_hal_option_t *o = &opts->items[i];
        const char *v = o->value != NULL ? o->value : "";

        if (o->key == NULL)
            continue;
        if (strncmp(o->key, "axis.", 5) == 0) {
            int axis = psc_hal_axis_parse(o->key + 5);
            bool invert = v[0] == '-';
            int kind = psc_hid_axis_kind_parse(invert ? v + 1 : v);

            if (axis < 0) {
                psc_hal_error_set(err, errlen, "%s: usb input option '%s': no logical axis '%s' (yaw, pitch, zoom)",
                                  map_origin(o), o->key, o->key + 5);
                return -EINVAL;
            }
            if (kind < 0 && !(strcmp(v, "none") == 0)) {
                psc_hal_error_set(err, errlen, "%s: usb input option '%s' must be a HID axis (x y z rx ry rz slider "
                                  "dial wheel throttle rudder accelerator brake, '-' to invert) or none, got '%s'",
                                  map_origin(o), o->key, v);
                return -EINVAL;
            }
            if (!axes_cleared) {   /* any axis line replaces the default axis map */
                for (unsigned a = 0; a < PSC_HAL_AXIS_COUNT; a++) {
                    map->axis_kind[a] = -1;
                    map->axis_invert[a] = false;
                }
                axes_cleared = true;
            }
            map->axis_kind[axis] = (int8_t)kind;
            map->axis_invert[axis] = kind >= 0 && invert;
        } else if (strncmp(o->key, "button.", 7) == 0) {
            unsigned n = map_button_number(o->key + 7);
            psc_hal_action_t action = psc_hal_action_parse(v);

            if (n == 0) {
                psc_hal_error_set(err, errlen, "%s: usb input option '%s': the button number must be 1 to %u",
                                  map_origin(o), o->key, (unsigned)PSC_HID_MAX_BUTTONS);
                return -EINVAL;
            }
            if (action == PSC_HAL_ACTION_NONE && strcmp(v, "none") != 0) {
                psc_hal_error_set(err, errlen, "%s: usb input option '%s' must be an action (pan_left pan_right "
                                  "look_up look_down zoom_in zoom_out home next_scene prev_scene select back) or "
                                  "none, got '%s'", map_origin(o), o->key, v);
                return -EINVAL;
            }
            if (!buttons_cleared) {   /* any button line replaces the default button map */
                memset(map->button_action, 0, sizeof map->button_action);
                buttons_cleared = true;
            }
            map->button_action[n - 1] = (uint8_t)action;
        } else if (strcmp(o->key, "hat") == 0) {
            if (strcmp(v, "pan") != 0 && strcmp(v, "none") != 0) {
                psc_hal_error_set(err, errlen, "%s: usb input option 'hat' must be pan or none, got '%s'",
                                  map_origin(o), v);
                return -EINVAL;
            }
            map->hat_pans = v[0] == 'p';
        }
    }
    return 0;
}

void psc_usb_pad_init(psc_usb_pad_t *pad, const psc_hid_gamepad_t *desc, const psc_usb_map_t *map,
                      uint8_t device, uint64_t now_us)
{
    memset(pad, 0, sizeof *pad);
    pad->desc = *desc;
    pad->device = device;
    for (unsigned a = 0; a < PSC_HAL_AXIS_COUNT; a++)
        pad->axis_index[a] = (int8_t)(map->axis_kind[a] < 0 ? -1
                                      : psc_hid_find_axis(desc, (psc_hid_axis_kind_t)map->axis_kind[a]));
    for (unsigned i = 0; i < PSC_HAL_ACTION_COUNT; i++)
        psc_hal_button_init(&pad->action[i], now_us);
}

static void pad_queue(psc_usb_pad_t *pad, psc_hal_event_queue_t *queue, psc_hal_input_type_t type, uint16_t code,
                      int32_t value, uint64_t t_us)
{
    psc_hal_input_event_t ev = { .type = type, .device = pad->device, .code = code, .value = value, .time_us = t_us };

    (void)psc_hal_event_queue_push(queue, &ev);   /* a full queue counts the loss itself */
}

static void pad_queue_edges(psc_usb_pad_t *pad, psc_hal_event_queue_t *queue, unsigned action,
                            const psc_hal_button_edge_t *edges, unsigned n)
{
    for (unsigned i = 0; i < n; i++)
        pad_queue(pad, queue, edges[i].type, (uint16_t)action, edges[i].type == PSC_HAL_INPUT_BUTTON_UP ? 0 : 1,
                  edges[i].time_us);
}

/* Q1.15 negated, keeping full deflection full: -(-32768) is 32767. */
static int32_t pad_invert(int32_t v)
{
    return v <= -32767 ? 32767 : -v;
}

int psc_usb_pad_report(psc_usb_pad_t *pad, const psc_usb_map_t *map, const psc_hal_button_timing_t *timing,
                       const uint8_t *data, size_t len, uint64_t now_us, psc_hal_event_queue_t *queue)
{
    bool held[PSC_HAL_ACTION_COUNT] = { false };
    psc_hal_button_edge_t edges[2];
    int rc = psc_hid_decode(&pad->desc, data, len, &pad->state);

    if (rc == -ENODATA) {
        pad->empty_reports++;
        return rc;
    }
    if (rc < 0) {
        pad->bad_reports++;
        return rc;
    }
    pad->reports++;
    for (unsigned a = 0; a < PSC_HAL_AXIS_COUNT; a++) {
        int32_t v;

        if (pad->axis_index[a] < 0)
            continue;
        v = pad->state.axis[pad->axis_index[a]];
        if (map->axis_invert[a])
            v = pad_invert(v);
        if (v != pad->axis_value[a]) {
            pad->axis_value[a] = v;
            pad_queue(pad, queue, PSC_HAL_INPUT_AXIS, (uint16_t)a, v, now_us);
        }
    }
    for (unsigned b = 0; b < PSC_HID_MAX_BUTTONS; b++)
        if ((pad->state.buttons >> b) & 1u)
            held[map->button_action[b] < PSC_HAL_ACTION_COUNT ? map->button_action[b] : 0] = true;
    if (map->hat_pans) {
        for (unsigned h = 0; h < pad->desc.hat_count; h++) {
            uint8_t bits = pad->state.hat[h];
            held[PSC_HAL_ACTION_LOOK_UP] |= (bits & PSC_HID_HAT_UP) != 0;
            held[PSC_HAL_ACTION_PAN_RIGHT] |= (bits & PSC_HID_HAT_RIGHT) != 0;
            held[PSC_HAL_ACTION_LOOK_DOWN] |= (bits & PSC_HID_HAT_DOWN) != 0;
            held[PSC_HAL_ACTION_PAN_LEFT] |= (bits & PSC_HID_HAT_LEFT) != 0;
        }
    }
    for (unsigned i = 1; i < PSC_HAL_ACTION_COUNT; i++) {   /* 0 is "none" */
        pad_queue_edges(pad, queue, i, edges, psc_hal_button_advance(&pad->action[i], timing, now_us, edges));
        psc_hal_button_set(&pad->action[i], held[i], now_us);
        pad_queue_edges(pad, queue, i, edges, psc_hal_button_advance(&pad->action[i], timing, now_us, edges));
    }
    return 0;
}

void psc_usb_pad_tick(psc_usb_pad_t *pad, const psc_hal_button_timing_t *timing, uint64_t now_us,
                      psc_hal_event_queue_t *queue)
{
    psc_hal_button_edge_t edges[2];

    for (unsigned i = 1; i < PSC_HAL_ACTION_COUNT; i++)
        pad_queue_edges(pad, queue, i, edges, psc_hal_button_advance(&pad->action[i], timing, now_us, edges));
}

psc_usb_next_t psc_usb_pad_transfer_done(psc_usb_pad_t *pad, const psc_usb_map_t *map,
                                         const psc_hal_button_timing_t *timing, psc_usb_xfer_status_t status,
                                         const uint8_t *data, size_t len, uint64_t now_us,
                                         psc_hal_event_queue_t *queue)
{
    switch (status) {
    case PSC_USB_XFER_COMPLETED:
        pad->errors_in_row = 0;
        (void)psc_usb_pad_report(pad, map, timing, data, len, now_us, queue);
        return PSC_USB_NEXT_RESUBMIT;
    case PSC_USB_XFER_TIMED_OUT:
        return PSC_USB_NEXT_RESUBMIT;   /* no report in time is not a failure */
    case PSC_USB_XFER_CANCELLED:
        return PSC_USB_NEXT_IDLE;
    case PSC_USB_XFER_NO_DEVICE:
        return PSC_USB_NEXT_GONE;
    case PSC_USB_XFER_OVERFLOW:
        pad->bad_reports++;
        break;
    case PSC_USB_XFER_STALL:
    case PSC_USB_XFER_ERROR:
        break;
    }
    if (++pad->errors_in_row >= PSC_USB_PAD_MAX_ERRORS)
        return PSC_USB_NEXT_GONE;
    return status == PSC_USB_XFER_STALL ? PSC_USB_NEXT_CLEAR_HALT : PSC_USB_NEXT_RESUBMIT;
}
