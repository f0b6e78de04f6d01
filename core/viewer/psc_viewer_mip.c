/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_mip.c - sampling the map pyramid (PSC_FILTER_MIP).
 *
 * Positions arrive as the level-0 row (Q16.16, integer = pixel centre) and
 * the longitude t from the map's left edge (binary angle). Level k has
 * exactly half the pixels of level k-1 each way, so its row is
 * (row + 1/2) / 2^k - 1/2 (a shift) and its column t * W_k / 2^32 - 1/2.
 * Each pixel is bilinear in the two levels around the span's level of
 * detail, blended by its fraction; like the other fast spans, one loop per
 * map format and output format, RGB565 to RGB565 through the packed blend.
 */
#include "viewer/psc_viewer_internal.h"

static PSC_ALWAYS_INLINE uint32_t texel(const uint8_t *row, uint32_t c, const psc_pixfmt_t in, const uint32_t *pal)
{
    if (in == PSC_PIX_RGB565)
        return ((const uint16_t *)(const void *)row)[c]; /* raw: blended packed or expanded by the caller */
    if (in == PSC_PIX_XRGB8888)
        return ((const uint32_t *)(const void *)row)[c];
    if (in == PSC_PIX_RGB888)
        return psc_rgb888_at(row, c);
    return pal[row[c]];
}

/*
 * Bilinear sample of level k: RGB565 when the map and the output both are,
 * else XRGB8888. Columns wrap, rows clamp.
 */
static PSC_ALWAYS_INLINE uint32_t level_sample(const psc_viewer_t *v, unsigned k, int32_t row, uint32_t t,
                                               const psc_pixfmt_t in, const bool packed565, const bool pow2)
{
    const psc_envmap_t *m = &v->levels[k];
    int32_t r = ((row + 32768) >> k) - 32768, hmax = m->height - 1;
    int32_t r0 = r >> 16, r1 = r0 + 1;
    uint32_t fr = ((uint32_t)r >> 8) & 255u;
    r0 = r0 < 0 ? 0 : r0;
    r1 = r1 > hmax ? hmax : r1;
    const uint32_t w = m->width;
    uint32_t tk = t - (v->half_col_bam << k); /* half a level-k column */
    uint32_t c0, fc;
    if (pow2) {
        unsigned s = v->col_shift + k;
        c0 = tk >> s;
        fc = tk << (32u - s) >> 24;
    } else {
        uint64_t q = (uint64_t)tk * w;
        c0 = (uint32_t)(q >> 32);
        fc = (uint32_t)(q >> 24) & 255u;
    }
    uint32_t c1 = c0 + 1u == w ? 0u : c0 + 1u;
    const uint8_t *p0 = (const uint8_t *)m->pixels + (size_t)r0 * m->stride;
    const uint8_t *p1 = (const uint8_t *)m->pixels + (size_t)r1 * m->stride;
    uint32_t a = texel(p0, c0, in, m->palette), b = texel(p0, c1, in, m->palette);
    uint32_t c = texel(p1, c0, in, m->palette), d = texel(p1, c1, in, m->palette);
    if (packed565)
        return psc_blend4_rgb565(a, b, c, d, (fc + 4u) >> 3, (fr + 4u) >> 3);
    if (in == PSC_PIX_RGB565) {
        a = psc_rgb565_to_xrgb(a);
        b = psc_rgb565_to_xrgb(b);
        c = psc_rgb565_to_xrgb(c);
        d = psc_rgb565_to_xrgb(d);
    }
    return psc_blend4_xrgb(a, b, c, d, fc, fr);
}

static PSC_ALWAYS_INLINE void span_mip(const psc_frame_t *f, unsigned x, unsigned n, int32_t row, uint32_t t,
                                       int32_t drow, int32_t dt, unsigned level, uint32_t frac,
                                       const psc_pixfmt_t in, const psc_sink_t sink, const bool pow2)
{
    const psc_viewer_t *v = f->v;
    const bool packed565 = in == PSC_PIX_RGB565 && sink == PSC_SINK_RGB565;
    for (unsigned i = 0; i < n; i++) {
        uint32_t px = level_sample(v, level, row, t, in, packed565, pow2);
        if (frac) {
            uint32_t q = level_sample(v, level + 1u, row, t, in, packed565, pow2);
            px = packed565 ? psc_blend4_rgb565(px, q, px, q, (frac + 4u) >> 3, 0)
                           : psc_blend4_xrgb(px, q, px, q, frac, 0);
        }
        if (sink == PSC_SINK_RGB565)
            ((uint16_t *)(void *)f->dst)[x + i] = (uint16_t)(packed565 ? px : psc_xrgb_to_rgb565(px));
        else
            ((uint32_t *)(void *)f->dst)[x + i] = px | 0xFF000000u;
        row += drow;
        t += (uint32_t)dt;
    }
}

#define MIP_SPAN(in, sink) \
    (pow2 ? span_mip(f, x, n, row, t, drow, dt, level, frac, in, sink, true) \
          : span_mip(f, x, n, row, t, drow, dt, level, frac, in, sink, false))
#define MIP_FOR_FORMAT(in) \
    do { \
        if (to565) \
            MIP_SPAN(in, PSC_SINK_RGB565); \
        else \
            MIP_SPAN(in, PSC_SINK_XRGB8888); \
    } while (0)

void psc_span_mip(const psc_frame_t *f, unsigned x, unsigned n, int32_t row, uint32_t t, int32_t drow, int32_t dt,
                  int32_t lod_q8)
{
    const psc_viewer_t *v = f->v;
    unsigned top = v->level_count - 1u;
    unsigned level = lod_q8 < 0 ? 0u : (unsigned)lod_q8 >> 8;
    uint32_t frac = lod_q8 < 0 ? 0u : (uint32_t)lod_q8 & 255u;
    if (level >= top) {
        level = top;
        frac = 0;
    }
    const bool pow2 = v->col_shift != 0, to565 = f->sink == PSC_SINK_RGB565;
    switch (v->map->format) {
    case PSC_PIX_RGB565: MIP_FOR_FORMAT(PSC_PIX_RGB565); break;
    case PSC_PIX_XRGB8888: MIP_FOR_FORMAT(PSC_PIX_XRGB8888); break;
    case PSC_PIX_PAL8: MIP_FOR_FORMAT(PSC_PIX_PAL8); break;
    case PSC_PIX_RGB888: MIP_FOR_FORMAT(PSC_PIX_RGB888); break;
    }
}
