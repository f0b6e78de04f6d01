/* SPDX-License-Identifier: MIT */
/*
 * test_bands.c - the viewer in bands (core/viewer/psc_viewer.h) and on
 * several threads (io/psc_io_bands.h):
 *  - 600 random views (maps of three projections and three formats, every
 *    filter and span, RGB565 and XRGB8888 output, pitches to the poles)
 *    rendered in 1..8 random bands of random heights give psc_viewer_render's
 *    bytes exactly, every band writing only its rows;
 *  - the worker pool with 1, 2, 3 and 7 threads gives the same bytes, frame
 *    after frame, as the view changes;
 *  - a band of a view that was not prepared, rows outside the output and a
 *    short scratch are refused.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "psc_io_bands.h"
#include "psc_testsupport.h"

#include <stdlib.h>
#include <string.h>

#define MAP_W 512u
#define MAP_H 256u
#define OUT_W 160u
#define OUT_H 120u

typedef struct {
    psc_projection_t proj;
    psc_pixfmt_t fmt;
} map_kind_t;

static const map_kind_t KINDS[] = {
    {PSC_PROJ_EQUIRECT, PSC_PIX_RGB565},
    {PSC_PROJ_EQUIRECT, PSC_PIX_XRGB8888},
    {PSC_PROJ_CYLINDER, PSC_PIX_PAL8},
    {PSC_PROJ_ELLIPTICAL, PSC_PIX_RGB565},
};

/* Scribble over the pixels (not the stride's guard bytes) so that a row no band draws shows. */
static void clear_rows(const psc_surface_t *s)
{
    for (unsigned y = 0; y < s->height; y++)
        memset((uint8_t *)s->pixels + (size_t)y * s->stride, 0x5A, (size_t)s->width * psc_pixfmt_bytes(s->format));
}

/* A synthetic map of kind k and a viewer of it with out_fmt output. */
static void open_map(const map_kind_t *k, psc_pixfmt_t out_fmt, tsup_map_t *m, tsup_viewer_t *tv)
{
    psc_envmap_t g = {0};
    g.projection = k->proj;
    g.format = k->fmt;
    g.width = MAP_W;
    g.height = MAP_H;
    assert_int_equal(tsup_synth_map(m, &g, 1, 0), 0);
    assert_int_equal(tsup_viewer_init(tv, &m->map, OUT_W, OUT_H, out_fmt), PSC_OK);
}

static psc_view_t random_view(tsup_rng_t *r)
{
    static const psc_filter_t filters[] = {PSC_FILTER_NEAREST, PSC_FILTER_BILINEAR, PSC_FILTER_MIP};
    return tsup_view_deg(tsup_rng_range(r, -180, 180), tsup_rng_range(r, -90, 90), tsup_rng_range(r, 20, 110),
                         filters[tsup_rng_below(r, 3)], tsup_rng_below(r, 5));
}

static void test_bands_equal_whole(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 2024);
    unsigned frames = 0, bands = 0;
    for (unsigned k = 0; k < sizeof KINDS / sizeof KINDS[0]; k++) {
        for (int fmt = 0; fmt < 2; fmt++) {
            tsup_map_t m;
            tsup_viewer_t tv;
            open_map(&KINDS[k], fmt ? PSC_PIX_XRGB8888 : PSC_PIX_RGB565, &m, &tv);
            size_t bytes = (size_t)tv.out.stride * OUT_H, sn = psc_viewer_band_scratch_size(OUT_W);
            uint8_t *whole = malloc(bytes);
            void *scratch;
            assert_non_null(whole);
            assert_int_equal(posix_memalign(&scratch, 64, sn), 0);
            for (unsigned i = 0; i < 75; i++) {
                psc_view_t view = random_view(&r);
                psc_viewer_clamp(&tv.v, &view, 0);
                assert_int_equal(psc_viewer_render(&tv.v, &view, &tv.out), PSC_OK);
                memcpy(whole, tv.out.pixels, bytes);
                clear_rows(&tv.out);
                /* random bands, in a random order of rendering (every other band first) */
                unsigned cut[10], n = 1 + tsup_rng_below(&r, 8);
                cut[0] = 0;
                for (unsigned b = 1; b < n; b++)
                    cut[b] = tsup_rng_below(&r, OUT_H + 1);
                cut[n] = OUT_H;
                for (unsigned a = 1; a < n; a++)   /* sort the cuts */
                    for (unsigned b = a + 1; b < n; b++)
                        if (cut[b] < cut[a]) {
                            unsigned t = cut[a];
                            cut[a] = cut[b], cut[b] = t;
                        }
                assert_int_equal(psc_viewer_prepare(&tv.v, &view), PSC_OK);
                for (unsigned pass = 0; pass < 2; pass++)
                    for (unsigned b = pass; b < n; b += 2) {
                        assert_int_equal(psc_viewer_render_band(&tv.v, &view, &tv.out, cut[b], cut[b + 1],
                                                                scratch, sn),
                                         PSC_OK);
                        bands++;
                    }
                assert_memory_equal(whole, tv.out.pixels, bytes);
                assert_true(tsup_viewer_guard_ok(&tv));
                frames++;
            }
            free(whole);
            free(scratch);
            tsup_viewer_free(&tv);
            tsup_map_free(&m);
        }
    }
    print_message("  %u random views in %u bands: the whole frame's bytes\n", frames, bands);
}

static void test_pool_equal_whole(void **state)
{
    (void)state;
    tsup_map_t m;
    tsup_viewer_t tv;
    open_map(&KINDS[0], PSC_PIX_XRGB8888, &m, &tv);
    size_t bytes = (size_t)tv.out.stride * OUT_H;
    uint8_t *whole = malloc(bytes);
    assert_non_null(whole);
    static const unsigned threads[] = {1, 2, 3, 7};
    tsup_rng_t r;
    tsup_rng_seed(&r, 77);
    for (unsigned t = 0; t < 4; t++) {
        char err[128];
        psc_io_bands_t *pool = psc_io_bands_start(threads[t], OUT_W, err, sizeof err);
        assert_non_null(pool);
        assert_int_equal(psc_io_bands_threads(pool), threads[t]);
        for (unsigned i = 0; i < 40; i++) {
            psc_view_t view = random_view(&r);
            psc_viewer_clamp(&tv.v, &view, 0);
            assert_int_equal(psc_viewer_render(&tv.v, &view, &tv.out), PSC_OK);
            memcpy(whole, tv.out.pixels, bytes);
            clear_rows(&tv.out);
            assert_int_equal(psc_io_bands_render(pool, &tv.v, &view, &tv.out), PSC_OK);
            assert_memory_equal(whole, tv.out.pixels, bytes);
        }
        psc_io_bands_stop(pool);
    }
    char err[128];
    assert_null(psc_io_bands_start(0, OUT_W, err, sizeof err));
    assert_null(psc_io_bands_start(PSC_IO_BANDS_MAX_THREADS + 1, OUT_W, err, sizeof err));
    assert_true(psc_io_online_cpus() >= 1);
    psc_io_bands_t *narrow = psc_io_bands_start(2, OUT_W - 1, err, sizeof err);   /* for a narrower viewer */
    psc_view_t view = tsup_view_deg(0, 0, 60, PSC_FILTER_NEAREST, 2);
    assert_int_equal(psc_io_bands_render(narrow, &tv.v, &view, &tv.out), PSC_ERR_ARG);
    psc_io_bands_stop(narrow);
    free(whole);
    tsup_viewer_free(&tv);
    tsup_map_free(&m);
}

static void test_band_refusals(void **state)
{
    (void)state;
    tsup_map_t m;
    tsup_viewer_t tv;
    open_map(&KINDS[0], PSC_PIX_RGB565, &m, &tv);
    size_t sn = psc_viewer_band_scratch_size(OUT_W);
    void *scratch;
    assert_int_equal(posix_memalign(&scratch, 64, sn), 0);
    psc_view_t a = tsup_view_deg(10, 0, 70, PSC_FILTER_BILINEAR, 2), b = tsup_view_deg(10, 0, 50, PSC_FILTER_BILINEAR, 2);
    assert_int_equal(psc_viewer_render_band(&tv.v, &a, &tv.out, 0, 10, scratch, sn), PSC_ERR_ARG);   /* never */
    assert_int_equal(psc_viewer_prepare(&tv.v, &a), PSC_OK);
    assert_int_equal(psc_viewer_render_band(&tv.v, &a, &tv.out, 0, 10, scratch, sn), PSC_OK);
    assert_int_equal(psc_viewer_render_band(&tv.v, &b, &tv.out, 0, 10, scratch, sn), PSC_ERR_ARG); /* other hfov */
    assert_int_equal(psc_viewer_render_band(&tv.v, &a, &tv.out, 10, OUT_H + 1, scratch, sn), PSC_ERR_ARG);
    assert_int_equal(psc_viewer_render_band(&tv.v, &a, &tv.out, 20, 10, scratch, sn), PSC_ERR_ARG);
    assert_int_equal(psc_viewer_render_band(&tv.v, &a, &tv.out, 0, 10, scratch, sn - 1), PSC_ERR_ARG);
    assert_int_equal(psc_viewer_render_band(&tv.v, &a, &tv.out, 0, 10, (uint8_t *)scratch + 4, sn), PSC_ERR_ARG);
    psc_view_t bad = a;
    bad.pitch = (int32_t)tsup_bam_from_deg(91);
    assert_int_equal(psc_viewer_prepare(&tv.v, &bad), PSC_ERR_ARG);
    free(scratch);
    tsup_viewer_free(&tv);
    tsup_map_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bands_equal_whole),
        cmocka_unit_test(test_pool_equal_whole),
        cmocka_unit_test(test_band_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
