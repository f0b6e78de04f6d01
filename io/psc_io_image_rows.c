/* SPDX-License-Identifier: MIT */
/*
 * psc_io_image_rows.c - JPEG and PNG images read row by row
 * (psc_io_image_rows.h). Both libraries report fatal errors through a
 * handler that must not return: ours longjmps back to a setjmp in the very
 * function that called into the library, so every entry point that decodes
 * has its own. All the state lives in the heap object, never in a setjmp
 * frame, so it is still valid after a longjmp and can be freed.
 *
 * The decode settings are psc_io_jpeg.c's and psc_io_png.c's, repeated here
 * because the row reader must give the same pixels: a change there needs the
 * same change here (tests/test_image_rows.c compares the two byte for byte).
 */
#include "psc_io_image_rows.h"
#include "psc_io_jpeg_fail.h"
#include "psc_io_png_src.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <errno.h>
#include <setjmp.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <jpeglib.h>
#include <jerror.h>
#include <png.h>

typedef enum { ROWS_JPEG, ROWS_PNG } rows_kind_t;


struct psc_io_image_rows {
    rows_kind_t kind;
    FILE *file;
    char *path;                  /* a copy, for the messages of later calls */
    uint32_t width, height;
    uint32_t next_row;           /* the row the next call returns */
    bool failed;                 /* an earlier call failed: the decoder's state is gone */
    bool probe;                  /* psc_io_image_probe: stop once the header has given the size */

    /* JPEG */
    struct jpeg_decompress_struct jpeg;
    psc_io_jpeg_fail_t jpeg_fail;
    bool jpeg_created;
    bool cmyk, inverted;         /* CMYK or YCCK output; Adobe's inverted ink */
    unsigned channels;           /* 3 (RGB) or 4 (CMYK) bytes a pixel from libjpeg */
    JSAMPLE *jpeg_row;           /* one decoded row */

    /* PNG */
    png_structp png;
    png_infop png_info;
    psc_io_png_src_t png_src;    /* libpng's error and read pointer: the file and its last error */
};

static const uint8_t rows_jpeg_magic[3] = {0xFF, 0xD8, 0xFF};
static const uint8_t rows_png_magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

/* ---- JPEG ------------------------------------------------------------------------------------- */

/* The bytes of libjpeg's whole-image coefficient buffer (a multi-scan file needs one): each
 * component's blocks, padded to its sampling factors, 64 coefficients of a JCOEF each. */
static uint64_t rows_jpeg_coef_bytes(const struct jpeg_decompress_struct *cinfo)
{
    uint64_t total = 0;
    for (int ci = 0; ci < cinfo->num_components; ci++) {
        const jpeg_component_info *c = &cinfo->comp_info[ci];
        uint64_t h = (uint64_t)c->h_samp_factor, v = (uint64_t)c->v_samp_factor;
        uint64_t w_blocks = (c->width_in_blocks + h - 1) / h * h, h_blocks = (c->height_in_blocks + v - 1) / v * v;
        total += w_blocks * h_blocks * DCTSIZE2 * sizeof(JCOEF);
    }
    return total;
}

/* The limits, from the header: 0, or -1 with the message. */
static int rows_check_size(psc_io_image_rows_t *r, uint32_t w, uint32_t h, uint32_t max_width, uint32_t max_height,
                           char *err, size_t errlen)
{
    uint32_t lim_w = max_width < PSC_IO_IMAGE_ROWS_MAX_SIDE ? max_width : PSC_IO_IMAGE_ROWS_MAX_SIDE;
    uint32_t lim_h = max_height < PSC_IO_IMAGE_ROWS_MAX_SIDE ? max_height : PSC_IO_IMAGE_ROWS_MAX_SIDE;
    if (w == 0 || h == 0)
        return psc_io_errorf(err, errlen, r->path, "image has no pixels (%ux%u)", (unsigned)w, (unsigned)h);
    if (w > lim_w)
        return psc_io_errorf(err, errlen, r->path, "image is %ux%u, wider than the limit of %u pixels",
                             (unsigned)w, (unsigned)h, (unsigned)lim_w);
    if (h > lim_h)
        return psc_io_errorf(err, errlen, r->path, "image is %ux%u, taller than the limit of %u pixels",
                             (unsigned)w, (unsigned)h, (unsigned)lim_h);
    r->width = w;
    r->height = h;
    return 0;
}

static int rows_jpeg_open(psc_io_image_rows_t *r, uint32_t max_width, uint32_t max_height, char *err, size_t errlen)
{
    struct jpeg_decompress_struct *cinfo = &r->jpeg;
    if (setjmp(r->jpeg_fail.jump))
        return psc_io_errorf(err, errlen, r->path, "corrupt or truncated JPEG (before row 0): %s", r->jpeg_fail.msg);

    /* Set first: destroying a half-created object is safe (its memory pool is NULL). */
    r->jpeg_created = true;
    jpeg_create_decompress(cinfo);
    jpeg_stdio_src(cinfo, r->file);
    jpeg_read_header(cinfo, TRUE);

    bool cmyk = cinfo->jpeg_color_space == JCS_CMYK || cinfo->jpeg_color_space == JCS_YCCK;
    if (!cmyk && cinfo->jpeg_color_space != JCS_GRAYSCALE && cinfo->jpeg_color_space != JCS_YCbCr &&
        cinfo->jpeg_color_space != JCS_RGB)
        return psc_io_errorf(err, errlen, r->path, "unsupported JPEG colour space %d", (int)cinfo->jpeg_color_space);
    if (rows_check_size(r, cinfo->image_width, cinfo->image_height, max_width, max_height, err, errlen) != 0)
        return -1;
    if (r->probe)
        return 0;
    /* A single-scan file is decoded an MCU row at a time; any other is read whole into
     * coefficients first, which only a small enough image may do. */
    if (jpeg_has_multiple_scans(cinfo)) {
        uint64_t need = rows_jpeg_coef_bytes(cinfo);
        if (need > PSC_IO_IMAGE_ROWS_JPEG_SCAN_BUDGET)
            return psc_io_errorf(err, errlen, r->path,
                                 "progressive or multi-scan JPEG of %ux%u: decoding it needs all of its %llu MiB of "
                                 "coefficients in memory, more than the row reader's %llu MiB; save it as a "
                                 "baseline JPEG",
                                 (unsigned)r->width, (unsigned)r->height, (unsigned long long)((need + 0xFFFFFu) >> 20),
                                 (unsigned long long)(PSC_IO_IMAGE_ROWS_JPEG_SCAN_BUDGET >> 20));
    }

    /* psc_io_jpeg.c's settings: libjpeg's defaults (ISLOW DCT, fancy upsampling), RGB or CMYK out. */
    cinfo->out_color_space = cmyk ? JCS_CMYK : JCS_RGB;
    jpeg_start_decompress(cinfo);
    r->cmyk = cmyk;
    r->channels = (unsigned)cinfo->output_components;
    r->inverted = cinfo->saw_Adobe_marker;
    if (cinfo->output_width != r->width || cinfo->output_height != r->height || r->channels != (cmyk ? 4u : 3u))
        return psc_io_errorf(err, errlen, r->path, "JPEG decoder produced an unexpected layout");
    r->jpeg_row = malloc((size_t)r->width * r->channels);
    if (!r->jpeg_row)
        return psc_io_errorf(err, errlen, r->path, "out of memory for a row of %u pixels", (unsigned)r->width);
    return 0;
}

static int rows_jpeg_next(psc_io_image_rows_t *r, uint32_t *xrgb, char *err, size_t errlen)
{
    struct jpeg_decompress_struct *cinfo = &r->jpeg;
    if (setjmp(r->jpeg_fail.jump))
        return psc_io_errorf(err, errlen, r->path, "corrupt or truncated JPEG at row %u of %u: %s",
                             (unsigned)r->next_row, (unsigned)r->height, r->jpeg_fail.msg);

    JSAMPROW rows[1] = {r->jpeg_row};
    if (jpeg_read_scanlines(cinfo, rows, 1) != 1)
        return psc_io_errorf(err, errlen, r->path, "JPEG data ends at row %u of %u", (unsigned)r->next_row,
                             (unsigned)r->height);
    for (uint32_t x = 0; x < r->width; x++) {
        const JSAMPLE *p = r->jpeg_row + (size_t)x * r->channels;
        xrgb[x] = r->cmyk ? psc_io_jpeg_cmyk_to_xrgb(p, r->inverted)
                          : 0xFF000000u | (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
    }
    /* After the last row, read on to the end marker: a file cut after its pixels fails here,
     * as psc_io_image_load refuses it. */
    if (r->next_row + 1u == r->height)
        jpeg_finish_decompress(cinfo);
    return 0;
}

/* ---- PNG -------------------------------------------------------------------------------------- */

/* psc_io_png.c's bound on an ancillary chunk read (8 MiB: a generous ICC profile). */
#define ROWS_PNG_CHUNK_MAX ((png_alloc_size_t)8 << 20)

static int rows_png_open(psc_io_image_rows_t *r, uint32_t max_width, uint32_t max_height, char *err, size_t errlen)
{
    png_structp png = r->png;
    png_infop info = r->png_info;
    if (setjmp(png_jmpbuf(png)))
        return psc_io_errorf(err, errlen, r->path, "corrupt or truncated PNG (before row 0): %s", r->png_src.msg);

    /* As psc_io_png.c: metadata chunks skipped unread (a tiny file may declare a huge one), any other bounded. */
    static const png_byte skipped[] = "tEXt\0zTXt\0iTXt\0iCCP\0sPLT\0eXIf\0hIST\0pHYs\0sBIT\0bKGD\0"
                                      "cHRM\0gAMA\0sRGB\0tIME\0oFFs\0pCAL\0sCAL";
    png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, skipped, (int)(sizeof skipped / 5));
    png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, NULL, 0);
    png_set_chunk_malloc_max(png, ROWS_PNG_CHUNK_MAX);
    png_set_chunk_cache_max(png, 1000);
    png_set_read_fn(png, &r->png_src, psc_io_png_on_read);
    png_read_info(png, info);
    if (rows_check_size(r, png_get_image_width(png, info), png_get_image_height(png, info), max_width, max_height,
                        err, errlen) != 0)
        return -1;
    if (r->probe)
        return 0;
    if (png_get_interlace_type(png, info) != PNG_INTERLACE_NONE)
        return psc_io_errorf(err, errlen, r->path,
                             "interlaced (Adam7) PNG of %ux%u: its rows need the whole image in memory, which the "
                             "row reader never holds; save it without interlacing",
                             (unsigned)r->width, (unsigned)r->height);

    /* psc_io_png.c's transforms, so the pixels are psc_io_image_load's: palettes and low depths
     * expand, grey becomes RGB, 16 bits scale down with rounding (png_set_scale_16, not
     * strip_16), and an opaque filler goes where there was no alpha. Alpha is then dropped,
     * not composited onto black: the colour is kept as stored. */
    png_set_expand(png);
    png_set_scale_16(png);
    png_set_gray_to_rgb(png);
    png_set_add_alpha(png, 0xFF, PNG_FILLER_AFTER);
    png_read_update_info(png, info);   /* starts the row reading too */
    if (png_get_bit_depth(png, info) != 8 || png_get_channels(png, info) != 4 ||
        png_get_rowbytes(png, info) != (size_t)r->width * 4u)
        return psc_io_errorf(err, errlen, r->path, "PNG decoder produced an unexpected layout");
    return 0;
}

static int rows_png_next(psc_io_image_rows_t *r, uint32_t *xrgb, char *err, size_t errlen)
{
    png_structp png = r->png;
    if (setjmp(png_jmpbuf(png)))
        return psc_io_errorf(err, errlen, r->path, "corrupt or truncated PNG at row %u of %u: %s",
                             (unsigned)r->next_row, (unsigned)r->height, r->png_src.msg);

    /* RGBA straight into the caller's row (width * 4 bytes), then each quad repacked in place. */
    png_read_row(png, (png_bytep)xrgb, NULL);
    for (uint32_t x = 0; x < r->width; x++) {
        const uint8_t *p = (const uint8_t *)(xrgb + x);
        xrgb[x] = 0xFF000000u | (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
    }
    /* After the last row, the rest of the file up to IEND, checked as psc_io_png.c does. */
    if (r->next_row + 1u == r->height)
        png_read_end(png, NULL);
    return 0;
}

/* ---- the front end ------------------------------------------------------------------------------ */

static int rows_open(const char *path, uint32_t max_width, uint32_t max_height, bool probe, psc_io_image_rows_t **out,
                     char *err, size_t errlen)
{
    if (out)
        *out = NULL;
    if (!path || !out)
        return psc_io_errorf(err, errlen, path, "no file, or nowhere to put the reader");
    psc_io_image_rows_t *r = calloc(1, sizeof *r);
    if (r)
        r->probe = probe;
    char *name = r ? strdup(path) : NULL;
    if (!name) {
        free(r);
        return psc_io_errorf(err, errlen, path, "out of memory");
    }
    r->path = name;
    /* No limit on the file's size: it is streamed, never held, so its size costs time, not memory
     * (the image's sides are what the caller limits). Special files are still refused. */
    r->file = psc_io_fopen_regular(path, UINT64_MAX, err, errlen);
    if (!r->file) {
        psc_io_image_rows_close(r);
        return -1;
    }
    uint8_t head[8];
    size_t got = fread(head, 1, sizeof head, r->file);
    int rc;
    if (ferror(r->file)) {
        rc = psc_io_errorf(err, errlen, path, "cannot read: %s", strerror(errno));
    } else if (fseek(r->file, 0, SEEK_SET) != 0) {
        rc = psc_io_errorf(err, errlen, path, "cannot seek: %s", strerror(errno));
    } else if (got >= sizeof rows_jpeg_magic && memcmp(head, rows_jpeg_magic, sizeof rows_jpeg_magic) == 0) {
        r->kind = ROWS_JPEG;
        psc_io_jpeg_fail_init(&r->jpeg, &r->jpeg_fail);   /* psc_io_jpeg.c's: the same files refused */
        rc = rows_jpeg_open(r, max_width, max_height, err, errlen);
    } else if (got >= sizeof rows_png_magic && memcmp(head, rows_png_magic, sizeof rows_png_magic) == 0) {
        r->kind = ROWS_PNG;
        r->png_src.file = r->file;   /* psc_io_png.c's callbacks: the same files refused, the same messages */
        r->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r->png_src, psc_io_png_on_error, psc_io_png_on_warning);
        r->png_info = r->png ? png_create_info_struct(r->png) : NULL;
        rc = r->png_info ? rows_png_open(r, max_width, max_height, err, errlen)
                         : psc_io_errorf(err, errlen, path, "out of memory (libpng)");
    } else {
        rc = psc_io_errorf(err, errlen, path, "not a JPEG or PNG image");
    }
    if (rc != 0) {
        psc_io_image_rows_close(r);
        return -1;
    }
    *out = r;
    return 0;
}

int psc_io_image_rows_open(const char *path, uint32_t max_width, uint32_t max_height, psc_io_image_rows_t **out,
                           char *err, size_t errlen)
{
    return rows_open(path, max_width, max_height, false, out, err, errlen);
}

int psc_io_image_probe(const char *path, uint32_t *width, uint32_t *height, char *err, size_t errlen)
{
    psc_io_image_rows_t *r;
    if (rows_open(path, PSC_IO_IMAGE_ROWS_MAX_SIDE, PSC_IO_IMAGE_ROWS_MAX_SIDE, true, &r, err, errlen) != 0)
        return -1;
    *width = r->width;
    *height = r->height;
    psc_io_image_rows_close(r);
    return 0;
}

void psc_io_image_rows_size(const psc_io_image_rows_t *r, uint32_t *width, uint32_t *height)
{
    if (width)
        *width = r ? r->width : 0;
    if (height)
        *height = r ? r->height : 0;
}

bool psc_io_image_rows_is_jpeg(const psc_io_image_rows_t *r)
{
    return r && r->kind == ROWS_JPEG;
}

int psc_io_image_rows_next(psc_io_image_rows_t *r, uint32_t *xrgb, char *err, size_t errlen)
{
    if (!r || !xrgb)
        return psc_io_errorf(err, errlen, r ? r->path : NULL, "no reader or no row to read into");
    if (r->failed)
        return psc_io_errorf(err, errlen, r->path, "cannot read row %u: an earlier read failed",
                             (unsigned)r->next_row);
    if (r->next_row >= r->height)
        return psc_io_errorf(err, errlen, r->path, "no row %u: the image has %u rows", (unsigned)r->next_row,
                             (unsigned)r->height);
    int rc = r->kind == ROWS_JPEG ? rows_jpeg_next(r, xrgb, err, errlen) : rows_png_next(r, xrgb, err, errlen);
    if (rc != 0) {
        r->failed = true;
        return -1;
    }
    r->next_row++;
    return 0;
}

void psc_io_image_rows_close(psc_io_image_rows_t *r)
{
    if (!r)
        return;
    if (r->jpeg_created)
        jpeg_destroy_decompress(&r->jpeg);   /* also after an unfinished decode */
    if (r->png)
        png_destroy_read_struct(&r->png, &r->png_info, NULL);
    free(r->jpeg_row);
    if (r->file)
        fclose(r->file);
    free(r->path);
    free(r);
}
