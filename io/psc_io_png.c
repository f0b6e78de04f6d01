/* SPDX-License-Identifier: MIT */
/*
 * psc_io_png.c - PNG files with libpng (psc_io_png.h): decoding of any colour
 * type and bit depth to 0xFFRRGGBB (alpha dropped), and 8-bit RGB encoding
 * into memory, then an atomic write.
 * libpng reports errors by calling our handler, which must not return: it
 * keeps the message and longjmps back to the setjmp in the job.
 */
#include "psc_io_png.h"
#include "psc_io_png_src.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <errno.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>
#include <png.h>

/** Fills one output row of 3*width bytes R, G, B for the encoder. */
typedef void (*png_row_fn)(const void *ctx, uint32_t y, uint8_t *rgb);

/* State that must survive a longjmp lives here, not in the setjmp frame. */
typedef struct {
    psc_io_png_src_t src;  /* first: libpng's error (and, decoding, read) pointer is the job */
    png_structp png;
    png_infop info;
    png_bytep *rows;       /* decoding: row pointers into the image */
    uint8_t *out;          /* encoding: growing output buffer */
    size_t out_len, out_cap;
    uint8_t *row;          /* encoding: one RGB row */
} png_job_t;

void psc_io_png_on_error(png_structp png, png_const_charp msg)
{
    psc_io_png_src_t *src = png_get_error_ptr(png);
    snprintf(src->msg, sizeof src->msg, "%s", msg);
    png_longjmp(png, 1);
}

/* Warnings (odd ancillary chunks, colour profiles) do not affect the pixels we use. */
void psc_io_png_on_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

void psc_io_png_on_read(png_structp png, png_bytep data, size_t len)
{
    psc_io_png_src_t *src = png_get_io_ptr(png);
    if (fread(data, 1, len, src->file) != len)
        png_error(png, ferror(src->file) ? "read error" : "file ends early (truncated)");
}

int psc_io_image_over_budget(char *err, size_t errlen, const char *path, uint32_t w, uint32_t h, uint64_t max_pixels)
{
    return psc_io_errorf(err, errlen, path,
                         "image is %ux%u (%llu pixels), more than the budget of %llu pixels (checked before decoding)",
                         (unsigned)w, (unsigned)h, (unsigned long long)w * h, (unsigned long long)max_pixels);
}

/* the largest ancillary chunk read (8 MiB: a generous ICC profile) */
#define PSC_IO_PNG_CHUNK_MAX ((png_alloc_size_t)8 << 20)

static int png_read_run(png_job_t *job, const char *path, uint32_t max_side, uint64_t max_pixels, psc_surface_t *img,
                        char *err, size_t errlen)
{
    png_structp png = job->png;
    png_infop info = job->info;
    if (setjmp(png_jmpbuf(png)))
        return psc_io_errorf(err, errlen, path, "corrupt or truncated PNG: %s", job->src.msg);

    /* The metadata chunks are skipped unread: the pixels need none of them, and a 43-byte
     * file can declare a 1 GiB text chunk that libpng would allocate whole (found by
     * fuzzing); any other chunk is bounded. After the setjmp: these may fail (memory). */
    static const png_byte skipped[] = "tEXt\0zTXt\0iTXt\0iCCP\0sPLT\0eXIf\0hIST\0pHYs\0sBIT\0bKGD\0"
                                      "cHRM\0gAMA\0sRGB\0tIME\0oFFs\0pCAL\0sCAL";
    png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, skipped, (int)(sizeof skipped / 5));
    png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, NULL, 0);
    png_set_chunk_malloc_max(png, PSC_IO_PNG_CHUNK_MAX);
    png_set_chunk_cache_max(png, 1000);
    png_set_read_fn(png, job, psc_io_png_on_read);
    png_read_info(png, info);
    uint32_t w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    if (w == 0 || h == 0)
        return psc_io_errorf(err, errlen, path, "image has no pixels (%ux%u)", (unsigned)w, (unsigned)h);
    if (w > max_side || h > max_side || w > UINT16_MAX || h > UINT16_MAX)
        return psc_io_errorf(err, errlen, path, "image is %ux%u, larger than the limit of %u pixels per side",
                             (unsigned)w, (unsigned)h, (unsigned)(max_side < UINT16_MAX ? max_side : UINT16_MAX));
    if ((uint64_t)w * h > max_pixels)
        return psc_io_image_over_budget(err, errlen, path, w, h, max_pixels);
    uint32_t *xrgb = malloc((size_t)w * h * sizeof(uint32_t));
    if (!xrgb)
        return psc_io_errorf(err, errlen, path, "out of memory for a %ux%u image", (unsigned)w, (unsigned)h);
    *img = (psc_surface_t){(uint16_t)w, (uint16_t)h, w * 4u, PSC_PIX_XRGB8888, xrgb};

    /* Normalise every colour type and depth to 8-bit RGBA: palettes and low
     * depths expand, grey becomes RGB, 16 bits scale down with rounding, and
     * opaque alpha is added where there was none (then ignored below). */
    png_set_expand(png);
    png_set_scale_16(png);
    png_set_gray_to_rgb(png);
    png_set_add_alpha(png, 0xFF, PNG_FILLER_AFTER);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_bit_depth(png, info) != 8 || png_get_channels(png, info) != 4 ||
        png_get_rowbytes(png, info) != (size_t)w * 4u)
        return psc_io_errorf(err, errlen, path, "PNG decoder produced an unexpected layout");

    /* Decode straight into the image, then repack each RGBA quad in place. */
    job->rows = malloc((size_t)h * sizeof *job->rows);
    if (!job->rows)
        return psc_io_errorf(err, errlen, path, "out of memory");
    for (uint32_t y = 0; y < h; y++)
        job->rows[y] = (png_bytep)(xrgb + (size_t)y * w);
    png_read_image(png, job->rows);
    png_read_end(png, NULL);

    for (size_t i = 0, n = (size_t)w * h; i < n; i++) {
        const uint8_t *p = (const uint8_t *)(xrgb + i);
        xrgb[i] = 0xFF000000u | (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
    }
    return 0;
}

int psc_io_png_decode(FILE *f, const char *path, uint32_t max_side, uint64_t max_pixels, psc_surface_t *img,
                      char *err, size_t errlen)
{
    *img = (psc_surface_t){0, 0, 0, PSC_PIX_XRGB8888, NULL};
    png_job_t *job = calloc(1, sizeof *job);
    if (!job)
        return psc_io_errorf(err, errlen, path, "out of memory");
    job->src.file = f;
    job->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, job, psc_io_png_on_error, psc_io_png_on_warning);
    job->info = job->png ? png_create_info_struct(job->png) : NULL;
    int rc = job->info ? png_read_run(job, path, max_side, max_pixels, img, err, errlen)
                       : psc_io_errorf(err, errlen, path, "out of memory (libpng)");
    png_destroy_read_struct(&job->png, &job->info, NULL);
    free(job->rows);
    free(job);
    if (rc != 0) {
        free(img->pixels);
        *img = (psc_surface_t){0, 0, 0, PSC_PIX_XRGB8888, NULL};
    }
    return rc;
}

static void png_job_write(png_structp png, png_bytep data, size_t len)
{
    png_job_t *job = png_get_io_ptr(png);
    if (len > job->out_cap - job->out_len) {
        size_t cap = job->out_cap ? job->out_cap : 65536;
        while (len > cap - job->out_len) {
            if (cap > SIZE_MAX / 2)
                png_error(png, "out of memory");
            cap *= 2;
        }
        uint8_t *grown = realloc(job->out, cap);
        if (!grown)
            png_error(png, "out of memory");
        job->out = grown;
        job->out_cap = cap;
    }
    memcpy(job->out + job->out_len, data, len);
    job->out_len += len;
}

static void png_job_flush(png_structp png)
{
    (void)png;
}

static int png_write_run(png_job_t *job, uint32_t w, uint32_t h, png_row_fn row, const void *ctx,
                         const char *path, char *err, size_t errlen)
{
    png_structp png = job->png;
    png_infop info = job->info;
    if (setjmp(png_jmpbuf(png)))
        return psc_io_errorf(err, errlen, path, "cannot encode PNG: %s", job->src.msg);

    job->row = malloc((size_t)w * 3u);
    if (!job->row)
        return psc_io_errorf(err, errlen, path, "out of memory");
    png_set_write_fn(png, job, png_job_write, png_job_flush);
    png_set_IHDR(png, info, w, h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (uint32_t y = 0; y < h; y++) {
        row(ctx, y, job->row);
        png_write_row(png, job->row);
    }
    png_write_end(png, NULL);
    return 0;
}

static int png_encode(uint32_t width, uint32_t height, png_row_fn row, const void *ctx,
                   uint8_t **png, size_t *png_len, const char *path, char *err, size_t errlen)
{
    *png = NULL;
    *png_len = 0;
    if (width == 0 || height == 0 || width > PNG_UINT_31_MAX || height > PNG_UINT_31_MAX)
        return psc_io_errorf(err, errlen, path, "cannot write a %ux%u PNG", (unsigned)width, (unsigned)height);
    png_job_t *job = calloc(1, sizeof *job);
    if (!job)
        return psc_io_errorf(err, errlen, path, "out of memory");
    job->png = png_create_write_struct(PNG_LIBPNG_VER_STRING, job, psc_io_png_on_error, psc_io_png_on_warning);
    job->info = job->png ? png_create_info_struct(job->png) : NULL;
    int rc = job->info ? png_write_run(job, width, height, row, ctx, path, err, errlen)
                       : psc_io_errorf(err, errlen, path, "out of memory (libpng)");
    png_destroy_write_struct(&job->png, &job->info);
    free(job->row);
    if (rc == 0) {
        *png = job->out;
        *png_len = job->out_len;
    } else {
        free(job->out);
    }
    free(job);
    return rc;
}

int psc_io_png_read(const char *path, uint32_t max_side, uint64_t max_pixels, psc_surface_t *img, char *err,
                    size_t errlen)
{
    static const uint8_t magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    uint8_t head[8];
    FILE *f;
    int rc;

    *img = (psc_surface_t){0, 0, 0, PSC_PIX_XRGB8888, NULL};
    if (!path || (f = psc_io_fopen_regular(path, PSC_IMAGE_MAX_FILE_BYTES, err, errlen)) == NULL)
        return -1;
    if (fread(head, 1, sizeof head, f) != sizeof head || memcmp(head, magic, sizeof magic) != 0)
        rc = psc_io_errorf(err, errlen, path, "not a PNG image");
    else if (fseek(f, 0, SEEK_SET) != 0)
        rc = psc_io_errorf(err, errlen, path, "cannot seek: %s", strerror(errno));
    else
        rc = psc_io_png_decode(f, path, max_side, max_pixels, img, err, errlen);
    fclose(f);
    return rc;
}

uint32_t psc_io_surface_pixel(const psc_surface_t *s, uint32_t x, uint32_t y)
{
    const uint8_t *p = (const uint8_t *)s->pixels + (size_t)y * s->stride;
    if (s->format == PSC_PIX_RGB565) {
        uint32_t v = p[2 * x] | (uint32_t)p[2 * x + 1] << 8;
        uint32_t r5 = v >> 11, g6 = (v >> 5) & 63u, b5 = v & 31u;
        uint32_t r = r5 << 3 | r5 >> 2, g = g6 << 2 | g6 >> 4, b = b5 << 3 | b5 >> 2;
        return 0xFF000000u | r << 16 | g << 8 | b;
    }
    /* XRGB8888 is a 32-bit word (psc_types.h); memcpy copes with any stride. */
    uint32_t word;
    memcpy(&word, p + 4 * (size_t)x, sizeof word);
    return 0xFF000000u | (word & 0xFFFFFFu);
}

bool psc_io_surface_is_valid(const psc_surface_t *s)
{
    uint32_t bpp = psc_pixfmt_bytes(s->format);
    return s->pixels && s->width > 0 && s->height > 0 &&
           (s->format == PSC_PIX_RGB565 || s->format == PSC_PIX_XRGB8888) &&
           s->stride >= (uint32_t)s->width * bpp;
}

static void surface_row_rgb(const void *ctx, uint32_t y, uint8_t *rgb)
{
    const psc_surface_t *s = ctx;
    for (uint32_t x = 0; x < s->width; x++) {
        uint32_t v = psc_io_surface_pixel(s, x, y);
        rgb[3 * x] = (uint8_t)(v >> 16);
        rgb[3 * x + 1] = (uint8_t)(v >> 8);
        rgb[3 * x + 2] = (uint8_t)v;
    }
}

int psc_io_png_write(const char *path, const psc_surface_t *s, char *err, size_t errlen)
{
    uint8_t *png = NULL;
    size_t len = 0;
    int rc;

    if (!path || !s || !psc_io_surface_is_valid(s))
        return psc_io_errorf(err, errlen, path, "no file name, or an invalid surface (size, stride, format)");
    /* encode in memory, then write atomically: a failed run never leaves half a PNG */
    if (png_encode(s->width, s->height, surface_row_rgb, s, &png, &len, path, err, errlen) != 0)
        return -1;
    rc = psc_io_write_atomic(path, png, len, err, errlen);
    free(png);
    return rc;
}
