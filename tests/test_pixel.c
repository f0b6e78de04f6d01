/* SPDX-License-Identifier: MIT */
/* test_pixel.c - core/base/psc_pixel.h conversions and the bilinear blend, exhaustively where possible. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>

#include "base/psc_pixel.h"
#include "psc_testsupport.h"

static void test_rgb565_expand_all(void **state)
{
    (void)state;
    for (uint32_t p = 0; p < 65536; p++) {
        uint32_t r5 = p >> 11, g6 = (p >> 5) & 63, b5 = p & 31;
        uint32_t want = 0xFF000000u | (((r5 << 3) | (r5 >> 2)) << 16) | (((g6 << 2) | (g6 >> 4)) << 8) |
                        ((b5 << 3) | (b5 >> 2));
        assert_int_equal(psc_rgb565_to_xrgb(p), want);
        /* expansion then reduction is the identity */
        assert_int_equal(psc_xrgb_to_rgb565(want), p);
    }
    assert_int_equal(psc_rgb565_to_xrgb(0x0000), 0xFF000000u);
    assert_int_equal(psc_rgb565_to_xrgb(0xFFFF), 0xFFFFFFFFu);
}

static void test_rgb565_reduce_all(void **state)
{
    (void)state;
    /* Each channel alone over 0..255 against round(v * levels / 255) in integers
     * (no ties exist: 2*v*31 and 2*v*63 are never odd multiples of 255). */
    for (uint32_t v = 0; v < 256; v++) {
        uint32_t r5 = (2 * v * 31 + 255) / 510, g6 = (2 * v * 63 + 255) / 510;
        assert_int_equal(psc_xrgb_to_rgb565(v << 16), r5 << 11);
        assert_int_equal(psc_xrgb_to_rgb565(v << 8), g6 << 5);
        assert_int_equal(psc_xrgb_to_rgb565(v), r5);
        assert_int_equal(psc_xrgb_to_rgb565(0xFF000000u | v), r5); /* X byte ignored */
    }
    /* Channels do not interfere. */
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 21);
    for (int k = 0; k < 100000; k++) {
        uint32_t p = tsup_rng_u32(&rng);
        uint32_t r = (p >> 16) & 255, g = (p >> 8) & 255, b = p & 255;
        uint32_t want = (((2 * r * 31 + 255) / 510) << 11) | (((2 * g * 63 + 255) / 510) << 5) | ((2 * b * 31 + 255) / 510);
        assert_int_equal(psc_xrgb_to_rgb565(p), want);
    }
}

static uint32_t ref_blend(uint32_t p00, uint32_t p01, uint32_t p10, uint32_t p11, uint32_t fx, uint32_t fy)
{
    uint32_t out = 0xFF000000u;
    for (int sh = 0; sh <= 16; sh += 8) {
        uint64_t a = (p00 >> sh) & 255, b = (p01 >> sh) & 255, c = (p10 >> sh) & 255, d = (p11 >> sh) & 255;
        uint64_t top = a * (256 - fx) + b * fx, bot = c * (256 - fx) + d * fx;
        out |= (uint32_t)((top * (256 - fy) + bot * fy + 32768) >> 16) << sh;
    }
    return out;
}

static void test_blend4(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 22);
    static const uint32_t corners[] = {0x00000000u, 0xFFFFFFFFu, 0x00FF00FFu, 0xFF00FF00u, 0x00808080u, 0x007F7F7Fu};
    for (size_t a = 0; a < 6; a++)
        for (size_t b = 0; b < 6; b++)
            for (uint32_t fx = 0; fx <= 256; fx += 32)
                for (uint32_t fy = 0; fy <= 256; fy += 32) {
                    uint32_t got = psc_blend4_xrgb(corners[a], corners[b], corners[b], corners[a], fx, fy);
                    assert_int_equal(got, ref_blend(corners[a], corners[b], corners[b], corners[a], fx, fy));
                }
    for (int k = 0; k < 1000000; k++) {
        uint32_t p[4];
        for (int i = 0; i < 4; i++)
            p[i] = tsup_rng_u32(&rng);
        uint32_t fx = tsup_rng_below(&rng, 257), fy = tsup_rng_below(&rng, 257);
        uint32_t got = psc_blend4_xrgb(p[0], p[1], p[2], p[3], fx, fy);
        uint32_t want = ref_blend(p[0], p[1], p[2], p[3], fx, fy);
        if (got != want)
            fail_msg("psc_blend4_xrgb(%08x %08x %08x %08x, %u, %u) = %08x, expected %08x", p[0], p[1], p[2], p[3],
                     fx, fy, got, want);
    }
    /* Weights at the ends select a texel exactly. */
    assert_int_equal(psc_blend4_xrgb(0x123456, 0xABCDEF, 0x000000, 0xFFFFFF, 0, 0), 0xFF123456u);
    assert_int_equal(psc_blend4_xrgb(0x123456, 0xABCDEF, 0x000000, 0xFFFFFF, 256, 0), 0xFFABCDEFu);
    assert_int_equal(psc_blend4_xrgb(0x123456, 0xABCDEF, 0x000000, 0xFFFFFF, 256, 256), 0xFFFFFFFFu);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rgb565_expand_all),
        cmocka_unit_test(test_rgb565_reduce_all),
        cmocka_unit_test(test_blend4),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
