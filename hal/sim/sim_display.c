/* SPDX-License-Identifier: MIT */
/*
 * sim_display.c - the simulated board's display: frame buffers in memory,
 * presents that advance the sim clock by one frame period, and PNG capture of
 * every K-th presented frame for humans and golden tests to look at.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

#include "psc_hal_buffer_ring.h"
#include "psc_hal_sim.h"
#include "sim_internal.h"
#include "psc_io_log.h"

#define SIM_DISPLAY_MAX_BUFFERS PSC_HAL_RING_MAX_BUFFERS
#define SIM_DISPLAY_PITCH_ALIGN 64u
#define SIM_DISPLAY_PATH_MAX 1024u

typedef struct {
    psc_hal_display_t base;   /* first: the HAL hands this pointer back to us */
    psc_hal_clock_t *clock;
    uint64_t start_us;        /* clock reading at open: frame 0's time */
    uint32_t frame_rate_mhz;
    psc_hal_buffer_ring_t ring;   /* mode, buffers, front */
    uint32_t presents;
    uint32_t capture_every;   /* 0 = never */
    char capture_dir[SIM_DISPLAY_PATH_MAX];
    char contact_sheet[SIM_DISPLAY_PATH_MAX];   /* written at close when non-empty */
    char path[SIM_DISPLAY_PATH_MAX + 32];   /* capture file name, built without allocating */
} sim_display_t;

static const char *const sim_display_known_options[] = { "capture_dir", "capture_every", "contact_sheet", NULL };

int psc_sim_capture_path(char *buf, size_t len, const char *dir, uint32_t frame)
{
    int n = snprintf(buf, len, "%s/frame_%06u.png", dir, (unsigned)frame);

    return (n < 0 || (size_t)n >= len) ? -1 : 0;
}

/* mkdir -p: captures go to a fresh output directory on the first run. */
static int make_dirs(const char *path, char *err, size_t errlen)
{
    char tmp[SIM_DISPLAY_PATH_MAX];
    size_t len = strlen(path);

    if (len == 0 || len >= sizeof tmp) {
        psc_hal_error_set(err, errlen, "sim display: capture directory name is empty or too long");
        return -EINVAL;
    }
    memcpy(tmp, path, len + 1);
    for (size_t i = 1; i <= len; i++) {
        if (tmp[i] != '/' && tmp[i] != '\0')
            continue;
        char saved = tmp[i];
        tmp[i] = '\0';
        if (mkdir(tmp, 0777) != 0 && errno != EEXIST) {
            psc_hal_error_set(err, errlen, "sim display: cannot create capture directory %s: %s",
                              tmp, strerror(errno));
            return -EIO;
        }
        tmp[i] = saved;
    }
    return 0;
}

static sim_display_t *to_sim(psc_hal_display_t *d)
{
    return (sim_display_t *)d;
}

static int sim_display_get_mode(psc_hal_display_t *d, psc_hal_display_mode_t *mode)
{
    *mode = to_sim(d)->ring.mode;
    return 0;
}

static int sim_display_get_back_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    sim_display_t *s = to_sim(d);

    psc_hal_buffer_ring_surface(&s->ring, psc_hal_buffer_ring_back(&s->ring), surface);
    return 0;
}

static int sim_display_get_front_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    sim_display_t *s = to_sim(d);

    psc_hal_buffer_ring_surface(&s->ring, s->ring.front, surface);
    return 0;
}

static int sim_display_present(psc_hal_display_t *d)
{
    sim_display_t *s = to_sim(d);
    uint32_t frame = s->presents;
    psc_surface_t shown;
    char err[256];

    psc_hal_buffer_ring_advance(&s->ring);
    s->presents++;
    /* Time of the next frame computed from the count, not by adding a
     * rounded period, so 30 fps stays exact over any number of frames. */
    psc_sim_clock_advance_to(s->clock, s->start_us + (uint64_t)s->presents * 1000000000u / s->frame_rate_mhz);

    if (s->capture_every == 0 || frame % s->capture_every != 0)
        return 0;
    psc_hal_buffer_ring_surface(&s->ring, s->ring.front, &shown);
    if (psc_sim_capture_path(s->path, sizeof s->path, s->capture_dir, frame) != 0) {
        psc_io_log(PSC_LOG_ERR, "sim display: capture path for frame %u is too long", (unsigned)frame);
        return -EIO;
    }
    if (psc_sim_capture_write(s->path, &shown, err, sizeof err) != 0) {
        /* present has no error buffer: the generic interface keeps runtime
         * errors to an errno, so the host-only sim says why on stderr. */
        psc_io_log(PSC_LOG_ERR, "sim display: frame %u not captured: %s", (unsigned)frame, err);
        return -EIO;
    }
    return 0;
}

static int sim_display_set_blank(psc_hal_display_t *d, bool blank)
{
    sim_display_t *s = to_sim(d);

    /* A blanked panel shows black: clear the front buffer so a capture of it
     * looks like what a person would see. */
    if (blank)
        memset(s->ring.buffers[s->ring.front], 0, (size_t)s->ring.mode.stride * s->ring.mode.height);
    return 0;
}

/* The run at a glance, once it is over (sim_capture_sheet.c). */
static void sim_display_write_contact_sheet(const sim_display_t *s)
{
    char err[1200];
    uint32_t thumbs;

    if (s->contact_sheet[0] == '\0' || s->capture_every == 0 || s->presents == 0)
        return;
    if (psc_sim_contact_sheet_write(s->capture_dir, s->presents, s->capture_every, s->contact_sheet, &thumbs, err,
                                    sizeof err) != 0)
        psc_io_log(PSC_LOG_ERR, "sim display: contact sheet: %s", err);
    else
        psc_io_log(PSC_LOG_INFO, "sim display: contact sheet: %s (%u frames)", s->contact_sheet, (unsigned)thumbs);
}

static void sim_display_close(psc_hal_display_t *d)
{
    sim_display_t *s = to_sim(d);

    sim_display_write_contact_sheet(s);
    for (unsigned i = 0; i < SIM_DISPLAY_MAX_BUFFERS; i++)
        free(s->ring.buffers[i]);
    free(s);
}

static const psc_hal_display_ops_t sim_display_ops = {
    .get_mode = sim_display_get_mode,
    .get_back_buffer = sim_display_get_back_buffer,
    .present = sim_display_present,
    .set_blank = sim_display_set_blank,
    .get_front_buffer = sim_display_get_front_buffer,
    .close = sim_display_close,
};

/* Check the generic part of the configuration before allocating anything. */
static int sim_display_check_config(const psc_hal_display_config_t *cfg, char *err, size_t errlen)
{
    if (cfg->width == 0 || cfg->height == 0 || cfg->width > PSC_MAX_OUT_DIM || cfg->height > PSC_MAX_OUT_DIM) {
        psc_hal_error_set(err, errlen, "sim display: size %ux%u is outside 1x1..%ux%u",
                          (unsigned)cfg->width, (unsigned)cfg->height, PSC_MAX_OUT_DIM, PSC_MAX_OUT_DIM);
        return -EINVAL;
    }
    if (cfg->format != PSC_PIX_RGB565 && cfg->format != PSC_PIX_XRGB8888) {
        psc_hal_error_set(err, errlen, "sim display: pixel format %d is not rgb565 or xrgb8888", (int)cfg->format);
        return -EINVAL;
    }
    if (cfg->buffer_count < 1 || cfg->buffer_count > SIM_DISPLAY_MAX_BUFFERS) {
        psc_hal_error_set(err, errlen, "sim display: %u buffers requested, 1..%u supported",
                          (unsigned)cfg->buffer_count, SIM_DISPLAY_MAX_BUFFERS);
        return -EINVAL;
    }
    if (cfg->frame_rate_mhz < 1000 || cfg->frame_rate_mhz > 1000000) {
        psc_hal_error_set(err, errlen, "sim display: frame rate %u mHz is outside 1..1000 Hz",
                          (unsigned)cfg->frame_rate_mhz);
        return -EINVAL;
    }
    return psc_hal_options_check(&cfg->options, sim_display_known_options, "display", "sim", err, errlen);
}

int psc_sim_display_open(const psc_hal_display_config_t *cfg, psc_hal_display_t **out, char *err, size_t errlen)
{
    const psc_hal_option_t *dir, *sheet;
    sim_display_t *s;
    size_t bytes;
    int rc;

    *out = NULL;
    rc = sim_display_check_config(cfg, err, errlen);
    if (rc != 0)
        return rc;
    s = calloc(1, sizeof *s);
    if (s == NULL)
        goto nomem;
    s->base.ops = &sim_display_ops;
    s->base.backend = "sim";
    s->clock = cfg->clock;
    s->start_us = cfg->clock != NULL ? psc_hal_clock_now_us(cfg->clock) : 0;
    s->frame_rate_mhz = cfg->frame_rate_mhz;
    s->ring.mode.width = cfg->width;
    s->ring.mode.height = cfg->height;
    s->ring.mode.format = cfg->format;
    s->ring.mode.stride = (cfg->width * psc_pixfmt_bytes(cfg->format) + SIM_DISPLAY_PITCH_ALIGN - 1u) &
                     ~(SIM_DISPLAY_PITCH_ALIGN - 1u);
    s->ring.mode.refresh_mhz = cfg->frame_rate_mhz;
    s->ring.mode.buffer_count = cfg->buffer_count;

    rc = psc_hal_options_get_u32(&cfg->options, "capture_every", 0, 1000000, 0, &s->capture_every, err, errlen);
    if (rc != 0)
        goto fail;
    dir = psc_hal_options_find(&cfg->options, "capture_dir");
    if (s->capture_every != 0) {
        if (dir == NULL || dir->value == NULL || dir->value[0] == '\0') {
            psc_hal_error_set(err, errlen, "sim display: capture_every is %u but no capture_dir is set",
                              (unsigned)s->capture_every);
            rc = -EINVAL;
            goto fail;
        }
        if (strlen(dir->value) >= sizeof s->capture_dir) {
            psc_hal_error_set(err, errlen, "%s: capture_dir is longer than %u characters",
                              dir->origin ? dir->origin : "sim display", SIM_DISPLAY_PATH_MAX - 1u);
            rc = -EINVAL;
            goto fail;
        }
        strcpy(s->capture_dir, dir->value);
        rc = make_dirs(s->capture_dir, err, errlen);
        if (rc != 0)
            goto fail;
    }
    if (s->capture_every != 0 && !psc_sim_capture_available()) {
        psc_hal_error_set(err, errlen, "sim display: this build has no PNG captures (its board's backends line "
                          "leaves out sim), so it cannot capture every %u frames", (unsigned)s->capture_every);
        rc = -EINVAL;
        goto fail;
    }
    sheet = psc_hal_options_find(&cfg->options, "contact_sheet");
    if (sheet != NULL && sheet->value != NULL) {
        if (strlen(sheet->value) >= sizeof s->contact_sheet) {
            psc_hal_error_set(err, errlen, "%s: contact_sheet is longer than %u characters",
                              sheet->origin ? sheet->origin : "sim display", SIM_DISPLAY_PATH_MAX - 1u);
            rc = -EINVAL;
            goto fail;
        }
        strcpy(s->contact_sheet, sheet->value);
    }

    bytes = (size_t)s->ring.mode.stride * s->ring.mode.height;
    for (unsigned i = 0; i < s->ring.mode.buffer_count; i++) {
        s->ring.buffers[i] = calloc(1, bytes);
        if (s->ring.buffers[i] == NULL)
            goto nomem;
    }
    *out = &s->base;
    return 0;

nomem:
    psc_hal_error_set(err, errlen, "sim display: out of memory for %ux%u buffers",
                      (unsigned)cfg->width, (unsigned)cfg->height);
    rc = -ENOMEM;
fail:
    if (s != NULL)
        sim_display_close(&s->base);
    return rc;
}
