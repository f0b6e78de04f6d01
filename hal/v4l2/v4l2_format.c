/* SPDX-License-Identifier: MIT */
/*
 * v4l2_format.c - format choice, frame checks, option parsing and the
 * per-frame conversion dispatch of the V4L2 camera (v4l2_internal.h).
 */
#include <string.h>

#include <linux/videodev2.h>

#include "psc_hal.h"
#include "v4l2_internal.h"

uint32_t psc_v4l2_pick_format(uint32_t want, bool has_yuyv, bool has_mjpeg)
{
    if (want == V4L2_PIX_FMT_YUYV)
        return has_yuyv ? want : 0u;
    if (want == V4L2_PIX_FMT_MJPEG)
        return has_mjpeg ? want : 0u;
    return has_yuyv ? V4L2_PIX_FMT_YUYV : has_mjpeg ? V4L2_PIX_FMT_MJPEG : 0u;
}

int psc_v4l2_check_frame(uint32_t fourcc, uint32_t width, uint32_t height, uint32_t bytesperline, uint32_t field,
                         char *err, size_t errlen)
{
    if (width < 2 || height < 2 || width > PSC_V4L2_MAX_SRC_WIDTH || height > PSC_V4L2_MAX_SRC_HEIGHT) {
        psc_hal_error_set(err, errlen, "the driver chose %ux%u frames: outside 2x2..%ux%u", (unsigned)width,
                          (unsigned)height, PSC_V4L2_MAX_SRC_WIDTH, PSC_V4L2_MAX_SRC_HEIGHT);
        return -EINVAL;
    }
    if (field != V4L2_FIELD_NONE && field != V4L2_FIELD_ANY) {
        psc_hal_error_set(err, errlen, "the driver delivers interlaced fields (field order %u); periscope needs "
                          "whole progressive frames", (unsigned)field);
        return -EINVAL;
    }
    if (fourcc == V4L2_PIX_FMT_YUYV && (width % 2u != 0 || bytesperline < 2u * width)) {
        psc_hal_error_set(err, errlen, "YUYV frames of %ux%u with %u bytes per line: the width must be even and "
                          "a line at least %u bytes", (unsigned)width, (unsigned)height, (unsigned)bytesperline,
                          (unsigned)(2u * width));
        return -EINVAL;
    }
    return 0;
}

void psc_v4l2_fourcc_name(uint32_t fourcc, char out[5])
{
    for (unsigned i = 0; i < 4; i++) {
        char c = (char)((fourcc >> (8u * i)) & 0xFFu);
        out[i] = (c >= 32 && c < 127) ? c : '?';
    }
    out[4] = '\0';
}

int psc_v4l2_parse_pixel_format(const char *s, uint32_t *fourcc)
{
    if (s == NULL)
        return -EINVAL;
    if (strcmp(s, "auto") == 0)
        *fourcc = 0;
    else if (strcmp(s, "yuyv") == 0)
        *fourcc = V4L2_PIX_FMT_YUYV;
    else if (strcmp(s, "mjpeg") == 0)
        *fourcc = V4L2_PIX_FMT_MJPEG;
    else
        return -EINVAL;
    return 0;
}

/* Digits up to a terminator, value in 2..8192. */
static const char *parse_dim(const char *s, char end, uint16_t *out)
{
    uint32_t v = 0;
    const char *p = s;

    for (; *p >= '0' && *p <= '9'; p++) {
        v = v * 10u + (uint32_t)(*p - '0');
        if (v > PSC_V4L2_MAX_SRC_WIDTH)
            return NULL;
    }
    if (p == s || *p != end || v < 2)
        return NULL;
    *out = (uint16_t)v;
    return p;
}

int psc_v4l2_parse_size(const char *s, uint16_t *width, uint16_t *height)
{
    uint16_t w, h;
    const char *p;

    if (s == NULL || (p = parse_dim(s, 'x', &w)) == NULL || parse_dim(p + 1, '\0', &h) == NULL)
        return -EINVAL;
    *width = w;
    *height = h;
    return 0;
}

int psc_v4l2_convert_frame(uint32_t fourcc, const psc_v4l2_resample_t *r, psc_v4l2_mjpeg_t *m, const uint8_t *data,
                           size_t bytesused, uint32_t bytesperline, psc_pixfmt_t fmt, uint8_t *dst,
                           uint32_t dst_stride, char *err, size_t errlen)
{
    if (fourcc == V4L2_PIX_FMT_MJPEG)
        return psc_v4l2_mjpeg_decode(m, r, data, bytesused, fmt, dst, dst_stride, err, errlen);
    if (fourcc != V4L2_PIX_FMT_YUYV) {
        psc_hal_error_set(err, errlen, "unsupported pixel format 0x%08x", (unsigned)fourcc);
        return -EINVAL;
    }
    /* the last line need not be padded to bytesperline */
    if (bytesused < (size_t)bytesperline * (r->src_height - 1u) + 2u * (size_t)r->src_width) {
        psc_hal_error_set(err, errlen, "YUYV frame of %zu bytes is too short for %ux%u", bytesused,
                          (unsigned)r->src_width, (unsigned)r->src_height);
        return -EINVAL;
    }
    psc_v4l2_convert_yuyv(r, data, bytesperline, fmt, dst, dst_stride);
    return 0;
}
