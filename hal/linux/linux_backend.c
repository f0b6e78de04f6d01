/* SPDX-License-Identifier: MIT */
/*
 * linux_backend.c - the descriptors of the plain-Linux backends:
 *   "linux"    clock: CLOCK_MONOTONIC with absolute-deadline sleeps;
 *              watchdog: the kernel's watchdog device (/dev/watchdog0);
 *   "systemd"  watchdog: sd_notify READY/WATCHDOG/STATUS/STOPPING datagrams.
 * Two names because a board picks them independently: a kiosk started by
 * hand still wants the real clock but has no service manager to notify.
 */
#include "linux_internal.h"
#include "psc_hal_backends.h"

const psc_hal_backend_t psc_hal_linux_backend = {
    .name = "linux",
    .description = "Linux CLOCK_MONOTONIC clock with absolute-time frame pacing; the kernel's watchdog device",
    .clock_open = psc_linux_clock_open,
    .watchdog_open = psc_dev_watchdog_open,
};

const psc_hal_backend_t psc_hal_systemd_backend = {
    .name = "systemd",
    .description = "systemd service watchdog over the sd_notify datagram protocol (no libsystemd)",
    .watchdog_open = psc_systemd_watchdog_open,
};
