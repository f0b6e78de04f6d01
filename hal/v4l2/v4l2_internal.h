/* SPDX-License-Identifier: MIT */
/*
 * v4l2_internal.h - the V4L2 camera's decisions that need no device (format
 * choice, frame checks, option parsing, frame conversion dispatch), apart
 * from the ioctl code so tests can drive them with made-up values.
 */
#ifndef PSC_V4L2_INTERNAL_H
#define PSC_V4L2_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <stdbool.h>

#include "psc_v4l2_convert.h"

/**
 * The pixel format to use: want (V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG, or 0
 * for auto: YUYV first, since it needs no decoding, then MJPEG) if offered,
 * else 0.
 */
uint32_t psc_v4l2_pick_format(uint32_t want, bool has_yuyv, bool has_mjpeg);

/**
 * Check a negotiated frame: size 2x2..PSC_V4L2_MAX_SRC_*, even width for
 * YUYV, bytesperline >= 2 * width for YUYV, progressive or field-merged
 * (V4L2_FIELD_NONE / ANY). 0, or -EINVAL with err naming the problem.
 */
int psc_v4l2_check_frame(uint32_t fourcc, uint32_t width, uint32_t height, uint32_t bytesperline, uint32_t field,
                         char *err, size_t errlen);

/** "auto" -> 0, "yuyv" -> V4L2_PIX_FMT_YUYV, "mjpeg" -> V4L2_PIX_FMT_MJPEG. 0 or -EINVAL. */
int psc_v4l2_parse_pixel_format(const char *s, uint32_t *fourcc);

/** "WxH" with both in 2..8192 (digits only). 0 or -EINVAL. */
int psc_v4l2_parse_size(const char *s, uint16_t *width, uint16_t *height);

/** The four characters of a fourcc ("YUYV", "MJPG"), unprintable bytes as '?'. */
void psc_v4l2_fourcc_name(uint32_t fourcc, char out[5]);

/**
 * Convert one captured frame (data[0..bytesused)) into the map at dst through
 * r: YUYV rows of bytesperline bytes, or one MJPEG image (decoded with m).
 * 0, or -EINVAL with err saying why the frame is unusable (too short for its
 * size, corrupt JPEG): the caller drops it.
 */
int psc_v4l2_convert_frame(uint32_t fourcc, const psc_v4l2_resample_t *r, psc_v4l2_mjpeg_t *m, const uint8_t *data,
                           size_t bytesused, uint32_t bytesperline, psc_pixfmt_t fmt, uint8_t *dst,
                           uint32_t dst_stride, char *err, size_t errlen);

#endif
