/* SPDX-License-Identifier: MIT */
/*
 * sim_clock.c - the simulated board's clock: starts at 0 and moves only when
 * told to. The sim display moves it one frame period per present and
 * sleep_until jumps to the deadline instead of waiting, so a headless tour
 * runs as fast as the host can render and still sees exactly the times a
 * real board at the configured frame rate would see.
 */
#include <stdlib.h>

#include "sim_internal.h"

typedef struct {
    psc_hal_clock_t base;   /* first: the HAL hands this pointer back to us */
    uint64_t now_us;
} sim_clock_t;

static const char *const sim_clock_known_options[] = { NULL };

static uint64_t sim_clock_now_us(psc_hal_clock_t *clk)
{
    return ((sim_clock_t *)clk)->now_us;
}

static int sim_clock_sleep_until(psc_hal_clock_t *clk, uint64_t t_us)
{
    sim_clock_t *c = (sim_clock_t *)clk;

    if (t_us > c->now_us)
        c->now_us = t_us;
    return 0;
}

static void sim_clock_close(psc_hal_clock_t *clk)
{
    free(clk);
}

static const psc_hal_clock_ops_t sim_clock_ops = {
    .now_us = sim_clock_now_us,
    .sleep_until = sim_clock_sleep_until,
    .close = sim_clock_close,
};

bool psc_sim_clock_advance_to(psc_hal_clock_t *clk, uint64_t t_us)
{
    if (clk == NULL || clk->ops != &sim_clock_ops)
        return false;
    sim_clock_sleep_until(clk, t_us);
    return true;
}

int psc_sim_clock_open(const psc_hal_clock_config_t *cfg, psc_hal_clock_t **out, char *err, size_t errlen)
{
    sim_clock_t *c;
    int rc;

    *out = NULL;
    if (cfg != NULL) {
        rc = psc_hal_options_check(&cfg->options, sim_clock_known_options, "clock", "sim", err, errlen);
        if (rc != 0)
            return rc;
    }
    c = calloc(1, sizeof *c);
    if (c == NULL) {
        psc_hal_error_set(err, errlen, "sim clock: out of memory");
        return -ENOMEM;
    }
    c->base.ops = &sim_clock_ops;
    c->base.backend = "sim";
    *out = &c->base;
    return 0;
}
