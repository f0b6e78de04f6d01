/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_tiles.c - a tiled map's spans (psc_viewer_init_tiled).
 *
 * The arithmetic is the flat samplers' (psc_viewer_scan.c's span_fast for
 * nearest and bilinear, psc_viewer_mip.c's for the pyramid): the same rows,
 * columns and weights, so a frame whose tiles are resident is the flat
 * frame's bytes. Only the texel's address differs: tile (row >> 8, col >> 8)
 * of its level, at (row & 255, col & 255) in it.
 *
 * Tiles are looked up once a span: positions move linearly along a span, so
 * the texels its first and last pixels read bound the rest (columns move one
 * way round; a wrap across the seam changes the tile, except on a level one
 * tile wide, where it does not matter). When they share one resident tile,
 * the span reads it directly; otherwise (a span across a tile edge, or an
 * absent tile) each texel is looked up, and an absent one is taken from the
 * finest level resident over it, its tile recorded for the caller to load.
 *
 * A partial panorama (part of a turn: a museum's gigapixel of one wall) has
 * no level-0 runs or vector kernels here: its spans take its flat map's
 * columns (psc_partial_col_q32: the fast spans' inside it), clamped at its
 * edges, at every level, so that at level 0 its frames are its flat map's
 * bytes too.
 */
#include "viewer/psc_viewer_internal.h"

/* Record tile i as absent, once per band (psc_viewer_band_requests). */
static void request(const psc_frame_t *f, uint32_t i)
{
    psc_tile_requests_t *r = f->requests;
    if (r->count > PSC_VIEWER_MAX_REQUESTS) {   /* a scratch never cleared: begin its record */
        r->count = r->dropped = r->cold_levels = 0;
        for (unsigned k = 0; k < PSC_TILE_SEEN_SLOTS; k++)
            r->seen[k] = 0;
    }
    uint32_t *seen = &r->seen[PSC_TILE_SEEN_SLOT(i)];
    if (*seen == i + 1u)   /* recorded */
        return;
    if (r->count == PSC_VIEWER_MAX_REQUESTS) {   /* full: a miss past the record (without looking: a frame of a
                                                  * pack just opened has tens of thousands) */
        r->dropped++;
        return;
    }
    for (uint32_t k = 0; *seen != 0 && k < r->count; k++)   /* the slot another's: look through the record */
        if (r->tile[k] == i) {
            *seen = i + 1u;
            return;
        }
    r->tile[r->count++] = i;
    *seen = i + 1u;
}

/* Texel (r, c) of a tile holding it: raw RGB565, XRGB8888 (RGB888 as it), or a palette entry (XRGB8888). */
static PSC_ALWAYS_INLINE uint32_t tile_read(const psc_tiles_t *t, const uint8_t *tile, uint32_t r, uint32_t c,
                                            const psc_pixfmt_t in)
{
    const uint8_t *row = tile + (r & (PSC_TILE_SIDE - 1u)) * t->tile_stride;
    c &= PSC_TILE_SIDE - 1u;
    if (in == PSC_PIX_RGB565)
        return ((const uint16_t *)(const void *)row)[c];
    if (in == PSC_PIX_XRGB8888)
        return ((const uint32_t *)(const void *)row)[c];
    if (in == PSC_PIX_RGB888)
        return psc_rgb888_at(row, c);
    return t->palette[row[c]];
}

/* Texel (r, c) of level k, looked up: where its tile is absent (and requested), the texel over it of the finest
 * level resident there; 0 where none is. */
static PSC_ALWAYS_INLINE uint32_t texel_at(const psc_frame_t *f, uint32_t k, uint32_t r, uint32_t c,
                                           const psc_pixfmt_t in)
{
    const psc_tiles_t *t = f->tiles;
    uint32_t i = psc_tiles_at(t, k, r, c);
    const uint8_t *p = t->resident[i];
    if (p)
        return tile_read(t, p, r, c, in);
    request(f, i);
    while (++k < t->level_count) {
        r >>= 1;
        c >>= 1;
        if (!(f->tile_levels >> k & 1u))
            continue;
        p = t->resident[psc_tiles_at(t, k, r, c)];
        if (p)
            return tile_read(t, p, r, c, in);
    }
    return 0;
}

/* A texel through a span's one tile (fast) or looked up. */
static PSC_ALWAYS_INLINE uint32_t fetch(const psc_frame_t *f, const uint8_t *tile, uint32_t k, uint32_t r, uint32_t c,
                                        const psc_pixfmt_t in, const bool fast)
{
    return fast ? tile_read(f->tiles, tile, r, c, in) : texel_at(f, k, r, c, in);
}

/* ---- positions: the flat samplers' ------------------------------------------------------------------------ */

/* How a longitude becomes a column: a full turn's by a shift (a power-of-two width) or a multiply, wrapping at the
 * seam; a partial panorama's as its flat map's (psc_partial_col_q32), clamped at its edges. */
typedef enum { COLS_SHIFT, COLS_MUL, COLS_CLAMP } cols_t;

static cols_t cols_of(const psc_viewer_t *v)
{
    return !v->addr.wraps ? COLS_CLAMP : v->col_shift != 0 ? COLS_SHIFT : COLS_MUL;
}

static PSC_ALWAYS_INLINE uint32_t clamp_col(int64_t c, uint32_t width)
{
    return c < 0 ? 0u : c >= (int64_t)width ? width - 1u : (uint32_t)c;
}

/* Nearest texel of level k (at level 0 span_fast's: the row rounded, clamped as its guard rows do; the column by
 * t); level k's row of a level-0 row is (row + 1/2) / 2^k - 1/2, as the pyramid's. */
typedef struct {
    uint32_t r, c;
} near_t;

static PSC_ALWAYS_INLINE near_t near_at(const psc_frame_t *f, uint32_t k, int32_t row, uint32_t t, const cols_t cols)
{
    const psc_tile_level_t *l = &f->tiles->level[k];
    int64_t rk = (((int64_t)row + 32768) >> k) - 32768;   /* Q16, level k's pixel centres */
    int32_t r = (int32_t)((rk + 32768) >> 16), hmax = (int32_t)l->height - 1;
    near_t n;
    n.r = (uint32_t)(r < 0 ? 0 : r > hmax ? hmax : r);
    if (cols == COLS_CLAMP)
        n.c = clamp_col(psc_partial_col_q32(f->v, k, t, false) >> 32, l->width);
    else
        n.c = cols == COLS_SHIFT ? t >> ((f->v->col_shift + k) & 31u) : (uint32_t)(((uint64_t)t * l->width) >> 32);
    return n;
}

/* The four texels and weights of a bilinear sample of level k (psc_viewer_mip.c's level_sample; at level 0
 * span_fast's). */
typedef struct {
    uint32_t r0, r1, c0, c1, fr, fc;
} taps_t;

static PSC_ALWAYS_INLINE taps_t taps_at(const psc_frame_t *f, uint32_t k, int32_t row, uint32_t t, const cols_t cols)
{
    const psc_tile_level_t *l = &f->tiles->level[k];
    taps_t q;
    int32_t r = (int32_t)(((int64_t)row + 32768) >> k) - 32768, hmax = (int32_t)l->height - 1;
    int32_t r0 = r >> 16, r1 = r0 + 1;
    q.fr = ((uint32_t)r >> 8) & 255u;
    q.r0 = (uint32_t)(r0 < 0 ? 0 : r0);
    q.r1 = (uint32_t)(r1 > hmax ? hmax : r1);
    if (cols == COLS_CLAMP) {   /* psc_sample_partial's: rows and columns clamped at the map's edges */
        q.r0 = r0 > hmax ? (uint32_t)hmax : q.r0;
        q.r1 = r1 < 0 ? 0u : q.r1;
        int64_t c = psc_partial_col_q32(f->v, k, t, true);
        q.c0 = clamp_col(c >> 32, l->width);
        q.c1 = clamp_col((c >> 32) + 1, l->width);
        q.fc = (uint32_t)(c >> 24) & 255u;
        return q;
    }
    uint32_t tk = t - (f->v->half_col_bam << k);
    if (cols == COLS_SHIFT) {
        unsigned s = f->v->col_shift + k;   /* < 32: a level is at least 2 wide */
        q.c0 = tk >> s;
        q.fc = tk << (32u - s) >> 24;
    } else {
        uint64_t m = (uint64_t)tk * l->width;
        q.c0 = (uint32_t)(m >> 32);
        q.fc = (uint32_t)(m >> 24) & 255u;
    }
    q.c1 = q.c0 + 1u == l->width ? 0u : q.c0 + 1u;
    return q;
}

/* Bilinear at level k: RGB565 when packed565 (map and output both RGB565), else XRGB8888. */
static PSC_ALWAYS_INLINE uint32_t bilinear(const psc_frame_t *f, const uint8_t *tile, uint32_t k, taps_t q,
                                           const psc_pixfmt_t in, const bool packed565, const bool fast)
{
    uint32_t a = fetch(f, tile, k, q.r0, q.c0, in, fast), b = fetch(f, tile, k, q.r0, q.c1, in, fast);
    uint32_t c = fetch(f, tile, k, q.r1, q.c0, in, fast), d = fetch(f, tile, k, q.r1, q.c1, in, fast);
    if (packed565)
        return psc_blend4_rgb565(a, b, c, d, (q.fc + 4u) >> 3, (q.fr + 4u) >> 3);
    if (in == PSC_PIX_RGB565) {
        a = psc_rgb565_to_xrgb(a);
        b = psc_rgb565_to_xrgb(b);
        c = psc_rgb565_to_xrgb(c);
        d = psc_rgb565_to_xrgb(d);
    }
    return psc_blend4_xrgb(a, b, c, d, q.fc, q.fr);
}

/* ---- one resident tile for a whole span? ---------------------------------------------------------------- */

static PSC_ALWAYS_INLINE bool same_tile(uint32_t a, uint32_t b)
{
    return (a >> PSC_TILE_LOG2) == (b >> PSC_TILE_LOG2);
}

#define NO_TILE UINT32_MAX

/* The tile every texel of a span of n pixels reads at level k (resident or not), or NO_TILE when they lie in
 * several. */
static uint32_t span_tile_bilinear(const psc_frame_t *f, uint32_t k, int32_t row, uint32_t t, int32_t drow,
                                   int32_t dt, unsigned n, const cols_t cols)
{
    const psc_tile_level_t *l = &f->tiles->level[k];
    if (l->tiles_x == 1u && l->tiles_y == 1u)   /* a level of one tile (the coarsest ones): every texel's */
        return l->first;
    taps_t a = taps_at(f, k, row, t, cols);
    taps_t b = taps_at(f, k, (int32_t)((uint32_t)row + (n - 1u) * (uint32_t)drow), t + (n - 1u) * (uint32_t)dt, cols);
    if (!same_tile(a.r0, a.r1) || !same_tile(a.r0, b.r0) || !same_tile(a.r0, b.r1) || !same_tile(a.c0, a.c1) ||
        !same_tile(a.c0, b.c0) || !same_tile(a.c0, b.c1))
        return NO_TILE;
    return psc_tiles_at(f->tiles, k, a.r0, a.c0);
}

static uint32_t span_tile_nearest(const psc_frame_t *f, uint32_t k, int32_t row, uint32_t t, int32_t drow,
                                  int32_t dt, unsigned n, const cols_t cols)
{
    near_t a = near_at(f, k, row, t, cols);
    near_t b = near_at(f, k, (int32_t)((uint32_t)row + (n - 1u) * (uint32_t)drow), t + (n - 1u) * (uint32_t)dt, cols);
    if (!same_tile(a.r, b.r) || !same_tile(a.c, b.c))
        return NO_TILE;
    return psc_tiles_at(f->tiles, k, a.r, a.c);
}

static PSC_ALWAYS_INLINE const uint8_t *resident_tile(const psc_frame_t *f, uint32_t id)
{
    return id == NO_TILE ? NULL : (const uint8_t *)f->tiles->resident[id];
}

/*
 * A cold level, none of whose tiles is resident (a pack just opened, a jump in zoom): its spans ask for one tile
 * of it a band (the tile of the first such span's first texel) and go straight to a coarser level. Looking up each
 * span's tiles there made a cold frame cost three times a warm one; once a tile of the level is resident its spans
 * ask for exactly theirs (so periscope-render, which draws until nothing is asked for, still ends exact), and the
 * device asks for the view's tiles besides (psc_viewer_view_tiles).
 */
static PSC_ALWAYS_INLINE bool level_cold(const psc_frame_t *f, uint32_t k)
{
    return !(f->tile_levels >> k & 1u);
}

static void request_cold(const psc_frame_t *f, uint32_t k, int32_t row, uint32_t t, const cols_t cols)
{
    psc_tile_requests_t *r = f->requests;
    if (r->count <= PSC_VIEWER_MAX_REQUESTS && (r->cold_levels >> k & 1u))   /* (a record begun: its bits hold) */
        return;
    near_t q = near_at(f, k, row, t, cols);
    request(f, psc_tiles_at(f->tiles, k, q.r, q.c));
    r->cold_levels |= 1u << k;
}

/* An absent tile's span (id not resident, requested): the finest coarser level with the span's texels in one
 * resident tile, *level and its tile; NULL when there is none (the texels then are looked up one by one). */
static const uint8_t *coarser_tile(const psc_frame_t *f, uint32_t *level, int32_t row, uint32_t t, int32_t drow,
                                   int32_t dt, unsigned n, const cols_t cols)
{
    /* the levels past *level with a resident tile, finest first */
    for (uint32_t more = f->tile_levels & ~((2u << *level) - 1u), j; more; more &= more - 1u) {
        j = (uint32_t)__builtin_ctz(more);
        const uint8_t *p = resident_tile(f, span_tile_bilinear(f, j, row, t, drow, dt, n, cols));
        if (p) {
            *level = j;
            return p;
        }
    }
    return NULL;
}

/* ---- the spans --------------------------------------------------------------------------------------------- */

static PSC_ALWAYS_INLINE void put(const psc_frame_t *f, unsigned x, uint32_t px, const psc_sink_t sink)
{
    if (sink == PSC_SINK_RGB565)
        ((uint16_t *)(void *)f->dst)[x] = (uint16_t)px;
    else
        ((uint32_t *)(void *)f->dst)[x] = px;
}

static PSC_ALWAYS_INLINE void span_nearest(const psc_frame_t *f, const uint8_t *tile, uint32_t k, unsigned x,
                                           unsigned n, int32_t row, uint32_t t, int32_t drow, int32_t dt,
                                           const psc_pixfmt_t in, const psc_sink_t sink, const cols_t cols,
                                           const bool fast)
{
    for (unsigned i = 0; i < n; i++, row = (int32_t)((uint32_t)row + (uint32_t)drow), t += (uint32_t)dt) {
        near_t q = near_at(f, k, row, t, cols);
        uint32_t p = fetch(f, tile, k, q.r, q.c, in, fast), px;
        if (in == PSC_PIX_RGB565)
            px = sink == PSC_SINK_RGB565 ? p : psc_rgb565_to_xrgb(p);
        else   /* XRGB8888, or a palette entry: pal565[i] is the entry converted */
            px = sink == PSC_SINK_RGB565 ? psc_xrgb_to_rgb565(p) : p | 0xFF000000u;
        put(f, x + i, px, sink);
    }
}

static PSC_ALWAYS_INLINE void span_bilinear(const psc_frame_t *f, const uint8_t *tile, uint32_t k, unsigned x,
                                            unsigned n, int32_t row, uint32_t t, int32_t drow, int32_t dt,
                                            const psc_pixfmt_t in, const psc_sink_t sink, const cols_t cols,
                                            const bool fast)
{
    const bool packed565 = in == PSC_PIX_RGB565 && sink == PSC_SINK_RGB565;
    for (unsigned i = 0; i < n; i++, row = (int32_t)((uint32_t)row + (uint32_t)drow), t += (uint32_t)dt) {
        uint32_t px = bilinear(f, tile, k, taps_at(f, k, row, t, cols), in, packed565, fast);
        if (sink == PSC_SINK_RGB565 && !packed565)
            px = psc_xrgb_to_rgb565(px);
        put(f, x + i, px, sink);
    }
}

static PSC_ALWAYS_INLINE void span_mip(const psc_frame_t *f, const uint8_t *ta, const uint8_t *tb, unsigned x,
                                       unsigned n, int32_t row, uint32_t t, int32_t drow, int32_t dt, uint32_t level,
                                       uint32_t frac, const psc_pixfmt_t in, const psc_sink_t sink, const cols_t cols,
                                       const bool fast)
{
    const bool packed565 = in == PSC_PIX_RGB565 && sink == PSC_SINK_RGB565;
    for (unsigned i = 0; i < n; i++, row = (int32_t)((uint32_t)row + (uint32_t)drow), t += (uint32_t)dt) {
        uint32_t px = bilinear(f, ta, level, taps_at(f, level, row, t, cols), in, packed565, fast);
        if (frac) {
            uint32_t q = bilinear(f, tb, level + 1u, taps_at(f, level + 1u, row, t, cols), in, packed565, fast);
            px = packed565 ? psc_blend4_rgb565(px, q, px, q, (frac + 4u) >> 3, 0) : psc_blend4_xrgb(px, q, px, q, frac, 0);
        }
        if (sink == PSC_SINK_RGB565)
            px = packed565 ? px : psc_xrgb_to_rgb565(px);
        else
            px |= 0xFF000000u;
        put(f, x + i, px, sink);
    }
}

/* Level 0 within one resident tile: span_fast's loops, the row's offset in its tile from the viewer's table (its
 * guard rows the edge rows) and the column within the tile. */
static PSC_ALWAYS_INLINE uint32_t tile_col(uint32_t c)
{
    return c & (PSC_TILE_SIDE - 1u);
}

static PSC_ALWAYS_INLINE uint32_t raw_at(const uint8_t *row, uint32_t c, const psc_pixfmt_t in, const uint32_t *pal)
{
    if (in == PSC_PIX_RGB565)
        return ((const uint16_t *)(const void *)row)[c];
    if (in == PSC_PIX_XRGB8888)
        return ((const uint32_t *)(const void *)row)[c];
    if (in == PSC_PIX_RGB888)
        return psc_rgb888_at(row, c);
    return pal[row[c]];
}

static PSC_ALWAYS_INLINE void span0_nearest(const psc_frame_t *f, const uint8_t *tile, unsigned x, unsigned n,
                                            int32_t row, uint32_t t, int32_t drow, int32_t dt, const psc_pixfmt_t in,
                                            const psc_sink_t sink, const bool pow2)
{
    const uint32_t *rowoff = f->v->row_offsets, *pal = f->tiles->palette, w = f->v->map->width, sh = f->v->col_shift;
    uint32_t r = (uint32_t)row + 65536u + 32768u;   /* biased by the guard row, rounded */
    for (unsigned i = 0; i < n; i++, r += (uint32_t)drow, t += (uint32_t)dt) {
        uint32_t c = pow2 ? t >> sh : (uint32_t)(((uint64_t)t * w) >> 32);
        uint32_t p = raw_at(tile + rowoff[r >> 16], tile_col(c), in, pal), px;
        if (in == PSC_PIX_RGB565)
            px = sink == PSC_SINK_RGB565 ? p : psc_rgb565_to_xrgb(p);
        else
            px = sink == PSC_SINK_RGB565 ? psc_xrgb_to_rgb565(p) : p | 0xFF000000u;
        put(f, x + i, px, sink);
    }
}

static PSC_ALWAYS_INLINE void span0_bilinear(const psc_frame_t *f, const uint8_t *tile, unsigned x, unsigned n,
                                             int32_t row, uint32_t t, int32_t drow, int32_t dt,
                                             const psc_pixfmt_t in, const psc_sink_t sink, const bool pow2)
{
    const uint32_t *rowoff = f->v->row_offsets, *pal = f->tiles->palette, w = f->v->map->width, sh = f->v->col_shift;
    uint32_t r = (uint32_t)row + 65536u;
    t -= f->v->half_col_bam;   /* column c0 is the one left of the sample point */
    for (unsigned i = 0; i < n; i++, r += (uint32_t)drow, t += (uint32_t)dt) {
        const uint8_t *p0 = tile + rowoff[r >> 16], *p1 = tile + rowoff[(r >> 16) + 1u];
        uint32_t c0, fc;
        if (pow2) {
            c0 = t >> sh;
            fc = t << (32u - sh) >> 24;
        } else {
            uint64_t q = (uint64_t)t * w;
            c0 = (uint32_t)(q >> 32);
            fc = (uint32_t)(q >> 24) & 255u;
        }
        uint32_t c1 = tile_col(c0 + 1u == w ? 0u : c0 + 1u), fr = (r >> 8) & 255u, px;
        c0 = tile_col(c0);
        if (in == PSC_PIX_RGB565 && sink == PSC_SINK_RGB565) {
            const uint16_t *a = (const uint16_t *)(const void *)p0, *b = (const uint16_t *)(const void *)p1;
            px = psc_blend4_rgb565(a[c0], a[c1], b[c0], b[c1], (fc + 4u) >> 3, (fr + 4u) >> 3);
        } else {
            uint32_t a = raw_at(p0, c0, in, pal), b = raw_at(p0, c1, in, pal), c = raw_at(p1, c0, in, pal);
            uint32_t d = raw_at(p1, c1, in, pal);
            if (in == PSC_PIX_RGB565) {
                a = psc_rgb565_to_xrgb(a);
                b = psc_rgb565_to_xrgb(b);
                c = psc_rgb565_to_xrgb(c);
                d = psc_rgb565_to_xrgb(d);
            }
            px = psc_blend4_xrgb(a, b, c, d, fc, fr);
            if (sink == PSC_SINK_RGB565)
                px = psc_xrgb_to_rgb565(px);
        }
        put(f, x + i, px, sink);
    }
}

/*
 * The tiles of level k that a span's texels lie in, the span across a tile's edge (its two ends' taps bound the
 * others, and a span is shorter than a tile: at most two rows by two columns of tiles): whether all are
 * resident, the absent ones asked for.
 */
static bool span_tiles_resident(const psc_frame_t *f, uint32_t k, int32_t row, uint32_t t, int32_t drow,
                                int32_t dt, unsigned n, const cols_t cols)
{
    taps_t a = taps_at(f, k, row, t, cols);
    taps_t b = taps_at(f, k, (int32_t)((uint32_t)row + (n - 1u) * (uint32_t)drow), t + (n - 1u) * (uint32_t)dt, cols);
    const uint32_t rows[4] = {a.r0, a.r1, b.r0, b.r1}, columns[4] = {a.c0, a.c1, b.c0, b.c1};
    bool all = true;
    for (unsigned i = 0; i < 4; i++)
        for (unsigned j = 0; j < 4; j++) {
            uint32_t id = psc_tiles_at(f->tiles, k, rows[i], columns[j]);
            if (!f->tiles->resident[id]) {
                request(f, id);
                all = false;
            }
        }
    return all;
}

/*
 * A PSC_FILTER_MIP span's levels and tiles (psc_span_mip's choice at lod_q8): both levels' tiles resident,
 * their level and fraction; else, the absent ones asked for, the finest coarser level with the span's texels in
 * one resident tile at fraction 0; else ta NULL (each texel looked up, at the levels and fraction asked for: a
 * span across a tile's edge with every tile resident, or no coarser tile over the span).
 */
typedef struct {
    const uint8_t *ta, *tb;
    uint32_t level, frac;
} mip_choice_t;

static mip_choice_t mip_choose_at(const psc_frame_t *f, int32_t row, uint32_t t, int32_t drow, int32_t dt,
                                  unsigned n, uint32_t level, uint32_t frac, const cols_t cols)
{
    mip_choice_t c = {NULL, NULL, level, frac};
    uint32_t next = c.frac ? c.level + 1u : c.level;
    if (level_cold(f, c.level) && level_cold(f, next)) {
        request_cold(f, c.level, row, t, cols);
        if (next != c.level)
            request_cold(f, next, row, t, cols);
        const uint8_t *tj = coarser_tile(f, &next, row, t, drow, dt, n, cols);
        return tj ? (mip_choice_t){tj, tj, next, 0} : c;
    }
    uint32_t ia = span_tile_bilinear(f, c.level, row, t, drow, dt, n, cols);
    uint32_t ib = c.frac ? span_tile_bilinear(f, c.level + 1u, row, t, drow, dt, n, cols) : ia;
    c.ta = resident_tile(f, ia);
    c.tb = resident_tile(f, ib);
    if (c.ta && c.tb)
        return c;
    /* absent tiles asked for (a span across a tile's edge: each of the tiles it reads); where all are resident
     * the span is across an edge only, its texels looked up one by one */
    bool absent = ia == NO_TILE ? !span_tiles_resident(f, c.level, row, t, drow, dt, n, cols) : !c.ta;
    if (ia != NO_TILE && !c.ta)
        request(f, ia);
    if (c.frac) {
        absent |= ib == NO_TILE ? !span_tiles_resident(f, c.level + 1u, row, t, drow, dt, n, cols) : !c.tb;
        if (ib != NO_TILE && !c.tb)
            request(f, ib);
    }
    if (absent) {   /* meanwhile the finest coarser level with the span in one resident tile */
        uint32_t j = c.frac ? c.level + 1u : c.level;
        const uint8_t *tj = c.tb ? c.tb : coarser_tile(f, &j, row, t, drow, dt, n, cols);
        if (tj)
            return (mip_choice_t){tj, tj, j, 0};
    }
    c.ta = c.tb = NULL;
    return c;
}

/* The level and fraction of a level of detail (psc_span_mip's), then the choice. */
static mip_choice_t mip_choose(const psc_frame_t *f, int32_t row, uint32_t t, int32_t drow, int32_t dt, unsigned n,
                               int32_t lod_q8, const cols_t cols)
{
    uint32_t top = f->tiles->level_count - 1u;
    uint32_t level = lod_q8 < 0 ? 0u : (uint32_t)lod_q8 >> 8, frac = lod_q8 < 0 ? 0u : (uint32_t)lod_q8 & 255u;
    if (level >= top) {
        level = top;
        frac = 0;
    }
    return mip_choose_at(f, row, t, drow, dt, n, level, frac, cols);
}

/* Nearest and bilinear: the finest level no coarser than the pixels (see span_tiled). */
static uint32_t fit_level(const psc_frame_t *f, int32_t lod_q8)
{
    int32_t fit_q8 = lod_q8 - MIP_LOD_BIAS_Q8;
    uint32_t k = fit_q8 < 256 ? 0u : (uint32_t)fit_q8 >> 8;
    return k < f->tiles->level_count ? k : f->tiles->level_count - 1u;
}

/* Nearest and bilinear: the tile holding the span's texels at level *k (fit_level's), or where it is absent
 * (asked for) a coarser level's, *k that level; NULL when the span's texels are to be looked up one by one (a span
 * across a tile's edge, or no coarser tile over it). */
static PSC_ALWAYS_INLINE const uint8_t *fit_tile(const psc_frame_t *f, uint32_t *k, int32_t row, uint32_t t,
                                                 int32_t drow, int32_t dt, unsigned n, const cols_t cols)
{
    if (level_cold(f, *k)) {
        request_cold(f, *k, row, t, cols);
        return coarser_tile(f, k, row, t, drow, dt, n, cols);
    }
    uint32_t id = f->filter == PSC_FILTER_NEAREST ? span_tile_nearest(f, *k, row, t, drow, dt, n, cols)
                                                  : span_tile_bilinear(f, *k, row, t, drow, dt, n, cols);
    const uint8_t *tile = resident_tile(f, id);
    if (!tile && id != NO_TILE) {
        request(f, id);
        tile = coarser_tile(f, k, row, t, drow, dt, n, cols);
    }
    return tile;
}

bool psc_tiled_span_level(const psc_frame_t *f, int32_t row, uint32_t t, int32_t drow, int32_t dt, unsigned n,
                          uint32_t *lod)
{
    const cols_t cols = cols_of(f->v);
    if (f->mip) {
        mip_choice_t c = mip_choose_at(f, row, t, drow, dt, n, *lod & 255u, *lod >> 16, cols);
        if (!c.ta)
            return false;
        uint32_t next = c.frac ? c.level + 1u : c.level;
        *lod = c.level | next << 8 | c.frac << 16;
        return true;
    }
    uint32_t k = *lod & 255u;
    if (!fit_tile(f, &k, row, t, drow, dt, n, cols))
        return false;   /* across a tile's edge, or no coarser tile: texel by texel */
    *lod = k | k << 8;
    return true;
}

/* One combination of map format, output and column addressing, all constants once inlined. */
static PSC_ALWAYS_INLINE void span_tiled(const psc_frame_t *f, unsigned x, unsigned n, int32_t row, uint32_t t,
                                         int32_t drow, int32_t dt, int32_t lod_q8, const psc_pixfmt_t in,
                                         const psc_sink_t sink, const cols_t cols)
{
    if (f->mip) {   /* psc_span_mip's choice of levels */
        mip_choice_t c = mip_choose(f, row, t, drow, dt, n, lod_q8, cols);
        if (c.ta)
            span_mip(f, c.ta, c.tb, x, n, row, t, drow, dt, c.level, c.frac, in, sink, cols, true);
        else
            span_mip(f, NULL, NULL, x, n, row, t, drow, dt, c.level, c.frac, in, sink, cols, false);
        return;
    }
    /* nearest and bilinear read the finest level no coarser than the pixels (level 0 zoomed in and down to two
     * texels a pixel: the flat map's bytes), so that a wide view of a huge map reads about as many texels as it
     * has pixels, not the whole map */
    uint32_t k = fit_level(f, lod_q8);
    const bool near = f->filter == PSC_FILTER_NEAREST;
    const uint8_t *tile = fit_tile(f, &k, row, t, drow, dt, n, cols);
    if (near) {
        if (tile && k == 0 && cols != COLS_CLAMP)
            span0_nearest(f, tile, x, n, row, t, drow, dt, in, sink, cols == COLS_SHIFT);
        else if (tile)
            span_nearest(f, tile, k, x, n, row, t, drow, dt, in, sink, cols, true);
        else
            span_nearest(f, NULL, k, x, n, row, t, drow, dt, in, sink, cols, false);
        return;
    }
    if (tile && k == 0 && cols != COLS_CLAMP)
        span0_bilinear(f, tile, x, n, row, t, drow, dt, in, sink, cols == COLS_SHIFT);
    else if (tile)
        span_bilinear(f, tile, k, x, n, row, t, drow, dt, in, sink, cols, true);
    else
        span_bilinear(f, NULL, k, x, n, row, t, drow, dt, in, sink, cols, false);
}

#define TILED_SPAN(in_, sink_) \
    (cols == COLS_SHIFT  ? span_tiled(f, x, n, row, t, drow, dt, lod_q8, in_, sink_, COLS_SHIFT) \
     : cols == COLS_MUL ? span_tiled(f, x, n, row, t, drow, dt, lod_q8, in_, sink_, COLS_MUL) \
                        : span_tiled(f, x, n, row, t, drow, dt, lod_q8, in_, sink_, COLS_CLAMP))
#define TILED_FOR_FORMAT(in_) \
    do { \
        if (to565) \
            TILED_SPAN(in_, PSC_SINK_RGB565); \
        else \
            TILED_SPAN(in_, PSC_SINK_XRGB8888); \
    } while (0)

void psc_span_tiled(const psc_frame_t *f, unsigned x, unsigned n, int32_t row, uint32_t t, int32_t drow, int32_t dt,
                    int32_t lod_q8)
{
    if (n == 0)
        return;
    const cols_t cols = cols_of(f->v);
    const bool to565 = f->sink == PSC_SINK_RGB565;
    switch (f->tiles->format) {
    case PSC_PIX_RGB565: TILED_FOR_FORMAT(PSC_PIX_RGB565); break;
    case PSC_PIX_XRGB8888: TILED_FOR_FORMAT(PSC_PIX_XRGB8888); break;
    case PSC_PIX_PAL8: TILED_FOR_FORMAT(PSC_PIX_PAL8); break;
    case PSC_PIX_RGB888: TILED_FOR_FORMAT(PSC_PIX_RGB888); break;
    }
}

/* ---- level-0 runs: a scanline's spans in one tile ----------------------------------------------------------------- */

/* One loop without branches (the compiler's vectors take it): the tile's row and column packed, no multiply. */
static PSC_ALWAYS_INLINE void boundary_keys(const psc_frame_t *f, unsigned count, uint32_t *key, const bool pow2)
{
    const int32_t *row = f->work.row;
    const uint32_t *lon = f->work.t, w = f->v->map->width, hmax = f->v->map->height - 1u, sh = f->v->col_shift;
    for (unsigned k = 0; k < count; k++) {
        uint32_t r0 = (uint32_t)(row[k] >> 16);   /* a guard row (-1) becomes huge: unsafe */
        uint32_t c = pow2 ? lon[k] >> sh : (uint32_t)(((uint64_t)lon[k] * w) >> 32);
        uint32_t rt = r0 & (PSC_TILE_SIDE - 1u), ct = c & (PSC_TILE_SIDE - 1u);
        uint32_t bad = (uint32_t)(r0 >= hmax) | (uint32_t)(rt == PSC_TILE_SIDE - 1u) |
                       (uint32_t)(ct - 1u >= PSC_TILE_SIDE - 2u) | (uint32_t)(c + 1u >= w);
        key[k] = bad ? PSC_TILES_NO_TILE : (r0 >> PSC_TILE_LOG2) << 16 | c >> PSC_TILE_LOG2;
    }
}

void psc_tiles_boundary_keys(const psc_frame_t *f, unsigned count, uint32_t *key)
{
    if (f->v->col_shift != 0)
        boundary_keys(f, count, key, true);
    else
        boundary_keys(f, count, key, false);
}

/* The spans of a run through one specialised loop. */
static PSC_ALWAYS_INLINE void run0(const psc_frame_t *f, const uint8_t *tile, unsigned k0, unsigned k1, unsigned x0,
                                   unsigned x1, const psc_filter_t filter, const psc_pixfmt_t in,
                                   const psc_sink_t sink, const bool pow2)
{
    const int32_t *row = f->work.row;
    const uint32_t *lon = f->work.t;
    const unsigned n = f->span, sl = f->view->span_log2;
    for (unsigned k = k0, x = x0; k < k1; k++, x += n) {
        unsigned len = x1 - x < n ? x1 - x : n;
        int32_t dr = row[k + 1u] - row[k], dl = (int32_t)(lon[k + 1u] - lon[k]);   /* span_at's steps */
        if (len == n) {
            dr >>= sl;
            dl >>= sl;
        } else {
            dr /= (int32_t)len;
            dl /= (int32_t)len;
        }
        int32_t r = row[k] + (dr >> 1);
        uint32_t t = lon[k] + (uint32_t)(dl >> 1);
        if (filter == PSC_FILTER_NEAREST)
            span0_nearest(f, tile, x, len, r, t, dr, dl, in, sink, pow2);
        else
            span0_bilinear(f, tile, x, len, r, t, dr, dl, in, sink, pow2);
    }
}

#define RUN0(fl_, in_, sink_) \
    (pow2 ? run0(f, tile, k0, k1, x0, x1, fl_, in_, sink_, true) : run0(f, tile, k0, k1, x0, x1, fl_, in_, sink_, false))
#define RUN0_FOR(in_) \
    do { \
        if (near) { \
            if (to565) RUN0(PSC_FILTER_NEAREST, in_, PSC_SINK_RGB565); \
            else RUN0(PSC_FILTER_NEAREST, in_, PSC_SINK_XRGB8888); \
        } else { \
            if (to565) RUN0(PSC_FILTER_BILINEAR, in_, PSC_SINK_RGB565); \
            else RUN0(PSC_FILTER_BILINEAR, in_, PSC_SINK_XRGB8888); \
        } \
    } while (0)

/*
 * The vector kernel's share of a run (its whole spans): the run's boundary
 * samples moved to the tile's own rows and columns (the tile's origin taken
 * off, exactly: it is a whole number of rows and of columns), so the kernel
 * draws the tile as a map of 256 rows of the tile's stride whose texels it
 * never reads past (the boundaries lie a texel inside it); then put back.
 * Returns the spans drawn.
 */
static unsigned run0_vector(const psc_frame_t *f, const uint8_t *tile, uint32_t id, unsigned k0, unsigned spans,
                            unsigned x0)
{
    const psc_viewer_t *v = f->v;
    const psc_tiles_t *t = f->tiles;
    if (!f->simd || v->col_shift == 0 || spans == 0)
        return 0;
    const psc_tile_level_t *l = &t->level[0];
    uint32_t at = id - l->first, tr = at / l->tiles_x, tc = at % l->tiles_x;
    uint32_t drow = (tr << PSC_TILE_LOG2) << 16, dt = (tc << PSC_TILE_LOG2) << v->col_shift;
    int32_t *row = f->work.row;
    uint32_t *lon = f->work.t;
    for (unsigned k = k0; k <= k0 + spans; k++) {
        row[k] = (int32_t)((uint32_t)row[k] - drow);
        lon[k] -= dt;
    }
    const unsigned bpp = f->sink == PSC_SINK_RGB565 ? 2u : 4u;
    const psc_simd_row_t job = {tile, v->tile_row_offsets, t->palette, row + k0, lon + k0, f->dst + (size_t)x0 * bpp,
                                spans << f->view->span_log2, f->view->span_log2, v->col_shift, v->half_col_bam,
                                PSC_TILE_SIDE, t->tile_stride, f->filter == PSC_FILTER_BILINEAR, (uint8_t)t->format,
                                f->sink == PSC_SINK_RGB565, l->width};
    unsigned done = f->simd->row(&job) >> f->view->span_log2;
    for (unsigned k = k0; k <= k0 + spans; k++) {
        row[k] = (int32_t)((uint32_t)row[k] + drow);
        lon[k] += dt;
    }
    return done;
}

void psc_tiled_run0(const psc_frame_t *f, const uint8_t *tile, uint32_t id, unsigned k0, unsigned k1, unsigned x0,
                    unsigned x1)
{
    /* whole spans to the vector kernel, the rest (and a short last span) here */
    unsigned whole = (x1 - x0) >> f->view->span_log2, done = run0_vector(f, tile, id, k0, whole, x0);
    k0 += done;
    x0 += done << f->view->span_log2;
    if (k0 >= k1)
        return;
    const bool pow2 = f->v->col_shift != 0, to565 = f->sink == PSC_SINK_RGB565, near = f->filter == PSC_FILTER_NEAREST;
    switch (f->tiles->format) {
    case PSC_PIX_RGB565: RUN0_FOR(PSC_PIX_RGB565); break;
    case PSC_PIX_XRGB8888: RUN0_FOR(PSC_PIX_XRGB8888); break;
    case PSC_PIX_PAL8: RUN0_FOR(PSC_PIX_PAL8); break;
    case PSC_PIX_RGB888: RUN0_FOR(PSC_PIX_RGB888); break;
    }
}

/* ---- the tiles of a view, for prefetching ------------------------------------------------------------------ */

/* Add tile i to tiles[0..*n) once (max of them). */
static void add_tile(uint32_t *tiles, unsigned *n, unsigned max, uint32_t i)
{
    for (unsigned k = 0; k < *n; k++)
        if (tiles[k] == i)
            return;
    if (*n < max)
        tiles[(*n)++] = i;
}

unsigned psc_tiles_of_view(const psc_frame_t *f, uint32_t *tiles, unsigned max)
{
    const psc_viewer_t *v = f->v;
    const psc_tiles_t *t = f->tiles;
    /* the level at the view's middle (the largest there), as the spans choose it */
    int32_t lod = v->lod_base_q8 - (psc_log2_q8((uint64_t)v->dist_q8 * v->dist_q8) - 16 * 256) / 2;
    uint32_t top = t->level_count - 1u, k0, k1;
    if (f->mip) {
        k0 = lod < 0 ? 0u : (uint32_t)lod >> 8;
        k0 = k0 < top ? k0 : top;
        k1 = k0 < top && lod >= 0 && (lod & 255) ? k0 + 1u : k0;
    } else {
        int32_t fit = lod - MIP_LOD_BIAS_Q8;
        k0 = fit < 256 ? 0u : (uint32_t)fit >> 8;
        k0 = k1 = k0 < top ? k0 : top;
    }
    /* a grid of the view's pixels, an eighth of its smaller side apart: at most two texels a pixel, so a
     * step under 256 texels, and no tile of the view falls between the points */
    const int32_t w = v->out_width, h = v->out_height, step = 2 * ((w < h ? w : h) / 8);
    const cols_t cols = cols_of(v);
    unsigned n = 0;
    for (int32_t yc = -(h - 1); ; yc += step) {
        yc = yc > h - 1 ? h - 1 : yc;
        for (int32_t xc = -(w - 1); ; xc += step) {
            xc = xc > w - 1 ? w - 1 : xc;
            psc_bam_t lon;
            int32_t lat;
            psc_exact_angles(f, xc, yc, &lon, &lat);
            int32_t row = psc_map_row_q16(v, lat);
            uint32_t at = lon - v->map->lon_min;
            for (uint32_t k = k0; k <= k1; k++) {   /* the texel and its neighbours: a bilinear pixel's four */
                near_t q = near_at(f, k, row, at, cols);
                const psc_tile_level_t *l = &t->level[k];
                for (int dr = -1; dr <= 1; dr++)
                    for (int dc = -1; dc <= 1; dc++) {
                        int64_t r = (int64_t)q.r + dr, c = (int64_t)q.c + dc;
                        r = r < 0 ? 0 : r >= l->height ? l->height - 1u : r;
                        if (cols == COLS_CLAMP)   /* a partial panorama's edge */
                            c = c < 0 ? 0 : c >= l->width ? l->width - 1u : c;
                        else   /* across the seam */
                            c = c < 0 ? c + l->width : c >= l->width ? c - l->width : c;
                        add_tile(tiles, &n, max, psc_tiles_at(t, k, (uint32_t)r, (uint32_t)c));
                    }
            }
            if (xc == w - 1)
                break;
        }
        if (yc == h - 1)
            break;
    }
    /* a pole in view: every longitude meets there, the whole row of tiles around it (the grid would pass
     * between them) - when the pole lies within the view's half diagonal of its axis */
    uint32_t corner = psc_isqrt64((uint64_t)((int64_t)w * w + (int64_t)h * h) << 16);   /* Q8 half-pixels */
    psc_bam_t half_diag = psc_atan2((int32_t)corner, (int32_t)v->dist_q8, NULL);
    for (int pole = 0; pole < 2; pole++) {
        int64_t off = pole ? (int64_t)f->view->pitch + (int64_t)PSC_BAM_90 : (int64_t)PSC_BAM_90 - f->view->pitch;
        if (off > (int64_t)half_diag)
            continue;
        for (uint32_t k = k0; k <= k1; k++) {
            const psc_tile_level_t *l = &t->level[k];
            uint32_t ty = pole ? l->tiles_y - 1u : 0u;
            for (uint32_t tx = 0; tx < l->tiles_x; tx++)
                add_tile(tiles, &n, max, l->first + ty * l->tiles_x + tx);
        }
    }
    return n;
}
