/* SPDX-License-Identifier: MIT */
/*
 * psc_io_pack_build.h - build a scene pack (format: core/pack/psc_pack.h) from an
 * image (loading one is io/psc_io_image.h). Uses the heap and
 * stdio freely.
 */
#ifndef PSC_PACK_BUILD_H
#define PSC_PACK_BUILD_H

#include <stddef.h>
#include <stdint.h>
#include "pack/psc_pack.h"
#include "psc_io_image.h"

typedef struct {
    psc_projection_t projection;   /* default EQUIRECT */
    psc_pixfmt_t format;           /* default RGB565 */
    uint16_t display_width, display_height;  /* default 640x480 */
    /* coverage; lon_span 0 and lat_top == lat_bottom == 0 mean "the projection's default" */
    psc_bam_t lon_min, lon_span;
    int32_t lat_top, lat_bottom;
    double hfov_min_deg;           /* default 20 */
    double hfov_switch_deg;        /* default 60: narrow LUT serves up to this */
    double hfov_max_deg;           /* default 120: wide LUT serves up to this */
    double default_yaw_deg, default_pitch_deg, default_hfov_deg;  /* default 0, 0, 90 */
    uint16_t lut_rows, lut_cols;   /* 0 = psc_io_lut_default_size() */
    unsigned map_levels;           /* pyramid levels incl. the map itself: 0 = as many as the size
                                    * allows (full-turn equirect, cylinder and sine maps), 1 = none */
    void (*progress)(const char *stage, unsigned percent, void *ctx);  /* may be NULL */
    void *progress_ctx;
} psc_pack_options_t;

void psc_io_pack_options_default(psc_pack_options_t *o);

/**
 * The longitudes the image covers, lo..hi degrees (periscope-pack's
 * --lon-range, or an image's GPano XMP): hi > lo, hi - lo <= 360. A partial
 * turn also turns the default view to its middle. 0, or -1 (o unchanged).
 */
int psc_io_pack_options_set_lon_range(psc_pack_options_t *o, double lo, double hi);

/**
 * The latitudes of the image's top and bottom edges (--lat-range, or GPano):
 * 90 >= top > bottom >= -90; the default view looks at their middle. 0, or -1.
 */
int psc_io_pack_options_set_lat_range(psc_pack_options_t *o, double top, double bottom);

/**
 * Build a pack in memory. *out is malloc'd (free()). 0 on success; -1 with err
 * filled (naming the problem) on failure. The map is the image converted to
 * opt->format (RGB565 rounded to nearest; PAL8 through a 256-colour palette).
 */
int psc_io_pack_build(const psc_image_t *img, const psc_pack_options_t *opt,
                   uint8_t **out, size_t *out_len, char *err, size_t errlen);

#endif
