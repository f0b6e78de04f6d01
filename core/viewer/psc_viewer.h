/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer.h - render perspective views of an environment map through a
 * scanline-coherent look-up table (seed US 5,748,194).
 *
 * Per frame:
 *  - each output scanline y maps to the LUT angle a = pitch + atan(y/d)
 *    (d = distance to the viewing plane from hfov) and is read as the blend of
 *    the two bounding LUT rows;
 *  - along it, pixel x maps to the LUT column u = x * cos(v) / d, a per-scanline
 *    scale factor recomputed only when the zoom changes;
 *  - the LUT is read every N-th pixel (N = 1 << span_log2) and the map indices
 *    are interpolated in between, the 360 degree wrap included;
 *  - yaw is a longitude offset (a column offset in the map);
 *  - pixels are fetched nearest or bilinear from the fractional indices.
 * Within a small cap around each pole, where polar angles are singular and
 * neither the table nor the index interpolation is accurate, map indices are
 * computed exactly per pixel with CORDIC: looking straight up or down shows
 * no hole, seam or smear.
 *
 * Memory: the caller hands the viewer one workspace of
 * psc_viewer_workspace_size() bytes at init; rendering allocates nothing.
 */
#ifndef PSC_VIEWER_H
#define PSC_VIEWER_H

#include "base/psc_types.h"
#include "envmap/psc_envmap.h"
#include "lut/psc_lut.h"
#include "tiles/psc_tiles.h"

typedef enum {
    PSC_FILTER_NEAREST = 0,  /* full-resolution map, nearest texel */
    PSC_FILTER_BILINEAR = 1, /* full-resolution map, bilinear */
    /* Map pyramid (psc_viewer_set_levels): per span of N pixels the level whose
     * texels match the pixel's footprint, bilinear in the two nearest levels
     * blended by the fractional level (trilinear). Zoomed-out views keep their
     * detail without shimmering. Full-turn equirect/cylinder/sine maps only;
     * other maps, or a viewer without levels, render it as bilinear. */
    PSC_FILTER_MIP = 2
} psc_filter_t;

#define PSC_SPAN_LOG2_MAX 4u      /* N up to 16 */
#define PSC_SPAN_LOG2_DEFAULT 2u  /* N = 4, the seed's preferred span */
#define PSC_VIEWER_MAX_LUTS 4u
#define PSC_VIEWER_MAX_LEVELS 12u
#define PSC_VIEWER_MAX_REQUESTS 64u   /* absent tiles a band records, the rest counted */
/* Narrowest field of view rendered (1 degree): keeps the viewing-plane
 * distance below 2^27 half-pixels (Q8) for outputs up to PSC_MAX_OUT_DIM. */
#define PSC_HFOV_MIN PSC_BAM_FROM_MDEG(1000)

/** One view: where the camera looks and how to draw it. */
typedef struct {
    psc_bam_t yaw;        /* > 0 turns right */
    int32_t pitch;        /* bam, -90..+90 degrees, > 0 looks up */
    psc_bam_t hfov;       /* horizontal field of view of the output */
    psc_filter_t filter;
    uint8_t span_log2;    /* LUT read every (1 << span_log2) pixels */
} psc_view_t;

/**
 * The code path that draws the viewer's scanlines. Every path gives the same
 * bytes (tests/test_simd.c); AUTO, the default, takes the fastest the build
 * and the CPU have: AVX2 on x86-64 CPUs that have it (maps with 4-byte
 * aligned rows), NEON on arm64 and armhf, else scalar (SSE2 is slower).
 */
typedef enum {
    PSC_SIMD_AUTO = 0,
    PSC_SIMD_SCALAR,
    PSC_SIMD_VECTOR, /* the baseline vectors: SSE2 or NEON */
    PSC_SIMD_AVX2
} psc_simd_t;

/** Per-scanline values that depend on zoom only (the seed's scale-factor table). */
typedef struct {
    int32_t v;              /* bam: atan(y / d), the scanline's angle from the view axis */
    uint32_t u_step_q24;    /* LUT columns per half-pixel along the scanline: cos(v)/d * (cols-1)/u_max, Q8.24 */
    uint32_t mag_q8;        /* sqrt(y^2 + d^2) in half-pixels, Q24.8: the scanline's distance from the eye */
} psc_scanline_t;

/** Map addressing derived at init: angles -> Q16.16 (row, column). */
typedef struct {
    psc_bam_t lon_center;       /* longitude of the map's middle */
    int64_t lon_half_span;      /* half the covered longitude, bam (2^31 for a full turn) */
    int64_t col_per_bam_q32;    /* map columns per bam, Q32.32 (= W for a full turn) */
    int64_t row_per_bam_q32;    /* linear-row projections: map rows per bam of latitude, Q32.32 */
    bool wraps;                 /* full turn: columns wrap around */
    bool fast;                  /* rectangular rows: the fast samplers apply (a partial map's away from its edges) */
    bool row_table;             /* rows come from lat_to_row (cylinder, sine) */
} psc_map_addressing_t;

typedef struct {
    const psc_envmap_t *map;
    const psc_tiles_t *tiles;    /* a tiled map (psc_viewer_init_tiled), else NULL */
    psc_map_addressing_t addr;
    const psc_envmap_t *levels;  /* map pyramid, levels[0] == *map (psc_viewer_set_levels) */
    uint8_t level_count;         /* 1 without a pyramid */
    int32_t lod_base_q8;         /* log2(2 * map rows per radian) + bias, Q24.8 (psc_viewer_scan.c) */
    const psc_lut_t *luts[PSC_VIEWER_MAX_LUTS];   /* increasing hfov_max */
    uint8_t lut_count;
    psc_bam_t hfov_switch;      /* informational: the LUT switch threshold */
    uint16_t out_width, out_height;
    /* workspace */
    psc_scanline_t *scan;       /* out_height entries */
    int32_t *lat_to_row;        /* projection table, PSC_LAT_TABLE_SIZE entries (Q16.16 rows) */
    int32_t *row_width_q16;     /* ELLIPTICAL/DIAMOND: width of each map row as a fraction of W, Q16.16 */
    uint16_t *palette565;       /* PAL8 maps: the palette converted for RGB565 output */
    uint32_t *row_offsets;      /* fast maps: byte offset of map row r at [r + 1], r = -1 .. H (edges repeated);
                                 * tiled: of row r within its tile */
    uint32_t *tile_row_offsets; /* tiled: one tile's rows, r = -1 .. 256, as a map of 256 rows */
    void *scratch;              /* a band's scanline workspace, for psc_viewer_render and tracing */
    uint8_t col_shift;          /* 32 - log2(col_width) for a power of two, else 0 */
    uint8_t simd;               /* psc_simd_t: PSC_SIMD_AUTO unless psc_viewer_set_simd says otherwise */
    uint32_t col_width;         /* the columns a full turn holds: W, or a partial map's W x turn / lon_span */
    uint32_t half_col_bam;      /* half a map column as a binary angle, 2^31 / col_width */
    uint32_t edge_margin;       /* a partial map: its fast spans keep t in [edge_margin, edge_margin + edge_inner) */
    uint32_t edge_inner;
    /* cached zoom state */
    psc_bam_t cached_hfov;
    const psc_lut_t *cached_lut;
    uint32_t dist_q8;           /* distance to the viewing plane in half-pixels, Q24.8 */
} psc_viewer_t;

#define PSC_LAT_TABLE_SIZE 4097u  /* samples of the row profile over [-90, +90] degrees */

/** Workspace bytes for an out_width x out_height output of map m. */
size_t psc_viewer_workspace_size(uint16_t out_width, uint16_t out_height, const psc_envmap_t *m);

/**
 * Prepare a viewer. luts: lut_count tables in increasing hfov_max (the pack
 * gives them so); ws: workspace of psc_viewer_workspace_size() bytes, aligned
 * to 8. The map, tables and workspace must outlive the viewer.
 */
psc_status_t psc_viewer_init(psc_viewer_t *v, const psc_envmap_t *map,
                             const psc_lut_t *luts, unsigned lut_count,
                             uint16_t out_width, uint16_t out_height,
                             void *ws, size_t ws_size);

/**
 * Prepare a viewer for a tiled map (tiles/psc_tiles.h): as psc_viewer_init,
 * `map` giving the projection, format, palette and coverage (its width and
 * height the tiles' level 0, its pixels unused), for full-turn equirect,
 * cylinder and sine maps (PSC_ERR_UNSUPPORTED for others). The workspace is
 * psc_viewer_workspace_size_tiled() bytes. Every filter applies; the pyramid
 * is the tiles'. A frame reads the residency table and never waits: where a
 * tile is absent it samples the finest level resident there and records the
 * tile (psc_viewer_requests). Once resident, a frame is the flat viewer's
 * bytes for the same map and view.
 */
psc_status_t psc_viewer_init_tiled(psc_viewer_t *v, const psc_envmap_t *map, const psc_tiles_t *tiles,
                                   const psc_lut_t *luts, unsigned lut_count, uint16_t out_width,
                                   uint16_t out_height, void *ws, size_t ws_size);
size_t psc_viewer_workspace_size_tiled(uint16_t out_width, uint16_t out_height, const psc_envmap_t *m);

/**
 * The tiles the bands drawn with this scratch since it was cleared
 * (psc_viewer_band_requests_clear; psc_viewer_render clears the viewer's own
 * and psc_viewer_requests reads it) found absent at the level they wanted:
 * their numbers into *tiles, how many returned, at most
 * PSC_VIEWER_MAX_REQUESTS (*dropped, may be NULL: the misses past those, a
 * tile as often as it was missed). Each tile once. Clear a band's scratch
 * before a frame's first band.
 */
unsigned psc_viewer_band_requests(const void *scratch, uint16_t out_width, const uint32_t **tiles,
                                  uint32_t *dropped);
void psc_viewer_band_requests_clear(void *scratch, uint16_t out_width);

/**
 * A tiled viewer: the tiles a view reads (resident or not) at the levels its
 * filter takes at its middle, found on a grid of its pixels fine enough that
 * no tile falls between them; into tiles[0..max), how many. For prefetching
 * where the view is going (it needs no pixels drawn). Between frames only:
 * it uses the viewer's own scratch.
 */
unsigned psc_viewer_view_tiles(psc_viewer_t *v, const psc_view_t *view, uint32_t *tiles, unsigned max);
unsigned psc_viewer_requests(const psc_viewer_t *v, const uint32_t **tiles, uint32_t *dropped);

/**
 * Give the viewer the map pyramid for PSC_FILTER_MIP: levels[0] describes the
 * same map as init's, level k is exactly (W >> k) x (H >> k) with the same
 * projection, format, palette and coverage (a parsed pack's levels are). The
 * levels must outlive the viewer. PSC_ERR_ARG if they do not match.
 */
psc_status_t psc_viewer_set_levels(psc_viewer_t *v, const psc_envmap_t *levels, unsigned count);

/**
 * Choose the scanline code path (psc_simd_t). PSC_ERR_UNSUPPORTED, and the
 * choice unchanged, if this build or this CPU lacks it.
 */
psc_status_t psc_viewer_set_simd(psc_viewer_t *v, psc_simd_t simd);
/** The path that draws the viewer's frames: never PSC_SIMD_AUTO. */
psc_simd_t psc_viewer_simd(const psc_viewer_t *v);
/** "scalar", "vector", "avx2". */
const char *psc_simd_name(psc_simd_t simd);

/** Widest hfov the viewer's tables serve. */
psc_bam_t psc_viewer_hfov_max(const psc_viewer_t *v);

/**
 * Bring a requested view inside what the map and tables can show: hfov into
 * [max(hfov_min, PSC_HFOV_MIN), hfov_max], pitch into [-90, 90] degrees, and for partial
 * panoramas yaw and pitch so that no output pixel looks outside the map.
 */
void psc_viewer_clamp(const psc_viewer_t *v, psc_view_t *view, psc_bam_t hfov_min);

/**
 * Render a view into out (RGB565 or XRGB8888, out_width x out_height).
 * PSC_ERR_ARG if the view is outside its ranges (pitch beyond +-90 degrees,
 * hfov below PSC_HFOV_MIN or above psc_viewer_hfov_max, span_log2 > 4).
 */
psc_status_t psc_viewer_render(psc_viewer_t *v, const psc_view_t *view, const psc_surface_t *out);

/**
 * Rendering in bands, for several cores (core knows no threads: the caller
 * runs the bands where it likes). psc_viewer_prepare computes the view's zoom
 * tables once per frame (it writes the viewer: call it alone); then each
 * psc_viewer_render_band draws output rows [y0, y1) with a scratch of its own
 * (psc_viewer_band_scratch_size(out_width) bytes, aligned to 8), reading the viewer and
 * writing only its rows, so the bands of a frame may run at once. Any split
 * gives the bytes of psc_viewer_render. PSC_ERR_ARG for a view that was not
 * prepared (or not as rendered), rows outside the output, or a short scratch.
 */
psc_status_t psc_viewer_prepare(psc_viewer_t *v, const psc_view_t *view);
size_t psc_viewer_band_scratch_size(uint16_t out_width);
psc_status_t psc_viewer_render_band(const psc_viewer_t *v, const psc_view_t *view, const psc_surface_t *out,
                                    unsigned y0, unsigned y1, void *scratch, size_t scratch_size);

/**
 * The fractional map position every pixel of output row y samples, exactly as
 * psc_viewer_render computes it: row_q16[x], col_q16[x] in Q16.16 map pixels,
 * where an integer value is the centre of that pixel (so the map's left edge
 * is column -0.5). Full-turn maps give columns wrapped into [0, W).
 * For ELLIPTICAL and DIAMOND maps col is the full-width longitude column,
 * before the row's width is applied.
 */
psc_status_t psc_viewer_trace_row(psc_viewer_t *v, const psc_view_t *view, uint16_t y,
                                  int32_t *row_q16, int32_t *col_q16);

#endif
