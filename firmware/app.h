/* SPDX-License-Identifier: MIT */
/*
 * app.h - the device program's runtime: start-up (board file, devices, scene
 * packs, every buffer), the frame loop, and shutdown, in that symmetric
 * order: psc_app_open / psc_app_run / psc_app_close.
 *
 * Frame loop, once per display frame:
 *   poll input -> controls -> select/home/scene requests (hotspots.h) ->
 *   motion step, or attract mode's turn after the idle time (attract.h) ->
 *   psc_viewer_clamp -> adaptive quality -> psc_viewer_render into the
 *   display's back buffer -> hotspot markers, missing devices -> present
 *   -> kick the watchdog -> sleep until the next frame time.
 * Nothing in the loop allocates: every buffer is sized at open from the
 * board (display mode) and the packs (map and table sizes).
 *
 * Times in the loop come from the HAL clock (deterministic on the sim
 * board); the wall-clock time in the stats is real time (CLOCK_MONOTONIC),
 * measured apart so a headless tour reports how fast the host rendered.
 */
#ifndef PSC_APP_H
#define PSC_APP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "board_config.h"
#include "cli.h"
#include "psc_hal_watchdog.h"

typedef struct psc_app psc_app_t;

/** What a run did, for the closing report and tests. */
typedef struct {
    uint32_t frames;              /* frames rendered and presented */
    uint64_t sim_time_us;         /* HAL clock time when the loop ended */
    uint64_t wall_time_us;        /* real time the loop took */
    uint32_t fast_frames;         /* frames rendered in the fast (cheap) quality */
    uint32_t quality_switches;
    uint32_t scene_switches;
    uint32_t attract_starts;      /* times attract mode began (attract.h) */
    uint32_t hotspot_follows;     /* hotspots followed with select (hotspots.h) */
    uint32_t reloads;             /* scene lists taken over after SIGHUP */
    uint32_t reload_failures;     /* reloads refused (the old scenes kept) */
    uint32_t status_reports;      /* status lines logged for SIGUSR1 */
    uint32_t capture_every;       /* the sim display's capture period, 0 = none */
    bool watchdog_known;          /* the watchdog fields below are filled */
    psc_hal_watchdog_status_t watchdog;
} psc_app_stats_t;

/**
 * Start up: read the board file, open clock, display, input, watchdog and
 * camera through the HAL, load every scene pack, size and allocate the
 * viewer workspace, place the camera at the first scene's default view.
 * Returns 0 with *out set, or -1 with err naming the file/line or device and
 * the problem (everything opened so far is closed again).
 */
int psc_app_open(const psc_cli_options_t *opt, psc_app_t **out, char *err, size_t errlen);

/**
 * Run the frame loop until the input sends QUIT (the sim tour's end) or
 * max_frames is reached. Returns 0, or -1 with err when a device or the
 * renderer failed; stats are filled either way.
 */
int psc_app_run(psc_app_t *app, psc_app_stats_t *stats, char *err, size_t errlen);

/**
 * Record each frame's wall-clock work (input to present, not the wait for
 * the next frame time) in microseconds into us[frame] for frames below cap,
 * from the next psc_app_run on (soak runs and benchmarks; the caller owns
 * the array, nothing is allocated). NULL stops recording.
 */
void psc_app_record_frame_times(psc_app_t *app, uint32_t *us, uint32_t cap);

/** The directory captures and the contact sheet go to ("" when none). */
const char *psc_app_out_dir(const psc_app_t *app);

/**
 * Ask a running psc_app_run to end after the frame in progress, as if the
 * input had sent QUIT. Async-signal-safe (it sets a sig_atomic_t), so the
 * program's SIGTERM/SIGINT handler calls it: systemd stopping the service
 * then restores the display's mode and tells the watchdog STOPPING=1.
 */
void psc_app_request_stop(void);

/**
 * Ask a running psc_app_run to load the scenes again (SIGHUP): they load
 * beside the current ones, which stay on screen, and take over between two
 * frames; if any fails the current ones stay and the log says why.
 * Async-signal-safe.
 */
void psc_app_request_reload(void);

/** Ask a running psc_app_run to log one status line (SIGUSR1). Async-signal-safe. */
void psc_app_request_status(void);

/** Close every device and free every buffer, in the reverse order of open (NULL is ignored). */
void psc_app_close(psc_app_t *app);

#endif
