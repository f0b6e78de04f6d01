/* SPDX-License-Identifier: MIT */
/*
 * device_status.h - which configured devices are missing, shown on screen
 * and told to the supervisor, so a kiosk with an unplugged camera or gamepad
 * keeps running and says what is wrong instead of failing or freezing.
 *
 * States: the camera is OK (streaming or opening), ABSENT (configured but
 * never seen since start-up) or LOST (it delivered frames, then went away);
 * an input device slot is LOST after a DEVICE_LEAVE until it arrives again;
 * the input source as a whole FAILED when its poll returned an error.
 * Indication: a black box in the top-right corner with one line per problem
 * in amber ("NO CAMERA", "CAMERA LOST", "INPUT 2 LOST" (devices counted from 1), "INPUT FAILED"),
 * drawn over the rendered frame with integers only (overlay_font.h); the
 * font scale is the display height / 240 (at least 1). Nothing is drawn
 * while every device is present, so frames stay bit-exact with the viewer's.
 */
#ifndef PSC_DEVICE_STATUS_H
#define PSC_DEVICE_STATUS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "psc_hal_input.h"
#include "base/psc_types.h"

#define PSC_DEVICE_STATUS_MAX_LINES 4u
#define PSC_DEVICE_STATUS_LINE_MAX 24u

typedef enum {
    PSC_DEVICE_OK = 0,
    PSC_DEVICE_ABSENT,
    PSC_DEVICE_LOST
} psc_device_state_t;

typedef struct {
    bool camera_configured;
    psc_device_state_t camera;
    bool input_lost[PSC_HAL_INPUT_MAX_DEVICES];
    bool input_failed;
} psc_device_status_t;

/** Everything present; camera_configured says whether the board has a camera. */
void psc_device_status_init(psc_device_status_t *st, bool camera_configured);

/**
 * Record the camera's state from a dequeue result: 0 or -EAGAIN -> OK,
 * -ENODEV (or any other error) -> LOST if a frame was ever received
 * (had_frames), else ABSENT. Returns true when the state changed.
 */
bool psc_device_status_camera(psc_device_status_t *st, int dequeue_rc, bool had_frames);

/** Record DEVICE_ARRIVE / DEVICE_LEAVE events (others are ignored). True when something changed. */
bool psc_device_status_input_event(psc_device_status_t *st, const psc_hal_input_event_t *ev);

/** Record whether the input source's poll is failing. True when that changed. */
bool psc_device_status_input_failed(psc_device_status_t *st, bool failed);

/** True when nothing is missing (then nothing is drawn). */
bool psc_device_status_all_present(const psc_device_status_t *st);

/** The indication's lines, upper case, at most PSC_DEVICE_STATUS_MAX_LINES; returns how many. */
unsigned psc_device_status_lines(const psc_device_status_t *st,
                                 char lines[PSC_DEVICE_STATUS_MAX_LINES][PSC_DEVICE_STATUS_LINE_MAX]);

/**
 * One line for logs and the supervisor (systemd STATUS=): "all devices
 * present" or the problems joined, e.g. "camera lost, input 2 lost".
 */
void psc_device_status_text(const psc_device_status_t *st, char *buf, size_t len);

/** Draw the indication into s (RGB565 or XRGB8888) when something is missing. */
void psc_device_status_draw(const psc_device_status_t *st, const psc_surface_t *s);

#endif
