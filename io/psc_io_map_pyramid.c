/* SPDX-License-Identifier: MIT */
/* psc_io_map_pyramid.c - filtered halving of environment maps (psc_io_map_pyramid.h). */
#include "psc_io_map_pyramid.h"

#include <stdlib.h>

static const unsigned taps[4] = {1, 3, 3, 1}; /* sum 8 */

static uint32_t wrap_or_clamp(int64_t i, uint32_t n, bool wrap)
{
    if (wrap)
        return (uint32_t)((i % n + n) % n);
    return i < 0 ? 0 : i >= n ? n - 1 : (uint32_t)i;
}

/* One filtered pass along rows (horizontal) from src (sw x h) to dst (sw/2 x h), channels kept x8. */
static void halve_rows(const uint32_t *src, uint32_t sw, uint32_t h, bool wrap, uint32_t *dst_sum)
{
    uint32_t dw = sw / 2;
    for (uint32_t y = 0; y < h; y++) {
        const uint32_t *s = src + (size_t)y * sw;
        for (uint32_t x = 0; x < dw; x++) {
            uint32_t r = 0, g = 0, b = 0;
            for (unsigned k = 0; k < 4; k++) {
                uint32_t p = s[wrap_or_clamp((int64_t)2 * x - 1 + k, sw, wrap)];
                r += taps[k] * ((p >> 16) & 255u);
                g += taps[k] * ((p >> 8) & 255u);
                b += taps[k] * (p & 255u);
            }
            /* channel sums up to 255 * 8, kept apart until the vertical pass */
            dst_sum[((size_t)y * dw + x) * 3 + 0] = r;
            dst_sum[((size_t)y * dw + x) * 3 + 1] = g;
            dst_sum[((size_t)y * dw + x) * 3 + 2] = b;
        }
    }
}

int psc_io_image_halve(const psc_image_t *in, bool wrap_columns, psc_image_t *out)
{
    if (!in || !out || in->width % 2 || in->height % 2 || in->width == 0 || in->height == 0)
        return -1;
    uint32_t dw = in->width / 2, dh = in->height / 2;
    uint32_t *sum = malloc((size_t)dw * in->height * 3 * sizeof *sum);
    uint32_t *px = malloc((size_t)dw * dh * sizeof *px);
    if (!sum || !px) {
        free(sum);
        free(px);
        return -1;
    }
    halve_rows(in->xrgb, in->width, in->height, wrap_columns, sum);
    for (uint32_t y = 0; y < dh; y++) {
        for (uint32_t x = 0; x < dw; x++) {
            uint32_t c[3] = {0, 0, 0};
            for (unsigned k = 0; k < 4; k++) {
                uint32_t sy = wrap_or_clamp((int64_t)2 * y - 1 + k, in->height, false);
                for (unsigned ch = 0; ch < 3; ch++)
                    c[ch] += taps[k] * sum[((size_t)sy * dw + x) * 3 + ch];
            }
            /* weights total 64: round to nearest */
            px[(size_t)y * dw + x] = 0xFF000000u | (((c[0] + 32) / 64) << 16) | (((c[1] + 32) / 64) << 8) |
                                     ((c[2] + 32) / 64);
        }
    }
    free(sum);
    out->width = dw;
    out->height = dh;
    out->xrgb = px;
    return 0;
}

unsigned psc_io_pyramid_levels(uint32_t w, uint32_t h, unsigned max_levels)
{
    unsigned n = 1;
    while (n < max_levels && w % 2 == 0 && h % 2 == 0 && w / 2 >= PSC_PYRAMID_MIN_SIDE &&
           h / 2 >= PSC_PYRAMID_MIN_SIDE) {
        w /= 2;
        h /= 2;
        n++;
    }
    return n;
}
