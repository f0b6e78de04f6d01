/* SPDX-License-Identifier: MIT */
/*
 * test_3d_threads.c - the 3D pipeline on several threads (io/psc_io_render3d.h).
 *
 *  - The same bytes for any thread count: random scenes of meshes (camera
 *    inside and outside, every shading), drawn on pools of 1 to 8 threads,
 *    full-screen configurations (shared as full-width bands), tiles, area
 *    subdivision, the A-buffer in tiles, and the A-buffer without tiles (kept
 *    on one thread): colour and exported depth equal psc_3d_render's on one
 *    thread with the configuration as given, and so do the counts of
 *    triangles, culled, clipped, outside and pixels written.
 *  - A frame of more triangles than the frame's list holds bins row by row, alike.
 *  - The threads really share the frame: with a pool of 2 a full-screen
 *    frame is drawn by 2 threads, an anti-aliased one without tiles by 1.
 *  - Bad starts are refused with a message.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "3d/psc_3d_render.h"
#include "psc_io_bands.h"
#include "psc_io_render3d.h"
#include "psc_testsupport.h"
#include "tsup_3d.h"

#define W 203
#define H 157
#define ABUF_FRAGMENTS 6000u

typedef struct {
    tsup_mesh_t meshes[3];
    psc_model_t geoms[3];
    tsup_texture_t tex;
    psc_3d_draw_t draws[3];
    unsigned n;
} scene_t;

static void scene_random(scene_t *sc, tsup_rng_t *rng)
{
    memset(sc, 0, sizeof *sc);
    assert_int_equal(tsup_texture_make(&sc->tex, 64, 32, PSC_PIX_RGB565), 0);
    sc->n = 1 + tsup_rng_below(rng, 3);
    double yaw = tsup_rng_range(rng, -180, 180), pitch = tsup_rng_range(rng, -80, 80);
    double dist = tsup_rng_range(rng, 0.0, 4.0);
    for (unsigned i = 0; i < sc->n; i++) {
        tsup_shape_make((tsup_shape_t)tsup_rng_below(rng, 4), &sc->geoms[i]);
        psc_model_color_by_index(&sc->geoms[i], i);
        assert_int_equal(tsup_mesh_from_geom(&sc->meshes[i], &sc->geoms[i], 1), 0);
        psc_3d_draw_t *d = &sc->draws[i];
        psc_3d_draw_defaults(d, &sc->meshes[i].mesh);
        psc_mat4_q16_t cam, obj, rot, tr;
        tsup_orbit_matrix(&cam, yaw, pitch, dist);
        psc_mat4_rotate_y(&rot, tsup_rng_u32(rng));
        psc_mat4_translate(&tr, (psc_vec3_q16_t){(int32_t)tsup_rng_range(rng, -65536, 65536),
                                                 (int32_t)tsup_rng_range(rng, -65536, 65536),
                                                 (int32_t)tsup_rng_range(rng, -65536, 65536)});
        psc_mat4_mul(&obj, &tr, &rot);
        psc_mat4_mul(&d->camera_from_object, &cam, &obj);
        d->shade = (psc_shade_t)tsup_rng_below(rng, 3);
        if (tsup_rng_below(rng, 4) == 0)
            d->shade = PSC_SHADE_PHONG;
        d->filter = (psc_tex_filter_t)tsup_rng_below(rng, 2);
        d->cull_back = tsup_rng_below(rng, 2);
        d->lit = tsup_rng_below(rng, 2);
        d->light_dir = psc_vec3_normalize((psc_vec3_q16_t){-20000, 30000, -40000});
        d->texture = &sc->tex.tex;
    }
}

static void scene_free(scene_t *sc)
{
    for (unsigned i = 0; i < sc->n; i++) {
        tsup_mesh_free(&sc->meshes[i]);
        psc_model_free(&sc->geoms[i]);
    }
    tsup_texture_free(&sc->tex);
}

typedef struct {
    psc_surface_t s;
    uint16_t *depth;
    psc_3d_stats_t st;
    unsigned threads;
} frame_t;

/* One frame of the scene: on the pool (NULL: psc_3d_render alone, the configuration as given). */
static void render(frame_t *f, const scene_t *sc, psc_3d_config_t cfg, bool aa, psc_pixfmt_t fmt,
                   psc_io_bands_t *pool)
{
    char err[256];
    if (pool)
        psc_io_render3d_config(&cfg, psc_io_bands_threads(pool), aa);
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
    size_t abuf_bytes = aa ? psc_3d_abuffer_bytes(&cfg, ABUF_FRAGMENTS) : 0;
    void *abuf = NULL;
    if (aa) {
        abuf = aligned_alloc(64, (abuf_bytes + 63u) & ~(size_t)63u);
        assert_int_equal(psc_3d_set_abuffer(&t.r, abuf, abuf_bytes), PSC_OK);
    }
    psc_io_render3d_t *threads = NULL;
    if (pool) {
        threads = psc_io_render3d_start(pool, &cfg, abuf_bytes, err, sizeof err);
        if (!threads)
            fail_msg("%s", err);
    }
    f->threads = psc_io_render3d_threads(threads);
    f->s = tsup_surface_new(W, H, fmt);
    f->depth = calloc((size_t)W * H, 2);
    t.r.depth_out = f->depth;
    uint32_t bg = 0x203040;
    assert_int_equal(psc_io_render3d_frame(threads, &t.r, sc->draws, sc->n, &bg, &f->s, &f->st), PSC_OK);
    psc_io_render3d_stop(threads);
    tsup_3d_free(&t);
    free(abuf);
}

static void frame_free(frame_t *f)
{
    tsup_surface_free(&f->s);
    free(f->depth);
}

static void test_same_bytes_any_threads(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 3131);
    char err[256];
    psc_io_bands_t *pools[8];
    for (unsigned k = 0; k < 8; k++) {
        pools[k] = psc_io_bands_start(k + 1, W, err, sizeof err);
        assert_non_null(pools[k]);
    }
    unsigned scenes = 24, shared = 0;
    for (unsigned s = 0; s < scenes; s++) {
        scene_t sc;
        scene_random(&sc, &rng);
        unsigned mode = s % 5; /* full screen, tiles, area, A-buffer in tiles, A-buffer full screen */
        bool aa = mode >= 3;
        psc_3d_config_t cfg = {W, H, 0, 0, tsup_rng_below(&rng, 2) ? 16 : 32, tsup_bam_from_deg(tsup_rng_range(&rng, 40, 120)),
                               PSC_Q16_ONE / 16, 64 * PSC_Q16_ONE, 3 * 12000, PSC_3D_HSR_ZBUFFER};
        if (mode == 1 || mode == 3)
            cfg.tile_width = cfg.tile_height = (uint16_t)(16 + 8 * tsup_rng_below(&rng, 6));
        if (mode == 2)
            cfg.hsr = PSC_3D_HSR_AREA;
        psc_pixfmt_t fmt = tsup_rng_below(&rng, 2) ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888;
        frame_t one;
        render(&one, &sc, cfg, aa, fmt, NULL);
        for (unsigned k = 0; k < 8; k++) {
            frame_t many;
            render(&many, &sc, cfg, aa, fmt, pools[k]);
            if (memcmp(one.s.pixels, many.s.pixels, (size_t)one.s.stride * H) != 0) {
                tsup_save_png(&one.s, "3d_threads_one.png");
                tsup_save_png(&many.s, "3d_threads_many.png");
                fail_msg("scene %u (mode %u): %u threads draw other bytes than one", s, mode, k + 1);
            }
            assert_memory_equal(one.depth, many.depth, (size_t)W * H * 2);
            assert_int_equal(one.st.triangles, many.st.triangles);
            assert_int_equal(one.st.culled, many.st.culled);
            assert_int_equal(one.st.clipped, many.st.clipped);
            assert_int_equal(one.st.outside, many.st.outside);
            if (mode != 2) /* areas differ with the bands they are cut from; the bytes do not */
                assert_int_equal(one.st.pixels, many.st.pixels);
            if (aa && mode == 4)
                assert_int_equal(many.threads, 1); /* the screen's A-buffer budget: one thread */
            else /* bands or tiles of at most 56 pixels: at least 3 rows to share */
                assert_true(k == 0 ? many.threads == 1 : many.threads >= 2 && many.threads <= k + 1);
            shared += many.threads > 1;
            frame_free(&many);
        }
        frame_free(&one);
        scene_free(&sc);
    }
    print_message("  %u random scenes x 1..8 threads (full screen in bands, tiles, area subdivision, the A-buffer): "
                  "the same bytes, depth and counts; %u frames shared among threads\n", scenes, shared);
    assert_true(shared > scenes * 4);
    for (unsigned k = 0; k < 8; k++)
        psc_io_bands_stop(pools[k]);
}

/* A frame of more triangles than its list holds (4 x max_vertices + 256: triangles reusing few vertices) bins row by
 * row instead, with the same bytes and counts on any number of threads. */
static void test_busy_frame(void **state)
{
    (void)state;
    enum { NV = 40, NT = 600 };
    static int32_t pos[3 * NV];
    static uint32_t col[NV];
    static uint16_t idx[3 * NT];
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 77);
    for (unsigned v = 0; v < NV; v++) {
        for (unsigned k = 0; k < 3; k++)
            pos[3 * v + k] = (int32_t)tsup_rng_range(&rng, -65536, 65536);
        col[v] = tsup_rng_u32(&rng) & 0xFFFFFFu;
    }
    for (unsigned i = 0; i < 3 * NT; i++)
        idx[i] = (uint16_t)tsup_rng_below(&rng, NV);
    psc_mesh_t m = {.vertex_count = NV, .triangle_count = NT, .position_q16 = pos, .color = col, .index = idx};
    scene_t sc;
    memset(&sc, 0, sizeof sc);
    sc.n = 1;
    psc_3d_draw_defaults(&sc.draws[0], &m);
    sc.draws[0].cull_back = false;
    tsup_orbit_matrix(&sc.draws[0].camera_from_object, 20, 10, 3.0);
    char err[256];
    psc_3d_config_t cfg = {W, H, 32, 32, 16, tsup_bam_from_deg(60), PSC_Q16_ONE / 16, 64 * PSC_Q16_ONE, NV,
                           PSC_3D_HSR_ZBUFFER};
    frame_t one, many;
    render(&one, &sc, cfg, false, PSC_PIX_XRGB8888, NULL);
    psc_io_bands_t *pool = psc_io_bands_start(3, W, err, sizeof err);
    assert_non_null(pool);
    render(&many, &sc, cfg, false, PSC_PIX_XRGB8888, pool);
    assert_memory_equal(one.s.pixels, many.s.pixels, (size_t)one.s.stride * H);
    assert_memory_equal(one.depth, many.depth, (size_t)W * H * 2);
    assert_int_equal(one.st.culled + one.st.outside, many.st.culled + many.st.outside);
    assert_int_equal(one.st.pixels, many.st.pixels);
    assert_true(one.st.pixels > 1000);
    frame_free(&one);
    frame_free(&many);
    psc_io_bands_stop(pool);
}

static void test_threads_share(void **state)
{
    (void)state;
    char err[256];
    psc_io_bands_t *pool = psc_io_bands_start(2, 800, err, sizeof err);
    assert_non_null(pool);
    psc_3d_config_t cfg = {800, 480, 0, 0, 16, tsup_bam_from_deg(60), PSC_Q16_ONE, 8 * PSC_Q16_ONE, 1000,
                           PSC_3D_HSR_ZBUFFER};
    psc_3d_config_t banded = cfg;
    psc_io_render3d_config(&banded, 2, false);
    assert_int_equal(banded.tile_width, 800);
    assert_int_equal(banded.tile_height, 64); /* 480 / (2 x 4 bands) = 60, up to a multiple of 8 */
    psc_io_render3d_t *t = psc_io_render3d_start(pool, &banded, 0, err, sizeof err);
    assert_non_null(t);
    assert_int_equal(psc_io_render3d_threads(t), 2);
    psc_io_render3d_stop(t);
    psc_3d_config_t aa = cfg;
    psc_io_render3d_config(&aa, 2, true); /* the A-buffer's budget is the screen's: left whole */
    assert_int_equal(aa.tile_width, 0);
    t = psc_io_render3d_start(pool, &aa, psc_3d_abuffer_bytes(&aa, 100), err, sizeof err);
    assert_non_null(t);
    assert_int_equal(psc_io_render3d_threads(t), 1);
    psc_io_render3d_stop(t);
    psc_3d_config_t bad = cfg;
    bad.depth_bits = 24;
    assert_null(psc_io_render3d_start(pool, &bad, 0, err, sizeof err));
    assert_non_null(strstr(err, "invalid"));
    psc_io_bands_stop(pool);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_bytes_any_threads),
        cmocka_unit_test(test_busy_frame),
        cmocka_unit_test(test_threads_share),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
