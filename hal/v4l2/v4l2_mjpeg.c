/* SPDX-License-Identifier: MIT */
/*
 * v4l2_mjpeg.c - Motion-JPEG camera frames decoded with libjpeg(-turbo)
 * straight from the mmap'd V4L2 buffer (jpeg_mem_src) into the map, one
 * scanline at a time through a row buffer allocated once.
 *
 * libjpeg reports fatal errors through error_exit, which must not return:
 * it longjmps back here, so a corrupt frame from a flaky USB cable costs one
 * dropped frame, never the process. Warnings (e.g. data ending early, which
 * libjpeg pads with grey) are not errors: the frame is shown.
 */
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jpeglib.h>

#include "psc_hal.h"
#include "psc_v4l2_convert.h"

typedef struct {
    struct jpeg_error_mgr pub;   /* first: libjpeg hands this pointer back */
    jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
} mjpeg_error_t;

struct psc_v4l2_mjpeg {
    struct jpeg_decompress_struct cinfo;
    mjpeg_error_t jerr;
    bool created;
    uint8_t *row;                /* PSC_V4L2_MAX_SRC_WIDTH * 3 bytes */
};

static void mjpeg_error_exit(j_common_ptr cinfo)
{
    mjpeg_error_t *e = (mjpeg_error_t *)(void *)cinfo->err;

    (*cinfo->err->format_message)(cinfo, e->message);
    longjmp(e->jump, 1);
}

/* Corrupt-data warnings would print to stderr once per frame: stay quiet. */
static void mjpeg_output_message(j_common_ptr cinfo)
{
    (void)cinfo;
}

/* jpeg_create_decompress fails only when out of memory, through error_exit. */
static bool mjpeg_create_cinfo(psc_v4l2_mjpeg_t *m)
{
    m->cinfo.err = jpeg_std_error(&m->jerr.pub);
    m->jerr.pub.error_exit = mjpeg_error_exit;
    m->jerr.pub.output_message = mjpeg_output_message;
    if (setjmp(m->jerr.jump) != 0)
        return false;
    jpeg_create_decompress(&m->cinfo);
    m->created = true;
    return true;
}

psc_v4l2_mjpeg_t *psc_v4l2_mjpeg_create(void)
{
    psc_v4l2_mjpeg_t *m = calloc(1, sizeof *m);

    if (m == NULL)
        return NULL;
    m->row = malloc((size_t)PSC_V4L2_MAX_SRC_WIDTH * 3u);
    if (m->row == NULL || !mjpeg_create_cinfo(m)) {
        psc_v4l2_mjpeg_destroy(m);
        return NULL;
    }
    return m;
}

void psc_v4l2_mjpeg_destroy(psc_v4l2_mjpeg_t *m)
{
    if (m == NULL)
        return;
    if (m->created)
        jpeg_destroy_decompress(&m->cinfo);
    free(m->row);
    free(m);
}

/* Start reading a frame's header; libjpeg errors come back through the caller's setjmp. */
static void mjpeg_begin(psc_v4l2_mjpeg_t *m, const uint8_t *jpeg, size_t len)
{
    jpeg_mem_src(&m->cinfo, jpeg, (unsigned long)len);
    jpeg_read_header(&m->cinfo, TRUE);
}

int psc_v4l2_mjpeg_size(psc_v4l2_mjpeg_t *m, const uint8_t *jpeg, size_t len, uint16_t *width, uint16_t *height,
                        char *err, size_t errlen)
{
    if (len < 4 || jpeg[0] != 0xFF || jpeg[1] != 0xD8) {
        psc_hal_error_set(err, errlen, "MJPEG frame of %zu bytes does not start with a JPEG SOI marker", len);
        return -EINVAL;
    }
    if (setjmp(m->jerr.jump) != 0) {
        jpeg_abort_decompress(&m->cinfo);
        psc_hal_error_set(err, errlen, "MJPEG frame header: %s", m->jerr.message);
        return -EINVAL;
    }
    mjpeg_begin(m, jpeg, len);
    if (m->cinfo.image_width == 0 || m->cinfo.image_height == 0 || m->cinfo.image_width > PSC_V4L2_MAX_SRC_WIDTH ||
        m->cinfo.image_height > PSC_V4L2_MAX_SRC_HEIGHT) {
        psc_hal_error_set(err, errlen, "MJPEG frame is %ux%u: outside 1x1..%ux%u", (unsigned)m->cinfo.image_width,
                          (unsigned)m->cinfo.image_height, PSC_V4L2_MAX_SRC_WIDTH, PSC_V4L2_MAX_SRC_HEIGHT);
        jpeg_abort_decompress(&m->cinfo);
        return -EINVAL;
    }
    *width = (uint16_t)m->cinfo.image_width;
    *height = (uint16_t)m->cinfo.image_height;
    jpeg_abort_decompress(&m->cinfo);
    return 0;
}

int psc_v4l2_mjpeg_decode(psc_v4l2_mjpeg_t *m, const psc_v4l2_resample_t *r, const uint8_t *jpeg, size_t len,
                          psc_pixfmt_t fmt, uint8_t *dst, uint32_t dst_stride, char *err, size_t errlen)
{
    /* volatile: modified between setjmp and a possible longjmp */
    volatile uint32_t dst_row = 0;

    if (len < 4 || jpeg[0] != 0xFF || jpeg[1] != 0xD8) {
        psc_hal_error_set(err, errlen, "MJPEG frame of %zu bytes does not start with a JPEG SOI marker", len);
        return -EINVAL;
    }
    if (setjmp(m->jerr.jump) != 0) {
        jpeg_abort_decompress(&m->cinfo);
        psc_hal_error_set(err, errlen, "MJPEG frame: %s", m->jerr.message);
        return -EINVAL;
    }
    mjpeg_begin(m, jpeg, len);
    if (m->cinfo.image_width != r->src_width || m->cinfo.image_height != r->src_height) {
        psc_hal_error_set(err, errlen, "MJPEG frame is %ux%u, the stream was negotiated at %ux%u",
                          (unsigned)m->cinfo.image_width, (unsigned)m->cinfo.image_height, (unsigned)r->src_width,
                          (unsigned)r->src_height);
        jpeg_abort_decompress(&m->cinfo);
        return -EINVAL;
    }
    m->cinfo.out_color_space = JCS_RGB;
    m->cinfo.dct_method = JDCT_ISLOW;   /* the accurate integer IDCT: the same picture on every CPU */
    jpeg_start_decompress(&m->cinfo);
    if (m->cinfo.output_components != 3 || m->cinfo.output_width != r->src_width) {
        psc_hal_error_set(err, errlen, "MJPEG frame decodes to %d components of %u pixels, expected RGB of %u",
                          m->cinfo.output_components, (unsigned)m->cinfo.output_width, (unsigned)r->src_width);
        jpeg_abort_decompress(&m->cinfo);
        return -EINVAL;
    }
    while (m->cinfo.output_scanline < m->cinfo.output_height) {
        JSAMPROW rows[1] = { m->row };
        uint32_t src_row = m->cinfo.output_scanline;

        if (jpeg_read_scanlines(&m->cinfo, rows, 1) != 1)
            break;
        /* every map row whose nearest source row this is (the table is non-decreasing) */
        while (dst_row < r->dst_height && r->row[dst_row] == src_row) {
            psc_v4l2_store_rgb_row(r, m->row, fmt, dst + (size_t)dst_row * dst_stride);
            dst_row = dst_row + 1u;
        }
    }
    jpeg_finish_decompress(&m->cinfo);
    if (dst_row != r->dst_height) {
        psc_hal_error_set(err, errlen, "MJPEG frame ended after %u of %u map rows", (unsigned)dst_row,
                          (unsigned)r->dst_height);
        return -EINVAL;
    }
    return 0;
}
