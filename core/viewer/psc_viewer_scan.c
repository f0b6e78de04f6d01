/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_scan.c - one output scanline: LUT samples, then spans between them.
 *
 * Samples. The LUT is read every N-th pixel. Pixel x and pixel W-1-x lie at
 * mirrored offsets from the view's centre line, so they read the same LUT
 * position and differ only in the sign of their longitude: samples are taken
 * at x = 0, N, 2N, ... from the left and at the mirrored columns from the
 * right, each LUT read serving two samples (a centre sample is added when the
 * middle gap is wider than N).
 *
 * Positions. A sample holds the map row (Q16.16) and the longitude from the
 * map's left edge as a binary angle t: on a full-turn map the column is
 * t * W / 2^32 (a shift for power-of-two widths), so the 360 degree seam costs
 * nothing, and the step between two samples, (int32_t)(t1 - t0), always takes
 * the short way round.
 *
 * Spans. Between samples, row and t advance by constant steps. Full-turn
 * rectangular maps (equirect, cylinder, sine) use specialised loops, one per
 * filter x map format x output format, with no per-pixel clamps: a row-offset
 * table with a repeated edge row on each side absorbs the half-pixel beyond
 * the poles. Other maps, the map pyramid and tracing go pixel by pixel
 * through the general samplers. Spans touching a polar cap read the LUT (or
 * compute exactly) at every pixel.
 */
#include "viewer/psc_viewer_internal.h"

/* ---- the scanline's LUT rows ---------------------------------------------------- */

typedef struct {
    const uint32_t *e0, *e1; /* the two bounding LUT rows */
    uint32_t fr;             /* blend weight of e1, Q0.8 (0..256) */
    bool lat_negative;       /* the scanline's LUT angle is below the horizon */
    bool over_pole;          /* |a| > 90 degrees: reflected, lon = 180 - lon */
    uint32_t u_step_q24;
    uint32_t mag_q8;         /* sqrt(yc^2 + d^2), Q8 half-pixels */
    int32_t yc;              /* half-pixels, up */
} row_setup_t;

static void row_setup(const psc_frame_t *f, unsigned y, row_setup_t *rs)
{
    const psc_lut_t *lut = f->lut;
    int32_t a = f->view->pitch + f->v->scan[y].v; /* |a| < 180 degrees */
    rs->lat_negative = a < 0;
    uint32_t abs_a = a < 0 ? (uint32_t)0 - (uint32_t)a : (uint32_t)a;
    rs->over_pole = abs_a > PSC_BAM_90;
    if (rs->over_pole)
        abs_a = PSC_BAM_180 - abs_a;
    uint32_t pos = (uint32_t)(((uint64_t)abs_a * (lut->rows - 1u) + (1u << 21)) >> 22); /* Q8 rows */
    uint32_t r0 = pos >> 8;
    rs->fr = pos & 255u;
    if (r0 >= lut->rows - 1u) {
        r0 = lut->rows - 2u;
        rs->fr = 256;
    }
    rs->e0 = lut->entries + (size_t)r0 * lut->cols;
    rs->e1 = rs->e0 + lut->cols;
    rs->u_step_q24 = f->v->scan[y].u_step_q24;
    rs->mag_q8 = f->v->scan[y].mag_q8;
    rs->yc = (int32_t)f->v->out_height - 1 - 2 * (int32_t)y;
}

static int32_t half_pixel_x(const psc_frame_t *f, unsigned x)
{
    return 2 * (int32_t)x + 1 - (int32_t)f->v->out_width;
}

/*
 * The LUT at |xc| half-pixels from the centre: the longitude offset for the
 * right-hand side (negate it on the left) and the latitude. Bilinear over two
 * rows and two columns with Q0.8 weights.
 */
static PSC_ALWAYS_INLINE void lut_read(const psc_frame_t *f, const row_setup_t *rs, uint32_t ax, uint32_t *lon_right, int32_t *lat)
{
    uint32_t pos = (uint32_t)(((uint64_t)ax * rs->u_step_q24 + (1u << 15)) >> 16); /* Q8 columns */
    uint32_t c0 = pos >> 8, fc = pos & 255u, cols = f->lut->cols;
    if (c0 >= cols - 1u) {
        c0 = cols - 2u;
        fc = 256;
    }
    uint32_t a = rs->e0[c0], b = rs->e0[c0 + 1], c = rs->e1[c0], d = rs->e1[c0 + 1];
    uint32_t ic = 256u - fc, ir = 256u - rs->fr;
    /* Each sum stays below 2^32: 65535 * 256 * 256 < 2^32. Units of 90deg / 2^32. */
    uint32_t lon = (PSC_LUT_LON(a) * ic + PSC_LUT_LON(b) * fc) * ir + (PSC_LUT_LON(c) * ic + PSC_LUT_LON(d) * fc) * rs->fr;
    uint32_t la = (PSC_LUT_LAT(a) * ic + PSC_LUT_LAT(b) * fc) * ir + (PSC_LUT_LAT(c) * ic + PSC_LUT_LAT(d) * fc) * rs->fr;
    /* to binary angles (90deg / 2^30), rounded */
    uint32_t lon_bam = (lon >> 2) + ((lon >> 1) & 1u), lat_bam = (la >> 2) + ((la >> 1) & 1u);
    *lon_right = rs->over_pole ? PSC_BAM_180 - lon_bam : lon_bam;
    *lat = rs->lat_negative ? -(int32_t)lat_bam : (int32_t)lat_bam;
}

/* ---- samples ---------------------------------------------------------------------- */

/* Map row of a latitude, Q16.16: linear rows inline, profile tables through the geometry code. */
static PSC_ALWAYS_INLINE int32_t row_of(const psc_viewer_t *v, int32_t lat)
{
    if (v->addr.row_table)
        return psc_map_row_q16(v, lat);
    /* |lat_top - lat| <= 2^31 and row_per_bam_q32 <= 2^22: the product fits */
    return (int32_t)((((int64_t)v->map->lat_top - lat) * v->addr.row_per_bam_q32) >> 16) - 32768;
}

/* A sample from a direction's angles. */
static PSC_ALWAYS_INLINE psc_scan_sample_t sample_from_angles(const psc_frame_t *f, unsigned x, psc_bam_t lon,
                                                              int32_t lat, bool polar)
{
    const psc_viewer_t *v = f->v;
    psc_scan_sample_t s;
    int32_t row = v->addr.fast ? row_of(v, lat) : psc_map_row_q16(v, lat);
    if (v->addr.fast) { /* within the row-offset table's guard rows */
        int32_t bottom = ((int32_t)v->map->height << 16) - 32768;
        row = row < -32768 ? -32768 : row > bottom ? bottom : row;
    }
    s.row = row;
    s.t = lon - v->map->lon_min;
    s.x = (uint16_t)x;
    s.polar = polar;
    return s;
}

/* The exact direction of pixel x (inside the inner polar cap). */
static psc_scan_sample_t exact_sample(const psc_frame_t *f, const row_setup_t *rs, unsigned x)
{
    psc_bam_t lon;
    int32_t lat;
    psc_exact_angles(f, half_pixel_x(f, x), rs->yc, &lon, &lat);
    return sample_from_angles(f, x, lon, lat, true);
}

/* The sample of pixel x on the side given by the sign of its xc, from a LUT read. */
static PSC_ALWAYS_INLINE psc_scan_sample_t side_sample(const psc_frame_t *f, const row_setup_t *rs, unsigned x, uint32_t lon_right,
                                     int32_t lat)
{
    int32_t abs_lat = lat < 0 ? -lat : lat;
    if (abs_lat >= f->cap_exact)
        return exact_sample(f, rs, x);
    uint32_t lon = half_pixel_x(f, x) < 0 ? (uint32_t)0 - lon_right : lon_right;
    return sample_from_angles(f, x, f->view->yaw + lon, lat, abs_lat >= f->cap_per_pixel);
}

/* Any single pixel's sample (used inside polar caps). */
static psc_scan_sample_t pixel_sample(const psc_frame_t *f, const row_setup_t *rs, unsigned x)
{
    int32_t xc = half_pixel_x(f, x);
    uint32_t lon_right;
    int32_t lat;
    lut_read(f, rs, xc < 0 ? (uint32_t)-xc : (uint32_t)xc, &lon_right, &lat);
    return side_sample(f, rs, x, lon_right, lat);
}

/*
 * Fill v->samples for the scanline: mirrored pairs from both ends, a centre
 * sample if the middle gap exceeds N, and a final copy of the last sample at
 * x = W so that every pixel lies in a span [s[k].x, s[k+1].x). Returns the count.
 */
static unsigned build_samples(const psc_frame_t *f, const row_setup_t *rs)
{
    psc_scan_sample_t *s = f->samples;
    const unsigned w = f->v->out_width, n = f->span, half = w / 2u;
    const unsigned pairs = (half + n - 1u) / n;            /* left samples: k*n < half */
    const unsigned last_left = (pairs - 1u) * n, gap = (w - 1u - last_left) - last_left;
    const bool centre = gap > n;
    const unsigned count = 2u * pairs + (centre ? 1u : 0u) + 1u;
    for (unsigned k = 0; k < pairs; k++) {
        unsigned xl = k * n, xr = w - 1u - xl;
        uint32_t lon_right;
        int32_t lat;
        lut_read(f, rs, (uint32_t)-half_pixel_x(f, xl), &lon_right, &lat);
        int32_t abs_lat = lat < 0 ? -lat : lat;
        if (abs_lat >= f->cap_exact) {
            s[k] = exact_sample(f, rs, xl);
            s[count - 2u - k] = exact_sample(f, rs, xr);
            continue;
        }
        bool polar = abs_lat >= f->cap_per_pixel;
        psc_bam_t yaw = f->view->yaw;
        s[k] = sample_from_angles(f, xl, yaw - lon_right, lat, polar);
        s[count - 2u - k] = sample_from_angles(f, xr, yaw + lon_right, lat, polar);
    }
    if (centre)
        s[pairs] = pixel_sample(f, rs, last_left + gap / 2u);
    s[count - 1u] = s[count - 2u];
    s[count - 1u].x = (uint16_t)w;
    return count;
}

/* Per-pixel steps from sample a to b over n pixels: a shift for full spans. */
static PSC_ALWAYS_INLINE void span_steps(const psc_frame_t *f, const psc_scan_sample_t *a, const psc_scan_sample_t *b,
                                         unsigned n, int32_t *drow, int32_t *dt)
{
    int32_t dr = b->row - a->row, dl = (int32_t)(b->t - a->t); /* the short way round */
    if (n == f->span) {
        dr >>= f->view->span_log2;
        dl >>= f->view->span_log2;
    } else {
        dr /= (int32_t)n;
        dl /= (int32_t)n;
    }
    *drow = dr;
    *dt = dl;
}

/* ---- the general path: one pixel at a time ------------------------------------------ */

/* Map column (Q16.16, integer = pixel centre) of t: wrapped on full-turn maps, unclamped on partial ones. */
static int32_t column_of(const psc_viewer_t *v, uint32_t t)
{
    if (v->addr.wraps) {
        int32_t col = (int32_t)(((uint64_t)t * v->map->width) >> 16) - 32768;
        return col < 0 ? col + ((int32_t)v->map->width << 16) : col;
    }
    return psc_map_col_q16(v, t + v->map->lon_min);
}

/*
 * Map level of detail at pixel x: log2 of map texels per output pixel (plus
 * the bias), Q24.8. A pixel (x, y) half-pixels from the centre spans
 * 2 / sqrt(x^2 + y^2 + d^2) radians across its ray.
 */
static int32_t pixel_lod_q8(const psc_frame_t *f, const row_setup_t *rs, unsigned x)
{
    int64_t xc = half_pixel_x(f, x);
    uint64_t dist2_q16 = (uint64_t)rs->mag_q8 * rs->mag_q8 + (uint64_t)(xc * xc) * 65536u;
    return f->v->lod_base_q8 - (psc_log2_q8(dist2_q16) - 16 * 256) / 2;
}

static void put_general(const psc_frame_t *f, unsigned x, int32_t row, uint32_t t)
{
    int32_t col = column_of(f->v, t);
    if (f->sink == PSC_SINK_TRACE) {
        f->trace_row[x] = row;
        f->trace_col[x] = col;
        return;
    }
    uint32_t px = psc_sample_general(f->v, f->filter, row, col);
    if (f->sink == PSC_SINK_RGB565)
        ((uint16_t *)(void *)f->dst)[x] = psc_xrgb_to_rgb565(px);
    else
        ((uint32_t *)(void *)f->dst)[x] = px;
}

/* Pixels [x, x + n) from sample a in steps, through the general samplers, the pyramid or the trace. */
static void span_general(const psc_frame_t *f, const row_setup_t *rs, unsigned x, unsigned n, int32_t row,
                         uint32_t t, int32_t drow, int32_t dt)
{
    if (f->mip && f->sink != PSC_SINK_TRACE) {
        psc_span_mip(f, x, n, row, t, drow, dt, pixel_lod_q8(f, rs, x + n / 2u));
        return;
    }
    for (unsigned i = 0; i < n; i++, row += drow, t += (uint32_t)dt)
        put_general(f, x + i, row, t);
}

/* ---- the fast spans: full-turn rectangular maps ------------------------------------------ */

static PSC_ALWAYS_INLINE uint32_t texel_xrgb(const uint8_t *row, uint32_t c, const psc_pixfmt_t in, const uint32_t *pal)
{
    if (in == PSC_PIX_RGB565)
        return psc_rgb565_to_xrgb(((const uint16_t *)(const void *)row)[c]);
    if (in == PSC_PIX_XRGB8888)
        return ((const uint32_t *)(const void *)row)[c];
    return pal[row[c]];
}

/* Nearest texel already in the output format. */
static PSC_ALWAYS_INLINE uint32_t texel_out(const uint8_t *row, uint32_t c, const psc_pixfmt_t in, const psc_sink_t sink,
                                            const uint32_t *pal, const uint16_t *pal565)
{
    if (in == PSC_PIX_RGB565) {
        uint32_t p = ((const uint16_t *)(const void *)row)[c];
        return sink == PSC_SINK_RGB565 ? p : psc_rgb565_to_xrgb(p);
    }
    if (in == PSC_PIX_XRGB8888) {
        uint32_t p = ((const uint32_t *)(const void *)row)[c];
        return sink == PSC_SINK_RGB565 ? psc_xrgb_to_rgb565(p) : p | 0xFF000000u;
    }
    return sink == PSC_SINK_RGB565 ? pal565[row[c]] : pal[row[c]] | 0xFF000000u;
}

static PSC_ALWAYS_INLINE void store(void *dst, unsigned x, uint32_t px, const psc_sink_t sink)
{
    if (sink == PSC_SINK_RGB565)
        ((uint16_t *)dst)[x] = (uint16_t)px;
    else
        ((uint32_t *)dst)[x] = px;
}

/*
 * Pixels [x, x + n) from (row, t) in steps (drow, dt) for one combination
 * of filter, map format and output, all compile-time constants once inlined.
 * pow2: the map width is a power of two (columns by shift).
 */
/* What every fast span of a scanline reads: loaded once, kept in registers across the spans. */
typedef struct {
    const uint8_t *base;
    const uint32_t *rowoff;   /* [0] and [H + 1] repeat the edge rows */
    uint32_t w, sh, half_col;
    const uint32_t *pal;
    const uint16_t *pal565;
    void *dst;
} fast_ctx_t;

static PSC_ALWAYS_INLINE void span_fast(const fast_ctx_t *cx, unsigned x, unsigned n, int32_t row, uint32_t t,
                                        int32_t drow, int32_t dt, const psc_filter_t filter, const psc_pixfmt_t in,
                                        const psc_sink_t sink, const bool pow2)
{
    const uint8_t *base = cx->base;
    const uint32_t *rowoff = cx->rowoff;
    const uint32_t w = cx->w, sh = cx->sh;
    const uint32_t *pal = cx->pal;
    const uint16_t *pal565 = cx->pal565;
    /* Rows biased by one (the guard row) so the table index is never negative. */
    uint32_t r = (uint32_t)(row + 65536);
    if (filter == PSC_FILTER_NEAREST) {
        r += 32768; /* round to the nearest row */
        for (unsigned i = 0; i < n; i++) {
            uint32_t c = pow2 ? t >> sh : (uint32_t)(((uint64_t)t * w) >> 32);
            store(cx->dst, x + i, texel_out(base + rowoff[r >> 16], c, in, sink, pal, pal565), sink);
            r += (uint32_t)drow;
            t += (uint32_t)dt;
        }
        return;
    }
    t -= cx->half_col; /* column c0 is the one left of the sample point */
    for (unsigned i = 0; i < n; i++) {
        const uint8_t *p0 = base + rowoff[r >> 16], *p1 = base + rowoff[(r >> 16) + 1u];
        uint32_t c0, fc;
        if (pow2) {
            c0 = t >> sh;
            fc = t << (32u - sh) >> 24; /* the 8 bits below the column */
        } else {
            uint64_t q = (uint64_t)t * w;
            c0 = (uint32_t)(q >> 32);
            fc = (uint32_t)(q >> 24) & 255u;
        }
        uint32_t c1 = pow2 ? (c0 + 1u) & (w - 1u) : (c0 + 1u == w ? 0u : c0 + 1u);
        uint32_t px;
        if (in == PSC_PIX_RGB565 && sink == PSC_SINK_RGB565) {
            const uint16_t *a = (const uint16_t *)(const void *)p0, *b = (const uint16_t *)(const void *)p1;
            px = psc_blend4_rgb565(a[c0], a[c1], b[c0], b[c1], (fc + 4u) >> 3, (((r >> 8) & 255u) + 4u) >> 3);
        } else {
            uint32_t fr = (r >> 8) & 255u;
            px = psc_blend4_xrgb(texel_xrgb(p0, c0, in, pal), texel_xrgb(p0, c1, in, pal), texel_xrgb(p1, c0, in, pal),
                                 texel_xrgb(p1, c1, in, pal), fc, fr);
            if (sink == PSC_SINK_RGB565)
                px = psc_xrgb_to_rgb565(px);
        }
        store(cx->dst, x + i, px, sink);
        r += (uint32_t)drow;
        t += (uint32_t)dt;
    }
}

static void polar_pixels(const psc_frame_t *f, const row_setup_t *rs, unsigned x, unsigned n);

/* Every span of a scanline through one specialised span_fast. */
static PSC_ALWAYS_INLINE void spans_fast(const psc_frame_t *f, const row_setup_t *rs, const psc_scan_sample_t *s,
                                         unsigned count, const psc_filter_t filter, const psc_pixfmt_t in,
                                         const psc_sink_t sink, const bool pow2)
{
    const psc_viewer_t *v = f->v;
    const fast_ctx_t cx = {v->map->pixels, v->row_offsets, v->map->width, v->col_shift, v->half_col_bam,
                           v->map->palette, v->palette565, f->dst};
    for (unsigned k = 0; k + 1u < count; k++) {
        const psc_scan_sample_t *a = &s[k], *b = &s[k + 1u];
        unsigned n = (unsigned)b->x - a->x;
        if (a->polar | b->polar) {
            polar_pixels(f, rs, a->x, n);
            continue;
        }
        int32_t drow, dt;
        span_steps(f, a, b, n, &drow, &dt);
        span_fast(&cx, a->x, n, a->row, a->t, drow, dt, filter, in, sink, pow2);
    }
}

#define SPANS(filter, in, sink) \
    (pow2 ? spans_fast(f, rs, s, count, filter, in, sink, true) : spans_fast(f, rs, s, count, filter, in, sink, false))
#define SPANS_FOR_FORMAT(in)                                                                              \
    do {                                                                                                  \
        if (nearest)                                                                                      \
            to565 ? SPANS(PSC_FILTER_NEAREST, in, PSC_SINK_RGB565) : SPANS(PSC_FILTER_NEAREST, in, PSC_SINK_XRGB8888); \
        else                                                                                              \
            to565 ? SPANS(PSC_FILTER_BILINEAR, in, PSC_SINK_RGB565) : SPANS(PSC_FILTER_BILINEAR, in, PSC_SINK_XRGB8888); \
    } while (0)

static void spans_fast_dispatch(const psc_frame_t *f, const row_setup_t *rs, const psc_scan_sample_t *s, unsigned count)
{
    const bool nearest = f->filter == PSC_FILTER_NEAREST, to565 = f->sink == PSC_SINK_RGB565;
    const bool pow2 = f->v->col_shift != 0;
    switch (f->v->map->format) {
    case PSC_PIX_RGB565: SPANS_FOR_FORMAT(PSC_PIX_RGB565); break;
    case PSC_PIX_XRGB8888: SPANS_FOR_FORMAT(PSC_PIX_XRGB8888); break;
    case PSC_PIX_PAL8: SPANS_FOR_FORMAT(PSC_PIX_PAL8); break;
    }
}

/* Whether pixels go through span_fast (else span_general). */
static bool uses_fast_spans(const psc_frame_t *f)
{
    return f->v->addr.fast && !f->mip && f->sink != PSC_SINK_TRACE;
}

/* Inside a polar cap: each pixel's own sample, drawn alone. */
static void polar_pixels(const psc_frame_t *f, const row_setup_t *rs, unsigned x, unsigned n)
{
    for (unsigned i = 0; i < n; i++) {
        psc_scan_sample_t p = pixel_sample(f, rs, x + i);
        if (uses_fast_spans(f)) {
            psc_scan_sample_t pair[2] = {p, p};
            pair[0].polar = pair[1].polar = 0;
            pair[1].x = (uint16_t)(x + i + 1u);
            spans_fast_dispatch(f, rs, pair, 2);
        } else {
            span_general(f, rs, x + i, 1, p.row, p.t, 0, 0);
        }
    }
}

void psc_scanline_render(const psc_frame_t *f, unsigned y)
{
    row_setup_t rs;
    row_setup(f, y, &rs);
    unsigned count = build_samples(f, &rs);
    const psc_scan_sample_t *s = f->samples;
    if (uses_fast_spans(f)) {
        spans_fast_dispatch(f, &rs, s, count);
        return;
    }
    for (unsigned k = 0; k + 1u < count; k++) {
        const psc_scan_sample_t *a = &s[k], *b = &s[k + 1u];
        unsigned n = (unsigned)b->x - a->x;
        if (a->polar | b->polar) {
            polar_pixels(f, &rs, a->x, n);
            continue;
        }
        int32_t drow, dt;
        span_steps(f, a, b, n, &drow, &dt);
        span_general(f, &rs, a->x, n, a->row, a->t, drow, dt);
    }
}
