/* SPDX-License-Identifier: MIT */
/*
 * camera_feed.c - the live camera as a scene's map (camera_feed.h).
 */
#include <string.h>

#include "camera_feed.h"

void psc_camera_feed_init(psc_camera_feed_t *f, psc_hal_camera_t *camera)
{
    memset(f, 0, sizeof *f);
    f->camera = camera;
}

void psc_camera_feed_set_fisheye(psc_camera_feed_t *f, const psc_fisheye_t *table, void *map_pixels)
{
    f->fisheye = table;
    f->fisheye_map = map_pixels;
}

/* Fisheye mode: the frame is copied (remapped) into the feed's own map, so
 * it goes back to the camera at once and nothing is held. */
static int feed_remap(psc_camera_feed_t *f, const psc_hal_camera_frame_t *frame)
{
    psc_envmap_t shape = psc_fisheye_map_shape(f->fisheye, frame->map.format, f->fisheye_map);
    psc_status_t s = psc_fisheye_remap(f->fisheye, &frame->map, f->fisheye_map, shape.stride, 0x000000u);

    if (f->had_frames && frame->sequence > f->last_sequence + 1u)
        f->dropped += frame->sequence - f->last_sequence - 1u;
    f->last_sequence = frame->sequence;
    psc_hal_camera_queue(f->camera, frame);
    if (s != PSC_OK) {
        f->rejected++;
        return -EINVAL;
    }
    f->had_frames = true;
    f->remapped = true;
    f->frames++;
    f->map = shape;
    return 0;
}

int psc_camera_feed_poll(psc_camera_feed_t *f)
{
    psc_hal_camera_frame_t frame;
    int rc;

    if (f->camera == NULL)
        return -ENODEV;
    rc = psc_hal_camera_dequeue(f->camera, &frame);
    if (rc != 0)
        return rc;
    if (f->fisheye != NULL)
        return feed_remap(f, &frame);
    if (f->holding) {
        if (frame.sequence > f->held.sequence + 1u)
            f->dropped += frame.sequence - f->held.sequence - 1u;
        psc_hal_camera_queue(f->camera, &f->held);
    }
    f->held = frame;
    f->holding = true;
    f->had_frames = true;
    f->frames++;
    f->map = frame.map;
    return 0;
}

bool psc_camera_feed_has_map(const psc_camera_feed_t *f)
{
    return f->holding || f->remapped;
}

psc_envmap_t psc_camera_feed_map_shape(uint16_t width, uint16_t height, psc_pixfmt_t format)
{
    psc_envmap_t m;

    memset(&m, 0, sizeof m);
    m.projection = PSC_PROJ_EQUIRECT;
    m.format = format;
    m.width = width;
    m.height = height;
    m.stride = (uint32_t)width * psc_pixfmt_bytes(format);
    psc_envmap_default_coverage(&m);
    return m;
}

void psc_camera_feed_release(psc_camera_feed_t *f)
{
    if (f->holding && f->camera != NULL)
        psc_hal_camera_queue(f->camera, &f->held);
    f->holding = false;
}
