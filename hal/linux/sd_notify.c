/* SPDX-License-Identifier: MIT */
/*
 * sd_notify.c - the sd_notify datagram protocol (psc_sd_notify.h).
 *
 * Each message is sent with sendto() to the address from NOTIFY_SOCKET on an
 * unconnected socket, as systemd's own implementation does: if systemd
 * re-executes and recreates its socket, the next datagram still finds it.
 */
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "psc_hal.h"
#include "psc_sd_notify.h"

int psc_sd_notify_parse_address(const char *value, struct sockaddr_un *addr, socklen_t *addr_len, char *err,
                                size_t errlen)
{
    size_t len = value != NULL ? strlen(value) : 0;

    memset(addr, 0, sizeof *addr);
    addr->sun_family = AF_UNIX;
    if (len == 0) {
        psc_hal_error_set(err, errlen, "NOTIFY_SOCKET is empty");
        return -EINVAL;
    }
    if (value[0] != '/' && value[0] != '@') {
        psc_hal_error_set(err, errlen,
                          "NOTIFY_SOCKET '%.64s' is neither an absolute path nor an abstract '@name' "
                          "(other address families such as vsock: are not supported)", value);
        return -EINVAL;
    }
    /* A path needs room for its terminating NUL; an abstract name does not
     * have one, its '@' becomes the leading NUL byte instead. */
    if (len > sizeof addr->sun_path - (value[0] == '/' ? 1u : 0u) || (value[0] == '@' && len < 2)) {
        psc_hal_error_set(err, errlen, "NOTIFY_SOCKET '%.64s...' has %zu bytes: a Unix socket address holds "
                          "1..%zu", value, len, sizeof addr->sun_path - 1u);
        return -EINVAL;
    }
    memcpy(addr->sun_path, value, len);
    if (value[0] == '@')
        addr->sun_path[0] = '\0';
    *addr_len = (socklen_t)(offsetof(struct sockaddr_un, sun_path) + len + (value[0] == '/' ? 1u : 0u));
    return 0;
}

int psc_sd_notify_open(psc_sd_notify_t *n, const char *value, char *err, size_t errlen)
{
    int rc;

    memset(n, 0, sizeof *n);
    n->fd = -1;
    if (value == NULL || value[0] == '\0')
        return 0;   /* not started by systemd: nothing to tell anyone */
    rc = psc_sd_notify_parse_address(value, &n->addr, &n->addr_len, err, errlen);
    if (rc != 0)
        return rc;
    n->fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (n->fd < 0) {
        rc = -errno;
        psc_hal_error_set(err, errlen, "NOTIFY_SOCKET: cannot create a Unix datagram socket: %s", strerror(errno));
        return rc;
    }
    n->enabled = true;
    return 0;
}

int psc_sd_notify_send(psc_sd_notify_t *n, const char *message)
{
    size_t len = strlen(message);
    ssize_t sent;

    if (!n->enabled)
        return 0;
    if (len == 0 || len > PSC_SD_NOTIFY_MAX_MESSAGE)
        return -EINVAL;
    sent = sendto(n->fd, message, len, MSG_DONTWAIT | MSG_NOSIGNAL, (const struct sockaddr *)&n->addr,
                  n->addr_len);
    if (sent < 0 || (size_t)sent != len) {
        n->failed++;
        return sent < 0 ? -errno : -EIO;
    }
    n->sent++;
    return 0;
}

void psc_sd_notify_close(psc_sd_notify_t *n)
{
    if (n->fd >= 0)
        close(n->fd);
    n->fd = -1;
    n->enabled = false;
}

/* A positive decimal number of at most 19 digits (no sign, no spaces). */
static bool parse_positive(const char *s, uint64_t *out)
{
    uint64_t v = 0;
    size_t i;

    for (i = 0; s[i] != '\0'; i++) {
        if (s[i] < '0' || s[i] > '9' || i >= 19)
            return false;
        v = v * 10u + (uint64_t)(s[i] - '0');
    }
    if (i == 0 || v == 0)
        return false;
    *out = v;
    return true;
}

int psc_sd_watchdog_parse(const char *usec, const char *pid, long own_pid, uint64_t *timeout_us, char *err,
                          size_t errlen)
{
    uint64_t t, p;

    *timeout_us = 0;
    if (usec == NULL)
        return 0;
    if (!parse_positive(usec, &t)) {
        psc_hal_error_set(err, errlen, "WATCHDOG_USEC '%.32s' is not a positive number of microseconds", usec);
        return -EINVAL;
    }
    if (pid != NULL) {
        if (!parse_positive(pid, &p)) {
            psc_hal_error_set(err, errlen, "WATCHDOG_PID '%.32s' is not a process id", pid);
            return -EINVAL;
        }
        if (p != (uint64_t)own_pid)
            return 0;   /* meant for another process (we were started by the service's main process) */
    }
    *timeout_us = t;
    return 0;
}
