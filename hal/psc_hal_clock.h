/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_clock.h - the monotonic clock every other device and the frame loop
 * keep time with.
 *
 * Units: microseconds since the clock was opened, uint64_t, never going back.
 * Real backends read CLOCK_MONOTONIC and sleep with clock_nanosleep(
 * TIMER_ABSTIME); the simulated one starts at 0 and moves only when the
 * simulated display presents a frame or someone sleeps past "now", so a tour
 * renders the same frames on every machine however fast it runs.
 */
#ifndef PSC_HAL_CLOCK_H
#define PSC_HAL_CLOCK_H

#include "psc_hal.h"

/** Configuration of a clock. */
typedef struct psc_hal_clock_config {
    psc_hal_options_t options;   /* backend-specific settings (none for sim) */
} psc_hal_clock_config_t;

typedef struct {
    /* Mandatory. Microseconds since open; never decreases. */
    uint64_t (*now_us)(psc_hal_clock_t *clk);
    /* Mandatory. Return once now_us() >= t_us (at once when it already is).
     * 0, or -EINTR when a signal cut the sleep short (the caller re-checks). */
    int (*sleep_until)(psc_hal_clock_t *clk, uint64_t t_us);
    /* Mandatory. Release the clock; devices opened with it must be closed first. */
    void (*close)(psc_hal_clock_t *clk);
} psc_hal_clock_ops_t;

/** The public part of a clock; backends embed it first in their state. */
struct psc_hal_clock {
    const psc_hal_clock_ops_t *ops;
    const char *backend;   /* the backend's board-file name, for messages */
};

/**
 * Open a clock of the named backend (board key "clock"). 0 and *out set, or a
 * negative errno (psc_hal.h) with err naming the backend and the problem.
 */
int psc_hal_clock_open(const char *backend, const psc_hal_clock_config_t *cfg,
                       psc_hal_clock_t **out, char *err, size_t errlen);

/** Close a clock opened with psc_hal_clock_open (NULL is ignored). */
void psc_hal_clock_close(psc_hal_clock_t *clk);

/** Microseconds since the clock was opened. */
static inline uint64_t psc_hal_clock_now_us(psc_hal_clock_t *clk)
{
    return clk->ops->now_us(clk);
}

/** Sleep until the clock reads t_us (the frame loop's pacing). 0 or -EINTR. */
static inline int psc_hal_clock_sleep_until(psc_hal_clock_t *clk, uint64_t t_us)
{
    return clk->ops->sleep_until(clk, t_us);
}

#endif
