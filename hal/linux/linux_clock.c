/* SPDX-License-Identifier: MIT */
/*
 * linux_clock.c - the "linux" clock: CLOCK_MONOTONIC, microseconds since
 * open, and absolute-time sleeps (clock_nanosleep with TIMER_ABSTIME).
 *
 * Why absolute sleeps: the frame loop sleeps until start + n * period. A
 * relative sleep of "period minus what the frame took" drifts by the time
 * spent between reading the clock and going to sleep, every frame; an
 * absolute deadline does not, so 30 fps stays 30 fps over hours.
 * CLOCK_MONOTONIC rather than CLOCK_REALTIME: NTP or a person setting the
 * date must not make the kiosk stall or race.
 */
#include <stdlib.h>
#include <time.h>

#include "linux_internal.h"

typedef struct {
    psc_hal_clock_t base;      /* first: the HAL hands this pointer back to us */
    struct timespec epoch;     /* CLOCK_MONOTONIC at open: now_us() == 0 */
} linux_clock_t;

static const char *const linux_clock_known_options[] = { NULL };

uint64_t psc_linux_timespec_diff_us(const struct timespec *later, const struct timespec *earlier)
{
    int64_t sec = (int64_t)later->tv_sec - (int64_t)earlier->tv_sec;
    int64_t nsec = (int64_t)later->tv_nsec - (int64_t)earlier->tv_nsec;
    int64_t us = sec * 1000000 + nsec / 1000;

    return us > 0 ? (uint64_t)us : 0u;
}

void psc_linux_timespec_add_us(struct timespec *ts, uint64_t us)
{
    uint64_t nsec = (uint64_t)ts->tv_nsec + (us % 1000000u) * 1000u;

    ts->tv_sec += (time_t)(us / 1000000u + nsec / 1000000000u);
    ts->tv_nsec = (long)(nsec % 1000000000u);
}

static uint64_t linux_clock_now_us(psc_hal_clock_t *clk)
{
    linux_clock_t *c = (linux_clock_t *)clk;
    struct timespec now;

    clock_gettime(CLOCK_MONOTONIC, &now);
    return psc_linux_timespec_diff_us(&now, &c->epoch);
}

static int linux_clock_sleep_until(psc_hal_clock_t *clk, uint64_t t_us)
{
    linux_clock_t *c = (linux_clock_t *)clk;
    struct timespec deadline = c->epoch;
    int rc;

    psc_linux_timespec_add_us(&deadline, t_us);
    /* clock_nanosleep returns the error number instead of setting errno; a
     * deadline already past returns 0 at once. */
    rc = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, NULL);
    return rc == 0 ? 0 : -rc;
}

static void linux_clock_close(psc_hal_clock_t *clk)
{
    free(clk);
}

static const psc_hal_clock_ops_t linux_clock_ops = {
    .now_us = linux_clock_now_us,
    .sleep_until = linux_clock_sleep_until,
    .close = linux_clock_close,
};

int psc_linux_clock_open(const psc_hal_clock_config_t *cfg, psc_hal_clock_t **out, char *err, size_t errlen)
{
    linux_clock_t *c;
    int rc;

    *out = NULL;
    if (cfg != NULL) {
        rc = psc_hal_options_check(&cfg->options, linux_clock_known_options, "clock", "linux", err, errlen);
        if (rc != 0)
            return rc;
    }
    c = calloc(1, sizeof *c);
    if (c == NULL) {
        psc_hal_error_set(err, errlen, "linux clock: out of memory");
        return -ENOMEM;
    }
    c->base.ops = &linux_clock_ops;
    c->base.backend = "linux";
    if (clock_gettime(CLOCK_MONOTONIC, &c->epoch) != 0) {
        psc_hal_error_set(err, errlen, "linux clock: CLOCK_MONOTONIC is not available");
        free(c);
        return -ENODEV;
    }
    *out = &c->base;
    return 0;
}
