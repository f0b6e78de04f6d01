/* SPDX-License-Identifier: MIT */
/*
 * controls.h - what the person at the kiosk is doing, built from HAL input
 * events: which buttons are held, where each stick is, which devices are
 * plugged in, and the one-shot requests (home, next/previous scene, quit).
 *
 * Formats: axis positions Q1.15 (-32768..32767 = -1.0..+1.0), as in
 * psc_hal_input.h. Held direction buttons count as a full stick on their
 * axis (pan_right = yaw +1.0, look_up = pitch +1.0, zoom_in = zoom +1.0);
 * sticks and buttons of every device add up, saturating at full deflection.
 * A device that leaves releases everything it held, so an unplugged gamepad
 * never leaves the view spinning.
 *
 * Stick shaping (board keys stick_dead_zone, stick_expo; both 0 = off, the
 * default, so scripted tours stay exact): every AXIS value first loses a
 * dead zone around the centre, the rest rescaled so that the edge of the
 * zone is 0 and full deflection stays full (no jump); then the response
 * curve blends linear and cubic, out = (1 - e) x + e x^3, fine control near
 * the centre and full speed at the edge. Integer Q1.15 throughout.
 */
#ifndef PSC_CONTROLS_H
#define PSC_CONTROLS_H

#include <stdbool.h>
#include <stdint.h>
#include "motion.h"
#include "psc_hal_input.h"

typedef struct {
    bool present[PSC_HAL_INPUT_MAX_DEVICES];
    bool held[PSC_HAL_INPUT_MAX_DEVICES][PSC_HAL_ACTION_COUNT];
    int32_t axis[PSC_HAL_INPUT_MAX_DEVICES][PSC_HAL_AXIS_COUNT];
    uint32_t pressed[PSC_HAL_ACTION_COUNT];   /* presses not yet taken */
    uint32_t long_pressed[PSC_HAL_ACTION_COUNT];
    bool quit;
    int32_t dead_zone_q15;    /* 0..29491 (0.9) */
    int32_t expo_q15;         /* 0..32768 (1.0) */
} psc_controls_t;

/** Nothing held, no device present, no stick shaping. */
void psc_controls_init(psc_controls_t *c);

/**
 * Set the stick shaping from the board's values in thousandths:
 * dead_zone_milli 0..900 of full deflection, expo_milli 0..1000 (larger
 * values are clamped). Applies to AXIS events from then on.
 */
void psc_controls_set_stick_shape(psc_controls_t *c, uint32_t dead_zone_milli, uint32_t expo_milli);

/** A Q1.15 stick value through the dead zone and response curve (see the header). */
int32_t psc_controls_shape_axis(const psc_controls_t *c, int32_t value);

/**
 * Apply one input event. Events with an out-of-range device, action or axis
 * are ignored (a backend bug must not index outside the tables).
 */
void psc_controls_apply(psc_controls_t *c, const psc_hal_input_event_t *ev);

/** The combined stick input for the motion model (see the header comment). */
void psc_controls_motion_input(const psc_controls_t *c, psc_motion_input_t *out);

/**
 * True, once per press, if action was pressed (BUTTON_DOWN) since the last
 * call for it: edge-triggered commands like "home" use this so a held
 * button does not repeat.
 */
bool psc_controls_take_press(psc_controls_t *c, psc_hal_action_t action);

/** Like psc_controls_take_press for long presses (BUTTON_LONG). */
bool psc_controls_take_long_press(psc_controls_t *c, psc_hal_action_t action);

#endif
