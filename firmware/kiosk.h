/* SPDX-License-Identifier: MIT */
/*
 * kiosk.h - what makes the device program a kiosk rather than a viewer:
 * attract mode (a slow turn after the idle time, handed back without a jump
 * when someone touches the controls, attract.h), the tour's hotspots
 * followed with select (hotspots.h), and the one-shot buttons: home, next
 * and previous scene. It decides; the frame loop carries the decision out.
 */
#ifndef PSC_KIOSK_H
#define PSC_KIOSK_H

#include <stdbool.h>
#include <stdint.h>

#include "attract.h"
#include "controls.h"
#include "hotspots.h"
#include "motion.h"

/** Scenes the back action can return through. */
#define PSC_KIOSK_HISTORY 16u

/** A scene left by a hotspot or the scene buttons, and the view it had. */
typedef struct {
    uint8_t scene;
    psc_bam_t yaw;
    int32_t pitch;
    psc_bam_t hfov;
} psc_kiosk_visit_t;

typedef struct {
    psc_attract_t attract;
    const psc_hotspot_t *hotspots;     /* the board's, or none with --scene */
    unsigned hotspot_count;
    bool quiet;                        /* no log lines */
    uint32_t attract_starts;           /* for the closing report */
    uint32_t hotspot_follows;
    uint32_t backs;
    psc_kiosk_visit_t history[PSC_KIOSK_HISTORY];   /* the oldest dropped when full */
    unsigned history_count;
} psc_kiosk_t;

/** A scene change the kiosk asks for this frame. */
typedef struct {
    unsigned scene;                    /* where to go */
    const psc_hotspot_t *via;          /* the hotspot followed (its view is where to look), or NULL */
    const psc_kiosk_visit_t *back;     /* back to a scene left before: the view it had, or NULL */
} psc_kiosk_go_t;

/** Start: attract after idle_ms without input (0 = never) turning at rate bam/s; now_us starts the idle time. */
void psc_kiosk_init(psc_kiosk_t *k, uint32_t idle_ms, int64_t rate, uint64_t now_us, const psc_hotspot_t *hotspots,
                    unsigned hotspot_count, bool quiet);

/**
 * Take this frame's one-shot presses from c: select follows the hotspot in
 * view (in a scene with places), home starts the glide home on m, next and
 * previous step through the scene_count scenes, back returns to the scene
 * left last (with the view it had; nothing when there is none). Returns true
 * with *go set when the scene is to change; a change other than back
 * remembers the scene left.
 */
bool psc_kiosk_requests(psc_kiosk_t *k, psc_controls_t *c, psc_motion_t *m, unsigned scene, unsigned scene_count,
                        bool places, psc_kiosk_go_t *go);

/** Follow link, the hotspot of an object tapped in scene (scene.ID.object ... hotspot=TARGET): to its scene, at its
 *  view when with_view, else at the scene's home; remembered for back. Always true. */
bool psc_kiosk_follow_link(psc_kiosk_t *k, const psc_motion_t *m, unsigned scene, const psc_hotspot_t *link,
                           bool with_view, psc_kiosk_go_t *go);

/**
 * A tap or click at pixel (x, y) of the frame showing view (width x height):
 * follows the hotspot there (psc_hotspot_pick_at, reach_px around its
 * marker) like select. True with *go set when there is one.
 */
bool psc_kiosk_tap(psc_kiosk_t *k, const psc_motion_t *m, unsigned scene, bool places, uint16_t width,
                   uint16_t height, int32_t x, int32_t y, int32_t reach_px, psc_kiosk_go_t *go);

/** Forget the scenes visited (a reload or a new scene list). */
void psc_kiosk_forget(psc_kiosk_t *k);

/**
 * Move the camera this frame: the person's input through the motion model,
 * or - after the idle time without any - attract mode's slow turn. activity
 * is a button event this frame; stick input counts too. Input stops
 * attract with the view where it is and the model at rest.
 */
void psc_kiosk_step_camera(psc_kiosk_t *k, psc_motion_t *m, const psc_motion_input_t *in, bool activity,
                           uint64_t now_us, uint32_t dt_us, uint32_t frame);

/**
 * The view a followed hotspot opens, brought inside the new scene's limits
 * (m's, set by entering that scene); home stays the scene's own default.
 */
void psc_kiosk_look_through(const psc_hotspot_t *h, psc_motion_t *m);

#endif
