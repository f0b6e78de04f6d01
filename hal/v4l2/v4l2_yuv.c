/* SPDX-License-Identifier: MIT */
/*
 * v4l2_yuv.c - exact integer BT.601 YUYV to RGB conversion and nearest
 * resampling (psc_v4l2_convert.h).
 *
 * Each channel is an integer numerator over one common denominator D, so the
 * exact rational value (not an approximation of it) is rounded. The
 * numerators stay below 2^43, so int64_t arithmetic cannot overflow; the
 * division by the constant D compiles to a multiply.
 */
#include "base/psc_pixel.h"
#include "psc_v4l2_convert.h"

/* D = 219 * 224 * 500 * 587: the denominators of E'Y (219), E'Pb/E'Pr (224),
 * 2(1-Kr) = 701/500 and 2(1-Kb) = 886/500, and Kg = 587/1000. */
#define YUV_D 14397936000LL
/* 255 * E'Y       = 255 (Y - 16) / 219                      -> * D */
#define YUV_KY (255LL * 224 * 500 * 587)
/* 255 * 1.402 E'Pr = 255 * 701 (V - 128) / (224 * 500)       -> * D */
#define YUV_KRV (255LL * 701 * 219 * 587)
/* 255 * 1.772 E'Pb = 255 * 886 (U - 128) / (224 * 500)       -> * D */
#define YUV_KBU (255LL * 886 * 219 * 587)
/* G = (E'Y - Kr R' - Kb B') / Kg, expanded: the Cb and Cr terms of G are
 * 1.772 * 0.114 / 0.587 E'Pb and 1.402 * 0.299 / 0.587 E'Pr. */
#define YUV_KGU (255LL * 886 * 114 * 219)
#define YUV_KGV (255LL * 701 * 299 * 219)

/* Round n / D to nearest, halves up, clamped to 0..255. */
static inline uint32_t yuv_channel(int64_t n)
{
    if (n <= 0)
        return 0;   /* values in (-0.5, 0] round to 0 as well */
    if (n >= 255 * YUV_D)
        return 255;
    return (uint32_t)((uint64_t)(n + YUV_D / 2) / (uint64_t)YUV_D);
}

/* Chroma part of the three numerators of one U, V pair. */
typedef struct {
    int64_t r, g, b;
} yuv_chroma_t;

static inline yuv_chroma_t yuv_chroma(uint8_t u, uint8_t v)
{
    int64_t cu = (int64_t)u - 128, cv = (int64_t)v - 128;

    return (yuv_chroma_t){ YUV_KRV * cv, -YUV_KGU * cu - YUV_KGV * cv, YUV_KBU * cu };
}

static inline uint32_t yuv_pixel(uint8_t y, yuv_chroma_t c)
{
    int64_t ny = YUV_KY * ((int64_t)y - 16);

    return 0xFF000000u | yuv_channel(ny + c.r) << 16 | yuv_channel(ny + c.g) << 8 | yuv_channel(ny + c.b);
}

uint32_t psc_v4l2_yuv_to_xrgb(uint8_t y, uint8_t u, uint8_t v)
{
    return yuv_pixel(y, yuv_chroma(u, v));
}

void psc_v4l2_resample_init(psc_v4l2_resample_t *r, uint16_t src_width, uint16_t src_height)
{
    r->src_width = src_width;
    r->src_height = src_height;
    for (uint32_t x = 0; x < r->dst_width; x++)
        r->col[x] = (uint16_t)(((2u * x + 1u) * (uint64_t)src_width) / (2u * (uint64_t)r->dst_width));
    for (uint32_t y = 0; y < r->dst_height; y++)
        r->row[y] = (uint16_t)(((2u * y + 1u) * (uint64_t)src_height) / (2u * (uint64_t)r->dst_height));
}

static inline void store_pixel(uint8_t *dst, uint32_t x, psc_pixfmt_t fmt, uint32_t xrgb)
{
    if (fmt == PSC_PIX_RGB565)
        ((uint16_t *)(void *)dst)[x] = psc_xrgb_to_rgb565(xrgb);
    else
        ((uint32_t *)(void *)dst)[x] = xrgb;
}

void psc_v4l2_convert_yuyv(const psc_v4l2_resample_t *r, const uint8_t *src, uint32_t src_stride, psc_pixfmt_t fmt,
                           uint8_t *dst, uint32_t dst_stride)
{
    bool same_width = r->src_width == r->dst_width;

    for (uint32_t y = 0; y < r->dst_height; y++) {
        const uint8_t *s = src + (size_t)r->row[y] * src_stride;
        uint8_t *d = dst + (size_t)y * dst_stride;

        if (same_width) {
            /* the common case: two pixels per U/V pair, chroma computed once */
            for (uint32_t x = 0; x + 1u < r->dst_width; x += 2u) {
                const uint8_t *q = s + 2u * x;
                yuv_chroma_t c = yuv_chroma(q[1], q[3]);
                store_pixel(d, x, fmt, yuv_pixel(q[0], c));
                store_pixel(d, x + 1u, fmt, yuv_pixel(q[2], c));
            }
            continue;
        }
        for (uint32_t x = 0; x < r->dst_width; x++) {
            uint32_t sx = r->col[x];
            const uint8_t *pair = s + 4u * (sx >> 1);
            store_pixel(d, x, fmt, yuv_pixel(s[2u * sx], yuv_chroma(pair[1], pair[3])));
        }
    }
}

void psc_v4l2_store_rgb_row(const psc_v4l2_resample_t *r, const uint8_t *rgb, psc_pixfmt_t fmt, uint8_t *dst)
{
    for (uint32_t x = 0; x < r->dst_width; x++) {
        const uint8_t *p = rgb + 3u * r->col[x];
        store_pixel(dst, x, fmt, 0xFF000000u | (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2]);
    }
}
