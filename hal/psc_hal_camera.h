/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_camera.h - a video source whose frames are environment maps (a
 * 360-degree camera delivering equirectangular frames, or a fixed camera
 * whose frames cover a partial panorama).
 *
 * Streaming model (V4L2's, so a V4L2 backend is a thin layer): at open the
 * backend allocates buffer_count buffers (VIDIOC_REQBUFS + mmap). start
 * queues all of them and starts streaming; dequeue hands the caller the
 * oldest filled buffer as a psc_hal_camera_frame_t whose map points into the
 * buffer (psc_envmap_t, ready for psc_viewer_init); the caller must queue it
 * back before the camera can fill it again. With every buffer dequeued the
 * camera starves and dequeue returns -EAGAIN.
 * Backends: v4l2 (hal/v4l2/: mmap streaming, YUYV or MJPEG converted into
 * map buffers, timestamps from the buffer, reopened after an unplug), sim (a
 * generated test-pattern map, one frame per frame period).
 *
 * A camera may come and go (a USB cable): dequeue returns -ENODEV while the
 * device is absent or lost; the backend keeps trying to reopen it by itself
 * and dequeue returns frames again once it is back. Maps the caller holds
 * stay valid (they are the backend's memory, not the driver's).
 */
#ifndef PSC_HAL_CAMERA_H
#define PSC_HAL_CAMERA_H

#include "psc_hal.h"
#include "envmap/psc_envmap.h"

#define PSC_HAL_CAMERA_MAX_BUFFERS 8u

/** Configuration of a camera. */
typedef struct psc_hal_camera_config {
    uint16_t width, height;       /* frame (map) size */
    psc_pixfmt_t format;          /* RGB565 or XRGB8888 */
    uint8_t buffer_count;         /* 2..PSC_HAL_CAMERA_MAX_BUFFERS */
    uint32_t frame_rate_mhz;      /* millihertz */
    psc_hal_clock_t *clock;       /* timestamps; must outlive the camera */
    psc_hal_options_t options;    /* backend-specific (none for sim) */
} psc_hal_camera_config_t;

/** A dequeued frame: a map description pointing into one of the camera's buffers. */
typedef struct {
    psc_envmap_t map;         /* projection, size, coverage and pixels of the frame */
    uint32_t index;           /* buffer index, for queue */
    uint32_t sequence;        /* frame counter since start; a gap means frames were dropped */
    uint64_t timestamp_us;    /* capture time on the camera's clock */
} psc_hal_camera_frame_t;

typedef struct {
    /* Mandatory. Start streaming. -EBUSY when already streaming. */
    int (*start)(psc_hal_camera_t *cam);
    /* Mandatory. Take the oldest filled buffer (a live camera may give the
     * newest and drop older ones; sequence shows the gap). -EAGAIN when none
     * is ready, -ENODEV while the device is absent or lost, -EINVAL when not
     * streaming. Never blocks. */
    int (*dequeue)(psc_hal_camera_t *cam, psc_hal_camera_frame_t *frame);
    /* Mandatory. Give a dequeued buffer back to be filled again. -EINVAL for
     * a frame that is not dequeued. */
    int (*queue)(psc_hal_camera_t *cam, const psc_hal_camera_frame_t *frame);
    /* Mandatory. Stop streaming; every buffer returns to the camera, and maps
     * handed out before must not be read any more. */
    int (*stop)(psc_hal_camera_t *cam);
    /* Optional. Set exposure in microseconds (0 = automatic). */
    int (*set_exposure)(psc_hal_camera_t *cam, uint32_t exposure_us);
    /* Mandatory. Stop if streaming, unmap and free everything. */
    void (*close)(psc_hal_camera_t *cam);
} psc_hal_camera_ops_t;

/** The public part of a camera; backends embed it first in their state. */
struct psc_hal_camera {
    const psc_hal_camera_ops_t *ops;
    const char *backend;
};

/**
 * Open a camera of the named backend (board key "camera") with its buffers
 * allocated. 0 and *out set, or a negative errno (psc_hal.h) with err filled.
 */
int psc_hal_camera_open(const char *backend, const psc_hal_camera_config_t *cfg,
                        psc_hal_camera_t **out, char *err, size_t errlen);

/** Close a camera opened with psc_hal_camera_open (NULL is ignored). */
void psc_hal_camera_close(psc_hal_camera_t *cam);

/** Start streaming. */
static inline int psc_hal_camera_start(psc_hal_camera_t *cam)
{
    return cam->ops->start(cam);
}

/** Take the oldest filled frame; -EAGAIN when none is ready. */
static inline int psc_hal_camera_dequeue(psc_hal_camera_t *cam, psc_hal_camera_frame_t *frame)
{
    return cam->ops->dequeue(cam, frame);
}

/** Give a dequeued frame's buffer back to the camera. */
static inline int psc_hal_camera_queue(psc_hal_camera_t *cam, const psc_hal_camera_frame_t *frame)
{
    return cam->ops->queue(cam, frame);
}

/** Stop streaming. */
static inline int psc_hal_camera_stop(psc_hal_camera_t *cam)
{
    return cam->ops->stop(cam);
}

/** Set the exposure time; -ENOSYS when the backend cannot. */
static inline int psc_hal_camera_set_exposure(psc_hal_camera_t *cam, uint32_t exposure_us)
{
    return cam->ops->set_exposure ? cam->ops->set_exposure(cam, exposure_us) : -ENOSYS;
}

#endif
