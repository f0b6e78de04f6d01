/* SPDX-License-Identifier: MIT */
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
#include "viewer/psc_viewer_internal.h"

/* 2^32 / (2 pi): binary-angle units per radian. */
#define BAM_PER_RAD INT64_C(683565276)
/* (pi/2) * 2^24: a quarter turn in Q8.24 radians. */
#define QUARTER_TURN_Q24 INT64_C(26353589)
#define MIN_OUT_DIM 8u

/* ---- workspace ------------------------------------------------------------ */

typedef struct {
    size_t scan, lat_table, row_width, palette565, row_offsets, samples, total;
} ws_layout_t;

static size_t align8(size_t n) { return (n + 7u) & ~(size_t)7u; }

#define SCAN_SAMPLES(w) ((size_t)(w) + 2u) /* boundary samples of a scanline, at most */

/* Rectangular rows (a full turn or part of one): the fast samplers' maps. */
static bool map_is_fast(const psc_envmap_t *m)
{
    return m->projection == PSC_PROJ_EQUIRECT || m->projection == PSC_PROJ_CYLINDER || m->projection == PSC_PROJ_SINE;
}

static ws_layout_t ws_layout(uint16_t out_width, uint16_t out_height, const psc_envmap_t *m, bool tiled)
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
    l.row_offsets = at;
    /* rows -1 .. H, the outer two repeating the edge rows; a tiled map's hold rows within their tiles, then one
     * tile's rows -1 .. 256 (the vector kernels' view of a tile) */
    if (map_is_fast(m))
        at += align8(((size_t)m->height + 2u + (tiled ? PSC_TILE_SIDE + 2u : 0u)) * sizeof(uint32_t));
    l.samples = at;
    at += align8(psc_viewer_band_scratch_size(out_width));
    l.total = at;
    return l;
}

size_t psc_viewer_workspace_size(uint16_t out_width, uint16_t out_height, const psc_envmap_t *m)
{
    return m ? ws_layout(out_width, out_height, m, false).total : 0;
}

size_t psc_viewer_workspace_size_tiled(uint16_t out_width, uint16_t out_height, const psc_envmap_t *m)
{
    return m ? ws_layout(out_width, out_height, m, true).total : 0;
}

/* A tiled map's description against its tiles: the flat checks on a stand-in of a flat map's size (the coverage),
 * the tiles' level 0 size, format and palette, and a projection of rectangular rows (a full turn or part of one). */
static psc_status_t tiled_map_check(const psc_envmap_t *map, const psc_tiles_t *tiles)
{
    psc_envmap_t chk = *map;
    chk.pixels = map;
    chk.width = chk.height = 1;
    chk.stride = 4;
    psc_status_t s = psc_envmap_check(&chk);
    if (s != PSC_OK)
        return s;
    if (!tiles->resident || tiles->level_count == 0 || map->width != tiles->level[0].width ||
        map->height != tiles->level[0].height || map->format != tiles->format ||
        (map->format == PSC_PIX_PAL8 && map->palette != tiles->palette))
        return PSC_ERR_ARG;
    return map_is_fast(map) ? PSC_OK : PSC_ERR_UNSUPPORTED;
}

static psc_status_t init_common(psc_viewer_t *v, const psc_envmap_t *map, const psc_tiles_t *tiles,
                                const psc_lut_t *luts, unsigned lut_count, uint16_t out_width, uint16_t out_height,
                                void *ws, size_t ws_size)
{
    if (!v || !map || !luts || lut_count == 0 || lut_count > PSC_VIEWER_MAX_LUTS || !ws ||
        ((uintptr_t)ws & 7u) != 0)
        return PSC_ERR_ARG;
    if (out_width < MIN_OUT_DIM || out_height < MIN_OUT_DIM || out_width > PSC_MAX_OUT_DIM ||
        out_height > PSC_MAX_OUT_DIM)
        return PSC_ERR_ARG;
    psc_status_t s = tiles ? tiled_map_check(map, tiles) : psc_envmap_check(map);
    if (s != PSC_OK)
        return s;
    for (unsigned i = 0; i < lut_count; i++) {
        if ((s = psc_lut_check(&luts[i])) != PSC_OK)
            return s;
        if (i > 0 && luts[i].hfov_max <= luts[i - 1].hfov_max)
            return PSC_ERR_ARG;
    }
    ws_layout_t l = ws_layout(out_width, out_height, map, tiles != NULL);
    if (ws_size < l.total)
        return PSC_ERR_NOMEM;

    *v = (psc_viewer_t){0};
    v->map = map;
    v->tiles = tiles;
    psc_map_addressing_init(&v->addr, map);
    for (unsigned i = 0; i < lut_count; i++)
        v->luts[i] = &luts[i];
    v->lut_count = (uint8_t)lut_count;
    v->out_width = out_width;
    v->out_height = out_height;
    v->levels = map;
    v->level_count = tiles ? (uint8_t)tiles->level_count : 1u;
    /* 2 * rows per radian, Q16: rows per bam (Q32) times bam per radian. */
    v->lod_base_q8 = psc_log2_q8((uint64_t)((v->addr.row_per_bam_q32 * BAM_PER_RAD) >> 15)) - 16 * 256 + MIP_LOD_BIAS_Q8;
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
    if (l.row_offsets != l.palette565) {
        v->palette565 = (uint16_t *)(void *)(base + l.palette565);
        for (unsigned i = 0; i < 256; i++)
            v->palette565[i] = psc_xrgb_to_rgb565(map->palette[i]);
    }
    if (l.samples != l.row_offsets) {
        v->row_offsets = (uint32_t *)(void *)(base + l.row_offsets);
        for (int32_t r = -1; r <= (int32_t)map->height; r++) {
            int32_t c = r < 0 ? 0 : r >= (int32_t)map->height ? (int32_t)map->height - 1 : r;
            /* a tiled map: the row's offset within its tile (psc_viewer_tiles.c's level-0 spans) */
            v->row_offsets[r + 1] = tiles ? ((uint32_t)c & (PSC_TILE_SIDE - 1u)) * tiles->tile_stride
                                          : (uint32_t)c * map->stride;
        }
        if (tiles) {
            v->tile_row_offsets = v->row_offsets + map->height + 2u;
            for (int32_t r = -1; r <= (int32_t)PSC_TILE_SIDE; r++) {
                int32_t c = r < 0 ? 0 : r >= (int32_t)PSC_TILE_SIDE ? (int32_t)PSC_TILE_SIDE - 1 : r;
                v->tile_row_offsets[r + 1] = (uint32_t)c * tiles->tile_stride;
            }
        }
    }
    v->scratch = base + l.samples;
    psc_viewer_band_requests_clear(v->scratch, out_width);
    /* Columns from a binary angle: t x col_width / 2^32, a shift where col_width is a power of two. A partial
     * map is a window of a full turn of col_width columns (its own W x 2^32 / lon_span, < 2^32: W <= 65536 and
     * lon_span >= a degree), so its fast spans address it as a full turn away from its edges. */
    v->col_width = v->addr.wraps ? map->width : (uint32_t)v->addr.col_per_bam_q32;
    v->col_shift = 0;
    for (unsigned k = 1; k <= 31; k++)
        if (v->col_width == 1u << k)
            v->col_shift = (uint8_t)(32u - k);
    v->half_col_bam = (uint32_t)((((uint64_t)1 << 31) + v->col_width / 2u) / v->col_width);
    /* a partial map's fast spans: two columns (rounded up) and one inside either edge (psc_viewer_scan.c's
     * mark_edges); in 64 bits, as a column of a map one column wide is the whole turn; a map a few columns wide
     * has no inside */
    uint64_t margin = 2u * ((((uint64_t)1 << 32) + v->col_width - 1u) / v->col_width) + 1u, span = map->lon_span;
    v->edge_inner = span > 2u * margin ? (uint32_t)(span - 2u * margin) : 0u;
    v->edge_margin = v->edge_inner ? (uint32_t)margin : 0u;
    return PSC_OK;
}

psc_status_t psc_viewer_init(psc_viewer_t *v, const psc_envmap_t *map, const psc_lut_t *luts,
                             unsigned lut_count, uint16_t out_width, uint16_t out_height, void *ws,
                             size_t ws_size)
{
    return init_common(v, map, NULL, luts, lut_count, out_width, out_height, ws, ws_size);
}

psc_status_t psc_viewer_init_tiled(psc_viewer_t *v, const psc_envmap_t *map, const psc_tiles_t *tiles,
                                   const psc_lut_t *luts, unsigned lut_count, uint16_t out_width,
                                   uint16_t out_height, void *ws, size_t ws_size)
{
    if (!tiles)
        return PSC_ERR_ARG;
    return init_common(v, map, tiles, luts, lut_count, out_width, out_height, ws, ws_size);
}

psc_status_t psc_viewer_set_levels(psc_viewer_t *v, const psc_envmap_t *levels, unsigned count)
{
    if (!v || !levels || count == 0 || count > PSC_VIEWER_MAX_LEVELS || v->tiles)
        return PSC_ERR_ARG;   /* (a tiled map's pyramid is its tiles') */
    const psc_envmap_t *m = v->map;
    for (unsigned k = 0; k < count; k++) {
        const psc_envmap_t *l = &levels[k];
        if (l->projection != m->projection || l->format != m->format || l->lon_min != m->lon_min ||
            l->lon_span != m->lon_span || l->lat_top != m->lat_top || l->lat_bottom != m->lat_bottom ||
            ((uint32_t)l->width << k) != m->width || ((uint32_t)l->height << k) != m->height || !l->pixels ||
            l->stride < psc_pixfmt_row_bytes(l->format, l->width) ||
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

/* ---- the scanline code path ---------------------------------------------------- */

/* The AVX2 kernel reads aligned 32-bit words around each texel (RGB888's at any byte): the map and its rows must be
 * 4-byte aligned. */
static bool map_words_aligned(const psc_envmap_t *m)
{
    return ((uintptr_t)m->pixels & 3u) == 0 && (m->stride & 3u) == 0;
}

static const psc_simd_kernel_t *simd_kernel(const psc_viewer_t *v, psc_simd_t simd)
{
    switch (simd) {
    case PSC_SIMD_AUTO: {
        /* x86-64 without AVX2 draws scalar: its SSE2 kernel, gathering lane by
         * lane, measured slower than the scalar spans (1.9 against 1.2 ms for
         * an 800x480 nearest frame on an AMD EPYC); NEON inserts and extracts
         * lanes in one instruction each, so ARM takes the vector kernel. */
        const psc_simd_kernel_t *k = psc_simd_kernel_avx2();
        if (k && map_words_aligned(v->map))
            return k;
#if defined(__x86_64__) || defined(__i386__)
        return 0;
#else
        return psc_simd_kernel_vector();
#endif
    }
    case PSC_SIMD_VECTOR: return psc_simd_kernel_vector();
    case PSC_SIMD_AVX2: return map_words_aligned(v->map) ? psc_simd_kernel_avx2() : 0;
    case PSC_SIMD_SCALAR: break;
    }
    return 0;
}

psc_status_t psc_viewer_set_simd(psc_viewer_t *v, psc_simd_t simd)
{
    if (!v || simd > PSC_SIMD_AVX2)
        return PSC_ERR_ARG;
    if (simd != PSC_SIMD_AUTO && simd != PSC_SIMD_SCALAR && !simd_kernel(v, simd))
        return PSC_ERR_UNSUPPORTED;
    v->simd = (uint8_t)simd;
    return PSC_OK;
}

psc_simd_t psc_viewer_simd(const psc_viewer_t *v)
{
    const psc_simd_kernel_t *k = simd_kernel(v, (psc_simd_t)v->simd);
    if (!k)
        return PSC_SIMD_SCALAR;
    return k == psc_simd_kernel_avx2() ? PSC_SIMD_AVX2 : PSC_SIMD_VECTOR;
}

const char *psc_simd_name(psc_simd_t simd)
{
    switch (simd) {
    case PSC_SIMD_AUTO: return "auto";
    case PSC_SIMD_SCALAR: return "scalar";
    case PSC_SIMD_VECTOR: return "vector";
    case PSC_SIMD_AVX2: return "avx2";
    }
    return "?";
}

/*
 * The vector kernel addresses every level by a 32-bit byte offset from level
 * 0's pixels (a pack holds its pyramid after the map); the AVX2 kernel also
 * needs each level's rows 4-byte aligned. Fills the frame's level tables.
 */
static bool mip_levels_addressable(const psc_viewer_t *v, psc_frame_t *f)
{
    const uintptr_t base = (uintptr_t)v->levels[0].pixels;
    for (unsigned k = 0; k < v->level_count; k++) {
        const psc_envmap_t *l = &v->levels[k];
        uintptr_t at = (uintptr_t)l->pixels;
        if (at < base || at - base + (uintptr_t)l->height * l->stride >= ((uintptr_t)1 << 31))
            return false;
        if (f->simd == psc_simd_kernel_avx2() && !map_words_aligned(l))
            return false;
        f->level_off[k] = (uint32_t)(at - base);
        f->level_stride[k] = l->stride;
        f->level_hmax[k] = l->height - 1u;
    }
    return true;
}

/* ---- public entry points ------------------------------------------------------- */

static bool view_ok(const psc_viewer_t *v, const psc_view_t *view)
{
    return v && view && view->span_log2 <= PSC_SPAN_LOG2_MAX &&
           (view->filter == PSC_FILTER_NEAREST || view->filter == PSC_FILTER_BILINEAR ||
            view->filter == PSC_FILTER_MIP) &&
           view->pitch <= (int32_t)PSC_BAM_90 && view->pitch >= -(int32_t)PSC_BAM_90 && view->hfov >= PSC_HFOV_MIN &&
           view->hfov <= psc_viewer_hfov_max(v);
}

/*
 * A scanline's workspace: boundary samples (at most W + 2: every pixel's left
 * edge, the right edge and one more when N does not divide W), their polar
 * flags and levels of detail, and the composite LUT row
 * (PSC_SCAN_COMPOSITE_COLS columns). One layout for the size and the
 * pointers: with scratch NULL only the size is computed.
 */
static size_t scan_work_layout(uint8_t *scratch, uint16_t out_width, psc_scan_work_t *w)
{
    const size_t n = SCAN_SAMPLES(out_width);
    const size_t row = 0, t = row + align8(n * sizeof(int32_t)), polar = t + align8(n * sizeof(uint32_t));
    const size_t lod = polar + align8(n), lut_row = lod + align8(n * sizeof(uint32_t));
    const size_t end = lut_row + (size_t)PSC_SCAN_COMPOSITE_COLS(out_width) * 2u * sizeof(uint32_t);
    if (scratch) {
        w->row = (int32_t *)(void *)(scratch + row);
        w->t = (uint32_t *)(void *)(scratch + t);
        w->polar = scratch + polar;
        w->lod = (uint32_t *)(void *)(scratch + lod);
        w->lut_row = (uint32_t *)(void *)(scratch + lut_row);
    }
    return align8(end);
}

/* The missed-tile record at the end of a band's scratch. */
static psc_tile_requests_t *requests_of(void *scratch, uint16_t out_width)
{
    return (psc_tile_requests_t *)(void *)((uint8_t *)scratch + 2u * scan_work_layout(NULL, out_width, NULL));
}

/* The frame of a prepared view (the zoom tables already for its hfov): reads the viewer, writes nothing of it. */
static psc_status_t frame_begin(const psc_viewer_t *v, const psc_view_t *view, psc_sink_t sink,
                                void *scratch, psc_frame_t *f)
{
    if (!view_ok(v, view) || v->cached_hfov != view->hfov || v->cached_lut == NULL)
        return PSC_ERR_ARG;
    *f = (psc_frame_t){0};
    f->v = v;
    f->view = view;
    size_t one = scan_work_layout(scratch, v->out_width, &f->work);
    scan_work_layout((uint8_t *)scratch + one, v->out_width, &f->work_next);
    f->simd = simd_kernel(v, (psc_simd_t)v->simd);
    f->lut = v->cached_lut;
    f->span = 1u << view->span_log2;
    f->sink = sink;
    /* The pyramid applies to full-turn rectangular maps that have one, and to tiled maps (rectangular rows). */
    f->mip = view->filter == PSC_FILTER_MIP && v->level_count > 1 && ((v->addr.fast && v->addr.wraps) || v->tiles);
    f->filter = view->filter == PSC_FILTER_MIP ? PSC_FILTER_BILINEAR : view->filter;
    f->simd_mip = f->mip && f->simd && !v->tiles && mip_levels_addressable(v, f);
    f->tiles = v->tiles;
    for (unsigned k = 0; f->tiles && k < f->tiles->level_count; k++) {   /* the tiled kernels' level tables */
        const psc_tile_level_t *l = &f->tiles->level[k];
        f->level_hmax[k] = l->height - 1u;
        f->tile_first[k] = l->first;
        f->tile_cols[k] = l->tiles_x;
        /* the levels holding a resident tile: an absent tile's span looks for a coarser one on these alone (a
         * pack just opened has its coarsest level only); residency does not change while a frame is drawn */
        for (uint32_t i = l->first, end = l->first + l->tiles_x * l->tiles_y; i < end; i++)
            if (f->tiles->resident[i]) {
                f->tile_levels |= 1u << k;
                break;
            }
    }
    f->requests = requests_of(scratch, v->out_width);   /* (read by tiled maps' spans only) */
    psc_sincos((psc_bam_t)view->pitch, &f->sin_pitch, &f->cos_pitch);
    polar_caps(v, f->lut, f->span, &f->cap_exact, &f->cap_per_pixel);
    return PSC_OK;
}

psc_status_t psc_viewer_prepare(psc_viewer_t *v, const psc_view_t *view)
{
    if (!view_ok(v, view))
        return PSC_ERR_ARG;
    psc_viewer_set_zoom(v, view->hfov);
    return PSC_OK;
}

size_t psc_viewer_band_scratch_size(uint16_t out_width)
{
    /* this scanline's and the next's, then the missed tiles */
    return 2u * scan_work_layout(NULL, out_width, NULL) + align8(sizeof(psc_tile_requests_t));
}

unsigned psc_viewer_band_requests(const void *scratch, uint16_t out_width, const uint32_t **tiles,
                                  uint32_t *dropped)
{
    const psc_tile_requests_t *r = requests_of((void *)(uintptr_t)scratch, out_width);
    if (tiles)
        *tiles = r->tile;
    if (dropped)
        *dropped = r->dropped;
    return r->count;
}

unsigned psc_viewer_view_tiles(psc_viewer_t *v, const psc_view_t *view, uint32_t *tiles, unsigned max)
{
    psc_frame_t f;
    if (!v || !v->tiles || !tiles || psc_viewer_prepare(v, view) != PSC_OK ||
        frame_begin(v, view, PSC_SINK_TRACE, v->scratch, &f) != PSC_OK)
        return 0;
    return psc_tiles_of_view(&f, tiles, max);
}

void psc_viewer_band_requests_clear(void *scratch, uint16_t out_width)
{
    psc_tile_requests_t *r = requests_of(scratch, out_width);
    r->count = r->dropped = r->cold_levels = 0;
    for (unsigned k = 0; k < PSC_TILE_SEEN_SLOTS; k++)
        r->seen[k] = 0;
}

unsigned psc_viewer_requests(const psc_viewer_t *v, const uint32_t **tiles, uint32_t *dropped)
{
    return psc_viewer_band_requests(v->scratch, v->out_width, tiles, dropped);
}

psc_status_t psc_viewer_render_band(const psc_viewer_t *v, const psc_view_t *view, const psc_surface_t *out,
                                    unsigned y0, unsigned y1, void *scratch, size_t scratch_size)
{
    if (!v || !out || !out->pixels || out->width != v->out_width || out->height != v->out_height || y0 > y1 ||
        y1 > v->out_height || !scratch || ((uintptr_t)scratch & 7u) != 0 ||
        scratch_size < psc_viewer_band_scratch_size(v->out_width))
        return PSC_ERR_ARG;
    if (out->format != PSC_PIX_RGB565 && out->format != PSC_PIX_XRGB8888)
        return PSC_ERR_UNSUPPORTED;
    if (out->stride < (uint32_t)out->width * psc_pixfmt_bytes(out->format))
        return PSC_ERR_ARG;
    psc_frame_t f;
    psc_status_t s = frame_begin(v, view, out->format == PSC_PIX_RGB565 ? PSC_SINK_RGB565 : PSC_SINK_XRGB8888,
                                 scratch, &f);
    if (s != PSC_OK)
        return s;
    psc_scan_rows(&f, y0, y1, (uint8_t *)out->pixels + (size_t)y0 * out->stride, out->stride);
    return PSC_OK;
}

psc_status_t psc_viewer_render(psc_viewer_t *v, const psc_view_t *view, const psc_surface_t *out)
{
    psc_status_t s = psc_viewer_prepare(v, view);
    if (s != PSC_OK)
        return s;
    psc_viewer_band_requests_clear(v->scratch, v->out_width);
    return psc_viewer_render_band(v, view, out, 0, v->out_height, v->scratch, psc_viewer_band_scratch_size(v->out_width));
}

psc_status_t psc_viewer_trace_row(psc_viewer_t *v, const psc_view_t *view, uint16_t y, int32_t *row_q16,
                                  int32_t *col_q16)
{
    if (!row_q16 || !col_q16 || !v || y >= v->out_height)
        return PSC_ERR_ARG;
    psc_frame_t f;
    psc_status_t s = psc_viewer_prepare(v, view);
    if (s == PSC_OK)
        s = frame_begin(v, view, PSC_SINK_TRACE, v->scratch, &f);
    if (s != PSC_OK)
        return s;
    f.trace_row = row_q16;
    f.trace_col = col_q16;
    psc_scanline_render(&f, y);
    return PSC_OK;
}
