/* SPDX-License-Identifier: MIT */
/*
 * sim_backend.c - the "sim" backend descriptor: how the registry finds the
 * simulated devices when a board file says "display = sim" and so on.
 */
#include "psc_hal_backends.h"
#include "sim_internal.h"

const psc_hal_backend_t psc_hal_sim_backend = {
    .name = "sim",
    .description = "simulated board: memory display with PNG capture, tour-script input, "
                   "deterministic clock, test-pattern camera, recording watchdog",
    .display_open = psc_sim_display_open,
    .input_open = psc_sim_input_open,
    .camera_open = psc_sim_camera_open,
    .clock_open = psc_sim_clock_open,
    .watchdog_open = psc_sim_watchdog_open,
};
