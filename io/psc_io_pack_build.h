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
    psc_pixfmt_t format;           /* default RGB888 */
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
    uint8_t tile_codec;            /* a tiled pack's tiles: PSC_TILE_CODEC_RAW (default) or PSC_TILE_CODEC_JPEG */
    uint8_t tile_quality;          /* JPEG tiles: 1..100 (default PSC_IO_TILE_JPEG_QUALITY) */
    void (*progress)(const char *stage, unsigned percent, void *ctx);  /* may be NULL */
    void *progress_ctx;
} psc_pack_options_t;

/* JPEG tiles' default quality: see docs/viewer.md, "JPEG tiles", for the measurements behind it. */
#define PSC_IO_TILE_JPEG_QUALITY 90u

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

/** What a tiled pack's container holds beside its scene and tables (psc_io_tiles.h writes the tiles). */
typedef struct {
    uint32_t level_count, tile_count;
    const void *index;         /* tile_count psc_pack_tile_raw_t, little-endian; NULL: only check the options */
    size_t index_size;
    uint64_t store_size;       /* the tile store's bytes, after the container */
} psc_io_tiled_head_t;

/**
 * The container of a tiled pack (core/pack/psc_pack.h) of a width x height
 * map: SCEN (map size 0), TINF, TIDX and the LUTs, its store placed at the
 * container's end rounded to 64 bytes. The options are checked as
 * psc_io_pack_build checks them, with the tiled limits (and full-turn
 * equirect, cylinder or sine maps only). *map_out (may be NULL): the map's
 * description. With tiles->index NULL only the checks run. 0, or -1 with err.
 */
int psc_io_pack_build_tiled_head(uint32_t width, uint32_t height, const psc_pack_options_t *opt,
                                 const psc_io_tiled_head_t *tiles, uint8_t **out, size_t *out_len,
                                 psc_envmap_t *map_out, char *err, size_t errlen);

/** The bytes of that container (where its store starts), known before any tile is made. */
uint64_t psc_io_pack_tiled_head_size(const psc_pack_options_t *opt, uint32_t tile_count);

#endif
