/*
 * psc_viewer.c - set-up and the scanline renderer (see psc_viewer.h).
 *
 * One output scanline at a time:
 *   1. its LUT angle a = pitch + v[y] picks two LUT rows and a blend weight;
 *   2. every N-th pixel reads the LUT (bilinear over those rows and the two
 *      columns around u = x * u_step[y]), reflects the octant, adds the yaw
 *      and converts the angles to a map (row, col);
 *   3. the pixels in between interpolate (row, col) linearly, the column
 *      taking the short way round the 360 degree seam;
 *   4. near the poles, where polar angles bend too fast for linear interpolation,
 *      spans read the LUT at every pixel, and in the small cap where even the
 *      LUT's cells are too coarse, pixels are computed exactly with CORDIC.
 */
#include "psc_viewer_internal.h"

/* 2^32 / (2 pi): binary-angle units per radian. */
#define BAM_PER_RAD INT64_C(683565276)
/* (pi/2) * 2^24: a quarter turn in Q8.24 radians. */
#define QUARTER_TURN_Q24 INT64_C(26353589)
#define MIN_OUT_DIM 8u
/*
 * Level-of-detail bias for PSC_FILTER_MIP, Q8 levels: the [1 3 3 1] pyramid
 * filter followed by bilinear reconstruction is wider than a pixel's own
 * footprint, so the sharpest alias-free choice is 0.625 level finer than the
 * footprint. Measured (tests/test_mip.c, 4096x2048 sample, hfov 120, against a
 * 4x4-supersampled reference): bias 0 gains +0.1 dB over bilinear, -0.5 gains
 * +6.3/+7.5 dB, -0.625 +7.1/+7.3 dB, -0.75 +6.4/+6.2 dB.
 */
#ifndef MIP_LOD_BIAS_Q8
#define MIP_LOD_BIAS_Q8 (-160)
#endif

/* ---- workspace ------------------------------------------------------------ */

typedef struct {
    size_t scan, lat_table, row_width, palette565, total;
} ws_layout_t;

static size_t align8(size_t n) { return (n + 7u) & ~(size_t)7u; }

static ws_layout_t ws_layout(uint16_t out_height, const psc_envmap_t *m)
{
    ws_layout_t l = {0};
    size_t at = 0;
    l.scan = at;
    at += align8((size_t)out_height * sizeof(psc_scanline_t));
    l.lat_table = at;
    if (m->projection == PSC_PROJ_CYLINDER || m->projection == PSC_PROJ_SINE)
        at += align8(PSC_LAT_TABLE_SIZE * sizeof(int32_t));
    l.row_width = at;
    if (m->projection == PSC_PROJ_ELLIPTICAL || m->projection == PSC_PROJ_DIAMOND)
        at += align8((size_t)m->height * sizeof(int32_t));
    l.palette565 = at;
    if (m->format == PSC_PIX_PAL8)
        at += align8(256u * sizeof(uint16_t));
    l.total = at;
    return l;
}

size_t psc_viewer_workspace_size(uint16_t out_width, uint16_t out_height, const psc_envmap_t *m)
{
    (void)out_width;
    return m ? ws_layout(out_height, m).total : 0;
}

psc_status_t psc_viewer_init(psc_viewer_t *v, const psc_envmap_t *map, const psc_lut_t *luts,
                             unsigned lut_count, uint16_t out_width, uint16_t out_height, void *ws,
                             size_t ws_size)
{
    if (!v || !map || !luts || lut_count == 0 || lut_count > PSC_VIEWER_MAX_LUTS || !ws ||
        ((uintptr_t)ws & 7u) != 0)
        return PSC_ERR_ARG;
    if (out_width < MIN_OUT_DIM || out_height < MIN_OUT_DIM || out_width > PSC_MAX_OUT_DIM ||
        out_height > PSC_MAX_OUT_DIM)
        return PSC_ERR_ARG;
    psc_status_t s = psc_envmap_check(map);
    if (s != PSC_OK)
        return s;
    for (unsigned i = 0; i < lut_count; i++) {
        if ((s = psc_lut_check(&luts[i])) != PSC_OK)
            return s;
        if (i > 0 && luts[i].hfov_max <= luts[i - 1].hfov_max)
            return PSC_ERR_ARG;
    }
    ws_layout_t l = ws_layout(out_height, map);
    if (ws_size < l.total)
        return PSC_ERR_NOMEM;

    *v = (psc_viewer_t){0};
    v->map = map;
    psc_map_addressing_init(&v->addr, map);
    for (unsigned i = 0; i < lut_count; i++)
        v->luts[i] = &luts[i];
    v->lut_count = (uint8_t)lut_count;
    v->out_width = out_width;
    v->out_height = out_height;
    v->levels = map;
    v->level_count = 1;
    /* 2 * rows per radian, Q16: rows per bam (Q32) times bam per radian. */
    v->lod_base_q8 = psc_log2_q8((uint64_t)((v->addr.row_per_bam_q32 * BAM_PER_RAD) >> 15)) - 16 * 256;
    uint8_t *base = ws;
    v->scan = (psc_scanline_t *)(void *)(base + l.scan);
    if (l.row_width != l.lat_table) {
        v->lat_to_row = (int32_t *)(void *)(base + l.lat_table);
        psc_lat_table_init(v->lat_to_row, map);
    }
    if (l.palette565 != l.row_width) {
        v->row_width_q16 = (int32_t *)(void *)(base + l.row_width);
        psc_row_width_init(v->row_width_q16, map);
    }
    if (l.total != l.palette565) {
        v->palette565 = (uint16_t *)(void *)(base + l.palette565);
        for (unsigned i = 0; i < 256; i++)
            v->palette565[i] = psc_xrgb_to_rgb565(map->palette[i]);
    }
    return PSC_OK;
}

psc_status_t psc_viewer_set_levels(psc_viewer_t *v, const psc_envmap_t *levels, unsigned count)
{
    if (!v || !levels || count == 0 || count > PSC_VIEWER_MAX_LEVELS)
        return PSC_ERR_ARG;
    const psc_envmap_t *m = v->map;
    for (unsigned k = 0; k < count; k++) {
        const psc_envmap_t *l = &levels[k];
        if (l->projection != m->projection || l->format != m->format || l->lon_min != m->lon_min ||
            l->lon_span != m->lon_span || l->lat_top != m->lat_top || l->lat_bottom != m->lat_bottom ||
            ((uint32_t)l->width << k) != m->width || ((uint32_t)l->height << k) != m->height || !l->pixels ||
            l->stride < (uint32_t)l->width * psc_pixfmt_bytes(l->format) ||
            (m->format == PSC_PIX_PAL8 && l->palette != m->palette))
            return PSC_ERR_ARG;
    }
    v->levels = levels;
    v->level_count = (uint8_t)count;
    return PSC_OK;
}

psc_bam_t psc_viewer_hfov_max(const psc_viewer_t *v)
{
    return v->luts[v->lut_count - 1]->hfov_max;
}

/* ---- zoom: the per-scanline scale-factor table ------------------------------ */

void psc_viewer_set_zoom(psc_viewer_t *v, psc_bam_t hfov)
{
    const psc_lut_t *lut = v->luts[v->lut_count - 1];
    for (unsigned i = 0; i < v->lut_count; i++) {
        if (v->luts[i]->hfov_max >= hfov) {
            lut = v->luts[i];
            break;
        }
    }
    if (hfov == v->cached_hfov && lut == v->cached_lut)
        return;
    /* Distance to the viewing plane in half-pixels: W / tan(hfov / 2), Q24.8. */
    int32_t s, c;
    psc_sincos(hfov / 2u, &s, &c);
    v->dist_q8 = (uint32_t)psc_div_round64((int64_t)v->out_width * c * 256, s);
    uint64_t cols1 = lut->cols - 1u;
    for (unsigned y = 0; y < v->out_height; y++) {
        int32_t yc = (int32_t)v->out_height - 1 - 2 * (int32_t)y; /* half-pixels, up */
        uint32_t mag_q8;                                          /* sqrt(yc^2 + d^2), Q8 */
        v->scan[y].v = (int32_t)psc_atan2(yc * 256, (int32_t)v->dist_q8, &mag_q8);
        /* u = x cos(v) / d = x / sqrt(y^2 + d^2): LUT columns per half-pixel,
         * (cols-1) / (u_max * mag), Q8.24, in two exact-enough divisions. */
        uint64_t t = (cols1 << 40) / mag_q8;
        uint64_t step = ((t << 16) + lut->u_max_q24 / 2u) / lut->u_max_q24;
        v->scan[y].u_step_q24 = step > UINT32_MAX ? UINT32_MAX : (uint32_t)step;
        v->scan[y].mag_q8 = mag_q8;
    }
    v->cached_hfov = hfov;
    v->cached_lut = lut;
}

/* ---- frame set-up: the polar caps --------------------------------------------- */

/*
 * Interpolating polar angles over a step of s radians at a distance e from a
 * pole is off by about s^2 / (8 e) (the chord bows away from the pole).
 * Returns the latitude beyond which that exceeds 1/POLE_TOLERANCE_DIV map pixel,
 * with s added so that a step whose ends are outside cannot pass over it.
 */
#define POLE_TOLERANCE_DIV 4 /* tolerance: a quarter of a map pixel */
static int32_t polar_cap_lat(const psc_viewer_t *v, int64_t s_q24)
{
    int64_t full_turn_cols = v->addr.col_per_bam_q32; /* map columns per turn */
    int64_t tol = (4 * QUARTER_TURN_Q24) / (POLE_TOLERANCE_DIV * full_turn_cols); /* Q8.24 rad */
    if (tol < 1)
        tol = 1;
    int64_t e = (s_q24 * s_q24) / (8 * tol) + s_q24;
    if (e >= QUARTER_TURN_Q24)
        return 0; /* everything */
    int64_t cap = (e * BAM_PER_RAD) >> 24;
    return (int32_t)(PSC_BAM_90 - (uint32_t)cap);
}

/* Angle between two pixels n apart at the view's centre: 2n / dist, Q8.24 rad. */
static int64_t pixel_step_q24(const psc_viewer_t *v, unsigned n)
{
    return ((int64_t)n << 33) / v->dist_q8;
}

/* The two caps: where the LUT's own cells are too coarse (exact CORDIC per
 * pixel), and where only the span interpolation is (LUT read per pixel). */
static void polar_caps(const psc_viewer_t *v, const psc_lut_t *lut, unsigned span, int32_t *exact, int32_t *per_pixel)
{
    int64_t cell = QUARTER_TURN_Q24 / (lut->rows - 1);
    int64_t cell_u = (int64_t)lut->u_max_q24 / (lut->cols - 1);
    if (cell_u > cell)
        cell = cell_u;
    int64_t one = pixel_step_q24(v, 1), s = pixel_step_q24(v, span);
    *exact = polar_cap_lat(v, cell > one ? cell : one);
    *per_pixel = polar_cap_lat(v, s > cell ? s : cell);
}

/* ---- LUT sampling ------------------------------------------------------------- */

typedef struct {
    const uint32_t *e0, *e1; /* the two bounding LUT rows */
    uint32_t fr;             /* blend weight of e1, Q0.8 (0..256) */
    bool lat_negative;       /* scanline below the horizon of the LUT's frame */
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

/* Angles of pixel x from the LUT: bilinear over two rows and two columns, Q0.8 weights. */
static psc_angles_t lut_angles(const psc_frame_t *f, const row_setup_t *rs, unsigned x)
{
    int32_t xc = 2 * (int32_t)x + 1 - (int32_t)f->v->out_width;
    uint32_t ax = xc < 0 ? (uint32_t)-xc : (uint32_t)xc;
    uint32_t pos = (uint32_t)(((uint64_t)ax * rs->u_step_q24 + (1u << 15)) >> 16); /* Q8 columns */
    uint32_t c0 = pos >> 8, fc = pos & 255u, cols = f->lut->cols;
    if (c0 >= cols - 1u) {
        c0 = cols - 2u;
        fc = 256;
    }
    uint32_t a = rs->e0[c0], b = rs->e0[c0 + 1], c = rs->e1[c0], d = rs->e1[c0 + 1];
    uint32_t ic = 256u - fc, ir = 256u - rs->fr;
    /* Each sum stays below 2^32: 65535 * 256 * 256 < 2^32. */
    uint32_t lon = (PSC_LUT_LON(a) * ic + PSC_LUT_LON(b) * fc) * ir + (PSC_LUT_LON(c) * ic + PSC_LUT_LON(d) * fc) * rs->fr;
    uint32_t lat = (PSC_LUT_LAT(a) * ic + PSC_LUT_LAT(b) * fc) * ir + (PSC_LUT_LAT(c) * ic + PSC_LUT_LAT(d) * fc) * rs->fr;
    /* Units of 90deg / 2^32; a binary angle is 90deg / 2^30. */
    psc_angles_t out;
    uint32_t lon_bam = (lon >> 2) + ((lon >> 1) & 1u), lat_bam = (lat >> 2) + ((lat >> 1) & 1u);
    if (rs->over_pole)
        lon_bam = PSC_BAM_180 - lon_bam;
    if (xc < 0)
        lon_bam = (uint32_t)0 - lon_bam;
    out.lon = f->view->yaw + lon_bam;
    out.lat = rs->lat_negative ? -(int32_t)lat_bam : (int32_t)lat_bam;
    return out;
}

/* ---- per-pixel output ------------------------------------------------------- */

typedef struct {
    int32_t row, col; /* map position, Q16.16 */
    bool polar;       /* inside a polar cap: no span interpolation from here */
} sample_t;

static sample_t position_of(const psc_frame_t *f, psc_bam_t lon, int32_t lat)
{
    sample_t s;
    s.row = psc_map_row_q16(f->v, lat);
    s.col = psc_map_col_q16(f->v, lon);
    s.polar = false;
    return s;
}

static sample_t exact_sample(const psc_frame_t *f, const row_setup_t *rs, unsigned x)
{
    psc_bam_t lon;
    int32_t lat;
    psc_exact_angles(f, 2 * (int32_t)x + 1 - (int32_t)f->v->out_width, rs->yc, &lon, &lat);
    sample_t s = position_of(f, lon, lat);
    s.polar = true;
    return s;
}

static sample_t lut_sample(const psc_frame_t *f, const row_setup_t *rs, unsigned x)
{
    psc_angles_t a = lut_angles(f, rs, x);
    int32_t abs_lat = a.lat < 0 ? -a.lat : a.lat;
    if (abs_lat >= f->cap_exact)
        return exact_sample(f, rs, x);
    sample_t s = position_of(f, a.lon, a.lat);
    s.polar = abs_lat >= f->cap_per_pixel;
    return s;
}

/* ---- the fast spans: full-turn rectangular maps -------------------------------- */

/*
 * One span of n pixels from (row, col) in steps (drow, dcol), for one
 * combination of filter, map format and sink, all compile-time constants
 * once inlined (so each combination is its own tight loop).
 * col stays in [0, W << 16): the map wraps.
 */
static PSC_ALWAYS_INLINE void span_fast(const psc_frame_t *f, unsigned x, unsigned n, int32_t row,
                                        int32_t col, int32_t drow, int32_t dcol, const psc_filter_t filter,
                                        const psc_pixfmt_t in, const psc_sink_t sink)
{
    const psc_envmap_t *m = f->v->map;
    const uint8_t *base = m->pixels;
    const uint32_t stride = m->stride;
    const int32_t w = m->width, hmax = m->height - 1, wq = w << 16;
    const uint32_t *pal = m->palette;
    const uint16_t *pal565 = f->v->palette565;
    for (unsigned i = 0; i < n; i++, row += drow) {
        uint32_t px;     /* XRGB8888, or RGB565 when the sink is RGB565 and no blend is needed */
        bool px_is_565 = false;
        if (filter == PSC_FILTER_NEAREST) {
            int32_t r = (row + 32768) >> 16, c = (col + 32768) >> 16;
            r = r < 0 ? 0 : r > hmax ? hmax : r;
            if (c >= w)
                c = 0;
            const uint8_t *p = base + (size_t)r * stride;
            if (in == PSC_PIX_RGB565) {
                px = ((const uint16_t *)(const void *)p)[c];
                px_is_565 = true;
            } else if (in == PSC_PIX_XRGB8888) {
                px = ((const uint32_t *)(const void *)p)[c];
            } else if (sink == PSC_SINK_RGB565) {
                px = pal565[p[c]];
                px_is_565 = true;
            } else {
                px = pal[p[c]];
            }
        } else {
            int32_t r0 = row >> 16, c0 = col >> 16;
            uint32_t fr = ((uint32_t)row >> 8) & 255u, fc = ((uint32_t)col >> 8) & 255u;
            int32_t r1 = r0 + 1, c1 = c0 + 1 == w ? 0 : c0 + 1;
            if (r0 < 0) {
                r0 = r1 = 0;
                fr = 0;
            } else if (r0 >= hmax) {
                r0 = r1 = hmax;
            }
            const uint8_t *p0 = base + (size_t)r0 * stride, *p1 = base + (size_t)r1 * stride;
            uint32_t t00, t01, t10, t11;
            if (in == PSC_PIX_RGB565) {
                const uint16_t *a = (const uint16_t *)(const void *)p0, *b = (const uint16_t *)(const void *)p1;
                t00 = psc_rgb565_to_xrgb(a[c0]);
                t01 = psc_rgb565_to_xrgb(a[c1]);
                t10 = psc_rgb565_to_xrgb(b[c0]);
                t11 = psc_rgb565_to_xrgb(b[c1]);
            } else if (in == PSC_PIX_XRGB8888) {
                const uint32_t *a = (const uint32_t *)(const void *)p0, *b = (const uint32_t *)(const void *)p1;
                t00 = a[c0];
                t01 = a[c1];
                t10 = b[c0];
                t11 = b[c1];
            } else {
                t00 = pal[p0[c0]];
                t01 = pal[p0[c1]];
                t10 = pal[p1[c0]];
                t11 = pal[p1[c1]];
            }
            px = psc_blend4_xrgb(t00, t01, t10, t11, fc, fr);
        }
        if (sink == PSC_SINK_RGB565)
            ((uint16_t *)(void *)f->dst)[x + i] = px_is_565 ? (uint16_t)px : psc_xrgb_to_rgb565(px);
        else
            ((uint32_t *)(void *)f->dst)[x + i] = px_is_565 ? psc_rgb565_to_xrgb(px) : (px | 0xFF000000u);
        col += dcol;
        if (col >= wq)
            col -= wq;
        else if (col < 0)
            col += wq;
    }
}

/* Each (filter, map format, sink) gets its own instance of span_fast. */
#define SPAN_CASES(in)                                                                                     \
    do {                                                                                                   \
        if (bilinear)                                                                                      \
            to565 ? span_fast(f, x, n, row, col, drow, dcol, PSC_FILTER_BILINEAR, in, PSC_SINK_RGB565)     \
                  : span_fast(f, x, n, row, col, drow, dcol, PSC_FILTER_BILINEAR, in, PSC_SINK_XRGB8888);  \
        else                                                                                               \
            to565 ? span_fast(f, x, n, row, col, drow, dcol, PSC_FILTER_NEAREST, in, PSC_SINK_RGB565)      \
                  : span_fast(f, x, n, row, col, drow, dcol, PSC_FILTER_NEAREST, in, PSC_SINK_XRGB8888);   \
    } while (0)

static void span_dispatch(const psc_frame_t *f, unsigned x, unsigned n, int32_t row, int32_t col, int32_t drow,
                          int32_t dcol)
{
    const bool bilinear = f->filter == PSC_FILTER_BILINEAR;
    const bool to565 = f->sink == PSC_SINK_RGB565;
    switch (f->v->map->format) {
    case PSC_PIX_RGB565: SPAN_CASES(PSC_PIX_RGB565); break;
    case PSC_PIX_XRGB8888: SPAN_CASES(PSC_PIX_XRGB8888); break;
    case PSC_PIX_PAL8: SPAN_CASES(PSC_PIX_PAL8); break;
    }
}

/*
 * Map level of detail at pixel x of the scanline: log2 of map texels per
 * output pixel, Q24.8. A pixel at (x, y) half-pixels from the centre spans
 * 2 / sqrt(x^2 + y^2 + d^2) radians (across the ray; the shorter radial
 * extent would under-filter).
 */
static int32_t pixel_lod_q8(const psc_frame_t *f, const row_setup_t *rs, unsigned x)
{
    int64_t xc = 2 * (int64_t)x + 1 - f->v->out_width;
    uint64_t dist2_q16 = (uint64_t)rs->mag_q8 * rs->mag_q8 + (uint64_t)(xc * xc) * 65536u;
    return f->v->lod_base_q8 - (psc_log2_q8(dist2_q16) - 16 * 256) / 2 + MIP_LOD_BIAS_Q8;
}

static void put_pixel(const psc_frame_t *f, const row_setup_t *rs, unsigned x, int32_t row, int32_t col)
{
    if (f->sink == PSC_SINK_TRACE) {
        f->trace_row[x] = row;
        f->trace_col[x] = col;
        return;
    }
    if (f->mip) {
        psc_span_mip(f, x, 1, row, col, 0, 0, pixel_lod_q8(f, rs, x));
        return;
    }
    if (f->v->addr.fast) {
        span_dispatch(f, x, 1, row, col, 0, 0);
        return;
    }
    uint32_t px = psc_sample_general(f->v, f->filter, row, col);
    if (f->sink == PSC_SINK_RGB565)
        ((uint16_t *)(void *)f->dst)[x] = psc_xrgb_to_rgb565(px);
    else
        ((uint32_t *)(void *)f->dst)[x] = px;
}

/* ---- spans -------------------------------------------------------------------- */

/* Draw pixels [x, x + n) interpolating from sample a to sample b (n >= 1). */
static void draw_span(const psc_frame_t *f, const row_setup_t *rs, unsigned x, unsigned n, sample_t a, sample_t b)
{
    if (a.polar || b.polar) { /* near a pole: every pixel from the LUT (or exactly) */
        put_pixel(f, rs, x, a.row, a.col);
        for (unsigned i = 1; i < n; i++) {
            sample_t s = lut_sample(f, rs, x + i);
            put_pixel(f, rs, x + i, s.row, s.col);
        }
        return;
    }
    int32_t drow = b.row - a.row, dcol = b.col - a.col;
    if (f->v->addr.wraps) { /* the short way round the seam */
        int32_t wq = (int32_t)f->v->map->width << 16;
        if (dcol > wq / 2)
            dcol -= wq;
        else if (dcol < -(wq / 2))
            dcol += wq;
    }
    if (n == f->span) {
        unsigned k = f->view->span_log2;
        drow >>= k;
        dcol >>= k;
    } else {
        drow /= (int32_t)n;
        dcol /= (int32_t)n;
    }
    if (f->sink != PSC_SINK_TRACE && f->mip) {
        psc_span_mip(f, x, n, a.row, a.col, drow, dcol, pixel_lod_q8(f, rs, x + n / 2));
        return;
    }
    if (f->sink != PSC_SINK_TRACE && f->v->addr.fast) {
        span_dispatch(f, x, n, a.row, a.col, drow, dcol);
        return;
    }
    int32_t row = a.row, col = a.col, wq = (int32_t)f->v->map->width << 16;
    for (unsigned i = 0; i < n; i++) {
        put_pixel(f, rs, x + i, row, col);
        row += drow;
        col += dcol;
        if (f->v->addr.wraps) {
            if (col >= wq)
                col -= wq;
            else if (col < 0)
                col += wq;
        }
    }
}

static void render_scanline(const psc_frame_t *f, unsigned y)
{
    row_setup_t rs;
    row_setup(f, y, &rs);
    const unsigned w = f->v->out_width, last = w - 1u;
    unsigned x0 = 0;
    sample_t s0 = lut_sample(f, &rs, 0);
    for (;;) {
        if (x0 == last) {
            draw_span(f, &rs, x0, 1, s0, s0);
            return;
        }
        unsigned x1 = x0 + f->span < last ? x0 + f->span : last;
        sample_t s1 = lut_sample(f, &rs, x1);
        draw_span(f, &rs, x0, x1 - x0, s0, s1);
        x0 = x1;
        s0 = s1;
    }
}

/* ---- public entry points ------------------------------------------------------- */

static psc_status_t frame_begin(psc_viewer_t *v, const psc_view_t *view, psc_sink_t sink, psc_frame_t *f)
{
    if (!v || !view || view->span_log2 > PSC_SPAN_LOG2_MAX ||
        (view->filter != PSC_FILTER_NEAREST && view->filter != PSC_FILTER_BILINEAR && view->filter != PSC_FILTER_MIP) ||
        view->pitch > (int32_t)PSC_BAM_90 || view->pitch < -(int32_t)PSC_BAM_90 || view->hfov < PSC_HFOV_MIN ||
        view->hfov > psc_viewer_hfov_max(v))
        return PSC_ERR_ARG;
    psc_viewer_set_zoom(v, view->hfov);
    *f = (psc_frame_t){0};
    f->v = v;
    f->view = view;
    f->lut = v->cached_lut;
    f->span = 1u << view->span_log2;
    f->sink = sink;
    /* The pyramid applies to full-turn rectangular maps that have one. */
    f->mip = view->filter == PSC_FILTER_MIP && v->level_count > 1 && v->addr.fast;
    f->filter = view->filter == PSC_FILTER_MIP ? PSC_FILTER_BILINEAR : view->filter;
    psc_sincos((psc_bam_t)view->pitch, &f->sin_pitch, &f->cos_pitch);
    polar_caps(v, f->lut, f->span, &f->cap_exact, &f->cap_per_pixel);
    return PSC_OK;
}

psc_status_t psc_viewer_render(psc_viewer_t *v, const psc_view_t *view, const psc_surface_t *out)
{
    if (!out || !out->pixels || out->width != v->out_width || out->height != v->out_height)
        return PSC_ERR_ARG;
    if (out->format != PSC_PIX_RGB565 && out->format != PSC_PIX_XRGB8888)
        return PSC_ERR_UNSUPPORTED;
    if (out->stride < (uint32_t)out->width * psc_pixfmt_bytes(out->format))
        return PSC_ERR_ARG;
    psc_frame_t f;
    psc_status_t s = frame_begin(v, view, out->format == PSC_PIX_RGB565 ? PSC_SINK_RGB565 : PSC_SINK_XRGB8888, &f);
    if (s != PSC_OK)
        return s;
    for (unsigned y = 0; y < v->out_height; y++) {
        f.dst = (uint8_t *)out->pixels + (size_t)y * out->stride;
        render_scanline(&f, y);
    }
    return PSC_OK;
}

psc_status_t psc_viewer_trace_row(psc_viewer_t *v, const psc_view_t *view, uint16_t y, int32_t *row_q16,
                                  int32_t *col_q16)
{
    if (!row_q16 || !col_q16 || !v || y >= v->out_height)
        return PSC_ERR_ARG;
    psc_frame_t f;
    psc_status_t s = frame_begin(v, view, PSC_SINK_TRACE, &f);
    if (s != PSC_OK)
        return s;
    f.trace_row = row_q16;
    f.trace_col = col_q16;
    render_scanline(&f, y);
    return PSC_OK;
}
