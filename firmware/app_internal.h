/* SPDX-License-Identifier: MIT */
/*
 * app_internal.h - the device program's state, shared by start-up and
 * shutdown (app.c) and the frame loop (frame_loop.c). Each part is its own
 * module's: devices.h, scene_list.h, kiosk.h, controls.h, motion.h, quality.h.
 */
#ifndef PSC_APP_INTERNAL_H
#define PSC_APP_INTERNAL_H

#include "app.h"
#include "controls.h"
#include "devices.h"
#include "frame_pacer.h"
#include "gestures.h"
#include "kiosk.h"
#include "motion.h"
#include "quality.h"
#include "scene/scene_list.h"
#include "scene/scene_fade.h"
#include "scene/scene_reload.h"
#include "dither/psc_dither.h"

struct psc_app {
    psc_board_config_t board;
    char board_path[PSC_BOARD_PATH_MAX + 64];
    char out_dir[PSC_BOARD_PATH_MAX];
    uint32_t capture_every;
    uint32_t max_frames;
    bool quiet;
    psc_cli_dump_t dumps[PSC_CLI_MAX_DUMPS];
    unsigned dump_count;
    char dump_error[300];      /* the first failed frame dump: the run ends non-zero */

    psc_devices_t dev;
    psc_scene_list_t scenes;
    psc_kiosk_t kiosk;
    psc_controls_t controls;
    psc_motion_t motion;
    psc_quality_config_t quality_cfg;
    psc_quality_t quality;
    psc_frame_pacer_t pacer;
    uint32_t scene_switches;
    char only_scene[PSC_BOARD_PATH_MAX];   /* --scene, or empty for the board's scene lines */
    psc_scene_reload_t reload;             /* SIGHUP: the scenes loaded again */
    uint32_t reloads, reload_failures;
    uint64_t run_start_us;                 /* for SIGUSR1's status line */
    uint32_t *frame_times_us;              /* psc_app_record_frame_times, or NULL */
    uint32_t frame_times_cap;
    psc_io_bands_t *bands;     /* the viewer's worker threads, started with the display */
    psc_gestures_t gestures;   /* mouse and touch on the picture */
    psc_scene_fade_t fade;     /* scene_fade_ms */
    psc_surface_t last_drawn;  /* where the last frame was drawn (a fade starts from it; pixels NULL: none yet) */
    /* display_dither on an RGB565 display: scenes draw 8 bits a channel here, and the frame loop
     * turns each frame into the back buffer's RGB565 through the 8 x 8 Bayer matrix (NULL: off) */
    psc_dither_565_t *dither565;
    psc_surface_t draw;        /* XRGB8888, the display's size (dither565 only) */
};

/**
 * Put scene i on screen with the camera at its home view: its limits and
 * the board's rates become the motion model's. 0, or -1 with err.
 */
int psc_app_enter_scene(psc_app_t *app, unsigned i, char *err, size_t errlen);

/** millidegrees (or per second) to bam in 64 bits, rounded to nearest: 720 deg/s is two turns. */
int64_t psc_app_bam_from_mdeg(int64_t mdeg);

#endif
