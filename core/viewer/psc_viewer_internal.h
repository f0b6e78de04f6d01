/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_internal.h - what the viewer's source files share; not part of
 * the public API.
 */
#ifndef PSC_VIEWER_INTERNAL_H
#define PSC_VIEWER_INTERNAL_H

#include "viewer/psc_viewer.h"
#include "base/psc_fixed.h"
#include "base/psc_pixel.h"
#include "viewer/psc_viewer_simd.h"

#define PSC_LAT_TABLE_SHIFT 19u /* 2^31 bam (180 degrees) / 4096 intervals */

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

/* The tiles a band found absent (at the level it wanted), at the end of its scratch; seen, a cache of which are
 * recorded (slot PSC_TILE_SEEN_SLOT(i) holds i + 1 if tile i is, else maybe another or 0), spares most of the
 * look-ups through the record. */
#define PSC_TILE_SEEN_SLOTS 64u   /* (every band's scratch has it, a microcontroller's too: 256 bytes) */
#define PSC_TILE_SEEN_SLOT(i) (((uint32_t)(i) * 2654435761u) >> 26)
typedef struct {
    uint32_t count, dropped;
    uint32_t cold_levels;   /* the levels without a resident tile that asked for one (psc_viewer_tiles.c) */
    uint32_t tile[PSC_VIEWER_MAX_REQUESTS];
    uint32_t seen[PSC_TILE_SEEN_SLOTS];
} psc_tile_requests_t;

/* What a rendering pass writes per pixel. */
typedef enum {
    PSC_SINK_RGB565,
    PSC_SINK_XRGB8888,
    PSC_SINK_TRACE /* the sampled (row, col), for tests and tools */
} psc_sink_t;

/*
 * A band's scanline workspace (psc_viewer_band_scratch_size bytes): the
 * samples at the span boundaries and the composite LUT row.
 */
typedef struct {
    int32_t *row;      /* map row, Q16.16 (integer = pixel centre), clamped to [-0.5, H - 0.5] on fast maps */
    uint32_t *t;       /* longitude from the map's left edge, binary angle (2^32 = a full turn) */
    uint8_t *polar;    /* inside a polar cap: no span interpolation from or to here */
    uint32_t *lut_row; /* the scanline's two LUT rows blended: (lon, lat) pairs */
    uint32_t *lod;     /* PSC_FILTER_MIP through the vector kernel: each span's levels (psc_simd_mip_t) */
} psc_scan_work_t;

/* Columns of the composite LUT row a scanline's workspace holds (a denser LUT is read directly). */
#define PSC_SCAN_COMPOSITE_COLS(out_width) ((uint32_t)(out_width) / 2u + 2u)

/* Everything fixed for one frame. */
typedef struct {
    const psc_viewer_t *v;
    const psc_view_t *view;
    psc_scan_work_t work;          /* this band's scanline workspace */
    psc_scan_work_t work_next;     /* and the next scanline's (psc_scan_rows) */
    const psc_simd_kernel_t *simd; /* the vector kernel, or NULL for the scalar path only */
    bool simd_mip;                 /* the pyramid through the kernel: its levels addressable from level 0 */
    uint32_t level_off[PSC_VIEWER_MAX_LEVELS], level_stride[PSC_VIEWER_MAX_LEVELS], level_hmax[PSC_VIEWER_MAX_LEVELS];
    uint32_t tile_first[PSC_VIEWER_MAX_LEVELS], tile_cols[PSC_VIEWER_MAX_LEVELS]; /* a tiled map's, for the kernel */
    uint32_t tile_levels;          /* a tiled map's levels with a tile resident (bit k: level k), when it began */
    const psc_lut_t *lut;
    int32_t sin_pitch, cos_pitch;  /* Q2.30 */
    int32_t cap_per_pixel;         /* |lat| >= this: LUT read at every pixel (polar cap) */
    int32_t cap_exact;             /* |lat| >= this: exact CORDIC per pixel (inner polar cap) */
    unsigned span;                 /* N: LUT read every N pixels */
    psc_sink_t sink;
    psc_filter_t filter;           /* nearest or bilinear: what the non-mip samplers do */
    bool mip;                      /* PSC_FILTER_MIP with a pyramid on a fast map */
    uint8_t *dst;                  /* current output row (RGB565/XRGB8888) */
    const psc_tiles_t *tiles;      /* a tiled map (psc_viewer_init_tiled), else NULL */
    psc_tile_requests_t *requests; /* the band's missed tiles (in its scratch) */
    int32_t *trace_row, *trace_col;
} psc_frame_t;

/* A LUT sample: the angles of one pixel, before the map's addressing. */
typedef struct {
    psc_bam_t lon;
    int32_t lat;
} psc_angles_t;

void psc_map_addressing_init(psc_map_addressing_t *a, const psc_envmap_t *m);
/* Map column / row (Q16.16, integer = pixel centre) of a longitude / latitude. */
int32_t psc_map_col_q16(const psc_viewer_t *v, psc_bam_t lon);
int32_t psc_map_row_q16(const psc_viewer_t *v, int32_t lat);
void psc_lat_table_init(int32_t *table, const psc_envmap_t *m);
void psc_row_width_init(int32_t *width_q16, const psc_envmap_t *m);
/* Exact angles of the ray through half-pixel coordinates (xc right, yc up from the centre). */
void psc_exact_angles(const psc_frame_t *f, int32_t xc, int32_t yc, psc_bam_t *lon, int32_t *lat);
/* Prepare zoom-dependent state (LUT choice, per-scanline table) for hfov. */
void psc_viewer_set_zoom(psc_viewer_t *v, psc_bam_t hfov);
/*
 * Trilinear spans: pixels [x, x + n) from level-0 row and longitude t (binary
 * angle from the map's left edge) in steps (drow, dt), at level of detail
 * lod_q8 (log2 texels per pixel, Q24.8).
 */
void psc_span_mip(const psc_frame_t *f, unsigned x, unsigned n, int32_t row, uint32_t t, int32_t drow, int32_t dt,
                  int32_t lod_q8);
/*
 * A tiled map's span (psc_viewer_tiles.c): pixels [x, x + n) from level-0 row
 * and longitude t in steps (drow, dt), through the frame's filter; for
 * PSC_FILTER_MIP at level of detail lod_q8. The flat samplers' arithmetic,
 * texels looked up in the tiles: the flat map's bytes where they are resident.
 */
void psc_span_tiled(const psc_frame_t *f, unsigned x, unsigned n, int32_t row, uint32_t t, int32_t drow, int32_t dt,
                    int32_t lod_q8);
/*
 * The levels a tiled span of n pixels from level-0 row and longitude t in steps (drow, dt) is drawn at
 * (psc_span_tiled's choice for the frame's filter, its absent tiles asked for), as the vector kernel's lod entry
 * (level | next level << 8 | fraction << 16; on entry the span's own levels, as mip_vector makes them from its
 * level of detail): false where the span's texels must be looked up one by one.
 */
bool psc_tiled_span_level(const psc_frame_t *f, int32_t row, uint32_t t, int32_t drow, int32_t dt, unsigned n,
                          uint32_t *lod);
/*
 * Each level-0 boundary sample of a scanline (count of them): the tile (row << 16 | column of tiles) holding
 * every texel a nearest or bilinear pixel next to it reads - rows r0 = floor(row) and r0 + 1 (nearest rounds to
 * one of them), columns c - 1 .. c + 1 (the bilinear pair is c - 1, c or c, c + 1; nearest c), none a guard row -
 * else PSC_TILES_NO_TILE; into key (psc_viewer_tiles.c).
 */
#define PSC_TILES_NO_TILE UINT32_MAX
void psc_tiles_boundary_keys(const psc_frame_t *f, unsigned count, uint32_t *key);
/* The spans from boundary k0 to k1 (pixels [x0, x1)), all in one resident tile at level 0: one loop. */
void psc_tiled_run0(const psc_frame_t *f, const uint8_t *tile, uint32_t id, unsigned k0, unsigned k1, unsigned x0,
                    unsigned x1);
/* The tiles a frame's view reads (psc_viewer_view_tiles), into tiles[0..max): how many. */
unsigned psc_tiles_of_view(const psc_frame_t *f, uint32_t *tiles, unsigned max);
/* Render (or trace) output scanline y of the frame. */
void psc_scanline_render(const psc_frame_t *f, unsigned y);
/* Render output rows [y0, y1) into dst0 (row y0) onwards, stride bytes apart. */
void psc_scan_rows(const psc_frame_t *f, unsigned y0, unsigned y1, uint8_t *dst0, size_t stride);
/* Sample any map at (row, col) Q16.16 through the general (per-pixel, clamping) path: XRGB8888. */
uint32_t psc_sample_general(const psc_viewer_t *v, psc_filter_t filter, int32_t row, int32_t col);

/*
 * A partial map's column position at level k, Q32.32 (the integer part a column of level k): t's offset from the
 * map's left edge taken signed (negative beyond it), in the columns of the full turn the map is a window of
 * (col_width >> k of them); for a bilinear sample less half a column (its left texel's). Where t lies inside the
 * map these are a full turn's fast spans' columns (t x col_width / 2^32); beyond it, in order, for clamping.
 * |rel| <= 2^32 and col_width < 2^25: the product fits.
 */
static inline int64_t psc_partial_col_q32(const psc_viewer_t *v, uint32_t k, uint32_t t, bool bilinear)
{
    const psc_map_addressing_t *a = &v->addr;
    int64_t rel = (int64_t)(int32_t)(t + v->map->lon_min - a->lon_center) + a->lon_half_span;
    if (bilinear)
        rel -= (int64_t)v->half_col_bam << k;
    return rel * (int64_t)(v->col_width >> k);
}

/*
 * Sample a partial map of rectangular rows at level-0 row (Q16.16) and t (psc_partial_col_q32's columns), rows
 * and columns clamped at its edges: its fast spans' arithmetic, so that a frame is the same bytes whichever path a
 * span takes. XRGB8888, or with packed565 (an RGB565 map drawn to RGB565) the RGB565 blend of the fast spans.
 */
uint32_t psc_sample_partial(const psc_viewer_t *v, psc_filter_t filter, int32_t row, uint32_t t, bool packed565);

#endif
