/* SPDX-License-Identifier: MIT */
/*
 * test_hal_v4l2.c - the V4L2 camera without a camera (hal/v4l2/): the
 * BT.601 YUYV conversion exact for all 2^24 inputs against an independent
 * rational-arithmetic reference, whole-frame conversion and resampling,
 * MJPEG frames through the camera's decode path (also without Huffman tables,
 * as UVC cameras send them, and corrupted), the device-free decisions, and a
 * camera whose device is absent or not a camera.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <jpeglib.h>
#include <linux/videodev2.h>

#include "psc_hal_camera.h"
#include "psc_hal_clock.h"
#include "base/psc_pixel.h"
#include "psc_testsupport.h"
#include "tsup_files.h"
#include "v4l2/psc_v4l2_convert.h"
#include "v4l2/v4l2_internal.h"

/* ---- YUV -> RGB, exhaustively ----------------------------------------------- */

__extension__ typedef __int128 i128;

/* round(num / den) halves up, clamped to 0..255, for den > 0 */
static uint32_t ref_round(i128 num, i128 den)
{
    i128 q;

    if (num < 0)
        return 0;
    q = (2 * num + den) / (2 * den);
    return q > 255 ? 255u : (uint32_t)q;
}

/* BT.601 from its definition (Rec. ITU-R BT.601-7, 2.5.1-2.5.3): E'Y, E'Pb,
 * E'Pr from the 8-bit codes, R' and B' from them, G' from the luma equation
 * E'Y = Kr R' + Kg G' + Kb B'. Exact rationals over a common denominator. */
static uint32_t ref_yuv(int y, int u, int v)
{
    const i128 den = (i128)219 * 224 * 1000;     /* E'Y, E'Pb/Pr and the 1/1000 of Kr, Kb */
    i128 ey = (i128)(y - 16) * 224 * 1000;       /* E'Y * den */
    i128 pb = (i128)(u - 128) * 219 * 1000;      /* E'Pb * den */
    i128 pr = (i128)(v - 128) * 219 * 1000;
    i128 r = 1000 * ey + 2 * (1000 - 299) * pr;  /* R' * den * 1000 */
    i128 b = 1000 * ey + 2 * (1000 - 114) * pb;
    i128 g = 1000 * 1000 * ey - 299 * r - 114 * b;   /* Kg G' * den * 10^6 */
    uint32_t R = ref_round(255 * r, den * 1000);
    uint32_t B = ref_round(255 * b, den * 1000);
    uint32_t G = ref_round(255 * g, den * 1000 * (1000 - 299 - 114));

    return 0xFF000000u | R << 16 | G << 8 | B;
}

static void test_yuv_exact_all_values(void **state)
{
    uint32_t mismatches = 0, first_y = 0, first_u = 0, first_v = 0;
    (void)state;

    for (int y = 0; y < 256; y++)
        for (int u = 0; u < 256; u++)
            for (int v = 0; v < 256; v++)
                if (psc_v4l2_yuv_to_xrgb((uint8_t)y, (uint8_t)u, (uint8_t)v) != ref_yuv(y, u, v)) {
                    if (mismatches++ == 0) {
                        first_y = (uint32_t)y;
                        first_u = (uint32_t)u;
                        first_v = (uint32_t)v;
                    }
                }
    if (mismatches != 0)
        print_error("%u mismatches, first at Y=%u U=%u V=%u: %08x vs %08x\n", mismatches, first_y, first_u, first_v,
                    psc_v4l2_yuv_to_xrgb((uint8_t)first_y, (uint8_t)first_u, (uint8_t)first_v),
                    ref_yuv((int)first_y, (int)first_u, (int)first_v));
    assert_int_equal(mismatches, 0);
    /* studio black and white, and saturated limits */
    assert_int_equal(psc_v4l2_yuv_to_xrgb(16, 128, 128), 0xFF000000u);
    assert_int_equal(psc_v4l2_yuv_to_xrgb(235, 128, 128), 0xFFFFFFFFu);
    assert_int_equal(psc_v4l2_yuv_to_xrgb(0, 128, 128), 0xFF000000u);
    assert_int_equal(psc_v4l2_yuv_to_xrgb(255, 128, 128), 0xFFFFFFFFu);
    /* mid grey: 255 * 110/219 = 128.08 -> 128 */
    assert_int_equal(psc_v4l2_yuv_to_xrgb(126, 128, 128), 0xFF808080u);
    /* BT.601 75% red (Y 65, Cb 100, Cr 212) is R 191, G 0, B 0 to within rounding */
    uint32_t red = psc_v4l2_yuv_to_xrgb(65, 100, 212);
    assert_in_range((red >> 16) & 255u, 190, 192);
    assert_in_range((red >> 8) & 255u, 0, 1);
    assert_in_range(red & 255u, 0, 1);
}

/* ---- whole frames and resampling ------------------------------------------- */

static void fill_random(uint8_t *p, size_t n, uint64_t seed)
{
    tsup_rng_t rng;

    tsup_rng_seed(&rng, seed);
    for (size_t i = 0; i < n; i++)
        p[i] = (uint8_t)tsup_rng_u32(&rng);
}

/* the nearest-source rule, computed independently in double precision */
static uint32_t ref_src(uint32_t x, uint32_t src, uint32_t dst)
{
    return (uint32_t)((x + 0.5) * src / dst);
}

static void check_yuyv_frame(uint16_t sw, uint16_t sh, uint16_t dw, uint16_t dh, psc_pixfmt_t fmt)
{
    uint32_t src_stride = 2u * sw + 12u, bpp = psc_pixfmt_bytes(fmt), dst_stride = dw * bpp + 8u;
    uint8_t *src = malloc((size_t)src_stride * sh), *dst = malloc((size_t)dst_stride * dh);
    uint16_t *col = malloc(dw * sizeof *col), *row = malloc(dh * sizeof *row);
    psc_v4l2_resample_t r = { .dst_width = dw, .dst_height = dh, .col = col, .row = row };
    char err[200];

    assert_non_null(src);
    assert_non_null(dst);
    fill_random(src, (size_t)src_stride * sh, (uint64_t)sw * 7919u + dh);
    psc_v4l2_resample_init(&r, sw, sh);
    assert_int_equal(psc_v4l2_convert_frame(V4L2_PIX_FMT_YUYV, &r, NULL, src, (size_t)src_stride * sh, src_stride,
                                            fmt, dst, dst_stride, err, sizeof err), 0);
    for (uint32_t y = 0; y < dh; y++)
        for (uint32_t x = 0; x < dw; x++) {
            uint32_t sx = ref_src(x, sw, dw), sy = ref_src(y, sh, dh);
            const uint8_t *line = src + (size_t)sy * src_stride;
            uint32_t want = psc_v4l2_yuv_to_xrgb(line[2 * sx], line[4 * (sx / 2) + 1], line[4 * (sx / 2) + 3]);
            const uint8_t *d = dst + (size_t)y * dst_stride;
            if (fmt == PSC_PIX_RGB565)
                assert_int_equal(((const uint16_t *)(const void *)d)[x], psc_xrgb_to_rgb565(want));
            else
                assert_int_equal(((const uint32_t *)(const void *)d)[x], want);
        }
    free(src);
    free(dst);
    free(col);
    free(row);
}

static void test_yuyv_frames(void **state)
{
    (void)state;
    check_yuyv_frame(64, 32, 64, 32, PSC_PIX_XRGB8888);    /* same size: the paired fast path */
    check_yuyv_frame(64, 32, 64, 32, PSC_PIX_RGB565);
    check_yuyv_frame(640, 360, 1024, 512, PSC_PIX_RGB565); /* vivid's webcam size up to a map */
    check_yuyv_frame(642, 480, 320, 160, PSC_PIX_XRGB8888);
    check_yuyv_frame(2, 2, 7, 3, PSC_PIX_XRGB8888);

    /* a frame too short for its size is refused, not read past its end */
    uint16_t col[8], row[4];
    psc_v4l2_resample_t r = { .dst_width = 8, .dst_height = 4, .col = col, .row = row };
    uint8_t src[64] = { 0 }, dst[8 * 4 * 4];
    char err[200];
    psc_v4l2_resample_init(&r, 8, 4);
    assert_int_equal(psc_v4l2_convert_frame(V4L2_PIX_FMT_YUYV, &r, NULL, src, 16 * 3 + 15, 16, PSC_PIX_XRGB8888, dst,
                                            32, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "too short for 8x4"));
    assert_int_equal(psc_v4l2_convert_frame(V4L2_PIX_FMT_YUYV, &r, NULL, src, 16 * 3 + 16, 16, PSC_PIX_XRGB8888, dst,
                                            32, err, sizeof err), 0);
    assert_int_equal(psc_v4l2_convert_frame(V4L2_PIX_FMT_NV12, &r, NULL, src, 64, 16, PSC_PIX_XRGB8888, dst, 32, err,
                                            sizeof err), -EINVAL);
}

/* ---- MJPEG ---------------------------------------------------------------- */

/* A w x h JPEG of a colour gradient with the standard Huffman tables. */
static uint8_t *make_jpeg(unsigned w, unsigned h, unsigned long *len)
{
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    unsigned char *buf = NULL;
    uint8_t *row = malloc(w * 3u);

    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    jpeg_mem_dest(&c, &buf, len);
    c.image_width = w;
    c.image_height = h;
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 85, TRUE);
    jpeg_start_compress(&c, TRUE);
    for (unsigned y = 0; y < h; y++) {
        for (unsigned x = 0; x < w; x++) {
            row[3 * x] = (uint8_t)(x * 255u / w);
            row[3 * x + 1] = (uint8_t)(y * 255u / h);
            row[3 * x + 2] = (uint8_t)((x ^ y) * 8u);
        }
        JSAMPROW r = row;
        jpeg_write_scanlines(&c, &r, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    free(row);
    return buf;
}

/* The JPEG without its DHT segments, as a UVC camera sends MJPEG. */
static uint8_t *strip_dht(const uint8_t *in, size_t len, size_t *out_len)
{
    uint8_t *out = malloc(len);
    size_t i = 2, n = 2;

    memcpy(out, in, 2);
    while (i + 4 <= len) {
        size_t seg = ((size_t)in[i + 2] << 8 | in[i + 3]) + 2u;
        if (in[i + 1] == 0xDA) {   /* start of scan: the rest is entropy-coded data */
            memcpy(out + n, in + i, len - i);
            n += len - i;
            break;
        }
        if (in[i + 1] != 0xC4) {
            memcpy(out + n, in + i, seg);
            n += seg;
        }
        i += seg;
    }
    *out_len = n;
    return out;
}

/* Reference: the same library decoding the plain way into 8-bit RGB. */
static uint8_t *reference_rgb(const uint8_t *jpeg, size_t len, unsigned *w, unsigned *h)
{
    struct jpeg_decompress_struct d;
    struct jpeg_error_mgr e;
    uint8_t *rgb;

    d.err = jpeg_std_error(&e);
    jpeg_create_decompress(&d);
    jpeg_mem_src(&d, jpeg, (unsigned long)len);
    jpeg_read_header(&d, TRUE);
    d.out_color_space = JCS_RGB;
    d.dct_method = JDCT_ISLOW;
    jpeg_start_decompress(&d);
    *w = d.output_width;
    *h = d.output_height;
    rgb = malloc((size_t)*w * *h * 3u);
    while (d.output_scanline < d.output_height) {
        JSAMPROW r = rgb + (size_t)d.output_scanline * *w * 3u;
        jpeg_read_scanlines(&d, &r, 1);
    }
    jpeg_finish_decompress(&d);
    jpeg_destroy_decompress(&d);
    return rgb;
}

static void check_mjpeg(psc_v4l2_mjpeg_t *m, const uint8_t *jpeg, size_t len, uint16_t dw, uint16_t dh,
                        psc_pixfmt_t fmt)
{
    unsigned w, h;
    uint8_t *rgb = reference_rgb(jpeg, len, &w, &h);
    uint32_t bpp = psc_pixfmt_bytes(fmt), stride = dw * bpp;
    uint8_t *dst = malloc((size_t)stride * dh);
    uint16_t *col = malloc(dw * sizeof *col), *row = malloc(dh * sizeof *row);
    psc_v4l2_resample_t r = { .dst_width = dw, .dst_height = dh, .col = col, .row = row };
    uint16_t fw, fh;
    char err[200];

    assert_int_equal(psc_v4l2_mjpeg_size(m, jpeg, len, &fw, &fh, err, sizeof err), 0);
    assert_int_equal(fw, w);
    assert_int_equal(fh, h);
    psc_v4l2_resample_init(&r, fw, fh);
    assert_int_equal(psc_v4l2_convert_frame(V4L2_PIX_FMT_MJPEG, &r, m, jpeg, len, 0, fmt, dst, stride, err,
                                            sizeof err), 0);
    for (uint32_t y = 0; y < dh; y++)
        for (uint32_t x = 0; x < dw; x++) {
            const uint8_t *p = rgb + ((size_t)ref_src(y, h, dh) * w + ref_src(x, w, dw)) * 3u;
            uint32_t want = 0xFF000000u | (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
            if (fmt == PSC_PIX_RGB565)
                assert_int_equal(((const uint16_t *)(const void *)(dst + y * stride))[x], psc_xrgb_to_rgb565(want));
            else
                assert_int_equal(((const uint32_t *)(const void *)(dst + y * stride))[x], want);
        }
    free(rgb);
    free(dst);
    free(col);
    free(row);
}

static void test_mjpeg_frames(void **state)
{
    unsigned long len;
    uint8_t *jpeg = make_jpeg(96, 48, &len);
    size_t bare_len;
    uint8_t *bare = strip_dht(jpeg, len, &bare_len);
    psc_v4l2_mjpeg_t *m = psc_v4l2_mjpeg_create();
    (void)state;

    assert_non_null(m);
    assert_true(bare_len < len);   /* the tables really are gone */
    check_mjpeg(m, jpeg, len, 96, 48, PSC_PIX_XRGB8888);
    check_mjpeg(m, jpeg, len, 96, 48, PSC_PIX_RGB565);
    check_mjpeg(m, jpeg, len, 200, 100, PSC_PIX_RGB565);
    check_mjpeg(m, jpeg, len, 30, 17, PSC_PIX_XRGB8888);
    /* without DHT the standard tables apply: the same picture */
    check_mjpeg(m, bare, bare_len, 96, 48, PSC_PIX_XRGB8888);
    free(bare);
    free(jpeg);
    psc_v4l2_mjpeg_destroy(m);
}

static void test_mjpeg_bad_frames(void **state)
{
    unsigned long len;
    uint8_t *jpeg = make_jpeg(64, 32, &len);
    uint8_t *copy = malloc(len);
    uint32_t stride = 64u * 4u;
    uint8_t *dst = malloc((size_t)stride * 32u);
    uint16_t col[64], row[32];
    psc_v4l2_resample_t r = { .dst_width = 64, .dst_height = 32, .col = col, .row = row };
    psc_v4l2_mjpeg_t *m = psc_v4l2_mjpeg_create();
    tsup_rng_t rng;
    char err[200];
    unsigned ok = 0, refused = 0;
    (void)state;

    psc_v4l2_resample_init(&r, 64, 32);
    /* not a JPEG at all */
    memset(copy, 0, len);
    assert_int_equal(psc_v4l2_mjpeg_decode(m, &r, copy, len, PSC_PIX_XRGB8888, dst, stride, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "SOI"));
    /* a frame of another size than negotiated */
    psc_v4l2_resample_init(&r, 32, 32);
    assert_int_equal(psc_v4l2_mjpeg_decode(m, &r, jpeg, len, PSC_PIX_XRGB8888, dst, stride, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "negotiated at 32x32"));
    psc_v4l2_resample_init(&r, 64, 32);
    /* truncated at every length: decoded (grey-padded) or refused, never a crash */
    for (size_t n = 0; n < len; n++) {
        int rc = psc_v4l2_mjpeg_decode(m, &r, jpeg, n, PSC_PIX_XRGB8888, dst, stride, err, sizeof err);
        assert_true(rc == 0 || rc == -EINVAL);
        rc == 0 ? ok++ : refused++;
    }
    /* random corruption of the entropy-coded data and the headers */
    tsup_rng_seed(&rng, 5);
    for (unsigned i = 0; i < 2000; i++) {
        memcpy(copy, jpeg, len);
        for (unsigned k = 0; k < 1u + i % 8u; k++)
            copy[2u + tsup_rng_below(&rng, (uint32_t)len - 2u)] = (uint8_t)tsup_rng_u32(&rng);
        int rc = psc_v4l2_mjpeg_decode(m, &r, copy, len, PSC_PIX_XRGB8888, dst, stride, err, sizeof err);
        assert_true(rc == 0 || rc == -EINVAL);
        rc == 0 ? ok++ : refused++;
    }
    assert_true(refused > 0);
    /* the decoder is still good after all that */
    assert_int_equal(psc_v4l2_mjpeg_decode(m, &r, jpeg, len, PSC_PIX_XRGB8888, dst, stride, err, sizeof err), 0);
    print_message("    MJPEG damage: %u frames decoded, %u refused\n", ok, refused);
    free(copy);
    free(dst);
    free(jpeg);
    psc_v4l2_mjpeg_destroy(m);
}

/* ---- decisions without a device --------------------------------------------- */

static void test_format_decisions(void **state)
{
    uint32_t f = 1;
    uint16_t w = 0, h = 0;
    char name[5], err[200];
    (void)state;

    assert_int_equal(psc_v4l2_pick_format(0, true, true), V4L2_PIX_FMT_YUYV);
    assert_int_equal(psc_v4l2_pick_format(0, false, true), V4L2_PIX_FMT_MJPEG);
    assert_int_equal(psc_v4l2_pick_format(0, false, false), 0);
    assert_int_equal(psc_v4l2_pick_format(V4L2_PIX_FMT_MJPEG, true, true), V4L2_PIX_FMT_MJPEG);
    assert_int_equal(psc_v4l2_pick_format(V4L2_PIX_FMT_MJPEG, true, false), 0);
    assert_int_equal(psc_v4l2_pick_format(V4L2_PIX_FMT_YUYV, false, true), 0);

    assert_int_equal(psc_v4l2_parse_pixel_format("auto", &f), 0);
    assert_int_equal(f, 0);
    assert_int_equal(psc_v4l2_parse_pixel_format("mjpeg", &f), 0);
    assert_int_equal(f, V4L2_PIX_FMT_MJPEG);
    assert_int_equal(psc_v4l2_parse_pixel_format("YUYV", &f), -EINVAL);
    assert_int_equal(psc_v4l2_parse_size("1280x720", &w, &h), 0);
    assert_int_equal(w, 1280);
    assert_int_equal(h, 720);
    assert_int_equal(psc_v4l2_parse_size("1280x", &w, &h), -EINVAL);
    assert_int_equal(psc_v4l2_parse_size("x720", &w, &h), -EINVAL);
    assert_int_equal(psc_v4l2_parse_size("1x720", &w, &h), -EINVAL);
    assert_int_equal(psc_v4l2_parse_size("9000x720", &w, &h), -EINVAL);
    assert_int_equal(psc_v4l2_parse_size("640x480 ", &w, &h), -EINVAL);
    assert_int_equal(psc_v4l2_parse_size("99999999999x2", &w, &h), -EINVAL);

    psc_v4l2_fourcc_name(V4L2_PIX_FMT_MJPEG, name);
    assert_string_equal(name, "MJPG");
    psc_v4l2_fourcc_name(0x01020359u, name);
    assert_string_equal(name, "Y???");

    assert_int_equal(psc_v4l2_check_frame(V4L2_PIX_FMT_YUYV, 640, 360, 1280, V4L2_FIELD_NONE, err, sizeof err), 0);
    assert_int_equal(psc_v4l2_check_frame(V4L2_PIX_FMT_YUYV, 641, 360, 1282, V4L2_FIELD_NONE, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "even"));
    assert_int_equal(psc_v4l2_check_frame(V4L2_PIX_FMT_YUYV, 640, 360, 1000, V4L2_FIELD_NONE, err, sizeof err), -EINVAL);
    assert_int_equal(psc_v4l2_check_frame(V4L2_PIX_FMT_MJPEG, 641, 360, 0, V4L2_FIELD_NONE, err, sizeof err), 0);
    assert_int_equal(psc_v4l2_check_frame(V4L2_PIX_FMT_YUYV, 640, 480, 1280, V4L2_FIELD_INTERLACED, err, sizeof err),
                     -EINVAL);
    assert_non_null(strstr(err, "interlaced"));
    assert_int_equal(psc_v4l2_check_frame(V4L2_PIX_FMT_YUYV, 16384, 480, 32768, V4L2_FIELD_NONE, err, sizeof err),
                     -EINVAL);
}

/* ---- the camera with no camera ------------------------------------------------ */

static int open_camera(psc_hal_clock_t *clk, const psc_hal_option_t *opts, size_t n, psc_hal_camera_t **cam,
                       char *err, size_t errlen)
{
    psc_hal_camera_config_t cfg = { .width = 64, .height = 32, .format = PSC_PIX_RGB565, .buffer_count = 2,
                                    .frame_rate_mhz = 15000, .clock = clk, .options = { opts, n } };

    return psc_hal_camera_open("v4l2", &cfg, cam, err, errlen);
}

static void test_camera_absent_or_wrong(void **state)
{
    psc_hal_clock_t *clk;
    psc_hal_camera_t *cam;
    psc_hal_camera_frame_t frame;
    char err[300], path[700];
    (void)state;

    assert_int_equal(psc_hal_clock_open("sim", &(psc_hal_clock_config_t){ { NULL, 0 } }, &clk, err, sizeof err), 0);

    /* absent at start-up: the kiosk starts anyway and keeps trying */
    psc_hal_option_t absent[] = { { "device", "/dev/periscope-no-such-video", "b.conf:4" },
                                  { "reopen_ms", "500", "b.conf:5" } };
    assert_int_equal(open_camera(clk, absent, 2, &cam, err, sizeof err), 0);
    assert_int_equal(psc_hal_camera_dequeue(cam, &frame), -EINVAL);   /* not started */
    assert_int_equal(psc_hal_camera_start(cam), 0);
    assert_int_equal(psc_hal_camera_start(cam), -EBUSY);
    for (uint64_t t = 0; t < 3000000; t += 100000) {
        psc_hal_clock_sleep_until(clk, t);
        assert_int_equal(psc_hal_camera_dequeue(cam, &frame), -ENODEV);
    }
    assert_int_equal(psc_hal_camera_queue(cam, &(psc_hal_camera_frame_t){ .index = 0 }), -EINVAL);
    assert_int_equal(psc_hal_camera_stop(cam), 0);
    psc_hal_camera_close(cam);

    /* unless the board says it must be there */
    psc_hal_option_t required[] = { { "device", "/dev/periscope-no-such-video", "b.conf:4" },
                                    { "required", "yes", "b.conf:6" } };
    assert_int_equal(open_camera(clk, required, 2, &cam, err, sizeof err), -ENODEV);
    assert_null(cam);
    assert_non_null(strstr(err, "/dev/periscope-no-such-video"));

    /* a file that is not a V4L2 device is a configuration mistake, not an absence */
    char rel[300], cwd[300];
    tsup_tmp_path(rel, sizeof rel, "v4l2", "not-a-camera");
    assert_int_equal(tsup_write_bytes(rel, "x", 1), 0);
    assert_non_null(getcwd(cwd, sizeof cwd));
    snprintf(path, sizeof path, "%s%s%s", rel[0] == '/' ? "" : cwd, rel[0] == '/' ? "" : "/", rel);
    psc_hal_option_t file[] = { { "device", path, "b.conf:4" } };
    assert_int_equal(open_camera(clk, file, 1, &cam, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "is not a V4L2 device"));
    psc_hal_option_t devnull[] = { { "device", "/dev/null", "b.conf:4" } };
    assert_int_equal(open_camera(clk, devnull, 1, &cam, err, sizeof err), -EINVAL);

    /* option mistakes name their line */
    psc_hal_option_t bad_fmt[] = { { "pixel_format", "h264", "b.conf:7" } };
    assert_int_equal(open_camera(clk, bad_fmt, 1, &cam, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "b.conf:7: camera option 'pixel_format' must be auto, yuyv or mjpeg"));
    psc_hal_option_t bad_size[] = { { "capture_size", "640*480", "b.conf:8" } };
    assert_int_equal(open_camera(clk, bad_size, 1, &cam, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "b.conf:8"));
    psc_hal_option_t bad_dev[] = { { "device", "video0", "b.conf:9" } };
    assert_int_equal(open_camera(clk, bad_dev, 1, &cam, err, sizeof err), -EINVAL);
    psc_hal_option_t unknown[] = { { "exposure", "10", "b.conf:10" } };
    assert_int_equal(open_camera(clk, unknown, 1, &cam, err, sizeof err), -EINVAL);
    assert_non_null(strstr(err, "b.conf:10"));
    psc_hal_option_t bad_timeout[] = { { "timeout_ms", "5", "b.conf:11" } };
    assert_int_equal(open_camera(clk, bad_timeout, 1, &cam, err, sizeof err), -EINVAL);
    psc_hal_camera_close(NULL);
    psc_hal_clock_close(clk);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_yuv_exact_all_values),
        cmocka_unit_test(test_yuyv_frames),
        cmocka_unit_test(test_mjpeg_frames),
        cmocka_unit_test(test_mjpeg_bad_frames),
        cmocka_unit_test(test_format_decisions),
        cmocka_unit_test(test_camera_absent_or_wrong),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
