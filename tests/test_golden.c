/* SPDX-License-Identifier: MIT */
/*
 * test_golden.c - rendered views against the double-precision reference
 * renderer (tests/support), on synthetic maps of every projection, format
 * and coverage.
 *
 * Metric: PSNR over the 8-bit RGB channels, 10 log10(255^2 / MSE), of the
 * viewer's output against the reference rendered at the exact ray of each
 * output pixel with the same filter and edge rules, quantised as a perfect
 * renderer would store it in the output format (tsup_mse_surface).
 * Thresholds:
 *   bilinear >= 38 dB (the brief's figure);
 *   nearest  >= NEAREST_MIN_DB (35 dB): a nearest sample flips to the
 *   neighbouring texel wherever the sampled position and the exact one
 *   straddle a texel boundary (index error ~0.02 px mean: a few % of pixels),
 *   and each flip costs a whole texel step of the grid lines and markers
 *   instead of a fraction of it, so nearest is inherently more sensitive than
 *   bilinear. Measured (printed table): 37.6..59 dB, the lowest on the
 *   partial equirect map at 30..60 deg hfov (magnified texels); 35 dB keeps
 *   ~2.5 dB of margin and still fails a systematic half-texel offset.
 * Sensitivity (measured once by offsetting the reference's yaw): a constant
 * 0.25 map-px error gives bilinear 38.3..42.7 dB, 0.5 px 32.5..37.0 dB,
 * 1 px 27..31.6 dB; nearest 32.2..36.5 / 29.1..33.4 / 25.8..30.5 dB.
 * Also printed: bilinear against a 4x4 supersampled reference (aliasing, no bound).
 *
 * Further checks: render and psc_viewer_trace_row agree (nearest texel
 * exactly, bilinear within 2 levels), identical bytes for identical views,
 * the stride padding is never written, the markers appear where the
 * conventions put them, argument checks, and psc_viewer_clamp keeps every
 * sample of a partial panorama inside the map.
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

#include "viewer/psc_viewer.h"
#include "psc_testsupport.h"

#define BILINEAR_MIN_DB 38.0
#define NEAREST_MIN_DB 35.0
#define MAP_W 1024
#define MAP_H 512

/* ---- maps ------------------------------------------------------------------- */

typedef struct {
    const char *name;
    psc_projection_t proj;
    psc_pixfmt_t fmt;
    int partial;                 /* 0: the projection's default coverage */
    double lon_min, lon_span;    /* degrees (partial only) */
    double lat_top, lat_bottom;  /* degrees (partial only) */
} map_spec_t;

static const map_spec_t MAPS[] = {
    {"equirect/565", PSC_PROJ_EQUIRECT, PSC_PIX_RGB565, 0, 0, 0, 0, 0},
    {"equirect/8888", PSC_PROJ_EQUIRECT, PSC_PIX_XRGB8888, 0, 0, 0, 0, 0},
    {"equirect/pal8", PSC_PROJ_EQUIRECT, PSC_PIX_PAL8, 0, 0, 0, 0, 0},
    {"cylinder/565", PSC_PROJ_CYLINDER, PSC_PIX_RGB565, 0, 0, 0, 0, 0},
    {"sine/565", PSC_PROJ_SINE, PSC_PIX_RGB565, 0, 0, 0, 0, 0},
    {"elliptical/565", PSC_PROJ_ELLIPTICAL, PSC_PIX_RGB565, 0, 0, 0, 0, 0},
    {"diamond/8888", PSC_PROJ_DIAMOND, PSC_PIX_XRGB8888, 0, 0, 0, 0, 0},
    {"equirect part/565", PSC_PROJ_EQUIRECT, PSC_PIX_RGB565, 1, -60.0, 150.0, 50.0, -35.0},
    {"cylinder part/pal8", PSC_PROJ_CYLINDER, PSC_PIX_PAL8, 1, 100.0, 140.0, 40.0, -40.0},
    {"sine part/8888", PSC_PROJ_SINE, PSC_PIX_XRGB8888, 1, 150.0, 100.0, 70.0, 0.0},
    {"equirect 360x(80..-20)/565", PSC_PROJ_EQUIRECT, PSC_PIX_RGB565, 2, -180.0, 0.0, 80.0, -20.0},
};
#define NMAPS (sizeof(MAPS) / sizeof(MAPS[0]))

static tsup_map_t g_maps[NMAPS];

static int make_map(size_t i)
{
    const map_spec_t *s = &MAPS[i];
    psc_envmap_t g = {0};
    g.projection = s->proj;
    g.format = s->fmt;
    g.width = MAP_W;
    g.height = MAP_H;
    if (s->partial) {
        g.lon_min = tsup_bam_from_deg(s->lon_min);
        g.lon_span = s->lon_span == 0.0 ? 0 : tsup_bam_from_deg(s->lon_span);
        g.lat_top = (int32_t)llround(s->lat_top / 360.0 * 4294967296.0);
        g.lat_bottom = (int32_t)llround(s->lat_bottom / 360.0 * 4294967296.0);
    }
    /* Odd maps get padded rows, so the stride is exercised. */
    return tsup_synth_map(&g_maps[i], &g, !s->partial, (i & 1) ? 8u : 0u);
}

static int setup_maps(void **state)
{
    (void)state;
    for (size_t i = 0; i < NMAPS; i++)
        if (make_map(i) != 0 || psc_envmap_check(&g_maps[i].map) != PSC_OK)
            return -1;
    return 0;
}

static int teardown_maps(void **state)
{
    (void)state;
    for (size_t i = 0; i < NMAPS; i++)
        tsup_map_free(&g_maps[i]);
    return 0;
}

/* ---- rendering and comparison ---------------------------------------------- */

typedef struct {
    double yaw, pitch, hfov;
} view_deg_t;

static double render_psnr(size_t map_i, uint16_t w, uint16_t h, psc_pixfmt_t out_fmt, psc_view_t view,
                          unsigned ss, psc_view_t *used)
{
    const psc_envmap_t *m = &g_maps[map_i].map;
    tsup_viewer_t tv;
    psc_status_t s = tsup_viewer_init(&tv, m, w, h, out_fmt);
    if (s != PSC_OK)
        fail_msg("%s: viewer init %s", MAPS[map_i].name, psc_status_str(s));
    psc_viewer_clamp(&tv.v, &view, tsup_bam_from_deg(20.0));
    s = psc_viewer_render(&tv.v, &view, &tv.out);
    if (s != PSC_OK)
        fail_msg("%s: render yaw 0x%08x pitch %d hfov 0x%08x: %s", MAPS[map_i].name, view.yaw, view.pitch, view.hfov,
                 psc_status_str(s));
    assert_true(tsup_viewer_guard_ok(&tv));
    double *ref = malloc((size_t)w * h * 3 * sizeof(double));
    assert_non_null(ref);
    tsup_ref_render(m, &view, w, h, ss, ref);
    double psnr = tsup_psnr(tsup_mse_surface(&tv.out, ref));
    free(ref);
    tsup_viewer_free(&tv);
    if (used)
        *used = view;
    return psnr;
}

static void print_row(const char *map, uint16_t w, uint16_t h, psc_pixfmt_t fmt, const char *filter,
                      const psc_view_t *v, double psnr, double bound)
{
    printf("  | %-26s | %3ux%-3u %-4s | %-8s | yaw %8.3f pitch %7.3f hfov %6.2f | %6.2f dB | >= %.0f\n", map, w, h,
           fmt == PSC_PIX_RGB565 ? "565" : "8888", filter, tsup_sbam_to_rad((int32_t)v->yaw) / TSUP_DEG,
           tsup_sbam_to_rad(v->pitch) / TSUP_DEG, tsup_bam_to_rad(v->hfov) / TSUP_DEG, psnr, bound);
}

static void print_header(void)
{
    printf("  | %-26s | %-12s | %-8s | %-40s | %-9s | bound\n", "map", "output", "filter", "view (after clamp)",
           "PSNR");
}

static const view_deg_t VIEWS[] = {
    {0.0, 0.0, 90.0},    {179.9, 0.0, 60.0},    {-180.0, 15.0, 61.0}, {37.0, 90.0, 90.0},
    {-120.0, -90.0, 120.0}, {179.9, -45.0, 30.0}, {-180.0, 70.0, 120.0}, {90.0, -20.0, 30.0},
};
#define NVIEWS (sizeof(VIEWS) / sizeof(VIEWS[0]))

/* One map, every view, both filters; the output format alternates per view. */
static void golden_map(size_t map_i, double *worst_bil, double *worst_near)
{
    for (size_t k = 0; k < NVIEWS; k++) {
        psc_pixfmt_t fmt = (k & 1) ? PSC_PIX_XRGB8888 : PSC_PIX_RGB565;
        uint16_t w = (k % 3 == 2) ? 160 : 320, h = (k % 3 == 2) ? 120 : 240;
        for (int f = 0; f < 2; f++) {
            psc_filter_t filter = f ? PSC_FILTER_NEAREST : PSC_FILTER_BILINEAR;
            psc_view_t v = tsup_view_deg(VIEWS[k].yaw, VIEWS[k].pitch, VIEWS[k].hfov, filter, 2), used;
            double psnr = render_psnr(map_i, w, h, fmt, v, 1, &used);
            double bound = f ? NEAREST_MIN_DB : BILINEAR_MIN_DB;
            print_row(MAPS[map_i].name, w, h, fmt, f ? "nearest" : "bilinear", &used, psnr, bound);
            double *worst = f ? worst_near : worst_bil;
            if (psnr < *worst)
                *worst = psnr;
            if (psnr < bound)
                fail_msg("%s %ux%u %s: PSNR %.2f dB < %.0f dB", MAPS[map_i].name, w, h,
                         f ? "nearest" : "bilinear", psnr, bound);
        }
    }
}

static void run_golden(size_t first, size_t last)
{
    double worst_bil = HUGE_VAL, worst_near = HUGE_VAL;
    print_header();
    for (size_t i = first; i <= last; i++)
        golden_map(i, &worst_bil, &worst_near);
    printf("  worst: bilinear %.2f dB (bound %.0f), nearest %.2f dB (bound %.0f)\n", worst_bil, BILINEAR_MIN_DB,
           worst_near, NEAREST_MIN_DB);
}

static void test_golden_equirect_formats(void **state)
{
    (void)state;
    run_golden(0, 2);
}

static void test_golden_projections(void **state)
{
    (void)state;
    run_golden(3, 6);
}

static void test_golden_partial(void **state)
{
    (void)state;
    run_golden(7, NMAPS - 1);
}

/* Every span length, bilinear, one demanding view (seam and a pole in the picture). */
static void test_golden_spans(void **state)
{
    (void)state;
    print_header();
    for (unsigned k = 0; k <= PSC_SPAN_LOG2_MAX; k++) {
        psc_view_t v = tsup_view_deg(179.9, 65.0, 100.0, PSC_FILTER_BILINEAR, k), used;
        double psnr = render_psnr(0, 320, 240, PSC_PIX_XRGB8888, v, 1, &used);
        char label[40];
        snprintf(label, sizeof(label), "equirect/565 N=%u", 1u << k);
        print_row(label, 320, 240, PSC_PIX_XRGB8888, "bilinear", &used, psnr, BILINEAR_MIN_DB);
        if (psnr < BILINEAR_MIN_DB)
            fail_msg("N=%u: PSNR %.2f dB", 1u << k, psnr);
    }
}

/* Against a 4x4 supersampled reference: how much the single-sample viewer aliases (printed, no bound). */
static void test_supersampled_reference(void **state)
{
    (void)state;
    static const view_deg_t v[] = {{0.0, 0.0, 90.0}, {37.0, 90.0, 120.0}, {20.0, 10.0, 30.0}};
    printf("  bilinear viewer vs 4x4 supersampled reference (information: aliasing of one sample per pixel)\n");
    for (size_t i = 0; i < sizeof(v) / sizeof(v[0]); i++) {
        psc_view_t view = tsup_view_deg(v[i].yaw, v[i].pitch, v[i].hfov, PSC_FILTER_BILINEAR, 2), used;
        double p1 = render_psnr(1, 160, 120, PSC_PIX_XRGB8888, view, 1, &used);
        double p4 = render_psnr(1, 160, 120, PSC_PIX_XRGB8888, view, 4, NULL);
        printf("  | equirect/8888 160x120 yaw %6.1f pitch %5.1f hfov %5.1f | vs 1x1 ref %6.2f dB | vs 4x4 ref %6.2f dB\n",
               v[i].yaw, v[i].pitch, v[i].hfov, p1, p4);
        assert_true(p1 >= BILINEAR_MIN_DB);
        assert_true(p4 < p1); /* the supersampled reference differs: it is not the same image */
    }
}

/* ---- render agrees with trace_row --------------------------------------------- */

static void test_render_matches_trace(void **state)
{
    (void)state;
    static const size_t maps[] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 41);
    for (size_t mi = 0; mi < sizeof(maps) / sizeof(maps[0]); mi++) {
        const psc_envmap_t *m = &g_maps[maps[mi]].map;
        int shaped = m->projection == PSC_PROJ_ELLIPTICAL || m->projection == PSC_PROJ_DIAMOND;
        tsup_viewer_t tv;
        assert_int_equal(tsup_viewer_init(&tv, m, 200, 150, PSC_PIX_XRGB8888), PSC_OK);
        int32_t rq[200], cq[200];
        long near_total = 0, near_mismatch = 0;
        double max_bil_diff = 0.0;
        for (int n = 0; n < 6; n++) {
            psc_view_t v;
            v.yaw = tsup_rng_u32(&rng);
            v.pitch = (int32_t)tsup_rng_below(&rng, 2u * PSC_BAM_90 + 1u) - (int32_t)PSC_BAM_90;
            v.hfov = tsup_bam_from_deg(tsup_rng_range(&rng, 30.0, 120.0));
            v.span_log2 = (uint8_t)tsup_rng_below(&rng, PSC_SPAN_LOG2_MAX + 1);
            for (int f = 0; f < 2; f++) {
                v.filter = f ? PSC_FILTER_NEAREST : PSC_FILTER_BILINEAR;
                psc_viewer_clamp(&tv.v, &v, tsup_bam_from_deg(20.0));
                assert_int_equal(psc_viewer_render(&tv.v, &v, &tv.out), PSC_OK);
                for (unsigned y = 0; y < 150; y += 7) {
                    assert_int_equal(psc_viewer_trace_row(&tv.v, &v, (uint16_t)y, rq, cq), PSC_OK);
                    for (unsigned x = 0; x < 200; x++) {
                        uint8_t got[3];
                        double want[3];
                        tsup_surface_rgb(&tv.out, x, y, got);
                        tsup_map_sample(m, rq[x] / 65536.0, cq[x] / 65536.0, v.filter, want);
                        double d = 0.0;
                        for (int c = 0; c < 3; c++)
                            d = fmax(d, fabs(got[c] - want[c]));
                        if (f) {
                            near_total++;
                            if (d != 0.0) {
                                near_mismatch++;
                                if (!shaped)
                                    fail_msg("%s nearest: pixel (%u,%u) is %02x%02x%02x, the texel at the traced "
                                             "position (%.5f, %.5f) is %02x%02x%02x",
                                             MAPS[maps[mi]].name, x, y, got[0], got[1], got[2], rq[x] / 65536.0,
                                             cq[x] / 65536.0, (int)want[0], (int)want[1], (int)want[2]);
                            }
                        } else {
                            if (d > max_bil_diff)
                                max_bil_diff = d;
                            if (d > 2.0)
                                fail_msg("%s bilinear: pixel (%u,%u) is %02x%02x%02x, bilinear at the traced "
                                         "position (%.5f, %.5f) is %.2f %.2f %.2f",
                                         MAPS[maps[mi]].name, x, y, got[0], got[1], got[2], rq[x] / 65536.0,
                                         cq[x] / 65536.0, want[0], want[1], want[2]);
                        }
                    }
                }
            }
        }
        printf("  %-26s render vs trace: nearest %ld/%ld texels differ, bilinear max diff %.2f levels\n",
               MAPS[maps[mi]].name, near_mismatch, near_total, max_bil_diff);
        /* Shaped rows: core scales the column in Q16.16, the reference in double; a rounding tie may differ. */
        assert_true(near_mismatch * 1000 <= near_total);
        tsup_viewer_free(&tv);
    }
}

/* ---- determinism, guards, markers, arguments ----------------------------------------- */

static void test_determinism(void **state)
{
    (void)state;
    const psc_envmap_t *m = &g_maps[0].map;
    tsup_viewer_t a, b;
    assert_int_equal(tsup_viewer_init(&a, m, 320, 240, PSC_PIX_RGB565), PSC_OK);
    assert_int_equal(tsup_viewer_init(&b, m, 320, 240, PSC_PIX_RGB565), PSC_OK);
    size_t bytes = (size_t)a.out.stride * 240;
    uint8_t *first = malloc(bytes);
    assert_non_null(first);
    psc_view_t v1 = tsup_view_deg(179.9, 80.0, 61.0, PSC_FILTER_BILINEAR, 2);
    psc_view_t v2 = tsup_view_deg(-30.0, -10.0, 30.0, PSC_FILTER_NEAREST, 4);
    assert_int_equal(psc_viewer_render(&a.v, &v1, &a.out), PSC_OK);
    memcpy(first, a.out_buf, bytes);
    /* The same view again, after a different zoom and filter, and on a fresh viewer. */
    assert_int_equal(psc_viewer_render(&a.v, &v1, &a.out), PSC_OK);
    assert_memory_equal(first, a.out_buf, bytes);
    assert_int_equal(psc_viewer_render(&a.v, &v2, &a.out), PSC_OK);
    assert_memory_not_equal(first, a.out_buf, bytes);
    assert_int_equal(psc_viewer_render(&a.v, &v1, &a.out), PSC_OK);
    assert_memory_equal(first, a.out_buf, bytes);
    assert_int_equal(psc_viewer_render(&b.v, &v1, &b.out), PSC_OK);
    assert_memory_equal(first, b.out_buf, bytes);
    assert_true(tsup_viewer_guard_ok(&a));
    assert_true(tsup_viewer_guard_ok(&b));
    free(first);
    tsup_viewer_free(&a);
    tsup_viewer_free(&b);
}

static int color_near(const uint8_t got[3], uint32_t want, int tol)
{
    int w[3] = {(int)(want >> 16 & 255), (int)(want >> 8 & 255), (int)(want & 255)};
    for (int c = 0; c < 3; c++)
        if (abs(got[c] - w[c]) > tol)
            return 0;
    return 1;
}

/* A marker's colour as the map stores it (quantised to the map's format). */
static uint32_t stored_color(const psc_envmap_t *m, tsup_marker_t k)
{
    uint32_t c;
    tsup_marker(k, NULL, NULL, &c);
    double r = c >> 16 & 255, g = c >> 8 & 255, b = c & 255;
    if (m->format == PSC_PIX_RGB565)
        return tsup_rgb565_to_rgb888(tsup_rgb888_to_rgb565(r, g, b));
    if (m->format == PSC_PIX_PAL8)
        return m->palette[tsup_pal8_index(r, g, b)] & 0xFFFFFFu;
    return c;
}

/* The conventions, visibly: each marker at the centre of the view that looks at it, on every projection. */
static void test_markers(void **state)
{
    (void)state;
    static const struct {
        tsup_marker_t k;
        double yaw, pitch;
    } looks[] = {
        {TSUP_MARK_LON0, 0.0, 0.0},      {TSUP_MARK_LON90E, 90.0, 0.0}, {TSUP_MARK_LON90W, -90.0, 0.0},
        {TSUP_MARK_LON180, 180.0, 0.0},  {TSUP_MARK_NORTH, 25.0, 90.0}, {TSUP_MARK_SOUTH, -70.0, -90.0},
    };
    for (size_t mi = 0; mi < 7; mi++) {
        const psc_envmap_t *m = &g_maps[mi].map;
        tsup_viewer_t tv;
        assert_int_equal(tsup_viewer_init(&tv, m, 161, 121, PSC_PIX_XRGB8888), PSC_OK);
        for (size_t i = 0; i < sizeof(looks) / sizeof(looks[0]); i++) {
            if (m->projection == PSC_PROJ_CYLINDER && looks[i].pitch != 0.0)
                continue; /* a cylinder map has no poles */
            psc_view_t v = tsup_view_deg(looks[i].yaw, looks[i].pitch, 30.0, PSC_FILTER_BILINEAR, 2);
            assert_int_equal(psc_viewer_render(&tv.v, &v, &tv.out), PSC_OK);
            uint32_t want = stored_color(m, looks[i].k);
            /* The disk is 4 deg in radius: at 30 deg hfov over 161 px the centre +-5 px is well inside. */
            for (int dy = -5; dy <= 5; dy += 5)
                for (int dx = -5; dx <= 5; dx += 5) {
                    uint8_t got[3];
                    tsup_surface_rgb(&tv.out, (unsigned)(80 + dx), (unsigned)(60 + dy), got);
                    if (!color_near(got, want, 6))
                        fail_msg("%s, yaw %.0f pitch %.0f: pixel (%d,%d) is %02x%02x%02x, marker colour %06x",
                                 MAPS[mi].name, looks[i].yaw, looks[i].pitch, 80 + dx, 60 + dy, got[0], got[1],
                                 got[2], want);
                }
        }
        tsup_viewer_free(&tv);
    }
}

static void test_arguments(void **state)
{
    (void)state;
    const psc_envmap_t *m = &g_maps[0].map;
    tsup_viewer_t tv;
    assert_int_equal(tsup_viewer_init(&tv, m, 64, 48, PSC_PIX_RGB565), PSC_OK);
    psc_view_t ok = tsup_view_deg(0.0, 0.0, 90.0, PSC_FILTER_BILINEAR, 2), v;
    int32_t rq[64], cq[64];
    assert_int_equal(psc_viewer_render(&tv.v, &ok, &tv.out), PSC_OK);
    v = ok;
    v.span_log2 = PSC_SPAN_LOG2_MAX + 1;
    assert_int_equal(psc_viewer_render(&tv.v, &v, &tv.out), PSC_ERR_ARG);
    v = ok;
    v.pitch = (int32_t)PSC_BAM_90 + 1;
    assert_int_equal(psc_viewer_render(&tv.v, &v, &tv.out), PSC_ERR_ARG);
    v = ok;
    v.hfov = psc_viewer_hfov_max(&tv.v) + 1u;
    assert_int_equal(psc_viewer_render(&tv.v, &v, &tv.out), PSC_ERR_ARG);
    assert_int_equal(psc_viewer_trace_row(&tv.v, &v, 0, rq, cq), PSC_ERR_ARG);
    v = ok;
    v.hfov = 0;
    assert_int_equal(psc_viewer_render(&tv.v, &v, &tv.out), PSC_ERR_ARG);
    v = ok;
    v.filter = (psc_filter_t)7;
    assert_int_equal(psc_viewer_render(&tv.v, &v, &tv.out), PSC_ERR_ARG);
    assert_int_equal(psc_viewer_trace_row(&tv.v, &ok, 48, rq, cq), PSC_ERR_ARG); /* row out of range */
    /* Wrong surfaces. */
    psc_surface_t s = tv.out;
    s.width = 63;
    assert_int_not_equal(psc_viewer_render(&tv.v, &ok, &s), PSC_OK);
    s = tv.out;
    s.stride = 64 * 2 - 1;
    assert_int_not_equal(psc_viewer_render(&tv.v, &ok, &s), PSC_OK);
    s = tv.out;
    s.format = PSC_PIX_PAL8;
    assert_int_not_equal(psc_viewer_render(&tv.v, &ok, &s), PSC_OK);
    assert_true(tsup_viewer_guard_ok(&tv)); /* refused renders wrote nothing */
    /* The widest table serves hfov 120 exactly as the pack's defaults promise. */
    assert_true(psc_viewer_hfov_max(&tv.v) >= tsup_bam_from_deg(120.0) - 2u);
    tsup_viewer_free(&tv);

    /* Init: workspace too small, misaligned, tables out of order. */
    psc_viewer_t vw;
    size_t need = psc_viewer_workspace_size(64, 48, m);
    uint64_t *ws = malloc(need + 16);
    assert_non_null(ws);
    tsup_luts_t l;
    const double hf[2] = {60.0, 120.0};
    assert_int_equal(tsup_luts_build(&l, 64, 48, hf, 2, 0, 0), 0);
    assert_int_equal(psc_viewer_init(&vw, m, l.luts, 2, 64, 48, ws, need), PSC_OK);
    assert_int_not_equal(psc_viewer_init(&vw, m, l.luts, 2, 64, 48, ws, need - 1), PSC_OK);
    assert_int_not_equal(psc_viewer_init(&vw, m, l.luts, 2, 64, 48, (uint8_t *)ws + 4, need), PSC_OK);
    psc_lut_t swapped[2] = {l.luts[1], l.luts[0]};
    assert_int_not_equal(psc_viewer_init(&vw, m, swapped, 2, 64, 48, ws, need), PSC_OK);
    assert_int_not_equal(psc_viewer_init(&vw, m, l.luts, 0, 64, 48, ws, need), PSC_OK);
    assert_int_not_equal(psc_viewer_init(&vw, m, l.luts, 2, 0, 48, ws, need), PSC_OK);
    assert_int_not_equal(psc_viewer_init(&vw, m, l.luts, 2, PSC_MAX_OUT_DIM + 1, 48, ws, need), PSC_OK);
    tsup_luts_free(&l);
    free(ws);
}

/*
 * The narrowest view: below PSC_HFOV_MIN (1 degree) render and trace refuse
 * with PSC_ERR_ARG (the viewing-plane distance (W/2)/tan(hfov/2) would
 * overflow or divide by zero); from it up the geometry stays exact.
 */
static void test_tiny_hfov(void **state)
{
    (void)state;
    const psc_envmap_t *m = &g_maps[0].map;
    tsup_viewer_t tv;
    assert_int_equal(tsup_viewer_init(&tv, m, 65, 49, PSC_PIX_RGB565), PSC_OK);
    static const psc_bam_t small[] = {1, 2, 3, 4, 5, 16, 255, 4096, 65536, 1u << 20, PSC_HFOV_MIN - 1u};
    int32_t rq[65], cq[65];
    for (size_t i = 0; i < sizeof(small) / sizeof(small[0]); i++) {
        psc_view_t v = tsup_view_deg(30.0, 20.0, 90.0, PSC_FILTER_BILINEAR, 2);
        v.hfov = small[i];
        if (psc_viewer_render(&tv.v, &v, &tv.out) != PSC_ERR_ARG)
            fail_msg("hfov %u bam (below PSC_HFOV_MIN): render did not refuse", small[i]);
        assert_int_equal(psc_viewer_trace_row(&tv.v, &v, 0, rq, cq), PSC_ERR_ARG);
    }
    static const psc_bam_t ok[] = {PSC_HFOV_MIN, PSC_HFOV_MIN + 1u, 2u * PSC_HFOV_MIN, 5u * PSC_HFOV_MIN};
    for (size_t i = 0; i < sizeof(ok) / sizeof(ok[0]); i++) {
        psc_view_t v = tsup_view_deg(30.0, 20.0, 90.0, PSC_FILTER_BILINEAR, 2);
        v.hfov = ok[i];
        assert_int_equal(psc_viewer_render(&tv.v, &v, &tv.out), PSC_OK);
        /* Centre and edge pixels look where the exact rays do (in map pixels). */
        assert_int_equal(psc_viewer_trace_row(&tv.v, &v, 24, rq, cq), PSC_OK);
        for (unsigned x = 0; x < 65; x += 32) {
            double lon, lat, slon, slat;
            tsup_view_ray(&v, 65, 49, x + 0.5, 24.5, &lon, &lat);
            tsup_map_dir(m, rq[x] / 65536.0, cq[x] / 65536.0, &slon, &slat);
            double err_px = tsup_angle_between(lon, lat, slon, slat) * m->width / (2.0 * TSUP_PI);
            if (err_px > 0.1)
                fail_msg("hfov %u bam: pixel %u samples %.3f map px away from its ray", ok[i], x, err_px);
        }
    }
    /* psc_viewer_clamp never lets a view below PSC_HFOV_MIN through, whatever hfov_min it is given. */
    psc_view_t v = tsup_view_deg(0.0, 0.0, 90.0, PSC_FILTER_BILINEAR, 2);
    v.hfov = 3;
    psc_viewer_clamp(&tv.v, &v, 1);
    assert_int_equal(v.hfov, PSC_HFOV_MIN);
    assert_true(tsup_viewer_guard_ok(&tv));
    tsup_viewer_free(&tv);
}

/* ---- partial panoramas: psc_viewer_clamp ------------------------------------------- */

static void test_clamp_partial_stays_inside(void **state)
{
    (void)state;
    static const size_t maps[] = {3, 7, 8, 9, 10}; /* cylinder (partial in lat), and the partial maps */
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 51);
    for (size_t mi = 0; mi < sizeof(maps) / sizeof(maps[0]); mi++) {
        const psc_envmap_t *m = &g_maps[maps[mi]].map;
        tsup_viewer_t tv;
        assert_int_equal(tsup_viewer_init(&tv, m, 160, 120, PSC_PIX_RGB565), PSC_OK);
        int32_t rq[160], cq[160];
        double lo_r = -0.5, hi_r = m->height - 0.5, lo_c = -0.5, hi_c = m->width - 0.5;
        double worst_trace = 1e9, worst_exact = 1e9; /* smallest margin seen, map pixels */
        for (int n = 0; n < 150; n++) {
            psc_view_t v;
            v.yaw = tsup_rng_u32(&rng);
            v.pitch = (int32_t)tsup_rng_u32(&rng); /* anything, even beyond +-90: clamp brings it back */
            v.hfov = tsup_bam_from_deg(tsup_rng_range(&rng, 5.0, 170.0));
            v.filter = PSC_FILTER_BILINEAR;
            v.span_log2 = (uint8_t)tsup_rng_below(&rng, 6);
            psc_viewer_clamp(&tv.v, &v, tsup_bam_from_deg(20.0));
            assert_true(v.pitch >= -(int32_t)PSC_BAM_90 && v.pitch <= (int32_t)PSC_BAM_90);
            assert_true(v.hfov >= tsup_bam_from_deg(20.0) - 1u && v.hfov <= psc_viewer_hfov_max(&tv.v));
            assert_true(v.span_log2 <= PSC_SPAN_LOG2_MAX);
            for (unsigned y = 0; y < 120; y += (y == 0 || y >= 118) ? 1 : 9) {
                assert_int_equal(psc_viewer_trace_row(&tv.v, &v, (uint16_t)y, rq, cq), PSC_OK);
                for (unsigned x = 0; x < 160; x++) {
                    double r = rq[x] / 65536.0, c = cq[x] / 65536.0;
                    double margin = fmin(fmin(r - lo_r, hi_r - r), m->lon_span ? fmin(c - lo_c, hi_c - c) : 1e9);
                    if (margin < worst_trace)
                        worst_trace = margin;
                    if (margin < 0.0)
                        fail_msg("%s: after clamp (yaw 0x%08x pitch %d hfov 0x%08x) pixel (%u,%u) samples "
                                 "(%.4f, %.4f), outside the map",
                                 MAPS[maps[mi]].name, v.yaw, v.pitch, v.hfov, x, y, r, c);
                    /* The exact direction of the pixel lies inside the map too. */
                    double lon, lat, er, ec;
                    tsup_view_ray(&v, 160, 120, x + 0.5, y + 0.5, &lon, &lat);
                    tsup_map_pos(m, lon, lat, &er, &ec);
                    double em = fmin(fmin(er - lo_r, hi_r - er), m->lon_span ? fmin(ec - lo_c, hi_c - ec) : 1e9);
                    if (em < worst_exact)
                        worst_exact = em;
                    if (em < 0.0)
                        fail_msg("%s: after clamp (yaw 0x%08x pitch %d hfov 0x%08x) pixel (%u,%u) looks at map "
                                 "(%.4f, %.4f), outside the map",
                                 MAPS[maps[mi]].name, v.yaw, v.pitch, v.hfov, x, y, er, ec);
                }
            }
        }
        printf("  %-26s 150 random views clamped: smallest margin to the map edge %.3f px traced, %.3f px exact\n",
               MAPS[maps[mi]].name, worst_trace, worst_exact);
        tsup_viewer_free(&tv);
    }
}

static void test_clamp_keeps_fitting_views(void **state)
{
    (void)state;
    /* Views well inside a partial map are left alone; full spheres only get pitch/hfov limits. */
    const psc_envmap_t *part = &g_maps[7].map; /* lon -60..90, lat 50..-35 */
    tsup_viewer_t tv;
    assert_int_equal(tsup_viewer_init(&tv, part, 160, 120, PSC_PIX_RGB565), PSC_OK);
    psc_view_t v = tsup_view_deg(15.0, 5.0, 40.0, PSC_FILTER_BILINEAR, 2), c = v;
    psc_viewer_clamp(&tv.v, &c, tsup_bam_from_deg(20.0));
    assert_int_equal(c.yaw, v.yaw);
    assert_int_equal(c.pitch, v.pitch);
    assert_int_equal(c.hfov, v.hfov);
    /* A view far outside is moved in, not just narrowed. */
    c = tsup_view_deg(-150.0, 80.0, 60.0, PSC_FILTER_BILINEAR, 2);
    psc_viewer_clamp(&tv.v, &c, tsup_bam_from_deg(20.0));
    double yaw = tsup_sbam_to_rad((int32_t)c.yaw) / TSUP_DEG, pitch = tsup_sbam_to_rad(c.pitch) / TSUP_DEG;
    assert_true(yaw > -60.0 && yaw < 90.0);
    assert_true(pitch < 50.0 && pitch > -35.0);
    tsup_viewer_free(&tv);

    const psc_envmap_t *full = &g_maps[0].map;
    assert_int_equal(tsup_viewer_init(&tv, full, 160, 120, PSC_PIX_RGB565), PSC_OK);
    v = tsup_view_deg(-150.0, 90.0, 200.0, PSC_FILTER_NEAREST, 9);
    v.pitch = (int32_t)PSC_BAM_90 + 5000;
    psc_viewer_clamp(&tv.v, &v, tsup_bam_from_deg(20.0));
    assert_int_equal(v.yaw, tsup_bam_from_deg(-150.0));
    assert_int_equal(v.pitch, (int32_t)PSC_BAM_90);
    assert_int_equal(v.hfov, psc_viewer_hfov_max(&tv.v));
    assert_int_equal(v.span_log2, PSC_SPAN_LOG2_MAX);
    v.hfov = tsup_bam_from_deg(5.0);
    psc_viewer_clamp(&tv.v, &v, tsup_bam_from_deg(20.0));
    assert_int_equal(v.hfov, tsup_bam_from_deg(20.0));
    tsup_viewer_free(&tv);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_golden_equirect_formats),
        cmocka_unit_test(test_golden_projections),
        cmocka_unit_test(test_golden_partial),
        cmocka_unit_test(test_golden_spans),
        cmocka_unit_test(test_supersampled_reference),
        cmocka_unit_test(test_render_matches_trace),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_markers),
        cmocka_unit_test(test_arguments),
        cmocka_unit_test(test_tiny_hfov),
        cmocka_unit_test(test_clamp_partial_stays_inside),
        cmocka_unit_test(test_clamp_keeps_fitting_views),
    };
    return cmocka_run_group_tests(tests, setup_maps, teardown_maps);
}
