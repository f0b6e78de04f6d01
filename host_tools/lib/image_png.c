/*
 * image_png.c - PNG decoding (any colour type and bit depth to 0xFFRRGGBB,
 * alpha dropped) and 8-bit RGB PNG encoding into memory, with libpng.
 * libpng reports errors by calling our handler, which must not return: it
 * keeps the message and longjmps back to the setjmp in the job.
 */
#include "image_codecs.h"
#include "errmsg.h"

#include <setjmp.h>
#include <stdlib.h>
#include <string.h>
#include <png.h>

/* State that must survive a longjmp lives here, not in the setjmp frame. */
typedef struct {
    png_structp png;
    png_infop info;
    FILE *file;            /* decoding */
    png_bytep *rows;       /* decoding: row pointers into the image */
    uint8_t *out;          /* encoding: growing output buffer */
    size_t out_len, out_cap;
    uint8_t *row;          /* encoding: one RGB row */
    char msg[200];
} png_job_t;

static void png_job_error(png_structp png, png_const_charp msg)
{
    png_job_t *job = png_get_error_ptr(png);
    snprintf(job->msg, sizeof job->msg, "%s", msg);
    png_longjmp(png, 1);
}

/* Warnings (odd ancillary chunks, colour profiles) do not affect the pixels we use. */
static void png_job_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

static void png_job_read(png_structp png, png_bytep data, size_t len)
{
    png_job_t *job = png_get_io_ptr(png);
    if (fread(data, 1, len, job->file) != len)
        png_error(png, ferror(job->file) ? "read error" : "file ends early (truncated)");
}

static int png_read_run(png_job_t *job, const char *path, psc_image_t *img, char *err, size_t errlen)
{
    png_structp png = job->png;
    png_infop info = job->info;
    if (setjmp(png_jmpbuf(png)))
        return psc_errorf(err, errlen, path, "corrupt or truncated PNG: %s", job->msg);

    png_set_read_fn(png, job, png_job_read);
    png_read_info(png, info);
    uint32_t w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    if (psc_image_alloc(img, w, h, path, err, errlen) != 0)
        return -1;

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
        return psc_errorf(err, errlen, path, "PNG decoder produced an unexpected layout");

    /* Decode straight into the image, then repack each RGBA quad in place. */
    job->rows = malloc((size_t)h * sizeof *job->rows);
    if (!job->rows)
        return psc_errorf(err, errlen, path, "out of memory");
    for (uint32_t y = 0; y < h; y++)
        job->rows[y] = (png_bytep)(img->xrgb + (size_t)y * w);
    png_read_image(png, job->rows);
    png_read_end(png, NULL);

    for (size_t i = 0, n = (size_t)w * h; i < n; i++) {
        const uint8_t *p = (const uint8_t *)(img->xrgb + i);
        img->xrgb[i] = 0xFF000000u | (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
    }
    return 0;
}

int psc_png_decode(FILE *f, const char *path, psc_image_t *img, char *err, size_t errlen)
{
    png_job_t *job = calloc(1, sizeof *job);
    if (!job)
        return psc_errorf(err, errlen, path, "out of memory");
    job->file = f;
    job->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, job, png_job_error, png_job_warning);
    job->info = job->png ? png_create_info_struct(job->png) : NULL;
    int rc = job->info ? png_read_run(job, path, img, err, errlen)
                       : psc_errorf(err, errlen, path, "out of memory (libpng)");
    png_destroy_read_struct(&job->png, &job->info, NULL);
    free(job->rows);
    free(job);
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

static int png_write_run(png_job_t *job, uint32_t w, uint32_t h, psc_png_row_fn row, const void *ctx,
                         const char *path, char *err, size_t errlen)
{
    png_structp png = job->png;
    png_infop info = job->info;
    if (setjmp(png_jmpbuf(png)))
        return psc_errorf(err, errlen, path, "cannot encode PNG: %s", job->msg);

    job->row = malloc((size_t)w * 3u);
    if (!job->row)
        return psc_errorf(err, errlen, path, "out of memory");
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

int psc_png_encode(uint32_t width, uint32_t height, psc_png_row_fn row, const void *ctx,
                   uint8_t **png, size_t *png_len, const char *path, char *err, size_t errlen)
{
    *png = NULL;
    *png_len = 0;
    if (width == 0 || height == 0 || width > PNG_UINT_31_MAX || height > PNG_UINT_31_MAX)
        return psc_errorf(err, errlen, path, "cannot write a %ux%u PNG", (unsigned)width, (unsigned)height);
    png_job_t *job = calloc(1, sizeof *job);
    if (!job)
        return psc_errorf(err, errlen, path, "out of memory");
    job->png = png_create_write_struct(PNG_LIBPNG_VER_STRING, job, png_job_error, png_job_warning);
    job->info = job->png ? png_create_info_struct(job->png) : NULL;
    int rc = job->info ? png_write_run(job, width, height, row, ctx, path, err, errlen)
                       : psc_errorf(err, errlen, path, "out of memory (libpng)");
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
