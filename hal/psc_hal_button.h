/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_button.h - one push button's debounce and long-press logic, as a
 * pure state machine driven by explicit times, so every backend (GPIO
 * lines, gamepad buttons) behaves alike and the timing rules are unit-tested
 * without sleeping.
 *
 * Rules (times in microseconds on the input's clock, never decreasing):
 *  - debounce: a new level counts once it has stayed unchanged for
 *    debounce_us; the DOWN/UP edge is reported at that moment (the last raw
 *    change + debounce_us), as the kernel's GPIO debouncer does. Shorter
 *    blips are swallowed. debounce_us = 0 takes every change at once.
 *  - long press: a button that has been (debounced) down for long_press_us
 *    gets one LONG at down time + long_press_us, before its UP;
 *    long_press_us = 0 never sends LONG.
 * Use: for every raw level change, first psc_hal_button_advance() to its
 * time (edges that became due before it), then psc_hal_button_set(); once
 * per poll, psc_hal_button_advance() to now.
 */
#ifndef PSC_HAL_BUTTON_H
#define PSC_HAL_BUTTON_H

#include <stdbool.h>
#include <stdint.h>
#include "psc_hal_input.h"

typedef struct {
    uint32_t debounce_us;    /* 0: no software debounce */
    uint32_t long_press_us;  /* 0: no long press */
} psc_hal_button_timing_t;

typedef struct {
    bool raw;                /* the last level seen */
    bool stable;             /* the debounced level */
    bool long_sent;          /* LONG already sent for this press */
    uint64_t raw_since;      /* when raw took its level */
    uint64_t down_at;        /* when stable went down */
} psc_hal_button_t;

/** One debounced edge: type is BUTTON_DOWN, BUTTON_UP or BUTTON_LONG. */
typedef struct {
    psc_hal_input_type_t type;
    uint64_t time_us;
} psc_hal_button_edge_t;

/** Start released (raw and stable) at time t_us; no edge. */
void psc_hal_button_init(psc_hal_button_t *b, uint64_t t_us);

/**
 * Move the button's time to t_us and write the edges that became due in
 * between (at most 2: a DOWN or UP, then a LONG) to out in time order.
 * Returns how many.
 */
unsigned psc_hal_button_advance(psc_hal_button_t *b, const psc_hal_button_timing_t *timing, uint64_t t_us,
                                psc_hal_button_edge_t out[2]);

/** The raw level became level at t_us (call advance to t_us first). Same level: no change. */
void psc_hal_button_set(psc_hal_button_t *b, bool level, uint64_t t_us);

#endif
