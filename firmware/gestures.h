/* SPDX-License-Identifier: MIT */
/*
 * gestures.h - a mouse or a touch screen on the picture, the way people
 * expect of panorama viewers (Pannellum, krpano, a phone's photo sphere):
 *  - grab-drag: the direction under the finger or pointer when it went down
 *    stays under it while it moves (view_geometry.h solves the view);
 *  - flick: a drag let go while still moving hands its speed to the motion
 *    model, which coasts it out with the board's inertia (motion.h);
 *  - pinch: two fingers; the field of view scales with the inverse of their
 *    distance (spread them to zoom in), about the view centre; the finger
 *    left down after a pinch grabs afresh;
 *  - wheel: each notch zooms by 2^(1/4) (four notches halve the field of
 *    view), the view centre kept;
 *  - tap: down and up within PSC_GESTURE_TAP_MS and the slop (8 pixels at
 *    240 lines, scaled with the display) is a tap at that pixel: the kiosk
 *    follows a hotspot there (kiosk.h).
 * The HAL's backends report contacts only (POINTER_* and WHEEL events,
 * psc_hal_input.h); this module owns what they mean, the same for the SDL
 * window, evdev touch screens and mice, and tours. Integer only; no
 * allocation.
 */
#ifndef PSC_GESTURES_H
#define PSC_GESTURES_H

#include <stdbool.h>
#include <stdint.h>

#include "motion.h"
#include "psc_hal_input.h"

#define PSC_GESTURE_TAP_MS 350u
/** A drag let go longer ago than this after its last movement does not fling. */
#define PSC_GESTURE_FLICK_IDLE_MS 80u

typedef struct {
    bool down;
    bool moved;            /* left the tap slop: a drag, never a tap */
    int32_t x, y;          /* where it is now */
    int32_t x0, y0;        /* where it went down */
    uint64_t t0_us;
} psc_gesture_contact_t;

typedef struct {
    uint16_t width, height;                 /* the display mode */
    int32_t slop_px;
    psc_gesture_contact_t contact[PSC_HAL_POINTER_MAX];
    unsigned down_count;
    /* grab: the direction held under contact grab_id */
    bool grabbing;
    uint8_t grab_id;
    psc_bam_t grab_yaw;
    int32_t grab_pitch;
    bool grab_dirty;                        /* the contact moved since the view was last solved */
    /* pinch: two contacts and the field of view at their first distance */
    bool pinching;
    uint8_t pinch_a, pinch_b;
    uint32_t pinch_dist0;
    psc_bam_t pinch_hfov0;
    /* flick: the view's speed while grabbed, bam/s, and when it last moved */
    int64_t vel_yaw, vel_pitch;
    uint64_t last_move_us, last_apply_us;
    psc_bam_t last_yaw;
    int32_t last_pitch;
    bool release_pending;                   /* the grab ended: fling at the next apply */
    int32_t wheel;                          /* notches not yet applied */
    bool tapped;
    int32_t tap_x, tap_y;
    uint32_t taps, drags, flicks, pinches;  /* for the closing report and tests */
} psc_gestures_t;

/** Start with no contact, for a width x height display. */
void psc_gestures_init(psc_gestures_t *g, uint16_t width, uint16_t height);

/**
 * Take one input event: true when it was a pointer or wheel event (consumed;
 * activity: attract mode stops). A DEVICE_LEAVE lifts the contacts without
 * a tap (any device: backends number contacts per input, one touch screen
 * at a time is what kiosks have). Needs the motion state to know the view a
 * grab starts from.
 */
bool psc_gestures_event(psc_gestures_t *g, const psc_hal_input_event_t *ev, const psc_motion_t *m);

/**
 * After the motion step of a frame at now_us: a grab or pinch sets the
 * view (rates zeroed, home glide cancelled), a released drag flings, wheel
 * notches zoom. True when the gestures moved the view this frame.
 */
bool psc_gestures_apply(psc_gestures_t *g, psc_motion_t *m, uint64_t now_us);

/** A tap since the last call: true with its pixel. */
bool psc_gestures_take_tap(psc_gestures_t *g, int32_t *x, int32_t *y);

/** Lift every contact (a scene change: a drag does not carry into the next scene). */
void psc_gestures_release_all(psc_gestures_t *g);

#endif
