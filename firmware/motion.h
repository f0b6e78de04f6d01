/* SPDX-License-Identifier: MIT */
/*
 * motion.h - the view camera's motion: yaw, pitch and zoom driven by sticks
 * and buttons, with acceleration, inertia and limits. Integer only.
 *
 * Formats (every value says its unit in its name or comment):
 *  - yaw: psc_bam_t (2^32 per turn, wraps for free); pitch: int32_t bam
 *    (2^30 = +90 deg, > 0 looks up); hfov: psc_bam_t. As in psc_types.h.
 *  - rates: int64_t bam per second, Q0 (90 deg/s = 2^30). int64 because a
 *    full turn per second (2^32) does not fit 32 bits. hfov_rate < 0 zooms in.
 *  - acceleration: int64_t bam per second squared, Q0.
 *  - control input: Q1.15 per axis, -32768..32767 = -1.0..+1.0 (full stick).
 *  - time steps and half-lives: microseconds.
 *  - decay factors: Q16 (65536 = 1.0).
 *
 * Behaviour per step of dt:
 *  - an axis with input moves its rate toward input * rate_max by at most
 *    accel * dt (a stick pushed fully reaches full rate in rate_max/accel);
 *  - an axis without input coasts: its rate decays exponentially, halving
 *    every inertia_half_life, and stops below PSC_MOTION_STOP_RATE;
 *  - with pan_follows_zoom, pan rates scale with hfov / 90 deg, so the
 *    picture moves across the screen equally fast at every zoom;
 *  - pitch stays in [pitch_min, pitch_max], hfov in [hfov_min, hfov_max];
 *    hitting a limit zeroes that rate (no "pushing" into a wall);
 *  - psc_motion_home starts a glide to the home view: each axis closes the
 *    remaining distance exponentially (halving every home_half_life) and
 *    snaps when within PSC_MOTION_HOME_SNAP; any stick input cancels it.
 */
#ifndef PSC_MOTION_H
#define PSC_MOTION_H

#include <stdbool.h>
#include <stdint.h>
#include "base/psc_types.h"

/** Rates below this (0.05 deg/s) stop instead of decaying forever. */
#define PSC_MOTION_STOP_RATE ((int64_t)PSC_BAM_FROM_MDEG(50))
/** A home glide ends when every axis is this close (0.01 deg). */
#define PSC_MOTION_HOME_SNAP ((int64_t)PSC_BAM_FROM_MDEG(10))
/** The zoom at which pan rates are the configured ones (pan_follows_zoom). */
#define PSC_MOTION_PAN_REF_HFOV PSC_BAM_90

/** Limits and dynamics, in the units of the header comment. */
typedef struct {
    int64_t yaw_rate_max;          /* bam/s at full stick */
    int64_t pitch_rate_max;        /* bam/s */
    int64_t hfov_rate_max;         /* bam/s of hfov change */
    int64_t accel;                 /* bam/s^2, every axis */
    uint32_t inertia_half_life_us; /* coasting after release */
    uint32_t home_half_life_us;    /* the home glide */
    int32_t pitch_min, pitch_max;  /* bam, within -2^30..2^30 */
    psc_bam_t hfov_min, hfov_max;  /* bam */
    bool pan_follows_zoom;
} psc_motion_config_t;

/** Stick positions for one step, Q1.15: yaw > 0 right, pitch > 0 up, zoom > 0 in. */
typedef struct {
    int32_t yaw, pitch, zoom;
} psc_motion_input_t;

/** The camera's state. */
typedef struct {
    psc_motion_config_t cfg;
    psc_bam_t yaw;
    int32_t pitch;
    psc_bam_t hfov;
    int64_t yaw_rate, pitch_rate, hfov_rate;   /* bam/s */
    bool homing;
    psc_bam_t home_yaw;
    int32_t home_pitch;
    psc_bam_t home_hfov;
} psc_motion_t;

/**
 * Start at rest at the given view, which is also the home view. The view is
 * brought inside the limits first. cfg is copied.
 */
void psc_motion_init(psc_motion_t *m, const psc_motion_config_t *cfg, psc_bam_t yaw, int32_t pitch,
                     psc_bam_t hfov);

/** Begin gliding back to the home view (the "home" button). */
void psc_motion_home(psc_motion_t *m);

/**
 * Advance the camera by dt_us under the given stick input (see the header
 * comment). dt_us of 0 changes nothing; steps longer than a second are cut
 * to a second, so a stall (debugger, swap) does not fling the view.
 */
void psc_motion_step(psc_motion_t *m, const psc_motion_input_t *in, uint32_t dt_us);

/**
 * Adopt a view changed from outside (psc_viewer_clamp narrowing a partial
 * panorama): a rate that pushes against a corrected axis is zeroed so it
 * does not wind up behind the limit.
 */
void psc_motion_set_view(psc_motion_t *m, psc_bam_t yaw, int32_t pitch, psc_bam_t hfov);

/**
 * 2^(-dt/half_life) in Q16: the fraction of a rate left after coasting dt_us
 * with the given half-life. Exact to about 1 unit in the last place; 0 for
 * dt >= 16 half-lives; 65536 for dt 0. half_life_us must be > 0.
 */
uint32_t psc_motion_decay_q16(uint32_t dt_us, uint32_t half_life_us);

#endif
