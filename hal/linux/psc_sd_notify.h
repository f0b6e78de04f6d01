/* SPDX-License-Identifier: MIT */
/*
 * psc_sd_notify.h - systemd's service notification protocol, written by hand
 * so the firmware needs no libsystemd (one fewer library on a small image).
 *
 * Protocol (sd_notify(3)): systemd passes the address of a Unix datagram
 * socket in the environment variable NOTIFY_SOCKET, either a file system path
 * ("/run/systemd/notify") or an abstract name written with a leading '@'
 * ("@/org/freedesktop/systemd1/notify/1234"; the '@' stands for the leading
 * NUL byte of an abstract address). A service sends it datagrams of
 * newline-separated VARIABLE=value assignments: READY=1 when start-up is
 * done, WATCHDOG=1 to feed the service watchdog, STATUS=text for
 * `systemctl status`, STOPPING=1 when shutting down. With WatchdogSec= set,
 * systemd exports WATCHDOG_USEC (the timeout in microseconds) and
 * WATCHDOG_PID (the process it applies to); sd_watchdog_enabled(3)
 * recommends sending WATCHDOG=1 at half that interval.
 */
#ifndef PSC_SD_NOTIFY_H
#define PSC_SD_NOTIFY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/socket.h>
#include <sys/un.h>

/** Longest datagram psc_sd_notify_send accepts (systemd reads far more). */
#define PSC_SD_NOTIFY_MAX_MESSAGE 512u

/** A notification socket: where to send, and whether there is anywhere. */
typedef struct {
    bool enabled;               /* NOTIFY_SOCKET was set: datagrams are sent */
    int fd;                     /* -1 when not enabled */
    struct sockaddr_un addr;
    socklen_t addr_len;         /* exact length: abstract names are not NUL-terminated */
    uint32_t sent;              /* datagrams sent */
    uint32_t failed;            /* datagrams the kernel refused (systemd gone, queue full) */
} psc_sd_notify_t;

/**
 * Parse a NOTIFY_SOCKET value into *addr / *addr_len: "/path" (absolute) or
 * "@name" (abstract). 0, or -EINVAL with err saying why ("relative path",
 * "longer than 107 bytes", an unsupported "vsock:" address, empty).
 */
int psc_sd_notify_parse_address(const char *value, struct sockaddr_un *addr, socklen_t *addr_len, char *err,
                                size_t errlen);

/**
 * Set up notifications to the socket named by value (the NOTIFY_SOCKET text;
 * NULL or "" means "not started by systemd": n is disabled and every send is
 * a successful no-op). Creates the datagram socket (close-on-exec). 0, or a
 * negative errno with err naming NOTIFY_SOCKET and the problem.
 */
int psc_sd_notify_open(psc_sd_notify_t *n, const char *value, char *err, size_t errlen);

/**
 * Send one datagram holding message (its bytes as given, no NUL). Never
 * blocks (MSG_DONTWAIT) and never raises SIGPIPE. 0 (also when disabled), or
 * a negative errno when the socket refused it; the frame loop carries on
 * either way, so failures are only counted.
 */
int psc_sd_notify_send(psc_sd_notify_t *n, const char *message);

/** Close the socket (a disabled or never-opened n is fine). */
void psc_sd_notify_close(psc_sd_notify_t *n);

/**
 * Parse WATCHDOG_USEC / WATCHDOG_PID as sd_watchdog_enabled(3) does: usec
 * NULL means no watchdog (*timeout_us = 0, returns 0). A value that is not a
 * positive decimal number is -EINVAL with err naming the variable. When pid
 * is set and is not own_pid the watchdog belongs to another process: 0 with
 * *timeout_us = 0.
 */
int psc_sd_watchdog_parse(const char *usec, const char *pid, long own_pid, uint64_t *timeout_us, char *err,
                          size_t errlen);

#endif
