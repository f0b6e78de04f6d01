/* SPDX-License-Identifier: MIT */
/*
 * dev_watchdog.c - the "linux" watchdog: the kernel's watchdog device
 * (/dev/watchdog0: bcm2835_wdt on a Raspberry Pi, iTCO_wdt or sp5100_tco on
 * a PC, i6300esb in QEMU), for a kiosk with no service manager above it (the
 * boot image's /init): if the frame loop stops, the hardware resets the
 * machine instead of leaving a frozen picture.
 *
 *   open    open the device, WDIOC_SETTIMEOUT to the board's timeout rounded
 *           up to whole seconds (the driver may adjust it: WDIOC_GETTIMEOUT
 *           reads back what it took); the watchdog runs from here on
 *   kick    a write, at most once per quarter of that timeout of real time
 *           (CLOCK_MONOTONIC: a watchdog counts real seconds, whatever the
 *           board's clock); the loop kicks every frame, the rest are counted
 *   close   the magic close ("V"): a driver that knows it stops the watchdog,
 *           so a clean exit does not reset the machine (a driver built with
 *           nowayout resets it anyway: the kernel's choice)
 * Options: watchdog.device (default /dev/watchdog0).
 */
#include <errno.h>
#include <fcntl.h>
#include <linux/watchdog.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include "linux_internal.h"

#define DEV_WATCHDOG_DEFAULT "/dev/watchdog0"

typedef struct {
    psc_hal_watchdog_t base;       /* first: the HAL hands this pointer back to us */
    psc_hal_clock_t *clock;
    int fd;
    uint64_t timeout_us;           /* what the driver took */
    uint64_t interval_us;          /* write at most this often, real time */
    struct timespec last_write;
    uint64_t last_kick_us;         /* board clock, for the status counters */
    psc_hal_watchdog_status_t status;
} dev_watchdog_t;

static const char *const dev_watchdog_known_options[] = { "device", NULL };

static int dev_watchdog_kick(psc_hal_watchdog_t *wd)
{
    dev_watchdog_t *s = (dev_watchdog_t *)wd;
    struct timespec t;

    psc_hal_watchdog_count_kick(&s->status, &s->last_kick_us, psc_hal_clock_now_us(s->clock), s->timeout_us);
    clock_gettime(CLOCK_MONOTONIC, &t);
    if (psc_linux_timespec_diff_us(&t, &s->last_write) < s->interval_us)
        return 0;
    s->last_write = t;
    return write(s->fd, "k", 1) == 1 ? 0 : -errno;
}

static int dev_watchdog_get_status(psc_hal_watchdog_t *wd, psc_hal_watchdog_status_t *status)
{
    *status = ((dev_watchdog_t *)wd)->status;
    return 0;
}

static void dev_watchdog_close(psc_hal_watchdog_t *wd)
{
    dev_watchdog_t *s = (dev_watchdog_t *)wd;

    /* the magic close: stop the watchdog rather than reset a machine that exited cleanly */
    if (write(s->fd, "V", 1) != 1) {
        /* nothing to do: the device goes away with the descriptor */
    }
    close(s->fd);
    free(s);
}

static const psc_hal_watchdog_ops_t dev_watchdog_ops = {
    .kick = dev_watchdog_kick,
    .get_status = dev_watchdog_get_status,
    .close = dev_watchdog_close,
};

int psc_dev_watchdog_open(const psc_hal_watchdog_config_t *cfg, psc_hal_watchdog_t **out, char *err, size_t errlen)
{
    const psc_hal_option_t *dev = psc_hal_options_find(&cfg->options, "device");
    const char *path = dev != NULL ? dev->value : DEV_WATCHDOG_DEFAULT;
    dev_watchdog_t *s;
    int secs, rc;

    *out = NULL;
    rc = psc_hal_watchdog_check_config(cfg, "linux", true, err, errlen);
    if (rc != 0)
        return rc;
    rc = psc_hal_options_check(&cfg->options, dev_watchdog_known_options, "watchdog", "linux", err, errlen);
    if (rc != 0)
        return rc;
    s = calloc(1, sizeof *s);
    if (s == NULL) {
        psc_hal_error_set(err, errlen, "linux watchdog: out of memory");
        return -ENOMEM;
    }
    s->fd = open(path, O_WRONLY | O_CLOEXEC);
    if (s->fd < 0) {
        rc = -errno;
        psc_hal_error_set(err, errlen, "linux watchdog: cannot open %s: %s (is the board's watchdog driver loaded?)",
                          path, strerror(errno));
        free(s);
        return rc;
    }
    /* whole seconds, rounded up: a shorter timeout than the board asked would reset a healthy loop */
    secs = (int)((cfg->timeout_ms + 999u) / 1000u);
    if (ioctl(s->fd, WDIOC_SETTIMEOUT, &secs) != 0 && errno == ENOTTY) {
        psc_hal_error_set(err, errlen, "linux watchdog: %s is not a watchdog device", path);
        close(s->fd);
        free(s);
        return -ENOTTY;
    }
    /* the driver may round or refuse: what it runs with is what counts */
    if (ioctl(s->fd, WDIOC_GETTIMEOUT, &secs) != 0 || secs <= 0)
        secs = (int)((cfg->timeout_ms + 999u) / 1000u);
    s->base.ops = &dev_watchdog_ops;
    s->base.backend = "linux";
    s->clock = cfg->clock;
    s->timeout_us = (uint64_t)secs * 1000000u;
    s->interval_us = s->timeout_us / 4u;
    clock_gettime(CLOCK_MONOTONIC, &s->last_write);
    s->last_kick_us = psc_hal_clock_now_us(cfg->clock);
    if (write(s->fd, "k", 1) != 1) {
        rc = -errno;
        psc_hal_error_set(err, errlen, "linux watchdog: cannot write to %s: %s", path, strerror(errno));
        dev_watchdog_close(&s->base);
        return rc;
    }
    *out = &s->base;
    return 0;
}
