/* SPDX-License-Identifier: MIT */
/*
 * sim_internal.h - what the simulated devices share among themselves and with
 * the backend descriptor (sim_backend.c). Not for the firmware: it talks to
 * the sim devices only through the generic HAL headers and psc_hal_sim.h.
 */
#ifndef PSC_SIM_INTERNAL_H
#define PSC_SIM_INTERNAL_H

#include "psc_hal_camera.h"
#include "psc_hal_clock.h"
#include "psc_hal_display.h"
#include "psc_hal_input.h"
#include "psc_hal_watchdog.h"

/** Open the deterministic clock (sim_clock.c). */
int psc_sim_clock_open(const psc_hal_clock_config_t *cfg, psc_hal_clock_t **out, char *err, size_t errlen);

/** Open the memory display with PNG capture (sim_display.c). */
int psc_sim_display_open(const psc_hal_display_config_t *cfg, psc_hal_display_t **out, char *err, size_t errlen);

/** Open the tour-script input (sim_input.c). */
int psc_sim_input_open(const psc_hal_input_config_t *cfg, psc_hal_input_t **out, char *err, size_t errlen);

/** Open the test-pattern camera (sim_camera.c). */
int psc_sim_camera_open(const psc_hal_camera_config_t *cfg, psc_hal_camera_t **out, char *err, size_t errlen);

/** Open the recording watchdog (sim_watchdog.c). */
int psc_sim_watchdog_open(const psc_hal_watchdog_config_t *cfg, psc_hal_watchdog_t **out, char *err, size_t errlen);

/**
 * Whether this build can capture (sim_capture_png.c with libpng; a build
 * without `sim` in its backends line has sim_capture_none.c instead).
 */
bool psc_sim_capture_available(void);

/** Write one captured frame as a PNG (sim_capture_png.c). 0, or -1 with err. */
int psc_sim_capture_write(const char *path, const psc_surface_t *s, char *err, size_t errlen);

/**
 * Build a contact sheet of a run of `frames` frames captured every `every`
 * frames in capture_dir (sim_capture_sheet.c) and write it to out_path;
 * *thumbs receives how many frames it shows. 0, or -1 with err naming the
 * capture or output file and the problem (a missing capture is an error:
 * the sheet must show what the run produced).
 */
int psc_sim_contact_sheet_write(const char *capture_dir, uint32_t frames, uint32_t every, const char *out_path,
                                uint32_t *thumbs, char *err, size_t errlen);

/**
 * Move a sim clock forward to t_us (never back). Returns false, and does
 * nothing, when clk is not a sim clock: the sim display may be paired with a
 * real clock, and then time simply runs by itself.
 */
bool psc_sim_clock_advance_to(psc_hal_clock_t *clk, uint64_t t_us);

#endif
