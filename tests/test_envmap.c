/* SPDX-License-Identifier: MIT */
/* test_envmap.c - map descriptions (core/envmap/psc_envmap.h): names, checks and default coverage. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "envmap/psc_envmap.h"
#include "psc_testsupport.h"

static uint8_t pixels[16];
static uint32_t palette[256];

static psc_envmap_t full_map(psc_projection_t p, psc_pixfmt_t f, uint16_t w, uint16_t h)
{
    psc_envmap_t m;
    memset(&m, 0, sizeof(m));
    m.projection = p;
    m.format = f;
    m.width = w;
    m.height = h;
    m.stride = (uint32_t)w * psc_pixfmt_bytes(f);
    m.pixels = pixels; /* never read by the checks */
    m.palette = palette;
    psc_envmap_default_coverage(&m);
    return m;
}

static void test_names(void **state)
{
    (void)state;
    assert_string_equal(psc_projection_name(PSC_PROJ_EQUIRECT), "equirect");
    assert_string_equal(psc_projection_name(PSC_PROJ_CYLINDER), "cylinder");
    assert_string_equal(psc_projection_name(PSC_PROJ_SINE), "sine");
    assert_string_equal(psc_projection_name(PSC_PROJ_ELLIPTICAL), "elliptical");
    assert_string_equal(psc_projection_name(PSC_PROJ_DIAMOND), "diamond");
    assert_string_equal(psc_projection_name((psc_projection_t)0), "?");
    assert_string_equal(psc_projection_name((psc_projection_t)77), "?");
    assert_int_equal(psc_pixfmt_bytes(PSC_PIX_RGB565), 2);
    assert_int_equal(psc_pixfmt_bytes(PSC_PIX_XRGB8888), 4);
    assert_int_equal(psc_pixfmt_bytes(PSC_PIX_PAL8), 1);
    assert_int_equal(psc_pixfmt_bytes((psc_pixfmt_t)9), 0);
}

static void test_default_coverage(void **state)
{
    (void)state;
    static const psc_projection_t sphere[] = {PSC_PROJ_EQUIRECT, PSC_PROJ_SINE, PSC_PROJ_ELLIPTICAL, PSC_PROJ_DIAMOND};
    for (size_t i = 0; i < 4; i++) {
        psc_envmap_t m = full_map(sphere[i], PSC_PIX_RGB565, 1024, 512);
        assert_int_equal(m.lon_min, PSC_BAM_180); /* column 0 starts at -180: the centre looks ahead */
        assert_int_equal(m.lon_span, 0);
        assert_int_equal(m.lat_top, (int32_t)PSC_BAM_90);
        assert_int_equal(m.lat_bottom, -(int32_t)PSC_BAM_90);
        assert_int_equal(psc_envmap_check(&m), PSC_OK);
    }
    /* Cylinder: tan(lat_top) = pi * H / W (the circumference is the width), capped at 85 degrees. */
    static const uint16_t sizes[][2] = {{1024, 512}, {2048, 512}, {4096, 1000}, {1000, 300}, {512, 1024}, {64, 2000}};
    for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); i++) {
        psc_envmap_t m = full_map(PSC_PROJ_CYLINDER, PSC_PIX_RGB565, sizes[i][0], sizes[i][1]);
        double want = atan(TSUP_PI * sizes[i][1] / sizes[i][0]);
        if (want > 85.0 * TSUP_DEG)
            want = 85.0 * TSUP_DEG;
        double got = tsup_sbam_to_rad(m.lat_top);
        if (fabs(got - want) > 1e-6)
            fail_msg("cylinder %ux%u: lat_top %.6f deg, expected %.6f", sizes[i][0], sizes[i][1], got / TSUP_DEG,
                     want / TSUP_DEG);
        assert_int_equal(m.lat_bottom, -m.lat_top);
        assert_int_equal(m.lon_span, 0);
        assert_int_equal(psc_envmap_check(&m), PSC_OK);
    }
}

static void test_check(void **state)
{
    (void)state;
    psc_envmap_t ok = full_map(PSC_PROJ_EQUIRECT, PSC_PIX_RGB565, 1024, 512), m;
    assert_int_not_equal(psc_envmap_check(NULL), PSC_OK);
    m = ok;
    m.pixels = NULL;
    assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
    m = ok;
    m.width = 0;
    assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
    m = ok;
    m.width = PSC_MAX_MAP_DIM + 1;
    m.stride = m.width * 2u;
    assert_int_equal(psc_envmap_check(&m), PSC_ERR_TOO_LARGE);
    m = ok;
    m.width = PSC_MAX_MAP_DIM;
    m.height = PSC_MAX_MAP_DIM;
    m.stride = m.width * 2u;
    assert_int_equal(psc_envmap_check(&m), PSC_OK);
    m = ok;
    m.stride = 1024 * 2 - 1;
    assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
    m = ok;
    m.format = (psc_pixfmt_t)0;
    assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
    m = full_map(PSC_PROJ_EQUIRECT, PSC_PIX_PAL8, 1024, 512);
    assert_int_equal(psc_envmap_check(&m), PSC_OK);
    m.palette = NULL;
    assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
    m = ok;
    m.projection = (psc_projection_t)6;
    assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
    /* Coverage. */
    m = ok;
    m.lat_top = m.lat_bottom;
    assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
    m = ok;
    m.lat_top = -(int32_t)tsup_bam_from_deg(10.0);
    m.lat_bottom = (int32_t)tsup_bam_from_deg(10.0);
    assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
    m = ok;
    m.lat_top = (int32_t)PSC_BAM_90 + 1;
    assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
    m = ok;
    m.lon_span = tsup_bam_from_deg(120.0);
    m.lat_top = (int32_t)tsup_bam_from_deg(30.0);
    assert_int_equal(psc_envmap_check(&m), PSC_OK); /* a partial equirect map */
    m = full_map(PSC_PROJ_CYLINDER, PSC_PIX_RGB565, 1024, 512);
    m.lat_top = (int32_t)tsup_bam_from_deg(85.0);
    m.lat_bottom = -(int32_t)tsup_bam_from_deg(85.0);
    assert_int_equal(psc_envmap_check(&m), PSC_OK);
    m.lat_top = (int32_t)tsup_bam_from_deg(86.0);
    assert_int_not_equal(psc_envmap_check(&m), PSC_OK); /* tan grows without bound: +-85 at most */
    static const psc_projection_t shaped[] = {PSC_PROJ_ELLIPTICAL, PSC_PROJ_DIAMOND};
    for (size_t i = 0; i < 2; i++) { /* their row widths are defined over the whole sphere only */
        m = full_map(shaped[i], PSC_PIX_RGB565, 1024, 512);
        m.lon_span = tsup_bam_from_deg(180.0);
        assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
        m = full_map(shaped[i], PSC_PIX_RGB565, 1024, 512);
        m.lat_bottom = 0;
        assert_int_not_equal(psc_envmap_check(&m), PSC_OK);
    }
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_default_coverage),
        cmocka_unit_test(test_check),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
