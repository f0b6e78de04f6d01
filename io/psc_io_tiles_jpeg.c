/* SPDX-License-Identifier: MIT */
/*
 * psc_io_tiles_jpeg.c - JPEG tiles: encoded by the tiled pack's writer,
 * decoded by its reader (psc_io_tiles_jpeg.h).
 *
 * Both sides go through 8-bit RGB rows: the writer encodes the image's pixels
 * (not the map's format: an RGB565 map's tiles keep the image's 8 bits), the
 * reader converts each decoded row as psc_io_map_convert converts a flat
 * pack's image, so a JPEG tile differs from a raw one by the JPEG's error
 * alone.
 */
#include "psc_io_tiles_jpeg.h"
#include "psc_io_image.h"
#include "psc_io_jpeg_fail.h"
#include "psc_io_map_convert.h"
#include "tiles/psc_tiles.h"

#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <jerror.h>
#include <jpeglib.h>

/* ---- encoding ----------------------------------------------------------------------------------------------- */

/* A destination that fills a caller's buffer and fails past its end (libjpeg's own grows a buffer it allocates). */
typedef struct {
    struct jpeg_destination_mgr mgr;
    uint8_t *buf;
    uint32_t cap;
} fixed_dest_t;

static void dest_init(j_compress_ptr c)
{
    fixed_dest_t *d = (fixed_dest_t *)c->dest;
    d->mgr.next_output_byte = d->buf;
    d->mgr.free_in_buffer = d->cap;
}

static boolean dest_full(j_compress_ptr c)
{
    ERREXIT(c, JERR_BUFFER_SIZE);   /* the tile does not fit: longjmps through error_exit */
    return FALSE;
}

static void dest_term(j_compress_ptr c)
{
    (void)c;
}

typedef struct {
    struct jpeg_error_mgr mgr;   /* first: libjpeg hands us a pointer to it */
    jmp_buf jump;
    char msg[JMSG_LENGTH_MAX];
} encode_fail_t;

static void encode_exit(j_common_ptr c)
{
    encode_fail_t *f = (encode_fail_t *)c->err;
    f->mgr.format_message(c, f->msg);
    longjmp(f->jump, 1);
}

/* The state the encoder's setjmp frame must not hold in locals. */
typedef struct {
    struct jpeg_compress_struct c;
    encode_fail_t fail;
    fixed_dest_t dest;
    JSAMPLE row[PSC_TILE_SIDE * 3];
} encode_job_t;

uint32_t psc_io_tile_jpeg_encode(const uint32_t *xrgb, unsigned quality, uint8_t *out, uint32_t cap, char *err,
                                 size_t errlen)
{
    encode_job_t *j = calloc(1, sizeof *j);
    if (!j) {
        snprintf(err, errlen, "out of memory for the JPEG encoder");
        return 0;
    }
    j->c.err = jpeg_std_error(&j->fail.mgr);
    j->fail.mgr.error_exit = encode_exit;
    if (setjmp(j->fail.jump)) {
        snprintf(err, errlen, "cannot encode a JPEG tile: %s", j->fail.msg);
        jpeg_destroy_compress(&j->c);
        free(j);
        return 0;
    }
    jpeg_create_compress(&j->c);
    j->dest = (fixed_dest_t){{.init_destination = dest_init, .empty_output_buffer = dest_full,
                              .term_destination = dest_term}, out, cap};
    j->c.dest = &j->dest.mgr;
    j->c.image_width = PSC_TILE_SIDE;
    j->c.image_height = PSC_TILE_SIDE;
    j->c.input_components = 3;
    j->c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&j->c);
    jpeg_set_quality(&j->c, (int)quality, TRUE);
    /* full chroma (4:4:4): a museum's picture has colour detail a pixel wide (a painting's strokes, a label's
     * letters) that 4:2:0 would blur; measured 11 % more bytes on a photograph, twice on one-pixel colour detail */
    j->c.comp_info[0].h_samp_factor = j->c.comp_info[0].v_samp_factor = 1;
    j->c.optimize_coding = TRUE;   /* Huffman tables for this tile: about 5 % smaller, for a little encoding time */
    jpeg_start_compress(&j->c, TRUE);
    for (uint32_t y = 0; y < PSC_TILE_SIDE; y++) {
        const uint32_t *src = xrgb + (size_t)y * PSC_TILE_SIDE;
        for (uint32_t x = 0; x < PSC_TILE_SIDE; x++) {
            j->row[3 * x] = (JSAMPLE)(src[x] >> 16 & 255u);
            j->row[3 * x + 1] = (JSAMPLE)(src[x] >> 8 & 255u);
            j->row[3 * x + 2] = (JSAMPLE)(src[x] & 255u);
        }
        JSAMPROW r = j->row;
        jpeg_write_scanlines(&j->c, &r, 1);
    }
    jpeg_finish_compress(&j->c);
    uint32_t size = (uint32_t)(cap - j->dest.mgr.free_in_buffer);
    jpeg_destroy_compress(&j->c);
    free(j);
    return size;
}

/* ---- decoding ----------------------------------------------------------------------------------------------- */

struct psc_io_tile_decoder {
    struct jpeg_decompress_struct c;   /* created once; aborted after each tile, good or bad */
    psc_io_jpeg_fail_t fail;
    uint8_t *buf;
    uint32_t cap;
    JSAMPLE rgb[PSC_TILE_SIDE * 3];
    uint32_t xrgb[PSC_TILE_SIDE];
};

psc_io_tile_decoder_t *psc_io_tile_decoder_new(uint32_t cap)
{
    psc_io_tile_decoder_t *volatile d = calloc(1, sizeof *d);   /* (volatile: read after the longjmp) */
    if (!d)
        return NULL;
    d->buf = malloc(cap ? cap : 1u);
    if (!d->buf) {
        free(d);
        return NULL;
    }
    d->cap = cap;
    psc_io_jpeg_fail_init(&d->c, &d->fail);
    if (setjmp(d->fail.jump)) {   /* (creating fails only when out of memory) */
        free(d->buf);
        free(d);
        return NULL;
    }
    jpeg_create_decompress(&d->c);
    return d;
}

void psc_io_tile_decoder_free(psc_io_tile_decoder_t *d)
{
    if (!d)
        return;
    jpeg_destroy_decompress(&d->c);
    free(d->buf);
    free(d);
}

uint8_t *psc_io_tile_decoder_buffer(psc_io_tile_decoder_t *d)
{
    return d->buf;
}

int psc_io_tile_jpeg_decode(psc_io_tile_decoder_t *d, uint32_t size, psc_pixfmt_t format, uint8_t *dst,
                            uint32_t stride, char *why, size_t whylen)
{
    if (size == 0 || size > d->cap) {
        snprintf(why, whylen, "has %u bytes, not a JPEG tile's 1..%u", (unsigned)size, (unsigned)d->cap);
        return -1;
    }
    if (format != PSC_PIX_RGB565 && format != PSC_PIX_RGB888 && format != PSC_PIX_XRGB8888) {
        snprintf(why, whylen, "is a JPEG tile of a map whose format holds no JPEG");
        return -1;
    }
    if (setjmp(d->fail.jump)) {
        snprintf(why, whylen, "is not a JPEG tile that decodes (%s)", d->fail.msg);
        jpeg_abort_decompress(&d->c);
        return -1;
    }
    jpeg_mem_src(&d->c, d->buf, size);
    jpeg_read_header(&d->c, TRUE);
    if (d->c.image_width != PSC_TILE_SIDE || d->c.image_height != PSC_TILE_SIDE) {
        snprintf(why, whylen, "is a %ux%u JPEG, not a %ux%u tile", (unsigned)d->c.image_width,
                 (unsigned)d->c.image_height, PSC_TILE_SIDE, PSC_TILE_SIDE);
        jpeg_abort_decompress(&d->c);
        return -1;
    }
    d->c.out_color_space = JCS_RGB;   /* from grey or YCbCr alike */
    jpeg_start_decompress(&d->c);
    const psc_image_t row = {PSC_TILE_SIDE, 1, d->xrgb};
    for (uint32_t y = 0; y < PSC_TILE_SIDE; y++) {
        JSAMPROW r = d->rgb;
        if (jpeg_read_scanlines(&d->c, &r, 1) != 1)
            ERREXIT(&d->c, JERR_INPUT_EOF);
        for (uint32_t x = 0; x < PSC_TILE_SIDE; x++)
            d->xrgb[x] = 0xFF000000u | (uint32_t)d->rgb[3 * x] << 16 | (uint32_t)d->rgb[3 * x + 1] << 8 |
                         (uint32_t)d->rgb[3 * x + 2];
        if (psc_io_map_convert(&row, format, dst + (size_t)y * stride, NULL, NULL, NULL) != 0)
            ERREXIT(&d->c, JERR_BAD_IN_COLORSPACE);   /* (not for these three formats) */
    }
    jpeg_finish_decompress(&d->c);
    return 0;
}
