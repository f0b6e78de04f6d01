/*
 * psc_viewer_internal.h - what the viewer's source files share; not part of
 * the public API.
 */
#ifndef PSC_VIEWER_INTERNAL_H
#define PSC_VIEWER_INTERNAL_H

#include "psc_viewer.h"
#include "psc_fixed.h"
#include "psc_pixel.h"

#define PSC_LAT_TABLE_SHIFT 19u /* 2^31 bam (180 degrees) / 4096 intervals */

/* What a rendering pass writes per pixel. */
typedef enum {
    PSC_SINK_RGB565,
    PSC_SINK_XRGB8888,
    PSC_SINK_TRACE /* the sampled (row, col), for tests and tools */
} psc_sink_t;

/* Everything fixed for one frame. */
typedef struct {
    psc_viewer_t *v;
    const psc_view_t *view;
    const psc_lut_t *lut;
    int32_t sin_pitch, cos_pitch;  /* Q2.30 */
    int32_t cap_per_pixel;         /* |lat| >= this: LUT read at every pixel (polar cap) */
    int32_t cap_exact;             /* |lat| >= this: exact CORDIC per pixel (inner polar cap) */
    unsigned span;                 /* N: LUT read every N pixels */
    psc_sink_t sink;
    psc_filter_t filter;           /* nearest or bilinear: what the non-mip samplers do */
    bool mip;                      /* PSC_FILTER_MIP with a pyramid on a fast map */
    uint8_t *dst;                  /* current output row (RGB565/XRGB8888) */
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
 * Trilinear spans: pixels [x, x + n) from level-0 position (row, col) in steps
 * (drow, dcol), at level of detail lod_q8 (log2 texels per pixel, Q24.8).
 */
void psc_span_mip(const psc_frame_t *f, unsigned x, unsigned n, int32_t row, int32_t col, int32_t drow, int32_t dcol,
                  int32_t lod_q8);
/* Sample any map at (row, col) Q16.16 through the general (per-pixel, clamping) path: XRGB8888. */
uint32_t psc_sample_general(const psc_viewer_t *v, psc_filter_t filter, int32_t row, int32_t col);

#endif
