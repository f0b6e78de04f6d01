/* SPDX-License-Identifier: MIT */
/*
 * drm_display.c - the "drm" display: KMS through libdrm on /dev/dri/cardN
 * (bochs-display in the VM tests, vc4 on a Raspberry Pi, i915/amdgpu on an
 * x86 kiosk), with dumb buffers and page flips on vertical blank.
 *
 * Start-up: the connector (by name, or the first connected one), its mode
 * (psc_drm_mode.h), a CRTC its encoder can drive, buffer_count dumb buffers
 * (DRM_IOCTL_MODE_CREATE_DUMB + drmModeAddFB2 + mmap) cleared to black, and a
 * modeset showing buffer 0. The CRTC's previous state is saved and put back
 * at close, so the console (or whatever ran before) comes back.
 *
 * Present: drmModePageFlip to the back buffer with a flip event, then wait
 * for that event (poll + drmHandleEvent) before returning, because until the
 * flip has happened at vblank the old front buffer is still being scanned
 * out and must not be drawn into. A driver that cannot flip gets a modeset
 * per frame instead (said once on stderr); with one buffer, frames are drawn
 * on screen and drmModeDirtyFB tells drivers that need it (virtual GPUs).
 *
 * Options (board lines "display.KEY = VALUE"):
 *   device      the card, or auto (default): the first of /dev/dri/card0..7
 *               with a connected display
 *   connector   a connector name as the kernel gives it ("HDMI-A-1",
 *               "Virtual-1"; default: the first connected one)
 *   mode        board (default), preferred, WxH or WxH@HZ (psc_drm_mode.h)
 *   flip_timeout_ms  how long present waits for a flip event (default 1000)
 * If the driver refuses the board's pixel format for scan-out, the other of
 * RGB565/XRGB8888 is used (get_mode says which) rather than failing.
 */
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <drm.h>
#include <drm_mode.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

#include "drm_internal.h"
#include "psc_drm_mode.h"
#include "psc_hal_display.h"
#include "psc_io_log.h"

#define DRM_MAX_BUFFERS 3u
#define DRM_PATH_MAX 256u

typedef struct {
    uint32_t handle;      /* dumb buffer handle, 0 = none */
    uint32_t fb_id;
    uint32_t pitch;
    uint64_t size;
    uint8_t *pixels;      /* mmap'd */
} drm_buffer_t;

typedef struct {
    psc_hal_display_t base;     /* first: the HAL hands this pointer back to us */
    char device[DRM_PATH_MAX];
    int fd;
    uint32_t connector_id, crtc_id;
    drmModeModeInfo mode_info;
    drmModeCrtc *saved_crtc;    /* the CRTC as it was, restored at close */
    uint32_t dpms_prop;         /* the connector's DPMS property, 0 if none */
    drm_buffer_t buffers[DRM_MAX_BUFFERS];
    uint8_t count;
    uint8_t front;
    bool modeset_done;
    bool flip_pending;
    bool flip_unsupported;      /* fall back to a modeset per frame */
    bool flip_timeout_reported;
    uint32_t flip_timeout_ms;
    psc_hal_display_mode_t mode;
} drm_display_t;

static const char *const drm_known_options[] = { "device", "connector", "mode", "flip_timeout_ms", NULL };

static drm_display_t *to_drm(psc_hal_display_t *d)
{
    return (drm_display_t *)d;
}

static void fill_surface(const drm_display_t *s, uint8_t index, psc_surface_t *out)
{
    out->width = s->mode.width;
    out->height = s->mode.height;
    out->stride = s->mode.stride;
    out->format = s->mode.format;
    out->pixels = s->buffers[index].pixels;
}

static int drm_get_mode(psc_hal_display_t *d, psc_hal_display_mode_t *mode)
{
    *mode = to_drm(d)->mode;
    return 0;
}

static int drm_get_back_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    drm_display_t *s = to_drm(d);

    fill_surface(s, (uint8_t)((s->front + 1u) % s->count), surface);
    return 0;
}

static int drm_get_front_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    drm_display_t *s = to_drm(d);

    fill_surface(s, s->front, surface);
    return 0;
}

static void on_page_flip(int fd, unsigned int sequence, unsigned int tv_sec, unsigned int tv_usec, void *data)
{
    (void)fd;
    (void)sequence;
    (void)tv_sec;
    (void)tv_usec;
    ((drm_display_t *)data)->flip_pending = false;
}

/* Wait for the pending flip's event. A lost event (a driver bug, a CRTC
 * switched off under us) is said once and otherwise ignored: one torn frame
 * is better than a kiosk that stops; a device error is -EIO. */
static int wait_for_flip(drm_display_t *s)
{
    drmEventContext ev = { .version = 2, .page_flip_handler = on_page_flip };
    struct pollfd pfd = { .fd = s->fd, .events = POLLIN };

    while (s->flip_pending) {
        int rc = poll(&pfd, 1, (int)s->flip_timeout_ms);
        if (rc < 0 && errno == EINTR)
            continue;
        if (rc == 0) {
            if (!s->flip_timeout_reported)
                psc_io_log(PSC_LOG_WARNING, "drm display %s: no page-flip event within %u ms; carrying on", s->device,
                        (unsigned)s->flip_timeout_ms);
            s->flip_timeout_reported = true;
            s->flip_pending = false;
            return 0;
        }
        if (rc < 0 || (pfd.revents & (POLLERR | POLLHUP | POLLNVAL)) || drmHandleEvent(s->fd, &ev) != 0) {
            s->flip_pending = false;
            return -EIO;
        }
    }
    return 0;
}

static int show_by_modeset(drm_display_t *s, uint8_t index)
{
    if (drmModeSetCrtc(s->fd, s->crtc_id, s->buffers[index].fb_id, 0, 0, &s->connector_id, 1, &s->mode_info) != 0)
        return errno == ENODEV ? -ENODEV : -EIO;
    return 0;
}

static int drm_present(psc_hal_display_t *d)
{
    drm_display_t *s = to_drm(d);
    uint8_t back;
    int rc;

    if (s->count == 1) {
        drmModeDirtyFB(s->fd, s->buffers[0].fb_id, NULL, 0);   /* -ENOSYS on real hardware: fine */
        return 0;
    }
    back = (uint8_t)((s->front + 1u) % s->count);
    if (!s->flip_unsupported) {
        rc = drmModePageFlip(s->fd, s->crtc_id, s->buffers[back].fb_id, DRM_MODE_PAGE_FLIP_EVENT, s);
        if (rc != 0 && errno == EBUSY) {
            /* a flip whose event we gave up on is still queued: wait a frame, try once more */
            s->flip_pending = true;
            wait_for_flip(s);
            rc = drmModePageFlip(s->fd, s->crtc_id, s->buffers[back].fb_id, DRM_MODE_PAGE_FLIP_EVENT, s);
        }
        if (rc == 0) {
            s->flip_pending = true;
            rc = wait_for_flip(s);
            s->front = back;
            return rc;
        }
        if (errno != EINVAL && errno != ENOSYS && errno != EOPNOTSUPP)
            return errno == ENODEV ? -ENODEV : -EIO;
        psc_io_log(PSC_LOG_WARNING, "drm display %s: page flips not supported (%s); showing frames by modeset, which may tear",
                s->device, strerror(errno));
        s->flip_unsupported = true;
    }
    rc = show_by_modeset(s, back);
    if (rc == 0)
        s->front = back;
    return rc;
}

static int drm_set_blank(psc_hal_display_t *d, bool blank)
{
    drm_display_t *s = to_drm(d);

    if (s->dpms_prop == 0)
        return -ENOSYS;
    if (drmModeConnectorSetProperty(s->fd, s->connector_id, s->dpms_prop,
                                    blank ? DRM_MODE_DPMS_OFF : DRM_MODE_DPMS_ON) != 0)
        return -EIO;
    return 0;
}

static void destroy_buffer(int fd, drm_buffer_t *b)
{
    if (b->pixels != NULL)
        munmap(b->pixels, (size_t)b->size);
    if (b->fb_id != 0)
        drmModeRmFB(fd, b->fb_id);
    if (b->handle != 0) {
        struct drm_mode_destroy_dumb destroy = { .handle = b->handle };
        drmIoctl(fd, DRM_IOCTL_MODE_DESTROY_DUMB, &destroy);
    }
    memset(b, 0, sizeof *b);
}

static void drm_close(psc_hal_display_t *d)
{
    drm_display_t *s = to_drm(d);

    if (s->fd >= 0) {
        if (s->flip_pending)
            wait_for_flip(s);
        if (s->modeset_done && s->saved_crtc != NULL && s->saved_crtc->mode_valid)
            drmModeSetCrtc(s->fd, s->saved_crtc->crtc_id, s->saved_crtc->buffer_id, s->saved_crtc->x,
                           s->saved_crtc->y, &s->connector_id, 1, &s->saved_crtc->mode);
        for (unsigned i = 0; i < DRM_MAX_BUFFERS; i++)
            destroy_buffer(s->fd, &s->buffers[i]);
        close(s->fd);
    }
    if (s->saved_crtc != NULL)
        drmModeFreeCrtc(s->saved_crtc);
    free(s);
}

static const psc_hal_display_ops_t drm_display_ops = {
    .get_mode = drm_get_mode,
    .get_back_buffer = drm_get_back_buffer,
    .present = drm_present,
    .set_blank = drm_set_blank,
    .get_front_buffer = drm_get_front_buffer,
    .close = drm_close,
};

/* ---- open --------------------------------------------------------------------- */

/* One dumb buffer of the mode's size in fourcc, mapped and cleared. */
static int create_buffer(drm_display_t *s, uint32_t fourcc, uint32_t bpp, drm_buffer_t *b, char *err, size_t errlen)
{
    struct drm_mode_create_dumb create = { .width = s->mode_info.hdisplay, .height = s->mode_info.vdisplay,
                                           .bpp = bpp };
    struct drm_mode_map_dumb map = { 0 };
    uint32_t handles[4] = { 0 }, pitches[4] = { 0 }, offsets[4] = { 0 };

    if (drmIoctl(s->fd, DRM_IOCTL_MODE_CREATE_DUMB, &create) != 0) {
        psc_hal_error_set(err, errlen, "%s: cannot create a %ux%u dumb buffer: %s", s->device,
                          (unsigned)create.width, (unsigned)create.height, strerror(errno));
        return -EIO;
    }
    b->handle = create.handle;
    b->pitch = create.pitch;
    b->size = create.size;
    handles[0] = b->handle;
    pitches[0] = b->pitch;
    if (drmModeAddFB2(s->fd, create.width, create.height, fourcc, handles, pitches, offsets, &b->fb_id, 0) != 0) {
        b->fb_id = 0;
        psc_hal_error_set(err, errlen, "%s: the driver refuses %s frame buffers: %s", s->device,
                          bpp == 16 ? "RGB565" : "XRGB8888", strerror(errno));
        return -EINVAL;
    }
    map.handle = b->handle;
    if (drmIoctl(s->fd, DRM_IOCTL_MODE_MAP_DUMB, &map) != 0) {
        psc_hal_error_set(err, errlen, "%s: DRM_IOCTL_MODE_MAP_DUMB: %s", s->device, strerror(errno));
        return -EIO;
    }
    b->pixels = mmap(NULL, (size_t)b->size, PROT_READ | PROT_WRITE, MAP_SHARED, s->fd, (off_t)map.offset);
    if (b->pixels == MAP_FAILED) {
        b->pixels = NULL;
        psc_hal_error_set(err, errlen, "%s: cannot map a dumb buffer: %s", s->device, strerror(errno));
        return -EIO;
    }
    memset(b->pixels, 0, (size_t)b->size);
    return 0;
}

/* Create count buffers in format fmt; on refusal of the format try the other. */
static int create_buffers(drm_display_t *s, psc_pixfmt_t fmt, uint8_t count, char *err, size_t errlen)
{
    psc_pixfmt_t order[2] = { fmt, fmt == PSC_PIX_RGB565 ? PSC_PIX_XRGB8888 : PSC_PIX_RGB565 };
    int rc = -EINVAL;

    for (unsigned k = 0; k < 2; k++) {
        uint32_t fourcc, bpp;
        psc_drm_format(order[k], &fourcc, &bpp);
        for (unsigned i = 0; i < count; i++) {
            rc = create_buffer(s, fourcc, bpp, &s->buffers[i], err, errlen);
            if (rc != 0)
                break;
        }
        if (rc == 0) {
            if (k == 1)
                psc_io_log(PSC_LOG_NOTICE, "drm display %s: %s scan-out refused, using %s", s->device,
                        fmt == PSC_PIX_RGB565 ? "RGB565" : "XRGB8888", bpp == 16 ? "RGB565" : "XRGB8888");
            s->mode.format = order[k];
            s->mode.stride = s->buffers[0].pitch;
            return 0;
        }
        for (unsigned i = 0; i < DRM_MAX_BUFFERS; i++)
            destroy_buffer(s->fd, &s->buffers[i]);
        if (rc != -EINVAL)
            return rc;   /* only a refused format is worth a second try */
    }
    return rc;
}

/* The connector to drive: the named one, or the first connected with modes. */
static drmModeConnector *find_connector(drm_display_t *s, drmModeRes *res, const char *want, char *err, size_t errlen)
{
    char seen[300] = "", name[32];
    size_t used = 0;

    for (int i = 0; i < res->count_connectors; i++) {
        drmModeConnector *c = drmModeGetConnector(s->fd, res->connectors[i]);
        if (c == NULL)
            continue;
        psc_drm_connector_name(c->connector_type, c->connector_type_id, name, sizeof name);
        if (used + 40 < sizeof seen)
            used += (size_t)snprintf(seen + used, sizeof seen - used, "%s%s (%s)", used ? ", " : "", name,
                                     c->connection == DRM_MODE_CONNECTED ? "connected"
                                     : c->connection == DRM_MODE_DISCONNECTED ? "disconnected" : "unknown");
        if (want != NULL ? strcmp(name, want) == 0 : (c->connection == DRM_MODE_CONNECTED && c->count_modes > 0))
            return c;
        drmModeFreeConnector(c);
    }
    psc_hal_error_set(err, errlen, "%s: %s%s%s; connectors: %s", s->device, want ? "no connector named " : "",
                      want ? want : "no connected connector with modes", want ? "" : " (is a monitor plugged in?)",
                      seen[0] ? seen : "none");
    return NULL;
}

/* A CRTC for the connector: its current encoder's, else any its encoders allow. */
static int find_crtc(drm_display_t *s, drmModeRes *res, const drmModeConnector *conn)
{
    if (conn->encoder_id != 0) {
        drmModeEncoder *e = drmModeGetEncoder(s->fd, conn->encoder_id);
        if (e != NULL) {
            uint32_t crtc = e->crtc_id;
            drmModeFreeEncoder(e);
            if (crtc != 0) {
                s->crtc_id = crtc;
                return 0;
            }
        }
    }
    for (int i = 0; i < conn->count_encoders; i++) {
        drmModeEncoder *e = drmModeGetEncoder(s->fd, conn->encoders[i]);
        if (e == NULL)
            continue;
        int k = psc_drm_pick_crtc(e->possible_crtcs, res->count_crtcs);
        drmModeFreeEncoder(e);
        if (k >= 0) {
            s->crtc_id = res->crtcs[k];
            return 0;
        }
    }
    return -ENODEV;
}

static uint32_t find_dpms(int fd, uint32_t connector_id)
{
    drmModeObjectProperties *props = drmModeObjectGetProperties(fd, connector_id, DRM_MODE_OBJECT_CONNECTOR);
    uint32_t id = 0;

    if (props == NULL)
        return 0;
    for (uint32_t i = 0; i < props->count_props && id == 0; i++) {
        drmModePropertyRes *p = drmModeGetProperty(fd, props->props[i]);
        if (p != NULL && strcmp(p->name, "DPMS") == 0)
            id = p->prop_id;
        drmModeFreeProperty(p);
    }
    drmModeFreeObjectProperties(props);
    return id;
}

static int read_options(drm_display_t *s, const psc_hal_display_config_t *cfg, const char **connector,
                        psc_drm_mode_request_t *req, char *err, size_t errlen)
{
    const psc_hal_option_t *o;
    int rc = psc_hal_options_check(&cfg->options, drm_known_options, "display", "drm", err, errlen);

    if (rc != 0)
        return rc;
    o = psc_hal_options_find(&cfg->options, "device");
    snprintf(s->device, sizeof s->device, "%s", o != NULL && o->value != NULL ? o->value : "auto");
    o = psc_hal_options_find(&cfg->options, "connector");
    *connector = o != NULL && o->value != NULL && o->value[0] != '\0' ? o->value : NULL;
    o = psc_hal_options_find(&cfg->options, "mode");
    if (psc_drm_parse_mode_request(o != NULL ? o->value : "board", req) != 0) {
        psc_hal_error_set(err, errlen, "%s: display option 'mode' must be board, preferred, WxH or WxH@HZ, got '%s'",
                          o->origin ? o->origin : "display", o->value ? o->value : "");
        return -EINVAL;
    }
    if (req->kind == PSC_DRM_MODE_BOARD) {
        req->width = cfg->width;
        req->height = cfg->height;
    }
    return psc_hal_options_get_u32(&cfg->options, "flip_timeout_ms", 10, 10000, 1000, &s->flip_timeout_ms, err,
                                   errlen);
}

/* Connector, mode and CRTC; fills s->mode_info / connector_id / crtc_id. */
static int choose_output(drm_display_t *s, const char *want_connector, const psc_drm_mode_request_t *req, char *err,
                         size_t errlen)
{
    drmModeRes *res = drmModeGetResources(s->fd);
    drmModeConnector *conn;
    char name[32], modes[400];
    int rc = 0, m;

    if (res == NULL) {
        psc_hal_error_set(err, errlen, "%s is not a KMS display device (drmModeGetResources: %s)", s->device,
                          strerror(errno));
        return -ENODEV;
    }
    conn = find_connector(s, res, want_connector, err, errlen);
    if (conn == NULL) {
        drmModeFreeResources(res);
        return -ENODEV;
    }
    psc_drm_connector_name(conn->connector_type, conn->connector_type_id, name, sizeof name);
    m = psc_drm_pick_mode(conn->modes, conn->count_modes, req);
    if (m < 0) {
        psc_drm_describe_modes(conn->modes, conn->count_modes, modes, sizeof modes);
        if (req->kind == PSC_DRM_MODE_PREFERRED)
            psc_hal_error_set(err, errlen, "%s %s has no usable mode (%s)", s->device, name, modes);
        else
            psc_hal_error_set(err, errlen, "%s %s has no %ux%u%s mode; it offers %s (set display_size to one of them, "
                              "or display.mode = preferred)", s->device, name, (unsigned)req->width,
                              (unsigned)req->height, req->refresh_hz ? " (at any refresh rate)" : "", modes);
        rc = -EINVAL;
    } else {
        s->mode_info = conn->modes[m];
        s->connector_id = conn->connector_id;
        if (find_crtc(s, res, conn) != 0) {
            psc_hal_error_set(err, errlen, "%s %s: no display controller (CRTC) can drive it", s->device, name);
            rc = -ENODEV;
        }
    }
    drmModeFreeConnector(conn);
    drmModeFreeResources(res);
    return rc;
}

/* Open s->device and choose its output. 0, or a negative errno with why. */
static int open_one_card(drm_display_t *s, const char *want_connector, const psc_drm_mode_request_t *req, char *why,
                         size_t whylen)
{
    int rc;

    s->fd = open(s->device, O_RDWR | O_CLOEXEC);
    if (s->fd < 0) {
        rc = errno == ENOENT || errno == ENODEV || errno == ENXIO ? -ENODEV : -EIO;
        psc_hal_error_set(why, whylen, "cannot open %s: %s", s->device, strerror(errno));
        return rc;
    }
    rc = choose_output(s, want_connector, req, why, whylen);
    if (rc != 0) {
        close(s->fd);
        s->fd = -1;
    }
    return rc;
}

/* device = auto: the first of /dev/dri/card0..7 that drives a connected
 * display. Boards differ in numbering (a Raspberry Pi's card0 may be the
 * render-only v3d and its display card1), so a kiosk need not know. */
static int open_card(drm_display_t *s, const char *want_connector, const psc_drm_mode_request_t *req, char *why,
                     size_t whylen)
{
    char first[300] = "";

    if (strcmp(s->device, "auto") != 0)
        return open_one_card(s, want_connector, req, why, whylen);
    for (unsigned k = 0; k < 8; k++) {
        char one[300];
        snprintf(s->device, sizeof s->device, "/dev/dri/card%u", k);
        if (open_one_card(s, want_connector, req, one, sizeof one) == 0)
            return 0;
        if (first[0] == '\0' || (strstr(first, "cannot open") != NULL && strstr(one, "cannot open") == NULL))
            snprintf(first, sizeof first, "%s", one);   /* keep the most telling reason */
    }
    snprintf(s->device, sizeof s->device, "auto");
    psc_hal_error_set(why, whylen, "no /dev/dri/card0..7 drives a connected display (%s)", first);
    return -ENODEV;
}

int psc_drm_display_open(const psc_hal_display_config_t *cfg, psc_hal_display_t **out, char *err, size_t errlen)
{
    psc_drm_mode_request_t req;
    const char *want_connector;
    drm_display_t *s;
    char why[500];
    int rc;

    *out = NULL;
    if (cfg->buffer_count < 1 || cfg->buffer_count > DRM_MAX_BUFFERS ||
        (cfg->format != PSC_PIX_RGB565 && cfg->format != PSC_PIX_XRGB8888)) {
        psc_hal_error_set(err, errlen, "drm display: %u buffers in format %d requested; 1..3 buffers of rgb565 or "
                          "xrgb8888 are supported", (unsigned)cfg->buffer_count, (int)cfg->format);
        return -EINVAL;
    }
    s = calloc(1, sizeof *s);
    if (s == NULL) {
        psc_hal_error_set(err, errlen, "drm display: out of memory");
        return -ENOMEM;
    }
    s->base.ops = &drm_display_ops;
    s->base.backend = "drm";
    s->fd = -1;
    rc = read_options(s, cfg, &want_connector, &req, err, errlen);
    if (rc != 0)
        goto fail;
    rc = open_card(s, want_connector, &req, why, sizeof why);
    if (rc != 0) {
        psc_hal_error_set(err, errlen, "drm display: %s", why);
        goto fail;
    }
    s->count = cfg->buffer_count;
    s->mode.width = s->mode_info.hdisplay;
    s->mode.height = s->mode_info.vdisplay;
    s->mode.refresh_mhz = psc_drm_mode_refresh_mhz(&s->mode_info);
    s->mode.buffer_count = s->count;
    rc = create_buffers(s, cfg->format, s->count, why, sizeof why);
    if (rc != 0) {
        psc_hal_error_set(err, errlen, "drm display: %s", why);
        goto fail;
    }
    s->saved_crtc = drmModeGetCrtc(s->fd, s->crtc_id);
    if (show_by_modeset(s, 0) != 0) {
        psc_hal_error_set(err, errlen, "drm display: %s: cannot set mode %ux%u: %s%s", s->device,
                          (unsigned)s->mode.width, (unsigned)s->mode.height, strerror(errno),
                          errno == EACCES || errno == EPERM ? " (another program - a desktop session? - is the "
                                                              "display's master)" : "");
        rc = -EIO;
        goto fail;
    }
    s->modeset_done = true;
    s->front = 0;
    s->dpms_prop = find_dpms(s->fd, s->connector_id);
    psc_io_log(PSC_LOG_NOTICE, "drm display %s: %ux%u@%u.%03u Hz %s, pitch %u, %u buffer%s", s->device,
            (unsigned)s->mode.width, (unsigned)s->mode.height, (unsigned)(s->mode.refresh_mhz / 1000u),
            (unsigned)(s->mode.refresh_mhz % 1000u), s->mode.format == PSC_PIX_RGB565 ? "RGB565" : "XRGB8888",
            (unsigned)s->mode.stride, (unsigned)s->count, s->count == 1 ? "" : "s, page flips");
    *out = &s->base;
    return 0;
fail:
    drm_close(&s->base);
    return rc;
}
