/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_scan.c - one output scanline: LUT samples, then spans between them.
 *
 * Samples. The scanline is cut into spans of N pixels from the left; the LUT
 * is read at the boundaries between spans (boundary b lies between pixels
 * b - 1 and b). Boundary b and boundary W - b lie at mirrored offsets from the
 * view's centre line, so they read the same LUT position and differ only in
 * the sign of their longitude: when N divides W every LUT read serves two
 * samples.
 *
 * The composite LUT row. A scanline's LUT angle falls between two LUT rows;
 * they are blended once per scanline into a composite row of (lon, lat)
 * pairs, so each sample blends two entries instead of four. Bilinear blending
 * is separable and the sums are exact, so this gives the same angles as
 * blending the four entries at every sample.
 *
 * Positions. A sample holds the map row (Q16.16) and the longitude from the
 * map's left edge as a binary angle t: on a full-turn map the column is
 * t * W / 2^32 (a shift for power-of-two widths), so the 360 degree seam costs
 * nothing, and the step between two samples, (int32_t)(t1 - t0), always takes
 * the short way round. Pixel i of a span from sample a to b sits at
 * a + step / 2 + i * step, step = (b - a) / N (a shift).
 *
 * Spans. Full-turn rectangular maps (equirect, cylinder, sine) use
 * specialised loops, one per filter x map format x output format, with no
 * per-pixel clamps: a row-offset table with a repeated edge row on each side
 * absorbs the half-pixel beyond the poles. Other maps, the map pyramid and
 * tracing go pixel by pixel through the general samplers. Spans touching a
 * polar cap read the LUT (or compute exactly) at every pixel.
 */
#include "viewer/psc_viewer_internal.h"
#include "viewer/psc_viewer_simd.h"

/* Whether pixels go through span_fast (else span_general). */
static bool uses_fast_spans(const psc_frame_t *f)
{
    return f->v->addr.fast && !f->mip && f->sink != PSC_SINK_TRACE && !f->tiles;
}

/* ---- the scanline's LUT row ------------------------------------------------------ */

typedef struct {
    const uint32_t *lut_row; /* composite row: (lon, lat) pairs, Q8.24 units of 90deg / 2^24; NULL: read e0, e1 */
    const uint32_t *e0, *e1; /* the two bounding LUT rows */
    uint32_t fr;             /* blend weight of e1, Q0.8 (0..256) */
    uint32_t lut_cols;       /* entries built: every column the scanline reads */
    bool lat_negative;       /* the scanline's LUT angle is below the horizon */
    bool over_pole;          /* |a| > 90 degrees: reflected, lon = 180 - lon */
    uint32_t u_step_q24;
    uint32_t mag_q8;         /* sqrt(yc^2 + d^2), Q8 half-pixels */
    int32_t yc;              /* half-pixels, up */
    bool any_polar;          /* a sample of the scanline lies in a polar cap */
    unsigned prefetched;     /* samples [0, n) and their mirrors: map lines prefetched by the kernel */
    bool tiled_level0;       /* a tiled map's nearest or bilinear scanline reads level 0 throughout */
} row_setup_t;

/* LUT column of a point |xc| half-pixels from the centre, Q8. */
static PSC_ALWAYS_INLINE uint32_t lut_col_q8(const row_setup_t *rs, uint32_t ax)
{
    return (uint32_t)(((uint64_t)ax * rs->u_step_q24 + (1u << 15)) >> 16);
}

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
    uint32_t r0 = pos >> 8, fr = pos & 255u;
    if (r0 >= lut->rows - 1u) {
        r0 = lut->rows - 2u;
        fr = 256;
    }
    rs->u_step_q24 = f->v->scan[y].u_step_q24;
    rs->mag_q8 = f->v->scan[y].mag_q8;
    rs->yc = (int32_t)f->v->out_height - 1 - 2 * (int32_t)y;
    /* Columns up to the one right of the outermost boundary (|xc| = W). */
    uint32_t last = (lut_col_q8(rs, f->v->out_width) >> 8) + 1u;
    rs->lut_cols = last < lut->cols ? last + 1u : lut->cols;
    const uint32_t *e0 = lut->entries + (size_t)r0 * lut->cols, *e1 = e0 + lut->cols;
    rs->e0 = e0;
    rs->e1 = e1;
    rs->fr = fr;
    rs->lut_row = NULL;
    /* A LUT denser than the scanline's samples is read directly: blending it
     * would cost more than it saves (and the workspace holds W / 2 + 2 columns). */
    if (rs->lut_cols > PSC_SCAN_COMPOSITE_COLS(f->v->out_width))
        return;
    uint32_t *c = f->work.lut_row, ir = 256u - fr;
    if (f->simd) {
        f->simd->composite(e0, e1, fr, rs->lut_cols, c);
    } else {
        for (uint32_t j = 0; j < rs->lut_cols; j++) { /* 65535 * 256 < 2^24 */
            c[2 * j] = PSC_LUT_LON(e0[j]) * ir + PSC_LUT_LON(e1[j]) * fr;
            c[2 * j + 1] = PSC_LUT_LAT(e0[j]) * ir + PSC_LUT_LAT(e1[j]) * fr;
        }
    }
    rs->lut_row = c;
}

static int32_t half_pixel_x(const psc_frame_t *f, unsigned x)
{
    return 2 * (int32_t)x + 1 - (int32_t)f->v->out_width;
}

/*
 * The composite LUT row at |xc| half-pixels from the centre: the longitude
 * offset for the right-hand side (negate it on the left) and the latitude.
 */
static PSC_ALWAYS_INLINE void lut_read(const row_setup_t *rs, uint32_t ax, uint32_t *lon_right, int32_t *lat)
{
    uint32_t pos = lut_col_q8(rs, ax);
    uint32_t c0 = pos >> 8, fc = pos & 255u;
    if (c0 >= rs->lut_cols - 1u) { /* only where the LUT itself ends */
        c0 = rs->lut_cols - 2u;
        fc = 256;
    }
    uint32_t lon, la, ic = 256u - fc;
    if (rs->lut_row) { /* Each sum stays below 2^32: 2^24 * 256. Units of 90deg / 2^32. */
        const uint32_t *e = rs->lut_row + 2u * c0;
        lon = e[0] * ic + e[2] * fc;
        la = e[1] * ic + e[3] * fc;
    } else { /* the same sums, blending the columns first: 65535 * 256 * 256 < 2^32 */
        uint32_t a = rs->e0[c0], b = rs->e0[c0 + 1], c = rs->e1[c0], d = rs->e1[c0 + 1], ir = 256u - rs->fr;
        lon = (PSC_LUT_LON(a) * ic + PSC_LUT_LON(b) * fc) * ir + (PSC_LUT_LON(c) * ic + PSC_LUT_LON(d) * fc) * rs->fr;
        la = (PSC_LUT_LAT(a) * ic + PSC_LUT_LAT(b) * fc) * ir + (PSC_LUT_LAT(c) * ic + PSC_LUT_LAT(d) * fc) * rs->fr;
    }
    /* to binary angles (90deg / 2^30), rounded */
    uint32_t lon_bam = (lon >> 2) + ((lon >> 1) & 1u), lat_bam = (la >> 2) + ((la >> 1) & 1u);
    *lon_right = rs->over_pole ? PSC_BAM_180 - lon_bam : lon_bam;
    *lat = rs->lat_negative ? -(int32_t)lat_bam : (int32_t)lat_bam;
}

/* ---- samples ---------------------------------------------------------------------- */

/* A boundary sample's flags (work.polar): in a polar cap (its spans' pixels take exact positions), near a partial
 * map's edge (its spans' pixels go through the general sampler, which clamps). */
#define POLAR_CAP 1u
#define MAP_EDGE 2u

/* Map row of a latitude, Q16.16: linear rows inline, profile tables through the geometry code. */
static PSC_ALWAYS_INLINE int32_t row_of(const psc_viewer_t *v, int32_t lat)
{
    if (v->addr.row_table)
        return psc_map_row_q16(v, lat);
    /* |lat_top - lat| <= 2^31 and row_per_bam_q32 <= 2^22: the product fits */
    return (int32_t)((((int64_t)v->map->lat_top - lat) * v->addr.row_per_bam_q32) >> 16) - 32768;
}

/* A map position from a direction's angles. */
typedef struct {
    int32_t row;
    uint32_t t;
} map_pos_t;

static PSC_ALWAYS_INLINE map_pos_t pos_from_angles(const psc_viewer_t *v, psc_bam_t lon, int32_t lat)
{
    map_pos_t p;
    int32_t row = v->addr.fast ? row_of(v, lat) : psc_map_row_q16(v, lat);
    if (v->addr.fast) { /* within the row-offset table's guard rows */
        int32_t bottom = (int32_t)(((int64_t)v->map->height << 16) - 32768);
        row = row < -32768 ? -32768 : row > bottom ? bottom : row;
    }
    p.row = row;
    p.t = lon - v->map->lon_min;
    return p;
}

/* The exact direction through half-pixel coordinates (xc, rs->yc). */
static map_pos_t exact_pos(const psc_frame_t *f, const row_setup_t *rs, int32_t xc)
{
    psc_bam_t lon;
    int32_t lat;
    psc_exact_angles(f, xc, rs->yc, &lon, &lat);
    return pos_from_angles(f->v, lon, lat);
}

/* The position at half-pixel xc (any point of the scanline), and whether it lies in a polar cap. */
static PSC_ALWAYS_INLINE map_pos_t point_pos(const psc_frame_t *f, const row_setup_t *rs, int32_t xc, bool *polar)
{
    uint32_t lon_right;
    int32_t lat;
    lut_read(rs, xc < 0 ? (uint32_t)-xc : (uint32_t)xc, &lon_right, &lat);
    int32_t abs_lat = lat < 0 ? -lat : lat;
    *polar = abs_lat >= f->cap_per_pixel;
    if (abs_lat >= f->cap_exact)
        return exact_pos(f, rs, xc);
    return pos_from_angles(f->v, f->view->yaw + (xc < 0 ? (uint32_t)0 - lon_right : lon_right), lat);
}

static PSC_ALWAYS_INLINE void put_sample(const psc_frame_t *f, row_setup_t *rs, unsigned k, map_pos_t p, bool polar)
{
    rs->any_polar |= polar;
    f->work.row[k] = p.row;
    f->work.t[k] = p.t;
    f->work.polar[k] = polar;
}

/*
 * build_samples for full-turn maps with linear rows (equirect), N dividing W:
 * the same samples with the per-scanline constants in registers and each
 * LUT read's row computed once for its two samples. The row is
 * ((lat_top - lat) * rows_per_bam) >> 16 - 1/2 with lat = sign * lat_bam,
 * expanded as lat_top * rows_per_bam - sign * rows_per_bam * lat_bam (exact
 * in 64 bits: |lat_top| <= 2^30, rows_per_bam < 2^22).
 */
/*
 * The map lines under the scanline's samples are prefetched (prefetch_samples)
 * every pf_step samples: one every 16 map bytes at 1:1, 8 pixels of RGB565
 * (measured faster than every 32 or 64 on a new view).
 */
static unsigned pf_step(const psc_frame_t *f)
{
    const unsigned px = 16u / psc_pixfmt_bytes(f->v->map->format);
    return px >> f->view->span_log2 ? px >> f->view->span_log2 : 1u;
}

static unsigned build_samples_linear(const psc_frame_t *f, row_setup_t *rs, unsigned count)
{
    const psc_viewer_t *v = f->v;
    const unsigned w = v->out_width, n = f->span;
    const int64_t rpb = v->addr.row_per_bam_q32, row_base = (int64_t)v->map->lat_top * rpb;
    const int64_t row_per_lat = rs->lat_negative ? rpb : -rpb;
    const int32_t bottom = (int32_t)(((int64_t)v->map->height << 16) - 32768);
    const uint32_t pole_base = rs->over_pole ? PSC_BAM_180 : 0u, pole_sign = rs->over_pole ? (uint32_t)-1 : 1u;
    const uint32_t t_base = f->view->yaw - v->map->lon_min, cols = rs->lut_cols, u_step = rs->u_step_q24;
    const int32_t cap_pp = f->cap_per_pixel, cap_exact = f->cap_exact;
    const uint32_t *lut_row = rs->lut_row;
    int32_t *row = f->work.row;
    uint32_t *t = f->work.t;
    uint8_t *polar = f->work.polar, any = 0;
    unsigned k0 = 0;
    if (f->simd && (uint64_t)w * u_step + 32768u <= UINT32_MAX) {
        /* the kernel prefetches too, where it can address columns by shift and the spans are fast */
        const uint32_t bpp = psc_pixfmt_bytes(v->map->format), step = pf_step(f);
        /* it addresses columns by shift (a partial map's edges: prefetch_samples' alone, which skips them) */
        const bool pf = uses_fast_spans(f) && v->col_shift != 0 && bpp != 3u && v->addr.wraps;
        const psc_simd_samples_t job = {lut_row, cols, u_step, w, n, w / (2u * n) + 1u, count, row_base,
                                        (int32_t)row_per_lat, bottom, pole_base, pole_sign, t_base, cap_pp,
                                        cap_exact, row, t, polar, pf ? v->map->pixels : 0,
                                        f->filter == PSC_FILTER_BILINEAR ? 65536u : 65536u + 32768u,
                                        v->map->stride, v->map->height, v->col_shift, bpp == 4 ? 2u : bpp == 2 ? 1u : 0u,
                                        step - 1u, f->filter == PSC_FILTER_BILINEAR};
        k0 = f->simd->samples(&job, &any);
        rs->prefetched = pf ? k0 : 0u;
    }
    for (unsigned k = k0; 2u * k * n <= w; k++) {
        uint32_t ax = w - 2u * k * n, r = count - 1u - k;
        uint32_t pos = (uint32_t)(((uint64_t)ax * u_step + (1u << 15)) >> 16);
        uint32_t c0 = pos >> 8, fc = pos & 255u;
        if (c0 >= cols - 1u) {
            c0 = cols - 2u;
            fc = 256;
        }
        const uint32_t *e = lut_row + 2u * c0, ic = 256u - fc;
        uint32_t lon = e[0] * ic + e[2] * fc, la = e[1] * ic + e[3] * fc;
        uint32_t lon_bam = (uint32_t)(((uint64_t)lon + 2u) >> 2), lat_bam = (uint32_t)(((uint64_t)la + 2u) >> 2);
        int32_t abs_lat = (int32_t)lat_bam; /* < 2^31: at most 90 degrees */
        uint8_t p = abs_lat >= cap_pp;
        if (abs_lat >= cap_exact) {
            map_pos_t a = exact_pos(f, rs, -(int32_t)ax), b = exact_pos(f, rs, (int32_t)ax);
            row[k] = a.row, t[k] = a.t, polar[k] = 1;
            row[r] = b.row, t[r] = b.t, polar[r] = 1;
            any = 1;
            continue;
        }
        uint32_t lon_right = pole_base + pole_sign * lon_bam;
        int32_t y = (int32_t)((row_base + row_per_lat * lat_bam) >> 16) - 32768;
        y = y < -32768 ? -32768 : y > bottom ? bottom : y;
        row[k] = y, t[k] = t_base - lon_right, polar[k] = p;
        row[r] = y, t[r] = t_base + lon_right, polar[r] = p;
        any |= p;
    }
    rs->any_polar = any;
    return count;
}

/*
 * Fill the boundary samples of the scanline: boundary k at pixel
 * min(k N, W), k = 0 .. count - 1. Returns the count.
 */
static unsigned build_samples(const psc_frame_t *f, row_setup_t *rs)
{
    rs->any_polar = false;
    rs->prefetched = 0;
    const unsigned w = f->v->out_width, n = f->span, count = (w + n - 1u) / n + 1u;
    if (w % n != 0) { /* boundaries not mirrored: one LUT read each */
        for (unsigned k = 0; k < count; k++) {
            unsigned b = k * n < w ? k * n : w;
            bool polar;
            map_pos_t p = point_pos(f, rs, 2 * (int32_t)b - (int32_t)w, &polar);
            put_sample(f, rs, k, p, polar);
        }
        return count;
    }
    if (f->v->addr.fast && !f->v->addr.row_table && rs->lut_row)
        return build_samples_linear(f, rs, count);
    const psc_bam_t yaw = f->view->yaw;
    for (unsigned k = 0; 2u * k * n <= w; k++) {
        uint32_t ax = w - 2u * k * n, lon_right; /* |xc| of boundaries k and count - 1 - k */
        int32_t lat;
        lut_read(rs, ax, &lon_right, &lat);
        int32_t abs_lat = lat < 0 ? -lat : lat;
        bool polar = abs_lat >= f->cap_per_pixel;
        if (abs_lat >= f->cap_exact) {
            put_sample(f, rs, k, exact_pos(f, rs, -(int32_t)ax), polar);
            put_sample(f, rs, count - 1u - k, exact_pos(f, rs, (int32_t)ax), polar);
            continue;
        }
        put_sample(f, rs, k, pos_from_angles(f->v, yaw - lon_right, lat), polar);
        put_sample(f, rs, count - 1u - k, pos_from_angles(f->v, yaw + lon_right, lat), polar);
    }
    return count;
}

/*
 * The span from boundary k to k + 1 (n pixels): its first pixel's position
 * and the per-pixel steps, a shift for full spans.
 */
typedef struct {
    int32_t row, drow, dt;
    uint32_t t;
} span_t;

static PSC_ALWAYS_INLINE span_t span_at(const psc_frame_t *f, unsigned k, unsigned n)
{
    const int32_t *row = f->work.row;
    const uint32_t *t = f->work.t;
    int32_t dr = row[k + 1] - row[k], dl = (int32_t)(t[k + 1] - t[k]); /* the short way round */
    if (n == f->span) {
        dr >>= f->view->span_log2;
        dl >>= f->view->span_log2;
    } else {
        dr /= (int32_t)n;
        dl /= (int32_t)n;
    }
    span_t s = {row[k] + (dr >> 1), dr, dl, t[k] + (uint32_t)(dl >> 1)};
    return s;
}

/* The span from boundary k (n pixels) begun `skip` pixels in, where a vector kernel stopped inside it. */
static PSC_ALWAYS_INLINE span_t span_from(const psc_frame_t *f, unsigned k, unsigned n, unsigned skip)
{
    span_t s = span_at(f, k, n);
    s.row = (int32_t)((uint32_t)s.row + skip * (uint32_t)s.drow);
    s.t += skip * (uint32_t)s.dt;
    return s;
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
 * Map level of detail at half-pixel xc of the scanline: log2 of map texels
 * per output pixel (plus the bias), Q24.8. A pixel (x, y) half-pixels from
 * the centre spans 2 / sqrt(x^2 + y^2 + d^2) radians across its ray. A span
 * takes the level of its centre (xc = 2 x + n - W), which a span and its
 * mirror share; a lone pixel its own.
 */
static int32_t lod_q8_at(const psc_frame_t *f, const row_setup_t *rs, int32_t xc)
{
    uint64_t dist2_q16 = (uint64_t)rs->mag_q8 * rs->mag_q8 + (uint64_t)((int64_t)xc * xc) * 65536u;
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
    /* a partial map of rectangular rows: its columns as its fast spans take them, clamped at its edges */
    const bool partial = !f->v->addr.wraps && !f->v->row_width_q16;
    const bool packed565 = partial && f->v->map->format == PSC_PIX_RGB565 && f->sink == PSC_SINK_RGB565;
    uint32_t px = partial ? psc_sample_partial(f->v, f->filter, row, t, packed565)
                          : psc_sample_general(f->v, f->filter, row, col);
    if (packed565)
        ((uint16_t *)(void *)f->dst)[x] = (uint16_t)px;
    else if (f->sink == PSC_SINK_RGB565)
        ((uint16_t *)(void *)f->dst)[x] = psc_xrgb_to_rgb565(px);
    else
        ((uint32_t *)(void *)f->dst)[x] = px;
}

/* Pixels [x, x + n) of a span through the general samplers, the pyramid or the trace. */
static void span_general(const psc_frame_t *f, const row_setup_t *rs, unsigned x, unsigned n, span_t s, int32_t lod_xc)
{
    if (f->tiles && f->sink != PSC_SINK_TRACE) {
        psc_span_tiled(f, x, n, s.row, s.t, s.drow, s.dt, rs->tiled_level0 ? MIP_LOD_BIAS_Q8 : lod_q8_at(f, rs, lod_xc));
        return;
    }
    if (f->mip && f->sink != PSC_SINK_TRACE) { /* the level of detail at half-pixel lod_xc */
        psc_span_mip(f, x, n, s.row, s.t, s.drow, s.dt, lod_q8_at(f, rs, lod_xc));
        return;
    }
    for (unsigned i = 0; i < n; i++, s.row += s.drow, s.t += (uint32_t)s.dt)
        put_general(f, x + i, s.row, s.t);
}

/* Pixels [a, b) of a scanline through its spans' general path (a tiled map's, here). */
static void pixels_general(const psc_frame_t *f, const row_setup_t *rs, unsigned a, unsigned b)
{
    const unsigned w = f->v->out_width, n = f->span;
    for (unsigned k = a / n, x = k * n; x < b; k++, x += n) {
        unsigned len = w - x < n ? w - x : n, lo = a > x ? a : x, hi = b < x + len ? b : x + len;
        span_general(f, rs, lo, hi - lo, span_from(f, k, len, lo - x), 2 * (int32_t)x + (int32_t)len - (int32_t)w);
    }
}

/* ---- the fast spans: full-turn rectangular maps ------------------------------------------ */

static PSC_ALWAYS_INLINE uint32_t texel_xrgb(const uint8_t *row, uint32_t c, const psc_pixfmt_t in, const uint32_t *pal)
{
    if (in == PSC_PIX_RGB565)
        return psc_rgb565_to_xrgb(((const uint16_t *)(const void *)row)[c]);
    if (in == PSC_PIX_XRGB8888)
        return ((const uint32_t *)(const void *)row)[c];
    if (in == PSC_PIX_RGB888)
        return psc_rgb888_at(row, c);
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
    if (in == PSC_PIX_XRGB8888 || in == PSC_PIX_RGB888) {
        uint32_t p = in == PSC_PIX_RGB888 ? psc_rgb888_at(row, c) : ((const uint32_t *)(const void *)row)[c];
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

/* What every fast span of a scanline reads: loaded once, kept in registers across the spans. */
typedef struct {
    const uint8_t *base;
    const uint32_t *rowoff;   /* [0] and [H + 1] repeat the edge rows */
    uint32_t w, sh, half_col;
    const uint32_t *pal;
    const uint16_t *pal565;
    void *dst;
} fast_ctx_t;

static fast_ctx_t fast_ctx(const psc_frame_t *f)
{
    const psc_viewer_t *v = f->v;
    fast_ctx_t cx = {v->map->pixels, v->row_offsets, v->col_width, v->col_shift, v->half_col_bam,
                     v->map->palette, v->palette565, f->dst};
    return cx;
}

/*
 * Pixels [x, x + n) of span s for one combination of filter, map format and
 * output, all compile-time constants once inlined.
 * pow2: the map width is a power of two (columns by shift).
 */
static PSC_ALWAYS_INLINE void span_fast(const fast_ctx_t *cx, unsigned x, unsigned n, span_t s,
                                        const psc_filter_t filter, const psc_pixfmt_t in, const psc_sink_t sink,
                                        const bool pow2)
{
    const uint8_t *base = cx->base;
    const uint32_t *rowoff = cx->rowoff;
    const uint32_t w = cx->w, sh = cx->sh;
    const uint32_t *pal = cx->pal;
    const uint16_t *pal565 = cx->pal565;
    /* Rows biased by one (the guard row) so the table index is never negative. */
    uint32_t r = (uint32_t)(s.row + 65536), t = s.t;
    if (filter == PSC_FILTER_NEAREST) {
        r += 32768; /* round to the nearest row */
        for (unsigned i = 0; i < n; i++) {
            uint32_t c = pow2 ? t >> sh : (uint32_t)(((uint64_t)t * w) >> 32);
            store(cx->dst, x + i, texel_out(base + rowoff[r >> 16], c, in, sink, pal, pal565), sink);
            r += (uint32_t)s.drow;
            t += (uint32_t)s.dt;
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
        r += (uint32_t)s.drow;
        t += (uint32_t)s.dt;
    }
}

#define FAST_VARIANTS(X)                                                                                   \
    X(PSC_FILTER_NEAREST, PSC_PIX_RGB565, PSC_SINK_RGB565)                                                 \
    X(PSC_FILTER_NEAREST, PSC_PIX_RGB565, PSC_SINK_XRGB8888)                                               \
    X(PSC_FILTER_NEAREST, PSC_PIX_XRGB8888, PSC_SINK_RGB565)                                               \
    X(PSC_FILTER_NEAREST, PSC_PIX_XRGB8888, PSC_SINK_XRGB8888)                                             \
    X(PSC_FILTER_NEAREST, PSC_PIX_PAL8, PSC_SINK_RGB565)                                                   \
    X(PSC_FILTER_NEAREST, PSC_PIX_PAL8, PSC_SINK_XRGB8888)                                                 \
    X(PSC_FILTER_NEAREST, PSC_PIX_RGB888, PSC_SINK_RGB565)                                                 \
    X(PSC_FILTER_NEAREST, PSC_PIX_RGB888, PSC_SINK_XRGB8888)                                               \
    X(PSC_FILTER_BILINEAR, PSC_PIX_RGB565, PSC_SINK_RGB565)                                                \
    X(PSC_FILTER_BILINEAR, PSC_PIX_RGB565, PSC_SINK_XRGB8888)                                              \
    X(PSC_FILTER_BILINEAR, PSC_PIX_XRGB8888, PSC_SINK_RGB565)                                              \
    X(PSC_FILTER_BILINEAR, PSC_PIX_XRGB8888, PSC_SINK_XRGB8888)                                            \
    X(PSC_FILTER_BILINEAR, PSC_PIX_PAL8, PSC_SINK_RGB565)                                                  \
    X(PSC_FILTER_BILINEAR, PSC_PIX_PAL8, PSC_SINK_XRGB8888)                                                \
    X(PSC_FILTER_BILINEAR, PSC_PIX_RGB888, PSC_SINK_RGB565)                                                \
    X(PSC_FILTER_BILINEAR, PSC_PIX_RGB888, PSC_SINK_XRGB8888)

/* One pixel (inside a polar cap) through the fast sampler of the frame's combination. */
static void pixel_fast(const psc_frame_t *f, unsigned x, map_pos_t p)
{
    const fast_ctx_t cx = fast_ctx(f);
    const span_t s = {p.row, 0, 0, p.t};
    const bool pow2 = f->v->col_shift != 0;
#define PIXEL_FAST(fl_, in_, sink_)                                                                           \
    if (f->filter == fl_ && f->v->map->format == in_ && f->sink == sink_) {                                   \
        pow2 ? span_fast(&cx, x, 1, s, fl_, in_, sink_, true) : span_fast(&cx, x, 1, s, fl_, in_, sink_, false); \
        return;                                                                                            \
    }
    FAST_VARIANTS(PIXEL_FAST)
#undef PIXEL_FAST
}

/* Inside a polar cap: each pixel's own position, drawn alone. */
static void polar_pixels(const psc_frame_t *f, const row_setup_t *rs, unsigned x, unsigned n)
{
    for (unsigned i = 0; i < n; i++) {
        bool polar;
        map_pos_t p = point_pos(f, rs, half_pixel_x(f, x + i), &polar);
        if (uses_fast_spans(f) && f->v->addr.wraps) {   /* (a partial map's: the general sampler clamps its edges) */
            pixel_fast(f, x + i, p);
        } else {
            span_t s = {p.row, 0, 0, p.t};
            span_general(f, rs, x + i, 1, s, half_pixel_x(f, x + i));
        }
    }
}

/* The spans of a scanline from pixel x0 on through one specialised span_fast. */
static PSC_ALWAYS_INLINE void spans_fast(const psc_frame_t *f, const row_setup_t *rs, unsigned count, unsigned x0,
                                         const psc_filter_t filter, const psc_pixfmt_t in, const psc_sink_t sink,
                                         const bool pow2)
{
    const fast_ctx_t cx = fast_ctx(f);
    const unsigned w = f->v->out_width, n = f->span;
    const uint8_t *polar = f->work.polar;
    for (unsigned k = x0 / n, x = k * n; k + 1u < count; k++, x += n) {
        unsigned len = w - x < n ? w - x : n, skip = x0 > x ? x0 - x : 0u;
        uint8_t p = polar[k] | polar[k + 1u];
        if (p & POLAR_CAP) {
            polar_pixels(f, rs, x + skip, len - skip);
            continue;
        }
        if (p) {   /* near a partial map's edge: its positions, through the general sampler */
            span_general(f, rs, x + skip, len - skip, span_from(f, k, len, skip),
                         2 * (int32_t)x + (int32_t)len - (int32_t)w);
            continue;
        }
        span_fast(&cx, x + skip, len - skip, span_from(f, k, len, skip), filter, in, sink, pow2);
    }
}

static void spans_fast_dispatch(const psc_frame_t *f, const row_setup_t *rs, unsigned count, unsigned x0)
{
    const bool pow2 = f->v->col_shift != 0;
#define SPANS_FAST(fl_, in_, sink_)                                                                                 \
    if (f->filter == fl_ && f->v->map->format == in_ && f->sink == sink_) {                                         \
        pow2 ? spans_fast(f, rs, count, x0, fl_, in_, sink_, true) : spans_fast(f, rs, count, x0, fl_, in_, sink_, false); \
        return;                                                                                                     \
    }
    FAST_VARIANTS(SPANS_FAST)
#undef SPANS_FAST
}

/*
 * The vector kernel's share of a scanline (psc_viewer_simd.h): pixels
 * [0, returned) when every span is N long and none is polar; the scalar
 * spans draw the rest.
 */
static unsigned row_vector(const psc_frame_t *f, const row_setup_t *rs)
{
    const psc_viewer_t *v = f->v;
    if (!f->simd || rs->any_polar || v->out_width % f->span != 0)
        return 0;
    const psc_simd_row_t job = {v->map->pixels, v->row_offsets, v->map->palette, f->work.row, f->work.t, f->dst,
                                v->out_width, f->view->span_log2, v->col_shift, v->half_col_bam,
                                v->map->height, v->map->stride,
                                f->filter == PSC_FILTER_BILINEAR, (uint8_t)v->map->format, f->sink == PSC_SINK_RGB565,
                                v->col_width};
    return f->simd->row(&job);
}

/*
 * Ask the cache for the map lines the scanline's samples fall on (every
 * 16 map bytes' worth of pixels; bilinear also the row below), so that they arrive while
 * the previous scanline is drawn: a frame of a new view finds little of its
 * map in the cache, and the scanline's gathers are not a pattern the
 * hardware prefetchers follow.
 */
/*
 * PSC_FILTER_MIP: the lines of the two levels around the scanline's middle
 * (the level changes little along a scanline), as psc_span_mip addresses them.
 */
static void prefetch_levels(const psc_frame_t *f, const row_setup_t *rs, unsigned count)
{
    const psc_viewer_t *v = f->v;
    const unsigned top = v->level_count - 1u, step = pf_step(f), sh = v->col_shift;
    if (sh == 0)
        return;
    int32_t lod_q8 = lod_q8_at(f, rs, 0);
    unsigned lv = lod_q8 < 0 ? 0u : (unsigned)lod_q8 >> 8;
    lv = lv > top ? top : lv;
    const unsigned lv2 = lv < top ? lv + 1u : top, bpp = psc_pixfmt_bytes(v->map->format);
    const psc_envmap_t *a = &v->levels[lv], *b = &v->levels[lv2];
    const int32_t *row = f->work.row;
    const uint32_t *t = f->work.t;
    for (unsigned k = 0; k < count; k += step) {
        int32_t ra = ((row[k] + 32768) >> lv) >> 16, rb = ((row[k] + 32768) >> lv2) >> 16;
        uint32_t ca = t[k] >> (sh + lv), cb = t[k] >> (sh + lv2);
        __builtin_prefetch((const uint8_t *)a->pixels + (size_t)(ra < 0 ? 0 : ra) * a->stride + (size_t)ca * bpp);
        __builtin_prefetch((const uint8_t *)b->pixels + (size_t)(rb < 0 ? 0 : rb) * b->stride + (size_t)cb * bpp);
    }
}

static void prefetch_samples(const psc_frame_t *f, const row_setup_t *rs, unsigned count)
{
    const psc_viewer_t *v = f->v;
    if (f->mip && f->sink != PSC_SINK_TRACE) {
        if (!f->tiles)
            prefetch_levels(f, rs, count);
        return;
    }
    if (!uses_fast_spans(f))
        return;
    const uint8_t *base = v->map->pixels;
    const uint32_t *rowoff = v->row_offsets, bpp = psc_pixfmt_bytes(v->map->format), w = v->col_width;
    const unsigned step = pf_step(f);
    const bool bilinear = f->filter == PSC_FILTER_BILINEAR;
    const int32_t *row = f->work.row;
    const uint32_t *t = f->work.t, sh = v->col_shift, round = bilinear ? 65536u : 65536u + 32768u;
    const uint32_t last = v->map->width - 1u;   /* (a partial map's samples beyond its edges) */
    /* the kernel did samples [0, p) and [count - p, count) */
    for (unsigned k = rs->prefetched, end = count - rs->prefetched; k < end; k += step) {
        uint32_t r = ((uint32_t)row[k] + round) >> 16;
        uint32_t c = sh ? t[k] >> sh : (uint32_t)((uint64_t)t[k] * w >> 32);
        c = c < last ? c : last;
        const uint8_t *p = base + (size_t)c * bpp;
        __builtin_prefetch(p + rowoff[r]);
        if (bilinear)
            __builtin_prefetch(p + rowoff[r + 1u]);
    }
}

/*
 * The vector kernel's share of a PSC_FILTER_MIP scanline, as row_vector's:
 * pixels [0, returned), each span's levels from its middle pixel's level of
 * detail (psc_span_mip's choice).
 */
static unsigned mip_vector(const psc_frame_t *f, const row_setup_t *rs, unsigned count)
{
    const psc_viewer_t *v = f->v;
    /* a tiled map's pyramid, and its nearest and bilinear scanlines past level 0 (each span at the finest level
     * with at most two texels a pixel, psc_span_tiled's choice): through the tiled kernel */
    const bool tiled = f->tiles && f->simd && f->tiles->format != PSC_PIX_PAL8;
    if (!(f->simd_mip || tiled) || f->sink == PSC_SINK_TRACE || rs->any_polar || v->out_width % f->span != 0 ||
        !v->addr.wraps)   /* (a partial panorama's tiles: the general sampler's spans) */
        return 0;
    const unsigned n = f->span, top = v->level_count - 1u, spans = count - 1u;
    const int32_t w = (int32_t)v->out_width;
    uint32_t *lod = f->work.lod;
    for (unsigned k = 0; 2u * k < spans; k++) { /* span k and its mirror spans - 1 - k share a level */
        int32_t lod_q8 = lod_q8_at(f, rs, 2 * (int32_t)(k * n) + (int32_t)n - w);
        uint32_t level = lod_q8 < 0 ? 0u : (uint32_t)lod_q8 >> 8, frac = lod_q8 < 0 ? 0u : (uint32_t)lod_q8 & 255u;
        if (!f->mip) {   /* one level, no blend */
            int32_t fit_q8 = lod_q8 - MIP_LOD_BIAS_Q8;
            level = fit_q8 < 256 ? 0u : (uint32_t)fit_q8 >> 8;
            frac = 0;
        }
        if (level >= top) {
            level = top;
            frac = 0;
        }
        uint32_t next = level < top ? level + 1u : top;
        lod[k] = lod[spans - 1u - k] = level | next << 8 | frac << 16;
    }
    lod[spans] = lod[spans - 1u]; /* read by the lanes beyond the last span, unused */
    const psc_simd_mip_t job = {tiled ? NULL : v->levels[0].pixels, f->level_off, f->level_stride, f->level_hmax,
                                v->map->palette, f->work.row, f->work.t, f->work.lod, f->dst, v->out_width,
                                f->view->span_log2, v->col_shift, v->half_col_bam, v->col_width - 1u,
                                (uint8_t)v->map->format, f->sink == PSC_SINK_RGB565};
    if (!tiled)
        return f->simd->mip(&job);
    /* the groups the kernel could not draw (a texel in an absent tile), listed in the composite LUT row's room:
     * drawing never reads it (without a polar cap, the case here) */
    uint16_t *miss = (uint16_t *)(void *)f->work.lut_row;
    uint32_t misses = 0;
    psc_simd_mip_tiled_t tj = {job,  f->tiles->resident, f->tile_first, f->tile_cols, f->tiles->tile_stride, miss,
                               &misses, NULL, 0,  f->filter == PSC_FILTER_NEAREST && !f->mip};
    /* the levels the scanline reads: from its ends' level to its middle's next (the level of detail grows from the
     * ends to the middle) */
    const uint32_t lo = lod[0] & 255u, hi = (lod[spans / 2u] >> 8) & 255u, used = (2u << hi) - (1u << lo);
    const unsigned lanes = f->simd->lanes;
    unsigned done;
    if (used & f->tile_levels) {
        done = f->simd->mip_tiled(&tj);
    } else {   /* no tile of the levels it reads is resident (a pack just opened): every group would miss */
        done = v->out_width - v->out_width % lanes;
        for (unsigned g = 0; g < done / lanes; g++)
            miss[misses++] = (uint16_t)g;
    }
    if (misses == 0)
        return done;
    /* The groups with a texel in an absent tile: each span they touch (the whole span, as the scalar spans decide
     * for it) takes the scalar spans' choice (psc_tiled_span_level: the tiles asked for, the finest coarser level
     * resident over the span meanwhile) into its lod entry, and the groups of those spans are drawn again by the
     * kernel at those levels; a span whose texels must be looked up one by one goes to the scalar spans whole,
     * with the groups it shares. */
    const unsigned groups = v->out_width / lanes;
    uint16_t *again = miss + groups + 1u, *left = again + groups + 1u;
    uint32_t n_again = 0, next = 0;   /* next: the first pixel no missed group's span has reached */
    for (uint32_t i = 0; i < misses; i++) {
        /* the pixels of the spans group miss[i] touches, whole: [a, b) */
        unsigned a = miss[i] * lanes / n * n, b = ((miss[i] + 1u) * lanes + n - 1u) / n * n;
        a = a < next ? next : a;
        if (a >= b)
            continue;
        next = b;
        bool ok = true;
        for (unsigned k = a / n; k * n < b && ok; k++) {
            span_t s = span_at(f, k, n);
            ok = psc_tiled_span_level(f, s.row, s.t, s.drow, s.dt, n, &lod[k]);   /* (its own levels on entry) */
        }
        if (ok)
            for (unsigned gi = a / lanes; gi < b / lanes; gi++)
                again[n_again++] = (uint16_t)gi;
        else
            pixels_general(f, rs, a, b);
    }
    if (n_again) {
        uint32_t n_left = 0;
        tj.misses = &n_left;
        tj.miss = left;   /* (none expected: every tile those levels read is resident) */
        tj.only = again;
        tj.only_n = n_again;
        f->simd->mip_tiled(&tj);
        for (uint32_t i = 0; i < n_left; i++)
            pixels_general(f, rs, left[i] * lanes / n * n, ((left[i] + 1u) * lanes + n - 1u) / n * n);
    }
    return done;
}

/* One scanline's samples, ready to draw. */
typedef struct {
    row_setup_t rs;
    unsigned count;
} scan_line_t;

/*
 * A partial map's fast spans address it as a window of a full turn (col_width columns): a span is fast only where
 * both its ends lie two columns or more inside the map's left and right edges (positions move linearly along a
 * span), so that no texel it reads is past them. The samples nearer an edge, or beyond it, are marked MAP_EDGE:
 * their spans go pixel by pixel through the general sampler, which clamps, at the spans' own positions.
 */
static void mark_edges(const psc_frame_t *f, row_setup_t *rs, unsigned count)
{
    const uint32_t margin = f->v->edge_margin, inner = f->v->edge_inner;   /* (psc_viewer_init's) */
    const uint32_t *t = f->work.t;
    uint8_t *polar = f->work.polar, any = 0;
    for (unsigned k = 0; k < count; k++) {
        uint8_t edge = t[k] - margin >= inner ? MAP_EDGE : 0u;   /* (t = lon - lon_min: high left of it) */
        polar[k] |= edge;
        any |= edge;
    }
    rs->any_polar |= any;
}

static void scanline_prepare(const psc_frame_t *f, unsigned y, scan_line_t *l)
{
    row_setup(f, y, &l->rs);
    l->count = build_samples(f, &l->rs);
    /* the scanline's middle has its largest level of detail (its pixels' footprints shrink outwards): level 0
     * there is level 0 throughout, and its spans need no level of their own */
    l->rs.tiled_level0 = f->tiles && f->v->addr.wraps && !f->mip && lod_q8_at(f, &l->rs, 0) - MIP_LOD_BIAS_Q8 < 256;
    if (!f->v->addr.wraps && uses_fast_spans(f))
        mark_edges(f, &l->rs, l->count);
}

/*
 * A tiled map's nearest or bilinear scanline at level 0: each boundary
 * keyed by the tile it lies safely inside (psc_tiles_boundary_keys), each
 * run of spans between boundaries of one resident tile drawn by one loop
 * (psc_tiled_run0); the other spans (across a tile's edge, an absent tile, a
 * polar cap) one by one.
 */
/*
 * The vector kernel's tiled row (psc_viewer_simd.h): every group of lanes
 * inside one resident tile drawn by it, the others (across a tile's edge, an
 * absent tile) and the row's tail through the spans. Where the kernel cannot
 * serve the scanline (a polar cap, uneven spans, no kernel), false.
 */
static bool scanline_tiled0_vector(const psc_frame_t *f, const scan_line_t *l)
{
    const psc_viewer_t *v = f->v;
    const psc_tiles_t *g = f->tiles;
    if (!f->simd || l->rs.any_polar || v->out_width % f->span != 0 || !v->addr.wraps || g->format == PSC_PIX_PAL8)
        return false;
    uint16_t *miss = (uint16_t *)(void *)f->work.lod;   /* (the pyramid's levels, unused at level 0) */
    uint32_t misses = 0;
    const psc_simd_row_tiled_t job = {
        {NULL, NULL, NULL, f->work.row, f->work.t, f->dst, v->out_width, f->view->span_log2, v->col_shift,
         v->half_col_bam, g->level[0].height, g->tile_stride, f->filter == PSC_FILTER_BILINEAR, (uint8_t)g->format,
         f->sink == PSC_SINK_RGB565, g->level[0].width},
        g->resident, g->level[0].tiles_x, miss, &misses};
    const unsigned done = f->simd->row_tiled(&job), lanes = f->simd->lanes, n = f->span;
    /* a missed group's spans again through the scalar spans, whole (they decide span by span) */
    for (uint32_t i = 0, last_b = 0; i < misses; i++) {
        unsigned a = miss[i] * lanes / n * n, b = ((miss[i] + 1u) * lanes + n - 1u) / n * n;
        a = a < last_b ? last_b : a;
        if (a < b)
            pixels_general(f, &l->rs, a, b);
        last_b = b > last_b ? b : last_b;
    }
    pixels_general(f, &l->rs, done, v->out_width);
    return true;
}

static void scanline_tiled0(const psc_frame_t *f, const scan_line_t *l)
{
    if (scanline_tiled0_vector(f, l))
        return;
    const row_setup_t *rs = &l->rs;
    const unsigned w = f->v->out_width, n = f->span, count = l->count;
    const uint8_t *polar = f->work.polar;
    const void *const *resident = f->tiles->resident;
    const uint32_t tiles_x = f->tiles->level[0].tiles_x;
    uint32_t *key = f->work.lod;   /* (the vector pyramid's, unused by tiled maps) */
    psc_tiles_boundary_keys(f, count, key);
    for (unsigned k = 0, x = 0; k + 1u < count;) {
        unsigned len = w - x < n ? w - x : n;
        uint32_t kk = key[k];
        const void *tile = kk == PSC_TILES_NO_TILE || key[k + 1u] != kk ? NULL
                                                                        : resident[(kk >> 16) * tiles_x + (kk & 0xFFFFu)];
        if (polar[k] | polar[k + 1u]) {
            polar_pixels(f, rs, x, len);
        } else if (!tile) {
            span_general(f, rs, x, len, span_at(f, k, len), 2 * (int32_t)x + (int32_t)len - (int32_t)w);
        } else {   /* a run: spans whose both ends lie in this tile, none polar */
            unsigned k1 = k + 1u;
            while (k1 + 1u < count && key[k1 + 1u] == kk && !(polar[k1] | polar[k1 + 1u]))
                k1++;
            unsigned x1 = k1 * n < w ? k1 * n : w;
            psc_tiled_run0(f, (const uint8_t *)tile, (kk >> 16) * tiles_x + (kk & 0xFFFFu), k, k1, x, x1);
            k = k1, x = x1;
            continue;
        }
        k++, x += len;
    }
}

static void scanline_draw(const psc_frame_t *f, const scan_line_t *l)
{
    const row_setup_t *rs = &l->rs;
    if (uses_fast_spans(f)) {
        spans_fast_dispatch(f, rs, l->count, row_vector(f, rs));
        return;
    }
    if (f->tiles && rs->tiled_level0 && f->sink != PSC_SINK_TRACE) {
        scanline_tiled0(f, l);
        return;
    }
    const unsigned w = f->v->out_width, n = f->span, x0 = mip_vector(f, rs, l->count);
    for (unsigned k = x0 / n, x = k * n; k + 1u < l->count; k++, x += n) {
        unsigned len = w - x < n ? w - x : n, skip = x0 > x ? x0 - x : 0u;
        if (f->work.polar[k] | f->work.polar[k + 1u]) {
            polar_pixels(f, rs, x + skip, len - skip);
            continue;
        }
        span_general(f, rs, x + skip, len - skip, span_from(f, k, len, skip), 2 * (int32_t)x + (int32_t)len - (int32_t)w);
    }
}

void psc_scanline_render(const psc_frame_t *f, unsigned y)
{
    scan_line_t l;
    scanline_prepare(f, y, &l);
    scanline_draw(f, &l);
}

void psc_scan_rows(const psc_frame_t *f, unsigned y0, unsigned y1, uint8_t *dst0, size_t stride)
{
    /* Two frames differing only in their workspace: the next scanline is
     * prepared (and its map lines prefetched) before this one is drawn. */
    psc_frame_t fr[2] = {*f, *f};
    fr[1].work = f->work_next;
    scan_line_t line[2];
    if (y0 < y1)
        scanline_prepare(&fr[0], y0, &line[0]);
    for (unsigned y = y0, cur = 0; y < y1; y++, cur ^= 1u) {
        if (y + 1u < y1) {
            scanline_prepare(&fr[cur ^ 1u], y + 1u, &line[cur ^ 1u]);
            prefetch_samples(&fr[cur ^ 1u], &line[cur ^ 1u].rs, line[cur ^ 1u].count);
        }
        fr[cur].dst = dst0 + (size_t)(y - y0) * stride;
        scanline_draw(&fr[cur], &line[cur]);
    }
}
