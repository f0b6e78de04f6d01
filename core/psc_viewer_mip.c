/*
 * psc_viewer_mip.c - sampling the map pyramid (PSC_FILTER_MIP).
 *
 * Positions arrive in level-0 coordinates (integer = pixel centre); level k
 * has exactly half the pixels of level k-1 in each direction, so its
 * coordinate is (p + 1/2) / 2^k - 1/2: a shift. Each pixel is bilinear in the
 * two levels around the span's level of detail, blended by its fraction.
 */
#include "psc_viewer_internal.h"

/* Texel (r, c) of a level as XRGB8888. */
static PSC_ALWAYS_INLINE uint32_t level_texel(const psc_envmap_t *m, const uint8_t *row, int32_t c)
{
    if (m->format == PSC_PIX_RGB565)
        return psc_rgb565_to_xrgb(((const uint16_t *)(const void *)row)[c]);
    if (m->format == PSC_PIX_XRGB8888)
        return ((const uint32_t *)(const void *)row)[c];
    return m->palette[row[c]];
}

/* Bilinear sample of level k at level-0 position (row, col); columns wrap, rows clamp. */
static uint32_t level_bilinear(const psc_envmap_t *m, unsigned k, int32_t row, int32_t col)
{
    int32_t r = ((row + 32768) >> k) - 32768, c = ((col + 32768) >> k) - 32768;
    int32_t w = m->width, hmax = m->height - 1;
    if (c < 0)
        c += w << 16;
    int32_t r0 = r >> 16, c0 = c >> 16;
    uint32_t fr = ((uint32_t)r >> 8) & 255u, fc = ((uint32_t)c >> 8) & 255u;
    if (c0 >= w)
        c0 -= w;
    int32_t c1 = c0 + 1 == w ? 0 : c0 + 1, r1 = r0 + 1;
    if (r0 < 0) {
        r0 = r1 = 0;
        fr = 0;
    } else if (r0 >= hmax) {
        r0 = r1 = hmax;
    }
    const uint8_t *p0 = (const uint8_t *)m->pixels + (size_t)r0 * m->stride;
    const uint8_t *p1 = (const uint8_t *)m->pixels + (size_t)r1 * m->stride;
    return psc_blend4_xrgb(level_texel(m, p0, c0), level_texel(m, p0, c1), level_texel(m, p1, c0),
                           level_texel(m, p1, c1), fc, fr);
}

void psc_span_mip(const psc_frame_t *f, unsigned x, unsigned n, int32_t row, uint32_t t, int32_t drow, int32_t dt,
                  int32_t lod_q8)
{
    const psc_viewer_t *v = f->v;
    const uint32_t w = v->map->width;
    int32_t top = v->level_count - 1;
    int32_t level = lod_q8 < 0 ? 0 : lod_q8 >> 8;
    uint32_t frac = lod_q8 < 0 ? 0 : (uint32_t)lod_q8 & 255u;
    if (level >= top) {
        level = top;
        frac = 0;
    }
    const psc_envmap_t *fine = &v->levels[level], *coarse = &v->levels[level + (frac ? 1 : 0)];
    for (unsigned i = 0; i < n; i++) {
        int32_t col = (int32_t)(((uint64_t)t * w) >> 16) - 32768; /* level 0, Q16.16, may be -0.5 */
        uint32_t px = level_bilinear(fine, (unsigned)level, row, col);
        if (frac)
            px = psc_blend4_xrgb(px, level_bilinear(coarse, (unsigned)level + 1u, row, col), px, px, frac, 0);
        if (f->sink == PSC_SINK_RGB565)
            ((uint16_t *)(void *)f->dst)[x + i] = psc_xrgb_to_rgb565(px);
        else
            ((uint32_t *)(void *)f->dst)[x + i] = px | 0xFF000000u;
        row += drow;
        t += (uint32_t)dt;
    }
}
