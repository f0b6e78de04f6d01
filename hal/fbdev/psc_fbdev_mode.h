/* SPDX-License-Identifier: MIT */
/*
 * psc_fbdev_mode.h - the Linux framebuffer (fbdev) display's decisions that
 * need no device: which pixel layouts it can draw, the mode it asks the
 * driver for, and how it double-buffers in what the driver granted. Kept
 * apart from the ioctl code (fbdev_display.c) so tests can feed it the
 * screen-info structures of real drivers (vfb, simplefb, vc4's fbdev
 * emulation) without a /dev/fb0.
 *
 * Buffering plans:
 *   PAN     buffer_count pages stacked in the virtual screen (yres_virtual
 *           >= n * yres), the back page drawn off screen and shown with
 *           FBIOPAN_DISPLAY - tear-free where the driver pans at vblank;
 *   DIRECT  one buffer, drawn on screen (the board asked for 1 buffer);
 *   COPY    the driver cannot pan (ypanstep 0, or too little memory for a
 *           second page): frames are drawn in memory and copied to the
 *           screen at present.
 * Channel order: some drivers keep red in the low bits whatever is asked
 * (vfb: XBGR8888 at 32 bpp, BGR565 at 16). periscope still draws RGB565 or
 * XRGB8888, into memory, and the present swaps red and blue on the way to
 * the screen (swap_rb): into the back page before panning where the driver
 * pans, else straight onto the visible page.
 */
#ifndef PSC_FBDEV_MODE_H
#define PSC_FBDEV_MODE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <linux/fb.h>

#include "base/psc_types.h"

typedef enum {
    PSC_FBDEV_PAN = 1,
    PSC_FBDEV_DIRECT,
    PSC_FBDEV_COPY
} psc_fbdev_buffering_t;

/** How the display will use the framebuffer the driver granted. */
typedef struct {
    psc_fbdev_buffering_t buffering;
    uint8_t pages;          /* PAN: pages in the virtual screen used (2..3); else 1 */
    psc_pixfmt_t format;    /* what periscope draws: RGB565 or XRGB8888 */
    bool swap_rb;           /* the screen holds it with red and blue swapped */
    uint32_t stride;        /* fix.line_length */
    uint32_t refresh_mhz;   /* from the var timings, 0 if the driver gives none */
} psc_fbdev_plan_t;

/**
 * The pixel format of a var/fix pair: RGB565 (16 bpp, red 11:5, green 5:6,
 * blue 0:5) or XRGB8888 (32 bpp, red 16:8, green 8:8, blue 0:8, any alpha),
 * packed pixels, true or direct colour; or either with red and blue
 * exchanged (BGR565, XBGR8888), which sets *swap_rb. Anything else (24 bpp,
 * palettes, planar, FOURCC modes) is -EINVAL with why[] describing the
 * layout, e.g. "24 bits per pixel, red 16:8 green 8:8 blue 0:8".
 */
int psc_fbdev_format(const struct fb_var_screeninfo *var, const struct fb_fix_screeninfo *fix, psc_pixfmt_t *fmt,
                     bool *swap_rb, char *why, size_t whylen);

/**
 * Copy a width x height frame of fmt from src to dst (strides in bytes),
 * exchanging red and blue when swap_rb (green and the spare bits stay).
 */
void psc_fbdev_copy_frame(uint8_t *dst, uint32_t dst_stride, const uint8_t *src, uint32_t src_stride,
                          uint16_t width, uint16_t height, psc_pixfmt_t fmt, bool swap_rb);

/**
 * The mode to ask for with FBIOPUT_VSCREENINFO: cur with the resolution set
 * to width x height, a virtual screen of pages * height rows, offsets 0, and
 * the bit layout of fmt (RGB565 or XRGB8888). Timings are kept from cur.
 */
void psc_fbdev_request(const struct fb_var_screeninfo *cur, uint16_t width, uint16_t height, psc_pixfmt_t fmt,
                       uint8_t pages, struct fb_var_screeninfo *out);

/**
 * Plan buffering for the mode in force (var, fix) when the board wants
 * buffers (1..3). 0, or -EINVAL with why[] when the mode is unusable (format,
 * a line_length shorter than a row, less memory than one screen).
 */
int psc_fbdev_plan(const struct fb_var_screeninfo *var, const struct fb_fix_screeninfo *fix, uint8_t buffers,
                   psc_fbdev_plan_t *plan, char *why, size_t whylen);

/** Refresh rate in millihertz from the var timings; 0 when pixclock is 0. */
uint32_t psc_fbdev_refresh_mhz(const struct fb_var_screeninfo *var);

#endif
