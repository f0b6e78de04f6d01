/* SPDX-License-Identifier: MIT */
/*
 * psc_dither.c - threshold-matrix quantization (see psc_dither.h).
 */
#include "dither/psc_dither.h"

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
