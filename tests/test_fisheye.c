/* SPDX-License-Identifier: MIT */
/*
 * test_fisheye.c - dual-fisheye cameras: the lens model's conventions, the
 * table's positions against the exact double-precision mapping, a synthetic
 * dual-fisheye frame of a known scene remapped through the table and compared
 * with the scene (PSNR), the integer bilinear remap pixel for pixel, the
 * table parser on truncated, corrupt and randomly mutated files, the tool,
 * and a whole run of the device program with a fisheye camera scene.
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

#include "app.h"
#include "board_config.h"
#include "camera_feed.h"
#include "cli.h"
#include "bake/fisheye.h"
#include "psc_io_pack_build.h"
#include "base/psc_crc32.h"
#include "fisheye/psc_fisheye.h"
#include "psc_hal_camera.h"
#include "base/psc_pixel.h"
#include "psc_testsupport.h"
#include "sim/psc_hal_sim.h"
#include "tsup_files.h"
#include "psc_io_load.h"
#include "psc_io_file.h"

/* ---- rigs ------------------------------------------------------------------------ */

/* A 1024x512 dual-fisheye frame: two 190-degree circles side by side. */
static psc_bake_fisheye_rig_t ideal_rig(void)
{
    psc_bake_fisheye_rig_t r;
    memset(&r, 0, sizeof r);
    r.frame_width = 1024;
    r.frame_height = 512;
    r.lens[0] = (psc_bake_fisheye_lens_t){ 255.5, 255.5, 254.0, 190.0, 0, 0, 0 };
    r.lens[1] = (psc_bake_fisheye_lens_t){ 767.5, 255.5, 254.0, 190.0, 0, 0, 0 };
    return r;
}

/* The same with off-centre circles, wider lenses and mounting corrections. */
static psc_bake_fisheye_rig_t skewed_rig(void)
{
    psc_bake_fisheye_rig_t r = ideal_rig();
    r.lens[0] = (psc_bake_fisheye_lens_t){ 252.25, 258.0, 248.0, 196.0, 2.0, -1.5, 3.0 };
    r.lens[1] = (psc_bake_fisheye_lens_t){ 770.0, 253.5, 250.5, 194.0, -1.0, 2.0, -2.5 };
    return r;
}

/* Build a table in a 64-byte aligned buffer and parse it. */
static uint8_t *build_table(const psc_bake_fisheye_rig_t *rig, uint16_t mw, uint16_t mh, size_t *len, psc_fisheye_t *t)
{
    char err[300];
    uint8_t *raw = NULL, *al = NULL;
    if (psc_bake_fisheye(rig, mw, mh, "test", &raw, len, err, sizeof err) != 0)
        fail_msg("build: %s", err);
    assert_int_equal(posix_memalign((void **)&al, 64, *len), 0);
    memcpy(al, raw, *len);
    free(raw);
    if (t) {
        psc_container_error_t pe = {0};
        assert_int_equal(psc_fisheye_parse(al, *len, t, &pe), PSC_OK);
    }
    return al;
}

static void dir_of(double lon_deg, double lat_deg, double d[3])
{
    double lon = lon_deg * TSUP_DEG, lat = lat_deg * TSUP_DEG;
    d[0] = cos(lat) * sin(lon);
    d[1] = sin(lat);
    d[2] = cos(lat) * cos(lon);
}

/* ---- the lens model's conventions --------------------------------------------------- */

static void expect_project(const psc_bake_fisheye_rig_t *rig, unsigned k, double lon, double lat, double x, double y)
{
    double d[3], px, py, th;
    dir_of(lon, lat, d);
    psc_bake_fisheye_project(rig, k, d, &px, &py, &th);
    if (fabs(px - x) > 1e-9 || fabs(py - y) > 1e-9)
        fail_msg("lens %u, lon %g lat %g: got (%.6f, %.6f), want (%.6f, %.6f)", k, lon, lat, px, py, x, y);
}

static void test_lens_conventions(void **state)
{
    (void)state;
    psc_bake_fisheye_rig_t rig = ideal_rig();
    double f = 254.0 / (95.0 * TSUP_DEG), q = f * TSUP_PI / 2.0; /* pixels at 90 degrees off-axis */

    /* ahead is the front circle's centre, behind the back one's */
    expect_project(&rig, 0, 0, 0, 255.5, 255.5);
    expect_project(&rig, 1, 180, 0, 767.5, 255.5);
    /* right (+X, lon 90) is the front image's right and the back image's left; up is up in both */
    expect_project(&rig, 0, 90, 0, 255.5 + q, 255.5);
    expect_project(&rig, 1, 90, 0, 767.5 - q, 255.5);
    expect_project(&rig, 0, 0, 90, 255.5, 255.5 - q);
    expect_project(&rig, 1, 0, 90, 767.5, 255.5 - q);
    expect_project(&rig, 0, 0, -45, 255.5, 255.5 + f * TSUP_PI / 4.0);
    /* the rim is at fov/2 = 95 degrees */
    double d[3], x, y, th;
    dir_of(95.0, 0, d);
    assert_true(psc_bake_fisheye_project(&rig, 0, d, &x, &y, &th));
    assert_true(fabs(x - (255.5 + 254.0)) < 1e-9);
    dir_of(95.5, 0, d);
    assert_false(psc_bake_fisheye_project(&rig, 0, d, &x, &y, &th));

    /* corrections: yaw turns the axis toward the image's right, pitch toward
     * its up; roll turns the image's right toward its up */
    rig.lens[0].yaw_deg = 5.0;
    expect_project(&rig, 0, 5, 0, 255.5, 255.5);
    rig.lens[0].yaw_deg = 0.0;
    rig.lens[0].pitch_deg = 4.0;
    expect_project(&rig, 0, 0, 4, 255.5, 255.5);
    rig.lens[0].pitch_deg = 0.0;
    rig.lens[0].roll_deg = 90.0 / 2.0;  /* within the +-45 limit: the lens's right at 45 degrees up */
    double a = 45.0 * TSUP_DEG, r = f * 30.0 * TSUP_DEG;
    /* a point 30 degrees along the lens's rolled right axis lies straight right in the image */
    double p[3] = { cos(a) * sin(30.0 * TSUP_DEG), sin(a) * sin(30.0 * TSUP_DEG), cos(30.0 * TSUP_DEG) };
    psc_bake_fisheye_project(&rig, 0, p, &x, &y, &th);
    assert_true(fabs(x - (255.5 + r)) < 1e-9 && fabs(y - 255.5) < 1e-9);
    rig.lens[1].yaw_deg = 5.0;   /* the back lens's right is -X: its axis turns toward lon 180 - 5 */
    expect_project(&rig, 1, -175, 0, 767.5, 255.5);

    /* unproject inverts project for every lens of the skewed rig */
    psc_bake_fisheye_rig_t sk = skewed_rig();
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 7);
    for (unsigned i = 0; i < 2000; i++) {
        unsigned k = i & 1u;
        double lon = tsup_rng_range(&rng, -180, 180), lat = tsup_rng_range(&rng, -89, 89), back[3];
        dir_of(lon, lat, d);
        if (!psc_bake_fisheye_project(&sk, k, d, &x, &y, &th))
            continue;
        assert_true(psc_bake_fisheye_unproject(&sk, k, x, y, back));
        for (unsigned c = 0; c < 3; c++)
            assert_true(fabs(back[c] - d[c]) < 1e-9);
    }
}

/* ---- the table against the exact mapping ---------------------------------------------- */

static void check_positions(const psc_bake_fisheye_rig_t *rig, uint16_t mw, uint16_t mh, unsigned *unseen_out)
{
    size_t len;
    psc_fisheye_t t;
    uint8_t *buf = build_table(rig, mw, mh, &len, &t);
    double max_err = 0.0;
    unsigned unseen = 0, lens_used[2] = {0, 0};

    assert_int_equal(t.frame_width, rig->frame_width);
    assert_int_equal(t.map_width, mw);
    assert_int_equal(t.map_height, mh);
    for (unsigned j = 0; j < mh; j++)
        for (unsigned i = 0; i < mw; i++) {
            const uint16_t *e = t.pos + 2 * ((size_t)j * mw + i);
            double x, y;
            int k = psc_bake_fisheye_source(rig, mw, mh, i, j, &x, &y);
            if (k < 0) {
                assert_int_equal(e[0], PSC_FISHEYE_UNSEEN);
                assert_int_equal(e[1], PSC_FISHEYE_UNSEEN);
                unseen++;
                continue;
            }
            lens_used[k]++;
            double ex = fabs(e[0] / 16.0 - x), ey = fabs(e[1] / 16.0 - y);
            max_err = fmax(max_err, fmax(ex, ey));
            /* the chosen lens is the one whose ray is nearer its axis */
            double d[3], px, py, th0, th1;
            psc_bake_fisheye_map_dir(mw, mh, i, j, d);
            psc_bake_fisheye_project(rig, 0, d, &px, &py, &th0);
            psc_bake_fisheye_project(rig, 1, d, &px, &py, &th1);
            assert_int_equal(k, th0 <= th1 ? 0 : 1);
        }
    /* Q12.4 rounding: at most half of 1/16 pixel per coordinate */
    print_message("    %ux%u map: max position error %.4f camera px (bound 1/32), %u unseen, lenses %u / %u\n",
                  mw, mh, max_err, unseen, lens_used[0], lens_used[1]);
    assert_true(max_err <= 1.0 / 32.0 + 1e-9);
    assert_int_equal(unseen, t.unseen_count);
    assert_true(lens_used[0] > 0 && lens_used[1] > 0);
    *unseen_out = unseen;
    free(buf);
}

static void test_positions_exact(void **state)
{
    (void)state;
    unsigned unseen;
    psc_bake_fisheye_rig_t rig = ideal_rig();
    check_positions(&rig, 512, 256, &unseen);
    assert_int_equal(unseen, 0);             /* 190 degrees each: the whole sphere */
    rig = skewed_rig();
    check_positions(&rig, 600, 300, &unseen);
    assert_int_equal(unseen, 0);
    /* 170-degree lenses leave a band around the sides unseen */
    rig = ideal_rig();
    rig.lens[0].fov_deg = rig.lens[1].fov_deg = 170.0;
    check_positions(&rig, 256, 128, &unseen);
    assert_true(unseen > 0);
}

/* ---- a synthetic dual-fisheye frame of a known scene --------------------------------- */

/* The frame the rig's camera would take of tsup_synth_color's scene: each
 * pixel the scene's colour in its ray's direction, black outside both circles. */
static void *synth_frame(const psc_bake_fisheye_rig_t *rig, psc_pixfmt_t fmt, psc_envmap_t *frame)
{
    unsigned w = rig->frame_width, h = rig->frame_height, bpp = psc_pixfmt_bytes(fmt);
    uint8_t *px = calloc((size_t)w * h, bpp);
    for (unsigned y = 0; y < h; y++)
        for (unsigned x = 0; x < w; x++) {
            double rgb[3] = {0, 0, 0}, d[3];
            for (unsigned k = 0; k < 2; k++)
                if (psc_bake_fisheye_unproject(rig, k, x, y, d)) {
                    tsup_synth_color(atan2(d[0], d[2]), asin(fmax(-1.0, fmin(1.0, d[1]))), rgb);
                    break;
                }
            if (fmt == PSC_PIX_XRGB8888)
                ((uint32_t *)(void *)px)[(size_t)y * w + x] = 0xFF000000u | (uint32_t)lround(rgb[0]) << 16 |
                                                              (uint32_t)lround(rgb[1]) << 8 | (uint32_t)lround(rgb[2]);
            else
                ((uint16_t *)(void *)px)[(size_t)y * w + x] = tsup_rgb888_to_rgb565(rgb[0], rgb[1], rgb[2]);
        }
    memset(frame, 0, sizeof *frame);
    frame->projection = PSC_PROJ_EQUIRECT;
    frame->format = fmt;
    frame->width = (uint16_t)w;
    frame->height = (uint16_t)h;
    frame->stride = w * bpp;
    frame->pixels = px;
    return px;
}

/* PSNR of the remapped map against the scene at the map pixels' centres. */
static double remap_psnr(const psc_bake_fisheye_rig_t *rig, uint16_t mw, uint16_t mh, psc_pixfmt_t fmt)
{
    size_t len;
    psc_fisheye_t t;
    uint8_t *buf = build_table(rig, mw, mh, &len, &t);
    psc_envmap_t frame;
    void *fpx = synth_frame(rig, fmt, &frame);
    unsigned bpp = psc_pixfmt_bytes(fmt);
    uint8_t *map = malloc((size_t)mw * mh * bpp);
    assert_int_equal(psc_fisheye_remap(&t, &frame, map, mw * bpp, 0x000000u), PSC_OK);
    psc_envmap_t m = psc_fisheye_map_shape(&t, fmt, map);
    double se = 0.0;
    for (unsigned j = 0; j < mh; j++)
        for (unsigned i = 0; i < mw; i++) {
            double lon, lat, rgb[3];
            tsup_map_dir(&m, j, i, &lon, &lat);
            tsup_synth_color(lon, lat, rgb);
            if (fmt == PSC_PIX_RGB565) {   /* compare with the scene as RGB565 can hold it */
                uint32_t q = tsup_rgb565_to_rgb888(tsup_rgb888_to_rgb565(rgb[0], rgb[1], rgb[2]));
                rgb[0] = q >> 16 & 255u;
                rgb[1] = q >> 8 & 255u;
                rgb[2] = q & 255u;
            }
            uint32_t got = tsup_map_texel(&m, (int)j, (int)i);
            double dr = (double)(got >> 16 & 255u) - rgb[0], dg = (double)(got >> 8 & 255u) - rgb[1],
                   db = (double)(got & 255u) - rgb[2];
            se += dr * dr + dg * dg + db * db;
        }
    free(map);
    free(fpx);
    free(buf);
    return tsup_psnr(se / (3.0 * mw * mh));
}

#define PSNR_BOUND_DB 34.0

static void test_remap_psnr(void **state)
{
    (void)state;
    psc_bake_fisheye_rig_t rigs[2] = { ideal_rig(), skewed_rig() };
    const char *names[2] = { "ideal", "skewed" };
    for (unsigned r = 0; r < 2; r++) {
        double p32 = remap_psnr(&rigs[r], 512, 256, PSC_PIX_XRGB8888);
        double p16 = remap_psnr(&rigs[r], 512, 256, PSC_PIX_RGB565);
        print_message("    %s rig, 1024x512 frame -> 512x256 map: PSNR %.2f dB (XRGB8888), %.2f dB (RGB565), "
                      "bound %.1f dB\n", names[r], p32, p16, PSNR_BOUND_DB);
        assert_true(p32 >= PSNR_BOUND_DB);
        assert_true(p16 >= PSNR_BOUND_DB);
    }
}

/* ---- the integer bilinear remap, pixel for pixel ---------------------------------------- */

static void test_remap_exact(void **state)
{
    (void)state;
    /* a hand-made 3x2 map over a 4x3 frame */
    enum { FW = 4, FH = 3, MW = 3, MH = 2 };
    static const uint16_t pos[MW * MH * 2] = {
        0, 0,            16 * 3, 16 * 2,   8, 8,             /* corner, last pixel, middle of four */
        16 + 5, 16 + 11, PSC_FISHEYE_UNSEEN, PSC_FISHEYE_UNSEEN, 16 * 3, 7, /* fractions; unseen; last column */
    };
    psc_fisheye_t t = { FW, FH, MW, MH, pos, 1, 0 };
    uint32_t f32[FW * FH];
    uint16_t f16[FW * FH];
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 3);
    for (unsigned i = 0; i < FW * FH; i++) {
        f32[i] = 0xFF000000u | (tsup_rng_u32(&rng) & 0xFFFFFFu);
        f16[i] = (uint16_t)tsup_rng_u32(&rng);
    }
    psc_envmap_t fr = { PSC_PROJ_EQUIRECT, PSC_PIX_XRGB8888, FW, FH, FW * 4, f32, NULL, 0, 0, 0, 0 };
    uint32_t out[MW * MH + 1];
    out[MW * MH] = 0xDEADBEEFu;
    assert_int_equal(psc_fisheye_remap(&t, &fr, out, MW * 4, 0x123456u), PSC_OK);
    assert_int_equal(out[MW * MH], 0xDEADBEEFu);          /* nothing past the map */
    for (unsigned i = 0; i < MW * MH; i++) {
        if (pos[2 * i] == PSC_FISHEYE_UNSEEN) {
            assert_int_equal(out[i], 0xFF123456u);
            continue;
        }
        /* the exact bilinear value, then rounded: within half a unit per channel */
        double x = pos[2 * i] / 16.0, y = pos[2 * i + 1] / 16.0;
        int x0 = (int)x, y0 = (int)y, x1 = x0 + (x > x0), y1 = y0 + (y > y0);
        double fx = x - x0, fy = y - y0;
        for (unsigned sh = 0; sh < 24; sh += 8) {
            double c00 = f32[y0 * FW + x0] >> sh & 255u, c01 = f32[y0 * FW + x1] >> sh & 255u;
            double c10 = f32[y1 * FW + x0] >> sh & 255u, c11 = f32[y1 * FW + x1] >> sh & 255u;
            double want = (c00 * (1 - fx) + c01 * fx) * (1 - fy) + (c10 * (1 - fx) + c11 * fx) * fy;
            assert_true(fabs((double)(out[i] >> sh & 255u) - want) <= 0.5 + 1e-9);
        }
    }
    assert_int_equal(out[0], f32[0]);
    assert_int_equal(out[1], f32[FW * FH - 1]);

    uint16_t o16[MW * MH];
    fr.format = PSC_PIX_RGB565;
    fr.stride = FW * 2;
    fr.pixels = f16;
    assert_int_equal(psc_fisheye_remap(&t, &fr, o16, MW * 2, 0xFFFFFFu), PSC_OK);
    assert_int_equal(o16[0], f16[0]);
    assert_int_equal(o16[1], f16[FW * FH - 1]);
    assert_int_equal(o16[4], 0xFFFFu);
    /* x = 3.0 exactly: the right neighbour is not read, only the rows blend */
    assert_int_equal(o16[5], psc_blend4_rgb565(f16[3], f16[3], f16[FW + 3], f16[FW + 3], 0, 14));

    /* mismatches write nothing */
    fr.width = FW + 1;
    assert_int_equal(psc_fisheye_remap(&t, &fr, o16, MW * 2, 0), PSC_ERR_ARG);
    fr.width = FW;
    fr.format = PSC_PIX_PAL8;
    assert_int_equal(psc_fisheye_remap(&t, &fr, o16, MW * 2, 0), PSC_ERR_ARG);
    fr.format = PSC_PIX_RGB565;
    assert_int_equal(psc_fisheye_remap(&t, &fr, o16, MW * 2 - 1, 0), PSC_ERR_ARG);
    fr.stride = FW * 2 - 2;
    assert_int_equal(psc_fisheye_remap(&t, &fr, o16, MW * 2, 0), PSC_ERR_ARG);
    assert_int_equal(psc_fisheye_remap(NULL, &fr, o16, MW * 2, 0), PSC_ERR_ARG);
}

/* ---- the parser -------------------------------------------------------------------------- */

static psc_bake_fisheye_rig_t small_rig(void)
{
    psc_bake_fisheye_rig_t r = ideal_rig();
    r.frame_width = 64;
    r.frame_height = 32;
    r.lens[0] = (psc_bake_fisheye_lens_t){ 15.5, 15.5, 15.5, 190.0, 0, 0, 0 };
    r.lens[1] = (psc_bake_fisheye_lens_t){ 47.5, 15.5, 15.5, 190.0, 0, 0, 0 };
    return r;
}

static void fix_crc(uint8_t *b, size_t len)
{
    memset(b + PSC_CONTAINER_CRC_OFFSET, 0, 4);
    tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, b, len));
}

static psc_status_t parse_copy(const uint8_t *b, size_t len, psc_fisheye_t *t, psc_container_error_t *pe)
{
    uint8_t *c = NULL;
    assert_int_equal(posix_memalign((void **)&c, 64, len ? len : 1), 0);
    memcpy(c, b, len);
    psc_status_t s = psc_fisheye_parse(c, len, t, pe);
    free(c);
    return s;
}

static void expect_bad(uint8_t *b, size_t len, psc_status_t want, const char *what)
{
    psc_fisheye_t t;
    psc_container_error_t pe = {0};
    fix_crc(b, len);
    psc_status_t s = psc_fisheye_parse(b, len, &t, &pe);
    if (s != want || pe.what == NULL || strstr(pe.what, what) == NULL)
        fail_msg("want %s \"%s\", got %s \"%s\"", psc_status_str(want), what, psc_status_str(s),
                 pe.what ? pe.what : "(none)");
}

static void test_parse_truncated(void **state)
{
    (void)state;
    psc_bake_fisheye_rig_t rig = small_rig();
    size_t len;
    uint8_t *b = build_table(&rig, 32, 16, &len, NULL);
    for (size_t n = 0; n < len; n++) {
        psc_fisheye_t t;
        psc_container_error_t pe = {0};
        psc_status_t s = parse_copy(b, n, &t, &pe);
        assert_int_not_equal(s, PSC_OK);
        assert_non_null(pe.what);
    }
    psc_fisheye_t t;
    assert_int_equal(parse_copy(b, len, &t, NULL), PSC_OK);
    print_message("    every truncation of the %zu-byte table fails cleanly\n", len);
    free(b);
}

static void test_parse_corrupt(void **state)
{
    (void)state;
    psc_bake_fisheye_rig_t rig = small_rig();
    size_t len;
    uint8_t *orig = build_table(&rig, 32, 16, &len, NULL);
    uint8_t *b = NULL;
    assert_int_equal(posix_memalign((void **)&b, 64, len + 64), 0);
    const size_t info = 64, pos = 128, e0 = PSC_CONTAINER_HEADER_SIZE, e1 = e0 + PSC_CONTAINER_SECTION_SIZE;
    psc_fisheye_t t;
    psc_container_error_t pe;

#define RESET() memcpy(b, orig, len)
    RESET();
    b[len / 2] ^= 0x10;   /* a flipped bit with the CRC left alone */
    assert_int_equal(psc_fisheye_parse(b, len, &t, &pe), PSC_ERR_CRC);
    RESET();
    b[0] = 'X';
    expect_bad(b, len, PSC_ERR_MAGIC, "not a dual-fisheye table");
    RESET();
    memcpy(b, "PSCPANO\x1a", 8);   /* another Periscope file */
    expect_bad(b, len, PSC_ERR_MAGIC, "not a dual-fisheye table");
    RESET();
    tsup_wr16(b + PSC_CONTAINER_VERSION_MAJOR_OFFSET, 2);
    expect_bad(b, len, PSC_ERR_VERSION, "major version");
    RESET();
    tsup_wr16(b + info, 0);
    expect_bad(b, len, PSC_ERR_CORRUPT, "frame size");
    RESET();
    tsup_wr16(b + info + 2, 4097);
    expect_bad(b, len, PSC_ERR_CORRUPT, "frame size");
    RESET();
    tsup_wr16(b + info + 4, 1);
    expect_bad(b, len, PSC_ERR_CORRUPT, "map size");
    RESET();
    tsup_wr16(b + info + 6, 17);   /* positions no longer match the map */
    expect_bad(b, len, PSC_ERR_CORRUPT, "FPOS size");
    RESET();
    b[info + 12] = 1;
    expect_bad(b, len, PSC_ERR_CORRUPT, "reserved");
    RESET();
    tsup_wr32(b + e0 + 8, 15);
    expect_bad(b, len, PSC_ERR_CORRUPT, "FINF section is not 16 bytes");
    RESET();
    tsup_wr32(b + e0, PSC_FOURCC('X', 'X', 'X', 'X'));   /* unknown: skipped, so FINF is missing */
    expect_bad(b, len, PSC_ERR_CORRUPT, "no FINF");
    RESET();
    tsup_wr32(b + e1, PSC_FOURCC('F', 'I', 'N', 'F'));
    expect_bad(b, len, PSC_ERR_CORRUPT, "two FINF");
    RESET();
    tsup_wr32(b + e1, PSC_FOURCC('X', 'X', 'X', 'X'));
    expect_bad(b, len, PSC_ERR_CORRUPT, "no FPOS");
    RESET();
    tsup_wr32(b + e1 + 4, pos + 4);
    expect_bad(b, len, PSC_ERR_CORRUPT, "aligned");
    RESET();
    tsup_wr32(b + e1 + 8, (uint32_t)(len - pos + 4));
    expect_bad(b, len, PSC_ERR_CORRUPT, "outside the file");
    /* positions: one past the last column or row, or half-marked unseen */
    RESET();
    tsup_wr16(b + pos + 40, 63 * 16 + 1);
    expect_bad(b, len, PSC_ERR_CORRUPT, "outside the camera frame");
    RESET();
    tsup_wr16(b + pos + 42, 31 * 16 + 1);
    expect_bad(b, len, PSC_ERR_CORRUPT, "outside the camera frame");
    RESET();
    tsup_wr16(b + pos + 40, PSC_FISHEYE_UNSEEN);
    expect_bad(b, len, PSC_ERR_CORRUPT, "outside the camera frame");
    RESET();
    tsup_wr16(b + pos + 40, 63 * 16);   /* the last pixel exactly is fine */
    tsup_wr16(b + pos + 42, 31 * 16);
    fix_crc(b, len);
    assert_int_equal(psc_fisheye_parse(b, len, &t, &pe), PSC_OK);
    RESET();
    tsup_wr16(b + pos, PSC_FISHEYE_UNSEEN);
    tsup_wr16(b + pos + 2, PSC_FISHEYE_UNSEEN);
    fix_crc(b, len);
    assert_int_equal(psc_fisheye_parse(b, len, &t, &pe), PSC_OK);
    assert_int_equal(t.unseen_count, 1);
    /* alignment, trailing bytes, no buffer */
    RESET();
    assert_int_equal(psc_fisheye_parse(b + 1, len - 1, &t, &pe), PSC_ERR_ARG);
    b[len] = 0;
    assert_int_equal(psc_fisheye_parse(b, len + 1, &t, &pe), PSC_ERR_CORRUPT);
    assert_int_equal(psc_fisheye_parse(NULL, len, &t, &pe), PSC_ERR_ARG);
    assert_int_equal(psc_fisheye_parse(b, len, NULL, &pe), PSC_ERR_ARG);
#undef RESET
    free(b);
    free(orig);
}

/* Random damage with the CRC made right again: the parser either refuses it
 * or promises positions the remap can read - and then the remap stays inside
 * a frame of exactly the parsed size. */
static void test_parse_fuzz(void **state)
{
    (void)state;
    psc_bake_fisheye_rig_t rig = small_rig();
    size_t len;
    uint8_t *orig = build_table(&rig, 32, 16, &len, NULL);
    uint8_t *b = NULL;
    assert_int_equal(posix_memalign((void **)&b, 64, len), 0);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 2026);
    unsigned accepted = 0;
    const unsigned rounds = 3000;
    for (unsigned r = 0; r < rounds; r++) {
        memcpy(b, orig, len);
        unsigned n = 1 + tsup_rng_below(&rng, 8);
        for (unsigned k = 0; k < n; k++) {
            /* half the damage in the header, table and info, where it matters most */
            size_t at = tsup_rng_below(&rng, 2) ? tsup_rng_below(&rng, 96) : tsup_rng_below(&rng, (uint32_t)len);
            switch (tsup_rng_below(&rng, 3)) {
            case 0: b[at] ^= (uint8_t)(1u << tsup_rng_below(&rng, 8)); break;
            case 1: b[at] = (uint8_t)tsup_rng_u32(&rng); break;
            default: b[at] = tsup_rng_below(&rng, 2) ? 0xFF : 0x00; break;
            }
        }
        fix_crc(b, len);
        psc_fisheye_t t;
        psc_container_error_t pe = {0};
        psc_status_t s = psc_fisheye_parse(b, len, &t, &pe);
        if (s != PSC_OK) {
            assert_non_null(pe.what);
            continue;
        }
        accepted++;
        assert_true(t.frame_width >= 1 && t.frame_width <= PSC_FISHEYE_MAX_FRAME_DIM);
        assert_true((const uint8_t *)t.pos >= b &&
                    (const uint8_t *)(t.pos + 2u * t.map_width * t.map_height) <= b + len);
        uint32_t *frame = calloc((size_t)t.frame_width * t.frame_height, 4);
        uint32_t *map = malloc((size_t)t.map_width * t.map_height * 4);
        psc_envmap_t fr = { PSC_PROJ_EQUIRECT, PSC_PIX_XRGB8888, t.frame_width, t.frame_height,
                            (uint32_t)t.frame_width * 4, frame, NULL, 0, 0, 0, 0 };
        assert_int_equal(psc_fisheye_remap(&t, &fr, map, (uint32_t)t.map_width * 4, 0), PSC_OK);
        free(frame);
        free(map);
    }
    print_message("    %u mutated tables (CRC fixed): %u refused with a reason, %u accepted and remapped safely\n",
                  rounds, rounds - accepted, accepted);
    assert_true(accepted < rounds);
    free(b);
    free(orig);
}

/* ---- files and the tool ---------------------------------------------------------------------- */

static char root[300];

static void test_file_and_tool(void **state)
{
    (void)state;
    char path[400], cmd[1200], err[600];
    psc_io_fisheye_t ff;
    const char *bin = getenv("PSC_BIN_DIR");

    snprintf(path, sizeof path, "%s/missing.pfish", root);
    assert_int_equal(psc_io_fisheye_load(path, &ff, err, sizeof err), -1);
    assert_true(tsup_msg_starts_with_path(err, path));

    /* the tool writes exactly what the library builds */
    snprintf(path, sizeof path, "%s/rig.pfish", root);
    snprintf(cmd, sizeof cmd, "%s/periscope-fisheye --frame 1024x512 --front 252.25:258:248:196 "
             "--back 770:253.5:250.5:194 --front-rot 2:-1.5:3 --back-rot=-1:2:-2.5 --map 600x300 -o %s >/dev/null",
             bin ? bin : "build/bin", path);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(psc_io_fisheye_load(path, &ff, err, sizeof err), 0);
    psc_bake_fisheye_rig_t rig = skewed_rig();
    uint8_t *want = NULL;
    size_t len;
    assert_int_equal(psc_bake_fisheye(&rig, 600, 300, "x", &want, &len, err, sizeof err), 0);
    assert_int_equal(ff.len, len);
    assert_memory_equal(ff.buf, want, len);
    free(want);
    psc_io_fisheye_free(&ff);

    /* a damaged file: the message names it and the problem */
    size_t n;
    uint8_t *bytes = tsup_read_bytes(path, &n);
    bytes[200] ^= 1;
    assert_int_equal(tsup_write_bytes(path, bytes, n), 0);
    free(bytes);
    assert_int_equal(psc_io_fisheye_load(path, &ff, err, sizeof err), -1);
    assert_true(tsup_msg_starts_with_path(err, path));
    assert_non_null(strstr(err, "CRC"));

    /* bad command lines are usage errors (2), bad lenses failures (1) */
    snprintf(cmd, sizeof cmd, "%s/periscope-fisheye --frame 1024x512 --front 1:2 --back 3:4:5 -o %s 2>/dev/null",
             bin ? bin : "build/bin", path);
    assert_int_equal(WEXITSTATUS(system(cmd)), 2);
    snprintf(cmd, sizeof cmd, "%s/periscope-fisheye --frame 1024x512 --front 2000:2:5 --back 3:4:5 -o %s 2>/dev/null",
             bin ? bin : "build/bin", path);
    assert_int_equal(WEXITSTATUS(system(cmd)), 1);
}

/* ---- the camera feed in fisheye mode --------------------------------------------------------- */

/* The sim camera without a clock delivers frame 0 once, then nothing new. */
static void feed_case(psc_pixfmt_t fmt, uint16_t table_w, int want_rc)
{
    char err[300];
    psc_hal_camera_t *cam = NULL;
    psc_hal_camera_config_t cc = { .width = 128, .height = 64, .format = fmt, .buffer_count = 2,
                                   .frame_rate_mhz = 15000 };
    assert_int_equal(psc_hal_camera_open("sim", &cc, &cam, err, sizeof err), 0);
    assert_int_equal(psc_hal_camera_start(cam), 0);
    psc_bake_fisheye_rig_t rig = small_rig();
    rig.frame_width = table_w;
    rig.frame_height = 64;
    rig.lens[0] = (psc_bake_fisheye_lens_t){ 31.5, 31.5, 31.5, 190.0, 0, 0, 0 };
    rig.lens[1] = (psc_bake_fisheye_lens_t){ 95.5, 31.5, 31.5, 190.0, 0, 0, 0 };
    size_t len;
    psc_fisheye_t t;
    uint8_t *tb = build_table(&rig, 96, 48, &len, &t);
    unsigned bpp = psc_pixfmt_bytes(fmt);
    uint8_t *map = calloc(96 * 48, bpp), *want = calloc(96 * 48, bpp), *frame = calloc(128 * 64, bpp);

    psc_camera_feed_t f;
    psc_camera_feed_init(&f, cam);
    psc_camera_feed_set_fisheye(&f, &t, map);
    assert_int_equal(psc_camera_feed_poll(&f), want_rc);
    assert_int_equal(psc_camera_feed_poll(&f), -EAGAIN);
    assert_false(f.holding);                    /* the frame went straight back */
    if (want_rc == 0) {
        assert_true(psc_camera_feed_has_map(&f));
        assert_int_equal(f.frames, 1);
        assert_ptr_equal(f.map.pixels, map);
        assert_int_equal(f.map.width, 96);
        assert_int_equal(f.map.format, fmt);
        psc_sim_pattern_fill(frame, 128 * bpp, 128, 64, fmt, 0);
        psc_envmap_t fr = { PSC_PROJ_EQUIRECT, fmt, 128, 64, 128 * bpp, frame, NULL, 0, 0, 0, 0 };
        assert_int_equal(psc_fisheye_remap(&t, &fr, want, 96 * bpp, 0), PSC_OK);
        assert_memory_equal(map, want, (size_t)96 * 48 * bpp);
    } else {
        assert_false(psc_camera_feed_has_map(&f));
        assert_int_equal(f.rejected, 1);
    }
    psc_camera_feed_release(&f);
    psc_hal_camera_close(cam);
    free(frame);
    free(want);
    free(map);
    free(tb);
}

static void test_feed_fisheye(void **state)
{
    (void)state;
    feed_case(PSC_PIX_XRGB8888, 128, 0);
    feed_case(PSC_PIX_RGB565, 128, 0);
    feed_case(PSC_PIX_RGB565, 120, -EINVAL);   /* a table for another frame size */
}

/* ---- the device program with a fisheye camera scene -------------------------------------------- */

static void write_text(const char *path, const char *text)
{
    assert_int_equal(tsup_write_bytes(path, text, strlen(text)), 0);
}

static void make_pack(const char *path)
{
    psc_image_t img = { 128, 64, malloc(128 * 64 * 4) };
    psc_pack_options_t o;
    uint8_t *buf;
    size_t len;
    char err[300];
    for (uint32_t i = 0; i < 128 * 64; i++)
        img.xrgb[i] = 0xFF204060u;
    psc_io_pack_options_default(&o);
    o.display_width = 160;
    o.display_height = 120;
    o.lut_rows = 32;
    o.lut_cols = 128;
    if (psc_io_pack_build(&img, &o, &buf, &len, err, sizeof err) != 0)
        fail_msg("pack: %s", err);
    free(img.xrgb);
    assert_int_equal(psc_io_write_atomic(path, buf, len, err, sizeof err), 0);
    free(buf);
}

static int run_board(const char *name, uint32_t frames, uint32_t dump_at, const char *dump_path, char *err,
                     size_t errlen)
{
    psc_cli_options_t opt;
    psc_app_stats_t st;
    psc_app_t *app = NULL;

    memset(&opt, 0, sizeof opt);
    opt.board = name;
    opt.boards_dir = root;
    opt.max_frames = frames;
    opt.quiet = true;
    opt.dumps[0] = (psc_cli_dump_t){ dump_at, dump_path };
    opt.dump_count = 1;
    if (psc_app_open(&opt, &app, err, errlen) != 0)
        return -1;
    int rc = psc_app_run(app, &st, err, errlen);
    psc_app_close(app);
    return rc;
}

static void write_board(const char *name, const char *pack, const char *table, const char *size)
{
    char dir[400], path[500], conf[1500], tour[400];
    snprintf(tour, sizeof tour, "%s/still.txt", root);
    write_text(tour, "wait 10s\nend\n");
    snprintf(dir, sizeof dir, "%s/%s", root, name);
    mkdir(dir, 0755);
    snprintf(path, sizeof path, "%s/board.conf", dir);
    snprintf(conf, sizeof conf,
             "display = sim\ndisplay_size = 160x120\ndisplay_format = xrgb8888\nframe_rate = 30\n"
             "input = sim\ntour = %s\nclock = sim\ncamera = sim\ncamera_size = %s\ncamera_rate = 15\n"
             "camera_scene = %s\n%s%s%squality = fixed\n", tour, size, pack, table ? "camera_fisheye_table = " : "",
             table ? table : "", table ? "\n" : "");
    write_text(path, conf);
}

static void test_firmware_fisheye_scene(void **state)
{
    (void)state;
    char pack[400], table[400], dump[400], err[800];
    psc_io_pack_t pf;
    psc_io_fisheye_t ff;

    snprintf(pack, sizeof pack, "%s/fish.pano", root);
    make_pack(pack);
    assert_int_equal(psc_io_pack_load(pack, &pf, err, sizeof err), 0);
    /* the sim camera's 256x128 frames read as a dual-fisheye frame */
    psc_bake_fisheye_rig_t rig = small_rig();
    rig.frame_width = 256;
    rig.frame_height = 128;
    rig.lens[0] = (psc_bake_fisheye_lens_t){ 63.5, 63.5, 63.0, 190.0, 0, 0, 0 };
    rig.lens[1] = (psc_bake_fisheye_lens_t){ 191.5, 63.5, 63.0, 190.0, 0, 0, 0 };
    uint8_t *tb;
    size_t len;
    assert_int_equal(psc_bake_fisheye(&rig, 192, 96, "t", &tb, &len, err, sizeof err), 0);
    snprintf(table, sizeof table, "%s/fish.pfish", root);
    assert_int_equal(tsup_write_bytes(table, tb, len), 0);
    free(tb);
    assert_int_equal(psc_io_fisheye_load(table, &ff, err, sizeof err), 0);

    write_board("fishboard", pack, table, "256x128");
    snprintf(dump, sizeof dump, "%s/fish9.raw", root);
    if (run_board("fishboard", 10, 9, dump, err, sizeof err) != 0)
        fail_msg("fishboard: %s", err);

    /* frame 9 (9/30 s) shows the camera's frame 4 remapped, through the pack's tables */
    uint32_t *cam = malloc(256 * 128 * 4), *map = malloc(192 * 96 * 4), *px = malloc(160 * 120 * 4);
    psc_sim_pattern_fill(cam, 256 * 4, 256, 128, PSC_PIX_XRGB8888, 4);
    psc_envmap_t fr = { PSC_PROJ_EQUIRECT, PSC_PIX_XRGB8888, 256, 128, 256 * 4, cam, NULL, 0, 0, 0, 0 };
    assert_int_equal(psc_fisheye_remap(&ff.table, &fr, map, 192 * 4, 0), PSC_OK);
    psc_envmap_t m = psc_fisheye_map_shape(&ff.table, PSC_PIX_XRGB8888, map);
    psc_viewer_t v;
    size_t ws_size = psc_viewer_workspace_size(160, 120, &m);
    void *ws = aligned_alloc(64, (ws_size + 63) & ~(size_t)63);
    psc_surface_t out = { 160, 120, 160 * 4, PSC_PIX_XRGB8888, px };
    psc_view_t view = { .yaw = pf.pack.default_yaw, .pitch = pf.pack.default_pitch, .hfov = pf.pack.default_hfov,
                        .filter = PSC_FILTER_MIP, .span_log2 = 2 };
    assert_int_equal(psc_viewer_init(&v, &m, pf.pack.luts, pf.pack.lut_count, 160, 120, ws, ws_size), PSC_OK);
    psc_viewer_clamp(&v, &view, pf.pack.hfov_min);
    assert_int_equal(psc_viewer_render(&v, &view, &out), PSC_OK);
    size_t n;
    uint8_t *got = tsup_read_bytes(dump, &n);
    assert_non_null(got);
    assert_int_equal(n, 160 * 120 * 4);
    assert_memory_equal(got, px, n);
    free(got);
    free(ws);
    free(px);
    free(map);
    free(cam);
    unlink(dump);

    /* a table for another frame size is refused at start-up, naming both */
    write_board("fishwrong", pack, table, "512x256");
    assert_int_equal(run_board("fishwrong", 2, 0, dump, err, sizeof err), -1);
    assert_non_null(strstr(err, "was built for a 256x128 frame but camera_size is 512x256"));
    /* a damaged table names the file */
    snprintf(dump, sizeof dump, "%s/nofile.pfish", root);
    write_board("fishmissing", pack, dump, "256x128");
    assert_int_equal(run_board("fishmissing", 2, 0, dump, err, sizeof err), -1);
    assert_non_null(strstr(err, "nofile.pfish"));
    psc_io_fisheye_free(&ff);
    psc_io_pack_free(&pf);

    /* the key needs a camera scene */
    psc_board_config_t cfg;
    char path[500];
    snprintf(path, sizeof path, "%s/lonely.conf", root);
    write_text(path, "display = sim\ndisplay_size = 160x120\ninput = sim\nclock = sim\ncamera = sim\n"
                     "camera_fisheye_table = x.pfish\n");
    assert_int_not_equal(psc_board_config_load(path, &cfg, err, sizeof err), 0);
    assert_non_null(strstr(err, "camera_fisheye_table is set but camera_scene is not"));
}

int main(void)
{
    const char *tmp = getenv("PSC_TEST_TMPDIR");
    snprintf(root, sizeof root, "%s/fisheye", tmp ? tmp : "/tmp");
    mkdir(tmp ? tmp : "/tmp", 0755);
    mkdir(root, 0755);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lens_conventions),
        cmocka_unit_test(test_positions_exact),
        cmocka_unit_test(test_remap_psnr),
        cmocka_unit_test(test_remap_exact),
        cmocka_unit_test(test_parse_truncated),
        cmocka_unit_test(test_parse_corrupt),
        cmocka_unit_test(test_parse_fuzz),
        cmocka_unit_test(test_file_and_tool),
        cmocka_unit_test(test_feed_fisheye),
        cmocka_unit_test(test_firmware_fisheye_scene),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
