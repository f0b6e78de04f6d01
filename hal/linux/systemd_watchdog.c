/* SPDX-License-Identifier: MIT */
/*
 * systemd_watchdog.c - the "systemd" watchdog: the frame loop's kicks become
 * sd_notify datagrams (psc_sd_notify.h), so systemd restarts a kiosk whose
 * loop hangs (WatchdogSec= in the unit, Type=notify).
 *
 * Datagrams, exactly:
 *   first kick              "READY=1\nWATCHDOG=1" ("READY=1" without a watchdog)
 *                           - the first frame is on screen, so start-up is
 *                           really over, not merely the devices opened;
 *   later kicks             "WATCHDOG=1", at most once per WATCHDOG_USEC / 2
 *                           of the HAL clock (the loop kicks every frame; the
 *                           rest are only counted), none without WATCHDOG_USEC;
 *   set_status(text)        "STATUS=text" (newlines become spaces, at most 200 bytes);
 *   close                   "STOPPING=1".
 * Without NOTIFY_SOCKET (started by hand) nothing is sent and kicks are only
 * counted, so the same board file runs from a shell and from systemd.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "linux_internal.h"
#include "psc_sd_notify.h"

#define STATUS_TEXT_MAX 200u

typedef struct {
    psc_hal_watchdog_t base;        /* first: the HAL hands this pointer back to us */
    psc_hal_clock_t *clock;
    psc_sd_notify_t notify;
    uint64_t systemd_timeout_us;    /* WATCHDOG_USEC, 0 = systemd's watchdog is off */
    uint64_t interval_us;           /* WATCHDOG=1 at most this often */
    uint64_t timeout_us;            /* for would_have_fired: systemd's, else the board's */
    uint64_t last_kick_us;
    uint64_t last_sent_us;
    bool ready_sent;
    psc_hal_watchdog_status_t status;
    char message[PSC_SD_NOTIFY_MAX_MESSAGE + 1];   /* built here: no allocation per kick */
} systemd_watchdog_t;

static const char *const systemd_watchdog_known_options[] = { NULL };

static int systemd_watchdog_kick(psc_hal_watchdog_t *wd)
{
    systemd_watchdog_t *s = (systemd_watchdog_t *)wd;
    uint64_t now = psc_hal_clock_now_us(s->clock);

    psc_hal_watchdog_count_kick(&s->status, &s->last_kick_us, now, s->timeout_us);
    if (!s->ready_sent) {
        s->ready_sent = true;
        s->last_sent_us = now;
        return psc_sd_notify_send(&s->notify, s->systemd_timeout_us ? "READY=1\nWATCHDOG=1" : "READY=1");
    }
    if (s->systemd_timeout_us == 0 || now - s->last_sent_us < s->interval_us)
        return 0;
    s->last_sent_us = now;
    return psc_sd_notify_send(&s->notify, "WATCHDOG=1");
}

static int systemd_watchdog_get_status(psc_hal_watchdog_t *wd, psc_hal_watchdog_status_t *status)
{
    *status = ((systemd_watchdog_t *)wd)->status;
    return 0;
}

static int systemd_watchdog_set_status(psc_hal_watchdog_t *wd, const char *text)
{
    systemd_watchdog_t *s = (systemd_watchdog_t *)wd;
    size_t n = strlen("STATUS=");

    memcpy(s->message, "STATUS=", n);
    /* one line: a newline would start a new assignment systemd would obey */
    for (size_t i = 0; text[i] != '\0' && i < STATUS_TEXT_MAX; i++)
        s->message[n++] = (text[i] == '\n' || text[i] == '\r') ? ' ' : text[i];
    s->message[n] = '\0';
    return psc_sd_notify_send(&s->notify, s->message);
}

static void systemd_watchdog_close(psc_hal_watchdog_t *wd)
{
    systemd_watchdog_t *s = (systemd_watchdog_t *)wd;

    psc_sd_notify_send(&s->notify, "STOPPING=1");
    psc_sd_notify_close(&s->notify);
    free(s);
}

static const psc_hal_watchdog_ops_t systemd_watchdog_ops = {
    .kick = systemd_watchdog_kick,
    .get_status = systemd_watchdog_get_status,
    .set_status = systemd_watchdog_set_status,
    .close = systemd_watchdog_close,
};

int psc_systemd_watchdog_open(const psc_hal_watchdog_config_t *cfg, psc_hal_watchdog_t **out, char *err,
                              size_t errlen)
{
    systemd_watchdog_t *s;
    char why[200] = "";
    int rc;

    *out = NULL;
    rc = psc_hal_watchdog_check_config(cfg, "systemd", true, err, errlen);
    if (rc != 0)
        return rc;
    rc = psc_hal_options_check(&cfg->options, systemd_watchdog_known_options, "watchdog", "systemd", err, errlen);
    if (rc != 0)
        return rc;
    s = calloc(1, sizeof *s);
    if (s == NULL) {
        psc_hal_error_set(err, errlen, "systemd watchdog: out of memory");
        return -ENOMEM;
    }
    s->base.ops = &systemd_watchdog_ops;
    s->base.backend = "systemd";
    s->clock = cfg->clock;
    s->notify.fd = -1;
    rc = psc_sd_watchdog_parse(getenv("WATCHDOG_USEC"), getenv("WATCHDOG_PID"), (long)getpid(),
                               &s->systemd_timeout_us, why, sizeof why);
    if (rc == 0)
        rc = psc_sd_notify_open(&s->notify, getenv("NOTIFY_SOCKET"), why, sizeof why);
    if (rc != 0) {
        psc_hal_error_set(err, errlen, "systemd watchdog: %s", why);
        free(s);
        return rc;
    }
    s->interval_us = s->systemd_timeout_us / 2u;
    s->timeout_us = s->systemd_timeout_us ? s->systemd_timeout_us : (uint64_t)cfg->timeout_ms * 1000u;
    s->last_kick_us = psc_hal_clock_now_us(cfg->clock);
    *out = &s->base;
    return 0;
}
