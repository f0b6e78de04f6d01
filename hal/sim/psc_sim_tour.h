/* SPDX-License-Identifier: MIT */
/*
 * psc_sim_tour.h - tour scripts: scripted input for the simulated board
 * (the grammar is documented at the top of sim_tour.c).
 *
 * A parsed tour is the list of input events a person with a keypad and
 * gamepads would have produced, each stamped with its time in microseconds
 * from the start of the tour (sorted by time; events at the same time keep
 * their script order), plus the time the tour ends. The sim input backend
 * replays it against the sim clock and sends PSC_HAL_INPUT_QUIT at end_us.
 */
#ifndef PSC_SIM_TOUR_H
#define PSC_SIM_TOUR_H

#include <stddef.h>
#include <stdint.h>
#include "psc_hal_input.h"

#define PSC_SIM_TOUR_MAX_EVENTS 65536u
#define PSC_SIM_TOUR_MAX_MS (24u * 3600u * 1000u)  /* a day: longer is a typo */
#define PSC_SIM_TOUR_MAX_LINE 511u                 /* characters per line */
#define PSC_SIM_TOUR_PRESS_MS 100u                 /* how long "press" holds a button */
#define PSC_SIM_TOUR_LONG_PRESS_MS 800u            /* default long-press time */

/** A parsed tour. events is malloc'd; free with psc_sim_tour_free. */
typedef struct {
    psc_hal_input_event_t *events;  /* sorted by time_us */
    size_t count;
    uint64_t end_us;                /* when the tour ends (QUIT) */
} psc_sim_tour_t;

/**
 * Parse a tour script held in text[0..len). name is the file name used in
 * error messages. A button held for long_press_ms or more also produces a
 * BUTTON_LONG event at down + long_press_ms. Returns 0 with *tour filled, or
 * -EINVAL with err = "<name>:<line>: <problem>" and *tour empty, or -ENOMEM.
 */
int psc_sim_tour_parse(const char *text, size_t len, const char *name, uint32_t long_press_ms,
                       psc_sim_tour_t *tour, char *err, size_t errlen);

/**
 * Read a tour script file and parse it (psc_sim_tour_parse). Errors name the
 * file: "cannot read tours/x.txt: No such file or directory" or a parse error.
 */
int psc_sim_tour_load(const char *path, uint32_t long_press_ms, psc_sim_tour_t *tour,
                      char *err, size_t errlen);

/** Free a tour's events (safe on a zeroed or already freed tour). */
void psc_sim_tour_free(psc_sim_tour_t *tour);

#endif
