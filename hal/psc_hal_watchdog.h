/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_watchdog.h - a watchdog the frame loop kicks once per frame, so a
 * hung kiosk is restarted instead of showing a frozen picture.
 *
 * Backends: systemd (hal/linux/systemd_watchdog.c: sd_notify "READY=1" with
 * the first kick, "WATCHDOG=1" every WATCHDOG_USEC / 2, "STATUS=" from
 * set_status, "STOPPING=1" at close); linux (hal/linux/dev_watchdog.c: the
 * kernel's /dev/watchdog0, WDIOC_SETTIMEOUT, a write per quarter timeout and
 * the magic close 'V'). The sim
 * backend only records the kicks on the sim clock and reports the longest gap,
 * so a tour shows whether the loop would have kept a real watchdog fed.
 */
#ifndef PSC_HAL_WATCHDOG_H
#define PSC_HAL_WATCHDOG_H

#include "psc_hal.h"

/** Configuration of a watchdog. */
typedef struct psc_hal_watchdog_config {
    uint32_t timeout_ms;          /* reset after this long without a kick (1..600000) */
    psc_hal_clock_t *clock;       /* must outlive the watchdog */
    psc_hal_options_t options;    /* backend-specific (none for sim) */
} psc_hal_watchdog_config_t;

/** What a watchdog has seen so far. */
typedef struct {
    uint32_t kicks;
    uint64_t longest_gap_us;      /* longest time between two kicks (or open and the first) */
    bool would_have_fired;        /* longest_gap_us exceeded the timeout */
} psc_hal_watchdog_status_t;

typedef struct {
    /* Mandatory. Tell the watchdog the program is alive. */
    int (*kick)(psc_hal_watchdog_t *wd);
    /* Optional. Counters for logs and tests. */
    int (*get_status)(psc_hal_watchdog_t *wd, psc_hal_watchdog_status_t *status);
    /* Optional. Tell the supervisor what the device is doing, one line of
     * text ("camera lost"), e.g. systemd's STATUS= for `systemctl status`. */
    int (*set_status)(psc_hal_watchdog_t *wd, const char *text);
    /* Mandatory. Orderly shutdown: disarm (magic close / "STOPPING=1") and free. */
    void (*close)(psc_hal_watchdog_t *wd);
} psc_hal_watchdog_ops_t;

/** The public part of a watchdog; backends embed it first in their state. */
struct psc_hal_watchdog {
    const psc_hal_watchdog_ops_t *ops;
    const char *backend;
};

/**
 * Open and arm a watchdog of the named backend (board key "watchdog"). 0 and
 * *out set, or a negative errno (psc_hal.h) with err filled.
 */
int psc_hal_watchdog_open(const char *backend, const psc_hal_watchdog_config_t *cfg,
                          psc_hal_watchdog_t **out, char *err, size_t errlen);

/** Disarm and close a watchdog opened with psc_hal_watchdog_open (NULL is ignored). */
void psc_hal_watchdog_close(psc_hal_watchdog_t *wd);

/* ---- for backends (psc_hal_watchdog_count.c) ------------------------------ */

/** The timeout within 1..600000 ms and, when needs_clock, a clock: 0 or -EINVAL naming the backend. */
int psc_hal_watchdog_check_config(const psc_hal_watchdog_config_t *cfg, const char *backend, bool needs_clock,
                                  char *err, size_t errlen);

/** Count a kick at now_us: kicks, the longest gap since *last_kick_us (then set to now_us), and
 *  would_have_fired when that gap exceeded timeout_us. */
void psc_hal_watchdog_count_kick(psc_hal_watchdog_status_t *st, uint64_t *last_kick_us, uint64_t now_us,
                                 uint64_t timeout_us);

/** Feed the watchdog. */
static inline int psc_hal_watchdog_kick(psc_hal_watchdog_t *wd)
{
    return wd->ops->kick(wd);
}

/** Counters so far; -ENOSYS when the backend keeps none. */
static inline int psc_hal_watchdog_get_status(psc_hal_watchdog_t *wd, psc_hal_watchdog_status_t *status)
{
    return wd->ops->get_status ? wd->ops->get_status(wd, status) : -ENOSYS;
}

/** Report a one-line status text to the supervisor; -ENOSYS when the backend has nowhere to show it. */
static inline int psc_hal_watchdog_set_status(psc_hal_watchdog_t *wd, const char *text)
{
    return wd->ops->set_status ? wd->ops->set_status(wd, text) : -ENOSYS;
}

#endif
