/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_template.c - the skeleton of a new backend. Copy it to
 * hal/<name>/<name>_display.c (and friends), rename "template" to the
 * backend's name, fill in the TODOs, then
 *   1. declare the descriptor in psc_hal_backends.h,
 *   2. list it in psc_hal_registry.c,
 *   3. write a board: boards/<board>/board.conf with "display = <name>" etc.
 * Nothing else in the firmware changes.
 *
 * What a porter must provide, per device kind (see each psc_hal_*.h):
 *   display   get_mode, get_back_buffer, present, close (set_blank and
 *             get_front_buffer are optional: leave them NULL and callers get
 *             -ENOSYS).
 *   input     poll (never blocking; debounce and long press are the
 *             backend's job), close.
 *   camera    start, dequeue, queue, stop, close (hal/sim/sim_camera.c is a
 *             complete example of the buffer bookkeeping).
 *   clock     now_us, sleep_until, close.
 *   watchdog  kick, close (get_status and set_status are optional).
 * Rules the firmware relies on:
 *   - open allocates everything (buffers, tables, descriptor parsing);
 *     callbacks run in the frame loop and must not allocate;
 *   - open validates every option with psc_hal_options_check, so a typo in a
 *     board file is reported with its file and line, and fails with a
 *     sentence in err (device, backend, what is wrong, what would be right);
 *   - close undoes open completely, in reverse order, and works on a
 *     half-opened device (open's error path calls it);
 *   - runtime failures return a negative errno (psc_hal.h), never exit().
 *
 * This file is compiled with the rest of the HAL so it cannot rot, but it is
 * not registered: every open fails with -ENODEV.
 */
#include <stdlib.h>
#include <string.h>

#include "psc_hal_backends.h"
#include "psc_hal_clock.h"
#include "psc_hal_display.h"
#include "psc_hal_input.h"

/* ---- display -------------------------------------------------------------- */

/* Options this backend reads from "display.<key> = value" board lines. */
static const char *const template_display_known_options[] = { "device", NULL };

typedef struct {
    psc_hal_display_t base;        /* first, so (template_display_t *)d works */
    psc_hal_display_mode_t mode;
    int fd;                        /* TODO: the device node, e.g. /dev/fb0 or /dev/dri/card0 */
    uint8_t *buffers[3];           /* TODO: mmap'd scan-out buffers */
    uint8_t back;
} template_display_t;

static int template_display_get_mode(psc_hal_display_t *d, psc_hal_display_mode_t *mode)
{
    *mode = ((template_display_t *)d)->mode;
    return 0;
}

static int template_display_get_back_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    template_display_t *t = (template_display_t *)d;

    surface->width = t->mode.width;
    surface->height = t->mode.height;
    surface->stride = t->mode.stride;
    surface->format = t->mode.format;
    surface->pixels = t->buffers[t->back];
    return 0;
}

static int template_display_present(psc_hal_display_t *d)
{
    template_display_t *t = (template_display_t *)d;

    /* TODO: flip to buffers[back] (FBIOPAN_DISPLAY / drmModePageFlip), wait
     * for the vertical blank or flip event, return -EIO if refused. */
    t->back = (uint8_t)((t->back + 1u) % t->mode.buffer_count);
    return 0;
}

static void template_display_close(psc_hal_display_t *d)
{
    /* TODO: restore the console mode, munmap, close(fd). */
    free(d);
}

static const psc_hal_display_ops_t template_display_ops = {
    .get_mode = template_display_get_mode,
    .get_back_buffer = template_display_get_back_buffer,
    .present = template_display_present,
    .set_blank = NULL,            /* optional: NULL means -ENOSYS for callers */
    .get_front_buffer = NULL,
    .close = template_display_close,
};

static int template_display_open(const psc_hal_display_config_t *cfg, psc_hal_display_t **out,
                                 char *err, size_t errlen)
{
    template_display_t *t;
    int rc;

    *out = NULL;
    rc = psc_hal_options_check(&cfg->options, template_display_known_options, "display", "template",
                               err, errlen);
    if (rc != 0)
        return rc;
    t = calloc(1, sizeof *t);
    if (t == NULL) {
        psc_hal_error_set(err, errlen, "template display: out of memory");
        return -ENOMEM;
    }
    t->base.ops = &template_display_ops;
    t->base.backend = "template";
    t->fd = -1;
    /* TODO: open the device named by option "device", set cfg->width x
     * cfg->height in cfg->format, map cfg->buffer_count buffers, fill t->mode.
     * On any failure: say what and where in err, close, return the errno. */
    psc_hal_error_set(err, errlen, "template display: this is a skeleton for porters, not a backend");
    template_display_close(&t->base);
    return -ENODEV;
}

/* ---- input ---------------------------------------------------------------- */

typedef struct {
    psc_hal_input_t base;
    psc_hal_clock_t *clock;        /* debounce and long-press timing */
    /* TODO: device handles, per-line debounce state, an event ring sized at open */
} template_input_t;

static int template_input_poll(psc_hal_input_t *in, uint64_t now_us, psc_hal_input_event_t *ev)
{
    (void)in;
    (void)now_us;
    (void)ev;
    /* TODO: read pending kernel events without blocking, debounce them, map
     * them to actions/axes, and return the oldest one whose time <= now_us. */
    return 0;
}

static void template_input_close(psc_hal_input_t *in)
{
    free(in);
}

static const psc_hal_input_ops_t template_input_ops = {
    .poll = template_input_poll,
    .get_device_name = NULL,
    .close = template_input_close,
};

static int template_input_open(const psc_hal_input_config_t *cfg, psc_hal_input_t **out,
                               char *err, size_t errlen)
{
    template_input_t *t = calloc(1, sizeof *t);

    *out = NULL;
    if (t == NULL) {
        psc_hal_error_set(err, errlen, "template input: out of memory");
        return -ENOMEM;
    }
    t->base.ops = &template_input_ops;
    t->base.backend = "template";
    t->clock = cfg->clock;
    psc_hal_error_set(err, errlen, "template input: this is a skeleton for porters, not a backend");
    template_input_close(&t->base);
    return -ENODEV;
}

/* ---- descriptor ----------------------------------------------------------- */

const psc_hal_backend_t psc_hal_template_backend = {
    .name = "template",
    .description = "skeleton for porters; drives nothing",
    .display_open = template_display_open,
    .input_open = template_input_open,
    .camera_open = NULL,      /* NULL: "the template backend does not drive a camera" */
    .clock_open = NULL,
    .watchdog_open = NULL,
};
