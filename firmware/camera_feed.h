/* SPDX-License-Identifier: MIT */
/*
 * camera_feed.h - the live camera as a scene's environment map.
 *
 * The device has no floating point to build viewer tables at start-up, so a
 * camera scene borrows them: the board names a scene pack packed for this
 * display (camera_scene = FILE.pano; its map is shown until the first camera
 * frame arrives, so it can be a "camera starting" picture), and each new
 * camera frame replaces the pack's map in the viewer. The pack's LUTs hold
 * angles, not map positions, so they serve any map size; the camera's frames
 * are equirectangular maps of the board's camera_size.
 *
 * Buffers: the feed holds exactly one dequeued frame - the one on screen -
 * and gives it back to the camera when a newer one arrives; the camera fills
 * the others meanwhile. After the camera is lost the held frame stays valid
 * (it is the camera backend's memory), so the last picture stays up.
 *
 * Dual-fisheye cameras (board key camera_fisheye_table): each frame is two
 * fisheye circles, not a map. With a table set (psc_camera_feed_set_fisheye)
 * every new frame is remapped through it (core/fisheye/psc_fisheye.h, integer
 * bilinear) into one map buffer the caller allocated at start-up, and the
 * frame goes straight back to the camera; feed->map then describes that
 * buffer (equirectangular, the table's map size).
 */
#ifndef PSC_CAMERA_FEED_H
#define PSC_CAMERA_FEED_H

#include <stdbool.h>
#include <stdint.h>

#include "envmap/psc_envmap.h"
#include "psc_hal_camera.h"
#include "fisheye/psc_fisheye.h"

typedef struct {
    psc_hal_camera_t *camera;        /* not owned */
    psc_hal_camera_frame_t held;     /* the frame on screen, valid while holding */
    bool holding;
    psc_envmap_t map;                /* the viewer points at this; updated per frame */
    bool had_frames;                 /* a frame ever arrived */
    uint32_t frames;                 /* frames taken */
    uint32_t dropped;                /* gaps in the camera's sequence numbers */
    const psc_fisheye_t *fisheye;    /* not owned; NULL = frames are maps already */
    void *fisheye_map;               /* the remapped map's pixels (caller's, rows of map_width pixels) */
    uint32_t rejected;               /* frames the fisheye table did not fit (size or format) */
    uint32_t last_sequence;          /* fisheye mode: the last frame's sequence number */
    bool remapped;                   /* fisheye mode: fisheye_map holds a frame */
} psc_camera_feed_t;

/** A feed of camera (NULL: no camera; every poll then returns -ENODEV). */
void psc_camera_feed_init(psc_camera_feed_t *f, psc_hal_camera_t *camera);

/**
 * Remap every frame through a dual-fisheye table into map_pixels (map_width x
 * map_height pixels of the camera's format, allocated by the caller and
 * valid while the feed lives). Call after init, before polling.
 */
void psc_camera_feed_set_fisheye(psc_camera_feed_t *f, const psc_fisheye_t *table, void *map_pixels);

/**
 * Take the camera's newest frame if there is one: 0 when feed->map now
 * describes a new frame, else the camera's -EAGAIN (nothing new) or -ENODEV
 * (absent or lost; the camera keeps trying to reopen by itself). Never blocks.
 * With a fisheye table, a frame the table does not fit (size or format) is
 * given back, counted in rejected, and -EINVAL returned (the map is unchanged).
 */
int psc_camera_feed_poll(psc_camera_feed_t *f);

/** True when feed->map holds a frame (from now or from before a loss). */
bool psc_camera_feed_has_map(const psc_camera_feed_t *f);

/**
 * The map description of a camera frame, for sizing the viewer's workspace
 * at start-up before any frame exists: equirectangular, full sphere.
 */
psc_envmap_t psc_camera_feed_map_shape(uint16_t width, uint16_t height, psc_pixfmt_t format);

/** Give the held frame back (before the camera stops). */
void psc_camera_feed_release(psc_camera_feed_t *f);

#endif
