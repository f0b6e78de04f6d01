/* SPDX-License-Identifier: MIT */
/*
 * sim_camera.c - the simulated board's camera: V4L2-style buffer streaming
 * whose frames are the equirectangular test pattern of psc_sim_pattern_fill.
 * Frames become due at the camera's frame rate on the sim clock; a caller
 * that keeps every buffer dequeued starves the camera exactly as a real
 * driver would, which is what firmware tests of the camera path need.
 */
#include <stdlib.h>
#include <string.h>

#include "psc_hal_sim.h"
#include "sim_internal.h"

typedef struct {
    psc_hal_camera_t base;    /* first: the HAL hands this pointer back to us */
    psc_hal_camera_config_t cfg;
    uint32_t stride;
    uint8_t *buffers[PSC_HAL_CAMERA_MAX_BUFFERS];
    bool dequeued[PSC_HAL_CAMERA_MAX_BUFFERS];
    bool streaming;
    uint64_t start_us;
    uint64_t next_seq;        /* the first frame not delivered yet */
    uint8_t next_buffer;      /* round robin, like the driver's queue order */
} sim_camera_t;

static const char *const sim_camera_known_options[] = { NULL };

static int sim_camera_start(psc_hal_camera_t *cam)
{
    sim_camera_t *s = (sim_camera_t *)cam;

    if (s->streaming)
        return -EBUSY;
    s->streaming = true;
    s->start_us = s->cfg.clock ? psc_hal_clock_now_us(s->cfg.clock) : 0;
    s->next_seq = 0;
    memset(s->dequeued, 0, sizeof s->dequeued);
    return 0;
}

static int sim_camera_dequeue(psc_hal_camera_t *cam, psc_hal_camera_frame_t *frame)
{
    sim_camera_t *s = (sim_camera_t *)cam;
    uint64_t now, due;
    unsigned i, b = PSC_HAL_CAMERA_MAX_BUFFERS;

    if (!s->streaming)
        return -EINVAL;
    now = s->cfg.clock ? psc_hal_clock_now_us(s->cfg.clock) : s->start_us;
    /* frames whose capture time has passed; the newest one is delivered and
     * any older undelivered ones count as dropped (a gap in sequence) */
    due = (now - s->start_us) * s->cfg.frame_rate_mhz / 1000000000u;
    if (due < s->next_seq)
        return -EAGAIN;
    for (i = 0; i < s->cfg.buffer_count; i++) {
        unsigned k = (s->next_buffer + i) % s->cfg.buffer_count;
        if (!s->dequeued[k]) {
            b = k;
            break;
        }
    }
    if (b == PSC_HAL_CAMERA_MAX_BUFFERS)
        return -EAGAIN;   /* starved: every buffer is with the caller */
    psc_sim_pattern_fill(s->buffers[b], s->stride, s->cfg.width, s->cfg.height, s->cfg.format, (uint32_t)due);
    s->dequeued[b] = true;
    s->next_buffer = (uint8_t)((b + 1u) % s->cfg.buffer_count);
    s->next_seq = due + 1u;

    memset(frame, 0, sizeof *frame);
    frame->map.projection = PSC_PROJ_EQUIRECT;
    frame->map.format = s->cfg.format;
    frame->map.width = s->cfg.width;
    frame->map.height = s->cfg.height;
    frame->map.stride = s->stride;
    frame->map.pixels = s->buffers[b];
    psc_envmap_default_coverage(&frame->map);
    frame->index = b;
    frame->sequence = (uint32_t)due;
    frame->timestamp_us = s->start_us + due * 1000000000u / s->cfg.frame_rate_mhz;
    return 0;
}

static int sim_camera_queue(psc_hal_camera_t *cam, const psc_hal_camera_frame_t *frame)
{
    sim_camera_t *s = (sim_camera_t *)cam;

    if (frame->index >= s->cfg.buffer_count || !s->dequeued[frame->index])
        return -EINVAL;
    s->dequeued[frame->index] = false;
    return 0;
}

static int sim_camera_stop(psc_hal_camera_t *cam)
{
    sim_camera_t *s = (sim_camera_t *)cam;

    s->streaming = false;
    memset(s->dequeued, 0, sizeof s->dequeued);
    return 0;
}

static void sim_camera_close(psc_hal_camera_t *cam)
{
    sim_camera_t *s = (sim_camera_t *)cam;

    for (unsigned i = 0; i < PSC_HAL_CAMERA_MAX_BUFFERS; i++)
        free(s->buffers[i]);
    free(s);
}

static const psc_hal_camera_ops_t sim_camera_ops = {
    .start = sim_camera_start,
    .dequeue = sim_camera_dequeue,
    .queue = sim_camera_queue,
    .stop = sim_camera_stop,
    .set_exposure = NULL,   /* a generated picture has no exposure */
    .close = sim_camera_close,
};

int psc_sim_camera_open(const psc_hal_camera_config_t *cfg, psc_hal_camera_t **out, char *err, size_t errlen)
{
    sim_camera_t *s;
    int rc;

    *out = NULL;
    if (cfg->width < 2 || cfg->height < 2 || cfg->width > PSC_MAX_MAP_DIM || cfg->height > PSC_MAX_MAP_DIM) {
        psc_hal_error_set(err, errlen, "sim camera: frame size %ux%u is outside 2x2..%ux%u",
                          (unsigned)cfg->width, (unsigned)cfg->height, PSC_MAX_MAP_DIM, PSC_MAX_MAP_DIM);
        return -EINVAL;
    }
    if (cfg->format != PSC_PIX_RGB565 && cfg->format != PSC_PIX_XRGB8888) {
        psc_hal_error_set(err, errlen, "sim camera: pixel format %d is not rgb565 or xrgb8888", (int)cfg->format);
        return -EINVAL;
    }
    if (cfg->buffer_count < 2 || cfg->buffer_count > PSC_HAL_CAMERA_MAX_BUFFERS) {
        psc_hal_error_set(err, errlen, "sim camera: %u buffers requested, 2..%u supported",
                          (unsigned)cfg->buffer_count, PSC_HAL_CAMERA_MAX_BUFFERS);
        return -EINVAL;
    }
    if (cfg->frame_rate_mhz < 1000 || cfg->frame_rate_mhz > 1000000) {
        psc_hal_error_set(err, errlen, "sim camera: frame rate %u mHz is outside 1..1000 Hz",
                          (unsigned)cfg->frame_rate_mhz);
        return -EINVAL;
    }
    rc = psc_hal_options_check(&cfg->options, sim_camera_known_options, "camera", "sim", err, errlen);
    if (rc != 0)
        return rc;
    s = calloc(1, sizeof *s);
    if (s == NULL)
        goto nomem;
    s->base.ops = &sim_camera_ops;
    s->base.backend = "sim";
    s->cfg = *cfg;
    s->cfg.options = (psc_hal_options_t){ NULL, 0 };   /* the caller's strings may not outlive open */
    s->stride = cfg->width * psc_pixfmt_bytes(cfg->format);
    for (unsigned i = 0; i < cfg->buffer_count; i++) {
        s->buffers[i] = calloc(cfg->height, s->stride);
        if (s->buffers[i] == NULL)
            goto nomem;
    }
    *out = &s->base;
    return 0;
nomem:
    if (s != NULL)
        sim_camera_close(&s->base);
    psc_hal_error_set(err, errlen, "sim camera: out of memory for %u buffers of %ux%u",
                      (unsigned)cfg->buffer_count, (unsigned)cfg->width, (unsigned)cfg->height);
    return -ENOMEM;
}
