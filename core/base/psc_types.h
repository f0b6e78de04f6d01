/* SPDX-License-Identifier: MIT */
/*
 * psc_types.h - types and conventions shared by every part of Periscope's core.
 *
 * Conventions (docs/viewer.md repeats them; code follows them exactly):
 *  - Angles are binary angles (psc_bam_t): 2^32 units = one full turn, so
 *    1 unit = 360/2^32 degrees and wrap-around at 360 degrees is free
 *    (unsigned overflow). Signed angles (pitch, latitude) use int32_t in the
 *    same unit: 2^30 = +90 degrees.
 *  - Yaw > 0 turns right (toward larger map columns), pitch > 0 looks up, no roll.
 *  - World axes: X right, Y up, Z ahead at yaw 0.
 *  - Longitude lon: angle about Y from +Z toward +X. Latitude lat: angle above
 *    the XZ plane.
 *  - Equirectangular W x H map: column c is longitude ((c+0.5)/W - 0.5)*360 deg,
 *    row r is latitude 90 - (r+0.5)/H*180 deg.
 *  - Fixed-point numbers name their format: Q16.16 is "_q16", an 8-bit
 *    fraction is "_q8". Every narrowing conversion rounds to nearest
 *    (ties away from zero for magnitudes, up for unsigned) unless its
 *    comment says otherwise.
 *
 * core/ is freestanding C11: no OS headers, no floating point, no allocation.
 */
#ifndef PSC_TYPES_H
#define PSC_TYPES_H

#include <stdint.h>
#include <stddef.h>
#include <stdbool.h>

/** Binary angle: 2^32 units per turn. */
typedef uint32_t psc_bam_t;

#define PSC_BAM_90  ((psc_bam_t)0x40000000u)
#define PSC_BAM_180 ((psc_bam_t)0x80000000u)
/** Binary angle from millidegrees (exact to 1 unit, rounded to nearest). */
#define PSC_BAM_FROM_MDEG(md) \
    ((psc_bam_t)(uint64_t)(((int64_t)(md) * 4294967296LL + ((md) >= 0 ? 180000 : -180000)) / 360000))

/** Result codes. Zero is success; every failure names its cause. */
typedef enum {
    PSC_OK = 0,
    PSC_ERR_ARG,        /* an argument is out of its documented range */
    PSC_ERR_TRUNCATED,  /* the data ends before a structure it announces */
    PSC_ERR_MAGIC,      /* not a Periscope file of the expected kind */
    PSC_ERR_VERSION,    /* a major version this build cannot read */
    PSC_ERR_CRC,        /* checksum mismatch: the data is corrupt */
    PSC_ERR_CORRUPT,    /* a field is inconsistent or out of range */
    PSC_ERR_TOO_LARGE,  /* a dimension exceeds the compiled-in limits */
    PSC_ERR_NOMEM,      /* the caller's buffer is smaller than required */
    PSC_ERR_UNSUPPORTED /* valid, but not handled by this build */
} psc_status_t;

/** Short English description of a status code (never NULL). */
const char *psc_status_str(psc_status_t s);

/** Pixel formats of environment maps and output surfaces. */
typedef enum {
    PSC_PIX_RGB565 = 1,   /* 16-bit, R in bits 15..11, little-endian in memory */
    PSC_PIX_XRGB8888 = 2, /* 32-bit word 0xXXRRGGBB, X ignored (written 0xFF) */
    PSC_PIX_PAL8 = 3,     /* 8-bit index into a 256-entry XRGB8888 palette (maps only) */
    PSC_PIX_RGB888 = 4    /* 24-bit, bytes B, G, R: the XRGB8888 word's low three (maps only); rows padded, see
                           * psc_pixfmt_row_bytes */
} psc_pixfmt_t;

/** Bytes per pixel of a format (0 for an unknown format). */
static inline uint32_t psc_pixfmt_bytes(psc_pixfmt_t f)
{
    return f == PSC_PIX_RGB565 ? 2u : f == PSC_PIX_XRGB8888 ? 4u : f == PSC_PIX_PAL8 ? 1u : f == PSC_PIX_RGB888 ? 3u : 0u;
}

/**
 * Bytes a row of w pixels takes in a map (w <= 2^24): w times the pixel's bytes, and for RGB888 at least one
 * spare byte more, rounded up to 4, so that a 32-bit load at any texel stays inside its row (the samplers read
 * a texel that way) and rows stay 4-byte aligned. A map's stride is at least this.
 */
static inline uint32_t psc_pixfmt_row_bytes(psc_pixfmt_t f, uint32_t w)
{
    return f == PSC_PIX_RGB888 ? (3u * w + 4u) & ~3u : w * psc_pixfmt_bytes(f);
}

/** A rectangle of pixels the caller owns: an output framebuffer or a view buffer. */
typedef struct {
    uint16_t width;
    uint16_t height;
    uint32_t stride;       /* bytes from one row to the next */
    psc_pixfmt_t format;   /* RGB565 or XRGB8888 for outputs */
    void *pixels;
} psc_surface_t;

/* Compiled-in limits: every buffer size is derived from these. */
#define PSC_MAX_OUT_DIM 4096u   /* output width/height */
#define PSC_MAX_MAP_DIM 16384u  /* environment map width/height */
#define PSC_MAX_LUT_DIM 2048u   /* LUT rows/cols */

#endif
