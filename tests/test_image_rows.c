/* SPDX-License-Identifier: MIT */
/*
 * test_image_rows.c - io/psc_io_image_rows.h: JPEG and PNG read row by row.
 *
 *  - JPEGs written here with libjpeg (4:2:0, 4:4:4, an odd size, RGB colour
 *    space, greyscale, progressive, restart markers, Adobe and plain CMYK)
 *    and PNGs (psc_io_image_write_png's 8-bit RGB of random pixels; palette
 *    1/4/8 bits with tRNS, grey 1/16, grey+alpha, RGB/RGBA 16 written with
 *    libpng) give, row by row, exactly psc_io_image_load's pixels;
 *  - every truncation of small JPEGs and PNGs, and deterministic random
 *    corruptions, fail where psc_io_image_load fails (at open, or at a row,
 *    the message naming the file and the row), and read the same rows where
 *    it succeeds; nothing crashes;
 *  - images over the caller's limits, or over 65536 pixels a side, are
 *    refused naming the size and the limit; a 65536-wide PNG (which
 *    psc_io_image_load refuses) is read; a header claiming 65536 x 32768
 *    opens without allocating the image and fails at the first missing row;
 *  - an interlaced PNG, and a progressive JPEG too large for the coefficient
 *    budget, are refused saying why; reading past the last row, a text file,
 *    an empty or missing file and a directory are refused naming the file;
 *  - the heap in use while reading a 4096-row image is that of a 64-row one
 *    (glibc's mallinfo2, where there is one).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <malloc.h>
#include <png.h>
#include <jpeglib.h>
#include <zlib.h>

#include "psc_io_image.h"
#include "psc_io_image_rows.h"
#include "psc_testsupport.h"
#include "tsup_jpeg.h"
#include "tsup_files.h"

#define ERRLEN 512

static void tmp_path(char *buf, size_t n, const char *name)
{
    tsup_tmp_path(buf, n, "test_image_rows", name);
}

/* ---- reading with the contract checked ------------------------------------------------------- */

/* A refusal's message: "<path>: <problem>", mentioning `mention` when given. */
static void check_message(const char *err, const char *path, const char *mention)
{
    if (!tsup_msg_starts_with_path(err, path))
        fail_msg("%s: the message does not begin with the path: \"%s\"", path, err);
    if (mention && !strstr(err, mention))
        fail_msg("%s: message \"%s\" should mention \"%s\"", path, err, mention);
}

/* Open with the given limits, which must fail; the message must mention `mention`. */
static void expect_open_refused(const char *path, uint32_t max_w, uint32_t max_h, const char *mention)
{
    psc_io_image_rows_t *r = (psc_io_image_rows_t *)(uintptr_t)1;
    char err[ERRLEN] = "";
    if (psc_io_image_rows_open(path, max_w, max_h, &r, err, sizeof err) == 0) {
        psc_io_image_rows_close(r);
        fail_msg("%s was opened, expected a refusal", path);
    }
    assert_null(r);
    check_message(err, path, mention);
    printf("  refused: \"%s\"\n", err);
}

/*
 * Read every row of path within the limits into a fresh image. 0 with *img, or -1 with err: then
 * either the open failed (*failed_row = -1) or row *failed_row did, the message naming the file and
 * that row, and every later read fails too.
 */
static int read_all_rows(const char *path, uint32_t max_w, uint32_t max_h, psc_image_t *img, long *failed_row,
                         char *err)
{
    psc_io_image_rows_t *r = NULL;
    *img = (psc_image_t){0, 0, NULL};
    *failed_row = -1;
    if (psc_io_image_rows_open(path, max_w, max_h, &r, err, ERRLEN) != 0) {
        assert_null(r);
        check_message(err, path, NULL);
        return -1;
    }
    uint32_t w = 0, h = 0;
    psc_io_image_rows_size(r, &w, &h);
    assert_true(w >= 1 && w <= max_w && w <= PSC_IO_IMAGE_ROWS_MAX_SIDE);
    assert_true(h >= 1 && h <= max_h && h <= PSC_IO_IMAGE_ROWS_MAX_SIDE);
    img->width = w;
    img->height = h;
    img->xrgb = malloc((size_t)w * h * sizeof *img->xrgb);
    assert_non_null(img->xrgb);
    for (uint32_t y = 0; y < h; y++) {
        if (psc_io_image_rows_next(r, img->xrgb + (size_t)y * w, err, ERRLEN) != 0) {
            char row[32];
            snprintf(row, sizeof row, "row %u", (unsigned)y);
            check_message(err, path, row);
            char again[ERRLEN];
            assert_int_equal(psc_io_image_rows_next(r, img->xrgb, again, sizeof again), -1);
            check_message(again, path, NULL);
            psc_io_image_rows_close(r);
            psc_io_image_free(img);
            *failed_row = (long)y;
            return -1;
        }
        for (uint32_t x = 0; x < w; x++)
            if ((img->xrgb[(size_t)y * w + x] >> 24) != 0xFFu)
                fail_msg("%s: pixel (%u, %u) is 0x%08X, not opaque", path, (unsigned)x, (unsigned)y,
                         (unsigned)img->xrgb[(size_t)y * w + x]);
    }
    /* Past the last row: an error naming the file, and the reader still closes cleanly. */
    char past[ERRLEN];
    uint32_t spare = 0x12345678u;
    assert_int_equal(psc_io_image_rows_next(r, w == 1 ? &spare : img->xrgb, past, sizeof past), -1);
    check_message(past, path, "no row");
    assert_true(w != 1 || spare == 0x12345678u);
    psc_io_image_rows_close(r);
    return 0;
}

/* Every row of path must be psc_io_image_load's, bit for bit. */
static void expect_rows_equal_load(const char *path, const char *what)
{
    psc_image_t want, got;
    char err[ERRLEN];
    long failed_row;
    if (psc_io_image_load(path, &want, err, sizeof err) != 0)
        fail_msg("%s (%s) did not load: %s", path, what, err);
    if (read_all_rows(path, PSC_IO_IMAGE_ROWS_MAX_SIDE, PSC_IO_IMAGE_ROWS_MAX_SIDE, &got, &failed_row, err) != 0)
        fail_msg("%s (%s): rows not read (row %ld): %s", path, what, failed_row, err);
    assert_int_equal(got.width, want.width);
    assert_int_equal(got.height, want.height);
    for (uint32_t y = 0; y < want.height; y++) {
        const uint32_t *a = want.xrgb + (size_t)y * want.width, *b = got.xrgb + (size_t)y * want.width;
        if (memcmp(a, b, (size_t)want.width * sizeof *a) != 0)
            for (uint32_t x = 0; x < want.width; x++)
                if (a[x] != b[x])
                    fail_msg("%s (%s): pixel (%u, %u) is 0x%08X, psc_io_image_load gives 0x%08X", path, what,
                             (unsigned)x, (unsigned)y, (unsigned)b[x], (unsigned)a[x]);
    }
    printf("  %-40s %4ux%-4u every row equals psc_io_image_load's\n", what, (unsigned)want.width,
           (unsigned)want.height);
    psc_io_image_free(&want);
    psc_io_image_free(&got);
}

/* ---- images written here -------------------------------------------------------------------------- */

typedef tsup_jpeg_spec_t jpeg_spec_t;

static void write_jpeg(const char *path, const uint8_t *pix, unsigned w, unsigned h, const jpeg_spec_t *spec)
{
    assert_int_equal(tsup_write_jpeg(path, pix, w, h, spec), 0);
}

/* Smooth gradients with an edge and some noise: chroma subsampling and the DCT both have work. */
static uint8_t *picture(tsup_rng_t *rng, unsigned w, unsigned h, int components)
{
    uint8_t *px = malloc((size_t)w * h * (unsigned)components);
    assert_non_null(px);
    for (unsigned y = 0; y < h; y++)
        for (unsigned x = 0; x < w; x++)
            for (int k = 0; k < components; k++) {
                double u = (x + 0.5) / w, v = (y + 0.5) / h;
                double c = k == 0 ? 30.0 + 195.0 * u : k == 1 ? 220.0 - 180.0 * v
                                                     : 128.0 + 100.0 * sin(2.0 * TSUP_PI * (u + 0.5 * v));
                c += (x > w / 3 ? 20.0 : -20.0) + (double)tsup_rng_below(rng, 17) - 8.0;
                px[((size_t)y * w + x) * (unsigned)components + (unsigned)k] =
                    (uint8_t)(c < 0.0 ? 0 : c > 255.0 ? 255 : lround(c));
            }
    return px;
}

static void write_jpeg_picture(tsup_rng_t *rng, const char *path, unsigned w, unsigned h, const jpeg_spec_t *spec)
{
    uint8_t *px = picture(rng, w, h, spec->components);
    write_jpeg(path, px, w, h, spec);
    free(px);
}

typedef struct {
    const char *name;
    int color_type, bit_depth, interlace;
    uint32_t w, h;
    int npal;   /* palette entries (palette images) */
    int trns;   /* add a tRNS chunk */
} png_spec_t;

static void png_test_error(png_structp png, png_const_charp msg)
{
    (void)png;
    fail_msg("libpng (writing a test image): %s", msg);
}

static unsigned png_channels(int color_type)
{
    switch (color_type) {
    case PNG_COLOR_TYPE_GRAY_ALPHA: return 2;
    case PNG_COLOR_TYPE_RGB: return 3;
    case PNG_COLOR_TYPE_RGB_ALPHA: return 4;
    default: return 1; /* grey, palette */
    }
}

/* A PNG of random samples of spec's kind (palette indices below npal), written with libpng. */
static void write_png_random(tsup_rng_t *rng, const char *path, const png_spec_t *sp)
{
    unsigned ch = png_channels(sp->color_type);
    size_t rowbytes = ((size_t)sp->w * ch * (size_t)sp->bit_depth + 7) / 8;
    uint8_t **rows = calloc(sp->h, sizeof *rows);
    assert_non_null(rows);
    for (uint32_t y = 0; y < sp->h; y++) {
        rows[y] = malloc(rowbytes);
        assert_non_null(rows[y]);
        for (size_t i = 0; i < rowbytes; i++)
            rows[y][i] = (uint8_t)tsup_rng_u32(rng);
        if (sp->color_type == PNG_COLOR_TYPE_PALETTE)   /* indices within the palette */
            for (uint32_t x = 0; x < sp->w; x++) {
                unsigned per = 8u / (unsigned)sp->bit_depth, shift = 8u - (unsigned)sp->bit_depth * (x % per + 1u);
                unsigned mask = (1u << sp->bit_depth) - 1u;
                uint8_t *b = &rows[y][x / per];
                unsigned idx = ((*b >> shift) & mask) % (unsigned)sp->npal;
                *b = (uint8_t)((*b & ~(mask << shift)) | idx << shift);
            }
    }
    png_color pal[256];
    png_byte alpha[256];
    for (int i = 0; i < 256; i++) {
        uint32_t v = tsup_rng_u32(rng);
        pal[i] = (png_color){(png_byte)v, (png_byte)(v >> 8), (png_byte)(v >> 16)};
        alpha[i] = (png_byte)(v >> 24);
    }
    png_color_16 trns_colour = {0, 17, 17, 17, 17};

    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, png_test_error, NULL);
    assert_non_null(png);
    png_infop info = png_create_info_struct(png);
    assert_non_null(info);
    png_init_io(png, f);
    png_set_IHDR(png, info, sp->w, sp->h, sp->bit_depth, sp->color_type, sp->interlace, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (sp->color_type == PNG_COLOR_TYPE_PALETTE)
        png_set_PLTE(png, info, pal, sp->npal);
    if (sp->trns)
        png_set_tRNS(png, info, alpha, sp->color_type == PNG_COLOR_TYPE_PALETTE ? sp->npal : 0, &trns_colour);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    assert_int_equal(fclose(f), 0);
    for (uint32_t y = 0; y < sp->h; y++)
        free(rows[y]);
    free(rows);
}

static psc_image_t random_image(tsup_rng_t *rng, uint32_t w, uint32_t h)
{
    psc_image_t img = {w, h, malloc((size_t)w * h * 4)};
    assert_non_null(img.xrgb);
    for (size_t i = 0; i < (size_t)w * h; i++)
        img.xrgb[i] = tsup_rng_u32(rng);
    return img;
}

static void write_png_image(tsup_rng_t *rng, const char *path, uint32_t w, uint32_t h)
{
    psc_image_t img = random_image(rng, w, h);
    char err[ERRLEN];
    if (psc_io_image_write_png(path, &img, err, sizeof err) != 0)
        fail_msg("psc_io_image_write_png %s: %s", path, err);
    free(img.xrgb);
}

/* ---- rows equal psc_io_image_load's ----------------------------------------------------------------- */

static void test_jpeg_rows(void **state)
{
    (void)state;
    static const struct {
        const char *what;
        unsigned w, h;
        jpeg_spec_t spec;
    } kinds[] = {
        {"JPEG 4:2:0 q90", 128, 96, {JCS_RGB, 3, 90, 0, 0, 0, 0, 0}},
        {"JPEG 4:2:0 odd size", 333, 77, {JCS_RGB, 3, 85, 0, 0, 0, 0, 0}},
        {"JPEG 4:4:4 q95", 64, 48, {JCS_RGB, 3, 95, 1, 0, 0, 0, 0}},
        {"JPEG stored as RGB", 50, 31, {JCS_RGB, 3, 90, 1, 0, 0, 0, 1}},
        {"JPEG greyscale", 97, 61, {JCS_GRAYSCALE, 1, 90, 0, 0, 0, 0, 0}},
        {"JPEG progressive 4:2:0", 200, 120, {JCS_RGB, 3, 80, 0, 1, 0, 0, 0}},
        {"JPEG greyscale progressive", 45, 99, {JCS_GRAYSCALE, 1, 80, 0, 1, 0, 0, 0}},
        {"JPEG restart markers", 128, 64, {JCS_RGB, 3, 90, 0, 0, 0, 1, 0}},
        {"JPEG Adobe CMYK", 50, 40, {JCS_CMYK, 4, 90, 0, 0, 0, 0, 0}},
        {"JPEG plain CMYK", 50, 40, {JCS_CMYK, 4, 90, 0, 0, 1, 0, 0}},
        {"JPEG tall and thin", 17, 1000, {JCS_RGB, 3, 75, 0, 0, 0, 0, 0}},
        {"JPEG one pixel", 1, 1, {JCS_RGB, 3, 90, 0, 0, 0, 0, 0}},
    };
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0x1A9E);
    char path[512];
    tmp_path(path, sizeof path, "kind.jpg");
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++) {
        write_jpeg_picture(&rng, path, kinds[i].w, kinds[i].h, &kinds[i].spec);
        expect_rows_equal_load(path, kinds[i].what);
    }
    unlink(path);
}

static const png_spec_t png_kinds[] = {
    {"PNG palette 8 with tRNS", PNG_COLOR_TYPE_PALETTE, 8, PNG_INTERLACE_NONE, 61, 37, 200, 1},
    {"PNG palette 4", PNG_COLOR_TYPE_PALETTE, 4, PNG_INTERLACE_NONE, 33, 20, 13, 0},
    {"PNG palette 1", PNG_COLOR_TYPE_PALETTE, 1, PNG_INTERLACE_NONE, 19, 7, 2, 1},
    {"PNG grey 1", PNG_COLOR_TYPE_GRAY, 1, PNG_INTERLACE_NONE, 29, 11, 0, 0},
    {"PNG grey 8 with tRNS", PNG_COLOR_TYPE_GRAY, 8, PNG_INTERLACE_NONE, 40, 30, 0, 1},
    {"PNG grey 16", PNG_COLOR_TYPE_GRAY, 16, PNG_INTERLACE_NONE, 23, 17, 0, 0},
    {"PNG grey+alpha 8", PNG_COLOR_TYPE_GRAY_ALPHA, 8, PNG_INTERLACE_NONE, 31, 9, 0, 0},
    {"PNG RGB 16", PNG_COLOR_TYPE_RGB, 16, PNG_INTERLACE_NONE, 27, 14, 0, 0},
    {"PNG RGBA 8", PNG_COLOR_TYPE_RGB_ALPHA, 8, PNG_INTERLACE_NONE, 45, 21, 0, 0},
    {"PNG RGBA 16", PNG_COLOR_TYPE_RGB_ALPHA, 16, PNG_INTERLACE_NONE, 12, 33, 0, 0},
};

static void test_png_rows(void **state)
{
    (void)state;
    static const uint32_t sizes[][2] = {{1, 1}, {2, 3}, {64, 48}, {333, 7}, {5, 200}, {1000, 3}};
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0x9A77);
    char path[512], what[64];
    tmp_path(path, sizeof path, "kind.png");
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        write_png_image(&rng, path, sizes[i][0], sizes[i][1]);
        snprintf(what, sizeof what, "PNG RGB 8 (psc_io_image_write_png)");
        expect_rows_equal_load(path, what);
    }
    for (size_t i = 0; i < sizeof png_kinds / sizeof png_kinds[0]; i++) {
        write_png_random(&rng, path, &png_kinds[i]);
        expect_rows_equal_load(path, png_kinds[i].name);
    }
    unlink(path);
}

/* ---- truncated and corrupt files ------------------------------------------------------------------- */

/*
 * The file at path must fail or succeed in the row reader as psc_io_image_load does, and give its
 * pixels when it succeeds. Returns the row the reader failed at (-1: at open), or -2 when it read all.
 */
static long expect_same_verdict(const char *path, const char *what)
{
    psc_image_t want, got;
    char err_load[ERRLEN], err_rows[ERRLEN];
    long failed_row;
    int load = psc_io_image_load(path, &want, err_load, sizeof err_load);
    int rows = read_all_rows(path, PSC_MAX_MAP_DIM, PSC_MAX_MAP_DIM, &got, &failed_row, err_rows);
    if (load != 0 && rows == 0)
        fail_msg("%s: psc_io_image_load refused it (\"%s\") but every row was read", what, err_load);
    /* What the row reader refuses by design (a valid file, read whole by psc_io_image_load). */
    if (load == 0 && rows != 0 && failed_row == -1 &&
        (strstr(err_rows, "interlaced") || strstr(err_rows, "progressive or multi-scan"))) {
        psc_io_image_free(&want);
        return -1;
    }
    if (load == 0 && rows != 0)
        fail_msg("%s: psc_io_image_load read it but the row reader refused it: \"%s\"", what, err_rows);
    if (load != 0)
        return failed_row;
    assert_int_equal(got.width, want.width);
    assert_int_equal(got.height, want.height);
    if (memcmp(got.xrgb, want.xrgb, (size_t)want.width * want.height * sizeof *want.xrgb) != 0)
        fail_msg("%s: read, but the rows differ from psc_io_image_load's", what);
    psc_io_image_free(&want);
    psc_io_image_free(&got);
    return -2;
}

/*
 * Every proper prefix of src (written to dst) must be refused, at open or at a named row; some at a
 * row when rows_fail (a multi-scan JPEG is read whole into coefficients at open, so fails there).
 */
static void truncate_every_length(const char *src, const char *dst, const char *what, int rows_fail)
{
    size_t len;
    uint8_t *b = tsup_read_bytes(src, &len);
    assert_non_null(b);
    unsigned at_open = 0, at_row = 0;
    char last[ERRLEN] = "";
    for (size_t n = 1; n < len; n++) {
        assert_int_equal(tsup_write_bytes(dst, b, n), 0);
        psc_image_t img;
        long failed_row;
        if (read_all_rows(dst, PSC_IO_IMAGE_ROWS_MAX_SIDE, PSC_IO_IMAGE_ROWS_MAX_SIDE, &img, &failed_row, last) == 0)
            fail_msg("%s cut to %zu of %zu bytes was read whole", what, n, len);
        if (failed_row < 0)
            at_open++;
        else
            at_row++;
    }
    printf("  %s: each of %zu truncations refused (%u at open, %u at a row), e.g. \"%s\"\n", what, len - 1, at_open,
           at_row, last);
    if (rows_fail)
        assert_true(at_row > 0);   /* the rows' own errors were reached, not only the header's */
    else
        assert_int_equal(at_row, 0);
    assert_int_equal(tsup_write_bytes(dst, b, len), 0);
    expect_rows_equal_load(dst, what);
    free(b);
    unlink(dst);
}

static void test_truncated(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0x7C07);
    char src[512], dst[512];
    tmp_path(src, sizeof src, "whole.img");
    tmp_path(dst, sizeof dst, "cut.img");

    jpeg_spec_t base = {JCS_RGB, 3, 90, 0, 0, 0, 0, 0}, prog = {JCS_RGB, 3, 80, 0, 1, 0, 0, 0};
    jpeg_spec_t grey = {JCS_GRAYSCALE, 1, 90, 0, 0, 0, 0, 0};
    write_jpeg_picture(&rng, src, 48, 40, &base);
    truncate_every_length(src, dst, "JPEG 48x40 baseline", 1);
    write_jpeg_picture(&rng, src, 32, 24, &grey);
    truncate_every_length(src, dst, "JPEG 32x24 greyscale", 1);
    write_jpeg_picture(&rng, src, 32, 32, &prog);
    truncate_every_length(src, dst, "JPEG 32x32 progressive", 0);

    write_png_image(&rng, src, 24, 16);
    truncate_every_length(src, dst, "PNG 24x16 RGB", 1);
    write_png_random(&rng, src, &png_kinds[0]);
    truncate_every_length(src, dst, "PNG 61x37 palette", 1);
    unlink(src);
}

/* Recompute every chunk's CRC so that corruption gets past libpng's checks to the decoder. */
static void png_fix_crcs(uint8_t *b, size_t len)
{
    size_t at = 8;
    while (at + 12 <= len) {
        uint32_t n = (uint32_t)b[at] << 24 | (uint32_t)b[at + 1] << 16 | (uint32_t)b[at + 2] << 8 | b[at + 3];
        if (n > len - at - 12)
            return;
        uint32_t crc = (uint32_t)crc32(0L, b + at + 4, n + 4u);
        uint8_t *c = b + at + 8 + n;
        c[0] = (uint8_t)(crc >> 24);
        c[1] = (uint8_t)(crc >> 16);
        c[2] = (uint8_t)(crc >> 8);
        c[3] = (uint8_t)crc;
        at += 12u + n;
    }
}

/* Random damage (a few bytes set, flipped or cut) past the signature: each verdict must be load's. */
static void corrupt_many(tsup_rng_t *rng, const char *src, const char *dst, int is_png, unsigned iterations,
                         const char *what)
{
    size_t len;
    uint8_t *orig = tsup_read_bytes(src, &len);
    assert_non_null(orig);
    uint8_t *b = malloc(len);
    assert_non_null(b);
    unsigned read_whole = 0, at_open = 0, at_row = 0;
    for (unsigned it = 0; it < iterations; it++) {
        memcpy(b, orig, len);
        size_t n = len;
        unsigned edits = 1u + tsup_rng_below(rng, 4);
        for (unsigned e = 0; e < edits; e++) {
            size_t at = 8u + tsup_rng_below(rng, (uint32_t)(n - 8u));
            switch (tsup_rng_below(rng, 3)) {
            case 0: b[at] = (uint8_t)tsup_rng_u32(rng); break;
            case 1: b[at] ^= (uint8_t)(1u << tsup_rng_below(rng, 8)); break;
            default: b[at] = 0; break;
            }
        }
        if (tsup_rng_below(rng, 8) == 0)
            n = 8u + tsup_rng_below(rng, (uint32_t)(len - 8u));
        if (is_png)
            png_fix_crcs(b, n);
        assert_int_equal(tsup_write_bytes(dst, b, n), 0);
        char label[128];
        snprintf(label, sizeof label, "%s, corruption %u", what, it);
        long v = expect_same_verdict(dst, label);
        if (v == -2)
            read_whole++;
        else if (v == -1)
            at_open++;
        else
            at_row++;
    }
    printf("  %s: %u corruptions, %u read whole (as loaded), %u refused at open, %u at a row\n", what, iterations,
           read_whole, at_open, at_row);
    free(orig);
    free(b);
    unlink(dst);
}

static void test_corrupt(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0xC0BB);
    char src[512], dst[512];
    tmp_path(src, sizeof src, "seed.img");
    tmp_path(dst, sizeof dst, "bad.img");
    jpeg_spec_t base = {JCS_RGB, 3, 90, 0, 0, 0, 1, 0}, prog = {JCS_RGB, 3, 80, 0, 1, 0, 0, 0};
    write_jpeg_picture(&rng, src, 40, 32, &base);
    corrupt_many(&rng, src, dst, 0, 400, "JPEG 40x32 with restarts");
    write_jpeg_picture(&rng, src, 40, 32, &prog);
    corrupt_many(&rng, src, dst, 0, 400, "JPEG 40x32 progressive");
    write_png_image(&rng, src, 20, 12);
    corrupt_many(&rng, src, dst, 1, 400, "PNG 20x12 RGB");
    write_png_random(&rng, src, &png_kinds[1]);
    corrupt_many(&rng, src, dst, 1, 400, "PNG 33x20 palette 4");
    unlink(src);
}

/* ---- limits ------------------------------------------------------------------------------------------ */

static void put_be32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* One PNG chunk (length, type, data, CRC) appended at *at. */
static void put_chunk(uint8_t *buf, size_t *at, const char type[4], const uint8_t *data, uint32_t n)
{
    put_be32(buf + *at, n);
    memcpy(buf + *at + 4, type, 4);
    if (n)
        memcpy(buf + *at + 8, data, n);
    put_be32(buf + *at + 8 + n, (uint32_t)crc32(0L, buf + *at + 4, n + 4u));
    *at += 12u + n;
}

/* A w x h 8-bit grey PNG whose rows are rows_given rows of value (row y: (y * 7 + x) & 255), then nothing. */
static void write_grey_png_rows(const char *path, uint32_t w, uint32_t h, uint32_t rows_given, int with_end)
{
    size_t raw_len = (size_t)rows_given * (w + 1u);
    uint8_t *raw = malloc(raw_len);
    assert_non_null(raw);
    for (uint32_t y = 0; y < rows_given; y++) {
        raw[(size_t)y * (w + 1u)] = 0;   /* filter: none */
        for (uint32_t x = 0; x < w; x++)
            raw[(size_t)y * (w + 1u) + 1u + x] = (uint8_t)(y * 7u + x);
    }
    uLongf z_len = compressBound((uLong)raw_len);
    uint8_t *buf = malloc(64 + z_len);
    assert_non_null(buf);
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    memcpy(buf, sig, 8);
    size_t at = 8;
    uint8_t ihdr[13] = {0};
    put_be32(ihdr, w);
    put_be32(ihdr + 4, h);
    ihdr[8] = 8;   /* bit depth; colour type 0 (grey), no interlace */
    put_chunk(buf, &at, "IHDR", ihdr, sizeof ihdr);
    uint8_t *z = malloc(z_len);
    assert_non_null(z);
    assert_int_equal(compress2(z, &z_len, raw, (uLong)raw_len, 9), Z_OK);
    put_chunk(buf, &at, "IDAT", z, (uint32_t)z_len);
    if (with_end)
        put_chunk(buf, &at, "IEND", NULL, 0);
    assert_int_equal(tsup_write_bytes(path, buf, at), 0);
    free(raw);
    free(z);
    free(buf);
}

/* Set the size in a JPEG's start-of-frame header (any SOFn). */
static void jpeg_set_size(uint8_t *b, size_t n, uint16_t w, uint16_t h)
{
    for (size_t i = 2; i + 9 < n; i++)
        if (b[i] == 0xFF && b[i + 1] >= 0xC0 && b[i + 1] <= 0xCF && b[i + 1] != 0xC4 && b[i + 1] != 0xC8 &&
            b[i + 1] != 0xCC) {
            b[i + 5] = (uint8_t)(h >> 8);
            b[i + 6] = (uint8_t)h;
            b[i + 7] = (uint8_t)(w >> 8);
            b[i + 8] = (uint8_t)w;
            return;
        }
    fail_msg("no start-of-frame marker in the test JPEG");
}

static void test_limits(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0x11A1);
    char path[512];
    psc_io_image_rows_t *r = NULL;
    char err[ERRLEN];

    /* The caller's limits, for both formats: the size and the limit named; at the limit is fine. */
    tmp_path(path, sizeof path, "limits.png");
    write_png_image(&rng, path, 300, 200);
    expect_open_refused(path, 299, 1000, "300x200");
    expect_open_refused(path, 299, 1000, "limit of 299 pixels");
    expect_open_refused(path, 1000, 199, "limit of 199 pixels");
    assert_int_equal(psc_io_image_rows_open(path, 300, 200, &r, err, sizeof err), 0);
    psc_io_image_rows_close(r);
    unlink(path);

    tmp_path(path, sizeof path, "limits.jpg");
    jpeg_spec_t base = {JCS_RGB, 3, 90, 0, 0, 0, 0, 0};
    write_jpeg_picture(&rng, path, 300, 200, &base);
    expect_open_refused(path, 299, 200, "limit of 299 pixels");
    expect_open_refused(path, 300, 199, "300x200, taller than the limit of 199 pixels");
    assert_int_equal(psc_io_image_rows_open(path, 300, 200, &r, err, sizeof err), 0);
    psc_io_image_rows_close(r);

    /* A progressive JPEG's coefficients must fit the budget: a header saying 60000 x 60000 is
     * refused before anything is allocated (the file holds no such data anyway). */
    jpeg_spec_t prog = {JCS_RGB, 3, 80, 0, 1, 0, 0, 0};
    write_jpeg_picture(&rng, path, 64, 64, &prog);
    size_t len;
    uint8_t *b = tsup_read_bytes(path, &len);
    assert_non_null(b);
    jpeg_set_size(b, len, 60000, 60000);
    assert_int_equal(tsup_write_bytes(path, b, len), 0);
    free(b);
    expect_open_refused(path, UINT32_MAX, UINT32_MAX, "progressive");
    expect_open_refused(path, UINT32_MAX, UINT32_MAX, "baseline");
    unlink(path);

    /* 65536 wide: past psc_io_image_load's 16384, read here; 65537 is past the reader's own limit
     * whatever the caller allows. */
    tmp_path(path, sizeof path, "wide.png");
    write_grey_png_rows(path, 65536, 3, 3, 1);
    psc_image_t none;
    assert_int_equal(psc_io_image_load(path, &none, err, sizeof err), -1);
    assert_int_equal(psc_io_image_rows_open(path, UINT32_MAX, UINT32_MAX, &r, err, sizeof err), 0);
    uint32_t w = 0, h = 0;
    psc_io_image_rows_size(r, &w, &h);
    assert_int_equal(w, 65536);
    assert_int_equal(h, 3);
    uint32_t *row = malloc(65536u * sizeof *row);
    assert_non_null(row);
    for (uint32_t y = 0; y < 3; y++) {
        if (psc_io_image_rows_next(r, row, err, sizeof err) != 0)
            fail_msg("65536-wide PNG, row %u: %s", (unsigned)y, err);
        for (uint32_t x = 0; x < 65536; x++) {
            uint32_t g = (y * 7u + x) & 0xFFu;
            if (row[x] != (0xFF000000u | g << 16 | g << 8 | g))
                fail_msg("65536-wide PNG: pixel (%u, %u) is 0x%08X", (unsigned)x, (unsigned)y, (unsigned)row[x]);
        }
    }
    psc_io_image_rows_close(r);
    printf("  a 65536x3 PNG read row by row (psc_io_image_load refuses it: \"%s\")\n", err);
    write_grey_png_rows(path, 65537, 1, 1, 1);
    expect_open_refused(path, UINT32_MAX, UINT32_MAX, "limit of 65536 pixels");

    /* The header of a 65536 x 32768 panorama with two rows of data: it opens (nothing is allocated
     * for the whole image), two rows read, the third fails naming the row. */
    write_grey_png_rows(path, 65536, 32768, 2, 0);
    assert_int_equal(psc_io_image_rows_open(path, 65536, 32768, &r, err, sizeof err), 0);
    psc_io_image_rows_size(r, &w, &h);
    assert_int_equal(w, 65536);
    assert_int_equal(h, 32768);
    assert_int_equal(psc_io_image_rows_next(r, row, err, sizeof err), 0);
    assert_int_equal(psc_io_image_rows_next(r, row, err, sizeof err), 0);
    assert_int_equal(psc_io_image_rows_next(r, row, err, sizeof err), -1);
    check_message(err, path, "row 2 of 32768");
    printf("  a 65536x32768 header with 2 rows of data: \"%s\"\n", err);
    psc_io_image_rows_close(r);
    free(row);
    unlink(path);
}

static void test_interlaced(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0xADA7);
    char path[512];
    tmp_path(path, sizeof path, "adam7.png");
    static const png_spec_t adam7[] = {
        {"PNG RGB 8 Adam7", PNG_COLOR_TYPE_RGB, 8, PNG_INTERLACE_ADAM7, 37, 29, 0, 0},
        {"PNG palette 8 Adam7", PNG_COLOR_TYPE_PALETTE, 8, PNG_INTERLACE_ADAM7, 16, 16, 40, 1},
        {"PNG grey 1 Adam7, one pixel", PNG_COLOR_TYPE_GRAY, 1, PNG_INTERLACE_ADAM7, 1, 1, 0, 0},
    };
    for (size_t i = 0; i < sizeof adam7 / sizeof adam7[0]; i++) {
        write_png_random(&rng, path, &adam7[i]);
        psc_image_t img;
        char err[ERRLEN];
        if (psc_io_image_load(path, &img, err, sizeof err) != 0)   /* a valid file: only the row reader refuses it */
            fail_msg("%s: %s", adam7[i].name, err);
        psc_io_image_free(&img);
        expect_open_refused(path, UINT32_MAX, UINT32_MAX, "interlaced");
    }
    unlink(path);
}

static void test_not_images(void **state)
{
    (void)state;
    char path[512], dir[512];
    tmp_path(path, sizeof path, "text.jpg");
    assert_int_equal(tsup_write_bytes(path, "hello, this is text\n", 20), 0);
    expect_open_refused(path, 100, 100, "not a JPEG or PNG image");
    assert_int_equal(tsup_write_bytes(path, "\xFF\xD8\xFF", 3), 0);
    expect_open_refused(path, 100, 100, "JPEG");
    assert_int_equal(tsup_write_bytes(path, "", 0), 0);
    expect_open_refused(path, 100, 100, "empty");
    unlink(path);
    expect_open_refused(path, 100, 100, "cannot open");
    tmp_path(dir, sizeof dir, "a-directory");
    assert_int_equal(mkdir(dir, 0700), 0);
    expect_open_refused(dir, 100, 100, "directory");
    rmdir(dir);

    /* No arguments, no reader: refused, never a crash; close takes NULL. */
    char err[ERRLEN];
    psc_io_image_rows_t *r = NULL;
    assert_int_equal(psc_io_image_rows_open(NULL, 100, 100, &r, err, sizeof err), -1);
    assert_null(r);
    assert_int_equal(psc_io_image_rows_open(path, 100, 100, NULL, err, sizeof err), -1);
    uint32_t px;
    assert_int_equal(psc_io_image_rows_next(NULL, &px, err, sizeof err), -1);
    assert_int_equal(psc_io_image_rows_next(NULL, &px, NULL, 0), -1);
    psc_io_image_rows_close(NULL);
}

/* ---- memory: a few rows, whatever the height ----------------------------------------------------------- */

#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
#define ROWS_HAVE_MALLINFO2 1
static size_t heap_in_use(void)
{
    struct mallinfo2 m = mallinfo2();
    return m.uordblks + m.hblkhd;   /* the arena's blocks and the mmap'd ones */
}
#else
#define ROWS_HAVE_MALLINFO2 0
static size_t heap_in_use(void)
{
    return 0;
}
#endif

/* The most heap the reader holds (above what was in use before it opened) over reading every row. */
static size_t peak_while_reading(const char *path)
{
    size_t before = heap_in_use(), peak = 0;
    psc_io_image_rows_t *r = NULL;
    char err[ERRLEN];
    uint32_t w, h;
    uint32_t row[512];
    if (psc_io_image_rows_open(path, 512, 1u << 16, &r, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_io_image_rows_size(r, &w, &h);
    assert_true(w <= 512);
    for (uint32_t y = 0; y < h; y++) {
        if (psc_io_image_rows_next(r, row, err, sizeof err) != 0)
            fail_msg("%s", err);
        size_t now = heap_in_use();
        if (now > before && now - before > peak)
            peak = now - before;
    }
    psc_io_image_rows_close(r);
    return peak;
}

static void test_memory_flat(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 0x3E3);
    char path[512];
    jpeg_spec_t base = {JCS_RGB, 3, 85, 0, 0, 0, 0, 0};
    static const struct {
        const char *what;
        int jpeg;
    } formats[] = {{"JPEG 4:2:0", 1}, {"PNG RGB 8", 0}};
    for (size_t i = 0; i < 2; i++) {
        tmp_path(path, sizeof path, formats[i].jpeg ? "tall.jpg" : "tall.png");
        size_t peak[2];
        static const unsigned heights[2] = {64, 4096};
        for (int k = 0; k < 2; k++) {
            if (formats[i].jpeg)
                write_jpeg_picture(&rng, path, 512, heights[k], &base);
            else
                write_png_image(&rng, path, 512, heights[k]);
            peak[k] = peak_while_reading(path);
        }
        printf("  %s 512 wide: %zu bytes held reading 64 rows, %zu reading 4096%s\n", formats[i].what, peak[0],
               peak[1], ROWS_HAVE_MALLINFO2 && peak[0] ? "" : " (no heap statistics here: not checked)");
        /* 64 times the rows, the same memory: a few KB of slack for the allocator's rounding */
        if (peak[1] > peak[0] + 16384)
            fail_msg("%s: the reader held %zu bytes for 4096 rows, %zu for 64", formats[i].what, peak[1], peak[0]);
        unlink(path);
    }
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_jpeg_rows),
        cmocka_unit_test(test_png_rows),
        cmocka_unit_test(test_truncated),
        cmocka_unit_test(test_corrupt),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_interlaced),
        cmocka_unit_test(test_not_images),
        cmocka_unit_test(test_memory_flat),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
