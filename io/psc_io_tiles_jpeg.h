/* SPDX-License-Identifier: MIT */
/*
 * psc_io_tiles_jpeg.h - JPEG tiles (core/pack/psc_pack.h, PSC_TILE_CODEC_JPEG):
 * a tile's 256 x 256 pixels encoded by the tiled pack's writer and decoded by
 * its reader, through libjpeg(-turbo). Internal to io's tiles.
 *
 * A decoder is made once per thread that reads tiles (the cache's own loads
 * and the loader thread's): its buffer for a tile's bytes and its libjpeg
 * state are allocated then. libjpeg still allocates its working buffers for
 * each tile it decodes (its memory manager's image pool, freed at the tile's
 * end: a few hundred KB, bounded by the tile's size); that is in the reading
 * thread, never in a frame.
 */
#ifndef PSC_IO_TILES_JPEG_H
#define PSC_IO_TILES_JPEG_H

#include <stddef.h>
#include <stdint.h>

#include "base/psc_types.h"

/**
 * Encode a tile of PSC_TILE_SIDE x PSC_TILE_SIDE pixels (xrgb, 0xFFRRGGBB,
 * rows of PSC_TILE_SIDE) at quality 1..100 (full chroma, 4:4:4) into out[0..cap).
 * The encoded size, or 0 with err naming the problem (a tile larger than
 * cap, a libjpeg error).
 */
uint32_t psc_io_tile_jpeg_encode(const uint32_t *xrgb, unsigned quality, uint8_t *out, uint32_t cap, char *err,
                                 size_t errlen);

typedef struct psc_io_tile_decoder psc_io_tile_decoder_t;

/** A decoder whose buffer holds up to cap bytes of a tile. NULL when out of memory. */
psc_io_tile_decoder_t *psc_io_tile_decoder_new(uint32_t cap);
void psc_io_tile_decoder_free(psc_io_tile_decoder_t *d);

/** Where a tile's bytes go before decoding (cap bytes). */
uint8_t *psc_io_tile_decoder_buffer(psc_io_tile_decoder_t *d);

/**
 * Decode the buffer's first size bytes, a JPEG of PSC_TILE_SIDE x
 * PSC_TILE_SIDE pixels, into dst: rows of stride bytes in format (RGB565,
 * RGB888 or XRGB8888), each converted as a flat pack converts its image
 * (io/psc_io_map_convert.h). 0, or -1 with why saying what is wrong with the
 * bytes (not a JPEG, another size, a damaged stream).
 */
int psc_io_tile_jpeg_decode(psc_io_tile_decoder_t *d, uint32_t size, psc_pixfmt_t format, uint8_t *dst,
                            uint32_t stride, char *why, size_t whylen);

#endif
