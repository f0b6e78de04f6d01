/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_sim.h - what the simulated board offers beyond the generic HAL, for
 * tests.
 *
 * The sim backend ("sim" in a board file) provides every device kind:
 *   clock     starts at 0 us; each display present moves it to exactly
 *             presents * 10^9 / frame_rate_mhz us; sleep_until jumps.
 *   display   buffer_count buffers in memory (stride = width * bytes per
 *             pixel rounded up to 64 bytes, like a DRM dumb buffer pitch).
 *             Options: capture_dir (directory, created if missing),
 *             capture_every (K >= 0; 0 = never): after presenting frame n
 *             (0-based) with n % K == 0 it writes the frame to
 *             psc_sim_capture_path(capture_dir, n); contact_sheet (a
 *             PNG path): when the display closes, a grid of the captured
 *             frames, labelled with their numbers, is written there.
 *   input     a tour script (psc_sim_tour.h). Option: script (file path,
 *             required). Long presses use the config's long_press_ms.
 *   camera    an equirectangular test pattern (psc_sim_pattern_fill), a new
 *             frame every frame period of the camera's own rate.
 *   watchdog  records kicks on the sim clock and the longest gap between them.
 */
#ifndef PSC_HAL_SIM_H
#define PSC_HAL_SIM_H

#include <stddef.h>
#include <stdint.h>
#include "base/psc_types.h"

/**
 * The file name the sim display captures frame n to: "<dir>/frame_NNNNNN.png".
 * One function so the display and whoever reads the captures back agree.
 * Returns 0, or -1 when buf is too small.
 */
int psc_sim_capture_path(char *buf, size_t len, const char *dir, uint32_t frame);

/**
 * Draw the sim camera's test pattern for frame sequence seq into an
 * equirectangular width x height map (RGB565 or XRGB8888, stride bytes per
 * row): hue follows longitude (red at 0 deg, green at 120, blue at 240),
 * brightness falls toward the poles, white grid lines every 30 degrees, a
 * black equator, a yellow north cap and a cyan south cap above/below
 * +-75 degrees, and a white band that moves 6 degrees of longitude per frame
 * so a viewer can see the camera is live. Pure integer code; never fails for
 * width, height >= 2.
 */
void psc_sim_pattern_fill(void *pixels, uint32_t stride, uint16_t width, uint16_t height,
                          psc_pixfmt_t format, uint32_t seq);

#endif
