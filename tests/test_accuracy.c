/* SPDX-License-Identifier: MIT */
/*
 * test_accuracy.c - where the viewer samples, against the exact geometry.
 *
 * For every traced output pixel (psc_viewer_trace_row) the map position is
 * turned back into a direction and compared with the exact ray of that pixel
 * (tests/support: ray -> lon/lat in double). The error metric is the angle
 * between the two directions in equatorial map pixels, angle * W / span
 * (span = 2 pi for a full turn): well defined everywhere, the poles included.
 * Away from the poles (|lat| < 80 deg) the raw (row, col) errors are reported
 * too, the column difference taken modulo W.
 *
 * Pass/fail (1024 x 512 equirect map, 320 x 240 output, hfov 30..120):
 *   N = 1, 2, 4:  mean <= 0.05 px, max <= 0.5 px
 *   N = 8:        mean <= 0.08 px, max <= 0.6 px
 *   N = 16:       mean <= 0.12 px, max <= 0.8 px
 *   (interpolating indices over longer spans bows away from the exact
 *   curve by ~N^2; the measured figures are printed.)
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

typedef struct {
    double max_px, sum_px;
    long n;
    double max_row, sum_row, max_col, sum_col;
    long n_rc;
    double worst_yaw, worst_pitch, worst_hfov; /* the view of max_px, degrees */
    unsigned worst_x, worst_y;
} acc_stats_t;

static const struct {
    double mean, max;
} SPAN_BOUNDS[PSC_SPAN_LOG2_MAX + 1] = {
    {0.05, 0.5}, /* N = 1 */
    {0.05, 0.5}, /* N = 2 */
    {0.05, 0.5}, /* N = 4 */
    {0.08, 0.6}, /* N = 8: measured max 0.32, mean 0.040 */
    {0.12, 0.8}, /* N = 16: measured max 0.24, mean 0.036 (the polar caps widen with N) */
};

static void stats_init(acc_stats_t *s)
{
    memset(s, 0, sizeof(*s));
}

/* Trace rows y0, y0 + row_step, ... of a view and accumulate its errors. */
static void trace_view(tsup_viewer_t *tv, const psc_envmap_t *m, const psc_view_t *view, unsigned row_step,
                       acc_stats_t *st)
{
    unsigned W = tv->v.out_width, H = tv->v.out_height;
    int32_t *rq = malloc(W * sizeof(int32_t)), *cq = malloc(W * sizeof(int32_t));
    assert_non_null(rq);
    assert_non_null(cq);
    double px_per_rad = m->width / tsup_map_lon_span(m);
    int full_turn = m->lon_span == 0;
    for (unsigned y = (row_step > 1 ? (unsigned)(view->yaw % row_step) : 0); y < H; y += row_step) {
        psc_status_t s = psc_viewer_trace_row(&tv->v, view, (uint16_t)y, rq, cq);
        if (s != PSC_OK)
            fail_msg("trace_row(yaw 0x%08x, pitch %d, hfov 0x%08x, y %u) = %s", view->yaw, view->pitch, view->hfov, y,
                     psc_status_str(s));
        for (unsigned x = 0; x < W; x++) {
            double row = rq[x] / 65536.0, col = cq[x] / 65536.0;
            double lon, lat, slon, slat;
            tsup_view_ray(view, W, H, x + 0.5, y + 0.5, &lon, &lat);
            tsup_map_dir(m, row, col, &slon, &slat);
            double err = tsup_angle_between(lon, lat, slon, slat) * px_per_rad;
            st->sum_px += err;
            st->n++;
            if (err > st->max_px) {
                st->max_px = err;
                st->worst_yaw = tsup_sbam_to_rad((int32_t)view->yaw) / TSUP_DEG;
                st->worst_pitch = tsup_sbam_to_rad(view->pitch) / TSUP_DEG;
                st->worst_hfov = tsup_bam_to_rad(view->hfov) / TSUP_DEG;
                st->worst_x = x;
                st->worst_y = y;
            }
            if (fabs(lat) < 80.0 * TSUP_DEG) {
                double erow, ecol;
                tsup_map_pos(m, lon, lat, &erow, &ecol);
                double dr = fabs(row - erow), dc = col - ecol;
                if (full_turn) {
                    dc = fmod(dc, (double)m->width);
                    if (dc > m->width / 2.0)
                        dc -= m->width;
                    if (dc < -m->width / 2.0)
                        dc += m->width;
                }
                dc = fabs(dc);
                st->sum_row += dr;
                st->sum_col += dc;
                st->n_rc++;
                if (dr > st->max_row)
                    st->max_row = dr;
                if (dc > st->max_col)
                    st->max_col = dc;
            }
        }
    }
    free(rq);
    free(cq);
}

static void print_stats(const char *label, const acc_stats_t *st)
{
    printf("  %-34s angle px: max %.4f mean %.5f | |lat|<80: row max %.4f mean %.5f, col max %.4f mean %.5f "
           "(%ld px; worst at yaw %.2f pitch %.2f hfov %.2f, pixel %u,%u)\n",
           label, st->max_px, st->sum_px / st->n, st->max_row, st->n_rc ? st->sum_row / st->n_rc : 0.0, st->max_col,
           st->n_rc ? st->sum_col / st->n_rc : 0.0, st->n, st->worst_yaw, st->worst_pitch, st->worst_hfov,
           st->worst_x, st->worst_y);
}

/* A random view: any yaw, pitch over [-90, 90] with the poles exactly one time in eight, hfov 30..120. */
static psc_view_t random_view(tsup_rng_t *rng, unsigned span_log2, double hfov_lo, double hfov_hi)
{
    psc_view_t v;
    v.yaw = tsup_rng_u32(rng);
    uint32_t k = tsup_rng_below(rng, 8);
    if (k == 0)
        v.pitch = (int32_t)PSC_BAM_90;
    else if (k == 1)
        v.pitch = -(int32_t)PSC_BAM_90;
    else
        v.pitch = (int32_t)tsup_rng_below(rng, 2u * PSC_BAM_90 + 1u) - (int32_t)PSC_BAM_90;
    v.hfov = tsup_bam_from_deg(tsup_rng_range(rng, hfov_lo, hfov_hi));
    v.filter = PSC_FILTER_BILINEAR;
    v.span_log2 = (uint8_t)span_log2;
    return v;
}

static psc_envmap_t map_desc(psc_projection_t p, uint16_t w, uint16_t h, void *pixels)
{
    psc_envmap_t m = {0};
    m.projection = p;
    m.format = PSC_PIX_RGB565;
    m.width = w;
    m.height = h;
    m.stride = (uint32_t)w * 2u;
    m.pixels = pixels;
    psc_envmap_default_coverage(&m);
    return m;
}

/* ---- tests ------------------------------------------------------------------------- */

static void test_conventions(void **state)
{
    (void)state;
    /* Odd output: the centre pixel's ray is the view axis exactly. */
    uint16_t *px = calloc(1024 * 512, 2);
    assert_non_null(px);
    psc_envmap_t m = map_desc(PSC_PROJ_EQUIRECT, 1024, 512, px);
    assert_int_equal(m.lon_min, PSC_BAM_180); /* the map's centre column looks ahead */
    assert_int_equal(m.lat_top, (int32_t)PSC_BAM_90);
    assert_int_equal(m.lat_bottom, -(int32_t)PSC_BAM_90);
    assert_int_equal(m.lon_span, 0);
    tsup_viewer_t tv;
    assert_int_equal(tsup_viewer_init(&tv, &m, 161, 121, PSC_PIX_RGB565), PSC_OK);
    int32_t rq[161], cq[161];
    static const struct {
        double yaw, pitch, col, row;
    } c[] = {
        {0.0, 0.0, 511.5, 255.5},    /* straight ahead: the map's centre */
        {90.0, 0.0, 767.5, 255.5},   /* yaw > 0 turns right: larger columns */
        {-45.0, 0.0, 383.5, 255.5},
        {0.0, 30.0, 511.5, 170.1667}, /* pitch > 0 looks up: smaller rows */
        {0.0, -60.0, 511.5, 426.1667},
        {179.9, 10.0, 1023.2156, 227.0556}, /* (179.9/360 + .5) * 1024 - .5; (80/180) * 512 - .5 */
    };
    for (size_t i = 0; i < sizeof(c) / sizeof(c[0]); i++) {
        psc_view_t v = tsup_view_deg(c[i].yaw, c[i].pitch, 90.0, PSC_FILTER_BILINEAR, 0);
        assert_int_equal(psc_viewer_trace_row(&tv.v, &v, 60, rq, cq), PSC_OK);
        double col = cq[80] / 65536.0, row = rq[80] / 65536.0;
        /* 0.02 pixel: the centre pixel lies midway between two LUT samples (span boundaries) */
        if (fabs(col - c[i].col) > 0.02 || fabs(row - c[i].row) > 0.02)
            fail_msg("view yaw %.1f pitch %.1f: centre pixel samples (row %.4f, col %.4f), expected (%.4f, %.4f)",
                     c[i].yaw, c[i].pitch, row, col, c[i].row, c[i].col);
        /* right of centre: larger columns; above centre: smaller rows (pitch 0 views) */
        if (c[i].pitch == 0.0) {
            assert_true(cq[150] > cq[80]);
            assert_true(cq[10] < cq[80]);
            int32_t rq_up[161], cq_up[161];
            assert_int_equal(psc_viewer_trace_row(&tv.v, &v, 10, rq_up, cq_up), PSC_OK);
            assert_true(rq_up[80] < rq[80]);
        }
    }
    tsup_viewer_free(&tv);
    free(px);
}

static void run_equirect_spans(uint16_t out_w, uint16_t out_h, int assert_bounds)
{
    uint16_t *px = calloc(1024 * 512, 2);
    assert_non_null(px);
    psc_envmap_t m = map_desc(PSC_PROJ_EQUIRECT, 1024, 512, px);
    tsup_viewer_t tv;
    assert_int_equal(tsup_viewer_init(&tv, &m, out_w, out_h, PSC_PIX_RGB565), PSC_OK);
    for (unsigned k = 0; k <= PSC_SPAN_LOG2_MAX; k++) {
        tsup_rng_t rng;
        tsup_rng_seed(&rng, 100 + k);
        acc_stats_t st;
        stats_init(&st);
        unsigned views = k == 2 ? 60 : 24, step = k == 2 ? 1 : 3;
        for (unsigned i = 0; i < views; i++) {
            psc_view_t v = random_view(&rng, k, 30.0, 120.0);
            trace_view(&tv, &m, &v, step, &st);
        }
        char label[64];
        snprintf(label, sizeof(label), "equirect 1024x512, %ux%u, N=%u:", out_w, out_h, 1u << k);
        print_stats(label, &st);
        if (assert_bounds) {
            double mean = st.sum_px / st.n;
            if (mean > SPAN_BOUNDS[k].mean || st.max_px > SPAN_BOUNDS[k].max)
                fail_msg("N=%u: error mean %.4f px (bound %.2f), max %.4f px (bound %.2f) at yaw %.3f pitch %.3f "
                         "hfov %.3f pixel (%u, %u)",
                         1u << k, mean, SPAN_BOUNDS[k].mean, st.max_px, SPAN_BOUNDS[k].max, st.worst_yaw,
                         st.worst_pitch, st.worst_hfov, st.worst_x, st.worst_y);
        }
    }
    tsup_viewer_free(&tv);
    free(px);
}

static void test_equirect_all_spans(void **state)
{
    (void)state;
    run_equirect_spans(320, 240, 1);
}

static void test_equirect_odd_sizes(void **state)
{
    (void)state;
    run_equirect_spans(173, 97, 1);
    run_equirect_spans(160, 120, 1);
}

/* The poles and the seam, deliberately: every hfov the tables serve at pitch +-90 and near it. */
static void test_poles_and_seam(void **state)
{
    (void)state;
    uint16_t *px = calloc(1024 * 512, 2);
    assert_non_null(px);
    psc_envmap_t m = map_desc(PSC_PROJ_EQUIRECT, 1024, 512, px);
    tsup_viewer_t tv;
    assert_int_equal(tsup_viewer_init(&tv, &m, 320, 240, PSC_PIX_RGB565), PSC_OK);
    static const double pitches[] = {90.0, -90.0, 89.99, -89.99, 85.0, 75.0, 60.0, 45.0};
    static const double yaws[] = {0.0, 179.9, -180.0, 180.0 - 1e-6, 90.0, 33.3};
    static const double hfovs[] = {30.0, 60.0, 61.0, 90.0, 120.0};
    acc_stats_t st;
    stats_init(&st);
    for (size_t p = 0; p < sizeof(pitches) / sizeof(pitches[0]); p++)
        for (size_t y = 0; y < sizeof(yaws) / sizeof(yaws[0]); y++)
            for (size_t h = 0; h < sizeof(hfovs) / sizeof(hfovs[0]); h++) {
                psc_view_t v = tsup_view_deg(yaws[y], pitches[p], hfovs[h], PSC_FILTER_BILINEAR, 2);
                trace_view(&tv, &m, &v, 4, &st);
            }
    print_stats("equirect poles/seam, 320x240, N=4:", &st);
    if (st.sum_px / st.n > SPAN_BOUNDS[2].mean || st.max_px > SPAN_BOUNDS[2].max)
        fail_msg("poles/seam: error mean %.4f px, max %.4f px at yaw %.3f pitch %.3f hfov %.3f pixel (%u, %u)",
                 st.sum_px / st.n, st.max_px, st.worst_yaw, st.worst_pitch, st.worst_hfov, st.worst_x, st.worst_y);
    tsup_viewer_free(&tv);
    free(px);
}

/* Every projection at N = 4 (views inside the map's coverage after psc_viewer_clamp). */
static void test_projections(void **state)
{
    (void)state;
    static const psc_projection_t projs[] = {PSC_PROJ_EQUIRECT, PSC_PROJ_CYLINDER, PSC_PROJ_SINE,
                                             PSC_PROJ_ELLIPTICAL, PSC_PROJ_DIAMOND};
    uint16_t *px = calloc(1024 * 512, 2);
    assert_non_null(px);
    for (size_t i = 0; i < sizeof(projs) / sizeof(projs[0]); i++) {
        psc_envmap_t m = map_desc(projs[i], 1024, 512, px);
        tsup_viewer_t tv;
        assert_int_equal(tsup_viewer_init(&tv, &m, 320, 240, PSC_PIX_RGB565), PSC_OK);
        tsup_rng_t rng;
        tsup_rng_seed(&rng, 200 + i);
        acc_stats_t st;
        stats_init(&st);
        for (unsigned k = 0; k < 24; k++) {
            psc_view_t v = random_view(&rng, 2, 30.0, 120.0);
            psc_viewer_clamp(&tv.v, &v, tsup_bam_from_deg(20.0));
            trace_view(&tv, &m, &v, 2, &st);
        }
        char label[64];
        snprintf(label, sizeof(label), "%s 1024x512, 320x240, N=4:", psc_projection_name(projs[i]));
        print_stats(label, &st);
        /* Non-linear row profiles (tan, sin) go through a 4097-entry table: allow 2x the equirect bounds. */
        double kmean = projs[i] == PSC_PROJ_EQUIRECT ? 1.0 : 2.0;
        if (st.sum_px / st.n > SPAN_BOUNDS[2].mean * kmean || st.max_px > SPAN_BOUNDS[2].max * kmean)
            fail_msg("%s: error mean %.4f px, max %.4f px at yaw %.3f pitch %.3f hfov %.3f pixel (%u, %u)",
                     psc_projection_name(projs[i]), st.sum_px / st.n, st.max_px, st.worst_yaw, st.worst_pitch,
                     st.worst_hfov, st.worst_x, st.worst_y);
        tsup_viewer_free(&tv);
    }
    free(px);
}

/* The same at a 4096 x 2048 map: index errors in map pixels grow with W (reported; bounds scaled by 4). */
static void test_large_map(void **state)
{
    (void)state;
    uint16_t *px = calloc((size_t)4096 * 2048, 2);
    assert_non_null(px);
    psc_envmap_t m = map_desc(PSC_PROJ_EQUIRECT, 4096, 2048, px);
    tsup_viewer_t tv;
    assert_int_equal(tsup_viewer_init(&tv, &m, 320, 240, PSC_PIX_RGB565), PSC_OK);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 300);
    acc_stats_t st;
    stats_init(&st);
    for (unsigned k = 0; k < 24; k++) {
        psc_view_t v = random_view(&rng, 2, 30.0, 120.0);
        trace_view(&tv, &m, &v, 3, &st);
    }
    print_stats("equirect 4096x2048, 320x240, N=4:", &st);
    if (st.sum_px / st.n > 4 * SPAN_BOUNDS[2].mean || st.max_px > 4 * SPAN_BOUNDS[2].max)
        fail_msg("4096x2048: error mean %.4f px, max %.4f px", st.sum_px / st.n, st.max_px);
    tsup_viewer_free(&tv);
    free(px);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_conventions),
        cmocka_unit_test(test_equirect_all_spans),
        cmocka_unit_test(test_equirect_odd_sizes),
        cmocka_unit_test(test_poles_and_seam),
        cmocka_unit_test(test_projections),
        cmocka_unit_test(test_large_map),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
