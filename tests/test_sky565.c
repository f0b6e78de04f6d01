/* SPDX-License-Identifier: MIT */
/*
 * test_sky565.c - a smooth sky packed with the defaults shows no bands on an RGB565 display (issue 30).
 *
 * A clear-sky panorama (8 bits a channel, as a photograph's JPEG holds it: pale at the horizon, deep blue at
 * the zenith, brighter toward the sun, a darker ground) is packed twice for a 320x240 display: with
 * periscope-pack's defaults (psc_io_pack_options_default: an RGB888 map) and with --format rgb565 (the default
 * before). Each is shown as the device shows it on an RGB565 display with display_dither = ordered: the
 * RGB888 pack drawn at 8 bits and dithered into RGB565 (psc_dither_row_rgb565, the frame loop's pass), the
 * RGB565 pack drawn straight into RGB565 (its scene fits RGB565). Each frame against the double-precision view
 * of the image (tsup_ref_render, bilinear, 2x2 supersampled), by the banding figure of
 * host_tools/lib/measure/banding.h (the error low-passed by a Gaussian of sigma 1.5 px, RMS over the channels,
 * in 8-bit levels):
 *  - the default pack: at most 1.2 levels in every view (the bound), and its map with its pyramid at
 *    most 1.5x the RGB565 map's bytes (plus RGB888's spare row bytes, under 1 %);
 *  - the RGB565 pack shows the bands the default removes: its figure at least 3x the default's.
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

#include "dither/psc_dither.h"
#include "measure/banding.h"
#include "pack/psc_pack.h"
#include "psc_io_pack_build.h"
#include "psc_io_pixfmt.h"
#include "psc_testsupport.h"
#include "viewer/psc_viewer.h"

#define MAP_W 2048u
#define MAP_H 1024u
#define OUT_W 320u
#define OUT_H 240u
#define BOUND_LEVELS 1.2

/* The sky at latitude lat, longitude lon (degrees), 0..255 a channel before rounding. */
static void sky(double lon, double lat, double rgb[3])
{
    static const double horizon[3] = {206.0, 218.0, 232.0}, zenith[3] = {58.0, 104.0, 186.0};
    static const double ground_near[3] = {92.0, 88.0, 70.0}, ground_far[3] = {150.0, 146.0, 128.0};
    double sun = 10.0 * cos((lon - 40.0) * M_PI / 180.0);   /* brighter toward the sun's side */
    if (lat >= 0.0) {
        double u = pow(lat / 90.0, 0.6);
        for (int c = 0; c < 3; c++)
            rgb[c] = horizon[c] + (zenith[c] - horizon[c]) * u + sun * (1.0 - u);
    } else {
        double u = pow(-lat / 90.0, 0.5);
        for (int c = 0; c < 3; c++)
            rgb[c] = ground_far[c] + (ground_near[c] - ground_far[c]) * u;
    }
}

static psc_image_t sky_image(void)
{
    psc_image_t img = {MAP_W, MAP_H, malloc((size_t)MAP_W * MAP_H * 4u)};
    assert_non_null(img.xrgb);
    for (uint32_t y = 0; y < MAP_H; y++)
        for (uint32_t x = 0; x < MAP_W; x++) {
            double rgb[3];
            sky((x + 0.5) * 360.0 / MAP_W - 180.0, 90.0 - (y + 0.5) * 180.0 / MAP_H, rgb);
            uint32_t p = 0xFF000000u;
            for (int c = 0; c < 3; c++)
                p |= (uint32_t)lround(rgb[c]) << (16 - 8 * c);
            img.xrgb[(size_t)y * MAP_W + x] = p;
        }
    return img;
}

typedef struct {
    uint8_t *bytes;
    psc_pack_t pack;
    tsup_viewer_t tv;
    size_t map_bytes;   /* the map and its pyramid */
} pack_t;

static void make_pack(pack_t *p, const psc_image_t *img, bool defaults, psc_pixfmt_t out_format)
{
    psc_pack_options_t o;
    psc_io_pack_options_default(&o);
    o.display_width = OUT_W;
    o.display_height = OUT_H;
    if (!defaults)
        o.format = PSC_PIX_RGB565;
    size_t len;
    char err[256];
    assert_int_equal(psc_io_pack_build(img, &o, &p->bytes, &len, err, sizeof err), 0);
    psc_container_error_t e = {0};
    assert_int_equal(psc_pack_parse(p->bytes, len, &p->pack, &e), PSC_OK);
    assert_int_equal(tsup_viewer_init(&p->tv, &p->pack.map, OUT_W, OUT_H, out_format), PSC_OK);
    assert_int_equal(psc_viewer_set_levels(&p->tv.v, p->pack.levels, p->pack.level_count), PSC_OK);
    p->map_bytes = 0;
    for (unsigned k = 0; k < p->pack.level_count; k++)
        p->map_bytes += (size_t)p->pack.levels[k].stride * p->pack.levels[k].height;
}

static void free_pack(pack_t *p)
{
    tsup_viewer_free(&p->tv);
    free(p->bytes);
}

/* What an RGB565 display shows of view: the device's path for the pack's map (see the file's comment). */
static void shown_565(pack_t *p, const psc_view_t *view, const psc_dither_565_t *t, uint16_t *shown)
{
    assert_int_equal(psc_viewer_render(&p->tv.v, view, &p->tv.out), PSC_OK);
    for (unsigned y = 0; y < OUT_H; y++) {
        const uint8_t *row = (const uint8_t *)p->tv.out.pixels + (size_t)y * p->tv.out.stride;
        if (p->tv.out.format == PSC_PIX_RGB565)
            memcpy(shown + (size_t)y * OUT_W, row, OUT_W * 2u);
        else
            psc_dither_row_rgb565(t, PSC_DITHER_ORDERED, (const uint32_t *)(const void *)row, OUT_W, 0, y,
                                  shown + (size_t)y * OUT_W);
    }
}

static void test_default_pack_sky_has_no_bands(void **state)
{
    (void)state;
    psc_image_t img = sky_image();
    pack_t def, p565;
    make_pack(&def, &img, true, PSC_PIX_XRGB8888);
    make_pack(&p565, &img, false, PSC_PIX_RGB565);
    assert_int_equal(def.pack.map.format, PSC_PIX_RGB888);
    print_message("  the default map: %s, %zu bytes with its %u levels; rgb565: %zu bytes (%.3fx)\n",
                  psc_io_pixfmt_name(def.pack.map.format), def.map_bytes, (unsigned)def.pack.level_count,
                  p565.map_bytes, (double)def.map_bytes / (double)p565.map_bytes);
    assert_true((double)def.map_bytes <= 1.5 * 1.01 * (double)p565.map_bytes);

    static psc_dither_565_t t;
    psc_dither_565_init(&t);
    psc_envmap_t ref_map = def.pack.map;   /* the image itself, as the reference samples it */
    ref_map.format = PSC_PIX_XRGB8888;
    ref_map.pixels = img.xrgb;
    ref_map.stride = MAP_W * 4u;
    static const struct {
        double yaw, pitch, hfov;
        psc_filter_t filter;
    } views[] = {
        {40, 35, 90, PSC_FILTER_MIP},       /* the sky toward the sun */
        {-150, 50, 70, PSC_FILTER_MIP},     /* away from it, higher */
        {100, 15, 60, PSC_FILTER_BILINEAR}, /* over the horizon */
        {0, 70, 40, PSC_FILTER_BILINEAR},   /* toward the zenith, zoomed in */
        {-60, 25, 20, PSC_FILTER_BILINEAR}, /* zoomed in: several pixels a texel */
    };
    uint16_t *a = malloc(OUT_W * OUT_H * 2u), *b = malloc(OUT_W * OUT_H * 2u);
    double *ref = malloc(OUT_W * OUT_H * 3u * sizeof *ref);
    assert_true(a && b && ref);
    double worst_def = 0, least_565 = 1e9;
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) {
        psc_view_t view = tsup_view_deg(views[i].yaw, views[i].pitch, views[i].hfov, views[i].filter, 2);
        shown_565(&def, &view, &t, a);
        shown_565(&p565, &view, &t, b);
        psc_view_t rv = view;
        rv.filter = PSC_FILTER_BILINEAR;
        tsup_ref_render(&ref_map, &rv, OUT_W, OUT_H, 2, ref);
        psc_measure_banding_t ma, mb;
        assert_int_equal(psc_measure_banding_ref(ref, a, OUT_W, OUT_H, &ma), 0);
        assert_int_equal(psc_measure_banding_ref(ref, b, OUT_W, OUT_H, &mb), 0);
        print_message("  yaw %4.0f pitch %2.0f hfov %2.0f %-8s: low-passed error %.2f levels (default, dithered), "
                      "%.2f (rgb565 pack); its largest step %.2f and %.2f\n",
                      views[i].yaw, views[i].pitch, views[i].hfov,
                      views[i].filter == PSC_FILTER_MIP ? "mip" : "bilinear", ma.rms, mb.rms, ma.estep, mb.estep);
        assert_true(ma.rms <= BOUND_LEVELS);
        assert_true(mb.rms >= 3.0 * ma.rms);
        worst_def = fmax(worst_def, ma.rms);
        least_565 = fmin(least_565, mb.rms);
    }
    print_message("  worst default %.2f levels (bound %.1f); the rgb565 pack at least %.2f\n", worst_def,
                  BOUND_LEVELS, least_565);
    free(a);
    free(b);
    free(ref);
    free_pack(&def);
    free_pack(&p565);
    free(img.xrgb);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_pack_sky_has_no_bands),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
