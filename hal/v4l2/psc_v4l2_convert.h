/* SPDX-License-Identifier: MIT */
/*
 * psc_v4l2_convert.h - turning camera frames (YUYV 4:2:2 or Motion-JPEG)
 * into environment-map pixels (RGB565 or XRGB8888), resampled to the map's
 * size. Used by the V4L2 camera (v4l2_camera.c); public so that tests can
 * check every conversion without a camera.
 *
 * YUYV (V4L2_PIX_FMT_YUYV) is ITU-R BT.601 "studio swing" Y'CbCr, as UVC
 * cameras and vivid deliver it: Kr = 0.299, Kb = 0.114, Y' 16..235, Cb/Cr
 * 16..240 centred on 128. With E'Y = (Y - 16) / 219, E'Pb = (U - 128) / 224,
 * E'Pr = (V - 128) / 224 the exact values are
 *   R = 255 (E'Y + 2 (1 - Kr) E'Pr)
 *   B = 255 (E'Y + 2 (1 - Kb) E'Pb)
 *   G = 255 (E'Y - Kr R/255 - Kb B/255) / (1 - Kr - Kb)
 * Rounding (stated, and checked for all 2^24 inputs by tests/test_hal_v4l2.c):
 * each channel is the exact rational value rounded to the nearest integer,
 * halves upward, then clamped to 0..255 - computed without floating point
 * from integer numerators over the common denominator 219*224*500*587.
 * RGB565 output then rounds each 8-bit channel to 5/6/5 bits to nearest
 * (psc_xrgb_to_rgb565, the project's convention); XRGB8888 writes X = 0xFF.
 *
 * Motion-JPEG frames are decoded with libjpeg(-turbo) to 8-bit RGB (JFIF
 * full-range Y'CbCr, the library's own integer conversion), then stored with
 * the same RGB565 rounding. UVC cameras often omit the Huffman tables from
 * MJPEG frames; libjpeg-turbo then uses the standard tables of JPEG Annex K.3.
 *
 * Resampling: nearest. Map column x of a map W wide takes source column
 * floor((2x + 1) * srcW / (2W)), the source pixel under the map pixel's
 * centre; rows likewise. Equal sizes copy every pixel.
 */
#ifndef PSC_V4L2_CONVERT_H
#define PSC_V4L2_CONVERT_H

#include <stddef.h>
#include <stdint.h>
#include "base/psc_types.h"

/** Widest camera frame (source) accepted; the MJPEG row buffer is sized for it. */
#define PSC_V4L2_MAX_SRC_WIDTH 8192u
/** Tallest camera frame accepted. */
#define PSC_V4L2_MAX_SRC_HEIGHT 8192u

/** Where each map pixel comes from (nearest source row and column). */
typedef struct {
    uint16_t src_width, src_height;   /* the camera frame */
    uint16_t dst_width, dst_height;   /* the map */
    uint16_t *col;                    /* dst_width entries: source column of each map column */
    uint16_t *row;                    /* dst_height entries: source row of each map row */
} psc_v4l2_resample_t;

/**
 * Fill r->col and r->row (allocated by the caller for r->dst_width and
 * r->dst_height entries) for a src_width x src_height source. No allocation,
 * so a camera that comes back with another frame size is handled in the
 * frame loop. Sizes must be at least 1 (callers check).
 */
void psc_v4l2_resample_init(psc_v4l2_resample_t *r, uint16_t src_width, uint16_t src_height);

/**
 * The exact BT.601 studio-swing conversion of one Y'CbCr sample to 8-bit
 * R, G, B (see the header comment), returned as 0xFFRRGGBB.
 */
uint32_t psc_v4l2_yuv_to_xrgb(uint8_t y, uint8_t u, uint8_t v);

/**
 * Convert a YUYV frame (src, src_stride bytes per row, r->src_width x
 * r->src_height; the width even, as V4L2 requires for 4:2:2) into a map of r->dst_width x r->dst_height pixels of format
 * fmt (RGB565 or XRGB8888) at dst, dst_stride bytes per row.
 */
void psc_v4l2_convert_yuyv(const psc_v4l2_resample_t *r, const uint8_t *src, uint32_t src_stride, psc_pixfmt_t fmt,
                           uint8_t *dst, uint32_t dst_stride);

/**
 * Store one map row from a row of packed 8-bit RGB (3 bytes per source
 * pixel), picking source columns through r->col: the MJPEG path's last step.
 */
void psc_v4l2_store_rgb_row(const psc_v4l2_resample_t *r, const uint8_t *rgb, psc_pixfmt_t fmt, uint8_t *dst);

/** A Motion-JPEG decoder kept for the camera's lifetime (opaque). */
typedef struct psc_v4l2_mjpeg psc_v4l2_mjpeg_t;

/**
 * Create a decoder with a row buffer for frames up to PSC_V4L2_MAX_SRC_WIDTH
 * pixels wide. NULL when out of memory. (libjpeg keeps its own per-frame
 * memory pool: the one allocation in the camera's frame path we cannot avoid,
 * bounded by the frame size and freed at the end of every frame.)
 */
psc_v4l2_mjpeg_t *psc_v4l2_mjpeg_create(void);

/** Free a decoder (NULL is ignored). */
void psc_v4l2_mjpeg_destroy(psc_v4l2_mjpeg_t *m);

/**
 * Read the size of the JPEG frame jpeg[0..len) without decoding it. 0, or
 * -EINVAL with err saying what is wrong with the data.
 */
int psc_v4l2_mjpeg_size(psc_v4l2_mjpeg_t *m, const uint8_t *jpeg, size_t len, uint16_t *width, uint16_t *height,
                        char *err, size_t errlen);

/**
 * Decode jpeg[0..len) into the map at dst through r (whose source size must
 * be the frame's: psc_v4l2_mjpeg_size, then psc_v4l2_resample_init). 0, or
 * -EINVAL for corrupt or truncated data, a size other than r's, or a frame
 * wider than PSC_V4L2_MAX_SRC_WIDTH, with err saying which (the camera drops
 * such a frame and goes on). The map is fully written only on success.
 */
int psc_v4l2_mjpeg_decode(psc_v4l2_mjpeg_t *m, const psc_v4l2_resample_t *r, const uint8_t *jpeg, size_t len,
                          psc_pixfmt_t fmt, uint8_t *dst, uint32_t dst_stride, char *err, size_t errlen);

#endif
