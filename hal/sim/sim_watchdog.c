/* SPDX-License-Identifier: MIT */
/*
 * sim_watchdog.c - the simulated board's watchdog: it cannot reset anything,
 * so it records each kick on the sim clock and remembers the longest gap.
 * A tour then shows whether the frame loop would have kept a real watchdog
 * fed, without a real one rebooting the developer's machine.
 */
#include <stdlib.h>

#include "sim_internal.h"

typedef struct {
    psc_hal_watchdog_t base;   /* first: the HAL hands this pointer back to us */
    psc_hal_clock_t *clock;
    uint64_t timeout_us;
    uint64_t last_us;
    psc_hal_watchdog_status_t status;
} sim_watchdog_t;

static const char *const sim_watchdog_known_options[] = { NULL };

static int sim_watchdog_kick(psc_hal_watchdog_t *wd)
{
    sim_watchdog_t *s = (sim_watchdog_t *)wd;
    uint64_t now = s->clock ? psc_hal_clock_now_us(s->clock) : s->last_us;

    psc_hal_watchdog_count_kick(&s->status, &s->last_us, now, s->timeout_us);
    return 0;
}

static int sim_watchdog_get_status(psc_hal_watchdog_t *wd, psc_hal_watchdog_status_t *status)
{
    *status = ((sim_watchdog_t *)wd)->status;
    return 0;
}

static void sim_watchdog_close(psc_hal_watchdog_t *wd)
{
    free(wd);
}

static const psc_hal_watchdog_ops_t sim_watchdog_ops = {
    .kick = sim_watchdog_kick,
    .get_status = sim_watchdog_get_status,
    .close = sim_watchdog_close,
};

int psc_sim_watchdog_open(const psc_hal_watchdog_config_t *cfg, psc_hal_watchdog_t **out, char *err, size_t errlen)
{
    sim_watchdog_t *s;
    int rc;

    *out = NULL;
    rc = psc_hal_watchdog_check_config(cfg, "sim", false, err, errlen);
    if (rc != 0)
        return rc;
    rc = psc_hal_options_check(&cfg->options, sim_watchdog_known_options, "watchdog", "sim", err, errlen);
    if (rc != 0)
        return rc;
    s = calloc(1, sizeof *s);
    if (s == NULL) {
        psc_hal_error_set(err, errlen, "sim watchdog: out of memory");
        return -ENOMEM;
    }
    s->base.ops = &sim_watchdog_ops;
    s->base.backend = "sim";
    s->clock = cfg->clock;
    s->timeout_us = (uint64_t)cfg->timeout_ms * 1000u;
    s->last_us = cfg->clock ? psc_hal_clock_now_us(cfg->clock) : 0;
    *out = &s->base;
    return 0;
}
