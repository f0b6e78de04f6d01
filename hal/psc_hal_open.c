/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_open.c - open and close devices of any kind by backend name.
 *
 * The firmware only ever calls these: it names a backend (from the board
 * file) and gets a device, or an error message that says which backends this
 * build has. Close goes through the device's own ops, so the caller never
 * needs to remember which backend a device came from.
 */
#include <stdio.h>
#include <string.h>

#include "psc_hal.h"
#include "psc_hal_camera.h"
#include "psc_hal_clock.h"
#include "psc_hal_display.h"
#include "psc_hal_input.h"
#include "psc_hal_input_multi.h"
#include "psc_hal_watchdog.h"

/* The backend called name, or NULL with err saying what exists instead. */
static const psc_hal_backend_t *backend_lookup(const char *name, const char *device,
                                               char *err, size_t errlen)
{
    const psc_hal_backend_t *b = psc_hal_backend_find(name);
    char list[128];

    if (b == NULL) {
        psc_hal_backend_list(list, sizeof list);
        psc_hal_error_set(err, errlen, "%s backend '%s' is not in this build (available: %s)",
                          device, name ? name : "", list);
    }
    return b;
}

/* The common tail of every open: a backend that lacks the device kind. */
static int backend_lacks(const psc_hal_backend_t *b, const char *device, char *err, size_t errlen)
{
    psc_hal_error_set(err, errlen, "the %s backend does not drive a %s", b->name, device);
    return -ENODEV;
}

int psc_hal_display_open(const char *backend, const psc_hal_display_config_t *cfg,
                         psc_hal_display_t **out, char *err, size_t errlen)
{
    const psc_hal_backend_t *b = backend_lookup(backend, "display", err, errlen);

    *out = NULL;
    if (b == NULL)
        return -ENODEV;
    if (b->display_open == NULL)
        return backend_lacks(b, "display", err, errlen);
    return b->display_open(cfg, out, err, errlen);
}

void psc_hal_display_close(psc_hal_display_t *d)
{
    if (d != NULL)
        d->ops->close(d);
}

int psc_hal_input_open(const char *backend, const psc_hal_input_config_t *cfg,
                       psc_hal_input_t **out, char *err, size_t errlen)
{
    const psc_hal_backend_t *b;

    /* "gpio,usb": several backends merged into one input (psc_hal_input_multi.h) */
    if (backend != NULL && strchr(backend, ',') != NULL)
        return psc_hal_input_multi_open(backend, cfg, out, err, errlen);
    b = backend_lookup(backend, "input", err, errlen);
    *out = NULL;
    if (b == NULL)
        return -ENODEV;
    if (b->input_open == NULL)
        return backend_lacks(b, "input", err, errlen);
    return b->input_open(cfg, out, err, errlen);
}

void psc_hal_input_close(psc_hal_input_t *in)
{
    if (in != NULL)
        in->ops->close(in);
}

int psc_hal_camera_open(const char *backend, const psc_hal_camera_config_t *cfg,
                        psc_hal_camera_t **out, char *err, size_t errlen)
{
    const psc_hal_backend_t *b = backend_lookup(backend, "camera", err, errlen);

    *out = NULL;
    if (b == NULL)
        return -ENODEV;
    if (b->camera_open == NULL)
        return backend_lacks(b, "camera", err, errlen);
    return b->camera_open(cfg, out, err, errlen);
}

void psc_hal_camera_close(psc_hal_camera_t *cam)
{
    if (cam != NULL)
        cam->ops->close(cam);
}

int psc_hal_clock_open(const char *backend, const psc_hal_clock_config_t *cfg,
                       psc_hal_clock_t **out, char *err, size_t errlen)
{
    const psc_hal_backend_t *b = backend_lookup(backend, "clock", err, errlen);

    *out = NULL;
    if (b == NULL)
        return -ENODEV;
    if (b->clock_open == NULL)
        return backend_lacks(b, "clock", err, errlen);
    return b->clock_open(cfg, out, err, errlen);
}

void psc_hal_clock_close(psc_hal_clock_t *clk)
{
    if (clk != NULL)
        clk->ops->close(clk);
}

int psc_hal_watchdog_open(const char *backend, const psc_hal_watchdog_config_t *cfg,
                          psc_hal_watchdog_t **out, char *err, size_t errlen)
{
    const psc_hal_backend_t *b = backend_lookup(backend, "watchdog", err, errlen);

    *out = NULL;
    if (b == NULL)
        return -ENODEV;
    if (b->watchdog_open == NULL)
        return backend_lacks(b, "watchdog", err, errlen);
    return b->watchdog_open(cfg, out, err, errlen);
}

void psc_hal_watchdog_close(psc_hal_watchdog_t *wd)
{
    if (wd != NULL)
        wd->ops->close(wd);
}
