/* SPDX-License-Identifier: MIT */
/*
 * drm_probe - check a KMS driver (bochs on QEMU's bochs-display in the VM)
 * the way the DRM backend will use it, through libdrm: capabilities, a
 * connected connector and its modes, two XRGB8888 dumb buffers, a mode set,
 * page flips with completion events, and the pixels read back.
 *
 *   drm_probe info DEV           driver, capabilities, connectors and modes
 *   drm_probe flip DEV W H OUT [DUMP]
 *                                set W x H on the first connected connector,
 *                                flip between two buffers holding the test
 *                                pattern (buffer 1 xor 0x00ffffff), waiting
 *                                for each flip's event; OUT gets buffer 0
 *                                read back through its mapping, rows
 *                                without pitch padding; with DUMP, the host
 *                                photographs the screen (buffer 0 on it) as
 *                                /share/DUMP.ppm before the probe lets go
 *   drm_probe pattern W H        the expected OUT (the host runs this)
 *   drm_probe ppm W H            the expected screendump (the host runs this)
 */
/* vm-pkg-config: libdrm */
#include <fcntl.h>
#include <poll.h>
#include <sys/mman.h>
#include <unistd.h>
#include <xf86drm.h>
#include <xf86drmMode.h>
#include <drm_fourcc.h>

#include "probe_util.h"

#define DRM_PROBE_FLIPS 4
#define DRM_PROBE_EVENT_MS 10000

typedef struct {
    uint32_t handle, pitch, fb_id;
    uint64_t size;
    uint8_t *map;
} drm_probe_buffer_t;

static int drm_open(const char *dev)
{
    int fd = open(dev, O_RDWR | O_CLOEXEC);

    if (fd < 0)
        probe_fail(errno, "open %s", dev);
    return fd;
}

static void drm_info(const char *dev)
{
    int fd = drm_open(dev);
    drmVersionPtr v = drmGetVersion(fd);
    drmModeResPtr res;
    uint64_t cap = 0;

    if (v == NULL)
        probe_fail(errno, "%s: drmGetVersion", dev);
    printf("driver %s\n", v->name);
    drmFreeVersion(v);
    if (drmGetCap(fd, DRM_CAP_DUMB_BUFFER, &cap) != 0)
        probe_fail(errno, "%s: DRM_CAP_DUMB_BUFFER", dev);
    printf("dumb_buffer %llu\n", (unsigned long long)cap);
    res = drmModeGetResources(fd);
    if (res == NULL)
        probe_fail(errno, "%s: drmModeGetResources (not a KMS device?)", dev);
    printf("crtcs %d connectors %d\n", res->count_crtcs, res->count_connectors);
    for (int i = 0; i < res->count_connectors; i++) {
        drmModeConnectorPtr c = drmModeGetConnector(fd, res->connectors[i]);

        if (c == NULL)
            continue;
        printf("connector %u %s modes %d\n", c->connector_id,
               c->connection == DRM_MODE_CONNECTED ? "connected" : "disconnected", c->count_modes);
        for (int m = 0; m < c->count_modes; m++)
            printf("mode %ux%u@%u\n", c->modes[m].hdisplay, c->modes[m].vdisplay, c->modes[m].vrefresh);
        drmModeFreeConnector(c);
    }
    drmModeFreeResources(res);
    close(fd);
}

static void drm_fill(drm_probe_buffer_t *b, uint32_t w, uint32_t h, uint32_t xor)
{
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            probe_store_pixel(b->map + (size_t)y * b->pitch + 4u * x, (probe_pattern(x, y) ^ xor) & 0x00ffffffu, 4);
}

static void drm_buffer(int fd, const char *dev, uint32_t w, uint32_t h, drm_probe_buffer_t *b)
{
    struct drm_mode_create_dumb create = { .width = w, .height = h, .bpp = 32 };
    struct drm_mode_map_dumb map = { 0 };
    uint32_t handles[4] = { 0 }, pitches[4] = { 0 }, offsets[4] = { 0 };

    if (drmIoctl(fd, DRM_IOCTL_MODE_CREATE_DUMB, &create) != 0)
        probe_fail(errno, "%s: DRM_IOCTL_MODE_CREATE_DUMB %ux%u", dev, w, h);
    b->handle = create.handle;
    b->pitch = create.pitch;
    b->size = create.size;
    handles[0] = b->handle;
    pitches[0] = b->pitch;
    if (drmModeAddFB2(fd, w, h, DRM_FORMAT_XRGB8888, handles, pitches, offsets, &b->fb_id, 0) != 0)
        probe_fail(errno, "%s: drmModeAddFB2 XRGB8888", dev);
    map.handle = b->handle;
    if (drmIoctl(fd, DRM_IOCTL_MODE_MAP_DUMB, &map) != 0)
        probe_fail(errno, "%s: DRM_IOCTL_MODE_MAP_DUMB", dev);
    b->map = mmap(NULL, b->size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, (off_t)map.offset);
    if (b->map == MAP_FAILED)
        probe_fail(errno, "%s: mmap dumb buffer", dev);
}

static void drm_flip_done(int fd, unsigned int sequence, unsigned int sec, unsigned int usec, void *data)
{
    (void)fd;
    (void)sequence;
    (void)sec;
    (void)usec;
    *(int *)data = 1;
}

static void drm_flip(const char *dev, uint32_t w, uint32_t h, const char *out, const char *dump)
{
    int fd = drm_open(dev);
    drmModeResPtr res = drmModeGetResources(fd);
    drmModeConnectorPtr conn = NULL;
    drmModeEncoderPtr enc;
    drmModeModeInfo *mode = NULL;
    drm_probe_buffer_t buf[2];
    drmEventContext ev = { .version = 2, .page_flip_handler = drm_flip_done };
    uint32_t crtc;
    FILE *f;

    if (res == NULL)
        probe_fail(errno, "%s: drmModeGetResources", dev);
    for (int i = 0; i < res->count_connectors && conn == NULL; i++) {
        conn = drmModeGetConnector(fd, res->connectors[i]);
        if (conn != NULL && (conn->connection != DRM_MODE_CONNECTED || conn->count_modes == 0)) {
            drmModeFreeConnector(conn);
            conn = NULL;
        }
    }
    if (conn == NULL)
        probe_fail(0, "%s: no connected connector", dev);
    for (int m = 0; m < conn->count_modes && mode == NULL; m++)
        if (conn->modes[m].hdisplay == w && conn->modes[m].vdisplay == h)
            mode = &conn->modes[m];
    if (mode == NULL)
        probe_fail(0, "%s: connector %u has no %ux%u mode", dev, conn->connector_id, w, h);
    enc = conn->encoder_id ? drmModeGetEncoder(fd, conn->encoder_id) : NULL;
    crtc = enc != NULL && enc->crtc_id ? enc->crtc_id : res->crtcs[0];
    for (int i = 0; i < 2; i++) {
        drm_buffer(fd, dev, w, h, &buf[i]);
        drm_fill(&buf[i], w, h, i == 0 ? 0 : 0x00ffffffu);
    }
    printf("buffers %ux%u pitch %u\n", w, h, buf[0].pitch);
    if (drmModeSetCrtc(fd, crtc, buf[0].fb_id, 0, 0, &conn->connector_id, 1, mode) != 0)
        probe_fail(errno, "%s: drmModeSetCrtc %ux%u", dev, w, h);
    printf("mode set %ux%u on crtc %u\n", w, h, crtc);
    for (int n = 1; n <= DRM_PROBE_FLIPS; n++) {
        struct pollfd pfd = { .fd = fd, .events = POLLIN };
        int done = 0;

        if (drmModePageFlip(fd, crtc, buf[n % 2].fb_id, DRM_MODE_PAGE_FLIP_EVENT, &done) != 0)
            probe_fail(errno, "%s: drmModePageFlip %d", dev, n);
        while (!done) {
            int r = poll(&pfd, 1, DRM_PROBE_EVENT_MS);

            if (r <= 0)
                probe_fail(r < 0 ? errno : 0, "%s: no event for page flip %d", dev, n);
            if (drmHandleEvent(fd, &ev) != 0)
                probe_fail(errno, "%s: drmHandleEvent", dev);
        }
        printf("flip %d done\n", n);
    }
    /* an even number of flips leaves buffer 0 on screen */
    if (dump != NULL)
        probe_screendump(dump);
    f = fopen(out, "wb");
    if (f == NULL)
        probe_fail(errno, "%s", out);
    for (uint32_t y = 0; y < h; y++)
        if (fwrite(buf[0].map + (size_t)y * buf[0].pitch, 4, w, f) != w)
            probe_fail(errno, "%s", out);
    if (fclose(f) != 0)
        probe_fail(errno, "%s", out);
    drmModeFreeConnector(conn);
    drmModeFreeResources(res);
    close(fd);
}

static void drm_expected(uint32_t w, uint32_t h)
{
    uint8_t px[4];

    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            probe_store_pixel(px, probe_pattern(x, y) & 0x00ffffffu, 4);
            if (fwrite(px, 1, 4, stdout) != 4)
                probe_fail(errno, "stdout");
        }
}

/* The screendump QEMU writes of buffer 0: PPM P6, 8-bit R, G, B. */
static void drm_expected_ppm(uint32_t w, uint32_t h)
{
    printf("P6\n%u %u\n255\n", w, h);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            uint32_t v = probe_pattern(x, y);
            uint8_t rgb[3] = { (uint8_t)(v >> 16), (uint8_t)(v >> 8), (uint8_t)v };

            if (fwrite(rgb, 1, 3, stdout) != 3)
                probe_fail(errno, "stdout");
        }
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "info") == 0) {
        drm_info(argv[2]);
    } else if ((argc == 6 || argc == 7) && strcmp(argv[1], "flip") == 0) {
        drm_flip(argv[2], (uint32_t)probe_number("width", argv[3]), (uint32_t)probe_number("height", argv[4]),
                 argv[5], argc == 7 ? argv[6] : NULL);
    } else if (argc == 4 && strcmp(argv[1], "ppm") == 0) {
        drm_expected_ppm((uint32_t)probe_number("width", argv[2]), (uint32_t)probe_number("height", argv[3]));
    } else if (argc == 4 && strcmp(argv[1], "pattern") == 0) {
        drm_expected((uint32_t)probe_number("width", argv[2]), (uint32_t)probe_number("height", argv[3]));
    } else {
        fprintf(stderr, "usage: drm_probe info DEV | flip DEV W H OUT [DUMP] | pattern W H | ppm W H\n");
        return 2;
    }
    return 0;
}
