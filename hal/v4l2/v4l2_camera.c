/* SPDX-License-Identifier: MIT */
/*
 * v4l2_camera.c - the "v4l2" camera: a V4L2 capture device (a UVC webcam or
 * 360-degree camera, vivid in the VM tests) streamed with mmap buffers, each
 * frame converted (psc_v4l2_convert.h) into an equirectangular map buffer
 * that the viewer renders as the live scene.
 *
 * Buffers: the driver's mmap buffers (VIDIOC_REQBUFS/QUERYBUF) never leave
 * this file. dequeue takes the newest filled one (older ones are handed
 * straight back, so the picture lags as little as possible), converts it into
 * one of cfg->buffer_count map buffers allocated at open, re-queues it at
 * once and hands the map to the caller, who queues the map back when it
 * shows a newer one.
 *
 * Never blocking: dequeue polls with a zero timeout. A camera that delivers
 * nothing for timeout_ms counts as lost, like one that was unplugged
 * (ENODEV/EIO from the driver): the device is closed, dequeue returns -ENODEV,
 * and every reopen_ms it is opened and negotiated again; when that works,
 * frames flow again with no help from the caller. Map buffers the caller
 * holds stay valid throughout, so the last picture can stay on screen.
 *
 * Options (board lines "camera.KEY = VALUE"):
 *   device        the video node (default /dev/video0)
 *   pixel_format  auto (YUYV if offered, else MJPEG), yuyv, mjpeg
 *   capture_size  WxH asked of the driver (default: the board's camera_size);
 *                 the driver may pick the nearest size it has, and frames are
 *                 resampled to camera_size either way
 *   timeout_ms    no frame for this long = lost (100..60000, default 2000)
 *   reopen_ms     retry period while lost (100..60000, default 1000)
 *   required      yes: fail at start-up when the camera is absent; no
 *                 (default): start without it and keep trying
 * Transitions (lost, back, dropped corrupt frames) are reported on stderr
 * with the device and the reason, once each.
 */
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include <linux/videodev2.h>

#include "psc_hal_backends.h"
#include "psc_hal_camera.h"
#include "psc_hal_clock.h"
#include "psc_hal_option_bool.h"
#include "psc_v4l2_convert.h"
#include "v4l2_internal.h"
#include "psc_io_log.h"

#define V4L2_MAX_DRIVER_BUFFERS 8u
#define V4L2_PATH_MAX 256u

typedef struct {
    void *start;
    size_t length;
} v4l2_mapping_t;

typedef struct {
    psc_hal_camera_t base;          /* first: the HAL hands this pointer back to us */
    /* configuration, fixed at open */
    uint16_t width, height;         /* the map */
    psc_pixfmt_t format;
    uint8_t buffer_count;
    uint32_t frame_rate_mhz;
    psc_hal_clock_t *clock;
    char device[V4L2_PATH_MAX];
    uint32_t want_fourcc;           /* 0 = auto */
    uint16_t capture_width, capture_height;
    uint32_t timeout_ms, reopen_ms;
    /* the device, while present */
    int fd;
    uint32_t fourcc;                /* negotiated V4L2_PIX_FMT_YUYV or _MJPEG */
    uint32_t bytesperline;
    v4l2_mapping_t driver[V4L2_MAX_DRIVER_BUFFERS];
    uint32_t driver_count;
    bool streaming;                 /* STREAMON done on fd */
    /* the caller's side */
    bool started;                   /* start() called, stop() not yet */
    uint8_t *maps[PSC_HAL_CAMERA_MAX_BUFFERS];
    bool dequeued[PSC_HAL_CAMERA_MAX_BUFFERS];
    uint32_t map_stride;
    psc_v4l2_resample_t resample;   /* col/row tables sized for the map at open */
    psc_v4l2_mjpeg_t *mjpeg;
    uint64_t last_frame_us;         /* HAL clock: the last frame, or (re)start */
    uint64_t next_retry_us;
    uint32_t sequence;              /* frame counter since start, gaps where frames were dropped */
    uint32_t driver_sequence;       /* the driver's sequence number of the last frame taken */
    bool driver_sequence_valid;     /* false until the first frame of a stream */
    bool lost_reported;
    char reason[200];               /* why the device is absent, for the log */
} v4l2_camera_t;

static const char *const v4l2_camera_known_options[] = {
    "device", "pixel_format", "capture_size", "timeout_ms", "reopen_ms", "required", NULL
};

static int xioctl(int fd, unsigned long request, void *arg)
{
    int rc;

    do {
        rc = ioctl(fd, request, arg);
    } while (rc < 0 && errno == EINTR);
    return rc;
}

/* ---- device: open, negotiate, stream, lose -------------------------------- */

static void device_close(v4l2_camera_t *c)
{
    if (c->fd >= 0 && c->streaming) {
        int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        xioctl(c->fd, VIDIOC_STREAMOFF, &type);
    }
    c->streaming = false;
    for (uint32_t i = 0; i < c->driver_count; i++)
        if (c->driver[i].start != NULL && c->driver[i].start != MAP_FAILED)
            munmap(c->driver[i].start, c->driver[i].length);
    memset(c->driver, 0, sizeof c->driver);
    if (c->fd >= 0 && c->driver_count > 0) {
        struct v4l2_requestbuffers req = { .count = 0, .type = V4L2_BUF_TYPE_VIDEO_CAPTURE,
                                           .memory = V4L2_MEMORY_MMAP };
        xioctl(c->fd, VIDIOC_REQBUFS, &req);   /* fails on an unplugged device; harmless */
    }
    c->driver_count = 0;
    if (c->fd >= 0)
        close(c->fd);
    c->fd = -1;
}

/* Pick the pixel format among those the device offers. */
static int device_choose_format(v4l2_camera_t *c, char *err, size_t errlen)
{
    char offered[120] = "", name[5];
    size_t used = 0;
    bool has_yuyv = false, has_mjpeg = false;

    for (uint32_t i = 0; i < 64; i++) {
        struct v4l2_fmtdesc d = { .index = i, .type = V4L2_BUF_TYPE_VIDEO_CAPTURE };
        if (xioctl(c->fd, VIDIOC_ENUM_FMT, &d) != 0)
            break;
        has_yuyv |= d.pixelformat == V4L2_PIX_FMT_YUYV;
        has_mjpeg |= d.pixelformat == V4L2_PIX_FMT_MJPEG;
        psc_v4l2_fourcc_name(d.pixelformat, name);
        if (used + 6 < sizeof offered)
            used += (size_t)snprintf(offered + used, sizeof offered - used, "%s%s", used ? " " : "", name);
    }
    c->fourcc = psc_v4l2_pick_format(c->want_fourcc, has_yuyv, has_mjpeg);
    if (c->fourcc == 0) {
        psc_hal_error_set(err, errlen, "%s offers %s; periscope reads %s", c->device, offered[0] ? offered : "no formats",
                          c->want_fourcc == V4L2_PIX_FMT_YUYV ? "YUYV (pixel_format = yuyv)"
                          : c->want_fourcc == V4L2_PIX_FMT_MJPEG ? "MJPG (pixel_format = mjpeg)"
                                                                 : "YUYV or MJPG");
        return -EINVAL;
    }
    return 0;
}

/* Set the format and size; the driver may adjust the size. */
static int device_set_format(v4l2_camera_t *c, char *err, size_t errlen)
{
    struct v4l2_format f = { .type = V4L2_BUF_TYPE_VIDEO_CAPTURE };
    struct v4l2_streamparm parm = { .type = V4L2_BUF_TYPE_VIDEO_CAPTURE };
    char name[5];

    f.fmt.pix.width = c->capture_width;
    f.fmt.pix.height = c->capture_height;
    f.fmt.pix.pixelformat = c->fourcc;
    f.fmt.pix.field = V4L2_FIELD_NONE;
    if (xioctl(c->fd, VIDIOC_S_FMT, &f) != 0) {
        psc_hal_error_set(err, errlen, "%s: VIDIOC_S_FMT failed: %s", c->device, strerror(errno));
        return -errno;
    }
    psc_v4l2_fourcc_name(f.fmt.pix.pixelformat, name);
    if (f.fmt.pix.pixelformat != c->fourcc) {
        psc_hal_error_set(err, errlen, "%s: the driver switched the format to %s", c->device, name);
        return -EINVAL;
    }
    if (psc_v4l2_check_frame(f.fmt.pix.pixelformat, f.fmt.pix.width, f.fmt.pix.height, f.fmt.pix.bytesperline,
                             f.fmt.pix.field, err, errlen) != 0)
        return -EINVAL;
    c->bytesperline = f.fmt.pix.bytesperline;
    psc_v4l2_resample_init(&c->resample, (uint16_t)f.fmt.pix.width, (uint16_t)f.fmt.pix.height);
    /* the frame rate is a wish: many drivers pick their own */
    parm.parm.capture.timeperframe.numerator = 1000;
    parm.parm.capture.timeperframe.denominator = c->frame_rate_mhz;
    xioctl(c->fd, VIDIOC_S_PARM, &parm);
    return 0;
}

static int device_map_buffers(v4l2_camera_t *c, char *err, size_t errlen)
{
    struct v4l2_requestbuffers req = { .count = c->buffer_count, .type = V4L2_BUF_TYPE_VIDEO_CAPTURE,
                                       .memory = V4L2_MEMORY_MMAP };

    if (xioctl(c->fd, VIDIOC_REQBUFS, &req) != 0 || req.count < 2) {
        psc_hal_error_set(err, errlen, "%s: mmap streaming is not available (VIDIOC_REQBUFS: %s)", c->device,
                          req.count < 2 && errno == 0 ? "fewer than 2 buffers" : strerror(errno));
        return -EIO;
    }
    c->driver_count = req.count < V4L2_MAX_DRIVER_BUFFERS ? req.count : V4L2_MAX_DRIVER_BUFFERS;
    for (uint32_t i = 0; i < c->driver_count; i++) {
        struct v4l2_buffer b = { .index = i, .type = V4L2_BUF_TYPE_VIDEO_CAPTURE, .memory = V4L2_MEMORY_MMAP };
        if (xioctl(c->fd, VIDIOC_QUERYBUF, &b) != 0) {
            psc_hal_error_set(err, errlen, "%s: VIDIOC_QUERYBUF %u: %s", c->device, (unsigned)i, strerror(errno));
            return -EIO;
        }
        c->driver[i].length = b.length;
        c->driver[i].start = mmap(NULL, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, c->fd, b.m.offset);
        if (c->driver[i].start == MAP_FAILED) {
            c->driver[i].start = NULL;
            psc_hal_error_set(err, errlen, "%s: mmap of buffer %u: %s", c->device, (unsigned)i, strerror(errno));
            return -EIO;
        }
    }
    return 0;
}

static int device_stream_on(v4l2_camera_t *c, char *err, size_t errlen)
{
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;

    for (uint32_t i = 0; i < c->driver_count; i++) {
        struct v4l2_buffer b = { .index = i, .type = V4L2_BUF_TYPE_VIDEO_CAPTURE, .memory = V4L2_MEMORY_MMAP };
        if (xioctl(c->fd, VIDIOC_QBUF, &b) != 0) {
            psc_hal_error_set(err, errlen, "%s: VIDIOC_QBUF: %s", c->device, strerror(errno));
            return -EIO;
        }
    }
    if (xioctl(c->fd, VIDIOC_STREAMON, &type) != 0) {
        psc_hal_error_set(err, errlen, "%s: VIDIOC_STREAMON: %s", c->device, strerror(errno));
        return -EIO;
    }
    c->streaming = true;
    c->driver_sequence_valid = false;   /* a new stream counts from its own start */
    c->last_frame_us = psc_hal_clock_now_us(c->clock);
    return 0;
}

/* Open and set up the device; streams too when the caller has started. On
 * failure the device is closed again and err says why. -ENODEV when the node
 * is not there (yet), another negative errno when it is the wrong device. */
static int device_open(v4l2_camera_t *c, char *err, size_t errlen)
{
    struct v4l2_capability cap;
    uint32_t caps;
    int rc;

    c->fd = open(c->device, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (c->fd < 0) {
        rc = errno == ENOENT || errno == ENODEV || errno == ENXIO ? -ENODEV : -errno;
        psc_hal_error_set(err, errlen, "cannot open %s: %s", c->device, strerror(errno));
        return rc;
    }
    memset(&cap, 0, sizeof cap);
    if (xioctl(c->fd, VIDIOC_QUERYCAP, &cap) != 0) {
        rc = errno == ENODEV ? -ENODEV : -EINVAL;
        psc_hal_error_set(err, errlen, "%s is not a V4L2 device (VIDIOC_QUERYCAP: %s)", c->device, strerror(errno));
        goto fail;
    }
    caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
    if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING)) {
        psc_hal_error_set(err, errlen, "%s (%.32s) is not a video capture device with streaming I/O "
                          "(capabilities 0x%08x; a UVC camera's second node carries only metadata)",
                          c->device, (const char *)cap.card, (unsigned)caps);
        rc = -EINVAL;
        goto fail;
    }
    if ((rc = device_choose_format(c, err, errlen)) != 0 || (rc = device_set_format(c, err, errlen)) != 0 ||
        (rc = device_map_buffers(c, err, errlen)) != 0)
        goto fail;
    if (c->started && (rc = device_stream_on(c, err, errlen)) != 0)
        goto fail;
    return 0;
fail:
    device_close(c);
    return rc;
}

static void device_report_open(const v4l2_camera_t *c)
{
    char name[5];

    psc_v4l2_fourcc_name(c->fourcc, name);
    psc_io_log(PSC_LOG_NOTICE, "v4l2 camera %s: %s %ux%u -> map %ux%u", c->device, name, (unsigned)c->resample.src_width,
            (unsigned)c->resample.src_height, (unsigned)c->width, (unsigned)c->height);
}

/* The device went away or stopped delivering: close it, try again later. */
static void device_lost(v4l2_camera_t *c, uint64_t now, const char *why)
{
    device_close(c);
    snprintf(c->reason, sizeof c->reason, "%s", why);
    c->next_retry_us = now + (uint64_t)c->reopen_ms * 1000u;
    if (!c->lost_reported)
        psc_io_log(PSC_LOG_WARNING, "v4l2 camera %s: lost (%s); retrying every %u ms", c->device, why, (unsigned)c->reopen_ms);
    c->lost_reported = true;
}

/* While absent: one reopen attempt per reopen_ms. 0 when the device is back. */
static int device_retry(v4l2_camera_t *c, uint64_t now)
{
    char why[200];

    if (now < c->next_retry_us)
        return -ENODEV;
    if (device_open(c, why, sizeof why) != 0) {
        c->next_retry_us = now + (uint64_t)c->reopen_ms * 1000u;
        if (strcmp(why, c->reason) != 0) {   /* report a new reason once, not every retry */
            snprintf(c->reason, sizeof c->reason, "%s", why);
            psc_io_log(PSC_LOG_WARNING, "v4l2 camera %s: still absent: %s", c->device, why);
        }
        return -ENODEV;
    }
    psc_io_log(PSC_LOG_NOTICE, "v4l2 camera %s: back", c->device);
    device_report_open(c);
    c->lost_reported = false;
    c->reason[0] = '\0';
    return 0;
}

/* ---- the camera interface ------------------------------------------------- */

static int v4l2_camera_start(psc_hal_camera_t *cam)
{
    v4l2_camera_t *c = (v4l2_camera_t *)cam;
    uint64_t now = psc_hal_clock_now_us(c->clock);
    char why[200];

    if (c->started)
        return -EBUSY;
    c->started = true;
    c->sequence = 0;
    memset(c->dequeued, 0, sizeof c->dequeued);
    c->last_frame_us = now;
    if (c->fd >= 0 && device_stream_on(c, why, sizeof why) != 0)
        device_lost(c, now, why);
    return 0;   /* an absent camera is not an error: it is retried from dequeue */
}

/* Take the newest filled driver buffer, giving older ones straight back.
 * 1 with *out set, 0 when none is ready, -ENODEV when the device failed. */
static int take_newest(v4l2_camera_t *c, struct v4l2_buffer *out, char *why, size_t whylen)
{
    bool have = false;

    for (;;) {
        struct v4l2_buffer b = { .type = V4L2_BUF_TYPE_VIDEO_CAPTURE, .memory = V4L2_MEMORY_MMAP };
        if (xioctl(c->fd, VIDIOC_DQBUF, &b) != 0) {
            if (errno == EAGAIN)
                return have ? 1 : 0;
            snprintf(why, whylen, "VIDIOC_DQBUF: %s", strerror(errno));
            if (have)
                xioctl(c->fd, VIDIOC_QBUF, out);
            return -ENODEV;
        }
        if (b.index >= c->driver_count) {
            snprintf(why, whylen, "the driver returned buffer %u of %u", (unsigned)b.index,
                     (unsigned)c->driver_count);
            return -ENODEV;
        }
        if (have)
            xioctl(c->fd, VIDIOC_QBUF, out);
        if (b.flags & V4L2_BUF_FLAG_ERROR) {   /* a damaged frame: give it back, keep looking */
            xioctl(c->fd, VIDIOC_QBUF, &b);
            have = false;
            continue;
        }
        *out = b;
        have = true;
    }
}

/* Capture time on the HAL clock: the driver stamps CLOCK_MONOTONIC. */
static uint64_t frame_time_us(const struct v4l2_buffer *b, uint64_t now)
{
    struct timespec mono;
    uint64_t stamp_us, mono_us;

    if ((b->flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) != V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC)
        return now;
    clock_gettime(CLOCK_MONOTONIC, &mono);
    mono_us = (uint64_t)mono.tv_sec * 1000000u + (uint64_t)mono.tv_nsec / 1000u;
    stamp_us = (uint64_t)b->timestamp.tv_sec * 1000000u + (uint64_t)b->timestamp.tv_usec;
    if (stamp_us > mono_us || mono_us - stamp_us > now)
        return now;
    return now - (mono_us - stamp_us);
}

static int v4l2_camera_dequeue(psc_hal_camera_t *cam, psc_hal_camera_frame_t *frame)
{
    v4l2_camera_t *c = (v4l2_camera_t *)cam;
    uint64_t now = psc_hal_clock_now_us(c->clock);
    struct v4l2_buffer b;
    struct pollfd pfd;
    char why[200];
    unsigned map = PSC_HAL_CAMERA_MAX_BUFFERS;
    int rc;

    if (!c->started)
        return -EINVAL;
    if (c->fd < 0)
        return device_retry(c, now) == 0 ? -EAGAIN : -ENODEV;   /* just reopened: no frame yet */
    for (unsigned i = 0; i < c->buffer_count; i++)
        if (!c->dequeued[i]) {
            map = i;
            break;
        }
    if (map == PSC_HAL_CAMERA_MAX_BUFFERS)
        return -EAGAIN;   /* every map is with the caller: the driver keeps filling its own buffers */

    pfd = (struct pollfd){ .fd = c->fd, .events = POLLIN };
    rc = poll(&pfd, 1, 0);
    if (rc == 0 || (rc > 0 && !(pfd.revents & (POLLIN | POLLERR | POLLHUP | POLLNVAL)))) {
        if (now > c->last_frame_us && now - c->last_frame_us > (uint64_t)c->timeout_ms * 1000u) {
            snprintf(why, sizeof why, "no frame for %u ms", (unsigned)c->timeout_ms);
            device_lost(c, now, why);
            c->next_retry_us = now;   /* a stalled stream is restarted at once */
            return -ENODEV;
        }
        return -EAGAIN;
    }
    /* POLLERR/POLLHUP: DQBUF tells what happened (ENODEV after an unplug) */
    rc = take_newest(c, &b, why, sizeof why);
    if (rc < 0) {
        device_lost(c, now, why);
        return -ENODEV;
    }
    if (rc == 0)
        return -EAGAIN;

    rc = psc_v4l2_convert_frame(c->fourcc, &c->resample, c->mjpeg, c->driver[b.index].start, b.bytesused,
                                c->bytesperline, c->format, c->maps[map], c->map_stride, why, sizeof why);
    xioctl(c->fd, VIDIOC_QBUF, &b);
    c->last_frame_us = now;   /* a corrupt frame still shows the camera is alive */
    if (rc != 0)
        return -EAGAIN;       /* dropped: the previous map stays on screen */

    memset(frame, 0, sizeof *frame);
    frame->map.projection = PSC_PROJ_EQUIRECT;
    frame->map.format = c->format;
    frame->map.width = c->width;
    frame->map.height = c->height;
    frame->map.stride = c->map_stride;
    frame->map.pixels = c->maps[map];
    psc_envmap_default_coverage(&frame->map);
    frame->index = map;
    /* frames the driver dropped or we skipped for a newer one leave a gap */
    if (c->driver_sequence_valid && b.sequence > c->driver_sequence + 1u)
        c->sequence += b.sequence - c->driver_sequence - 1u;
    c->driver_sequence = b.sequence;
    c->driver_sequence_valid = true;
    frame->sequence = c->sequence++;
    frame->timestamp_us = frame_time_us(&b, now);
    c->dequeued[map] = true;
    return 0;
}

static int v4l2_camera_queue(psc_hal_camera_t *cam, const psc_hal_camera_frame_t *frame)
{
    v4l2_camera_t *c = (v4l2_camera_t *)cam;

    if (frame->index >= c->buffer_count || !c->dequeued[frame->index])
        return -EINVAL;
    c->dequeued[frame->index] = false;
    return 0;
}

static int v4l2_camera_stop(psc_hal_camera_t *cam)
{
    v4l2_camera_t *c = (v4l2_camera_t *)cam;

    if (c->fd >= 0 && c->streaming) {
        int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        xioctl(c->fd, VIDIOC_STREAMOFF, &type);   /* also returns every driver buffer to us */
    }
    c->streaming = false;
    c->started = false;
    memset(c->dequeued, 0, sizeof c->dequeued);
    return 0;
}

static void v4l2_camera_close(psc_hal_camera_t *cam)
{
    v4l2_camera_t *c = (v4l2_camera_t *)cam;

    device_close(c);
    for (unsigned i = 0; i < PSC_HAL_CAMERA_MAX_BUFFERS; i++)
        free(c->maps[i]);
    free(c->resample.col);
    free(c->resample.row);
    psc_v4l2_mjpeg_destroy(c->mjpeg);
    free(c);
}

static const psc_hal_camera_ops_t v4l2_camera_ops = {
    .start = v4l2_camera_start,
    .dequeue = v4l2_camera_dequeue,
    .queue = v4l2_camera_queue,
    .stop = v4l2_camera_stop,
    .set_exposure = NULL,
    .close = v4l2_camera_close,
};

/* ---- open ----------------------------------------------------------------- */

static int v4l2_read_options(v4l2_camera_t *c, const psc_hal_camera_config_t *cfg, bool *required, char *err,
                             size_t errlen)
{
    const psc_hal_option_t *o;
    int rc;

    rc = psc_hal_options_check(&cfg->options, v4l2_camera_known_options, "camera", "v4l2", err, errlen);
    if (rc != 0)
        return rc;
    o = psc_hal_options_find(&cfg->options, "device");
    snprintf(c->device, sizeof c->device, "%s", o != NULL && o->value != NULL ? o->value : "/dev/video0");
    if (c->device[0] != '/') {
        psc_hal_error_set(err, errlen, "%s: camera option 'device' must be a path like /dev/video0, got '%s'",
                          o->origin ? o->origin : "camera", c->device);
        return -EINVAL;
    }
    o = psc_hal_options_find(&cfg->options, "pixel_format");
    if (o != NULL && psc_v4l2_parse_pixel_format(o->value, &c->want_fourcc) != 0) {
        psc_hal_error_set(err, errlen, "%s: camera option 'pixel_format' must be auto, yuyv or mjpeg, got '%s'",
                          o->origin ? o->origin : "camera", o->value ? o->value : "");
        return -EINVAL;
    }
    c->capture_width = cfg->width;
    c->capture_height = cfg->height;
    o = psc_hal_options_find(&cfg->options, "capture_size");
    if (o != NULL && psc_v4l2_parse_size(o->value, &c->capture_width, &c->capture_height) != 0) {
        psc_hal_error_set(err, errlen, "%s: camera option 'capture_size' must be WxH from 2x2 to %ux%u, got '%s'",
                          o->origin ? o->origin : "camera", PSC_V4L2_MAX_SRC_WIDTH, PSC_V4L2_MAX_SRC_HEIGHT,
                          o->value ? o->value : "");
        return -EINVAL;
    }
    if ((rc = psc_hal_options_get_u32(&cfg->options, "timeout_ms", 100, 60000, 2000, &c->timeout_ms, err, errlen)) ||
        (rc = psc_hal_options_get_u32(&cfg->options, "reopen_ms", 100, 60000, 1000, &c->reopen_ms, err, errlen)))
        return rc;
    return psc_hal_options_get_bool(&cfg->options, "required", "camera", false, required, err, errlen);
}

static int v4l2_camera_open(const psc_hal_camera_config_t *cfg, psc_hal_camera_t **out, char *err, size_t errlen)
{
    v4l2_camera_t *c;
    bool required = false;
    char why[200];
    int rc;

    *out = NULL;
    if (cfg->width < 2 || cfg->height < 2 || cfg->width > PSC_MAX_MAP_DIM || cfg->height > PSC_MAX_MAP_DIM) {
        psc_hal_error_set(err, errlen, "v4l2 camera: map size %ux%u is outside 2x2..%ux%u", (unsigned)cfg->width,
                          (unsigned)cfg->height, PSC_MAX_MAP_DIM, PSC_MAX_MAP_DIM);
        return -EINVAL;
    }
    if (cfg->format != PSC_PIX_RGB565 && cfg->format != PSC_PIX_XRGB8888) {
        psc_hal_error_set(err, errlen, "v4l2 camera: map format %d is not rgb565 or xrgb8888", (int)cfg->format);
        return -EINVAL;
    }
    if (cfg->buffer_count < 2 || cfg->buffer_count > PSC_HAL_CAMERA_MAX_BUFFERS) {
        psc_hal_error_set(err, errlen, "v4l2 camera: %u buffers requested, 2..%u supported",
                          (unsigned)cfg->buffer_count, PSC_HAL_CAMERA_MAX_BUFFERS);
        return -EINVAL;
    }
    if (cfg->clock == NULL || cfg->frame_rate_mhz < 1000 || cfg->frame_rate_mhz > 1000000) {
        psc_hal_error_set(err, errlen, "v4l2 camera: needs a clock and a frame rate of 1..1000 Hz");
        return -EINVAL;
    }
    c = calloc(1, sizeof *c);
    if (c == NULL)
        goto nomem;
    c->base.ops = &v4l2_camera_ops;
    c->base.backend = "v4l2";
    c->fd = -1;
    c->width = cfg->width;
    c->height = cfg->height;
    c->format = cfg->format;
    c->buffer_count = cfg->buffer_count;
    c->frame_rate_mhz = cfg->frame_rate_mhz;
    c->clock = cfg->clock;
    rc = v4l2_read_options(c, cfg, &required, err, errlen);
    if (rc != 0)
        goto fail;
    c->map_stride = (uint32_t)cfg->width * psc_pixfmt_bytes(cfg->format);
    for (unsigned i = 0; i < cfg->buffer_count; i++)
        if ((c->maps[i] = calloc(cfg->height, c->map_stride)) == NULL)
            goto nomem;
    c->resample.dst_width = cfg->width;
    c->resample.dst_height = cfg->height;
    c->resample.col = calloc(cfg->width, sizeof *c->resample.col);
    c->resample.row = calloc(cfg->height, sizeof *c->resample.row);
    c->mjpeg = psc_v4l2_mjpeg_create();
    if (c->resample.col == NULL || c->resample.row == NULL || c->mjpeg == NULL)
        goto nomem;

    rc = device_open(c, why, sizeof why);
    if (rc == 0) {
        device_report_open(c);
    } else if (rc == -ENODEV && !required) {
        /* absent at start-up: run without it, keep trying (a kiosk must not
         * refuse to start because a USB camera is unplugged) */
        psc_io_log(PSC_LOG_WARNING, "v4l2 camera: %s; starting without it, retrying every %u ms", why,
                (unsigned)c->reopen_ms);
        snprintf(c->reason, sizeof c->reason, "%s", why);
        c->lost_reported = true;
    } else {
        psc_hal_error_set(err, errlen, "v4l2 camera: %s", why);
        goto fail;
    }
    *out = &c->base;
    return 0;
nomem:
    psc_hal_error_set(err, errlen, "v4l2 camera: out of memory for %u maps of %ux%u", (unsigned)cfg->buffer_count,
                      (unsigned)cfg->width, (unsigned)cfg->height);
    rc = -ENOMEM;
fail:
    if (c != NULL)
        v4l2_camera_close(&c->base);
    return rc;
}

const psc_hal_backend_t psc_hal_v4l2_backend = {
    .name = "v4l2",
    .description = "V4L2 capture device (UVC camera): mmap streaming, YUYV or MJPEG, frames as the live map",
    .camera_open = v4l2_camera_open,
};
