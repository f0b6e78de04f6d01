/* SPDX-License-Identifier: MIT */
/*
 * test_dither.c - frames for displays with few levels (core/dither):
 *  - a smooth grey ramp through each target: the local average of what the
 *    display shows (over one tile of the matrix) stays within the bound the
 *    matrix allows, step / (2 M^2) plus rounding, while rounding each pixel to
 *    the nearest level is off by up to half a step (and is measured to be);
 *  - the colour cube: the same on a colour ramp, channel by channel;
 *  - 4000 random pixels: the level is the nearest one or the next toward the
 *    value (never further), flat areas of a level the display has stay flat,
 *    and the packing round-trips with the bits beyond a row's end zero;
 *  - the halftone cell grows from its centre: level k of 17 darkens k dots
 *    that touch each other, the first at the centre.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "dither/psc_dither.h"
#include "base/psc_pixel.h"
#include "psc_io_levels.h"
#include "psc_testsupport.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 512u
#define H 32u

static double luma_of(uint32_t px)
{
    return (77.0 * ((px >> 16) & 255u) + 150.0 * ((px >> 8) & 255u) + 29.0 * (px & 255u)) / 256.0;
}

/*
 * Worst difference, over aligned m x m tiles, between the mean input and the
 * mean shown value of channel ch (-1: luma) of a w x h frame.
 */
static double tile_error(const uint32_t *in, const uint32_t *shown, unsigned m, int ch)
{
    double worst = 0.0;
    for (unsigned ty = 0; ty + m <= H; ty += m)
        for (unsigned tx = 0; tx + m <= W; tx += m) {
            double a = 0.0, b = 0.0;
            for (unsigned y = ty; y < ty + m; y++)
                for (unsigned x = tx; x < tx + m; x++) {
                    uint32_t p = in[y * W + x], q = shown[y * W + x];
                    a += ch < 0 ? luma_of(p) : (double)((p >> (8 * ch)) & 255u);
                    b += ch < 0 ? luma_of(q) : (double)((q >> (8 * ch)) & 255u);
                }
            double e = fabs(a - b) / (double)(m * m);
            worst = e > worst ? e : worst;
        }
    return worst;
}

/* Dither a frame and expand what the display shows. */
static void show(psc_dither_target_t t, psc_dither_method_t m, const uint32_t *in, uint32_t *shown)
{
    uint8_t row[W];
    for (unsigned y = 0; y < H; y++) {
        psc_dither_row(t, m, in + y * W, W, y, row);
        for (unsigned x = 0; x < W; x++)
            shown[y * W + x] = psc_dither_level_xrgb(t, psc_dither_get(t, row, x));
    }
}

/* A W x H ramp, 0..255 left to right: grey, or red up, green down and blue half a turn apart on odd rows. */
static uint32_t *ramp_new(bool colour)
{
    uint32_t *in = malloc(W * H * 4);
    assert_non_null(in);
    for (unsigned y = 0; y < H; y++)
        for (unsigned x = 0; x < W; x++) {
            uint32_t v = x * 255u / (W - 1u); /* two pixels a level */
            in[y * W + x] = 0xFF000000u | (colour ? v << 16 | (255u - v) << 8 | (v + 128u * (y & 1u)) % 256u
                                                  : v * 0x010101u);
        }
    return in;
}

static void test_grey_ramp_keeps_local_average(void **state)
{
    (void)state;
    uint32_t *in = ramp_new(false), *shown = malloc(W * H * 4);
    assert_non_null(shown);
    static const struct {
        psc_dither_target_t t;
        const char *name;
        double step; /* the display's step between levels, in 8-bit units */
    } targets[] = {{PSC_DITHER_MONO, "mono", 255.0}, {PSC_DITHER_GREY4, "grey4", 17.0}};
    for (unsigned i = 0; i < 2; i++) {
        show(targets[i].t, PSC_DITHER_NONE, in, shown);
        double none = tile_error(in, shown, 8, -1);
        show(targets[i].t, PSC_DITHER_ORDERED, in, shown);
        double ordered = tile_error(in, shown, 8, -1);
        show(targets[i].t, PSC_DITHER_HALFTONE, in, shown);
        double halftone = tile_error(in, shown, 4, -1);
        print_message("  %-5s ramp: worst tile-average error nearest %.2f, ordered (8x8) %.2f, halftone (4x4) %.2f "
                      "(8-bit units; a step is %.0f)\n",
                      targets[i].name, none, ordered, halftone, targets[i].step);
        /* the bound: half a step spread over the tile's cells, plus the ramp's own spread and rounding */
        assert_true(ordered <= targets[i].step / (2.0 * 64.0) + 1.5);
        assert_true(halftone <= targets[i].step / (2.0 * 16.0) + 1.5);
        assert_true(none >= targets[i].step / 4.0); /* rounding alone loses the in-between levels */
    }
    free(in);
    free(shown);
}

static void test_colour_cube_ramp(void **state)
{
    (void)state;
    uint32_t *in = ramp_new(true), *shown = malloc(W * H * 4);
    assert_non_null(shown);
    show(PSC_DITHER_PAL8, PSC_DITHER_ORDERED, in, shown);
    double worst = 0.0;
    for (int ch = 0; ch < 3; ch++) {
        double e = tile_error(in, shown, 8, ch);
        worst = e > worst ? e : worst;
    }
    show(PSC_DITHER_PAL8, PSC_DITHER_NONE, in, shown);
    double none = tile_error(in, shown, 8, 2);
    print_message("  pal8 colour ramp: worst channel tile-average error ordered %.2f, nearest %.2f\n", worst, none);
    /* steps of 51 (6 levels) and 42.5 (7 levels), plus the ramp's spread in a tile and the shown levels'
     * rounding to 8 bits; blue alternates rows by half the range */
    assert_true(worst <= 51.0 / 128.0 + 2.0);
    assert_true(none > 5.0);
    free(in);
    free(shown);
}

static void test_random_pixels(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 99);
    static const psc_dither_target_t targets[] = {PSC_DITHER_MONO, PSC_DITHER_GREY4, PSC_DITHER_PAL8};
    static const psc_dither_method_t methods[] = {PSC_DITHER_NONE, PSC_DITHER_ORDERED, PSC_DITHER_HALFTONE};
    for (unsigned k = 0; k < 4000; k++) {
        psc_dither_target_t t = targets[k % 3];
        psc_dither_method_t m = methods[(k / 3) % 3];
        unsigned n = 1 + tsup_rng_below(&r, 40), y = tsup_rng_below(&r, 1000);
        uint32_t src[40];
        uint8_t row[41];
        memset(row, 0xEE, sizeof row);
        for (unsigned x = 0; x < n; x++)
            src[x] = tsup_rng_u32(&r) | 0xFF000000u;
        psc_dither_row(t, m, src, n, y, row);
        size_t bytes = psc_dither_row_bytes(t, n);
        assert_int_equal(row[bytes], 0xEE); /* nothing written past the row */
        if (t == PSC_DITHER_MONO && n % 8)
            assert_int_equal(row[bytes - 1] & ((1u << (8 - n % 8)) - 1u), 0);
        if (t == PSC_DITHER_GREY4 && n % 2)
            assert_int_equal(row[bytes - 1] & 15u, 0);
        for (unsigned x = 0; x < n; x++) {
            uint32_t v = psc_dither_get(t, row, x), shown = psc_dither_level_xrgb(t, v);
            for (int ch = 0; ch < (t == PSC_DITHER_PAL8 ? 3 : 1); ch++) {
                double want = t == PSC_DITHER_PAL8 ? (double)((src[x] >> (8 * ch)) & 255u) : luma_of(src[x]);
                double got = t == PSC_DITHER_PAL8 ? (double)((shown >> (8 * ch)) & 255u) : (double)(shown & 255u);
                double step = t == PSC_DITHER_MONO ? 255.0 : t == PSC_DITHER_GREY4 ? 17.0 : ch == 1 ? 42.5 : 51.0;
                /* the nearest level, or for the matrices one of the two around the value */
                assert_true(fabs(got - want) <= (m == PSC_DITHER_NONE ? step / 2.0 + 1.0 : step + 1.0));
            }
        }
    }
    /* a level the display has is shown flat, whatever the matrix */
    uint32_t flat[16];
    uint8_t row[16];
    for (unsigned i = 0; i < 16; i++)
        flat[i] = 0xFF000000u | 0x888888u; /* grey 136 = level 8 of 16 */
    for (unsigned y = 0; y < 8; y++) {
        psc_dither_row(PSC_DITHER_GREY4, PSC_DITHER_ORDERED, flat, 16, y, row);
        for (unsigned x = 0; x < 16; x++)
            assert_int_equal(psc_dither_get(PSC_DITHER_GREY4, row, x), 8);
    }
}

static void test_halftone_cell_grows_from_centre(void **state)
{
    (void)state;
    for (unsigned k = 1; k <= 16; k++) {
        /* a grey that darkens k of the 16 dots of a mono cell: the ink, as on paper */
        uint32_t v = ((16u - k) * 510u + 255u) / 32u, src[4];
        for (unsigned i = 0; i < 4; i++)
            src[i] = 0xFF000000u | v * 0x010101u;
        unsigned cells[16][2], nc = 0;
        for (unsigned y = 0; y < 4; y++) {
            uint8_t row[1];
            psc_dither_row(PSC_DITHER_MONO, PSC_DITHER_HALFTONE, src, 4, y, row);
            for (unsigned x = 0; x < 4; x++)
                if (!psc_dither_get(PSC_DITHER_MONO, row, x)) {
                    cells[nc][0] = x, cells[nc][1] = y;
                    nc++;
                }
        }
        assert_int_equal(nc, k);
        /* one cluster round the centre: the first dot is a centre one, every dark dot touches another */
        if (k == 1)
            assert_true(cells[0][0] >= 1 && cells[0][0] <= 2 && cells[0][1] >= 1 && cells[0][1] <= 2);
        for (unsigned i = 0; i < nc && nc > 1; i++) {
            int touches = 0;
            for (unsigned j = 0; j < nc; j++)
                touches |= abs((int)cells[i][0] - (int)cells[j][0]) + abs((int)cells[i][1] - (int)cells[j][1]) == 1;
            assert_true(touches);
        }
    }
}

/* The names the tools and boards use, and a frame turned in place in either format: an RGB565 frame with only the
 * 16 greys (as RGB565 holds them), an XRGB8888 one with only black and white; off leaves the frame alone. */
static void test_levels_in_place(void **state)
{
    (void)state;
    psc_io_levels_t l;
    char name[32];
    assert_int_equal(psc_io_levels_parse("grey4", &l), 0);
    assert_true(l.on && l.target == PSC_DITHER_GREY4 && l.method == PSC_DITHER_ORDERED);
    assert_string_equal(psc_io_levels_name(&l, name, sizeof name), "grey4:ordered");
    assert_int_equal(psc_io_levels_parse("pal8:none", &l), 0);
    assert_true(l.target == PSC_DITHER_PAL8 && l.method == PSC_DITHER_NONE);
    assert_int_equal(psc_io_levels_parse("grey", &l), -1);
    assert_int_equal(psc_io_levels_parse("mono:", &l), -1);
    assert_int_equal(psc_io_levels_parse("mono:halftone:x", &l), -1);
    enum { LW = 64, LH = 16 };
    static uint16_t p565[LW * LH];
    static uint32_t p8888[LW * LH];
    for (unsigned i = 0; i < LW * LH; i++) {
        uint32_t c = (i % LW) * 4u * 0x010101u;
        p565[i] = psc_xrgb_to_rgb565(c);
        p8888[i] = 0xFF000000u | c;
    }
    psc_surface_t s565 = {LW, LH, LW * 2, PSC_PIX_RGB565, p565}, s8888 = {LW, LH, LW * 4, PSC_PIX_XRGB8888, p8888};
    psc_io_levels_t off = {false, PSC_DITHER_MONO, PSC_DITHER_ORDERED};
    psc_io_levels_apply(&off, &s8888);
    assert_int_equal(p8888[5] & 0xFFFFFFu, 20u * 0x010101u);
    assert_int_equal(psc_io_levels_parse("grey4", &l), 0);
    psc_io_levels_apply(&l, &s565);
    for (unsigned i = 0; i < LW * LH; i++) {
        bool grey = false;
        for (uint32_t k = 0; k < 16; k++)
            grey |= p565[i] == psc_xrgb_to_rgb565(k * 17u * 0x010101u);
        if (!grey)
            fail_msg("grey4 in RGB565: pixel %u is %04X", i, (unsigned)p565[i]);
    }
    assert_int_equal(psc_io_levels_parse("mono:halftone", &l), 0);
    psc_io_levels_apply(&l, &s8888);
    for (unsigned i = 0; i < LW * LH; i++)
        assert_true((p8888[i] & 0xFFFFFFu) == 0 || (p8888[i] & 0xFFFFFFu) == 0xFFFFFFu);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grey_ramp_keeps_local_average),
        cmocka_unit_test(test_colour_cube_ramp),
        cmocka_unit_test(test_random_pixels),
        cmocka_unit_test(test_halftone_cell_grows_from_centre),
        cmocka_unit_test(test_levels_in_place),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
