/* SPDX-License-Identifier: MIT */
/*
 * psc_tiles.c - a tiled map's geometry (psc_tiles.h).
 *
 * The cache an 800 x 480 view needs at 1:1: its footprint is at most about
 * 800 x 480 texels, which touch ceil(800 / 256) + 1 = 5 tile columns and
 * ceil(480 / 256) + 1 = 3 tile rows, 15 tiles, plus the next level's few for
 * the blend of PSC_FILTER_MIP: about 20.
 */
#include "tiles/psc_tiles.h"

uint32_t psc_tiles_level_count(uint32_t width, uint32_t height)
{
    uint32_t n = 1;
    while (n < PSC_TILES_MAX_LEVELS && ((width >> (n - 1u)) & 1u) == 0 && ((height >> (n - 1u)) & 1u) == 0 &&
           (width >> n) > 1 && (height >> n) > 0)
        n++;
    return n;
}

psc_status_t psc_tiles_init(psc_tiles_t *t, uint32_t width, uint32_t height, uint32_t levels, psc_pixfmt_t format,
                            const uint32_t *palette)
{
    if (!t || width == 0 || height == 0 || psc_pixfmt_bytes(format) == 0 || (format == PSC_PIX_PAL8 && !palette))
        return PSC_ERR_ARG;
    if (width > PSC_TILES_MAX_WIDTH || height > PSC_TILES_MAX_HEIGHT)
        return PSC_ERR_TOO_LARGE;
    if (levels == 0 || levels > psc_tiles_level_count(width, height))
        return PSC_ERR_ARG;
    *t = (psc_tiles_t){0};
    t->format = format;
    t->palette = format == PSC_PIX_PAL8 ? palette : NULL;
    t->level_count = levels;
    t->tile_stride = psc_pixfmt_row_bytes(format, PSC_TILE_SIDE);
    t->tile_bytes = t->tile_stride * PSC_TILE_SIDE;
    uint32_t first = 0;
    for (uint32_t k = 0; k < levels; k++) {
        psc_tile_level_t *l = &t->level[k];
        l->width = width >> k;
        l->height = height >> k;
        l->tiles_x = (l->width + PSC_TILE_SIDE - 1u) >> PSC_TILE_LOG2;
        l->tiles_y = (l->height + PSC_TILE_SIDE - 1u) >> PSC_TILE_LOG2;
        l->first = first;
        first += l->tiles_x * l->tiles_y;   /* at most 256 x 128 at level 0: no overflow */
    }
    t->tile_count = first;
    return PSC_OK;
}

uint32_t psc_tiles_level_of(const psc_tiles_t *t, uint32_t i)
{
    uint32_t k = 0;
    while (k + 1u < t->level_count && i >= t->level[k + 1u].first)
        k++;
    return k;
}
