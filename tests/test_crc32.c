/* SPDX-License-Identifier: MIT */
/* test_crc32.c - psc_crc32 against zlib's crc32 (CRC-32/ISO-HDLC). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>

#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "base/psc_crc32.h"
#include "psc_testsupport.h"

static void test_check_value(void **state)
{
    (void)state;
    assert_int_equal(psc_crc32(0, "123456789", 9), 0xCBF43926u);
    assert_int_equal(psc_crc32(0, "", 0), 0u);
    assert_int_equal(psc_crc32(0, NULL, 0), 0u);
    assert_int_equal(psc_crc32(0x12345678u, NULL, 0), 0x12345678u); /* empty continuation is the identity */
    assert_int_equal(psc_crc32(0, "a", 1), 0xE8B7BE43u);
    /* 32 zero bytes and 32 0xFF bytes (catalogue values of CRC-32/ISO-HDLC) */
    uint8_t z[32], f[32];
    memset(z, 0, sizeof(z));
    memset(f, 0xFF, sizeof(f));
    assert_int_equal(psc_crc32(0, z, 32), 0x190A55ADu);
    assert_int_equal(psc_crc32(0, f, 32), 0xFF6CAB0Bu);
}

static void test_matches_zlib(void **state)
{
    (void)state;
    enum { MAXLEN = 4200 };
    uint8_t *buf = malloc(MAXLEN + 8);
    assert_non_null(buf);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 7);
    for (size_t i = 0; i < MAXLEN + 8; i++)
        buf[i] = (uint8_t)tsup_rng_u32(&rng);
    /* Every length 0..1100 and a spread beyond, at every alignment 0..7. */
    for (size_t len = 0; len <= MAXLEN; len += len < 1100 ? 1 : 97) {
        for (size_t off = 0; off < 8; off++) {
            uint32_t want = (uint32_t)crc32(0L, buf + off, (uInt)len);
            uint32_t got = psc_crc32(0, buf + off, len);
            if (got != want)
                fail_msg("len %zu offset %zu: psc_crc32 0x%08x, zlib 0x%08x", len, off, got, want);
        }
    }
    free(buf);
}

static void test_split_points(void **state)
{
    (void)state;
    enum { LEN = 3000 };
    uint8_t *buf = malloc(LEN);
    assert_non_null(buf);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 8);
    for (size_t i = 0; i < LEN; i++)
        buf[i] = (uint8_t)tsup_rng_u32(&rng);
    uint32_t whole = (uint32_t)crc32(0L, buf, LEN);
    /* Two pieces at every split point; three pieces at random ones. */
    for (size_t cut = 0; cut <= LEN; cut++)
        assert_int_equal(psc_crc32(psc_crc32(0, buf, cut), buf + cut, LEN - cut), whole);
    for (int k = 0; k < 2000; k++) {
        size_t a = tsup_rng_below(&rng, LEN + 1), b = tsup_rng_below(&rng, LEN + 1);
        if (a > b) {
            size_t t = a;
            a = b;
            b = t;
        }
        uint32_t c = psc_crc32(0, buf, a);
        c = psc_crc32(c, buf + a, b - a);
        c = psc_crc32(c, buf + b, LEN - b);
        assert_int_equal(c, whole);
        /* continuing from an arbitrary start value agrees with zlib too */
        uint32_t seed = tsup_rng_u32(&rng);
        assert_int_equal(psc_crc32(seed, buf + a, b - a), (uint32_t)crc32(seed, buf + a, (uInt)(b - a)));
    }
    free(buf);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_check_value),
        cmocka_unit_test(test_matches_zlib),
        cmocka_unit_test(test_split_points),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
