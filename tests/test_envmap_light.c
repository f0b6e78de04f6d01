/* SPDX-License-Identifier: MIT */
/*
 * test_envmap_light.c - the light a panorama casts on its objects
 * (core/envmap/psc_envmap_light.h):
 *  - 400 random maps (dark ground, a sky of 50..110 of 255, a sun disc of
 *    14..22 degrees anywhere, brighter than the sky as a region: across the
 *    +-180 degree seam, near the poles, below the horizon), in
 *    each map format (RGB565, XRGB8888, RGB888, PAL8): the light points within
 *    one cell's diagonal (16 degrees) of the sun's centre, and the ambient share
 *    is the double-precision rule's (the sphere's mean luminance over the
 *    brightest region's, clamped to 1/4..3/4) within 2/256;
 *  - an evenly lit map gives the softest light (3/4), a small bright sun over
 *    a dark world the hardest (1/4);
 *  - maps it cannot read (a cylinder, a partial turn, fewer than 32 x 16
 *    texels) are refused, so the caller keeps its default light;
 *  - the light's colour: a grey world's is white exactly; over 200 random
 *    two-colour worlds (each texel one of two colours, in every format) it is
 *    the double-precision rule's (the mean colour scaled to grey's luminance,
 *    half way from white, each channel 1/2..3/2) within 2/256;
 *  - the pyramid level it reads: the smallest at least 64 wide.
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

#include "envmap/psc_envmap_light.h"
#include "psc_testsupport.h"

#define MW 256u
#define MH 128u

typedef struct {
    psc_envmap_t m;
    uint8_t *pixels;
    uint32_t palette[256];
} map_t;

/* The map's texel (x, y) made rgb in its format (PAL8: a grey ramp palette, the nearest grey). */
static void put(map_t *k, uint32_t x, uint32_t y, uint32_t r, uint32_t g, uint32_t b)
{
    uint8_t *row = k->pixels + (size_t)y * k->m.stride;
    switch (k->m.format) {
    case PSC_PIX_RGB565: {
        uint32_t p = (r * 31u + 127u) / 255u << 11 | (g * 63u + 127u) / 255u << 5 | (b * 31u + 127u) / 255u;
        row[2 * x] = (uint8_t)p, row[2 * x + 1] = (uint8_t)(p >> 8);
        break;
    }
    case PSC_PIX_RGB888:
        row[3 * x] = (uint8_t)b, row[3 * x + 1] = (uint8_t)g, row[3 * x + 2] = (uint8_t)r;
        break;
    case PSC_PIX_PAL8:
        row[x] = (uint8_t)((77u * r + 150u * g + 29u * b) >> 8);
        break;
    default:
        row[4 * x] = (uint8_t)b, row[4 * x + 1] = (uint8_t)g, row[4 * x + 2] = (uint8_t)r, row[4 * x + 3] = 255;
        break;
    }
}

static void map_new(map_t *k, psc_pixfmt_t f, uint32_t w, uint32_t h)
{
    memset(k, 0, sizeof *k);
    k->m.projection = PSC_PROJ_EQUIRECT;
    k->m.format = f;
    k->m.width = w, k->m.height = h;
    k->m.stride = psc_pixfmt_row_bytes(f, w);
    psc_envmap_default_coverage(&k->m);
    k->pixels = calloc(k->m.stride, h);
    assert_non_null(k->pixels);
    k->m.pixels = k->pixels;
    for (unsigned i = 0; i < 256; i++)
        k->palette[i] = 0xFF000000u | i << 16 | i << 8 | i;
    k->m.palette = k->palette;
}

/* Texel (x, y) as stored, its channels in double (RGB565 widened as core widens it: c * 255 / 31, truncated). */
static void stored_rgb(const map_t *k, unsigned x, unsigned y, double rgb[3])
{
    const uint8_t *row = k->pixels + (size_t)y * k->m.stride;
    if (k->m.format == PSC_PIX_RGB565) {
        unsigned p = row[2 * x] | row[2 * x + 1] << 8;
        rgb[0] = (p >> 11) * 255 / 31, rgb[1] = (p >> 5 & 63) * 255 / 63, rgb[2] = (p & 31) * 255 / 31;
    } else if (k->m.format == PSC_PIX_RGB888) {
        rgb[0] = row[3 * x + 2], rgb[1] = row[3 * x + 1], rgb[2] = row[3 * x];
    } else if (k->m.format == PSC_PIX_PAL8) {
        rgb[0] = rgb[1] = rgb[2] = row[x];
    } else {
        rgb[0] = row[4 * x + 2], rgb[1] = row[4 * x + 1], rgb[2] = row[4 * x];
    }
}

/* The centre direction of texel (x, y). */
static void texel_dir(const psc_envmap_t *m, uint32_t x, uint32_t y, double *lon, double *lat)
{
    *lon = tsup_bam_to_rad(m->lon_min) + (x + 0.5) / m->width * 2 * M_PI;
    double top = tsup_sbam_to_rad(m->lat_top), bottom = tsup_sbam_to_rad(m->lat_bottom);
    *lat = top + (y + 0.5) / m->height * (bottom - top);
}

static void test_sun(void **state)
{
    (void)state;
    static const psc_pixfmt_t formats[4] = {PSC_PIX_RGB565, PSC_PIX_XRGB8888, PSC_PIX_RGB888, PSC_PIX_PAL8};
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 3201);
    double worst = 0, worst_amb = 0;
    unsigned seam = 0, poles = 0;
    for (unsigned n = 0; n < 400; n++) {
        map_t k;
        map_new(&k, formats[n % 4], MW, MH);
        double slon = tsup_rng_range(&rng, -M_PI, M_PI), slat = asin(tsup_rng_range(&rng, -0.95, 0.99));
        if (n % 10 == 0)
            slon = M_PI - 0.02;   /* on the seam */
        double rad = tsup_rng_range(&rng, 14, 22) * M_PI / 180, sky = tsup_rng_range(&rng, 50, 110);
        seam += fabs(slon) > 170 * M_PI / 180;
        poles += fabs(slat) > 60 * M_PI / 180;
        for (uint32_t y = 0; y < MH; y++)
            for (uint32_t x = 0; x < MW; x++) {
                double lon, lat;
                texel_dir(&k.m, x, y, &lon, &lat);
                double d = tsup_angle_between(lon, lat, slon, slat);
                uint32_t v = d < rad ? 250u : lat > 0 ? (uint32_t)sky : 30u;
                put(&k, x, y, v, v, v);
            }
        int32_t t[3];
        uint16_t amb;
        assert_int_equal(psc_envmap_light(&k.m, t, &amb), PSC_OK);
        double x = t[0] / 65536.0, y = t[1] / 65536.0, z = t[2] / 65536.0;
        double llon = atan2(x, z), llat = atan2(y, hypot(x, z));
        double e = tsup_angle_between(llon, llat, slon, slat) * 180 / M_PI;
        worst = e > worst ? e : worst;
        if (e > 16)
            fail_msg("map %u: sun at %.1f,%.1f (radius %.1f): light toward %.1f,%.1f, %.1f degrees off", n,
                     slon * 180 / M_PI, slat * 180 / M_PI, rad * 180 / M_PI, llon * 180 / M_PI, llat * 180 / M_PI, e);
        /* the ambient rule in double over the same cells */
        double cell[PSC_ENVMAP_LIGHT_ROWS][PSC_ENVMAP_LIGHT_COLS], num = 0, den = 0;
        for (unsigned j = 0; j < PSC_ENVMAP_LIGHT_ROWS; j++)
            for (unsigned i = 0; i < PSC_ENVMAP_LIGHT_COLS; i++) {
                unsigned cw = MW / PSC_ENVMAP_LIGHT_COLS, ch = MH / PSC_ENVMAP_LIGHT_ROWS;
                double s = 0;
                for (unsigned yy = j * ch; yy < (j + 1) * ch; yy++)
                    for (unsigned xx = i * cw; xx < (i + 1) * cw; xx++) {
                        double c[3];
                        stored_rgb(&k, xx, yy, c);
                        s += floor((77 * c[0] + 150 * c[1] + 29 * c[2]) / 256);
                    }
                cell[j][i] = s / (cw * ch);
                double w = cos((90 - (j + 0.5) * 180.0 / PSC_ENVMAP_LIGHT_ROWS) * M_PI / 180);
                num += cell[j][i] * w, den += w;
            }
        double best = 0;
        for (int j = 0; j < (int)PSC_ENVMAP_LIGHT_ROWS; j++)
            for (int i = 0; i < (int)PSC_ENVMAP_LIGHT_COLS; i++) {
                double s = 0, c = 0;
                for (int dj = -1; dj <= 1; dj++)
                    for (int di = -1; di <= 1; di++)
                        if (j + dj >= 0 && j + dj < (int)PSC_ENVMAP_LIGHT_ROWS)
                            s += cell[j + dj][(i + di + PSC_ENVMAP_LIGHT_COLS) % PSC_ENVMAP_LIGHT_COLS], c++;
                best = fmax(best, s / c);
            }
        double want = fmin(fmax(num / den / best * 256, 64), 192);
        worst_amb = fmax(worst_amb, fabs(amb - want));
        if (fabs(amb - want) > 2)
            fail_msg("map %u: ambient %u/256, the rule in double %.2f", n, amb, want);
        free(k.pixels);
    }
    print_message("  400 maps, 4 formats: the light at most %.1f degrees from the sun's centre (%u on the seam, %u "
                  "near a pole), the ambient within %.2f/256 of the rule in double\n", worst, seam, poles, worst_amb);
    assert_true(seam >= 40 && poles >= 20);
}

static void test_soft_and_hard(void **state)
{
    (void)state;
    map_t k;
    map_new(&k, PSC_PIX_XRGB8888, MW, MH);
    for (uint32_t y = 0; y < MH; y++)
        for (uint32_t x = 0; x < MW; x++)
            put(&k, x, y, 128, 128, 128);
    int32_t t[3];
    uint16_t amb;
    assert_int_equal(psc_envmap_light(&k.m, t, &amb), PSC_OK);
    assert_int_equal(amb, PSC_ENVMAP_AMBIENT_MAX_Q8);   /* even: the softest */
    for (uint32_t y = 0; y < MH; y++)
        for (uint32_t x = 0; x < MW; x++) {
            double lon, lat;
            texel_dir(&k.m, x, y, &lon, &lat);
            uint32_t v = tsup_angle_between(lon, lat, 0.5, 0.6) < 0.15 ? 255u : 10u;
            put(&k, x, y, v, v, v);
        }
    assert_int_equal(psc_envmap_light(&k.m, t, &amb), PSC_OK);
    assert_int_equal(amb, PSC_ENVMAP_AMBIENT_MIN_Q8);   /* a small sun over a dark world: the hardest */
    free(k.pixels);
}

static void test_refused(void **state)
{
    (void)state;
    map_t k;
    int32_t t[3];
    uint16_t amb;
    map_new(&k, PSC_PIX_XRGB8888, MW, MH);
    k.m.projection = PSC_PROJ_CYLINDER;
    assert_int_equal(psc_envmap_light(&k.m, t, &amb), PSC_ERR_UNSUPPORTED);
    k.m.projection = PSC_PROJ_EQUIRECT;
    k.m.lon_span = PSC_BAM_180;   /* half a turn */
    assert_int_equal(psc_envmap_light(&k.m, t, &amb), PSC_ERR_UNSUPPORTED);
    k.m.lon_span = 0;
    k.m.width = 31;
    assert_int_equal(psc_envmap_light(&k.m, t, &amb), PSC_ERR_UNSUPPORTED);
    k.m.width = MW;
    assert_int_equal(psc_envmap_light(NULL, t, &amb), PSC_ERR_ARG);
    assert_int_equal(psc_envmap_light(&k.m, t, &amb), PSC_OK);
    free(k.pixels);
    psc_envmap_t levels[4];
    for (unsigned i = 0; i < 4; i++)
        levels[i].width = 512u >> (2 * i), levels[i].height = 256u >> (2 * i);   /* 512, 128, 32, 8 */
    assert_ptr_equal(psc_envmap_light_level(levels, 4), &levels[1]);
    assert_ptr_equal(psc_envmap_light_level(levels, 1), &levels[0]);
    assert_null(psc_envmap_light_level(levels, 0));
}

static void test_colour(void **state)
{
    (void)state;
    static const psc_pixfmt_t formats[3] = {PSC_PIX_XRGB8888, PSC_PIX_RGB888, PSC_PIX_RGB565};
    map_t k;
    uint16_t c[3];
    map_new(&k, PSC_PIX_XRGB8888, MW, MH);
    for (uint32_t y = 0; y < MH; y++)
        for (uint32_t x = 0; x < MW; x++)
            put(&k, x, y, 90, 90, 90);
    assert_int_equal(psc_envmap_light_colour(&k.m, c), PSC_OK);
    assert_true(c[0] == 256 && c[1] == 256 && c[2] == 256);
    free(k.pixels);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 3202);
    double worst = 0;
    for (unsigned n = 0; n < 200; n++) {
        map_new(&k, formats[n % 3], MW, MH);
        uint32_t a[3], b[3];
        for (unsigned i = 0; i < 3; i++)
            a[i] = tsup_rng_below(&rng, 256), b[i] = tsup_rng_below(&rng, 256);
        uint32_t split = 1 + tsup_rng_below(&rng, MH - 2);   /* rows above: a; below: b */
        for (uint32_t y = 0; y < MH; y++)
            for (uint32_t x = 0; x < MW; x++)
                put(&k, x, y, y < split ? a[0] : b[0], y < split ? a[1] : b[1], y < split ? a[2] : b[2]);
        assert_int_equal(psc_envmap_light_colour(&k.m, c), PSC_OK);
        /* the rule in double, over the cells as the product reads them (the texels as stored) */
        double sum[3] = {0, 0, 0};
        for (unsigned j = 0; j < PSC_ENVMAP_LIGHT_ROWS; j++) {
            double w = floor(cos((90 - (j + 0.5) * 180.0 / PSC_ENVMAP_LIGHT_ROWS) * M_PI / 180) * 32768);
            for (unsigned i = 0; i < PSC_ENVMAP_LIGHT_COLS; i++) {
                unsigned cw = MW / PSC_ENVMAP_LIGHT_COLS, ch = MH / PSC_ENVMAP_LIGHT_ROWS;
                double acc[3] = {0, 0, 0};
                unsigned cnt = 0;
                for (unsigned yy = j * ch; yy < (j + 1) * ch; yy += 1)
                    for (unsigned xx = i * cw; xx < (i + 1) * cw; xx += 1) {
                        double px[3];
                        stored_rgb(&k, xx, yy, px);
                        acc[0] += px[0], acc[1] += px[1], acc[2] += px[2], cnt++;
                    }
                for (unsigned q = 0; q < 3; q++)
                    sum[q] += acc[q] / cnt * w;
            }
        }
        double lum = 77 * sum[0] + 150 * sum[1] + 29 * sum[2];
        for (unsigned q = 0; q < 3; q++) {
            double want = lum > 0 ? (sum[q] * 65536 / lum + 256) / 2 : 256;
            want = fmin(fmax(want, 128), 384);
            worst = fmax(worst, fabs(c[q] - want));
            if (fabs(c[q] - want) > 2)
                fail_msg("world %u (%u %u %u over %u %u %u, split at row %u): channel %u is %u/256, the rule %.2f", n,
                         a[0], a[1], a[2], b[0], b[1], b[2], split, q, c[q], want);
        }
        free(k.pixels);
    }
    print_message("  200 two-colour worlds: the light's colour within %.2f/256 of the rule in double\n", worst);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sun),
        cmocka_unit_test(test_soft_and_hard),
        cmocka_unit_test(test_colour),
        cmocka_unit_test(test_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
