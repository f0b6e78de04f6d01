/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_sample.c - the general sampler: any projection, partial maps,
 * one pixel at a time. Columns wrap around a full turn (within the row's own
 * width on ELLIPTICAL/DIAMOND maps) and clamp at the edges of partial maps;
 * rows clamp at the top and bottom. Never reads outside the map. A partial
 * map of rectangular rows has its own (psc_sample_partial): its fast spans'
 * columns, so that the spans near its edges, drawn here, join theirs.
 */
#include "viewer/psc_viewer_internal.h"

static uint32_t texel(const psc_envmap_t *m, int32_t r, int32_t c)
{
    const uint8_t *row = (const uint8_t *)m->pixels + (size_t)r * m->stride;
    switch (m->format) {
    case PSC_PIX_RGB565: return psc_rgb565_to_xrgb(((const uint16_t *)(const void *)row)[c]);
    case PSC_PIX_XRGB8888: return ((const uint32_t *)(const void *)row)[c] | 0xFF000000u;
    case PSC_PIX_PAL8: return m->palette[row[c]] | 0xFF000000u;
    case PSC_PIX_RGB888: return psc_rgb888_at(row, (uint32_t)c) | 0xFF000000u;
    }
    return 0xFF000000u;
}

/* Valid pixel range [*lo, *hi] of map row r and the row's column of full-width column col. */
static int32_t row_column(const psc_viewer_t *v, int32_t r, int32_t col, int32_t *lo, int32_t *hi)
{
    const psc_envmap_t *m = v->map;
    int32_t w = m->width;
    if (!v->row_width_q16) {
        *lo = 0;
        *hi = w - 1;
        return col;
    }
    /* The row's pixels are centred: col_r = W/2 - 0.5 + (col + 0.5 - W/2) * width_r. */
    int64_t f = v->row_width_q16[r];
    int64_t half_w = (int64_t)w << 15;
    int32_t col_r = (int32_t)(half_w - 32768 + (((int64_t)col + 32768 - half_w) * f >> 16));
    int64_t half_row = ((int64_t)w * f) >> 1;          /* half the row's width, Q16.16 */
    int32_t left = (int32_t)(half_w - half_row - 32768); /* the row's left edge, Q16.16 */
    int32_t right = (int32_t)(half_w + half_row - 32768);
    *lo = (left + 65535) >> 16; /* first pixel centre inside */
    *hi = right >> 16;
    if (*hi < *lo) /* rows narrower than a pixel keep their middle pixel */
        *lo = *hi = (w - 1) / 2;
    return col_r;
}

static int32_t clamp_i32(int32_t x, int32_t lo, int32_t hi) { return x < lo ? lo : x > hi ? hi : x; }

/* Wrap (full turn) or clamp (partial map) a pixel column into [lo, hi]. */
static int32_t fix_column(const psc_viewer_t *v, int32_t c, int32_t lo, int32_t hi)
{
    if (v->addr.wraps) {
        int32_t n = hi - lo + 1;
        if (c < lo)
            c += n * ((lo - c + n - 1) / n);
        else if (c > hi)
            c -= n * ((c - hi + n - 1) / n);
        return c;
    }
    return clamp_i32(c, lo, hi);
}

static uint32_t lerp_xrgb(uint32_t a, uint32_t b, uint32_t f)
{
    return psc_blend4_xrgb(a, b, a, b, f, 0);
}

/* Horizontal bilinear sample of map row r at full-width column col. */
static uint32_t sample_row(const psc_viewer_t *v, int32_t r, int32_t col)
{
    int32_t lo, hi;
    int32_t cr = row_column(v, r, col, &lo, &hi);
    int32_t c0 = cr >> 16;
    uint32_t fc = ((uint32_t)cr >> 8) & 255u;
    int32_t a = fix_column(v, c0, lo, hi), b = fix_column(v, c0 + 1, lo, hi);
    return lerp_xrgb(texel(v->map, r, a), texel(v->map, r, b), fc);
}

/* A bilinear sample's rows at level-0 row (Q16.16) on a map hmax + 1 rows tall: the upper *r0 and the lower *r1
 * (the same at the edges, where the weight of the lower is 0), the weight returned (Q0.8). */
static uint32_t bilinear_rows(int32_t row, int32_t hmax, int32_t *r0, int32_t *r1)
{
    int32_t r = row >> 16;
    uint32_t fr = ((uint32_t)row >> 8) & 255u;
    if (r < 0) {
        r = 0;
        fr = 0;
    } else if (r >= hmax) {
        r = hmax;
        fr = 0;
    }
    *r0 = r;
    *r1 = fr ? r + 1 : r;
    return fr;
}

uint32_t psc_sample_general(const psc_viewer_t *v, psc_filter_t filter, int32_t row, int32_t col)
{
    const psc_envmap_t *m = v->map;
    int32_t hmax = m->height - 1;
    if (filter == PSC_FILTER_NEAREST) {
        int32_t r = clamp_i32((row + 32768) >> 16, 0, hmax), lo, hi;
        int32_t cr = row_column(v, r, col, &lo, &hi);
        return texel(m, r, fix_column(v, (cr + 32768) >> 16, lo, hi));
    }
    int32_t r0, r1;
    uint32_t fr = bilinear_rows(row, hmax, &r0, &r1);
    uint32_t top = sample_row(v, r0, col);
    if (fr == 0)
        return top;
    return lerp_xrgb(top, sample_row(v, r1, col), fr);
}

static int32_t clamp_col64(int64_t c, int32_t hi) { return c < 0 ? 0 : c > hi ? hi : (int32_t)c; }

static uint32_t raw_texel(const psc_envmap_t *m, int32_t r, int32_t c)
{
    return ((const uint16_t *)(const void *)((const uint8_t *)m->pixels + (size_t)r * m->stride))[c];
}

uint32_t psc_sample_partial(const psc_viewer_t *v, psc_filter_t filter, int32_t row, uint32_t t, bool packed565)
{
    const psc_envmap_t *m = v->map;
    int32_t hmax = m->height - 1, wmax = m->width - 1;
    if (filter == PSC_FILTER_NEAREST) {
        int32_t r = clamp_i32((row + 32768) >> 16, 0, hmax);
        int32_t c = clamp_col64(psc_partial_col_q32(v, 0, t, false) >> 32, wmax);
        return packed565 ? raw_texel(m, r, c) : texel(m, r, c);
    }
    int32_t r0, r1;
    uint32_t fr = bilinear_rows(row, hmax, &r0, &r1);
    int64_t q = psc_partial_col_q32(v, 0, t, true);
    int32_t a = clamp_col64(q >> 32, wmax), b = clamp_col64((q >> 32) + 1, wmax);
    uint32_t fc = (uint32_t)(q >> 24) & 255u;
    if (packed565)
        return psc_blend4_rgb565(raw_texel(m, r0, a), raw_texel(m, r0, b), raw_texel(m, r1, a), raw_texel(m, r1, b),
                                 (fc + 4u) >> 3, (fr + 4u) >> 3);
    return psc_blend4_xrgb(texel(m, r0, a), texel(m, r0, b), texel(m, r1, a), texel(m, r1, b), fc, fr);
}
