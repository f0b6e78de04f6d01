/* SPDX-License-Identifier: MIT */
/*
 * psc_tiles.h - a map too large for memory, as a pyramid of tiles of which
 * only some are resident (issue 30: gigapixel panoramas in bounded memory).
 *
 * Level 0 is the whole map, W x H; level k is exactly (W >> k) x (H >> k),
 * filtered down from level k - 1 as a flat pack's pyramid is (so a tiled
 * pack's levels are the flat pack's bytes); levels exist while both sides
 * halve exactly, at most PSC_TILES_MAX_LEVELS. Each level is cut into tiles
 * of PSC_TILE_SIDE x PSC_TILE_SIDE pixels from its top-left corner, row by
 * row; a tile at the right or bottom edge is stored whole, its pixels beyond
 * the level unused. The tiles of all levels are numbered level 0 first.
 *
 * Why 256: a 4-pixel span of the viewer at 1:1 reads a 5 x 2 texel box, so
 * with 256 the box straddles two tiles for about one span in 30 (those read
 * texel by texel); a tile is 128 KB of RGB565, 256 KB of XRGB8888, large
 * enough that a read from storage is one sequential transfer, small enough
 * that a 64 MB cache holds 256 to 512 of them: an 800 x 480 view at 1:1 needs
 * about 20 (psc_tiles.c has the arithmetic).
 *
 * Residency is the caller's (a cache in the io layer, which core does not
 * know): a table of one pointer per tile, NULL where the tile is not in
 * memory, changed between frames only. core reads it while it draws and
 * records the tiles it missed (psc_viewer.h, psc_viewer_requests); where a
 * tile is missing it samples the finest level that is resident there.
 */
#ifndef PSC_TILES_H
#define PSC_TILES_H

#include "base/psc_types.h"

#define PSC_TILE_LOG2 8u
#define PSC_TILE_SIDE (1u << PSC_TILE_LOG2)
#define PSC_TILES_MAX_LEVELS 12u
#define PSC_TILES_MAX_WIDTH 65536u     /* level 0: a 2-gigapixel full sphere */
#define PSC_TILES_MAX_HEIGHT 32768u
/* tiles of a 65536 x 32768 pyramid of 12 levels: 32768 + 8192 + 2048 + ... + 1 */
#define PSC_TILES_MAX_COUNT 43694u

/** One level's geometry. */
typedef struct {
    uint32_t width, height;      /* pixels */
    uint32_t tiles_x, tiles_y;   /* tiles across and down */
    uint32_t first;              /* number of its first tile */
} psc_tile_level_t;

/** A tiled map: geometry, pixel format and the caller's residency table. */
typedef struct {
    psc_pixfmt_t format;
    const uint32_t *palette;            /* PAL8: 256 XRGB8888 entries */
    uint32_t level_count, tile_count;
    uint32_t tile_stride;               /* bytes per tile row: psc_pixfmt_row_bytes(format, PSC_TILE_SIDE) */
    uint32_t tile_bytes;                /* a whole tile */
    psc_tile_level_t level[PSC_TILES_MAX_LEVELS];
    const void *const *resident;        /* tile_count pointers (tile_bytes each, aligned to 4), NULL: absent */
} psc_tiles_t;

/** The number of levels a W x H map has (exact halvings, at most PSC_TILES_MAX_LEVELS). */
uint32_t psc_tiles_level_count(uint32_t width, uint32_t height);

/**
 * Describe a tiled map of width x height (level 0) with `levels` levels
 * (1..psc_tiles_level_count) in format (palette: PAL8's, else NULL); the
 * residency table (`resident`, tile_count entries) is the caller's to set.
 * PSC_ERR_ARG or PSC_ERR_TOO_LARGE for sizes outside 1..PSC_TILES_MAX_WIDTH x
 * PSC_TILES_MAX_HEIGHT.
 */
psc_status_t psc_tiles_init(psc_tiles_t *t, uint32_t width, uint32_t height, uint32_t levels, psc_pixfmt_t format,
                            const uint32_t *palette);

/** The tile of level k holding pixel (row, col) of that level (inside it). */
static inline uint32_t psc_tiles_at(const psc_tiles_t *t, uint32_t k, uint32_t row, uint32_t col)
{
    const psc_tile_level_t *l = &t->level[k];
    return l->first + (row >> PSC_TILE_LOG2) * l->tiles_x + (col >> PSC_TILE_LOG2);
}

/** Tile number i's level (the level whose tiles hold it). */
uint32_t psc_tiles_level_of(const psc_tiles_t *t, uint32_t i);

#endif
