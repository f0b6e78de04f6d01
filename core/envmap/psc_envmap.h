/* SPDX-License-Identifier: MIT */
/*
 * psc_envmap.h - environment maps: a scene projected onto a surface of
 * revolution and stored as rows of pixels (seed US 5,748,194, "environment map").
 *
 * A map is addressed by the angles of a direction (longitude lon, latitude lat,
 * see psc_types.h). Each projection turns them into a fractional (row, column):
 *
 *   EQUIRECT   (lon, lat)       rows linear in lat, columns linear in lon.
 *   CYLINDER   (lon, tan lat)   rows linear in tan(lat); limited vertical field.
 *   SINE       (lon, sin lat)   rows linear in sin(lat): compressed near the poles.
 *   ELLIPTICAL (cos lat * lon, lat)  row r holds W*cos(lat_r) pixels, centred.
 *   DIAMOND    ((1-|lat|/90) * lon, lat)  row width falls linearly to the poles.
 *
 * Partial panoramas cover lon in [lon_min, lon_min + lon_span) and lat in
 * [lat_bottom, lat_top]; lon_span == 0 means the full turn (columns wrap).
 * The map's edges are at those angles: column c covers lon_min + [c, c+1)*span/W,
 * row r covers lat_top .. lat_bottom in H equal steps of the projection's
 * row coordinate (lat, tan lat or sin lat).
 */
#ifndef PSC_ENVMAP_H
#define PSC_ENVMAP_H

#include "base/psc_types.h"

typedef enum {
    PSC_PROJ_EQUIRECT = 1,
    PSC_PROJ_CYLINDER = 2,
    PSC_PROJ_SINE = 3,
    PSC_PROJ_ELLIPTICAL = 4,
    PSC_PROJ_DIAMOND = 5
} psc_projection_t;

/** Name of a projection ("equirect", "cylinder", "sine", "elliptical", "diamond"), or "?". */
const char *psc_projection_name(psc_projection_t p);

/** Description of a map whose pixels the caller owns. */
typedef struct {
    psc_projection_t projection;
    psc_pixfmt_t format;       /* RGB565, XRGB8888 or PAL8 */
    uint32_t width, height;    /* a flat map: up to PSC_MAX_MAP_DIM; a tiled one (psc_tiles.h) larger */
    uint32_t stride;           /* bytes per map row */
    const void *pixels;
    const uint32_t *palette;   /* 256 XRGB8888 entries when format is PAL8 */
    psc_bam_t lon_min;         /* longitude of the left edge of column 0 */
    psc_bam_t lon_span;        /* 0 = the full 360 degrees */
    int32_t lat_top;           /* latitude of the top edge of row 0 (bam, signed) */
    int32_t lat_bottom;        /* latitude of the bottom edge of the last row */
} psc_envmap_t;

/**
 * Check a map description: dimensions within limits, coverage consistent with
 * the projection (ELLIPTICAL and DIAMOND must be full spheres, CYLINDER must
 * stay inside +-85 degrees). Returns PSC_OK or PSC_ERR_ARG / PSC_ERR_TOO_LARGE.
 */
psc_status_t psc_envmap_check(const psc_envmap_t *m);

/** The default full coverage of a projection for a W x H map (cylinder: tan(lat_top) = pi*H/W). */
void psc_envmap_default_coverage(psc_envmap_t *m);

#endif
