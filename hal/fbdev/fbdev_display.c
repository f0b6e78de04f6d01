/* SPDX-License-Identifier: MIT */
/*
 * fbdev_display.c - the "fbdev" display: a Linux framebuffer device
 * (/dev/fbN: vfb in the VM tests, simplefb or a DRM driver's fbdev
 * emulation on small boards), memory-mapped and drawn into directly.
 *
 * Start-up: read the mode (FBIOGET_VSCREENINFO / FBIOGET_FSCREENINFO); unless
 * set_mode = no, ask for the board's size and format with a virtual screen of
 * display_buffers pages (FBIOPUT_VSCREENINFO), falling back to one page and
 * then to the mode as it was; re-read what the driver granted and plan the
 * buffering (psc_fbdev_mode.h). The mode actually in force is what get_mode
 * reports: a driver that keeps its own size or format still works (the
 * firmware renders whatever the display has), one with a layout periscope
 * cannot draw is refused with a message saying which.
 *
 * Present: PAN shows the back page with FBIOPAN_DISPLAY and then waits for
 * the vertical blank (FBIO_WAITFORVSYNC, where the driver has it) so the old
 * page is off screen before it is drawn into again; COPY waits for the blank
 * and copies the memory frame to the screen; DIRECT does nothing. A screen
 * with red and blue swapped (vfb) is drawn in memory too, and the present
 * swaps the channels while copying into the back page (PAN) or the screen.
 *
 * Options (board lines "display.KEY = VALUE"):
 *   device    the framebuffer node (default /dev/fb0)
 *   set_mode  yes (default): ask for the board's mode; no: use it as it is
 *   console   a virtual terminal (e.g. /dev/tty1) switched to graphics mode
 *             while periscope runs, so the text console's cursor does not
 *             blink over the picture; restored at close
 * Close puts the original mode (and pan offset) back.
 */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <linux/fb.h>
#include <linux/kd.h>

#include "fbdev_internal.h"
#include "psc_fbdev_mode.h"
#include "psc_hal_display.h"
#include "psc_hal_option_bool.h"
#include "psc_io_log.h"

#define FBDEV_PATH_MAX 256u

typedef struct {
    psc_hal_display_t base;         /* first: the HAL hands this pointer back to us */
    char device[FBDEV_PATH_MAX];
    int fd;
    int console_fd;                 /* -1 unless option console */
    struct fb_var_screeninfo orig;  /* the mode before us, restored at close */
    struct fb_var_screeninfo var;   /* the mode in force */
    bool mode_changed;
    psc_fbdev_plan_t plan;
    psc_hal_display_mode_t mode;
    uint8_t *screen;                /* the mmap'd framebuffer */
    size_t screen_len;
    uint8_t *memory;                /* COPY or swap_rb: the frame drawn in memory */
    uint8_t front;                  /* PAN: page on screen */
    bool vsync_missing;             /* FBIO_WAITFORVSYNC is not implemented */
} fbdev_display_t;

static const char *const fbdev_known_options[] = { "device", "set_mode", "console", NULL };

static fbdev_display_t *to_fbdev(psc_hal_display_t *d)
{
    return (fbdev_display_t *)d;
}

static int xioctl(int fd, unsigned long request, void *arg)
{
    int rc;

    do {
        rc = ioctl(fd, request, arg);
    } while (rc < 0 && errno == EINTR);
    return rc;
}

static uint8_t *page_pixels(const fbdev_display_t *f, uint8_t page)
{
    return f->screen + (size_t)page * f->var.yres * f->plan.stride;
}

static void fill_surface(const fbdev_display_t *f, uint8_t *pixels, psc_surface_t *s)
{
    s->width = f->mode.width;
    s->height = f->mode.height;
    s->stride = f->mode.stride;
    s->format = f->mode.format;
    s->pixels = pixels;
}

static int fbdev_get_mode(psc_hal_display_t *d, psc_hal_display_mode_t *mode)
{
    *mode = to_fbdev(d)->mode;
    return 0;
}

/* Frames are drawn in memory when the screen cannot take them as drawn:
 * no panning (COPY) or red and blue swapped on the screen. */
static bool uses_memory(const fbdev_display_t *f)
{
    return f->plan.swap_rb || f->plan.buffering == PSC_FBDEV_COPY;
}

static int fbdev_get_back_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    fbdev_display_t *f = to_fbdev(d);

    if (uses_memory(f))
        fill_surface(f, f->memory, surface);
    else if (f->plan.buffering == PSC_FBDEV_PAN)
        fill_surface(f, page_pixels(f, (uint8_t)((f->front + 1u) % f->plan.pages)), surface);
    else
        fill_surface(f, f->screen, surface);
    return 0;
}

/* The frame last presented, in the format periscope draws (for a swapped
 * screen that is the memory frame, not the screen's bytes). */
static int fbdev_get_front_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    fbdev_display_t *f = to_fbdev(d);

    if (uses_memory(f))
        fill_surface(f, f->memory, surface);
    else
        fill_surface(f, f->plan.buffering == PSC_FBDEV_PAN ? page_pixels(f, f->front) : f->screen, surface);
    return 0;
}

static void wait_vsync(fbdev_display_t *f)
{
    __u32 screen = 0;

    if (f->vsync_missing)
        return;
    if (xioctl(f->fd, FBIO_WAITFORVSYNC, &screen) != 0 && (errno == ENOTTY || errno == EINVAL || errno == ENOSYS))
        f->vsync_missing = true;   /* vfb, simplefb: no vblank to wait for */
}

static int fbdev_present(psc_hal_display_t *d)
{
    fbdev_display_t *f = to_fbdev(d);

    if (f->plan.buffering == PSC_FBDEV_PAN) {
        uint8_t back = (uint8_t)((f->front + 1u) % f->plan.pages);
        struct fb_var_screeninfo pan = f->var;

        if (f->plan.swap_rb)
            psc_fbdev_copy_frame(page_pixels(f, back), f->plan.stride, f->memory, f->plan.stride, f->mode.width,
                                 f->mode.height, f->mode.format, true);
        pan.xoffset = 0;
        pan.yoffset = (uint32_t)back * f->var.yres;
        if (xioctl(f->fd, FBIOPAN_DISPLAY, &pan) != 0)
            return errno == ENODEV ? -ENODEV : -EIO;
        wait_vsync(f);
        f->front = back;
        return 0;
    }
    if (uses_memory(f)) {
        if (f->plan.buffering == PSC_FBDEV_COPY)
            wait_vsync(f);
        psc_fbdev_copy_frame(f->screen, f->plan.stride, f->memory, f->plan.stride, f->mode.width, f->mode.height,
                             f->mode.format, f->plan.swap_rb);
    }
    return 0;
}

static int fbdev_set_blank(psc_hal_display_t *d, bool blank)
{
    fbdev_display_t *f = to_fbdev(d);

    if (ioctl(f->fd, FBIOBLANK, blank ? FB_BLANK_POWERDOWN : FB_BLANK_UNBLANK) != 0)
        return errno == EINVAL || errno == ENOTTY ? -ENOSYS : -EIO;
    return 0;
}

static void fbdev_close(psc_hal_display_t *d)
{
    fbdev_display_t *f = to_fbdev(d);

    if (f->screen != NULL && f->screen != MAP_FAILED)
        munmap(f->screen, f->screen_len);
    if (f->fd >= 0) {
        if (f->mode_changed) {
            struct fb_var_screeninfo orig = f->orig;
            orig.activate = FB_ACTIVATE_NOW;
            xioctl(f->fd, FBIOPUT_VSCREENINFO, &orig);
        } else if (f->plan.buffering == PSC_FBDEV_PAN) {
            struct fb_var_screeninfo pan = f->var;
            pan.xoffset = f->orig.xoffset;
            pan.yoffset = f->orig.yoffset;
            xioctl(f->fd, FBIOPAN_DISPLAY, &pan);
        }
        close(f->fd);
    }
    if (f->console_fd >= 0) {
        ioctl(f->console_fd, KDSETMODE, KD_TEXT);
        close(f->console_fd);
    }
    free(f->memory);
    free(f);
}

static const psc_hal_display_ops_t fbdev_display_ops = {
    .get_mode = fbdev_get_mode,
    .get_back_buffer = fbdev_get_back_buffer,
    .present = fbdev_present,
    .set_blank = fbdev_set_blank,
    .get_front_buffer = fbdev_get_front_buffer,
    .close = fbdev_close,
};

/* Ask for the board's mode: n pages, then one page; keep the old mode if
 * the driver refuses both (fixed-mode drivers like simplefb do). */
static void fbdev_request_mode(fbdev_display_t *f, const psc_hal_display_config_t *cfg)
{
    struct fb_var_screeninfo want;
    uint8_t tries[2] = { cfg->buffer_count, 1 };

    for (unsigned i = 0; i < 2; i++) {
        if (i == 1 && tries[0] <= 1)
            break;
        psc_fbdev_request(&f->orig, cfg->width, cfg->height, cfg->format, tries[i], &want);
        if (xioctl(f->fd, FBIOPUT_VSCREENINFO, &want) == 0) {
            f->mode_changed = true;
            return;
        }
    }
    psc_io_log(PSC_LOG_NOTICE, "fbdev display %s: the driver keeps its mode (%ux%u, %u bpp): FBIOPUT_VSCREENINFO: %s",
            f->device, (unsigned)f->orig.xres, (unsigned)f->orig.yres, (unsigned)f->orig.bits_per_pixel,
            strerror(errno));
}

static int fbdev_read_options(fbdev_display_t *f, const psc_hal_display_config_t *cfg, bool *set_mode, char *err,
                              size_t errlen)
{
    const psc_hal_option_t *o;
    int rc = psc_hal_options_check(&cfg->options, fbdev_known_options, "display", "fbdev", err, errlen);

    if (rc != 0)
        return rc;
    o = psc_hal_options_find(&cfg->options, "device");
    snprintf(f->device, sizeof f->device, "%s", o != NULL && o->value != NULL ? o->value : "/dev/fb0");
    rc = psc_hal_options_get_bool(&cfg->options, "set_mode", "display", true, set_mode, err, errlen);
    if (rc != 0)
        return rc;
    o = psc_hal_options_find(&cfg->options, "console");
    if (o != NULL && o->value != NULL && o->value[0] != '\0') {
        f->console_fd = open(o->value, O_RDWR | O_CLOEXEC | O_NOCTTY);
        if (f->console_fd < 0 || ioctl(f->console_fd, KDSETMODE, KD_GRAPHICS) != 0) {
            psc_hal_error_set(err, errlen, "%s: display option 'console': cannot switch %s to graphics mode: %s",
                              o->origin ? o->origin : "display", o->value, strerror(errno));
            return -EINVAL;
        }
    }
    return 0;
}

int psc_fbdev_display_open(const psc_hal_display_config_t *cfg, psc_hal_display_t **out, char *err, size_t errlen)
{
    struct fb_fix_screeninfo fix;
    fbdev_display_t *f;
    bool set_mode;
    char why[300];
    int rc;

    *out = NULL;
    if (cfg->buffer_count < 1 || cfg->buffer_count > 3 ||
        (cfg->format != PSC_PIX_RGB565 && cfg->format != PSC_PIX_XRGB8888)) {
        psc_hal_error_set(err, errlen, "fbdev display: %u buffers in format %d requested; 1..3 buffers of rgb565 or "
                          "xrgb8888 are supported", (unsigned)cfg->buffer_count, (int)cfg->format);
        return -EINVAL;
    }
    f = calloc(1, sizeof *f);
    if (f == NULL) {
        psc_hal_error_set(err, errlen, "fbdev display: out of memory");
        return -ENOMEM;
    }
    f->base.ops = &fbdev_display_ops;
    f->base.backend = "fbdev";
    f->fd = -1;
    f->console_fd = -1;
    rc = fbdev_read_options(f, cfg, &set_mode, err, errlen);
    if (rc != 0)
        goto fail;
    f->fd = open(f->device, O_RDWR | O_CLOEXEC);
    if (f->fd < 0) {
        rc = errno == ENOENT || errno == ENODEV || errno == ENXIO ? -ENODEV : -EIO;
        psc_hal_error_set(err, errlen, "fbdev display: cannot open %s: %s%s", f->device, strerror(errno),
                          errno == ENOENT ? " (is the framebuffer driver loaded? display.device names another node)"
                                          : "");
        goto fail;
    }
    if (xioctl(f->fd, FBIOGET_VSCREENINFO, &f->orig) != 0) {
        psc_hal_error_set(err, errlen, "fbdev display: %s is not a framebuffer (FBIOGET_VSCREENINFO: %s)", f->device,
                          strerror(errno));
        rc = -ENODEV;
        goto fail;
    }
    if (set_mode)
        fbdev_request_mode(f, cfg);
    if (xioctl(f->fd, FBIOGET_VSCREENINFO, &f->var) != 0 || xioctl(f->fd, FBIOGET_FSCREENINFO, &fix) != 0) {
        psc_hal_error_set(err, errlen, "fbdev display: %s: reading the mode back failed: %s", f->device,
                          strerror(errno));
        rc = -EIO;
        goto fail;
    }
    rc = psc_fbdev_plan(&f->var, &fix, cfg->buffer_count, &f->plan, why, sizeof why);
    if (rc != 0) {
        psc_hal_error_set(err, errlen, "fbdev display: %s (%.16s): %s", f->device, fix.id, why);
        goto fail;
    }
    f->screen_len = fix.smem_len;
    f->screen = mmap(NULL, f->screen_len, PROT_READ | PROT_WRITE, MAP_SHARED, f->fd, 0);
    if (f->screen == MAP_FAILED) {
        f->screen = NULL;
        psc_hal_error_set(err, errlen, "fbdev display: cannot map %s (%u bytes): %s", f->device,
                          (unsigned)fix.smem_len, strerror(errno));
        rc = -EIO;
        goto fail;
    }
    f->mode = (psc_hal_display_mode_t){
        .width = (uint16_t)f->var.xres, .height = (uint16_t)f->var.yres, .stride = f->plan.stride,
        .format = f->plan.format, .refresh_mhz = f->plan.refresh_mhz,
        .buffer_count = f->plan.buffering == PSC_FBDEV_PAN ? f->plan.pages
                        : f->plan.buffering == PSC_FBDEV_COPY ? 2 : 1,
    };
    if (f->plan.buffering == PSC_FBDEV_PAN) {
        /* start on page 0, whatever the console left the offset at */
        struct fb_var_screeninfo pan = f->var;
        pan.xoffset = 0;
        pan.yoffset = 0;
        if (xioctl(f->fd, FBIOPAN_DISPLAY, &pan) != 0) {
            f->plan.buffering = PSC_FBDEV_COPY;   /* claims to pan but will not: copy instead */
            f->plan.pages = 1;
            f->mode.buffer_count = 2;
        }
    }
    if (uses_memory(f)) {
        f->memory = calloc(f->var.yres, f->plan.stride);
        if (f->memory == NULL) {
            psc_hal_error_set(err, errlen, "fbdev display: out of memory for a %ux%u frame", (unsigned)f->var.xres,
                              (unsigned)f->var.yres);
            rc = -ENOMEM;
            goto fail;
        }
    }
    psc_io_log(PSC_LOG_NOTICE, "fbdev display %s (%.16s): %ux%u %s%s, stride %u, %s", f->device, fix.id,
            (unsigned)f->var.xres, (unsigned)f->var.yres, f->plan.format == PSC_PIX_RGB565 ? "RGB565" : "XRGB8888",
            f->plan.swap_rb ? " (red and blue swapped on screen)" : "", (unsigned)f->plan.stride,
            f->plan.buffering == PSC_FBDEV_PAN ? (f->plan.pages == 3 ? "3 pages, pan-display" : "2 pages, pan-display")
            : f->plan.buffering == PSC_FBDEV_COPY ? "no panning: drawn in memory and copied"
            : f->plan.swap_rb                     ? "single buffer: drawn in memory and copied"
                                                  : "single buffer drawn on screen");
    *out = &f->base;
    return 0;
fail:
    fbdev_close(&f->base);
    return rc;
}
