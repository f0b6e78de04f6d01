/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_watchdog_count.c - what every watchdog backend does alike: check
 * the board's timeout (and, for the real ones, that there is a clock), and
 * count kicks with the longest gap, so logs and tests see the same figures
 * from the sim, systemd and kernel watchdogs (psc_hal_watchdog.h).
 */
#include "psc_hal_watchdog.h"

int psc_hal_watchdog_check_config(const psc_hal_watchdog_config_t *cfg, const char *backend, bool needs_clock,
                                  char *err, size_t errlen)
{
    if (needs_clock && cfg->clock == NULL) {
        psc_hal_error_set(err, errlen, "%s watchdog: needs the board's clock", backend);
        return -EINVAL;
    }
    if (cfg->timeout_ms < 1 || cfg->timeout_ms > 600000) {
        psc_hal_error_set(err, errlen, "%s watchdog: timeout %u ms is outside 1..600000", backend,
                          (unsigned)cfg->timeout_ms);
        return -EINVAL;
    }
    return 0;
}

void psc_hal_watchdog_count_kick(psc_hal_watchdog_status_t *st, uint64_t *last_kick_us, uint64_t now_us,
                                 uint64_t timeout_us)
{
    uint64_t gap = now_us - *last_kick_us;

    if (gap > st->longest_gap_us)
        st->longest_gap_us = gap;
    if (gap > timeout_us)
        st->would_have_fired = true;
    *last_kick_us = now_us;
    st->kicks++;
}
