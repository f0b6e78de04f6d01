/* SPDX-License-Identifier: MIT */
/*
 * test_mip.c - the map pyramid and PSC_FILTER_MIP.
 *
 *  - psc_io_image_halve is the [1 3 3 1]/8 binomial filter, wrapping columns;
 *  - a pack keeps exact halvings as levels, and the parser refuses broken ones;
 *  - zoomed in (level of detail below 0) mip is bit-exact bilinear;
 *  - zoomed out on the bundled 4096x2048 sample at hfov 120, measured against
 *    a 4x4-supersampled double-precision reference (PSNR over 8-bit RGB),
 *    mip beats the single-level bilinear render by at least 3 dB.
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

#include <zlib.h>

#include "psc_io_map_pyramid.h"
#include "psc_io_pack_build.h"
#include "pack/psc_pack.h"
#include "viewer/psc_viewer.h"
#include "psc_testsupport.h"

#define SAMPLE "assets/pannellum-examplepano.jpg"
#define OUT_W 640u
#define OUT_H 480u

static void test_halve_is_binomial(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 7);
    psc_image_t in = {16, 10, malloc(16 * 10 * sizeof(uint32_t))}, out;
    for (unsigned i = 0; i < 160; i++)
        in.xrgb[i] = 0xFF000000u | (tsup_rng_u32(&rng) & 0xFFFFFFu);
    for (int wrap = 0; wrap <= 1; wrap++) {
        assert_int_equal(psc_io_image_halve(&in, wrap, &out), 0);
        assert_int_equal(out.width, 8);
        assert_int_equal(out.height, 5);
        static const double w[4] = {1, 3, 3, 1};
        for (unsigned y = 0; y < 5; y++)
            for (unsigned x = 0; x < 8; x++)
                for (unsigned ch = 0; ch < 3; ch++) {
                    double sum = 0;
                    for (int j = 0; j < 4; j++)
                        for (int i = 0; i < 4; i++) {
                            int sx = 2 * (int)x - 1 + i, sy = 2 * (int)y - 1 + j;
                            sx = wrap ? (sx + 16) % 16 : sx < 0 ? 0 : sx > 15 ? 15 : sx;
                            sy = sy < 0 ? 0 : sy > 9 ? 9 : sy;
                            sum += w[i] * w[j] * ((in.xrgb[sy * 16 + sx] >> (8 * (2 - ch))) & 255u);
                        }
                    unsigned want = (unsigned)floor(sum / 64.0 + 0.5);
                    unsigned got = (out.xrgb[y * 8 + x] >> (8 * (2 - ch))) & 255u;
                    /* the two passes keep exact sums: rounding once, at the end */
                    assert_int_equal(got, want);
                }
        psc_io_image_free(&out);
    }
    in.width = 15;
    assert_int_equal(psc_io_image_halve(&in, true, &out), -1); /* odd sides have no exact half */
    free(in.xrgb);
    assert_int_equal(psc_io_pyramid_levels(4096, 2048, 12), 9); /* down to 16x8 */
    assert_int_equal(psc_io_pyramid_levels(4096, 2048, 3), 3);
    assert_int_equal(psc_io_pyramid_levels(1000, 500, 12), 3); /* 500 -> 250 -> 125 (odd) */
}

/* The bundled sample packed with XRGB8888 pixels (no RGB565 rounding in the comparison). */
typedef struct {
    psc_image_t img;
    uint8_t *pack_bytes;
    size_t pack_len;
    psc_pack_t pack;
} sample_t;

static int load_sample(sample_t *s, unsigned levels)
{
    char err[256];
    memset(s, 0, sizeof *s);
    if (psc_io_image_load(SAMPLE, &s->img, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    psc_pack_options_t o;
    psc_io_pack_options_default(&o);
    o.format = PSC_PIX_XRGB8888;
    o.display_width = OUT_W;
    o.display_height = OUT_H;
    o.map_levels = levels;
    if (psc_io_pack_build(&s->img, &o, &s->pack_bytes, &s->pack_len, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    psc_container_error_t perr;
    return psc_pack_parse(s->pack_bytes, s->pack_len, &s->pack, &perr) == PSC_OK ? 0 : -1;
}

static void free_sample(sample_t *s)
{
    psc_io_image_free(&s->img);
    free(s->pack_bytes);
}

static void test_pack_levels(void **state)
{
    (void)state;
    sample_t s;
    assert_int_equal(load_sample(&s, 0), 0);
    const psc_pack_t *p = &s.pack;
    assert_int_equal(p->level_count, 9);
    for (unsigned k = 0; k < p->level_count; k++) {
        assert_int_equal(p->levels[k].width, 4096u >> k);
        assert_int_equal(p->levels[k].height, 2048u >> k);
    }
    /* level 1 is the filtered level 0 image */
    psc_image_t half;
    assert_int_equal(psc_io_image_halve(&s.img, true, &half), 0);
    const uint32_t *l1 = p->levels[1].pixels;
    for (size_t i = 0; i < (size_t)half.width * half.height; i += 997)
        assert_int_equal(l1[i] & 0xFFFFFFu, half.xrgb[i] & 0xFFFFFFu);
    psc_io_image_free(&half);

    /* a level whose section is renamed to leave a gap is refused */
    uint8_t *copy = malloc(s.pack_len);
    memcpy(copy, s.pack_bytes, s.pack_len);
    unsigned nsec = tsup_rd16(copy + PSC_CONTAINER_SECTION_COUNT_OFFSET);
    for (unsigned i = 0; i < nsec; i++) {
        uint8_t *e = copy + PSC_CONTAINER_HEADER_SIZE + i * PSC_CONTAINER_SECTION_SIZE;
        if (tsup_rd32(e) == PSC_SECTION_MAP_LEVEL(2))
            tsup_wr32(e, PSC_SECTION_MAP_LEVEL(11));
    }
    tsup_wr32(copy + PSC_CONTAINER_CRC_OFFSET, 0);
    tsup_wr32(copy + PSC_CONTAINER_CRC_OFFSET, (uint32_t)crc32(0, copy, (unsigned)s.pack_len));
    psc_pack_t bad;
    psc_container_error_t perr;
    assert_int_equal(psc_pack_parse(copy, s.pack_len, &bad, &perr), PSC_ERR_CORRUPT);
    printf("  gap in the levels: \"%s\" (offset %u)\n", perr.what, (unsigned)perr.offset);
    free(copy);
    free_sample(&s);
}

typedef struct {
    psc_viewer_t v;
    void *ws;
    psc_surface_t out;
} viewer_t;

static void viewer_open(viewer_t *vw, const psc_pack_t *p, unsigned levels)
{
    size_t n = psc_viewer_workspace_size(OUT_W, OUT_H, &p->map);
    vw->ws = aligned_alloc(8, (n + 7) & ~(size_t)7);
    assert_int_equal(psc_viewer_init(&vw->v, &p->map, p->luts, p->lut_count, OUT_W, OUT_H, vw->ws, n), PSC_OK);
    assert_int_equal(psc_viewer_set_levels(&vw->v, p->levels, levels), PSC_OK);
    vw->out = (psc_surface_t){OUT_W, OUT_H, OUT_W * 4, PSC_PIX_XRGB8888, malloc(OUT_W * OUT_H * 4)};
}

static void viewer_close(viewer_t *vw)
{
    free(vw->ws);
    free(vw->out.pixels);
}

static void test_zoomed_in_mip_is_bilinear(void **state)
{
    (void)state;
    sample_t s;
    assert_int_equal(load_sample(&s, 0), 0);
    viewer_t vw;
    viewer_open(&vw, &s.pack, s.pack.level_count);
    uint32_t *bil = malloc(OUT_W * OUT_H * 4);
    /* hfov 25: 4096/pi rows per radian against 640/tan(12.5 deg) px: < 1 texel per pixel everywhere */
    psc_view_t v = tsup_view_deg(40.0, -10.0, 25.0, PSC_FILTER_BILINEAR, 2);
    assert_int_equal(psc_viewer_render(&vw.v, &v, &vw.out), PSC_OK);
    memcpy(bil, vw.out.pixels, OUT_W * OUT_H * 4);
    v.filter = PSC_FILTER_MIP;
    assert_int_equal(psc_viewer_render(&vw.v, &v, &vw.out), PSC_OK);
    assert_memory_equal(bil, vw.out.pixels, OUT_W * OUT_H * 4);
    free(bil);
    viewer_close(&vw);
    free_sample(&s);
}

static void test_zoom_out_quality(void **state)
{
    (void)state;
    sample_t s;
    assert_int_equal(load_sample(&s, 0), 0);
    viewer_t vw;
    viewer_open(&vw, &s.pack, s.pack.level_count);
    double *ref = malloc(sizeof(double) * OUT_W * OUT_H * 3);
    static const double views[][2] = {{30.0, 10.0}, {-120.0, -35.0}};
    printf("  | view (hfov 120)      | bilinear  | mip       | gain     (PSNR vs 4x4 supersampled reference)\n");
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) {
        psc_view_t v = tsup_view_deg(views[i][0], views[i][1], 120.0, PSC_FILTER_BILINEAR, 2);
        tsup_ref_render(&s.pack.map, &v, OUT_W, OUT_H, 4, ref);
        assert_int_equal(psc_viewer_render(&vw.v, &v, &vw.out), PSC_OK);
        double p_bil = tsup_psnr(tsup_mse_surface(&vw.out, ref));
        v.filter = PSC_FILTER_MIP;
        assert_int_equal(psc_viewer_render(&vw.v, &v, &vw.out), PSC_OK);
        double p_mip = tsup_psnr(tsup_mse_surface(&vw.out, ref));
        printf("  | yaw %6.1f pitch %5.1f | %6.2f dB | %6.2f dB | %+5.2f dB\n", views[i][0], views[i][1], p_bil,
               p_mip, p_mip - p_bil);
        assert_true(p_mip - p_bil >= 3.0);
    }
    free(ref);
    viewer_close(&vw);
    free_sample(&s);
}

static void test_set_levels_checks(void **state)
{
    (void)state;
    sample_t s;
    assert_int_equal(load_sample(&s, 3), 0);
    assert_int_equal(s.pack.level_count, 3);
    viewer_t vw;
    viewer_open(&vw, &s.pack, 3);
    psc_envmap_t bad[3];
    memcpy(bad, s.pack.levels, sizeof bad);
    bad[2].width++;
    assert_int_equal(psc_viewer_set_levels(&vw.v, bad, 3), PSC_ERR_ARG);
    memcpy(bad, s.pack.levels, sizeof bad);
    bad[1].format = PSC_PIX_RGB565;
    assert_int_equal(psc_viewer_set_levels(&vw.v, bad, 3), PSC_ERR_ARG);
    assert_int_equal(psc_viewer_set_levels(&vw.v, s.pack.levels, 0), PSC_ERR_ARG);
    assert_int_equal(psc_viewer_set_levels(&vw.v, s.pack.levels, PSC_VIEWER_MAX_LEVELS + 1), PSC_ERR_ARG);
    viewer_close(&vw);
    free_sample(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_halve_is_binomial),
        cmocka_unit_test(test_pack_levels),
        cmocka_unit_test(test_zoomed_in_mip_is_bilinear),
        cmocka_unit_test(test_zoom_out_quality),
        cmocka_unit_test(test_set_levels_checks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
