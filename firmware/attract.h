/* SPDX-License-Identifier: MIT */
/*
 * attract.h - attract mode: a kiosk nobody has touched for a while slowly
 * turns on its own, so passers-by see that it is alive, and hands control
 * back the instant someone touches it.
 *
 * Behaviour (times on the HAL clock, so it is exact on the sim board):
 *  - the idle timer restarts at every user input (psc_attract_input; the
 *    firmware calls it for every button event and every frame a stick is
 *    off centre after the dead zone - a device arriving or leaving is not
 *    a person);
 *  - attract starts on the first update at or after last input + idle time
 *    (idle time 0 disables it), from the view on screen at that moment;
 *  - while active, the view is a closed-form function of the time since the
 *    start: yaw = start yaw + rate x t (any length of idle time, no drift
 *    from frame to frame), pitch = default pitch + (start pitch - default
 *    pitch) x 2^(-t / PSC_ATTRACT_PITCH_HALF_LIFE_US); the zoom is left as
 *    it was;
 *  - input stops it at once: the view stays where attract left it and the
 *    motion model continues from there at rest (no jump, no left-over spin).
 * Units: yaw as psc_bam_t, pitch int32_t bam (as motion.h), rate int64_t bam
 * per second (signed: < 0 turns left), times in microseconds.
 */
#ifndef PSC_ATTRACT_H
#define PSC_ATTRACT_H

#include <stdbool.h>
#include <stdint.h>
#include "base/psc_types.h"

/** How fast the pitch settles back to the scene's default while attracting (halves every 1.5 s). */
#define PSC_ATTRACT_PITCH_HALF_LIFE_US 1500000u

typedef struct {
    uint64_t idle_us;          /* 0 = attract mode off */
    int64_t rate;              /* bam/s */
    uint64_t last_input_us;    /* when the idle time started */
    bool active;
    uint64_t start_us;         /* when attract began (valid while active) */
    psc_bam_t start_yaw;
    int32_t start_pitch;
} psc_attract_t;

/**
 * Set up attract mode: idle_ms without input before it starts (0 = never),
 * rate in bam per second. now_us starts the first idle period (the kiosk
 * switched on counts as an input).
 */
void psc_attract_init(psc_attract_t *a, uint32_t idle_ms, int64_t rate, uint64_t now_us);

/**
 * A person did something at now_us: attract stops if it was running and
 * the idle time starts again. Returns true when this stopped attract (the
 * caller then takes the view on screen as the motion model's, at rest).
 */
bool psc_attract_input(psc_attract_t *a, uint64_t now_us);

/**
 * Once per frame before moving the camera: start attract when the idle time
 * has run out, taking (yaw, pitch) - the view on screen now - as its start.
 * Returns whether attract drives the view this frame.
 */
bool psc_attract_update(psc_attract_t *a, uint64_t now_us, psc_bam_t yaw, int32_t pitch);

/**
 * The attract view at now_us (>= the start; earlier times count as the
 * start) easing the pitch toward default_pitch. Only meaningful while active.
 */
void psc_attract_view(const psc_attract_t *a, uint64_t now_us, int32_t default_pitch, psc_bam_t *yaw,
                      int32_t *pitch);

#endif
