/* SPDX-License-Identifier: MIT */
/*
 * test_hal_display.c - the fbdev and DRM displays' decisions without the
 * devices (hal/fbdev/psc_fbdev_mode.h, hal/drm/psc_drm_mode.h): pixel
 * layouts accepted and refused, the mode requested, the buffering plan in
 * what a driver granted (vfb, a fixed-mode simplefb, a driver without
 * panning), mode choice from real monitors' and virtual devices' lists,
 * connector names; and both backends failing cleanly, with a message, when
 * the device is missing or is not a display. The real drivers (vfb, bochs
 * DRM) are exercised by the VM tests.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdbool.h>
#include <string.h>
#include <unistd.h>

#include <drm_fourcc.h>

#include "drm/psc_drm_mode.h"
#include "fbdev/psc_fbdev_mode.h"
#include "psc_hal_clock.h"
#include "psc_hal_display.h"

/* ---- fbdev ------------------------------------------------------------------------ */

/* What vfb reports for mode_option=640x480-32 (standard VESA timings). */
static void vfb_640x480_32(struct fb_var_screeninfo *v, struct fb_fix_screeninfo *f)
{
    memset(v, 0, sizeof *v);
    memset(f, 0, sizeof *f);
    v->xres = v->xres_virtual = 640;
    v->yres = 480;
    v->yres_virtual = 960;
    v->bits_per_pixel = 32;
    v->red = (struct fb_bitfield){ 16, 8, 0 };
    v->green = (struct fb_bitfield){ 8, 8, 0 };
    v->blue = (struct fb_bitfield){ 0, 8, 0 };
    v->transp = (struct fb_bitfield){ 24, 8, 0 };
    v->pixclock = 39721;
    v->left_margin = 48;
    v->right_margin = 16;
    v->upper_margin = 33;
    v->lower_margin = 10;
    v->hsync_len = 96;
    v->vsync_len = 2;
    strcpy(f->id, "Virtual FB");
    f->type = FB_TYPE_PACKED_PIXELS;
    f->visual = FB_VISUAL_TRUECOLOR;
    f->ypanstep = 1;
    f->line_length = 640 * 4;
    f->smem_len = 640 * 4 * 960;
}

static void test_fbdev_formats(void **state)
{
    struct fb_var_screeninfo v;
    struct fb_fix_screeninfo f;
    psc_pixfmt_t fmt = 0;
    bool swap = true;
    char why[400];
    (void)state;

    vfb_640x480_32(&v, &f);
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), 0);
    assert_int_equal(fmt, PSC_PIX_XRGB8888);
    assert_false(swap);
    v.transp = (struct fb_bitfield){ 0, 0, 0 };   /* no alpha field: the same pixels */
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), 0);
    assert_int_equal(fmt, PSC_PIX_XRGB8888);

    v.bits_per_pixel = 16;
    v.red = (struct fb_bitfield){ 11, 5, 0 };
    v.green = (struct fb_bitfield){ 5, 6, 0 };
    v.blue = (struct fb_bitfield){ 0, 5, 0 };
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), 0);
    assert_int_equal(fmt, PSC_PIX_RGB565);
    assert_false(swap);

    /* vfb keeps red in the low bits: BGR565 and XBGR8888, drawn with red and blue swapped */
    v.blue = (struct fb_bitfield){ 11, 5, 0 };
    v.red = (struct fb_bitfield){ 0, 5, 0 };
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), 0);
    assert_int_equal(fmt, PSC_PIX_RGB565);
    assert_true(swap);
    v.bits_per_pixel = 32;
    v.red = (struct fb_bitfield){ 0, 8, 0 };
    v.green = (struct fb_bitfield){ 8, 8, 0 };
    v.blue = (struct fb_bitfield){ 16, 8, 0 };
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), 0);
    assert_int_equal(fmt, PSC_PIX_XRGB8888);
    assert_true(swap);

    /* refused, with the layout in the message */
    v.bits_per_pixel = 16;
    v.red = (struct fb_bitfield){ 10, 5, 0 };    /* XRGB1555 */
    v.green = (struct fb_bitfield){ 5, 5, 0 };
    v.blue = (struct fb_bitfield){ 0, 5, 0 };
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), -EINVAL);
    assert_non_null(strstr(why, "16 bits per pixel, red 10:5 green 5:5 blue 0:5"));
    assert_non_null(strstr(why, "RGB565"));
    v.bits_per_pixel = 24;
    v.red = (struct fb_bitfield){ 16, 8, 0 };
    v.green = (struct fb_bitfield){ 8, 8, 0 };
    v.blue = (struct fb_bitfield){ 0, 8, 0 };
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), -EINVAL);
    assert_non_null(strstr(why, "24 bits per pixel"));
    v.bits_per_pixel = 32;
    v.red = (struct fb_bitfield){ 24, 8, 0 };    /* RGBX8888 */
    v.green = (struct fb_bitfield){ 16, 8, 0 };
    v.blue = (struct fb_bitfield){ 8, 8, 0 };
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), -EINVAL);
    vfb_640x480_32(&v, &f);
    v.grayscale = 0x34325258;                    /* a FOURCC mode */
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), -EINVAL);
    assert_non_null(strstr(why, "FOURCC"));
    vfb_640x480_32(&v, &f);
    f.visual = FB_VISUAL_PSEUDOCOLOR;            /* a palette */
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), -EINVAL);
    f.visual = FB_VISUAL_TRUECOLOR;
    f.type = FB_TYPE_PLANES;
    assert_int_equal(psc_fbdev_format(&v, &f, &fmt, &swap, why, sizeof why), -EINVAL);
}

static void test_fbdev_request(void **state)
{
    struct fb_var_screeninfo cur, want;
    struct fb_fix_screeninfo f;
    psc_pixfmt_t fmt;
    bool swap;
    char why[300];
    (void)state;

    vfb_640x480_32(&cur, &f);
    cur.yoffset = 480;   /* the console had panned */
    psc_fbdev_request(&cur, 320, 240, PSC_PIX_RGB565, 2, &want);
    assert_int_equal(want.xres, 320);
    assert_int_equal(want.yres, 240);
    assert_int_equal(want.xres_virtual, 320);
    assert_int_equal(want.yres_virtual, 480);
    assert_int_equal(want.yoffset, 0);
    assert_int_equal(want.bits_per_pixel, 16);
    assert_int_equal(want.activate, FB_ACTIVATE_NOW);
    assert_int_equal(want.pixclock, cur.pixclock);   /* timings kept */
    assert_int_equal(psc_fbdev_format(&want, &f, &fmt, &swap, why, sizeof why), 0);
    assert_int_equal(fmt, PSC_PIX_RGB565);
    psc_fbdev_request(&cur, 800, 600, PSC_PIX_XRGB8888, 3, &want);
    assert_int_equal(want.yres_virtual, 1800);
    assert_int_equal(psc_fbdev_format(&want, &f, &fmt, &swap, why, sizeof why), 0);
    assert_int_equal(fmt, PSC_PIX_XRGB8888);
}

static void test_fbdev_plan(void **state)
{
    struct fb_var_screeninfo v;
    struct fb_fix_screeninfo f;
    psc_fbdev_plan_t p;
    char why[300];
    (void)state;

    vfb_640x480_32(&v, &f);
    assert_int_equal(psc_fbdev_plan(&v, &f, 2, &p, why, sizeof why), 0);
    assert_int_equal(p.buffering, PSC_FBDEV_PAN);
    assert_int_equal(p.pages, 2);
    assert_int_equal(p.stride, 2560);
    assert_int_equal(p.format, PSC_PIX_XRGB8888);
    assert_int_equal(p.refresh_mhz, 59942);   /* 10^15 / (39721 ps * 800 * 525) */
    /* three wanted, two fit the virtual screen */
    assert_int_equal(psc_fbdev_plan(&v, &f, 3, &p, why, sizeof why), 0);
    assert_int_equal(p.pages, 2);
    v.yres_virtual = 1440;
    f.smem_len = 2560 * 1440;
    assert_int_equal(psc_fbdev_plan(&v, &f, 3, &p, why, sizeof why), 0);
    assert_int_equal(p.pages, 3);
    /* virtual screen tall enough but too little memory mapped: two pages */
    f.smem_len = 2560 * 1000;
    assert_int_equal(psc_fbdev_plan(&v, &f, 3, &p, why, sizeof why), 0);
    assert_int_equal(p.buffering, PSC_FBDEV_PAN);
    assert_int_equal(p.pages, 2);
    /* one buffer asked: drawn on screen */
    assert_int_equal(psc_fbdev_plan(&v, &f, 1, &p, why, sizeof why), 0);
    assert_int_equal(p.buffering, PSC_FBDEV_DIRECT);
    /* simplefb: fixed mode, one page, no panning -> drawn in memory and copied */
    vfb_640x480_32(&v, &f);
    v.yres_virtual = 480;
    f.ypanstep = 0;
    f.smem_len = 2560 * 480;
    v.pixclock = 0;
    assert_int_equal(psc_fbdev_plan(&v, &f, 2, &p, why, sizeof why), 0);
    assert_int_equal(p.buffering, PSC_FBDEV_COPY);
    assert_int_equal(p.refresh_mhz, 0);
    /* a driver that lists two pages but cannot pan */
    vfb_640x480_32(&v, &f);
    f.ypanstep = 0;
    assert_int_equal(psc_fbdev_plan(&v, &f, 2, &p, why, sizeof why), 0);
    assert_int_equal(p.buffering, PSC_FBDEV_COPY);
    /* pan steps that do not divide the page height */
    vfb_640x480_32(&v, &f);
    f.ypanstep = 7;
    assert_int_equal(psc_fbdev_plan(&v, &f, 2, &p, why, sizeof why), 0);
    assert_int_equal(p.buffering, PSC_FBDEV_COPY);
    /* a padded line (stride > width) is used as given */
    vfb_640x480_32(&v, &f);
    f.line_length = 2816;
    f.smem_len = 2816 * 960;
    assert_int_equal(psc_fbdev_plan(&v, &f, 2, &p, why, sizeof why), 0);
    assert_int_equal(p.stride, 2816);
    /* unusable */
    f.line_length = 2000;
    assert_int_equal(psc_fbdev_plan(&v, &f, 2, &p, why, sizeof why), -EINVAL);
    assert_non_null(strstr(why, "line_length 2000"));
    vfb_640x480_32(&v, &f);
    f.smem_len = 1000;
    assert_int_equal(psc_fbdev_plan(&v, &f, 2, &p, why, sizeof why), -EINVAL);
    assert_non_null(strstr(why, "less than one 640x480 screen"));
    vfb_640x480_32(&v, &f);
    v.xres = 0;
    assert_int_equal(psc_fbdev_plan(&v, &f, 2, &p, why, sizeof why), -EINVAL);
}

static void test_fbdev_copy_frame(void **state)
{
    uint32_t src32[2 * 3] = { 0xFF112233u, 0x00ABCDEFu, 0x12345678u, 0, 0xFFFFFFFFu, 0x80FF0001u };
    uint32_t dst32[2 * 4];
    uint16_t src16[3 * 2] = { 0xF800u, 0x07E0u, 0x001Fu, 0x1234u, 0xFFFFu, 0 };
    uint16_t dst16[4 * 2];
    (void)state;

    /* 32 bpp, source stride 3 pixels (one padding), destination 4 */
    memset(dst32, 0xEE, sizeof dst32);
    psc_fbdev_copy_frame((uint8_t *)dst32, 16, (const uint8_t *)src32, 12, 2, 2, PSC_PIX_XRGB8888, true);
    assert_int_equal(dst32[0], 0xFF332211u);
    assert_int_equal(dst32[1], 0x00EFCDABu);
    assert_int_equal(dst32[2], 0xEEEEEEEEu);    /* padding untouched */
    assert_int_equal(dst32[4], 0x00000000u);
    assert_int_equal(dst32[5], 0xFFFFFFFFu);
    psc_fbdev_copy_frame((uint8_t *)dst32, 16, (const uint8_t *)src32, 12, 2, 2, PSC_PIX_XRGB8888, false);
    assert_int_equal(dst32[0], 0xFF112233u);
    assert_int_equal(dst32[5], 0xFFFFFFFFu);
    /* 16 bpp: red and blue fields exchanged, green kept */
    psc_fbdev_copy_frame((uint8_t *)dst16, 8, (const uint8_t *)src16, 6, 3, 2, PSC_PIX_RGB565, true);
    assert_int_equal(dst16[0], 0x001Fu);
    assert_int_equal(dst16[1], 0x07E0u);
    assert_int_equal(dst16[2], 0xF800u);
    assert_int_equal(dst16[4], (0x1234u & 0x07E0u) | (0x1234u >> 11) | ((0x1234u & 0x1Fu) << 11));
    assert_int_equal(dst16[5], 0xFFFFu);
    assert_int_equal(dst16[6], 0x0000u);
}

/* ---- DRM ---------------------------------------------------------------------------- */

static drmModeModeInfo mode(uint16_t w, uint16_t h, uint32_t clock_khz, uint16_t htotal, uint16_t vtotal,
                            uint32_t vrefresh, uint32_t type, uint32_t flags)
{
    drmModeModeInfo m;

    memset(&m, 0, sizeof m);
    m.hdisplay = w;
    m.vdisplay = h;
    m.clock = clock_khz;
    m.htotal = htotal;
    m.vtotal = vtotal;
    m.vrefresh = vrefresh;
    m.type = type | DRM_MODE_TYPE_DRIVER;
    m.flags = flags;
    return m;
}

static void test_drm_mode_request(void **state)
{
    psc_drm_mode_request_t r;
    (void)state;

    assert_int_equal(psc_drm_parse_mode_request("board", &r), 0);
    assert_int_equal(r.kind, PSC_DRM_MODE_BOARD);
    assert_int_equal(psc_drm_parse_mode_request("preferred", &r), 0);
    assert_int_equal(r.kind, PSC_DRM_MODE_PREFERRED);
    assert_int_equal(psc_drm_parse_mode_request("1280x720", &r), 0);
    assert_int_equal(r.kind, PSC_DRM_MODE_SIZE);
    assert_int_equal(r.width, 1280);
    assert_int_equal(r.height, 720);
    assert_int_equal(r.refresh_hz, 0);
    assert_int_equal(psc_drm_parse_mode_request("1920x1080@50", &r), 0);
    assert_int_equal(r.refresh_hz, 50);
    const char *bad[] = { "", "1280", "1280x", "x720", "1280x720@", "1280x720@0", "0x720", "5000x720",
                          "1280x720@60Hz", "Preferred", "1280X720", NULL };
    for (unsigned i = 0; bad[i] != NULL; i++)
        assert_int_equal(psc_drm_parse_mode_request(bad[i], &r), -EINVAL);
    assert_int_equal(psc_drm_parse_mode_request(NULL, &r), -EINVAL);
}

static void test_drm_pick_mode(void **state)
{
    /* an HDMI monitor (CEA timings) */
    drmModeModeInfo tv[] = {
        mode(1920, 1080, 148500, 2200, 1125, 60, DRM_MODE_TYPE_PREFERRED, 0),
        mode(1920, 1080, 148500, 2640, 1125, 50, 0, 0),
        mode(1920, 1080, 74250, 2200, 1125, 60, 0, DRM_MODE_FLAG_INTERLACE),
        mode(1280, 720, 74250, 1980, 750, 50, 0, 0),
        mode(1280, 720, 74250, 1650, 750, 60, 0, 0),
        mode(640, 480, 25175, 800, 525, 60, 0, 0),
    };
    /* bochs-display: a long list, no preferred flag on the first of the size */
    drmModeModeInfo bochs[] = {
        mode(1024, 768, 65000, 1344, 806, 60, DRM_MODE_TYPE_PREFERRED, 0),
        mode(800, 600, 40000, 1056, 628, 60, 0, 0),
        mode(640, 480, 25175, 800, 525, 60, 0, 0),
    };
    drmModeModeInfo only_interlaced[] = { mode(1920, 1080, 74250, 2200, 1125, 60, 0, DRM_MODE_FLAG_INTERLACE) };
    psc_drm_mode_request_t r = { PSC_DRM_MODE_BOARD, 1280, 720, 0 };
    char text[300];
    (void)state;

    assert_int_equal(psc_drm_pick_mode(tv, 6, &r), 4);          /* of the size, the highest refresh */
    r.refresh_hz = 50;
    assert_int_equal(psc_drm_pick_mode(tv, 6, &r), 3);
    r = (psc_drm_mode_request_t){ PSC_DRM_MODE_SIZE, 1920, 1080, 0 };
    assert_int_equal(psc_drm_pick_mode(tv, 6, &r), 0);          /* the preferred one of the size */
    r.refresh_hz = 30;
    assert_int_equal(psc_drm_pick_mode(tv, 6, &r), 1);          /* closest to 30 Hz, never interlaced */
    r = (psc_drm_mode_request_t){ PSC_DRM_MODE_PREFERRED, 0, 0, 0 };
    assert_int_equal(psc_drm_pick_mode(tv, 6, &r), 0);
    tv[0].type = DRM_MODE_TYPE_DRIVER;                          /* no preferred flag at all: the first */
    assert_int_equal(psc_drm_pick_mode(tv, 6, &r), 0);
    r = (psc_drm_mode_request_t){ PSC_DRM_MODE_BOARD, 800, 600, 0 };
    assert_int_equal(psc_drm_pick_mode(tv, 6, &r), -1);
    assert_int_equal(psc_drm_pick_mode(bochs, 3, &r), 1);
    r = (psc_drm_mode_request_t){ PSC_DRM_MODE_BOARD, 640, 480, 0 };
    assert_int_equal(psc_drm_pick_mode(bochs, 3, &r), 2);
    r = (psc_drm_mode_request_t){ PSC_DRM_MODE_PREFERRED, 0, 0, 0 };
    assert_int_equal(psc_drm_pick_mode(only_interlaced, 1, &r), -1);
    assert_int_equal(psc_drm_pick_mode(NULL, 0, &r), -1);

    assert_int_equal(psc_drm_mode_refresh_mhz(&tv[0]), 60000);
    assert_int_equal(psc_drm_mode_refresh_mhz(&tv[1]), 50000);
    assert_int_equal(psc_drm_mode_refresh_mhz(&bochs[2]), 59940);
    drmModeModeInfo no_timing = mode(640, 480, 0, 0, 0, 75, 0, 0);
    assert_int_equal(psc_drm_mode_refresh_mhz(&no_timing), 75000);

    psc_drm_describe_modes(bochs, 3, text, sizeof text);
    assert_string_equal(text, "1024x768@60 (preferred), 800x600@60, 640x480@60");
    psc_drm_describe_modes(tv, 3, text, 20);   /* truncated, still terminated */
    assert_int_equal(strlen(text), 19);
    psc_drm_describe_modes(tv, 0, text, sizeof text);
    assert_string_equal(text, "no modes");
}

static void test_drm_names_and_formats(void **state)
{
    uint32_t fourcc = 0, bpp = 0;
    char name[32];
    (void)state;

    assert_int_equal(psc_drm_format(PSC_PIX_RGB565, &fourcc, &bpp), 0);
    assert_int_equal(fourcc, DRM_FORMAT_RGB565);
    assert_int_equal(bpp, 16);
    assert_int_equal(psc_drm_format(PSC_PIX_XRGB8888, &fourcc, &bpp), 0);
    assert_int_equal(fourcc, DRM_FORMAT_XRGB8888);
    assert_int_equal(bpp, 32);
    assert_int_equal(psc_drm_format(PSC_PIX_PAL8, &fourcc, &bpp), -EINVAL);

    psc_drm_connector_name(DRM_MODE_CONNECTOR_HDMIA, 1, name, sizeof name);
    assert_string_equal(name, "HDMI-A-1");
    psc_drm_connector_name(DRM_MODE_CONNECTOR_VIRTUAL, 1, name, sizeof name);
    assert_string_equal(name, "Virtual-1");
    psc_drm_connector_name(DRM_MODE_CONNECTOR_DSI, 2, name, sizeof name);
    assert_string_equal(name, "DSI-2");
    psc_drm_connector_name(DRM_MODE_CONNECTOR_DisplayPort, 3, name, sizeof name);
    assert_string_equal(name, "DP-3");
    psc_drm_connector_name(99, 1, name, sizeof name);
    assert_string_equal(name, "Unknown-1");

    assert_int_equal(psc_drm_pick_crtc(0x1, 2), 0);
    assert_int_equal(psc_drm_pick_crtc(0x6, 3), 1);
    assert_int_equal(psc_drm_pick_crtc(0x4, 2), -1);   /* only a CRTC the card does not list */
    assert_int_equal(psc_drm_pick_crtc(0, 4), -1);
}

/* ---- the backends without their devices ----------------------------------------------- */

static int open_display(const char *backend, const psc_hal_option_t *opts, size_t n, psc_hal_display_t **d,
                        char *err, size_t errlen)
{
    psc_hal_display_config_t cfg = { .width = 640, .height = 480, .format = PSC_PIX_XRGB8888, .buffer_count = 2,
                                     .frame_rate_mhz = 30000, .options = { opts, n } };

    return psc_hal_display_open(backend, &cfg, d, err, errlen);
}

static void test_backends_without_devices(void **state)
{
    psc_hal_display_t *d;
    char err[400];
    (void)state;

    psc_hal_option_t fb_missing[] = { { "device", "/dev/periscope-no-fb", "b.conf:2" } };
    assert_int_equal(open_display("fbdev", fb_missing, 1, &d, err, sizeof err), -ENODEV);
    assert_null(d);
    assert_non_null(strstr(err, "fbdev display: cannot open /dev/periscope-no-fb"));
    psc_hal_option_t fb_null[] = { { "device", "/dev/null", "b.conf:2" } };
    assert_int_equal(open_display("fbdev", fb_null, 1, &d, err, sizeof err), -ENODEV);
    assert_non_null(strstr(err, "/dev/null is not a framebuffer"));
    psc_hal_option_t fb_bad[] = { { "set_mode", "maybe", "b.conf:3" } };
    assert_int_equal(open_display("fbdev", fb_bad, 1, &d, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "b.conf:3: display option 'set_mode' must be yes or no"));
    psc_hal_option_t fb_unknown[] = { { "connector", "HDMI-A-1", "b.conf:4" } };
    assert_int_equal(open_display("fbdev", fb_unknown, 1, &d, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "b.conf:4"));

    psc_hal_option_t drm_missing[] = { { "device", "/dev/dri/periscope-no-card", "b.conf:2" } };
    assert_int_equal(open_display("drm", drm_missing, 1, &d, err, sizeof err), -ENODEV);
    assert_non_null(strstr(err, "drm display: cannot open /dev/dri/periscope-no-card"));
    if (access("/dev/dri", F_OK) != 0) {   /* device = auto on a machine without DRM (never take over a desktop's) */
        assert_int_equal(open_display("drm", NULL, 0, &d, err, sizeof err), -ENODEV);
        assert_non_null(strstr(err, "no /dev/dri/card0..7 drives a connected display"));
    }
    psc_hal_option_t drm_null[] = { { "device", "/dev/null", "b.conf:2" } };
    assert_int_equal(open_display("drm", drm_null, 1, &d, err, sizeof err), -ENODEV);
    assert_non_null(strstr(err, "/dev/null is not a KMS display device"));
    psc_hal_option_t drm_mode[] = { { "mode", "huge", "b.conf:5" } };
    assert_int_equal(open_display("drm", drm_mode, 1, &d, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "b.conf:5: display option 'mode' must be board, preferred, WxH or WxH@HZ"));
    psc_hal_option_t drm_timeout[] = { { "flip_timeout_ms", "0", "b.conf:6" } };
    assert_int_equal(open_display("drm", drm_timeout, 1, &d, err, sizeof err), -EINVAL);

    psc_hal_display_config_t cfg = { .width = 640, .height = 480, .format = PSC_PIX_PAL8, .buffer_count = 2 };
    assert_int_equal(psc_hal_display_open("drm", &cfg, &d, err, sizeof err), -EINVAL);
    assert_int_equal(psc_hal_display_open("fbdev", &cfg, &d, err, sizeof err), -EINVAL);
    cfg.format = PSC_PIX_RGB565;
    cfg.buffer_count = 0;
    assert_int_equal(psc_hal_display_open("fbdev", &cfg, &d, err, sizeof err), -EINVAL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fbdev_formats),
        cmocka_unit_test(test_fbdev_request),
        cmocka_unit_test(test_fbdev_plan),
        cmocka_unit_test(test_fbdev_copy_frame),
        cmocka_unit_test(test_drm_mode_request),
        cmocka_unit_test(test_drm_pick_mode),
        cmocka_unit_test(test_drm_names_and_formats),
        cmocka_unit_test(test_backends_without_devices),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
