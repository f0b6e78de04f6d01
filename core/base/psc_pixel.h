/* SPDX-License-Identifier: MIT */
/*
 * psc_pixel.h - pixel conversions and blends shared by the samplers.
 *
 * RGB565 -> 8 bits per channel by bit replication (r8 = r5<<3 | r5>>2,
 * g8 = g6<<2 | g6>>4): 0 and full scale map exactly to 0 and 255.
 * 8 bits -> RGB565 rounds to nearest: r5 = round(r8*31/255), g6 = round(g8*63/255),
 * done with exact multiply-shift forms (checked for all 256 inputs in tests).
 */
#ifndef PSC_PIXEL_H
#define PSC_PIXEL_H

#include "base/psc_types.h"

#if defined(__GNUC__) || defined(__clang__)
#define PSC_ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define PSC_ALWAYS_INLINE inline
#endif

static PSC_ALWAYS_INLINE uint32_t psc_rgb565_to_xrgb(uint32_t p)
{
    uint32_t r = (p >> 11) & 31u, g = (p >> 5) & 63u, b = p & 31u;
    r = (r << 3) | (r >> 2);
    g = (g << 2) | (g >> 4);
    b = (b << 3) | (b >> 2);
    return 0xFF000000u | (r << 16) | (g << 8) | b;
}

/*
 * Texel c of an RGB888 row as XRGB8888 with X = 0: one 32-bit load (the row's spare byte keeps it inside,
 * psc_pixfmt_row_bytes), its fourth byte dropped. Little-endian, as every pack is.
 */
static PSC_ALWAYS_INLINE uint32_t psc_rgb888_at(const uint8_t *row, uint32_t c)
{
    uint32_t w;
    __builtin_memcpy(&w, row + 3u * c, sizeof w);
    return w & 0xFFFFFFu;
}

static PSC_ALWAYS_INLINE uint16_t psc_xrgb_to_rgb565(uint32_t p)
{
    uint32_t r = (p >> 16) & 255u, g = (p >> 8) & 255u, b = p & 255u;
    r = (r * 249u + 1014u) >> 11; /* == round(r * 31 / 255) for r in 0..255 */
    g = (g * 253u + 505u) >> 10;  /* == round(g * 63 / 255) */
    b = (b * 249u + 1014u) >> 11;
    return (uint16_t)((r << 11) | (g << 5) | b);
}

/*
 * Bilinear blend of four XRGB8888 texels, weights Q0.8 (fx, fy in 0..256):
 * top = p00*(256-fx) + p01*fx, bottom likewise, out = (top*(256-fy) + bottom*fy
 * + 2^15) >> 16 per channel: rounded to nearest. Red and blue share one
 * 32-bit lane pair in the first stage (each lane stays below 2^16).
 */
static PSC_ALWAYS_INLINE uint32_t psc_blend4_xrgb(uint32_t p00, uint32_t p01, uint32_t p10, uint32_t p11,
                                                  uint32_t fx, uint32_t fy)
{
    uint32_t ix = 256u - fx, iy = 256u - fy;
    uint32_t rb0 = (p00 & 0xFF00FFu) * ix + (p01 & 0xFF00FFu) * fx; /* lanes < 2^16 */
    uint32_t rb1 = (p10 & 0xFF00FFu) * ix + (p11 & 0xFF00FFu) * fx;
    uint32_t g0 = ((p00 >> 8) & 0xFFu) * ix + ((p01 >> 8) & 0xFFu) * fx;
    uint32_t g1 = ((p10 >> 8) & 0xFFu) * ix + ((p11 >> 8) & 0xFFu) * fx;
    uint32_t r = (((rb0 >> 16) & 0xFFFFu) * iy + ((rb1 >> 16) & 0xFFFFu) * fy + 32768u) >> 16;
    uint32_t b = ((rb0 & 0xFFFFu) * iy + (rb1 & 0xFFFFu) * fy + 32768u) >> 16;
    uint32_t g = (g0 * iy + g1 * fy + 32768u) >> 16;
    return 0xFF000000u | (r << 16) | (g << 8) | b;
}

/*
 * RGB565 spread so that each channel has five spare bits above it:
 * green in bits 21..26, red in 11..15, blue in 0..4. Multiplying by a
 * weight of at most 32 cannot carry from one channel into the next.
 */
#define PSC_RGB565_SPREAD_MASK 0x07E0F81Fu
static PSC_ALWAYS_INLINE uint32_t psc_rgb565_spread(uint32_t p)
{
    return (p | (p << 16)) & PSC_RGB565_SPREAD_MASK;
}

/*
 * Bilinear blend of four RGB565 texels in RGB565, weights Q0.5 (fx, fy in
 * 0..32): horizontal then vertical, each stage rounded to nearest. Used for
 * RGB565 maps drawn to RGB565 outputs, where the 8-bit path's precision would
 * be lost in the final RGB565 rounding anyway.
 */
static PSC_ALWAYS_INLINE uint32_t psc_blend4_rgb565(uint32_t p00, uint32_t p01, uint32_t p10, uint32_t p11,
                                                    uint32_t fx, uint32_t fy)
{
    const uint32_t half = 0x02008010u; /* 16 in each channel's lowest bit position */
    uint32_t ix = 32u - fx;
    uint32_t top = ((psc_rgb565_spread(p00) * ix + psc_rgb565_spread(p01) * fx + half) >> 5) & PSC_RGB565_SPREAD_MASK;
    uint32_t bot = ((psc_rgb565_spread(p10) * ix + psc_rgb565_spread(p11) * fx + half) >> 5) & PSC_RGB565_SPREAD_MASK;
    uint32_t v = ((top * (32u - fy) + bot * fy + half) >> 5) & PSC_RGB565_SPREAD_MASK;
    return (v | (v >> 16)) & 0xFFFFu;
}

#endif
