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
 *    that touch each other, the first at the centre;
 *  - RGB565 (psc_dither_row_rgb565): every 8-bit value against every threshold
 *    shows one of the two RGB565 levels around it, the 64 cells average to it
 *    within 1/128 of a step, each of the 65 536 RGB565 colours comes back
 *    unchanged in every cell, "none" is psc_xrgb_to_rgb565 byte for byte, and
 *    the pattern is fixed to the screen (x0);
 *  - RGB565 banding, the metric issue 17 quotes: a smooth 8-bit sky gradient
 *    and a slow grey ramp shown as RGB565 with and without the dither; the
 *    error against the 8-bit picture (in double) low-passed by a Gaussian of
 *    sigma 1.5 px, about what the eye integrates at viewing distance: its RMS
 *    must be at least 2x lower dithered, the largest jump of the low-passed
 *    luma between neighbouring pixels (the visible band edge) and of the
 *    low-passed luma error each at least 2x lower, and the mean colour kept
 *    within 0.25 of an 8-bit unit.
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
#include "measure/banding.h"

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

/* ---- RGB565 ---------------------------------------------------------------------------------------------- */

/* The RGB565 level k of a channel bits wide as the display shows it (bit replication). */
static uint32_t e565(uint32_t k, unsigned bits)
{
    return k << (8u - bits) | k >> (2u * bits - 8u);
}

static void test_rgb565_levels(void **state)
{
    (void)state;
    static psc_dither_565_t t;
    psc_dither_565_init(&t);
    /* one channel at a time in a grey-free pixel: every value against all 64 cells (8 x 8 positions) */
    for (unsigned ch = 0; ch < 3; ch++) {
        unsigned bits = ch == 1 ? 6u : 5u, shift = ch == 0 ? 11u : ch == 1 ? 5u : 0u;
        uint32_t top = (1u << bits) - 1u;
        for (uint32_t v = 0; v < 256; v++) {
            uint32_t k = 0;
            while (k < top && e565(k + 1u, bits) <= v)
                k++;
            uint32_t src[8], sum = 0;
            uint16_t dst[8];
            for (unsigned x = 0; x < 8; x++)
                src[x] = v << (16u - 8u * ch);
            for (unsigned y = 0; y < 8; y++) {
                psc_dither_row_rgb565(&t, PSC_DITHER_ORDERED, src, 8, 0, y, dst);
                for (unsigned x = 0; x < 8; x++) {
                    uint32_t q = (dst[x] >> shift) & top;
                    if (q != k && q != k + 1u)
                        fail_msg("channel %u value %u cell (%u,%u): level %u, not %u or %u", ch, v, x, y, q, k, k + 1u);
                    if (v == e565(k, bits) && q != k)
                        fail_msg("channel %u: the display's own level %u (value %u) changed to %u", ch, k, v, q);
                    sum += q - k;
                }
            }
            /* the 64 cells' mean, in steps above k, against (v - E(k)) / d: within 1/128 */
            if (k < top) {
                double want = (double)(v - e565(k, bits)) / (double)(e565(k + 1u, bits) - e565(k, bits));
                assert_true(fabs((double)sum / 64.0 - want) <= 1.0 / 128.0 + 1e-12);
            }
        }
    }
    /* every RGB565 colour drawn again stays itself, at every position; none is today's rounding */
    static uint32_t row[65536];
    static uint16_t out[65536];
    for (uint32_t p = 0; p < 65536; p++)
        row[p] = psc_rgb565_to_xrgb(p);
    for (unsigned y = 0; y < 8; y++) {
        psc_dither_row_rgb565(&t, PSC_DITHER_ORDERED, row, 65536, y * 3u, y, out);
        for (uint32_t p = 0; p < 65536; p++)
            if (out[p] != p)
                fail_msg("RGB565 %04X drawn again at (%u,%u) became %04X", p, p, y, out[p]);
    }
    tsup_rng_t r;
    tsup_rng_seed(&r, 565);
    for (uint32_t i = 0; i < 65536; i++)
        row[i] = tsup_rng_u32(&r);
    psc_dither_row_rgb565(&t, PSC_DITHER_NONE, row, 65536, 5, 3, out);
    for (uint32_t i = 0; i < 65536; i++)
        assert_int_equal(out[i], psc_xrgb_to_rgb565(row[i]));
    /* x0 places the row on the screen: a row drawn from column 3 is the tail of the row drawn from 0 */
    static uint16_t whole[64];
    for (unsigned y = 0; y < 16; y++) {
        psc_dither_row_rgb565(&t, PSC_DITHER_ORDERED, row, 64, 0, y, whole);
        psc_dither_row_rgb565(&t, PSC_DITHER_ORDERED, row + 3, 61, 3, y, out);
        assert_memory_equal(out, whole + 3, 61 * sizeof out[0]);
        /* halftone is taken as ordered */
        psc_dither_row_rgb565(&t, PSC_DITHER_HALFTONE, row, 64, 0, y, out);
        assert_memory_equal(out, whole, 64 * sizeof out[0]);
    }
}

#define SW 320u
#define SH 240u
static void test_rgb565_banding(void **state)
{
    (void)state;
    static psc_dither_565_t t;
    static uint32_t pic[SW * SH];
    static uint16_t none[SW * SH], ordered[SW * SH];
    psc_dither_565_init(&t);
    for (unsigned kind = 0; kind < 2; kind++) {
        /* 0: a clear sky, darker blue at the top of the screen to pale at the horizon (each channel a few RGB565
         *    steps over the screen's height) with a slight drift across it;
         * 1: a slow grey ramp, 8-bit values 100..131 left to right (four red/blue, eight green RGB565 steps) */
        for (unsigned y = 0; y < SH; y++)
            for (unsigned x = 0; x < SW; x++) {
                double rgb[3], v = (double)y / (double)(SH - 1u), u = (double)x / (double)(SW - 1u);
                if (kind == 0) {
                    rgb[0] = 78.0 + 34.0 * v + 5.0 * u;
                    rgb[1] = 128.0 + 40.0 * v + 3.0 * u;
                    rgb[2] = 196.0 + 30.0 * v;
                } else {
                    rgb[0] = rgb[1] = rgb[2] = 100.0 + 31.0 * u;
                }
                uint32_t p = 0xFF000000u;
                for (unsigned c = 0; c < 3; c++)
                    p |= (uint32_t)lround(rgb[c]) << (16u - 8u * c);
                pic[y * SW + x] = p;
            }
        for (unsigned y = 0; y < SH; y++) {
            psc_dither_row_rgb565(&t, PSC_DITHER_NONE, pic + y * SW, SW, 0, y, none + y * SW);
            psc_dither_row_rgb565(&t, PSC_DITHER_ORDERED, pic + y * SW, SW, 0, y, ordered + y * SW);
        }
        psc_measure_banding_t a, b;
        assert_int_equal(psc_measure_banding(pic, none, SW, SH, &a), 0);
        assert_int_equal(psc_measure_banding(pic, ordered, SW, SH, &b), 0);
        double own = psc_measure_banding_step(pic, SW, SH);
        print_message("  RGB565 banding, %s %ux%u (error against the 8-bit picture, Gaussian sigma %.1f px):\n"
                      "    low-passed RMS error: none %.3f, ordered %.3f (%.1fx lower)\n"
                      "    largest low-passed luma step: none %.3f, ordered %.3f (the picture's own %.3f)\n"
                      "    largest step of the low-passed luma error: none %.3f, ordered %.3f\n"
                      "    mean error R/G/B: none %+.3f %+.3f %+.3f, ordered %+.3f %+.3f %+.3f\n",
                      kind == 0 ? "sky gradient" : "grey ramp", SW, SH, PSC_MEASURE_BANDING_SIGMA, a.rms, b.rms, a.rms / b.rms, a.step,
                      b.step, own, a.estep, b.estep, a.bias[0], a.bias[1], a.bias[2], b.bias[0], b.bias[1], b.bias[2]);
        assert_true(b.rms * 2.0 <= a.rms);
        assert_true(b.step * 2.0 <= a.step);
        assert_true(b.estep * 2.0 <= a.estep);
        for (unsigned c = 0; c < 3; c++)
            assert_true(fabs(b.bias[c]) <= 0.25);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grey_ramp_keeps_local_average),
        cmocka_unit_test(test_colour_cube_ramp),
        cmocka_unit_test(test_random_pixels),
        cmocka_unit_test(test_halftone_cell_grows_from_centre),
        cmocka_unit_test(test_levels_in_place),
        cmocka_unit_test(test_rgb565_levels),
        cmocka_unit_test(test_rgb565_banding),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
