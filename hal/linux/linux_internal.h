/* SPDX-License-Identifier: MIT */
/*
 * linux_internal.h - what the "linux" and "systemd" backends (clock, watchdog
 * device, sd_notify watchdog) share with their descriptors. Not for the firmware.
 */
#ifndef PSC_LINUX_INTERNAL_H
#define PSC_LINUX_INTERNAL_H

#include <stdint.h>
#include <time.h>

#include "psc_hal_clock.h"
#include "psc_hal_watchdog.h"

/** Open the CLOCK_MONOTONIC clock (linux_clock.c). */
int psc_linux_clock_open(const psc_hal_clock_config_t *cfg, psc_hal_clock_t **out, char *err, size_t errlen);

/** Open the sd_notify watchdog (systemd_watchdog.c). */
int psc_systemd_watchdog_open(const psc_hal_watchdog_config_t *cfg, psc_hal_watchdog_t **out, char *err,
                              size_t errlen);

/** Open the kernel watchdog device (dev_watchdog.c). */
int psc_dev_watchdog_open(const psc_hal_watchdog_config_t *cfg, psc_hal_watchdog_t **out, char *err, size_t errlen);

/** later - earlier in microseconds, 0 when later is not after earlier. */
uint64_t psc_linux_timespec_diff_us(const struct timespec *later, const struct timespec *earlier);

/** Move ts forward by us microseconds, keeping tv_nsec normalised. */
void psc_linux_timespec_add_us(struct timespec *ts, uint64_t us);

#endif
