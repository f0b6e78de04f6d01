/* SPDX-License-Identifier: MIT */
/*
 * fuzz_tile_jpeg.c - a tiled pack's JPEG tile (core/pack/psc_pack.h,
 * PSC_TILE_CODEC_JPEG) through the reader's decoder (io/psc_io_tiles_jpeg.h)
 * into a tile of each map format the codec serves, one decoder for all (as a
 * reading thread keeps its own across tiles). A tile decodes, or is refused
 * with a reason; a refused one leaves the decoder usable: a known-good tile
 * decodes after it, to the same pixels every time.
 */
#include <stdlib.h>
#include <string.h>

#include "fuzz_support.h"
#include "psc_io_tiles_jpeg.h"
#include "tiles/psc_tiles.h"
#include "pack/psc_pack.h"

#define SIDE PSC_TILE_SIDE
#define CAP PSC_TILE_JPEG_MAX_BYTES(SIDE * SIDE * 4u)

static uint8_t good[CAP];
static uint32_t good_size;
static uint8_t first[SIDE * SIDE * 4u];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static psc_io_tile_decoder_t *dec;
    static uint8_t tile[SIDE * SIDE * 4u];
    if (!dec) {   /* once: the decoder, and a good tile (a gradient) to decode after each input */
        dec = psc_io_tile_decoder_new(CAP);
        FUZZ_REQUIRE(dec != NULL);
        static uint32_t px[SIDE * SIDE];
        for (uint32_t i = 0; i < SIDE * SIDE; i++)
            px[i] = 0xFF000000u | (i % SIDE) << 16 | (i / SIDE) << 8 | ((i * 7u) & 255u);
        char err[256];
        good_size = psc_io_tile_jpeg_encode(px, 75, good, CAP, err, sizeof err);
        FUZZ_REQUIRE(good_size > 0);
        memcpy(psc_io_tile_decoder_buffer(dec), good, good_size);
        FUZZ_REQUIRE(psc_io_tile_jpeg_decode(dec, good_size, PSC_PIX_XRGB8888, first, SIDE * 4u, err, sizeof err) == 0);
    }
    static const psc_pixfmt_t fmts[] = {PSC_PIX_RGB888, PSC_PIX_XRGB8888, PSC_PIX_RGB565, PSC_PIX_PAL8};
    psc_pixfmt_t fmt = fmts[fuzz_hash(data, size) % 4u];
    uint32_t n = size > CAP ? CAP : (uint32_t)size;
    memcpy(psc_io_tile_decoder_buffer(dec), data, n);
    char why[256] = "";
    int rc = psc_io_tile_jpeg_decode(dec, n, fmt, tile, psc_pixfmt_row_bytes(fmt, SIDE), why, sizeof why);
    FUZZ_REQUIRE(rc == 0 || why[0] != '\0');
    FUZZ_REQUIRE(rc != 0 || fmt != PSC_PIX_PAL8);   /* a PAL8 map holds no JPEG tiles */
    /* the decoder still decodes: the good tile, the same pixels */
    memcpy(psc_io_tile_decoder_buffer(dec), good, good_size);
    FUZZ_REQUIRE(psc_io_tile_jpeg_decode(dec, good_size, PSC_PIX_XRGB8888, tile, SIDE * 4u, why, sizeof why) == 0);
    FUZZ_REQUIRE(memcmp(tile, first, sizeof first) == 0);
    return 0;
}
