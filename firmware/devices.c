/* SPDX-License-Identifier: MIT */
/* devices.c - open, poll and close the program's devices (devices.h). */
#include <stdio.h>
#include <string.h>

#include "devices.h"
#include "psc_io_log.h"
#include "psc_hal.h"

#define DEVICES_MAX_OPTIONS (PSC_BOARD_MAX_OPTIONS + 4u)

/* The HAL options of one device kind: the board's lines plus extra ones the
 * command line turns into (tour -> script, ...). */
static size_t devices_options(const psc_board_config_t *b, psc_board_dev_t dev, const psc_hal_option_t *extra,
                              size_t extra_count, psc_hal_option_t *items)
{
    size_t n = psc_board_config_options(b, dev, items, PSC_BOARD_MAX_OPTIONS);

    for (size_t i = 0; i < extra_count && n < DEVICES_MAX_OPTIONS; i++)
        items[n++] = extra[i];
    return n;
}

static int devices_open_display(psc_devices_t *d, const psc_board_config_t *b, const psc_devices_extra_t *x,
                                char *err, size_t errlen)
{
    psc_hal_option_t items[DEVICES_MAX_OPTIONS], extra[3];
    char every[16], sheet[PSC_BOARD_PATH_MAX + 16];
    size_t n_extra = 0, n;

    if (x->capture_every != 0) {
        snprintf(every, sizeof every, "%u", (unsigned)x->capture_every);
        snprintf(sheet, sizeof sheet, "%s/contact.png", x->capture_dir);
        extra[n_extra++] = (psc_hal_option_t){ "capture_every", every, x->capture_every_origin };
        extra[n_extra++] = (psc_hal_option_t){ "capture_dir", x->capture_dir, x->capture_dir_origin };
        extra[n_extra++] = (psc_hal_option_t){ "contact_sheet", sheet, "(the run at a glance)" };
    }
    n = devices_options(b, PSC_BOARD_DEV_DISPLAY, extra, n_extra, items);
    psc_hal_display_config_t cfg = {
        .width = b->display_width, .height = b->display_height, .format = b->display_format,
        .buffer_count = b->display_buffers, .frame_rate_mhz = b->frame_rate_mhz,
        .clock = d->clock, .options = { items, n },
    };
    if (psc_hal_display_open(b->display_backend, &cfg, &d->display, err, errlen) != 0 ||
        psc_hal_display_get_mode(d->display, &d->mode) != 0)
        return -1;
    return 0;
}

int psc_devices_open(psc_devices_t *d, const psc_board_config_t *b, const psc_devices_extra_t *x, char *err,
                     size_t errlen)
{
    psc_hal_option_t items[DEVICES_MAX_OPTIONS], extra[1];
    size_t n, n_extra = 0;

    memset(d, 0, sizeof *d);
    psc_device_status_init(&d->status, strcmp(b->camera_backend, "none") != 0);
    n = devices_options(b, PSC_BOARD_DEV_CLOCK, NULL, 0, items);
    if (psc_hal_clock_open(b->clock_backend, &(psc_hal_clock_config_t){ { items, n } }, &d->clock, err,
                           errlen) != 0)
        return -1;
    if (devices_open_display(d, b, x, err, errlen) != 0)
        return -1;

    if (x->tour != NULL)
        extra[n_extra++] = (psc_hal_option_t){ "script", x->tour, x->tour_origin };
    else if (b->tour[0] != '\0')
        extra[n_extra++] = (psc_hal_option_t){ "script", b->tour, b->tour_origin };
    n = devices_options(b, PSC_BOARD_DEV_INPUT, extra, n_extra, items);
    psc_hal_input_config_t icfg = { .clock = d->clock,
                                    .long_press_ms = b->long_press_ms,
                                    .display_width = b->display_width,
                                    .display_height = b->display_height,
                                    .options = { items, n } };
    if (psc_hal_input_open(b->input_backend, &icfg, &d->input, err, errlen) != 0)
        return -1;

    if (strcmp(b->watchdog_backend, "none") != 0) {
        n = devices_options(b, PSC_BOARD_DEV_WATCHDOG, NULL, 0, items);
        psc_hal_watchdog_config_t wcfg = { b->watchdog_timeout_ms, d->clock, { items, n } };
        if (psc_hal_watchdog_open(b->watchdog_backend, &wcfg, &d->watchdog, err, errlen) != 0)
            return -1;
    }
    /* The camera is opened here so a board's camera settings fail at
     * start-up, not later; it streams once the scenes are loaded. */
    if (strcmp(b->camera_backend, "none") != 0) {
        n = devices_options(b, PSC_BOARD_DEV_CAMERA, NULL, 0, items);
        psc_hal_camera_config_t ccfg = {
            .width = b->camera_width, .height = b->camera_height, .format = b->display_format,
            .buffer_count = b->camera_buffers, .frame_rate_mhz = b->camera_rate_mhz,
            .clock = d->clock, .options = { items, n },
        };
        if (psc_hal_camera_open(b->camera_backend, &ccfg, &d->camera, err, errlen) != 0)
            return -1;
    }
    psc_camera_feed_init(&d->feed, d->camera);
    return 0;
}

int psc_devices_start(psc_devices_t *d, const psc_board_config_t *b, char *err, size_t errlen)
{
    if (d->camera != NULL && psc_hal_camera_start(d->camera) != 0) {
        psc_hal_error_set(err, errlen, "%s: the %s camera did not start streaming", b->file, b->camera_backend);
        return -1;
    }
    return 0;
}

void psc_devices_poll_camera(psc_devices_t *d)
{
    int rc;

    if (d->camera == NULL)
        return;
    bool had = d->feed.had_frames;
    rc = psc_camera_feed_poll(&d->feed);
    if (!had && d->feed.had_frames)   /* until now the camera scene showed its pack's own map */
        psc_io_log(PSC_LOG_NOTICE, "camera: first frame, %ux%u", (unsigned)d->feed.map.width,
                   (unsigned)d->feed.map.height);
    psc_device_status_camera(&d->status, rc, d->feed.had_frames);
}

void psc_devices_close(psc_devices_t *d)
{
    psc_camera_feed_release(&d->feed);
    if (d->camera != NULL)
        psc_hal_camera_stop(d->camera);
    psc_hal_camera_close(d->camera);
    psc_hal_watchdog_close(d->watchdog);
    psc_hal_input_close(d->input);
    psc_hal_display_close(d->display);
    psc_hal_clock_close(d->clock);
    memset(d, 0, sizeof *d);
}
