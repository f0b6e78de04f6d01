/* SPDX-License-Identifier: MIT */
/*
 * test_lut.c - the scanline-coherent table (core/lut/psc_lut.h) as built by
 * io/psc_io_lut_build.c: the stored octant plus the reflections that
 * psc_lut.h documents must reproduce the whole cylinder, a in [-180, 180)
 * degrees and u in [-u_max, u_max], within the Q0.16 quantisation.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "psc_io_lut_build.h"
#include "lut/psc_lut.h"
#include "psc_testsupport.h"

#define UNIT (TSUP_PI / 2.0 / 65536.0) /* one Q0.16 step of 90 degrees, in radians */

typedef struct {
    uint16_t rows, cols;
    double hfov_deg;
} lut_case_t;

static const lut_case_t cases[] = {
    {65, 33, 60.0},   /* small narrow table */
    {256, 107, 120.0}, /* psc_io_lut_default_size for a 640-wide display */
    {2, 2, 170.0},    /* the smallest table at the widest field */
    {181, 64, 90.0},
};

/* Error of a stored angle (units) against the exact one; saturated entries are allowed one unit. */
static void check_angle(double got_rad, double exact_rad, uint32_t stored, const char *what, int k, int m,
                        const lut_case_t *c, double *max_err)
{
    double err = fabs(tsup_wrap_pi(got_rad - exact_rad)) / UNIT;
    if (stored != 0xFFFFu && err > *max_err)
        *max_err = err; /* the quantisation error proper; saturated entries are bounded below */
    double bound = stored == 0xFFFFu ? 1.0 + 1e-6 : 0.5 + 1e-6;
    if (err > bound)
        fail_msg("%ux%u %.0f deg table, a step %d, u step %d: %s %.6f units off the exact angle (stored 0x%04x)",
                 c->rows, c->cols, c->hfov_deg, k, m, what, err, stored);
}

static void test_octant_reflections_reproduce_full_table(void **state)
{
    (void)state;
    for (size_t n = 0; n < sizeof(cases) / sizeof(cases[0]); n++) {
        const lut_case_t *c = &cases[n];
        uint32_t *entries = malloc(psc_lut_bytes(c->rows, c->cols));
        assert_non_null(entries);
        psc_lut_t lut;
        assert_int_equal(psc_io_lut_build(c->rows, c->cols, c->hfov_deg, entries, &lut), 0);
        double u_max = lut.u_max_q24 / 16777216.0;
        int R = c->rows - 1, C = c->cols - 1;
        double max_lon = 0.0, max_lat = 0.0;
        /* The full table in double: a = k * 90/(rows-1), k in [-2R, 2R); u = m * u_max/(cols-1). */
        for (int k = -2 * R; k < 2 * R; k++) {
            double a = (TSUP_PI / 2.0) * k / R;
            for (int m = -C; m <= C; m++) {
                double u = u_max * m / C, lon_x, lat_x;
                psc_io_lut_exact_angles(a, u, &lon_x, &lat_x);
                /* The documented reflections, from the stored octant. */
                int ak = abs(k);
                int over_pole = ak > R;
                int i = over_pole ? 2 * R - ak : ak;
                uint32_t e = entries[(size_t)i * c->cols + (size_t)abs(m)];
                double lon = PSC_LUT_LON(e) * UNIT, lat = PSC_LUT_LAT(e) * UNIT;
                if (over_pole)
                    lon = TSUP_PI - lon;
                if (m < 0)
                    lon = -lon;
                if (k < 0)
                    lat = -lat;
                check_angle(lon, lon_x, PSC_LUT_LON(e), "lon", k, m, c, &max_lon);
                check_angle(lat, lat_x, PSC_LUT_LAT(e), "lat", k, m, c, &max_lat);
            }
        }
        printf("  %4ux%-4u %5.1f deg: full table (%d x %d points) from the octant, max error lon %.4f, lat %.4f "
               "units of 90/65536 deg (saturated 0xFFFF entries: <= 1 unit)\n",
               c->rows, c->cols, c->hfov_deg, 4 * R, 2 * C + 1, max_lon, max_lat);
        free(entries);
    }
}

static void test_entry_packing(void **state)
{
    (void)state;
    assert_int_equal(PSC_LUT_ENTRY(0x1234, 0xABCD), 0xABCD1234u);
    assert_int_equal(PSC_LUT_LON(0xABCD1234u), 0x1234u);
    assert_int_equal(PSC_LUT_LAT(0xABCD1234u), 0xABCDu);
    assert_int_equal(PSC_LUT_ENTRY(0x12345, 0), 0x2345u); /* lon is masked to 16 bits */
    assert_int_equal(PSC_LUT_ENTRY(0xFFFF, 0xFFFF), 0xFFFFFFFFu);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 31);
    for (int i = 0; i < 100000; i++) {
        uint32_t lon = tsup_rng_u32(&rng) & 0xFFFF, lat = tsup_rng_u32(&rng) & 0xFFFF;
        uint32_t e = PSC_LUT_ENTRY(lon, lat);
        assert_int_equal(PSC_LUT_LON(e), lon);
        assert_int_equal(PSC_LUT_LAT(e), lat);
    }
    assert_int_equal(psc_lut_bytes(256, 107), 256u * 107u * 4u);
    assert_int_equal(psc_lut_bytes(PSC_MAX_LUT_DIM, PSC_MAX_LUT_DIM), (size_t)PSC_MAX_LUT_DIM * PSC_MAX_LUT_DIM * 4u);
}

static void test_saturation_and_shape(void **state)
{
    (void)state;
    enum { ROWS = 91, COLS = 41 };
    uint32_t *e = malloc(psc_lut_bytes(ROWS, COLS));
    assert_non_null(e);
    psc_lut_t lut;
    assert_int_equal(psc_io_lut_build(ROWS, COLS, 120.0, e, &lut), 0);
    /* a = 0, u = 0: straight ahead. */
    assert_int_equal(e[0], 0u);
    /* a = 90 deg: lat is 90 at u = 0 and saturates to 0xFFFF (not 0x10000 wrapping to 0). */
    const uint32_t *top = e + (size_t)(ROWS - 1) * COLS;
    assert_int_equal(PSC_LUT_LAT(top[0]), 0xFFFFu);
    assert_int_equal(PSC_LUT_LON(top[0]), 0u);
    for (unsigned j = 1; j < COLS; j++) {
        assert_int_equal(PSC_LUT_LON(top[j]), 0xFFFFu); /* lon = atan2(u, cos 90) = 90 deg */
        assert_true(PSC_LUT_LAT(top[j]) < 0xFFFFu);
    }
    for (unsigned i = 0; i < ROWS; i++) {
        const uint32_t *r = e + (size_t)i * COLS;
        for (unsigned j = 0; j < COLS; j++) {
            if (i == 0)
                assert_int_equal(PSC_LUT_LAT(r[j]), 0u); /* a = 0: the horizon */
            if (j == 0)
                assert_int_equal(PSC_LUT_LON(r[j]), 0u); /* u = 0: the view's meridian */
            if (j > 0) {                                 /* along a row: lon rises, lat falls */
                assert_true(PSC_LUT_LON(r[j]) >= PSC_LUT_LON(r[j - 1]));
                assert_true(PSC_LUT_LAT(r[j]) <= PSC_LUT_LAT(r[j - 1]));
            }
            if (i > 0) { /* down the table: lat rises, lon rises (cos a falls) */
                const uint32_t *up = e + (size_t)(i - 1) * COLS;
                assert_true(PSC_LUT_LAT(r[j]) >= PSC_LUT_LAT(up[j]));
                assert_true(PSC_LUT_LON(r[j]) >= PSC_LUT_LON(up[j]));
            }
        }
    }
    /* u = u_max on the horizon row is half the field of view. */
    double lon_edge = PSC_LUT_LON(e[COLS - 1]) * UNIT;
    assert_true(fabs(lon_edge - 60.0 * TSUP_DEG) <= UNIT);
    free(e);
}

static void test_build_metadata_and_check(void **state)
{
    (void)state;
    enum { ROWS = 32, COLS = 16 };
    uint32_t *e = malloc(psc_lut_bytes(ROWS, COLS));
    assert_non_null(e);
    psc_lut_t lut;
    const double hfovs[] = {1.0, 30.0, 60.0, 90.0, 120.0, 150.0, 170.0};
    for (size_t i = 0; i < sizeof(hfovs) / sizeof(hfovs[0]); i++) {
        assert_int_equal(psc_io_lut_build(ROWS, COLS, hfovs[i], e, &lut), 0);
        assert_int_equal(lut.rows, ROWS);
        assert_int_equal(lut.cols, COLS);
        assert_ptr_equal(lut.entries, e);
        double u = tan(hfovs[i] * TSUP_DEG / 2.0);
        assert_true(fabs(lut.u_max_q24 - u * 16777216.0) <= 0.5 + 1e-6);
        /* hfov_max is the reach of the rounded u_max: within 1e-5 degrees of the request */
        double reach_deg = tsup_bam_to_rad(lut.hfov_max) / TSUP_DEG;
        assert_true(fabs(reach_deg - hfovs[i]) < 1e-5);
        assert_int_equal(psc_lut_check(&lut), PSC_OK);
    }
    /* psc_io_lut_build refuses what the format cannot hold. */
    assert_int_not_equal(psc_io_lut_build(1, COLS, 90.0, e, &lut), 0);
    assert_int_not_equal(psc_io_lut_build(ROWS, 1, 90.0, e, &lut), 0);
    assert_int_not_equal(psc_io_lut_build(PSC_MAX_LUT_DIM + 1, 2, 90.0, e, &lut), 0);
    assert_int_not_equal(psc_io_lut_build(ROWS, COLS, 0.0, e, &lut), 0);
    assert_int_not_equal(psc_io_lut_build(ROWS, COLS, 170.5, e, &lut), 0);
    assert_int_not_equal(psc_io_lut_build(ROWS, COLS, NAN, e, &lut), 0);

    /* psc_lut_check: dimensions and u_max, not contents. */
    assert_int_equal(psc_io_lut_build(ROWS, COLS, 90.0, e, &lut), 0);
    psc_lut_t bad = lut;
    bad.entries = NULL;
    assert_int_not_equal(psc_lut_check(&bad), PSC_OK);
    assert_int_not_equal(psc_lut_check(NULL), PSC_OK);
    bad = lut;
    bad.rows = 1;
    assert_int_not_equal(psc_lut_check(&bad), PSC_OK);
    /* A table claiming to reach almost 180 degrees (tan(hfov/2) near 2^30 in Q24) while u_max says 90: refused
     * (issue 16: the reach comparison overflowed int64 there and let it pass, so views past the table were drawn). */
    static const uint32_t far_reach[] = {0x7FFFFFFFu, 0x7FFF0000u, 0x7F000000u, 0x7E000000u};
    for (size_t i = 0; i < sizeof far_reach / sizeof far_reach[0]; i++) {
        bad = lut;
        bad.hfov_max = far_reach[i];
        assert_int_equal(psc_lut_check(&bad), PSC_ERR_CORRUPT);
    }
    bad = lut;
    bad.cols = 0;
    assert_int_not_equal(psc_lut_check(&bad), PSC_OK);
    bad = lut;
    bad.rows = PSC_MAX_LUT_DIM + 1;
    assert_int_equal(psc_lut_check(&bad), PSC_ERR_TOO_LARGE);
    bad = lut;
    bad.cols = PSC_MAX_LUT_DIM + 1;
    assert_int_equal(psc_lut_check(&bad), PSC_ERR_TOO_LARGE);
    bad = lut;
    bad.rows = PSC_MAX_LUT_DIM;
    bad.cols = PSC_MAX_LUT_DIM;
    assert_int_equal(psc_lut_check(&bad), PSC_OK); /* the limits themselves are allowed */
    bad = lut;
    bad.u_max_q24 = 0;
    assert_int_not_equal(psc_lut_check(&bad), PSC_OK);
    bad = lut;
    bad.u_max_q24 = (uint32_t)(tan(86.0 * TSUP_DEG) * 16777216.0); /* beyond the 170 degree limit */
    assert_int_not_equal(psc_lut_check(&bad), PSC_OK);
    bad = lut;
    bad.hfov_max = 0;
    assert_int_not_equal(psc_lut_check(&bad), PSC_OK);
    bad = lut;
    bad.hfov_max = PSC_BAM_180;
    assert_int_not_equal(psc_lut_check(&bad), PSC_OK);
    free(e);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_octant_reflections_reproduce_full_table),
        cmocka_unit_test(test_entry_packing),
        cmocka_unit_test(test_saturation_and_shape),
        cmocka_unit_test(test_build_metadata_and_check),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
