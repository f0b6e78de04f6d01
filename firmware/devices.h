/* SPDX-License-Identifier: MIT */
/*
 * devices.h - the device program's devices, opened through the HAL from the
 * board file: clock, display, input, watchdog and camera (the last two
 * optional), the live camera's feed, and which of them are missing
 * (device_status.h). Opened in that order and closed in reverse.
 */
#ifndef PSC_DEVICES_H
#define PSC_DEVICES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "board_config.h"
#include "camera_feed.h"
#include "device_status.h"
#include "psc_hal_camera.h"
#include "psc_hal_clock.h"
#include "psc_hal_display.h"
#include "psc_hal_input.h"
#include "psc_hal_watchdog.h"

typedef struct {
    psc_hal_clock_t *clock;
    psc_hal_display_t *display;
    psc_hal_input_t *input;
    psc_hal_watchdog_t *watchdog;      /* NULL: none */
    psc_hal_camera_t *camera;          /* NULL: none */
    psc_hal_display_mode_t mode;
    psc_camera_feed_t feed;            /* the camera's frames as a map (camera scenes) */
    psc_device_status_t status;        /* what is missing, shown on screen */
} psc_devices_t;

/** What the command line adds to the board's device options. */
typedef struct {
    uint32_t capture_every;            /* the sim display's captures, 0 = none */
    const char *capture_dir;           /* where captures and the contact sheet go */
    const char *capture_every_origin;  /* "--frames-every" or the board file, for messages */
    const char *capture_dir_origin;
    const char *tour;                  /* the sim input's script, NULL = the board's */
    const char *tour_origin;
} psc_devices_extra_t;

/**
 * Open every device the board names. 0, or -1 with err naming the device
 * and the problem (what opened stays for psc_devices_close).
 */
int psc_devices_open(psc_devices_t *d, const psc_board_config_t *b, const psc_devices_extra_t *x, char *err,
                     size_t errlen);

/** Start the camera streaming, once the scenes are loaded. 0, or -1 with err. */
int psc_devices_start(psc_devices_t *d, const psc_board_config_t *b, char *err, size_t errlen);

/**
 * Once per frame: take the camera's newest frame into the feed and record
 * whether the camera is there.
 */
void psc_devices_poll_camera(psc_devices_t *d);

/** Close every device in the reverse order of open (a zeroed struct is fine). */
void psc_devices_close(psc_devices_t *d);

#endif
