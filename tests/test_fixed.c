/* SPDX-License-Identifier: MIT */
/*
 * test_fixed.c - core/base/psc_fixed.h and the binary-angle macro of psc_types.h
 * against independent references (exact integer arithmetic, or libm in
 * double where the function approximates a transcendental).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "base/psc_fixed.h"
#include "base/psc_oct.h"
#include "raster/psc_raster.h"
#include "psc_testsupport.h"

__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;

/* ---- rounding shifts and Q16.16 product (inline helpers) --------------------- */

/* floor(v / 2^s + 1/2) exactly: ties toward +inf. */
static int64_t ref_shr_round(i128 v, unsigned s)
{
    i128 den = (i128)1 << s;
    i128 n = 2 * v + den; /* floor((2v + 2^s) / 2^(s+1)) */
    i128 d = 2 * den;
    i128 q = n / d;
    if ((n % d != 0) && (n < 0))
        q--;
    return (int64_t)q;
}

static void test_shr_round(void **state)
{
    (void)state;
    assert_int_equal(psc_shr_round64(3, 1), 2);   /* 1.5 -> 2 */
    assert_int_equal(psc_shr_round64(-3, 1), -1); /* -1.5 -> -1: ties toward +inf */
    assert_int_equal(psc_shr_round64(-5, 1), -2);
    assert_int_equal(psc_shr_round64(5, 2), 1);   /* 1.25 */
    assert_int_equal(psc_shr_round64(-6, 2), -1); /* -1.5 -> -1 */
    assert_int_equal(psc_shr_round32(0x7FFF, 16), 0);
    assert_int_equal(psc_shr_round32(0x8000, 16), 1);
    assert_int_equal(psc_shr_round32(-0x8000, 16), 0);
    assert_int_equal(psc_shr_round32(-0x8001, 16), -1);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 11);
    for (int k = 0; k < 200000; k++) {
        unsigned s = 1 + tsup_rng_below(&rng, 62);
        int64_t v = (int64_t)tsup_rng_u64(&rng) >> tsup_rng_below(&rng, 8); /* keep v + 2^(s-1) in range */
        if (v > INT64_MAX - ((int64_t)1 << (s - 1)))
            continue;
        int64_t got = psc_shr_round64(v, s);
        if (got != ref_shr_round(v, s))
            fail_msg("psc_shr_round64(%lld, %u) = %lld, expected %lld", (long long)v, s, (long long)got,
                     (long long)ref_shr_round(v, s));
        unsigned s32 = 1 + tsup_rng_below(&rng, 30);
        int32_t v32 = (int32_t)tsup_rng_u32(&rng);
        int32_t g32 = psc_shr_round32(v32, s32);
        if (g32 != ref_shr_round(v32, s32))
            fail_msg("psc_shr_round32(%d, %u) = %d, expected %lld", v32, s32, g32,
                     (long long)ref_shr_round(v32, s32));
    }
}

static void test_mul_q16(void **state)
{
    (void)state;
    assert_int_equal(psc_mul_q16(PSC_Q16_ONE, PSC_Q16_ONE), PSC_Q16_ONE);
    assert_int_equal(psc_mul_q16(3 * PSC_Q16_ONE / 2, -2 * PSC_Q16_ONE), -3 * PSC_Q16_ONE);
    assert_int_equal(psc_mul_q16(1, 0x8000), 1);  /* 0.5 unit -> 1 (ties up) */
    assert_int_equal(psc_mul_q16(-1, 0x8000), 0); /* -0.5 unit -> 0 (ties toward +inf) */
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 12);
    for (int k = 0; k < 200000; k++) {
        int32_t a = (int32_t)tsup_rng_u32(&rng) >> tsup_rng_below(&rng, 16);
        int32_t b = (int32_t)tsup_rng_u32(&rng) >> tsup_rng_below(&rng, 16);
        i128 p = (i128)a * b;
        if (p >= ((i128)1 << 47) || p <= -((i128)1 << 47))
            continue; /* outside the documented overflow-free range */
        assert_int_equal(psc_mul_q16(a, b), ref_shr_round(p, 16));
    }
}

/* ---- integer square root ------------------------------------------------------ */

static void check_isqrt(uint64_t v)
{
    uint64_t r = psc_isqrt64(v);
    /* r = floor(sqrt(v)) <=> r^2 <= v < (r+1)^2, checked in 128 bits. */
    i128 r2 = (i128)r * r, r12 = (i128)(r + 1) * (r + 1);
    if (!(r2 <= (i128)v && (i128)v < r12))
        fail_msg("psc_isqrt64(%llu) = %llu", (unsigned long long)v, (unsigned long long)r);
}

static void test_isqrt_exhaustive_small(void **state)
{
    (void)state;
    /* Every value 0..2^20, compared with a running reference root. */
    uint32_t root = 0;
    for (uint64_t v = 0; v <= (1u << 20); v++) {
        while ((uint64_t)(root + 1) * (root + 1) <= v)
            root++;
        if (psc_isqrt64(v) != root)
            fail_msg("psc_isqrt64(%llu) = %u, expected %u", (unsigned long long)v, psc_isqrt64(v), root);
    }
}

static void test_isqrt_limits_and_random(void **state)
{
    (void)state;
    assert_int_equal(psc_isqrt64(0), 0);
    assert_int_equal(psc_isqrt64(1), 1);
    assert_int_equal(psc_isqrt64(UINT64_MAX), 0xFFFFFFFFu);
    assert_int_equal(psc_isqrt64(0xFFFFFFFE00000001ull), 0xFFFFFFFFu); /* (2^32-1)^2 */
    assert_int_equal(psc_isqrt64(0xFFFFFFFE00000000ull), 0xFFFFFFFEu); /* one less */
    assert_int_equal(psc_isqrt64((uint64_t)1 << 62), 1u << 31);
    assert_int_equal(psc_isqrt64(((uint64_t)1 << 62) - 1), (1u << 31) - 1);
    assert_int_equal(psc_isqrt64((uint64_t)1 << 63), 3037000499u);
    for (uint64_t k = 0xFFFFFF00u; k <= 0xFFFFFFFFu; k++) {
        check_isqrt(k * k);
        check_isqrt(k * k - 1);
        check_isqrt(k * k + 2 * k); /* (k+1)^2 - 1 without overflow */
    }
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 1);
    for (int i = 0; i < 300000; i++) {
        uint64_t v = tsup_rng_u64(&rng);
        check_isqrt(v);
        check_isqrt(v >> tsup_rng_below(&rng, 64));
        uint64_t k = tsup_rng_u32(&rng) >> tsup_rng_below(&rng, 32);
        check_isqrt(k * k);
        if (k)
            check_isqrt(k * k - 1);
    }
}

/* ---- reciprocal square root ------------------------------------------------------ */

/* psc_rsqrt_q30 within 2^-16 of 2^30 / sqrt(x) (relative) plus its final rounding, over every power of two, the
 * table's step boundaries and a million random values; the Newton step matters (the table alone is 2^-9 off). */
static void check_rsqrt(uint32_t x, double *worst)
{
    double want = 1073741824.0 / sqrt((double)x), got = psc_rsqrt_q30(x);
    double err = fabs(got - want) - 0.5;
    double rel = err > 0 ? err / want : 0;
    if (rel > *worst)
        *worst = rel;
    if (rel > 1.0 / 65536)
        fail_msg("psc_rsqrt_q30(%u) = %.0f, expected %.3f", x, got, want);
}

static void test_rsqrt(void **state)
{
    (void)state;
    double worst = 0;
    assert_int_equal(psc_rsqrt_q30(0), UINT32_MAX);
    check_rsqrt(1, &worst);
    check_rsqrt(4, &worst);
    check_rsqrt(1u << 28, &worst);
    for (unsigned e = 0; e < 32; e++)
        for (uint32_t m = 64; m < 256; m++) {
            uint64_t v = e >= 7 ? (uint64_t)m << (e - 7) : m >> (7 - e);
            if (v == 0 || v > UINT32_MAX)
                continue;
            check_rsqrt((uint32_t)v, &worst);
            if (v > 1)
                check_rsqrt((uint32_t)v - 1u, &worst);
        }
    check_rsqrt(UINT32_MAX, &worst);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 7);
    for (int i = 0; i < 1000000; i++) {
        uint32_t v = tsup_rng_u32(&rng) >> tsup_rng_below(&rng, 32);
        if (v)
            check_rsqrt(v, &worst);
    }
    print_message("  worst relative error beyond the rounding: %.2e (bound 2^-16 = %.2e)\n", worst, 1.0 / 65536);
    /* psc_rsqrt46 over the whole 64-bit range (the shadows' normalising) */
    double worst46 = 0;
    assert_true(psc_rsqrt46(0) == UINT64_MAX);
    for (int i = 0; i < 1000000; i++) {
        uint64_t v = tsup_rng_u64(&rng) >> tsup_rng_below(&rng, 64);
        if (v == 0)
            continue;
        long double want = 70368744177664.0L / sqrtl((long double)v), got = (long double)psc_rsqrt46(v);
        double rel = (double)(fabsl(got - want) - 0.5L) / (double)want;
        worst46 = rel > worst46 ? rel : worst46;
        if (rel > 1.0 / 65536)
            fail_msg("psc_rsqrt46(%llu) = %.0Lf, expected %.3Lf", (unsigned long long)v, got, want);
    }
    print_message("  psc_rsqrt46 over 64-bit values: worst relative error %.2e\n", worst46);
}

/* psc_unit3_q16 against the double-precision direction: random vectors of every magnitude up to the 64-bit
 * limits (INT64_MIN included), each component within 1.5 units of Q16.16 (the scaling's dropped bits and rsqrt46's
 * 2^-16 together), zero kept zero. */
static void test_unit3(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 33);
    int32_t out[3];
    const int64_t zero[3] = {0, 0, 0};
    psc_unit3_q16(zero, out);
    assert_true(out[0] == 0 && out[1] == 0 && out[2] == 0);
    double worst = 0;
    for (int i = 0; i < 300000; i++) {
        int64_t v[3];
        unsigned bits = 1 + tsup_rng_below(&rng, 63);
        for (unsigned a = 0; a < 3; a++) {
            uint64_t m = tsup_rng_u64(&rng) >> (64 - bits);
            v[a] = tsup_rng_below(&rng, 2) ? -(int64_t)(m >> 1) : (int64_t)(m >> 1);
        }
        if (i < 8)   /* the limits */
            v[i % 3] = i < 4 ? INT64_MIN : INT64_MAX;
        long double len = sqrtl((long double)v[0] * v[0] + (long double)v[1] * v[1] + (long double)v[2] * v[2]);
        if (len == 0)
            continue;
        psc_unit3_q16(v, out);
        for (unsigned a = 0; a < 3; a++) {
            double err = fabs((double)((long double)v[a] / len * 65536.0L) - out[a]);
            worst = err > worst ? err : worst;
            if (err > 1.5)
                fail_msg("psc_unit3_q16(%lld, %lld, %lld)[%u] = %d", (long long)v[0], (long long)v[1],
                         (long long)v[2], a, out[a]);
        }
    }
    print_message("  psc_unit3_q16: worst component error %.2f units of Q16.16\n", worst);
}

/* psc_mul_rcp62 against a 128-bit product, rounded half away from zero. */
static void test_mul_rcp62(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 62);
    for (int i = 0; i < 1000000; i++) {
        int64_t n = (int64_t)(tsup_rng_u64(&rng) >> (1 + tsup_rng_below(&rng, 63)));
        if (i & 1)
            n = -n;
        uint64_t r = tsup_rng_u64(&rng) >> (2 + tsup_rng_below(&rng, 62));
        u128 p = (u128)(n < 0 ? -(u128)n : (u128)n) * r;
        u128 q = (p + ((u128)1 << 61)) >> 62;
        if (q > (u128)INT64_MAX)
            continue; /* outside the documented range */
        int64_t want = n < 0 ? -(int64_t)q : (int64_t)q;
        if (psc_mul_rcp62(n, r) != want)
            fail_msg("psc_mul_rcp62(%lld, %llu) = %lld, expected %lld", (long long)n, (unsigned long long)r,
                     (long long)psc_mul_rcp62(n, r), (long long)want);
    }
    assert_int_equal(psc_mul_rcp62(INT64_MAX, UINT64_C(1) << 62), INT64_MAX);
    assert_int_equal(psc_mul_rcp62(-INT64_MAX, UINT64_C(1) << 62), -INT64_MAX);
    assert_int_equal(psc_mul_rcp62(3, UINT64_C(1) << 61), 2);   /* 1.5 rounds away from zero */
    assert_int_equal(psc_mul_rcp62(-3, UINT64_C(1) << 61), -2);
}

/* ---- rounded division -------------------------------------------------------- */

static int64_t ref_div_round(int64_t n, int64_t d)
{
    i128 N = n, D = d;
    i128 q = N / D, r = N % D; /* truncating */
    i128 ar = r < 0 ? -r : r, ad = D < 0 ? -D : D;
    if (2 * ar >= ad)
        q += ((N < 0) != (D < 0)) ? -1 : 1;
    return (int64_t)q;
}

static void test_div_round(void **state)
{
    (void)state;
    static const struct {
        int64_t n, d, q;
    } cases[] = {
        {5, 2, 3},   {-5, 2, -3},  {5, -2, -3}, {-5, -2, 3}, {1, 2, 1}, {-1, 2, -1}, {3, 2, 2},
        {7, 2, 4},   {1, 3, 0},    {-1, 3, 0},  {2, 3, 1},   {-2, 3, -1}, {0, 7, 0}, {0, -7, 0},
        {6, 4, 2},   {-6, 4, -2},  {5, 4, 1},   {-5, 4, -1},
        {INT64_MAX, 1, INT64_MAX}, {INT64_MIN, 1, INT64_MIN}, {INT64_MAX, -1, -INT64_MAX},
        {INT64_MIN + 1, -1, INT64_MAX}, {INT64_MIN, 2, INT64_MIN / 2}, {INT64_MIN, -2, -(INT64_MIN / 2)},
        {INT64_MAX, 2, (int64_t)1 << 62}, {-INT64_MAX, 2, -((int64_t)1 << 62)},
        {INT64_MAX, INT64_MAX, 1}, {INT64_MIN, INT64_MIN, 1}, {INT64_MIN, INT64_MAX, -1},
        {INT64_MAX, INT64_MIN, -1}, {INT64_MIN, 3, -3074457345618258603LL},
        {INT64_MAX, 3, 3074457345618258602LL}, {1, INT64_MIN, 0}, {-1, INT64_MAX, 0},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        int64_t got = psc_div_round64(cases[i].n, cases[i].d);
        if (got != cases[i].q || got != ref_div_round(cases[i].n, cases[i].d))
            fail_msg("psc_div_round64(%lld, %lld) = %lld, expected %lld", (long long)cases[i].n,
                     (long long)cases[i].d, (long long)got, (long long)cases[i].q);
    }
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 2);
    for (int i = 0; i < 500000; i++) {
        int64_t n = (int64_t)tsup_rng_u64(&rng) >> tsup_rng_below(&rng, 63);
        int64_t d = (int64_t)tsup_rng_u64(&rng) >> tsup_rng_below(&rng, 63);
        if (i % 4 == 0) { /* exact ties: n = (2k+1) * d/2 with d even */
            int64_t half = (d >> 33) != 0 ? (d >> 33) : 1;
            d = 2 * half;
            n = ((int64_t)(tsup_rng_u32(&rng) >> 2) * 2 - INT32_MAX) * half;
        }
        if (d == 0 || (n == INT64_MIN && d == -1))
            continue; /* d == 0 is outside the contract; INT64_MIN / -1 is not representable */
        int64_t got = psc_div_round64(n, d), want = ref_div_round(n, d);
        if (got != want)
            fail_msg("psc_div_round64(%lld, %lld) = %lld, expected %lld", (long long)n, (long long)d,
                     (long long)got, (long long)want);
    }
    /* Ties with every sign combination. */
    for (int64_t k = -1000; k <= 1000; k++) {
        for (int64_t d = 2; d <= 64; d += 2) {
            int64_t n = (2 * k + 1) * (d / 2);
            assert_int_equal(psc_div_round64(n, d), ref_div_round(n, d));
            assert_int_equal(psc_div_round64(n, -d), ref_div_round(n, -d));
        }
    }
}

/* ---- sine and cosine ------------------------------------------------------------- */

#define SINCOS_BOUND 2.0 /* psc_fixed.h: |error| <= 2 units of 2^-30 */

static double g_sincos_max;

static void check_sincos(psc_bam_t a)
{
    int32_t s, c;
    psc_sincos(a, &s, &c);
    double ang = (double)a / 4294967296.0 * 2.0 * TSUP_PI;
    double es = fabs(s - sin(ang) * 1073741824.0), ec = fabs(c - cos(ang) * 1073741824.0);
    if (es > g_sincos_max)
        g_sincos_max = es;
    if (ec > g_sincos_max)
        g_sincos_max = ec;
    if (es > SINCOS_BOUND || ec > SINCOS_BOUND)
        fail_msg("psc_sincos(0x%08x): sin %d (exact %.3f), cos %d (exact %.3f)", a, s, sin(ang) * 1073741824.0, c,
                 cos(ang) * 1073741824.0);
}

static void test_sincos(void **state)
{
    (void)state;
    g_sincos_max = 0.0;
    for (uint32_t k = 0; k < 65536; k++)
        check_sincos(k << 16);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 3);
    for (int i = 0; i < 1000000; i++)
        check_sincos(tsup_rng_u32(&rng));
    /* Around the quadrant boundaries, where the quadrant reduction switches. */
    for (uint32_t q = 0; q < 4; q++)
        for (int32_t e = -300; e <= 300; e++) {
            check_sincos(q * PSC_BAM_90 + (uint32_t)e);
            check_sincos(q * PSC_BAM_90 + (uint32_t)(e * 65536));
        }
    printf("  psc_sincos: max |error| %.3f units of 2^-30 (bound %.0f) over 65536 + 1000000 + 4808 angles\n",
           g_sincos_max, SINCOS_BOUND);

    /* Either output may be NULL. */
    int32_t s = 123, c = 456, s2, c2;
    psc_sincos(PSC_BAM_FROM_MDEG(30000), &s2, &c2);
    psc_sincos(PSC_BAM_FROM_MDEG(30000), &s, NULL);
    psc_sincos(PSC_BAM_FROM_MDEG(30000), NULL, &c);
    psc_sincos(PSC_BAM_FROM_MDEG(30000), NULL, NULL);
    assert_int_equal(s, s2);
    assert_int_equal(c, c2);
    assert_true(abs(s - (1 << 29)) <= 2); /* sin 30 = 0.5 */
}

/* ---- atan2 and magnitude --------------------------------------------------------- */

/*
 * psc_fixed.h states "|error| <= 2^-28 turn" (16 units); the CORDIC in
 * psc_fixed.c keeps 16 guard bits over 40 iterations, so the tests hold it to
 * 1 unit (2^-32 turn; "far under one unit" of residual angle) and reports the
 * measured maximum.
 */
#define ATAN2_BOUND 1.0

static double g_atan_max;
static long g_mag_off;

static uint64_t ref_round_sqrt(uint64_t s)
{
    uint64_t r = (uint64_t)sqrt((double)s);
    while ((i128)r * r > (i128)s)
        r--;
    while ((i128)(r + 1) * (r + 1) <= (i128)s)
        r++;
    /* sqrt(s) >= r + 1/2 <=> s >= r^2 + r + 1/4 <=> s - r^2 > r (integers) */
    return (s - r * r > r) ? r + 1 : r;
}

static int g_check_mag;

static void check_atan2(int32_t y, int32_t x)
{
    uint32_t mag = 0xDEADBEEFu;
    psc_bam_t got = psc_atan2(y, x, &mag);
    assert_int_equal(psc_atan2(y, x, NULL), got);
    if (x == 0 && y == 0) {
        assert_int_equal(got, 0);
        assert_int_equal(mag, 0);
        return;
    }
    if (g_check_mag) {
        /* psc_fixed.h: mag = sqrt(x^2 + y^2), rounded (to nearest). */
        uint64_t s = (uint64_t)((int64_t)x * x) + (uint64_t)((int64_t)y * y);
        uint64_t want = ref_round_sqrt(s);
        long off = (long)((int64_t)mag - (int64_t)want);
        if (labs(off) > g_mag_off)
            g_mag_off = labs(off);
        if (mag != want)
            fail_msg("psc_atan2(%d, %d): mag %u, expected round(sqrt(%llu)) = %llu (exact %.4f)", y, x, mag,
                     (unsigned long long)s, (unsigned long long)want, sqrt((double)s));
        return;
    }
    double ref = atan2((double)y, (double)x) / (2.0 * TSUP_PI) * 4294967296.0; /* (-2^31, 2^31] */
    double err = fmod((double)got - ref + 1.5 * 4294967296.0, 4294967296.0) - 0.5 * 4294967296.0;
    if (fabs(err) > g_atan_max)
        g_atan_max = fabs(err);
    if (fabs(err) > ATAN2_BOUND)
        fail_msg("psc_atan2(%d, %d) = 0x%08x, exact %.3f units (error %.3f)", y, x, got, ref, err);
}

static const int32_t extreme_values[] = {0, 1, -1, 2, -2, 3, 1000, -1000, 46341, -46341, 65536, INT32_MAX, INT32_MIN,
                                         INT32_MAX - 1, INT32_MIN + 1, 1 << 30, -(1 << 30), 0x55555555, -0x55555555};

static void run_atan2_inputs(void)
{
    size_t n = sizeof(extreme_values) / sizeof(extreme_values[0]);
    for (size_t i = 0; i < n; i++)
        for (size_t j = 0; j < n; j++)
            check_atan2(extreme_values[i], extreme_values[j]);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 4);
    for (int i = 0; i < 1000000; i++) {
        unsigned sh = tsup_rng_below(&rng, 32);
        int32_t y = (int32_t)tsup_rng_u32(&rng) >> sh;
        int32_t x = (int32_t)tsup_rng_u32(&rng) >> (i & 1 ? sh : tsup_rng_below(&rng, 32));
        check_atan2(y, x);
    }
    /* Angles just off the axes and diagonals. */
    for (int32_t e = -50; e <= 50; e++) {
        check_atan2(e, INT32_MAX);
        check_atan2(INT32_MAX, e);
        check_atan2(e, INT32_MIN);
        check_atan2(INT32_MIN, e);
        check_atan2(1000000 + e, 1000000);
        check_atan2(-1000000 - e, 1000000);
    }
}

static void test_atan2_angle(void **state)
{
    (void)state;
    g_atan_max = 0.0;
    g_check_mag = 0;
    assert_int_equal(psc_atan2(0, 0, NULL), 0);
    assert_int_equal(psc_atan2(0, 1, NULL), 0);
    assert_int_equal(psc_atan2(0, INT32_MAX, NULL), 0);
    assert_int_equal(psc_atan2(0, -1, NULL), PSC_BAM_180);
    assert_int_equal(psc_atan2(0, INT32_MIN, NULL), PSC_BAM_180);
    /* The axes and diagonals land within the bound of the exact eighth turns. */
    assert_true(abs((int32_t)(psc_atan2(INT32_MIN, 0, NULL) - 0xC0000000u)) <= ATAN2_BOUND);
    assert_true(abs((int32_t)(psc_atan2(1, 0, NULL) - PSC_BAM_90)) <= ATAN2_BOUND);
    assert_true(abs((int32_t)(psc_atan2(INT32_MIN, INT32_MIN, NULL) - 0xA0000000u)) <= ATAN2_BOUND);
    run_atan2_inputs();
    printf("  psc_atan2: max |angle error| %.3f units of 2^-32 turn (bound %.0f) over %d inputs\n", g_atan_max,
           ATAN2_BOUND, 19 * 19 + 1000000 + 606);
}

static void test_atan2_magnitude(void **state)
{
    (void)state;
    g_mag_off = 0;
    g_check_mag = 1;
    uint32_t mag;
    psc_atan2(0, INT32_MIN, &mag);
    assert_int_equal(mag, 2147483648u); /* exactly 2^31 */
    psc_atan2(INT32_MIN, INT32_MIN, &mag);
    assert_int_equal(mag, 3037000500u); /* round(2^31 sqrt 2) = round(3037000499.98) */
    psc_atan2(3, 4, &mag);
    assert_int_equal(mag, 5u);
    run_atan2_inputs();
    g_check_mag = 0;
}

/* ---- PSC_BAM_FROM_MDEG ------------------------------------------------------------- */

static psc_bam_t ref_bam_from_mdeg(int64_t md)
{
    i128 n = (i128)md * ((i128)1 << 32);
    i128 q = n / 360000, r = n % 360000;
    if (2 * (r < 0 ? -r : r) >= 360000)
        q += n < 0 ? -1 : 1;
    return (psc_bam_t)(uint64_t)(q & 0xFFFFFFFF);
}

static const psc_bam_t const_table[] = {PSC_BAM_FROM_MDEG(90000), PSC_BAM_FROM_MDEG(-90000)}; /* constant expressions */

static void test_bam_from_mdeg(void **state)
{
    (void)state;
    assert_int_equal(const_table[0], PSC_BAM_90);
    assert_int_equal(const_table[1], 0xC0000000u);
    assert_int_equal(PSC_BAM_FROM_MDEG(0), 0);
    assert_int_equal(PSC_BAM_FROM_MDEG(180000), PSC_BAM_180);
    assert_int_equal(PSC_BAM_FROM_MDEG(-180000), PSC_BAM_180);
    assert_int_equal(PSC_BAM_FROM_MDEG(360000), 0);
    assert_int_equal(PSC_BAM_FROM_MDEG(45000), 0x20000000u);
    assert_int_equal(PSC_BAM_FROM_MDEG(1), 11930u);           /* 11930.46 */
    assert_int_equal(PSC_BAM_FROM_MDEG(-1), (psc_bam_t)-11930); /* rounded symmetrically */
    assert_int_equal(PSC_BAM_FROM_MDEG(60000), 715827883u);   /* 715827882.67 */
    assert_int_equal(PSC_BAM_FROM_MDEG(-60000), (psc_bam_t)-715827883);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 5);
    for (int i = 0; i < 500000; i++) {
        int32_t md = (int32_t)tsup_rng_u32(&rng) >> tsup_rng_below(&rng, 24);
        psc_bam_t got = PSC_BAM_FROM_MDEG(md);
        if (got != ref_bam_from_mdeg(md))
            fail_msg("PSC_BAM_FROM_MDEG(%d) = %u, expected %u", md, got, ref_bam_from_mdeg(md));
        /* and within half a unit of the exact angle */
        double exact = fmod((double)md / 360000.0 * 4294967296.0, 4294967296.0);
        double err = fmod((double)got - exact + 1.5 * 4294967296.0, 4294967296.0) - 0.5 * 4294967296.0;
        assert_true(fabs(err) <= 0.5 + 1e-6);
    }
}

/* The octahedral normal code (psc_oct.h): every one of the 65 536 codes decodes onto the octahedron (|x| + |y| + |z|
 * = 16384 within rounding) and encodes back to a direction within 0.8 degrees; random unit vectors, the axes, the
 * fold's diagonals and the range's ends survive the round trip within 1 degree (8 bits a coordinate: the worst
 * measured 0.954, on the lower half's diagonal), and the zero vector is +z. */
static double angle_deg(const double a[3], const int32_t b[3])
{
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double lb = sqrt((double)b[0] * b[0] + (double)b[1] * b[1] + (double)b[2] * b[2]);
    double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
    return acos(fmin(1.0, fmax(-1.0, c))) * 180.0 / M_PI;
}

/* A random direction: a point of the unit ball at least min_len from the centre (rejection), scaled to unit length. */
static void random_direction(tsup_rng_t *r, double min_len, double v[3])
{
    double l;
    do {
        for (unsigned a = 0; a < 3; a++)
            v[a] = tsup_rng_below(r, 2000001) / 1e6 - 1.0;
        l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (l < min_len || l > 1);
    for (unsigned a = 0; a < 3; a++)
        v[a] /= l;
}

static void test_oct16(void **state)
{
    (void)state;
    for (uint32_t c = 0; c < 65536u; c++) {
        int32_t n[3], m[3];
        psc_oct16_decode((uint16_t)c, n);
        int32_t l1 = abs(n[0]) + abs(n[1]) + abs(n[2]);
        assert_true(l1 >= 16382 && l1 <= 16386);
        psc_oct16_decode(psc_oct16_encode(n), m);
        double d[3] = {n[0], n[1], n[2]};
        assert_true(angle_deg(d, m) < 0.8);
    }
    tsup_rng_t r;
    tsup_rng_seed(&r, 7);
    double worst = 0;
    for (unsigned k = 0; k < 200000; k++) {
        double v[3];
        random_direction(&r, 1e-3, v);
        int32_t q[3] = {(int32_t)lround(v[0] * 16384), (int32_t)lround(v[1] * 16384), (int32_t)lround(v[2] * 16384)},
                n[3];
        psc_oct16_decode(psc_oct16_encode(q), n);
        double e = angle_deg(v, n);
        worst = e > worst ? e : worst;
    }
    print_message("  octahedral code: worst round trip of 200 000 random directions %.3f degrees\n", worst);
    assert_true(worst < 1.0);
    static const double fixed[][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1},
                                      {1, 1, 0}, {-1, 1, 0}, {1, -1, 0}, {-1, -1, 0}, {1, 1, -1}, {-1, -1, -1}};
    for (unsigned k = 0; k < sizeof fixed / sizeof fixed[0]; k++) {
        int32_t q[3] = {(int32_t)(fixed[k][0] * 40000), (int32_t)(fixed[k][1] * 40000), (int32_t)(fixed[k][2] * 40000)};
        int32_t n[3];
        psc_oct16_decode(psc_oct16_encode(q), n);
        assert_true(angle_deg(fixed[k], n) < 1.0);   /* (1, 1, -1): 0.954 */
    }
    const int32_t big[3] = {INT32_MAX, INT32_MIN + 1, INT32_MAX};   /* the range's ends: no overflow */
    int32_t n[3];
    psc_oct16_decode(psc_oct16_encode(big), n);
    assert_true(angle_deg((const double[3]){1, -1, 1}, n) < 1.0);
    const int32_t zero[3] = {0, 0, 0};
    psc_oct16_decode(psc_oct16_encode(zero), n);
    assert_true(n[2] > 16000);   /* +z */
}

/* psc_lambert_relight against the formula in double over random normals, lights, ambients and colours: each channel
 * within one level (the ratio rounded in Q16, the dot products in Q2.14), saturated at 255; the same light leaves a
 * colour as it is; the zero normal too. */
static void test_lambert_relight(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 11);
    unsigned off = 0, sat = 0;
    for (unsigned k = 0; k < 100000; k++) {
        double v[3][3];
        int16_t q[2][3];
        int32_t n[3];
        for (unsigned i = 0; i < 3; i++)
            random_direction(&r, 1e-2, v[i]);
        uint32_t scale = 2000 + tsup_rng_below(&r, 14385);   /* the normal's length: any up to 2^14 */
        for (unsigned a = 0; a < 3; a++) {
            n[a] = (int32_t)lround(v[0][a] * scale);
            q[0][a] = (int16_t)lround(v[1][a] * 16384);
            q[1][a] = (int16_t)lround(v[2][a] * 16384);
        }
        psc_lambert_q14_t now = {{q[0][0], q[0][1], q[0][2]}, (uint16_t)tsup_rng_below(&r, 16385)};
        psc_lambert_q14_t bake = {{q[1][0], q[1][1], q[1][2]}, (uint16_t)(2000 + tsup_rng_below(&r, 14385))};
        uint32_t c = tsup_rng_u32(&r) & 0xFFFFFFu, out = psc_lambert_relight(&now, &bake, n, c);
        double nn = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        double d = (n[0] * v[1][0] + n[1] * v[1][1] + n[2] * v[1][2]) / nn;
        double d0 = (n[0] * v[2][0] + n[1] * v[2][1] + n[2] * v[2][2]) / nn;
        double a = now.ambient_q14 / 16384.0, a0 = bake.ambient_q14 / 16384.0;
        double g = (a + (1 - a) * fmax(d, 0)) / (a0 + (1 - a0) * fmax(d0, 0));
        for (int sh = 0; sh < 24; sh += 8) {
            double want = fmin(255.0, ((c >> sh) & 255u) * g);
            double got = (out >> sh) & 255u;
            off += fabs(got - want) > 1.0 + 0.002 * want;
            sat += want >= 255.0;
        }
        assert_int_equal(psc_lambert_relight(&bake, &bake, n, c), c);
    }
    print_message("  relit colours: %u of 300 000 channels more than a level off the formula, %u saturated\n", off, sat);
    assert_true(off <= 300);   /* 0.1 %%: the Q2.14 dot products where the ratio is steep */
    assert_true(sat > 0);
    const int32_t zero[3] = {0, 0, 0};
    psc_lambert_q14_t l = {{0, 16384, 0}, 0}, l0 = {{16384, 0, 0}, 8192};
    assert_int_equal(psc_lambert_relight(&l, &l0, zero, 0x123456u), 0x123456u);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_oct16),
        cmocka_unit_test(test_lambert_relight),
        cmocka_unit_test(test_shr_round),
        cmocka_unit_test(test_mul_q16),
        cmocka_unit_test(test_isqrt_exhaustive_small),
        cmocka_unit_test(test_isqrt_limits_and_random),
        cmocka_unit_test(test_rsqrt),
        cmocka_unit_test(test_unit3),
        cmocka_unit_test(test_mul_rcp62),
        cmocka_unit_test(test_div_round),
        cmocka_unit_test(test_sincos),
        cmocka_unit_test(test_atan2_angle),
        cmocka_unit_test(test_atan2_magnitude),
        cmocka_unit_test(test_bam_from_mdeg),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
