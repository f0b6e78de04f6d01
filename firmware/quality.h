/* SPDX-License-Identifier: MIT */
/*
 * quality.h - adaptive rendering quality: while the view moves fast, render
 * cheaply (nearest-neighbour pixels, the LUT read every 8 or 16 pixels) to
 * keep the frame rate, since motion hides the difference; once it has been
 * calm for a few frames, return to bilinear filtering and the fine span.
 *
 * Units:
 *  - speed: thousandths of a view width per second (mvw/s): how fast the
 *    picture crosses the screen, independent of zoom. 1000 = the whole view
 *    width per second. Computed from yaw, pitch and hfov changes between two
 *    frames relative to the hfov (psc_quality_speed).
 *  - settle_frames: consecutive frames below the threshold before returning
 *    to the calm quality (hysteresis, so a slowing pan does not flicker).
 *  - span_log2: the viewer reads its LUT every 1 << span_log2 pixels.
 */
#ifndef PSC_QUALITY_H
#define PSC_QUALITY_H

#include <stdbool.h>
#include <stdint.h>
#include "viewer/psc_viewer.h"

/** The thresholds and the two qualities (from the board file). */
typedef struct {
    bool adaptive;             /* false: always the calm quality */
    uint32_t fast_speed;       /* mvw/s at or above which the view counts as fast */
    uint32_t settle_frames;    /* calm frames needed to leave the fast quality */
    psc_filter_t fast_filter;
    uint8_t fast_span_log2;
    psc_filter_t calm_filter;
    uint8_t calm_span_log2;
} psc_quality_config_t;

/** The state: which quality is in force and for how long it has been calm. */
typedef struct {
    bool fast;
    uint32_t calm_frames;
    uint32_t fast_frames_total;   /* frames rendered in the fast quality, for reports */
    uint32_t switches;            /* number of quality changes, for reports */
} psc_quality_t;

/** Start in the calm quality. */
void psc_quality_init(psc_quality_t *q);

/**
 * How fast the picture moved from view a to view b in dt_us, in mvw/s (see
 * the header comment); 0 when dt_us is 0. Saturates at UINT32_MAX.
 */
uint32_t psc_quality_speed(const psc_view_t *a, const psc_view_t *b, uint32_t dt_us);

/**
 * Account for one frame moving at speed (mvw/s) and return true when the
 * quality changed. Fast as soon as speed >= fast_speed; calm again after
 * settle_frames frames in a row below it.
 */
bool psc_quality_update(psc_quality_t *q, const psc_quality_config_t *cfg, uint32_t speed);

/** Write the quality in force into a view's filter and span_log2. */
void psc_quality_apply(const psc_quality_t *q, const psc_quality_config_t *cfg, psc_view_t *view);

#endif
