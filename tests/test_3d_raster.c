/* SPDX-License-Identifier: MIT */
/*
 * test_3d_raster.c - the rasterizer's and the pipeline's exact properties.
 *
 *  - Watertight and no double drawing: closed meshes drawn without depth
 *    test, without culling and with additive blending count the triangles
 *    over each pixel; every pixel of a closed surface is crossed an even
 *    number of times (a crack leaves an odd count, a double-drawn edge pixel
 *    too). Planar tilings of a square count exactly 1 inside and 0 outside.
 *  - Tile mode: random scenes (meshes, cameras inside and outside, clipping,
 *    every shading) give byte-identical colour and exported depth in full and
 *    tile mode, for several tile sizes including ones that do not divide the
 *    screen.
 *  - Depth order: two interpenetrating triangles show the nearer one at every
 *    pixel farther than 1.5 px from their intersection line, in both orders.
 *  - Near-plane and guard-band clipping at extreme cameras: inside a mesh, on
 *    a vertex, triangles crossing the near plane with coordinates near
 *    +-32000 units; nothing behind the camera is drawn and the result agrees
 *    with the double-precision reference.
 *  - Argument checks and the workspace/depth-memory figures.
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

#include "3d/psc_3d_render.h"
#include "base/psc_pixel.h"
#include "psc_testsupport.h"
#include "tsup_3d.h"

static psc_3d_config_t config(uint16_t w, uint16_t h, double hfov_deg, uint32_t max_vertices)
{
    psc_3d_config_t c = {w, h, 0, 0, 32, tsup_bam_from_deg(hfov_deg), PSC_Q16_ONE / 16, 64 * PSC_Q16_ONE,
                         max_vertices, PSC_3D_HSR_ZBUFFER};
    return c;
}

/* Render with counting: no depth test, no culling, each write adds 1 to blue. */
static void render_count(const psc_3d_config_t *cfg, const psc_mesh_t *m, const psc_mat4_q16_t *cam,
                         psc_surface_t *s)
{
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, cfg), PSC_OK);
    psc_3d_draw_t d;
    psc_3d_draw_defaults(&d, m);
    d.camera_from_object = *cam;
    d.shade = PSC_SHADE_FLAT;
    d.cull_back = false;
    d.depth_test = false;
    d.blend = PSC_BLEND_ADD;
    d.color = 0x000001;
    psc_mesh_t mm = *m;
    mm.color = NULL;
    d.mesh = &mm;
    uint32_t black = 0;
    assert_int_equal(psc_3d_render(&t.r, &d, 1, &black, s, NULL), PSC_OK);
    tsup_3d_free(&t);
}

static uint32_t count_at(const psc_surface_t *s, unsigned x, unsigned y)
{
    return ((const uint32_t *)s->pixels)[(size_t)y * s->width + x] & 0xFFu;
}

static void check_parity(const char *name, const psc_model_t *g, double yaw, double pitch, double dist,
                         double hfov)
{
    tsup_mesh_t m;
    assert_int_equal(tsup_mesh_from_geom(&m, g, 0), 0);
    psc_3d_config_t cfg = config(160, 120, hfov, m.mesh.vertex_count);
    psc_mat4_q16_t cam;
    tsup_orbit_matrix(&cam, yaw, pitch, dist);
    psc_surface_t s = tsup_surface_new(160, 120, PSC_PIX_XRGB8888);
    render_count(&cfg, &m.mesh, &cam, &s);
    unsigned covered = 0, odd = 0;
    for (unsigned y = 0; y < s.height; y++)
        for (unsigned x = 0; x < s.width; x++) {
            uint32_t c = count_at(&s, x, y);
            covered += c > 0;
            if (c & 1u) {
                if (odd == 0)
                    print_message("%s: odd count %u at (%u, %u)\n", name, c, x, y);
                odd++;
            }
        }
    if (odd)
        tsup_save_png(&s, "3d_parity_fail.png");
    assert_int_equal(odd, 0);
    assert_true(covered > 500); /* the shape is really on the screen */
    tsup_surface_free(&s);
    tsup_mesh_free(&m);
}

static void test_watertight_closed_meshes(void **state)
{
    (void)state;
    psc_model_t g;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 3);
    psc_model_sphere(&g, 1.0, 24, 13);
    for (int i = 0; i < 12; i++)
        check_parity("sphere", &g, tsup_rng_range(&rng, -180, 180), tsup_rng_range(&rng, -89, 89),
                     tsup_rng_range(&rng, 2.2, 6), tsup_rng_range(&rng, 30, 100));
    psc_model_free(&g);
    psc_model_torus(&g, 1.0, 0.35, 40, 16);
    for (int i = 0; i < 12; i++)
        check_parity("torus", &g, tsup_rng_range(&rng, -180, 180), tsup_rng_range(&rng, -89, 89),
                     tsup_rng_range(&rng, 2.5, 6), tsup_rng_range(&rng, 30, 100));
    psc_model_free(&g);
    /* Random closed meshes: a sphere with every vertex moved radially. */
    for (int k = 0; k < 8; k++) {
        psc_model_sphere(&g, 1.0, 9 + k, 6 + k);
        for (uint32_t v = 0; v < g.vertex_count; v++) {
            double f = tsup_rng_range(&rng, 0.6, 1.3);
            for (int a = 0; a < 3; a++)
                g.pos[3 * v + a] *= f;
        }
        check_parity("random closed", &g, tsup_rng_range(&rng, -180, 180), tsup_rng_range(&rng, -80, 80),
                     tsup_rng_range(&rng, 2.5, 5), 60);
        psc_model_free(&g);
    }
}

/* A square of side 2 tiled by jittered triangles: every pixel whose centre is inside counts 1. */
static void test_shared_edges_drawn_once(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 11);
    for (int trial = 0; trial < 20; trial++) {
        unsigned n = 3 + (unsigned)trial % 7;
        psc_model_t g = {0};
        g.vertex_count = (n + 1) * (n + 1);
        g.triangle_count = 2 * n * n;
        g.pos = calloc(g.vertex_count * 3, sizeof(double));
        g.index = calloc(g.triangle_count * 3, sizeof(uint32_t));
        for (unsigned i = 0; i <= n; i++)
            for (unsigned j = 0; j <= n; j++) {
                double x = -1 + 2.0 * j / n, y = -1 + 2.0 * i / n, h = 0.8 / n;
                if (i > 0 && i < n)
                    y += tsup_rng_range(&rng, -h / 2, h / 2);
                if (j > 0 && j < n)
                    x += tsup_rng_range(&rng, -h / 2, h / 2);
                g.pos[3 * (i * (n + 1) + j)] = x;
                g.pos[3 * (i * (n + 1) + j) + 1] = y;
            }
        uint32_t k = 0;
        for (unsigned i = 0; i < n; i++)
            for (unsigned j = 0; j < n; j++) {
                uint32_t a = i * (n + 1) + j, b = a + 1, c = a + n + 2, d = a + n + 1;
                bool diag = tsup_rng_below(&rng, 2);
                uint32_t t[6] = {a, b, diag ? c : d, diag ? a : b, c, d};
                memcpy(&g.index[3 * k], t, sizeof t);
                k += 2;
            }
        tsup_mesh_t m;
        assert_int_equal(tsup_mesh_from_geom(&m, &g, 0), 0);
        /* The square faces the camera, slightly turned; rendered at an odd size. */
        psc_3d_config_t cfg = config(97, 83, 60, m.mesh.vertex_count);
        psc_mat4_q16_t cam;
        tsup_orbit_matrix(&cam, tsup_rng_range(&rng, -30, 30), tsup_rng_range(&rng, -30, 30),
                          tsup_rng_range(&rng, 2.0, 3.5));
        psc_surface_t s = tsup_surface_new(97, 83, PSC_PIX_XRGB8888);
        render_count(&cfg, &m.mesh, &cam, &s);
        /* Inside/outside from the reference renderer's coverage of the two halves of the square. */
        uint8_t *cover = malloc((size_t)97 * 83);
        double *rgb = malloc((size_t)97 * 83 * 3 * sizeof(double));
        psc_model_t sq = {0};
        double sqpos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
        uint32_t sqidx[6] = {0, 1, 2, 0, 2, 3};
        for (int v = 0; v < 4; v++) { /* the outline with the quantised corners */
            sqpos[3 * v] = m.mesh.position_q16[3 * (v == 0 ? 0 : v == 1 ? n : v == 2 ? g.vertex_count - 1 : n * (n + 1))] / 65536.0;
            sqpos[3 * v + 1] = m.mesh.position_q16[3 * (v == 0 ? 0 : v == 1 ? n : v == 2 ? g.vertex_count - 1 : n * (n + 1)) + 1] / 65536.0;
        }
        sq.pos = sqpos;
        sq.index = sqidx;
        sq.vertex_count = 4;
        sq.triangle_count = 2;
        tsup_mesh_t msq;
        assert_int_equal(tsup_mesh_from_geom(&msq, &sq, 0), 0);
        psc_3d_draw_t d;
        psc_3d_draw_defaults(&d, &msq.mesh);
        d.camera_from_object = cam;
        d.cull_back = false;
        d.depth_test = false;
        tsup_ref_render3d(&cfg, &d, 1, 0, rgb, cover);
        unsigned bad = 0;
        for (unsigned y = 0; y < 83; y++)
            for (unsigned x = 0; x < 97; x++) {
                uint32_t c = count_at(&s, x, y);
                if (c > 1)
                    bad++;
                /* The outline's own pixels may differ by sub-pixel snapping; the inside may not. */
                bool edge_zone = false;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int xx = (int)x + dx, yy = (int)y + dy;
                        if (xx >= 0 && yy >= 0 && xx < 97 && yy < 83 && cover[yy * 97 + xx] != cover[y * 97 + x])
                            edge_zone = true;
                    }
                if (!edge_zone && c != cover[y * 97 + x])
                    bad++;
            }
        if (bad)
            tsup_save_png(&s, "3d_shared_edges_fail.png");
        assert_int_equal(bad, 0);
        free(cover);
        free(rgb);
        tsup_mesh_free(&msq);
        tsup_surface_free(&s);
        tsup_mesh_free(&m);
        psc_model_free(&g);
    }
}

/* ---- tiles --------------------------------------------------------------------------- */

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
    assert_int_equal(tsup_texture_make(&sc->tex, 64, 32, tsup_rng_below(rng, 2) ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888),
                     0);
    sc->n = 1 + tsup_rng_below(rng, 3);
    double yaw = tsup_rng_range(rng, -180, 180), pitch = tsup_rng_range(rng, -80, 80);
    double dist = tsup_rng_range(rng, 0.0, 4.0); /* 0..1: inside the shapes, near-plane clipping */
    for (unsigned i = 0; i < sc->n; i++) {
        psc_model_t *g = &sc->geoms[i];
        switch (tsup_rng_below(rng, 4)) {
        case 0: psc_model_sphere(g, tsup_rng_range(rng, 0.3, 1.5), 16, 9); break;
        case 1: psc_model_torus(g, 1.0, 0.3, 24, 10); break;
        case 2: psc_model_cube(g, tsup_rng_range(rng, 0.3, 1.2)); break;
        default: psc_model_teapot(g, 3); break;
        }
        psc_model_color_by_index(g, i);
        assert_int_equal(tsup_mesh_from_geom(&sc->meshes[i], g, tsup_rng_below(rng, 2)), 0);
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

static void render_scene(const scene_t *sc, psc_3d_config_t cfg, psc_surface_t *s, uint16_t *depth,
                         psc_3d_stats_t *st)
{
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
    t.r.depth_out = depth;
    uint32_t bg = 0x203040;
    assert_int_equal(psc_3d_render(&t.r, sc->draws, sc->n, &bg, s, st), PSC_OK);
    tsup_3d_free(&t);
}

static void test_tiles_identical(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 2024);
    static const uint16_t tiles[][2] = {{16, 16}, {64, 32}, {37, 23}, {200, 8}, {1, 150}};
    unsigned scenes = 60, drawn = 0;
    for (unsigned k = 0; k < scenes; k++) {
        scene_t sc;
        scene_random(&sc, &rng);
        psc_pixfmt_t fmt = tsup_rng_below(&rng, 2) ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888;
        psc_3d_config_t cfg = config(161, 121, tsup_rng_range(&rng, 30, 150), 3 * 2000);
        cfg.depth_bits = tsup_rng_below(&rng, 2) ? 16 : 32;
        psc_surface_t full = tsup_surface_new(161, 121, fmt), tiled = tsup_surface_new(161, 121, fmt);
        uint16_t *zf = calloc(161 * 121, 2), *zt = calloc(161 * 121, 2);
        psc_3d_stats_t sf, stt;
        render_scene(&sc, cfg, &full, zf, &sf);
        const uint16_t *tile = tiles[k % 5];
        cfg.tile_width = tile[0];
        cfg.tile_height = tile[1];
        render_scene(&sc, cfg, &tiled, zt, &stt);
        if (memcmp(full.pixels, tiled.pixels, (size_t)full.stride * full.height) != 0) {
            tsup_save_png(&full, "3d_tiles_full.png");
            tsup_save_png(&tiled, "3d_tiles_tiled.png");
            fail_msg("scene %u: tile mode %ux%u differs from full-buffer mode", k, tile[0], tile[1]);
        }
        assert_memory_equal(zf, zt, 161 * 121 * 2);
        drawn += sf.pixels > 0;
        assert_int_equal(sf.pixels, stt.pixels);
        assert_int_equal(sf.triangles, stt.triangles);
        assert_int_equal(sf.culled, stt.culled);
        assert_int_equal(sf.outside, stt.outside);
        assert_int_equal(sf.clipped, stt.clipped);
        free(zf);
        free(zt);
        tsup_surface_free(&full);
        tsup_surface_free(&tiled);
        scene_free(&sc);
    }
    print_message("  %u random scenes (%u with pixels drawn): tile mode byte-identical (colour and depth), 5 tile shapes\n",
                  scenes, drawn);
    assert_true(drawn >= scenes * 2 / 3);
}

/* ---- depth order ---------------------------------------------------------------------- */

/* Depth of the plane through triangle p[9] (camera space) along the ray of raster point (px, py)
 * of a 128x96 view with hfov 90 degrees. */
static double plane_depth(const double *p, double px, double py)
{
    double f = 64.0, dx = (px - 64) / f, dy = (48 - py) / f;
    double e1[3] = {p[3] - p[0], p[4] - p[1], p[5] - p[2]}, e2[3] = {p[6] - p[0], p[7] - p[1], p[8] - p[2]};
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    return (n[0] * p[0] + n[1] * p[1] + n[2] * p[2]) / (n[0] * dx + n[1] * dy + n[2]);
}

static void test_depth_order_interpenetrating(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 77);
    for (int trial = 0; trial < 40; trial++) {
        /* Two large triangles through the origin with random tilts: they cross along a line. */
        double pos[18];
        for (int t = 0; t < 2; t++) {
            double ax = tsup_rng_range(&rng, -1.2, 1.2), ay = tsup_rng_range(&rng, -1.2, 1.2);
            double base[3][2] = {{-3, -2.5}, {3, -2.5}, {0, 3}};
            for (int v = 0; v < 3; v++) {
                double x = base[v][0], y = base[v][1];
                pos[9 * t + 3 * v] = x;
                pos[9 * t + 3 * v + 1] = y;
                pos[9 * t + 3 * v + 2] = 4 + (t ? -1 : 1) * (ax * x + ay * y) * 0.3;
            }
        }
        uint32_t idx[6] = {0, 1, 2, 3, 4, 5};
        uint32_t colors[6] = {0xFF0000, 0xFF0000, 0xFF0000, 0x00FF00, 0x00FF00, 0x00FF00};
        psc_model_t g = {pos, NULL, NULL, colors, idx, 6, 2, NULL, NULL};
        tsup_mesh_t m;
        assert_int_equal(tsup_mesh_from_geom(&m, &g, 0), 0);
        psc_3d_config_t cfg = config(128, 96, 90, 6);
        cfg.depth_bits = trial % 2 ? 16 : 32;
        psc_3d_draw_t d;
        psc_3d_draw_defaults(&d, &m.mesh);
        d.shade = PSC_SHADE_FLAT;
        d.cull_back = false;
        psc_surface_t s1 = tsup_surface_new(128, 96, PSC_PIX_XRGB8888), s2 = tsup_surface_new(128, 96, PSC_PIX_XRGB8888);
        tsup_3d_t t;
        assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
        uint32_t bg = 0;
        assert_int_equal(psc_3d_render(&t.r, &d, 1, &bg, &s1, NULL), PSC_OK);
        /* The other drawing order. */
        uint16_t swapped[6] = {3, 4, 5, 0, 1, 2};
        psc_mesh_t m2 = m.mesh;
        m2.index = swapped;
        d.mesh = &m2;
        assert_int_equal(psc_3d_render(&t.r, &d, 1, &bg, &s2, NULL), PSC_OK);
        tsup_3d_free(&t);
        /* The exact answer at each pixel: which plane is nearer along its ray; pixels
         * within 2 px of where the planes cross are not judged. */
        unsigned checked = 0;
        for (unsigned y = 0; y < 96; y++)
            for (unsigned x = 0; x < 128; x++) {
                int sign = 0, mixed = 0;
                for (int dy = -2; dy <= 2; dy++)
                    for (int dx = -2; dx <= 2; dx++) {
                        double dd = plane_depth(&pos[0], x + 0.5 + dx, y + 0.5 + dy) -
                                    plane_depth(&pos[9], x + 0.5 + dx, y + 0.5 + dy);
                        int sg = dd < 0 ? -1 : 1;
                        if (dx == 0 && dy == 0)
                            sign = sg;
                        else if (sg != (plane_depth(&pos[0], x + 0.5, y + 0.5) - plane_depth(&pos[9], x + 0.5, y + 0.5) < 0 ? -1 : 1))
                            mixed = 1;
                    }
                uint32_t c1 = ((uint32_t *)s1.pixels)[y * 128 + x] & 0xFFFFFFu;
                uint32_t c2 = ((uint32_t *)s2.pixels)[y * 128 + x] & 0xFFFFFFu;
                if (c1 == 0 || mixed)
                    continue; /* outside both, or at the crossing */
                uint32_t want = sign < 0 ? 0xFF0000u : 0x00FF00u;
                if (c1 != want || c2 != want)
                    fail_msg("trial %d pixel (%u,%u): got %06x / %06x, nearer is %06x", trial, x, y, c1, c2, want);
                checked++;
            }
        assert_true(checked > 2000);
        tsup_surface_free(&s1);
        tsup_surface_free(&s2);
        tsup_mesh_free(&m);
    }
}

/* ---- clipping ---------------------------------------------------------------------------- */

/* Render a scene in core and in the reference; most pixels must agree, none behind the camera drawn. */
static void compare_reference(const char *name, psc_3d_draw_t *d, unsigned n, psc_3d_config_t cfg, double max_frac)
{
    psc_surface_t s = tsup_surface_new(cfg.width, cfg.height, PSC_PIX_XRGB8888);
    double *rgb = malloc((size_t)cfg.width * cfg.height * 3 * sizeof(double));
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
    uint32_t bg = 0x101010;
    assert_int_equal(psc_3d_render(&t.r, d, n, &bg, &s, NULL), PSC_OK);
    tsup_3d_free(&t);
    tsup_ref_render3d(&cfg, d, n, bg, rgb, NULL);
    double frac = tsup_frac_differing(&s, rgb, 24);
    print_message("  %-34s %.3f%% of pixels differ by more than 24 levels\n", name, frac * 100);
    if (frac > max_frac) {
        char fn[128];
        snprintf(fn, sizeof fn, "3d_clip_%s.png", name);
        tsup_save_png(&s, fn);
    }
    assert_true(frac <= max_frac);
    free(rgb);
    tsup_surface_free(&s);
}

static void test_near_plane_extremes(void **state)
{
    (void)state;
    psc_model_t g;
    psc_model_sphere(&g, 1.0, 32, 17);
    psc_model_color_by_index(&g, 5);
    tsup_mesh_t m;
    assert_int_equal(tsup_mesh_from_geom(&m, &g, 0), 0);
    psc_3d_config_t cfg = config(160, 120, 90, m.mesh.vertex_count);
    psc_3d_draw_t d;
    psc_3d_draw_defaults(&d, &m.mesh);
    d.cull_back = false;
    /* Inside, at the centre and off-centre, looking around. */
    for (int k = 0; k < 6; k++) {
        psc_mat4_q16_t cam;
        psc_vec3_q16_t eye = {k * 9000, -k * 5000, k * 3000};
        psc_mat4_camera(&cam, eye, tsup_bam_from_deg(k * 61.0), (int32_t)tsup_bam_from_deg(k * 23.0 - 60));
        d.camera_from_object = cam;
        compare_reference("inside sphere", &d, 1, cfg, 0.03);
    }
    /* On a vertex of the mesh: that vertex has z = 0. */
    for (uint32_t v = 0; v < m.mesh.vertex_count; v += 37) {
        psc_vec3_q16_t eye = {m.mesh.position_q16[3 * v], m.mesh.position_q16[3 * v + 1], m.mesh.position_q16[3 * v + 2]};
        psc_mat4_q16_t cam;
        psc_mat4_camera(&cam, eye, tsup_bam_from_deg(v * 7.0), (int32_t)tsup_bam_from_deg((double)(v % 120) - 60));
        d.camera_from_object = cam;
        compare_reference("camera on a vertex", &d, 1, cfg, 0.03);
    }
    tsup_mesh_free(&m);
    psc_model_free(&g);

    /* Huge triangles crossing the near plane and the guard band, coordinates near +-32000 units. */
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 99);
    for (int k = 0; k < 60; k++) {
        double pos[9];
        for (int i = 0; i < 9; i++)
            pos[i] = tsup_rng_range(&rng, -32000, 32000);
        if (k % 3 == 0)
            pos[2] = tsup_rng_range(&rng, -1e-3, 1e-3); /* a vertex on the camera plane */
        uint32_t idx[3] = {0, 1, 2}, col[3] = {0xFF0000, 0x00FF00, 0x0000FF};
        psc_model_t tri = {pos, NULL, NULL, col, idx, 3, 1, NULL, NULL};
        tsup_mesh_t tm;
        assert_int_equal(tsup_mesh_from_geom(&tm, &tri, 0), 0);
        psc_3d_config_t c2 = config(128, 96, tsup_rng_range(&rng, 20, 160), 3);
        c2.far_q16 = 32767 * PSC_Q16_ONE;
        c2.near_q16 = PSC_Q16_ONE;
        psc_3d_draw_t td;
        psc_3d_draw_defaults(&td, &tm.mesh);
        td.cull_back = false;
        td.shade = k % 2 ? PSC_SHADE_GOURAUD : PSC_SHADE_FLAT;
        compare_reference("huge triangle across near plane", &td, 1, c2, 0.02);
        tsup_mesh_free(&tm);
    }
}

/* Nothing behind the camera: a mesh entirely behind it draws no pixel. */
static void test_nothing_behind_camera(void **state)
{
    (void)state;
    psc_model_t g;
    psc_model_cube(&g, 1.0);
    tsup_mesh_t m;
    assert_int_equal(tsup_mesh_from_geom(&m, &g, 0), 0);
    psc_3d_config_t cfg = config(64, 48, 120, 24);
    psc_3d_draw_t d;
    psc_3d_draw_defaults(&d, &m.mesh);
    d.cull_back = false;
    psc_mat4_q16_t cam;
    psc_mat4_translate(&cam, (psc_vec3_q16_t){0, 0, -3 * PSC_Q16_ONE}); /* the cube at z = -3: behind */
    d.camera_from_object = cam;
    psc_surface_t s = tsup_surface_new(64, 48, PSC_PIX_RGB565);
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
    psc_3d_stats_t st;
    uint32_t bg = 0;
    assert_int_equal(psc_3d_render(&t.r, &d, 1, &bg, &s, &st), PSC_OK);
    assert_int_equal(st.pixels, 0);
    assert_int_equal(st.outside, 12);
    tsup_3d_free(&t);
    tsup_surface_free(&s);
    tsup_mesh_free(&m);
    psc_model_free(&g);
}

/* ---- arguments and memory -------------------------------------------------------------------- */

static void test_config_and_memory(void **state)
{
    (void)state;
    psc_3d_config_t c = config(320, 240, 60, 10000);
    assert_true(psc_3d_workspace_size(&c) > 0);
    assert_int_equal(psc_3d_depth_bytes(&c), 320 * 240 * 4);
    c.depth_bits = 16;
    assert_int_equal(psc_3d_depth_bytes(&c), 320 * 240 * 2);
    c.tile_width = 64;
    c.tile_height = 32;
    assert_int_equal(psc_3d_depth_bytes(&c), 64 * 32 * 2);
    psc_3d_config_t bad = c;
    bad.depth_bits = 24;
    assert_int_equal(psc_3d_workspace_size(&bad), 0);
    bad = c;
    bad.far_q16 = bad.near_q16; /* far < 2 near */
    assert_int_equal(psc_3d_workspace_size(&bad), 0);
    bad = c;
    bad.far_q16 = bad.near_q16 * 65536 + 1 > INT32_MAX ? INT32_MAX : bad.near_q16 * 65536 + 1;
    bad.near_q16 = 1;
    assert_int_equal(psc_3d_workspace_size(&bad), 0);
    bad = c;
    bad.hfov = 0;
    assert_int_equal(psc_3d_workspace_size(&bad), 0);
    bad = c;
    bad.tile_height = 0;
    assert_int_equal(psc_3d_workspace_size(&bad), 0);
    /* A short workspace and a frame with too many vertices are refused. */
    psc_3d_t r;
    size_t n = psc_3d_workspace_size(&c);
    void *ws = aligned_alloc(64, (n + 63) / 64 * 64);
    assert_int_equal(psc_3d_init(&r, &c, ws, n - 1), PSC_ERR_NOMEM);
    c.max_vertices = 10;
    assert_int_equal(psc_3d_init(&r, &c, ws, n), PSC_OK);
    psc_model_t g;
    psc_model_cube(&g, 1.0);
    tsup_mesh_t m;
    assert_int_equal(tsup_mesh_from_geom(&m, &g, 0), 0);
    psc_3d_draw_t d;
    psc_3d_draw_defaults(&d, &m.mesh);
    psc_surface_t s = tsup_surface_new(320, 240, PSC_PIX_RGB565);
    assert_int_equal(psc_3d_render(&r, &d, 1, NULL, &s, NULL), PSC_ERR_NOMEM);
    /* A bad index is refused, not followed. */
    c.max_vertices = 100;
    assert_int_equal(psc_3d_init(&r, &c, ws, n), PSC_OK);
    m.index[5] = 24;
    assert_int_equal(psc_3d_render(&r, &d, 1, NULL, &s, NULL), PSC_ERR_ARG);
    m.index[5] = 3;
    /* A wrong surface size is refused. */
    psc_surface_t small = tsup_surface_new(32, 24, PSC_PIX_RGB565);
    assert_int_equal(psc_3d_render(&r, &d, 1, NULL, &small, NULL), PSC_ERR_ARG);
    assert_int_equal(psc_3d_render(&r, &d, 1, NULL, &s, NULL), PSC_OK);
    tsup_surface_free(&small);
    tsup_surface_free(&s);
    tsup_mesh_free(&m);
    psc_model_free(&g);
    free(ws);
}

/* ---- row spans ------------------------------------------------------------------------ */

/* A random coordinate in 1/16 pixel: mostly near the target, sometimes far outside (up to the raster's range). */
static int32_t span_coord(tsup_rng_t *rng, int32_t size_px)
{
    switch (tsup_rng_below(rng, 6)) {
    case 0: /* anywhere the rasterizer takes */
        return (int32_t)tsup_rng_range(rng, -PSC_RASTER_COORD_MAX_Q4 + 1, PSC_RASTER_COORD_MAX_Q4 - 1);
    case 1: /* on a pixel centre or a pixel edge, exactly */
        return (int32_t)tsup_rng_below(rng, (uint32_t)size_px * 2u + 1u) * 8 - 8 * (int32_t)tsup_rng_below(rng, 2);
    default:
        return (int32_t)tsup_rng_range(rng, -4 * 16, (size_px + 4) * 16);
    }
}

/* The rows a triangle draws are exactly the pixel centres its three edge functions (psc_raster_edges) put inside,
 * within the target rectangle: narrow boxes (walked), wide ones (divided), slivers, huge and vertex-on-centre
 * triangles, 20 000 of them, flat and Gouraud, without and with a depth buffer (every depth nearer than the
 * cleared buffer's, so that the depth test passes everywhere). */
static void test_spans_follow_edge_functions(void **state)
{
    (void)state;
    enum { W = 157, H = 61 };
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 2611);
    psc_surface_t s = tsup_surface_new(W, H, PSC_PIX_XRGB8888);
    uint16_t *depth = malloc((size_t)W * H * sizeof *depth);
    unsigned drawn_total = 0, wide = 0, tiny_empty = 0;
    for (int trial = 0; trial < 20000; trial++) {
        psc_raster_vertex_t v[3];
        memset(v, 0, sizeof v);
        int32_t scale = tsup_rng_below(&rng, 4) == 0 ? 1 : 16; /* tiny triangles: coordinates within a pixel or two */
        for (int k = 0; k < 3; k++) {
            v[k].x_q4 = scale == 1 ? (int32_t)tsup_rng_range(&rng, 0, W * 16) : span_coord(&rng, W);
            v[k].y_q4 = scale == 1 ? (int32_t)tsup_rng_range(&rng, 0, H * 16) : span_coord(&rng, H);
            v[k].depth_q32 = tsup_rng_u32(&rng) >> 1;
            v[k].q_q28 = PSC_RASTER_Q_ONE;
            v[k].color = tsup_rng_u32(&rng) & 0xFFFFFFu;
            v[k].light_q8 = 256;
        }
        if (scale == 1) /* a tiny one: the other two vertices within 2 pixels of the first */
            for (int k = 1; k < 3; k++) {
                v[k].x_q4 = v[0].x_q4 + (int32_t)tsup_rng_range(&rng, -32, 32);
                v[k].y_q4 = v[0].y_q4 + (int32_t)tsup_rng_range(&rng, -32, 32);
            }
        psc_raster_edge_t e[3];
        bool some = psc_raster_edges(&v[0], &v[1], &v[2], e);
        uint16_t x0 = (uint16_t)tsup_rng_below(&rng, W / 3), y0 = (uint16_t)tsup_rng_below(&rng, H / 3);
        uint16_t x1 = (uint16_t)(W - tsup_rng_below(&rng, W / 3)), y1 = (uint16_t)(H - tsup_rng_below(&rng, H / 3));
        bool use_depth = tsup_rng_below(&rng, 2);
        psc_raster_state_t st = {0};
        st.shade = tsup_rng_below(&rng, 2) ? PSC_SHADE_GOURAUD : PSC_SHADE_FLAT;
        st.blend = PSC_BLEND_REPLACE;
        st.depth_test = use_depth;
        st.opacity_q8 = 256;
        memset(s.pixels, 0, (size_t)s.stride * H);
        for (size_t i = 0; i < (size_t)W * H; i++)
            depth[i] = 0xFFFF;
        psc_raster_target_t t = {&s, use_depth ? depth + (size_t)y0 * W + x0 : NULL, W * sizeof *depth, 16,
                                 x0, y0, x1, y1, NULL, NULL, 0, NULL, 0, 0};
        uint32_t drawn = psc_raster_triangle(&t, &st, &v[0], &v[1], &v[2]);
        unsigned inside = 0, bad = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                int64_t cx = 16 * x + 8, cy = 16 * y + 8;
                bool in = some && x >= x0 && x < x1 && y >= y0 && y < y1;
                for (int k = 0; k < 3 && in; k++)
                    in = e[k].a * cx + e[k].b * cy + e[k].c >= 0;
                /* a drawn pixel is opaque (even black), and every depth is nearer than the cleared buffer's */
                bool lit = ((uint32_t *)s.pixels)[(size_t)y * (s.stride / 4) + x] != 0;
                if (in != lit)
                    bad++;
                inside += in;
            }
        if (bad)
            fail_msg("trial %d: %u pixels differ from the edge functions' (%d,%d) (%d,%d) (%d,%d)", trial, bad,
                     v[0].x_q4, v[0].y_q4, v[1].x_q4, v[1].y_q4, v[2].x_q4, v[2].y_q4);
        assert_int_equal(drawn, inside);
        drawn_total += drawn;
        wide += inside > 0 && (x1 - x0) > 16;
        tiny_empty += scale == 1 && some && inside == 0;
    }
    /* the cases reached: many triangles drew, wide boxes among them, and tiny ones holding no centre (left before
     * their set-up: psc_raster_triangle's small boxes) */
    print_message("  %u pixels drawn, %u wide boxes, %u tiny triangles holding no pixel centre\n", drawn_total, wide,
                  tiny_empty);
    assert_true(drawn_total > 1000000u);
    assert_true(wide > 2000u);
    assert_true(tiny_empty > 2000u);
    free(depth);
    tsup_surface_free(&s);
}

/* An RGB565 texture draws what the same texture widened to XRGB8888 (psc_rgb565_to_xrgb) draws, byte for byte:
 * nearest and bilinear, perspective and affine, lit and not, over 3 000 random triangles with texels of every value. */
static void test_rgb565_texture_is_its_xrgb(void **state)
{
    (void)state;
    enum { W = 96, H = 72, T = 64 };
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 565);
    uint16_t *t565 = malloc((size_t)T * T * sizeof *t565);
    uint32_t *t888 = malloc((size_t)T * T * sizeof *t888);
    for (uint32_t i = 0; i < (uint32_t)T * T; i++) {
        t565[i] = (uint16_t)(i < 65536u / 16u ? i * 16u + tsup_rng_below(&rng, 16) : tsup_rng_u32(&rng));
        t888[i] = psc_rgb565_to_xrgb(t565[i]);
    }
    psc_texture_t a, b;
    assert_int_equal(psc_texture_init(&a, T, T, PSC_PIX_RGB565, T * 2, t565), PSC_OK);
    assert_int_equal(psc_texture_init(&b, T, T, PSC_PIX_XRGB8888, T * 4, t888), PSC_OK);
    psc_surface_t sa = tsup_surface_new(W, H, PSC_PIX_XRGB8888), sb = tsup_surface_new(W, H, PSC_PIX_XRGB8888);
    unsigned drawn = 0;
    for (int trial = 0; trial < 3000; trial++) {
        psc_raster_vertex_t v[3];
        memset(v, 0, sizeof v);
        for (int k = 0; k < 3; k++) {
            v[k].x_q4 = (int32_t)tsup_rng_range(&rng, -8 * 16, (W + 8) * 16);
            v[k].y_q4 = (int32_t)tsup_rng_range(&rng, -8 * 16, (H + 8) * 16);
            v[k].depth_q32 = tsup_rng_u32(&rng);
            v[k].q_q28 = trial % 2 ? PSC_RASTER_Q_ONE
                                   : (int32_t)tsup_rng_range(&rng, PSC_RASTER_Q_MIN, PSC_RASTER_Q_ONE);
            v[k].u_q16 = (int32_t)tsup_rng_range(&rng, -2 * 65536, 3 * 65536);
            v[k].v_q16 = (int32_t)tsup_rng_range(&rng, -2 * 65536, 3 * 65536);
            v[k].light_q8 = (int32_t)tsup_rng_below(&rng, 257);
        }
        psc_raster_state_t st = {0};
        st.shade = PSC_SHADE_TEXTURE;
        st.filter = tsup_rng_below(&rng, 3) ? PSC_TEX_BILINEAR : PSC_TEX_NEAREST;
        st.blend = PSC_BLEND_REPLACE;
        st.opacity_q8 = 256;
        st.modulate = tsup_rng_below(&rng, 2);
        memset(sa.pixels, 0, (size_t)sa.stride * H);
        memset(sb.pixels, 0, (size_t)sb.stride * H);
        psc_raster_target_t ta = {&sa, NULL, 0, 16, 0, 0, W, H, NULL, NULL, 0, NULL, 0, 0}, tb = ta;
        tb.surface = &sb;
        st.texture = &a;
        uint32_t na = psc_raster_triangle(&ta, &st, &v[0], &v[1], &v[2]);
        st.texture = &b;
        uint32_t nb = psc_raster_triangle(&tb, &st, &v[0], &v[1], &v[2]);
        assert_int_equal(na, nb);
        assert_memory_equal(sa.pixels, sb.pixels, (size_t)sa.stride * H);
        drawn += na;
    }
    assert_true(drawn > 1000000u);
    tsup_surface_free(&sa);
    tsup_surface_free(&sb);
    free(t565);
    free(t888);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_watertight_closed_meshes),
        cmocka_unit_test(test_shared_edges_drawn_once),
        cmocka_unit_test(test_spans_follow_edge_functions),
        cmocka_unit_test(test_rgb565_texture_is_its_xrgb),
        cmocka_unit_test(test_tiles_identical),
        cmocka_unit_test(test_depth_order_interpenetrating),
        cmocka_unit_test(test_near_plane_extremes),
        cmocka_unit_test(test_nothing_behind_camera),
        cmocka_unit_test(test_config_and_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
