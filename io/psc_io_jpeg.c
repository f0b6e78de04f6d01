/* SPDX-License-Identifier: MIT */
/*
 * psc_io_jpeg.c - JPEG decoding with libjpeg(-turbo) into 0xFFRRGGBB pixels,
 * and the error manager both of io's JPEG readers use (psc_io_jpeg_fail.h).
 */
#include "psc_io_image_codecs.h"
#include "psc_io_error.h"
#include "psc_io_jpeg_fail.h"

#include <setjmp.h>
#include <stdlib.h>
#include <string.h>
#include <jpeglib.h>
#include <jerror.h>

/* Everything the decoder allocates, kept outside the setjmp frame so that it
 * is still valid after a longjmp and can be freed. */
typedef struct {
    struct jpeg_decompress_struct cinfo;
    psc_io_jpeg_fail_t fail;
    bool created;
    JSAMPLE *row;
} jpeg_job_t;

static void jpeg_fail_exit(j_common_ptr cinfo)
{
    psc_io_jpeg_fail_t *fail = (psc_io_jpeg_fail_t *)cinfo->err;
    fail->mgr.format_message(cinfo, fail->msg);
    longjmp(fail->jump, 1);
}

/* Warnings libjpeg recovers from with the image intact are let through. */
static bool jpeg_warning_is_fatal(int code)
{
    switch (code) {
    case JWRN_ADOBE_XFORM:
    case JWRN_EXTRANEOUS_DATA:
    case JWRN_JFIF_MAJOR:
    case JWRN_BOGUS_ICC:
    case JWRN_TOO_MUCH_DATA:
        return false;
    default:
        return true;
    }
}

static void jpeg_fail_message(j_common_ptr cinfo, int level)
{
    /* level < 0: a warning; >= 0: trace output, of no interest here. */
    if (level < 0 && jpeg_warning_is_fatal(cinfo->err->msg_code))
        jpeg_fail_exit(cinfo);
}

void psc_io_jpeg_fail_init(struct jpeg_decompress_struct *cinfo, psc_io_jpeg_fail_t *fail)
{
    cinfo->err = jpeg_std_error(&fail->mgr);
    fail->mgr.error_exit = jpeg_fail_exit;
    fail->mgr.emit_message = jpeg_fail_message;
}

uint32_t psc_io_jpeg_cmyk_to_xrgb(const JSAMPLE *p, bool inverted)
{
    uint32_t c = p[0], m = p[1], y = p[2], k = p[3];
    if (!inverted) {
        c = 255u - c;
        m = 255u - m;
        y = 255u - y;
        k = 255u - k;
    }
    uint32_t r = (c * k + 127u) / 255u, g = (m * k + 127u) / 255u, b = (y * k + 127u) / 255u;
    return 0xFF000000u | r << 16 | g << 8 | b;
}

static int jpeg_run(jpeg_job_t *job, FILE *f, const char *path, uint64_t max_pixels, psc_image_t *img, char *err,
                    size_t errlen)
{
    struct jpeg_decompress_struct *cinfo = &job->cinfo;
    if (setjmp(job->fail.jump))
        return psc_io_errorf(err, errlen, path, "corrupt or truncated JPEG: %s", job->fail.msg);

    /* Set first: destroying a half-created object is safe (its memory pool is NULL). */
    job->created = true;
    jpeg_create_decompress(cinfo);
    jpeg_stdio_src(cinfo, f);
    jpeg_read_header(cinfo, TRUE);

    bool cmyk = cinfo->jpeg_color_space == JCS_CMYK || cinfo->jpeg_color_space == JCS_YCCK;
    if (!cmyk && cinfo->jpeg_color_space != JCS_GRAYSCALE && cinfo->jpeg_color_space != JCS_YCbCr &&
        cinfo->jpeg_color_space != JCS_RGB)
        return psc_io_errorf(err, errlen, path, "unsupported JPEG colour space %d", (int)cinfo->jpeg_color_space);
    if (psc_io_image_alloc(img, cinfo->image_width, cinfo->image_height, max_pixels, path, err, errlen) != 0)
        return -1;

    cinfo->out_color_space = cmyk ? JCS_CMYK : JCS_RGB;
    jpeg_start_decompress(cinfo);
    unsigned channels = (unsigned)cinfo->output_components;
    if (cinfo->output_width != img->width || cinfo->output_height != img->height ||
        channels != (cmyk ? 4u : 3u))
        return psc_io_errorf(err, errlen, path, "JPEG decoder produced an unexpected layout");

    job->row = malloc((size_t)img->width * channels);
    if (!job->row)
        return psc_io_errorf(err, errlen, path, "out of memory");
    bool inverted = cinfo->saw_Adobe_marker;
    while (cinfo->output_scanline < cinfo->output_height) {
        uint32_t y = cinfo->output_scanline;
        JSAMPROW rows[1] = {job->row};
        if (jpeg_read_scanlines(cinfo, rows, 1) != 1)
            return psc_io_errorf(err, errlen, path, "JPEG data ends at row %u", (unsigned)y);
        uint32_t *dst = img->xrgb + (size_t)y * img->width;
        for (uint32_t x = 0; x < img->width; x++) {
            const JSAMPLE *p = job->row + (size_t)x * channels;
            dst[x] = cmyk ? psc_io_jpeg_cmyk_to_xrgb(p, inverted)
                          : 0xFF000000u | (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
        }
    }
    /* Reads up to the end marker, so a file cut after the last row is refused too. */
    jpeg_finish_decompress(cinfo);
    return 0;
}

int psc_io_jpeg_decode(FILE *f, const char *path, uint64_t max_pixels, psc_image_t *img, char *err, size_t errlen)
{
    jpeg_job_t *job = calloc(1, sizeof *job);
    if (!job)
        return psc_io_errorf(err, errlen, path, "out of memory");
    psc_io_jpeg_fail_init(&job->cinfo, &job->fail);
    int rc = jpeg_run(job, f, path, max_pixels, img, err, errlen);
    if (job->created)
        jpeg_destroy_decompress(&job->cinfo);
    free(job->row);
    free(job);
    return rc;
}
