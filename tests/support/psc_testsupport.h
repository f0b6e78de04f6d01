/* SPDX-License-Identifier: MIT */
/*
 * psc_testsupport.h - shared helpers for Periscope's tests (host only: double,
 * heap and libc allowed). Built into libpsc_testsupport.a from tests/support/.
 *
 * Conventions are those of core/base/psc_types.h and core/envmap/psc_envmap.h, restated
 * here in double precision so that the tests check core against an
 * independent implementation:
 *  - angles in radians unless a name says _deg; lon in [-pi, pi), lat in
 *    [-pi/2, pi/2];
 *  - output pixel (i, j) of a W x H view has the camera ray
 *    (i + 0.5 - W/2, H/2 - (j + 0.5), d), d = (W/2) / tan(hfov/2), pitched
 *    about X then yawed about Y (yaw > 0 turns right, pitch > 0 looks up);
 *  - a map position (row, col) is continuous with integers at pixel centres;
 *    col is the full-width longitude column (for ELLIPTICAL and DIAMOND maps
 *    the row's width factor is applied only when sampling).
 */
#ifndef PSC_TESTSUPPORT_H
#define PSC_TESTSUPPORT_H

#include <stddef.h>
#include <stdint.h>
#include "base/psc_types.h"
#include "envmap/psc_envmap.h"
#include "lut/psc_lut.h"
#include "viewer/psc_viewer.h"

#define TSUP_PI 3.14159265358979323846
#define TSUP_DEG (TSUP_PI / 180.0)

/* ---- angles --------------------------------------------------------------- */

/** Unsigned binary angle to radians in [0, 2pi). */
double tsup_bam_to_rad(psc_bam_t a);
/** Binary angle read as signed (pitch, latitude, or a turn in [-180, 180)) to radians. */
double tsup_sbam_to_rad(int32_t a);
/** Degrees to the nearest binary angle (wraps modulo one turn). */
psc_bam_t tsup_bam_from_deg(double deg);
/** Radians wrapped into [-pi, pi). */
double tsup_wrap_pi(double x);
/** Great-circle angle between two directions given as (lon, lat). */
double tsup_angle_between(double lon1, double lat1, double lon2, double lat2);

/* ---- deterministic random numbers (splitmix64) ---------------------------- */

typedef struct {
    uint64_t state;
} tsup_rng_t;

void tsup_rng_seed(tsup_rng_t *r, uint64_t seed);
uint64_t tsup_rng_u64(tsup_rng_t *r);
uint32_t tsup_rng_u32(tsup_rng_t *r);
/** Uniform in [0, 1). */
double tsup_rng_unit(tsup_rng_t *r);
/** Uniform in [lo, hi). */
double tsup_rng_range(tsup_rng_t *r, double lo, double hi);
/** Uniform integer in [0, n) (n > 0). */
uint32_t tsup_rng_below(tsup_rng_t *r, uint32_t n);

/* ---- exact geometry -------------------------------------------------------- */

/**
 * The exact direction (lon, lat) of the continuous output point (px, py) of an
 * out_w x out_h view (pixel (i, j) has its centre at (i + 0.5, j + 0.5)).
 */
void tsup_view_ray(const psc_view_t *view, unsigned out_w, unsigned out_h,
                   double px, double py, double *lon, double *lat);

/** The projection's row coordinate of a latitude: lat, tan lat or sin lat. */
double tsup_row_coord(psc_projection_t p, double lat);
/** Inverse of tsup_row_coord. */
double tsup_row_coord_inv(psc_projection_t p, double v);
/** Width of a map row at latitude lat as a fraction of W (1, cos lat, 1 - |lat|/90deg). */
double tsup_row_width_factor(psc_projection_t p, double lat);
/** Longitude span of a map in radians (2pi when lon_span == 0). */
double tsup_map_lon_span(const psc_envmap_t *m);

/**
 * Map position of a direction: row from the projection's row coordinate and
 * the coverage, col the full-width longitude column. For a full-turn map col is
 * in [-0.5, W - 0.5); for a partial map, longitudes are taken nearest to the
 * covered span (positions outside [-0.5, W - 0.5] are outside the map).
 */
void tsup_map_pos(const psc_envmap_t *m, double lon, double lat, double *row, double *col);
/** Inverse of tsup_map_pos: the direction at map position (row, col). */
void tsup_map_dir(const psc_envmap_t *m, double row, double col, double *lon, double *lat);
/** Latitude of the centre of map row r. */
double tsup_map_row_lat(const psc_envmap_t *m, int r);

/* ---- synthetic panoramas --------------------------------------------------- */

/**
 * The synthetic scene, an analytic function of direction, RGB in [0, 255]:
 * smooth colour gradients (functions of the 3D direction, so continuous at
 * the poles), soft dark grid lines every 15 degrees of lon (|lat| < 78) and
 * of lat, and coloured disk markers of 4 degrees radius:
 * north pole red, south pole blue, equator lon 0 green, lon +90 yellow,
 * lon -90 magenta, lon 180 cyan.
 */
void tsup_synth_color(double lon, double lat, double rgb[3]);

typedef enum {
    TSUP_MARK_NORTH = 0,
    TSUP_MARK_SOUTH,
    TSUP_MARK_LON0,
    TSUP_MARK_LON90E,
    TSUP_MARK_LON90W,
    TSUP_MARK_LON180,
    TSUP_MARK_COUNT
} tsup_marker_t;

/** Centre direction and colour (0xRRGGBB) of a marker. */
void tsup_marker(tsup_marker_t k, double *lon, double *lat, uint32_t *rgb);

/** A map the tests own: the description plus its heap buffers. */
typedef struct {
    psc_envmap_t map;
    uint8_t *pixels;
    uint32_t *palette;   /* PAL8 only */
} tsup_map_t;

/**
 * Fill a map with the synthetic scene. geom gives projection, format, width,
 * height and coverage (lon_min, lon_span, lat_top, lat_bottom); pass
 * default_coverage = 1 to take psc_envmap_default_coverage() instead. Every
 * pixel gets the colour of its centre's direction; for ELLIPTICAL and DIAMOND
 * maps pixels more than 2 px outside a row's width are black, those nearer
 * continue the scene across the seam. stride_pad adds bytes to each row.
 * Returns 0, or -1 on a bad argument / no memory.
 */
int tsup_synth_map(tsup_map_t *out, const psc_envmap_t *geom, int default_coverage, uint32_t stride_pad);
void tsup_map_free(tsup_map_t *m);

/** A map pixel as 0xRRGGBB, 8 bits per channel (RGB565 expanded by bit replication). */
uint32_t tsup_map_texel(const psc_envmap_t *m, int row, int col);

/** RGB565 <-> 8-bit conversions (bit replication on expansion; reduction round(v*31/255), round(v*63/255)). */
uint32_t tsup_rgb565_to_rgb888(uint16_t p);
uint16_t tsup_rgb888_to_rgb565(double r, double g, double b);
/** The 6x7x6 palette used for PAL8 maps (entries 252..255 are black). */
void tsup_pal8_palette(uint32_t pal[256]);
uint8_t tsup_pal8_index(double r, double g, double b);

/* ---- reference renderer and metrics ---------------------------------------- */

/**
 * Sample map m at (row, col) (col: full-width longitude column) with the
 * viewer's edge rules as the tests define them: rows clamp at the first and
 * last row; columns wrap modulo W on full-turn maps and clamp on partial ones;
 * ELLIPTICAL/DIAMOND rows take the column scaled by each row's width factor
 * and wrap within the row's own pixels (those whose centres lie inside the
 * row's width, centred at W/2).
 */
void tsup_map_sample(const psc_envmap_t *m, double row, double col, psc_filter_t filter, double rgb[3]);

/**
 * Render a view in double precision into rgb[out_w*out_h*3] (0..255):
 * exact ray -> (lon, lat) -> map position -> tsup_map_sample with
 * view->filter. ss > 1 averages ss x ss sub-pixel samples.
 */
void tsup_ref_render(const psc_envmap_t *m, const psc_view_t *view, unsigned out_w, unsigned out_h,
                     unsigned ss, double *rgb);

/** An output pixel as 8-bit RGB (RGB565 expanded by bit replication). */
void tsup_surface_rgb(const psc_surface_t *s, unsigned x, unsigned y, uint8_t rgb[3]);

/**
 * Mean squared error over the 8-bit RGB channels between a surface and a
 * reference image; the reference is first quantised exactly as a perfect
 * renderer would store it in the surface's format (XRGB8888: rounded;
 * RGB565: round(v*31/255) / round(v*63/255), then expanded).
 */
double tsup_mse_surface(const psc_surface_t *s, const double *ref_rgb);
/** 10 log10(255^2 / mse); +inf (HUGE_VAL) for mse == 0. */
double tsup_psnr(double mse);

/* ---- tables and viewers in memory -------------------------------------------- */

typedef struct {
    uint32_t *entries[PSC_VIEWER_MAX_LUTS];
    psc_lut_t luts[PSC_VIEWER_MAX_LUTS];
    unsigned count;
} tsup_luts_t;

/**
 * Build n tables (increasing hfov_max_deg[]) with psc_io_lut_build; rows/cols 0
 * take psc_io_lut_default_size(disp_w, disp_h, ...). 0 on success.
 */
int tsup_luts_build(tsup_luts_t *l, uint16_t disp_w, uint16_t disp_h, const double *hfov_max_deg,
                    unsigned n, uint16_t rows, uint16_t cols);
void tsup_luts_free(tsup_luts_t *l);

typedef struct {
    psc_viewer_t v;
    tsup_luts_t luts;
    void *ws;
    size_t ws_size;
    psc_surface_t out;        /* out_w x out_h, stride padded by 12 bytes */
    uint8_t *out_buf;         /* out.stride * out_h bytes + guard */
    size_t out_buf_size;
} tsup_viewer_t;

/**
 * A viewer for map m with two tables (60 and 120 degrees, as the pack's
 * defaults) sized for an out_w x out_h display, and an output surface of
 * out_fmt whose stride padding is filled with 0xA5 guard bytes. The
 * workspace is filled with garbage before psc_viewer_init. Returns the
 * status of psc_viewer_init, or PSC_ERR_NOMEM / PSC_ERR_ARG from the helper.
 */
psc_status_t tsup_viewer_init(tsup_viewer_t *tv, const psc_envmap_t *m, uint16_t out_w, uint16_t out_h,
                              psc_pixfmt_t out_fmt);
/** Like tsup_viewer_init with the caller's tables (hfov_max_deg[n], rows/cols 0 = default). */
psc_status_t tsup_viewer_init_luts(tsup_viewer_t *tv, const psc_envmap_t *m, uint16_t out_w, uint16_t out_h,
                                   psc_pixfmt_t out_fmt, const double *hfov_max_deg, unsigned n,
                                   uint16_t rows, uint16_t cols);
void tsup_viewer_free(tsup_viewer_t *tv);
/** 1 if every guard byte of the output buffer (row padding and tail) still reads 0xA5. */
int tsup_viewer_guard_ok(const tsup_viewer_t *tv);

/** A view from degrees. */
psc_view_t tsup_view_deg(double yaw_deg, double pitch_deg, double hfov_deg, psc_filter_t f, unsigned span_log2);

/* ---- little-endian byte access (pack tests) -------------------------------- */

uint16_t tsup_rd16(const uint8_t *p);
uint32_t tsup_rd32(const uint8_t *p);
void tsup_wr16(uint8_t *p, uint16_t v);
void tsup_wr32(uint8_t *p, uint32_t v);

#endif
