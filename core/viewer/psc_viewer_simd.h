/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_simd.h - the viewer's vector scanlines (internal).
 *
 * A scanline whose spans are all N pixels long and none touches a polar cap
 * (the common case) can be drawn several pixels at a time: pixel x lies in
 * span k = x >> log2 N at i = x & (N - 1), at sample k plus step / 2 plus
 * i * step, exactly the positions the scalar spans reach by adding the step.
 * A kernel draws pixels [0, n) of the row for the combinations it serves and
 * returns n (a multiple of its lane count, 0 if it serves none); the scalar
 * spans draw the rest. Every kernel gives the scalar path's bytes
 * (tests/test_simd.c).
 *
 * The kernels are one source (psc_viewer_simd_kernel.h) built with GCC/clang
 * vector extensions: four lanes with the CPU's baseline vectors (SSE2 on
 * x86-64, NEON on arm64 and armhf), eight with AVX2 gathers where the CPU has
 * them (chosen at run time). Other targets (Cortex-M) have the scalar path only.
 */
#ifndef PSC_VIEWER_SIMD_H
#define PSC_VIEWER_SIMD_H

#include "base/psc_types.h"
#include "tiles/psc_tiles.h"

typedef struct {
    const uint8_t *base;      /* map pixels */
    const uint32_t *rowoff;   /* byte offset of map row r at [r + 1], r = -1 .. H (edge rows repeated) */
    const uint32_t *pal;      /* PAL8 maps: the palette */
    const int32_t *row;       /* the scanline's boundary samples: map row, Q16.16 */
    const uint32_t *t;        /* and longitude from the map's left edge, binary angle */
    void *dst;                /* output row */
    uint32_t width;           /* output pixels, a multiple of the span */
    uint32_t span_log2;
    uint32_t col_shift;       /* 32 - log2(map width) for a power-of-two width, else 0 (map_width's multiply) */
    uint32_t half_col;        /* half a map column, binary angle */
    uint32_t map_height;      /* rows */
    uint32_t stride;          /* bytes from one map row to the next */
    uint8_t bilinear;         /* else nearest */
    uint8_t in;               /* psc_pixfmt_t of the map */
    uint8_t out_565;          /* RGB565 output, else XRGB8888 */
    uint32_t map_width;       /* columns (a full turn): column = t * map_width >> 32 */
} psc_simd_row_t;

/*
 * The mirrored LUT reads of an equirect scanline (build_samples_linear of
 * psc_viewer_scan.c): read k at |xc| = W - 2 k N half-pixels gives samples k
 * and count - 1 - k. A kernel does reads [0, returned) (a multiple of its
 * lanes), stopping before a group that has a read in the exact polar cap, and
 * ORs their polar flags into *any_polar; the scalar loop does the rest.
 */
typedef struct {
    const uint32_t *lut_row;  /* composite LUT row: (lon, lat) pairs */
    uint32_t lut_cols;        /* entries built */
    uint32_t u_step_q24;      /* LUT columns per half-pixel; W * u_step < 2^32 - 2^15 (the caller checks) */
    uint32_t width, span, reads, count;
    int64_t row_base;         /* lat_top * rows_per_bam */
    int32_t row_per_lat;      /* -+rows_per_bam (the scanline's latitude sign folded in) */
    int32_t bottom;           /* last row, Q16.16: H - 1/2 */
    uint32_t pole_base, pole_sign; /* lon_right = pole_base + pole_sign * lon */
    uint32_t t_base;          /* yaw - the map's lon_min */
    int32_t cap_per_pixel, cap_exact;
    int32_t *row;
    uint32_t *t;
    uint8_t *polar;
    /* prefetch of the map lines under every pf_step-th sample (prefetch_samples
     * of psc_viewer_scan.c), or pf_base NULL for none */
    const uint8_t *pf_base;
    uint32_t pf_round;        /* added to the row before >> 16: 1 (the guard row), + 1/2 for nearest */
    uint32_t pf_stride, pf_height, pf_col_shift, pf_bpp_log2, pf_step_mask;
    uint8_t pf_two_rows;      /* bilinear: the row below too */
} psc_simd_samples_t;

/*
 * A row of PSC_FILTER_MIP (psc_viewer_mip.c): each span's level of detail
 * comes from lod[k] (level | next level << 8 | fraction << 16, the next level
 * clamped to the top, fraction 0 at the top), then per lane the two levels
 * are sampled bilinearly and blended, as span_mip does pixel by pixel.
 */
typedef struct {
    const uint8_t *base;        /* level 0 pixels */
    const uint32_t *level_off;  /* level k pixels - level 0 pixels, bytes (all within 2 GiB) */
    const uint32_t *level_stride, *level_hmax;
    const uint32_t *pal;
    const int32_t *row;
    const uint32_t *t, *lod;
    void *dst;
    uint32_t width, span_log2, col_shift, half_col, col_mask; /* col_mask: level 0 width - 1 (col_shift: 0 where
                                                                 * that width is not a power of two) */
    uint8_t in, out_565;
} psc_simd_mip_t;

/*
 * A tiled map's level-0 row, nearest or bilinear (psc_viewer_tiles.c): row's
 * fields as for a flat map but base and rowoff (unused), map_height (level
 * 0's rows) and stride (a tile row's bytes). Each group of the kernel's lanes
 * whose texels all lie in one resident tile is drawn from it as row draws a
 * flat map, lane by lane from several where they straddle a tile's edge;
 * the groups with a texel in an absent tile are left undrawn, their indices
 * (group g: pixels [g * lanes, (g + 1) * lanes)) in miss[0 .. *misses), for
 * the scalar spans. Returns the pixels the groups cover, as row does. PAL8
 * maps (never tiled) are not served.
 */
typedef struct {
    psc_simd_row_t row;
    const void *const *resident;   /* level 0's tiles, row by row (psc_tiles_t's table) */
    uint32_t tiles_x;              /* level 0's tiles a row */
    uint16_t *miss;                /* room for width / lanes entries */
    uint32_t *misses;
} psc_simd_row_tiled_t;

/*
 * A tiled map's row of PSC_FILTER_MIP, or of nearest or bilinear at each
 * span's level (fraction 0): mip's fields but base, level_off and
 * level_stride (unused; level_hmax is each level's last row), each level's
 * texels from its tiles; the groups with a texel in an absent tile listed in
 * miss as for the tiled row.
 */
typedef struct {
    psc_simd_mip_t mip;
    const void *const *resident;                   /* every tile (psc_tiles_t's numbering and table) */
    const uint32_t *level_first, *level_tiles_x;   /* each level's first tile and tiles a row */
    uint32_t tile_stride;
    uint16_t *miss;
    uint32_t *misses;
    const uint16_t *only;                          /* if not NULL, these only_n groups alone */
    uint32_t only_n;
    uint8_t nearest;                               /* the nearest texel of each span's level (its lod entry's) */
} psc_simd_mip_tiled_t;

/*
 * A kernel's functions: the row, the samples, and the composite LUT row
 * (composite: lon and lat of n entries of the two LUT rows e0, e1 blended
 * with weight fr of e1, Q0.8, into (lon, lat) pairs at out), the pyramid's
 * row, a tiled map's rows, and the pixels a group of lanes draws.
 */
typedef struct {
    unsigned (*row)(const psc_simd_row_t *r);
    unsigned (*samples)(const psc_simd_samples_t *s, uint8_t *any_polar);
    void (*composite)(const uint32_t *e0, const uint32_t *e1, uint32_t fr, uint32_t n, uint32_t *out);
    unsigned (*mip)(const psc_simd_mip_t *m);
    unsigned (*row_tiled)(const psc_simd_row_tiled_t *r);
    unsigned (*mip_tiled)(const psc_simd_mip_tiled_t *m);
    unsigned lanes;
} psc_simd_kernel_t;

/* The kernels this build has (NULL where the target has none, and AVX2's where the CPU lacks it). */
const psc_simd_kernel_t *psc_simd_kernel_vector(void);
const psc_simd_kernel_t *psc_simd_kernel_avx2(void);

#endif
