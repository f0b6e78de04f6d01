/* SPDX-License-Identifier: MIT */
/*
 * test_simd.c - the viewer's vector scanlines (core/viewer/psc_viewer_simd.h)
 * give the scalar path's bytes:
 *  - every path this build and CPU have (baseline vectors: SSE2 or NEON;
 *    AVX2) against the scalar path on random views of maps of four formats
 *    and three projections, every filter and span, RGB565 and XRGB8888
 *    output, at widths with and without a lane tail and one the span does
 *    not divide, pitches to the poles;
 *  - maps whose rows are not 4-byte aligned (the AVX2 kernel reads aligned
 *    words, so AUTO must take another path there) and maps whose width is not
 *    a power of two (scalar) give the same bytes;
 *  - the map pyramid (PSC_FILTER_MIP) through each path: packs of a random
 *    image in four formats with every level, random views zoomed in and out;
 *  - an RGB888 map's frames are an XRGB8888 map's of the same picture, every
 *    sampler, projection and output;
 *  - psc_viewer_set_simd refuses what the build or CPU lacks and names
 *    the path it draws with.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "psc_io_pack_build.h"
#include "pack/psc_pack.h"
#include "psc_testsupport.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    psc_projection_t proj;
    psc_pixfmt_t fmt;
    uint16_t w, h;
    uint32_t stride_pad; /* bytes after each row */
    uint16_t part_deg;   /* a partial map: the longitudes it covers (latitudes 50 to -40), 0: the sphere */
} map_kind_t;

static const map_kind_t KINDS[] = {
    {PSC_PROJ_EQUIRECT, PSC_PIX_RGB565, 1024, 512, 0, 0},
    {PSC_PROJ_EQUIRECT, PSC_PIX_XRGB8888, 512, 256, 0, 0},
    {PSC_PROJ_EQUIRECT, PSC_PIX_PAL8, 512, 256, 0, 0},
    {PSC_PROJ_CYLINDER, PSC_PIX_RGB565, 512, 256, 0, 0},
    {PSC_PROJ_SINE, PSC_PIX_PAL8, 256, 128, 0, 0},
    {PSC_PROJ_EQUIRECT, PSC_PIX_RGB565, 512, 256, 2, 0}, /* rows at odd 16-bit words */
    {PSC_PROJ_EQUIRECT, PSC_PIX_PAL8, 512, 256, 1, 0},   /* rows at odd bytes */
    {PSC_PROJ_EQUIRECT, PSC_PIX_RGB565, 600, 300, 0, 0}, /* not a power of two */
    {PSC_PROJ_EQUIRECT, PSC_PIX_RGB888, 1024, 512, 0, 0},
    {PSC_PROJ_CYLINDER, PSC_PIX_RGB888, 600, 300, 0, 0},
    {PSC_PROJ_EQUIRECT, PSC_PIX_RGB888, 512, 256, 1, 0}, /* rows at odd bytes: no AVX2 */
    /* partial maps: a window of a full turn of W x 360 / span columns (the fast spans inside, the general sampler
     * near the edges): by multiplying, and by shifting (1024 over 90 degrees: 4096 a turn) */
    {PSC_PROJ_EQUIRECT, PSC_PIX_RGB565, 1000, 400, 0, 150},
    {PSC_PROJ_CYLINDER, PSC_PIX_XRGB8888, 1024, 512, 0, 90},
    {PSC_PROJ_EQUIRECT, PSC_PIX_RGB888, 777, 300, 0, 200},
};

static const struct {
    uint16_t w, h;
} SIZES[] = {{160, 120}, {164, 90}, {173, 97}};

#define VIEWS 24u

static psc_view_t random_view(tsup_rng_t *r)
{
    static const psc_filter_t filters[] = {PSC_FILTER_NEAREST, PSC_FILTER_BILINEAR, PSC_FILTER_MIP};
    double pitch = tsup_rng_below(r, 4) == 0 ? tsup_rng_range(r, 75, 90) * (tsup_rng_below(r, 2) ? 1 : -1)
                                             : tsup_rng_range(r, -60, 60);
    return tsup_view_deg(tsup_rng_range(r, -180, 180), pitch, tsup_rng_range(r, 20, 120), filters[tsup_rng_below(r, 3)],
                         tsup_rng_below(r, 5));
}

/* Scribble over the pixels (not the stride's guard bytes) so that a pixel no path draws shows. */
static void clear_rows(const psc_surface_t *s)
{
    for (unsigned y = 0; y < s->height; y++)
        memset((uint8_t *)s->pixels + (size_t)y * s->stride, 0x5A, (size_t)s->width * psc_pixfmt_bytes(s->format));
}

/*
 * Render view through the scalar path, then through each of paths[n] (and
 * AUTO when with_auto), failing with what names the case if any differs.
 * Returns the comparisons made; counts[k] adds one per path k (0 = AUTO).
 */
static unsigned compare_paths(tsup_viewer_t *tv, const psc_view_t *view, const psc_simd_t *paths, unsigned n,
                              bool with_auto, uint8_t *scalar, const char *what, unsigned counts[3])
{
    size_t bytes = (size_t)tv->out.stride * tv->out.height;
    assert_int_equal(psc_viewer_set_simd(&tv->v, PSC_SIMD_SCALAR), PSC_OK);
    assert_int_equal(psc_viewer_render(&tv->v, view, &tv->out), PSC_OK);
    memcpy(scalar, tv->out.pixels, bytes);
    unsigned made = 0;
    for (unsigned p = 0; p < n + (with_auto ? 1u : 0u); p++) {
        psc_simd_t s = p < n ? paths[p] : PSC_SIMD_AUTO;
        assert_int_equal(psc_viewer_set_simd(&tv->v, s), PSC_OK);
        if (s != PSC_SIMD_AUTO)
            assert_int_equal(psc_viewer_simd(&tv->v), s);   /* the frame is drawn with that kernel */
        clear_rows(&tv->out);
        assert_int_equal(psc_viewer_render(&tv->v, view, &tv->out), PSC_OK);
        if (memcmp(scalar, tv->out.pixels, bytes) != 0)
            fail_msg("%s, path %s: yaw %u pitch %d hfov %u filter %d span %u differs from the scalar path", what,
                     psc_simd_name(s), (unsigned)view->yaw, (int)view->pitch, (unsigned)view->hfov, (int)view->filter,
                     1u << view->span_log2);
        counts[s == PSC_SIMD_AUTO ? 0 : s == PSC_SIMD_VECTOR ? 1 : 2]++;
        made++;
    }
    assert_true(tsup_viewer_guard_ok(tv));
    return made;
}

/* Whether this CPU has AVX2 (the x86-64 build always has the AVX2 kernel: then it must be compared). */
static bool cpu_has_avx2(void)
{
#if defined(__x86_64__)
    return __builtin_cpu_supports("avx2") != 0;
#else
    return false;
#endif
}

/* The vector paths this build and this CPU have. */
static unsigned vector_paths(psc_viewer_t *v, psc_simd_t *out)
{
    unsigned n = 0;
    static const psc_simd_t all[] = {PSC_SIMD_VECTOR, PSC_SIMD_AVX2};
    for (unsigned i = 0; i < 2; i++)
        if (psc_viewer_set_simd(v, all[i]) == PSC_OK)
            out[n++] = all[i];
    assert_int_equal(psc_viewer_set_simd(v, PSC_SIMD_AUTO), PSC_OK);
    return n;
}

static void test_paths_equal_scalar(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 5150);
    unsigned frames = 0, compared[3] = {0};
    for (unsigned k = 0; k < sizeof KINDS / sizeof KINDS[0]; k++) {
        psc_envmap_t g = {0};
        g.projection = KINDS[k].proj;
        g.format = KINDS[k].fmt;
        g.width = KINDS[k].w;
        g.height = KINDS[k].h;
        if (KINDS[k].part_deg) {
            g.lon_min = tsup_bam_from_deg(-KINDS[k].part_deg / 2.0);
            g.lon_span = tsup_bam_from_deg(KINDS[k].part_deg);
            g.lat_top = (int32_t)tsup_bam_from_deg(50.0);
            g.lat_bottom = -(int32_t)tsup_bam_from_deg(40.0);
        }
        tsup_map_t m;
        assert_int_equal(tsup_synth_map(&m, &g, !KINDS[k].part_deg, KINDS[k].stride_pad), 0);
        for (unsigned sz = 0; sz < sizeof SIZES / sizeof SIZES[0]; sz++) {
            for (int fmt = 0; fmt < 2; fmt++) {
                tsup_viewer_t tv;
                assert_int_equal(tsup_viewer_init(&tv, &m.map, SIZES[sz].w, SIZES[sz].h,
                                                  fmt ? PSC_PIX_XRGB8888 : PSC_PIX_RGB565),
                                 PSC_OK);
                psc_simd_t paths[2];
                unsigned npaths = vector_paths(&tv.v, paths);
                uint8_t *scalar = malloc((size_t)tv.out.stride * tv.out.height);
                assert_non_null(scalar);
                char what[160];
                snprintf(what, sizeof what, "map %u (%ux%u, format %d), %ux%u %s output", k, (unsigned)m.map.width,
                         (unsigned)m.map.height, (int)m.map.format, (unsigned)SIZES[sz].w, (unsigned)SIZES[sz].h,
                         fmt ? "xrgb8888" : "rgb565");
                for (unsigned i = 0; i < VIEWS; i++) {
                    psc_view_t view = random_view(&r);
                    psc_viewer_clamp(&tv.v, &view, 0);
                    compare_paths(&tv, &view, paths, npaths, true, scalar, what, compared);
                    frames++;
                }
                free(scalar);
                tsup_viewer_free(&tv);
            }
        }
        tsup_map_free(&m);
    }
    print_message("  %u random views: scalar bytes from auto %u, vector %u, avx2 %u times (AVX2 %s)\n", frames,
                  compared[0], compared[1], compared[2], cpu_has_avx2() ? "on this CPU: its kernel ran" :
                                                                          "not on this CPU: its kernel did not run");
    if (cpu_has_avx2())
        assert_true(compared[2] > 0);   /* where the CPU has it, the AVX2 kernel drew and was compared */
#if defined(__SSE2__) || defined(__ARM_NEON)
    assert_true(compared[1] > 0); /* this target has baseline vectors: they were compared */
#endif
}

/* A pack with its pyramid, of a noisy 1024x512 image in format fmt. */
static void mip_pack(psc_pixfmt_t fmt, tsup_rng_t *r, uint8_t **buf, size_t *len, psc_pack_t *p)
{
    psc_image_t img = {1024, 512, malloc(1024u * 512u * sizeof(uint32_t))};
    assert_non_null(img.xrgb);
    for (unsigned i = 0; i < 1024u * 512u; i++) /* smooth bands plus noise: every level differs */
        img.xrgb[i] = 0xFF000000u | ((i * 7u) & 0xFF0000u) | ((i / 1024u * 3u) & 255u) << 8 | (tsup_rng_u32(r) & 255u);
    psc_pack_options_t opt;
    psc_io_pack_options_default(&opt);
    opt.format = fmt;
    opt.display_width = 88;
    opt.display_height = 40;
    char err[256];
    assert_int_equal(psc_io_pack_build(&img, &opt, buf, len, err, sizeof err), 0);
    psc_container_error_t perr = {0};
    assert_int_equal(psc_pack_parse(*buf, *len, p, &perr), PSC_OK);
    assert_true(p->level_count > 3);
    psc_io_image_free(&img);
}

static void test_mip_paths_equal_scalar(void **state)
{
    (void)state;
    static const psc_pixfmt_t fmts[] = {PSC_PIX_RGB565, PSC_PIX_XRGB8888, PSC_PIX_PAL8, PSC_PIX_RGB888};
    tsup_rng_t r;
    tsup_rng_seed(&r, 4242);
    unsigned frames = 0, compared = 0, counts[3] = {0};
    for (unsigned fi = 0; fi < sizeof fmts / sizeof fmts[0]; fi++) {
        uint8_t *buf;
        size_t len;
        psc_pack_t p;
        mip_pack(fmts[fi], &r, &buf, &len, &p);
        for (int out565 = 0; out565 < 4; out565++) { /* small outputs: many texels a pixel, every level in use */
            tsup_viewer_t tv;
            assert_int_equal(tsup_viewer_init(&tv, &p.map, out565 < 2 ? 48 : 88, out565 < 2 ? 32 : 40,
                                              out565 & 1 ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888),
                             PSC_OK);
            assert_int_equal(psc_viewer_set_levels(&tv.v, p.levels, p.level_count), PSC_OK);
            psc_simd_t paths[2];
            unsigned npaths = vector_paths(&tv.v, paths);
            uint8_t *scalar = malloc((size_t)tv.out.stride * tv.out.height);
            assert_non_null(scalar);
            char what[96];
            snprintf(what, sizeof what, "mip, map format %d, %s output", (int)fmts[fi], out565 & 1 ? "rgb565" : "xrgb8888");
            for (unsigned i = 0; i < VIEWS; i++) {
                psc_view_t view = random_view(&r);
                view.filter = PSC_FILTER_MIP;
                view.hfov = tsup_bam_from_deg(tsup_rng_range(&r, 20, 120)); /* up to 3 levels down at 48 px */
                psc_viewer_clamp(&tv.v, &view, 0);
                compared += compare_paths(&tv, &view, paths, npaths, false, scalar, what, counts);
                frames++;
            }
            free(scalar);
            tsup_viewer_free(&tv);
        }
        free(buf);
    }
    print_message("  %u random mip views: the scalar bytes %u times (vector %u, avx2 %u)\n", frames, compared, counts[1],
                  counts[2]);
    assert_true(compared > 0);
    if (cpu_has_avx2())
        assert_true(counts[2] > 0);
}

/*
 * An RGB888 map holds what an XRGB8888 map of the same picture holds, in three bytes a texel: every view of it,
 * through every sampler (the general one of elliptical maps, the fast spans, the pyramid) and to either output,
 * is the XRGB8888 map's frame, byte for byte; its rows' spare bytes (0x5A here) never show.
 */
static void test_rgb888_is_xrgb8888(void **state)
{
    (void)state;
    static const psc_projection_t projs[] = {PSC_PROJ_EQUIRECT, PSC_PROJ_CYLINDER, PSC_PROJ_SINE, PSC_PROJ_ELLIPTICAL};
    tsup_rng_t r;
    tsup_rng_seed(&r, 888);
    unsigned frames = 0;
    for (unsigned k = 0; k < sizeof projs / sizeof projs[0]; k++) {
        psc_envmap_t g = {0};
        g.projection = projs[k];
        g.width = 600;
        g.height = 300;
        tsup_map_t m8888, m888;
        g.format = PSC_PIX_XRGB8888;
        assert_int_equal(tsup_synth_map(&m8888, &g, 1, 0), 0);
        g.format = PSC_PIX_RGB888;
        assert_int_equal(tsup_synth_map(&m888, &g, 1, k), 0);   /* and spare bytes beyond the least */
        for (int out = 0; out < 2; out++) {
            psc_pixfmt_t of = out ? PSC_PIX_XRGB8888 : PSC_PIX_RGB565;
            tsup_viewer_t a, b;
            assert_int_equal(tsup_viewer_init(&a, &m8888.map, 173, 97, of), PSC_OK);
            assert_int_equal(tsup_viewer_init(&b, &m888.map, 173, 97, of), PSC_OK);
            for (unsigned i = 0; i < VIEWS; i++) {
                psc_view_t view = random_view(&r);
                psc_viewer_clamp(&a.v, &view, 0);
                assert_int_equal(psc_viewer_render(&a.v, &view, &a.out), PSC_OK);
                assert_int_equal(psc_viewer_render(&b.v, &view, &b.out), PSC_OK);
                if (memcmp(a.out.pixels, b.out.pixels, (size_t)a.out.stride * a.out.height) != 0)
                    fail_msg("%s map, %s output: yaw %u pitch %d hfov %u filter %d: rgb888 differs from xrgb8888",
                             psc_projection_name(projs[k]), out ? "xrgb8888" : "rgb565", (unsigned)view.yaw,
                             (int)view.pitch, (unsigned)view.hfov, (int)view.filter);
                frames++;
            }
            tsup_viewer_free(&a);
            tsup_viewer_free(&b);
        }
        tsup_map_free(&m8888);
        tsup_map_free(&m888);
    }
    /* the pyramid: packs of one picture in both formats */
    uint8_t *buf[2];
    size_t len[2];
    psc_pack_t p[2];
    tsup_rng_t same = r;
    mip_pack(PSC_PIX_XRGB8888, &r, &buf[0], &len[0], &p[0]);
    mip_pack(PSC_PIX_RGB888, &same, &buf[1], &len[1], &p[1]);
    assert_true(len[1] < len[0] * 4 / 5);   /* three bytes a texel, not four */
    tsup_viewer_t tv[2];
    for (int i = 0; i < 2; i++) {
        assert_int_equal(tsup_viewer_init(&tv[i], &p[i].map, 48, 32, PSC_PIX_XRGB8888), PSC_OK);
        assert_int_equal(psc_viewer_set_levels(&tv[i].v, p[i].levels, p[i].level_count), PSC_OK);
    }
    for (unsigned i = 0; i < VIEWS; i++, frames++) {
        psc_view_t view = random_view(&r);
        view.filter = PSC_FILTER_MIP;
        psc_viewer_clamp(&tv[0].v, &view, 0);
        assert_int_equal(psc_viewer_render(&tv[0].v, &view, &tv[0].out), PSC_OK);
        assert_int_equal(psc_viewer_render(&tv[1].v, &view, &tv[1].out), PSC_OK);
        assert_memory_equal(tv[0].out.pixels, tv[1].out.pixels, (size_t)tv[0].out.stride * tv[0].out.height);
    }
    for (int i = 0; i < 2; i++) {
        tsup_viewer_free(&tv[i]);
        free(buf[i]);
    }
    print_message("  %u random views: an rgb888 map's frames are the xrgb8888 map's, byte for byte (pack %zu bytes "
                  "against %zu)\n", frames, len[1], len[0]);
}

static void test_choice(void **state)
{
    (void)state;
    psc_envmap_t g = {0};
    g.projection = PSC_PROJ_EQUIRECT;
    g.format = PSC_PIX_RGB565;
    g.width = 512;
    g.height = 256;
    tsup_map_t aligned, odd;
    assert_int_equal(tsup_synth_map(&aligned, &g, 1, 0), 0);
    assert_int_equal(tsup_synth_map(&odd, &g, 1, 2), 0);
    tsup_viewer_t a, o;
    assert_int_equal(tsup_viewer_init(&a, &aligned.map, 160, 120, PSC_PIX_RGB565), PSC_OK);
    assert_int_equal(tsup_viewer_init(&o, &odd.map, 160, 120, PSC_PIX_RGB565), PSC_OK);
    assert_int_equal(psc_viewer_set_simd(&a.v, (psc_simd_t)7), PSC_ERR_ARG);
    assert_int_equal(psc_viewer_set_simd(&a.v, PSC_SIMD_SCALAR), PSC_OK);
    assert_int_equal(psc_viewer_simd(&a.v), PSC_SIMD_SCALAR);
    assert_int_equal(psc_viewer_set_simd(&a.v, PSC_SIMD_AUTO), PSC_OK);
#if defined(__x86_64__)
    /* x86-64: SSE2 always; AVX2 exactly when the CPU has it, and AUTO takes it */
    assert_int_equal(psc_viewer_set_simd(&a.v, PSC_SIMD_VECTOR), PSC_OK);
    int avx2 = __builtin_cpu_supports("avx2") != 0;
    assert_int_equal(psc_viewer_set_simd(&a.v, PSC_SIMD_AVX2), avx2 ? PSC_OK : PSC_ERR_UNSUPPORTED);
    assert_int_equal(psc_viewer_set_simd(&a.v, PSC_SIMD_AUTO), PSC_OK);
    assert_int_equal(psc_viewer_simd(&a.v), avx2 ? PSC_SIMD_AVX2 : PSC_SIMD_SCALAR);
    /* rows not 4-byte aligned: never the AVX2 kernel; x86-64 then draws scalar (SSE2 is slower) */
    assert_int_equal(psc_viewer_set_simd(&o.v, PSC_SIMD_AVX2), PSC_ERR_UNSUPPORTED);
    assert_int_equal(psc_viewer_simd(&o.v), PSC_SIMD_SCALAR);
    print_message("  x86-64, AVX2 %s: auto draws with %s\n", avx2 ? "present" : "absent", psc_simd_name(psc_viewer_simd(&a.v)));
#elif defined(__aarch64__) || defined(__ARM_NEON)
    assert_int_equal(psc_viewer_simd(&a.v), PSC_SIMD_VECTOR);
#endif
    assert_string_equal(psc_simd_name(PSC_SIMD_SCALAR), "scalar");
    tsup_viewer_free(&a);
    tsup_viewer_free(&o);
    tsup_map_free(&aligned);
    tsup_map_free(&odd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_paths_equal_scalar),
        cmocka_unit_test(test_mip_paths_equal_scalar),
        cmocka_unit_test(test_rgb888_is_xrgb8888),
        cmocka_unit_test(test_choice),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
