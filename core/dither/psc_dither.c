/* SPDX-License-Identifier: MIT */
/*
 * psc_dither.c - threshold-matrix quantization (see psc_dither.h).
 */
#include "dither/psc_dither.h"
#include "base/psc_pixel.h"

/* 8 x 8 Bayer: each 2 x 2 refinement puts the next four thresholds as far apart as it can. */
static const uint8_t bayer8[8][8] = {
    {0, 32, 8, 40, 2, 34, 10, 42},   {48, 16, 56, 24, 50, 18, 58, 26}, {12, 44, 4, 36, 14, 46, 6, 38},
    {60, 28, 52, 20, 62, 30, 54, 22}, {3, 35, 11, 43, 1, 33, 9, 41},   {51, 19, 59, 27, 49, 17, 57, 25},
    {15, 47, 7, 39, 13, 45, 5, 37},   {63, 31, 55, 23, 61, 29, 53, 21},
};

/* 4 x 4 clustered dot: the dots turn on from the cell's centre outwards. */
static const uint8_t cluster4[4][4] = {
    {12, 5, 6, 13},
    {4, 0, 1, 7},
    {11, 3, 2, 8},
    {15, 10, 9, 14},
};

#define CUBE_R 6u
#define CUBE_G 7u
#define CUBE_B 6u

/* A method's threshold at (x, y) as (2 T + 1) and the matrix size M^2; none: the middle. */
typedef struct {
    uint32_t twice_t_plus_1, cells;
} threshold_t;

static threshold_t threshold_at(psc_dither_method_t m, unsigned x, unsigned y)
{
    threshold_t t = {1u, 1u}; /* T = 0 of 1: round to nearest */
    if (m == PSC_DITHER_ORDERED)
        t = (threshold_t){2u * bayer8[y & 7u][x & 7u] + 1u, 64u};
    else if (m == PSC_DITHER_HALFTONE)
        t = (threshold_t){2u * cluster4[y & 3u][x & 3u] + 1u, 16u};
    return t;
}

/*
 * floor(v (L - 1) / 255 + (T + 1/2) / M^2) as
 * (2 v (L - 1) M^2 + (2 T + 1) 255) / (510 M^2): below 2^32 for v <= 255,
 * L <= 16, M^2 <= 64. At most L - 1: (2 T + 1) 255 < 510 M^2.
 */
static uint32_t quantize(uint32_t v, uint32_t levels, threshold_t t)
{
    return (2u * v * (levels - 1u) * t.cells + t.twice_t_plus_1 * 255u) / (510u * t.cells);
}

static uint32_t luma(uint32_t px)
{
    return (77u * ((px >> 16) & 255u) + 150u * ((px >> 8) & 255u) + 29u * (px & 255u) + 128u) >> 8;
}

size_t psc_dither_row_bytes(psc_dither_target_t target, unsigned n)
{
    switch (target) {
    case PSC_DITHER_MONO: return ((size_t)n + 7u) / 8u;
    case PSC_DITHER_GREY4: return ((size_t)n + 1u) / 2u;
    case PSC_DITHER_PAL8: break;
    }
    return n;
}

void psc_dither_row(psc_dither_target_t target, psc_dither_method_t method, const uint32_t *src, unsigned n,
                    unsigned y, uint8_t *dst)
{
    size_t bytes = psc_dither_row_bytes(target, n);
    for (size_t i = 0; i < bytes; i++)
        dst[i] = 0;
    for (unsigned x = 0; x < n; x++) {
        threshold_t t = threshold_at(method, x, y);
        uint32_t px = src[x];
        switch (target) {
        case PSC_DITHER_MONO:
            dst[x >> 3] |= (uint8_t)(quantize(luma(px), 2u, t) << (7u - (x & 7u)));
            break;
        case PSC_DITHER_GREY4:
            dst[x >> 1] |= (uint8_t)(quantize(luma(px), 16u, t) << (x & 1u ? 0u : 4u));
            break;
        case PSC_DITHER_PAL8: {
            uint32_t r = quantize((px >> 16) & 255u, CUBE_R, t), g = quantize((px >> 8) & 255u, CUBE_G, t);
            uint32_t b = quantize(px & 255u, CUBE_B, t);
            dst[x] = (uint8_t)(r * CUBE_G * CUBE_B + g * CUBE_B + b);
            break;
        }
        }
    }
}

uint32_t psc_dither_get(psc_dither_target_t target, const uint8_t *row, unsigned x)
{
    switch (target) {
    case PSC_DITHER_MONO: return (row[x >> 3] >> (7u - (x & 7u))) & 1u;
    case PSC_DITHER_GREY4: return (row[x >> 1] >> (x & 1u ? 0u : 4u)) & 15u;
    case PSC_DITHER_PAL8: break;
    }
    return row[x];
}

/* Level q of L as 8 bits, rounded. */
static uint32_t level8(uint32_t q, uint32_t levels)
{
    return (q * 510u + (levels - 1u)) / (2u * (levels - 1u));
}

uint32_t psc_dither_level_xrgb(psc_dither_target_t target, uint32_t v)
{
    uint32_t r, g, b;
    switch (target) {
    case PSC_DITHER_MONO: r = g = b = v ? 255u : 0u; break;
    case PSC_DITHER_GREY4: r = g = b = level8(v & 15u, 16u); break;
    default:
        if (v >= CUBE_R * CUBE_G * CUBE_B)
            v = 0; /* the four entries beyond the cube show black */
        r = level8(v / (CUBE_G * CUBE_B), CUBE_R);
        g = level8(v / CUBE_B % CUBE_G, CUBE_G);
        b = level8(v % CUBE_B, CUBE_B);
        break;
    }
    return 0xFF000000u | r << 16 | g << 8 | b;
}

/* ---- RGB565 ---------------------------------------------------------------------------------------------- */

/* One channel's table: bits wide (5 or 6), levels shown by bit replication. */
static void dither_565_channel(uint16_t *tab, unsigned bits)
{
    uint32_t top = (1u << bits) - 1u, k = 0;
    for (uint32_t v = 0; v < 256u; v++) {
        while (k < top && ((k + 1u) << (8u - bits) | (k + 1u) >> (2u * bits - 8u)) <= v)
            k++;
        uint32_t e0 = k << (8u - bits) | k >> (2u * bits - 8u), c = 0;
        if (k < top) {
            uint32_t d = ((k + 1u) << (8u - bits) | (k + 1u) >> (2u * bits - 8u)) - e0;
            c = (128u * (v - e0) + d - 1u) / (2u * d);
        }
        tab[v] = (uint16_t)(k << 8 | c);
    }
}

void psc_dither_565_init(psc_dither_565_t *t)
{
    dither_565_channel(t->ch5, 5u);
    dither_565_channel(t->ch6, 6u);
}

static PSC_ALWAYS_INLINE uint16_t dither_565_pixel(const psc_dither_565_t *t, uint32_t p, uint32_t bias)
{
    uint32_t r = (t->ch5[(p >> 16) & 255u] + bias) >> 8, g = (t->ch6[(p >> 8) & 255u] + bias) >> 8;
    uint32_t b = (t->ch5[p & 255u] + bias) >> 8;
    return (uint16_t)(r << 11 | g << 5 | b);
}

void psc_dither_row_rgb565(const psc_dither_565_t *t, psc_dither_method_t method, const uint32_t *src, unsigned n,
                           unsigned x0, unsigned y, uint16_t *dst)
{
    if (method == PSC_DITHER_NONE) {
        for (unsigned x = 0; x < n; x++)
            dst[x] = psc_xrgb_to_rgb565(src[x]);
        return;
    }
    /* (k << 8 | c) + 255 - T carries into k exactly when c > T: one add and one shift a channel */
    uint32_t bias[8];
    for (unsigned i = 0; i < 8u; i++)
        bias[i] = 255u - bayer8[y & 7u][(x0 + i) & 7u];
    for (unsigned x = 0; x < n; x++)
        dst[x] = dither_565_pixel(t, src[x], bias[x & 7u]);
}
