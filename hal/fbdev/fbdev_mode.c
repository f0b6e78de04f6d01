/* SPDX-License-Identifier: MIT */
/*
 * fbdev_mode.c - format recognition, mode request and buffering plan of the
 * fbdev display (psc_fbdev_mode.h).
 */
#include <stdio.h>
#include <string.h>

#include "psc_fbdev_mode.h"
#include "psc_hal.h"

static int field_is(const struct fb_bitfield *f, uint32_t offset, uint32_t length)
{
    return f->offset == offset && f->length == length && f->msb_right == 0;
}

int psc_fbdev_format(const struct fb_var_screeninfo *var, const struct fb_fix_screeninfo *fix, psc_pixfmt_t *fmt,
                     bool *swap_rb, char *why, size_t whylen)
{
    *swap_rb = false;
    if (fix->type != FB_TYPE_PACKED_PIXELS ||
        (fix->visual != FB_VISUAL_TRUECOLOR && fix->visual != FB_VISUAL_DIRECTCOLOR)) {
        psc_hal_error_set(why, whylen, "framebuffer type %u visual %u: periscope draws packed true-colour pixels only",
                          (unsigned)fix->type, (unsigned)fix->visual);
        return -EINVAL;
    }
    if (var->grayscale > 1 || var->nonstd != 0) {
        psc_hal_error_set(why, whylen, "a FOURCC or non-standard pixel mode (grayscale %u, nonstd %u)",
                          (unsigned)var->grayscale, (unsigned)var->nonstd);
        return -EINVAL;
    }
    if (var->bits_per_pixel == 16 && field_is(&var->green, 5, 6) &&
        ((field_is(&var->red, 11, 5) && field_is(&var->blue, 0, 5)) ||
         (field_is(&var->red, 0, 5) && field_is(&var->blue, 11, 5)))) {
        *fmt = PSC_PIX_RGB565;
        *swap_rb = var->red.offset == 0;
        return 0;
    }
    if (var->bits_per_pixel == 32 && field_is(&var->green, 8, 8) &&
        ((field_is(&var->red, 16, 8) && field_is(&var->blue, 0, 8)) ||
         (field_is(&var->red, 0, 8) && field_is(&var->blue, 16, 8)))) {
        *fmt = PSC_PIX_XRGB8888;
        *swap_rb = var->red.offset == 0;
        return 0;
    }
    psc_hal_error_set(why, whylen, "%u bits per pixel, red %u:%u green %u:%u blue %u:%u (offset:length) is not a "
                      "layout periscope draws: it needs RGB565 (16 bpp, red 11:5 green 5:6 blue 0:5) or XRGB8888 "
                      "(32 bpp, red 16:8 green 8:8 blue 0:8), or either with red and blue exchanged",
                      (unsigned)var->bits_per_pixel, (unsigned)var->red.offset, (unsigned)var->red.length,
                      (unsigned)var->green.offset, (unsigned)var->green.length, (unsigned)var->blue.offset,
                      (unsigned)var->blue.length);
    return -EINVAL;
}

static void set_field(struct fb_bitfield *f, uint32_t offset, uint32_t length)
{
    f->offset = offset;
    f->length = length;
    f->msb_right = 0;
}

void psc_fbdev_request(const struct fb_var_screeninfo *cur, uint16_t width, uint16_t height, psc_pixfmt_t fmt,
                       uint8_t pages, struct fb_var_screeninfo *out)
{
    *out = *cur;
    out->xres = width;
    out->yres = height;
    out->xres_virtual = width;
    out->yres_virtual = (uint32_t)height * (pages ? pages : 1u);
    out->xoffset = 0;
    out->yoffset = 0;
    out->grayscale = 0;
    out->nonstd = 0;
    out->activate = FB_ACTIVATE_NOW;
    if (fmt == PSC_PIX_RGB565) {
        out->bits_per_pixel = 16;
        set_field(&out->red, 11, 5);
        set_field(&out->green, 5, 6);
        set_field(&out->blue, 0, 5);
        set_field(&out->transp, 0, 0);
    } else {
        out->bits_per_pixel = 32;
        set_field(&out->red, 16, 8);
        set_field(&out->green, 8, 8);
        set_field(&out->blue, 0, 8);
        set_field(&out->transp, 24, 0);
    }
}

uint32_t psc_fbdev_refresh_mhz(const struct fb_var_screeninfo *var)
{
    uint64_t htotal = (uint64_t)var->xres + var->left_margin + var->right_margin + var->hsync_len;
    uint64_t vtotal = (uint64_t)var->yres + var->upper_margin + var->lower_margin + var->vsync_len;
    uint64_t frame_ps = (uint64_t)var->pixclock * htotal * vtotal;

    if (var->pixclock == 0 || frame_ps == 0)
        return 0;
    /* 10^15 mHz*ps: frames per second = 10^12 / frame_ps; rounded to nearest */
    return (uint32_t)((1000000000000000ull + frame_ps / 2u) / frame_ps);
}

int psc_fbdev_plan(const struct fb_var_screeninfo *var, const struct fb_fix_screeninfo *fix, uint8_t buffers,
                   psc_fbdev_plan_t *plan, char *why, size_t whylen)
{
    uint64_t page;
    uint32_t pages_fit;
    int rc;

    memset(plan, 0, sizeof *plan);
    rc = psc_fbdev_format(var, fix, &plan->format, &plan->swap_rb, why, whylen);
    if (rc != 0)
        return rc;
    if (var->xres == 0 || var->yres == 0 || var->xres > PSC_MAX_OUT_DIM || var->yres > PSC_MAX_OUT_DIM) {
        psc_hal_error_set(why, whylen, "a %ux%u screen is outside 1x1..%ux%u", (unsigned)var->xres,
                          (unsigned)var->yres, PSC_MAX_OUT_DIM, PSC_MAX_OUT_DIM);
        return -EINVAL;
    }
    if (fix->line_length < var->xres * psc_pixfmt_bytes(plan->format)) {
        psc_hal_error_set(why, whylen, "line_length %u is shorter than a row of %u pixels",
                          (unsigned)fix->line_length, (unsigned)var->xres);
        return -EINVAL;
    }
    page = (uint64_t)fix->line_length * var->yres;
    if (fix->smem_len < page) {
        psc_hal_error_set(why, whylen, "the driver maps %u bytes, less than one %ux%u screen (%llu bytes)",
                          (unsigned)fix->smem_len, (unsigned)var->xres, (unsigned)var->yres,
                          (unsigned long long)page);
        return -EINVAL;
    }
    plan->stride = fix->line_length;
    plan->refresh_mhz = psc_fbdev_refresh_mhz(var);
    plan->pages = 1;
    if (buffers <= 1) {
        plan->buffering = PSC_FBDEV_DIRECT;
        return 0;
    }
    /* pages that fit both the virtual screen and the mapped memory, at
     * offsets the driver can pan to (multiples of ypanstep) */
    pages_fit = var->yres_virtual / var->yres;
    if ((uint64_t)pages_fit * page > fix->smem_len)
        pages_fit = (uint32_t)(fix->smem_len / page);
    if (fix->ypanstep == 0 || var->yres % fix->ypanstep != 0 || pages_fit < 2 || var->xoffset != 0) {
        plan->buffering = PSC_FBDEV_COPY;
        return 0;
    }
    plan->buffering = PSC_FBDEV_PAN;
    plan->pages = (uint8_t)(pages_fit < buffers ? pages_fit : buffers);
    return 0;
}

void psc_fbdev_copy_frame(uint8_t *dst, uint32_t dst_stride, const uint8_t *src, uint32_t src_stride,
                          uint16_t width, uint16_t height, psc_pixfmt_t fmt, bool swap_rb)
{
    size_t row = (size_t)width * psc_pixfmt_bytes(fmt);

    for (uint32_t y = 0; y < height; y++) {
        uint8_t *d = dst + (size_t)y * dst_stride;
        const uint8_t *s = src + (size_t)y * src_stride;

        if (!swap_rb) {
            memcpy(d, s, row);
        } else if (fmt == PSC_PIX_RGB565) {
            const uint16_t *sp = (const uint16_t *)(const void *)s;
            uint16_t *dp = (uint16_t *)(void *)d;
            for (uint32_t x = 0; x < width; x++) {
                uint32_t p = sp[x];
                dp[x] = (uint16_t)((p & 0x07E0u) | p >> 11 | (p & 0x1Fu) << 11);
            }
        } else {
            const uint32_t *sp = (const uint32_t *)(const void *)s;
            uint32_t *dp = (uint32_t *)(void *)d;
            for (uint32_t x = 0; x < width; x++) {
                uint32_t p = sp[x];
                dp[x] = (p & 0xFF00FF00u) | (p >> 16 & 0xFFu) | (p & 0xFFu) << 16;
            }
        }
    }
}
