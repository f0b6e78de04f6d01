/* SPDX-License-Identifier: MIT */
/*
 * test_3d_area.c - area subdivision (psc_3d_render.h, cfg.hsr = PSC_3D_HSR_AREA) against the z-buffer.
 *
 *  - Bytes: random triangle soups (large and tiny triangles, many overlapping,
 *    intersecting and coincident ones - equal depths, where only submission
 *    order decides - triangles crossing the near plane, draws without the
 *    depth test or blending additively) and random scenes of meshes (camera
 *    inside and outside, every shading but view textures), at 16- and 32-bit
 *    depth, both output formats, with and without tiles: area subdivision
 *    writes the z-buffer's colour and depth bytes, and the same counts of
 *    triangles, culled, clipped and outside.
 *  - Savings: on a scene of large polygons (a room's walls, boxes) area
 *    subdivision depth-tests fewer pixels and writes fewer than the z-buffer,
 *    and finishes areas whole; it never tests more than the z-buffer.
 *  - With the A-buffer, the z-buffer's bytes (tiles drawn through the depth buffer).
 *  - The configuration check and the workspace the method adds.
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
#include "psc_testsupport.h"
#include "tsup_3d.h"

#define W 161
#define H 121
#define MAX_TRIS 400

/* A triangle soup in camera space (the draw's transform is the identity). */
typedef struct {
    int32_t pos[3 * 3 * MAX_TRIS];
    int16_t uv[2 * 3 * MAX_TRIS];
    uint32_t color[3 * MAX_TRIS];
    uint16_t index[3 * MAX_TRIS];
    psc_mesh_t mesh;
} soup_t;

/* A point at raster-ish position (sx, sy) in [-0.2, 1.2] of the view and depth z (units), hfov 90 degrees. */
static void put_vertex(soup_t *s, unsigned v, double sx, double sy, double z)
{
    double aspect = (double)H / W;
    s->pos[3 * v] = (int32_t)lround((sx * 2 - 1) * z * 65536.0);
    s->pos[3 * v + 1] = (int32_t)lround((1 - sy * 2) * aspect * z * 65536.0);
    s->pos[3 * v + 2] = (int32_t)lround(z * 65536.0);
}

/* n triangles of every kind the method must get right. */
static void soup_random(soup_t *s, tsup_rng_t *rng, unsigned n)
{
    memset(s, 0, sizeof *s);
    unsigned v = 0;
    for (unsigned t = 0; t < n; t++) {
        unsigned kind = tsup_rng_below(rng, 10);
        double z0 = tsup_rng_range(rng, 0.3, 12.0);
        if (kind == 0 && t > 0) { /* coincident with an earlier one: equal depths, another colour */
            unsigned src = tsup_rng_below(rng, t);
            for (unsigned k = 0; k < 3; k++) {
                memcpy(&s->pos[3 * (v + k)], &s->pos[3 * (3 * src + k)], 3 * sizeof(int32_t));
                s->uv[2 * (v + k)] = s->uv[2 * (3 * src + k)];
                s->uv[2 * (v + k) + 1] = s->uv[2 * (3 * src + k) + 1];
            }
        } else {
            double size = kind <= 3 ? tsup_rng_range(rng, 0.6, 2.5)     /* large: covers areas whole */
                          : kind <= 5 ? tsup_rng_range(rng, 0.002, 0.03) /* tiny */
                                      : tsup_rng_range(rng, 0.05, 0.4);
            double cx = tsup_rng_range(rng, -0.1, 1.1), cy = tsup_rng_range(rng, -0.1, 1.1);
            for (unsigned k = 0; k < 3; k++) {
                double z = z0 + tsup_rng_range(rng, -1, 1) * (kind == 9 ? z0 * 1.2 : z0 * 0.3); /* 9: near-plane */
                put_vertex(s, v + k, cx + tsup_rng_range(rng, -size, size), cy + tsup_rng_range(rng, -size, size),
                           z < 0.01 ? 0.01 : z);
                s->uv[2 * (v + k)] = (int16_t)tsup_rng_range(rng, -8000, 8000);
                s->uv[2 * (v + k) + 1] = (int16_t)tsup_rng_range(rng, -8000, 8000);
            }
            if (kind == 8) /* a flat one, facing the camera: equal depth at every pixel */
                for (unsigned k = 1; k < 3; k++)
                    s->pos[3 * (v + k) + 2] = s->pos[3 * v + 2];
        }
        for (unsigned k = 0; k < 3; k++) {
            s->color[v + k] = tsup_rng_u32(rng) & 0xFFFFFFu;
            s->index[v + k] = (uint16_t)(v + k);
        }
        v += 3;
    }
    s->mesh = (psc_mesh_t){.vertex_count = v, .triangle_count = n, .position_q16 = s->pos, .uv_q12 = s->uv,
                           .color = s->color, .index = s->index, .base_color = 0x808080};
}

typedef struct {
    psc_surface_t s;
    uint16_t *depth;
    psc_3d_stats_t st;
} frame_t;

/* One frame, with its depth exported (depth) or not (area subdivision then draws whole areas untested). */
static void render(frame_t *f, psc_3d_config_t cfg, const psc_3d_draw_t *d, unsigned n, psc_pixfmt_t fmt, bool depth)
{
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
    f->s = tsup_surface_new(cfg.width, cfg.height, fmt);
    f->depth = calloc((size_t)cfg.width * cfg.height, 2);
    assert_non_null(f->depth);
    t.r.depth_out = depth ? f->depth : NULL;
    uint32_t bg = 0x203040;
    assert_int_equal(psc_3d_render(&t.r, d, n, &bg, &f->s, &f->st), PSC_OK);
    tsup_3d_free(&t);
}

static void frame_free(frame_t *f)
{
    tsup_surface_free(&f->s);
    free(f->depth);
}

/* Render both ways; fail with pictures when a byte differs. */
static void compare(const char *what, unsigned k, psc_3d_config_t cfg, const psc_3d_draw_t *d, unsigned n,
                    psc_pixfmt_t fmt, psc_3d_stats_t *z_st, psc_3d_stats_t *a_st)
{
    frame_t z, a, u;
    cfg.hsr = PSC_3D_HSR_ZBUFFER;
    render(&z, cfg, d, n, fmt, true);
    cfg.hsr = PSC_3D_HSR_AREA;
    render(&a, cfg, d, n, fmt, true);
    render(&u, cfg, d, n, fmt, false);
    if (memcmp(z.s.pixels, u.s.pixels, (size_t)z.s.stride * z.s.height) != 0) {
        tsup_save_png(&z.s, "3d_area_zbuffer.png");
        tsup_save_png(&u.s, "3d_area_untested.png");
        fail_msg("%s %u (tiles %ux%u, depth %u bits): area subdivision without the depth export differs from the "
                 "z-buffer", what, k, cfg.tile_width, cfg.tile_height, cfg.depth_bits);
    }
    assert_true(u.st.depth_tests <= a.st.depth_tests);
    assert_int_equal(u.st.areas_whole, a.st.areas_whole);
    if (memcmp(z.s.pixels, a.s.pixels, (size_t)z.s.stride * z.s.height) != 0 ||
        memcmp(z.depth, a.depth, (size_t)cfg.width * cfg.height * 2) != 0) {
        tsup_save_png(&z.s, "3d_area_zbuffer.png");
        tsup_save_png(&a.s, "3d_area_area.png");
        unsigned bad = 0;
        for (size_t i = 0; i < (size_t)cfg.width * cfg.height; i++)
            bad += z.depth[i] != a.depth[i];
        fail_msg("%s %u (tiles %ux%u, depth %u bits): area subdivision differs from the z-buffer (%u depths)", what,
                 k, cfg.tile_width, cfg.tile_height, cfg.depth_bits, bad);
    }
    assert_int_equal(z.st.triangles, a.st.triangles);
    assert_int_equal(z.st.culled, a.st.culled);
    assert_int_equal(z.st.clipped, a.st.clipped);
    assert_int_equal(z.st.outside, a.st.outside);
    assert_true(a.st.depth_tests <= z.st.depth_tests);
    assert_true(a.st.pixels <= z.st.pixels);
    assert_int_equal(z.st.areas_whole + z.st.areas_leaf, 0);
    *z_st = z.st;
    *a_st = u.st;
    frame_free(&z);
    frame_free(&a);
    frame_free(&u);
}

static psc_3d_config_t config(tsup_rng_t *rng, double hfov, uint32_t max_vertices)
{
    static const uint16_t tiles[][2] = {{0, 0}, {16, 16}, {64, 32}, {37, 23}, {200, 8}};
    const uint16_t *tl = tiles[tsup_rng_below(rng, 5)];
    psc_3d_config_t c = {W, H, tl[0], tl[1], tsup_rng_below(rng, 2) ? 16 : 32, tsup_bam_from_deg(hfov),
                         PSC_Q16_ONE / 16, 64 * PSC_Q16_ONE, max_vertices, PSC_3D_HSR_ZBUFFER};
    return c;
}

static void test_soups_bytes(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 31);
    tsup_texture_t tex;
    assert_int_equal(tsup_texture_make(&tex, 64, 32, PSC_PIX_RGB565), 0);
    static soup_t soups[3];
    unsigned scenes = 150, whole = 0;
    uint64_t tests_z = 0, tests_a = 0;
    for (unsigned k = 0; k < scenes; k++) {
        unsigned nd = 1 + tsup_rng_below(&rng, 3);
        psc_3d_draw_t d[3];
        for (unsigned i = 0; i < nd; i++) {
            soup_random(&soups[i], &rng, 1 + tsup_rng_below(&rng, i == 0 ? MAX_TRIS : 40));
            psc_3d_draw_defaults(&d[i], &soups[i].mesh);
            d[i].shade = (psc_shade_t)tsup_rng_below(&rng, 3);
            d[i].filter = (psc_tex_filter_t)tsup_rng_below(&rng, 2);
            d[i].texture = &tex.tex;
            d[i].cull_back = tsup_rng_below(&rng, 2);
            if (i > 0 && tsup_rng_below(&rng, 4) == 0) /* drawn over whatever the depth */
                d[i].depth_test = false;
            else if (i > 0 && tsup_rng_below(&rng, 4) == 0)
                d[i].blend = PSC_BLEND_ADD;
        }
        psc_3d_config_t cfg = config(&rng, 90, 3 * 3 * MAX_TRIS);
        psc_3d_stats_t zs, as;
        compare("soup", k, cfg, d, nd, tsup_rng_below(&rng, 2) ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888, &zs, &as);
        whole += as.areas_whole;
        tests_z += zs.depth_tests;
        tests_a += as.depth_tests;
    }
    print_message("  %u random soups: area subdivision = z-buffer bytes; %u areas finished whole, depth tests %.2f of "
                  "the z-buffer's\n", scenes, whole, (double)tests_a / (double)tests_z);
    assert_true(whole > scenes);           /* the method really finishes areas early */
    assert_true(tests_a < tests_z);
    tsup_texture_free(&tex);
}

static void test_meshes_bytes(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 2031);
    tsup_texture_t tex;
    assert_int_equal(tsup_texture_make(&tex, 64, 32, PSC_PIX_XRGB8888), 0);
    unsigned scenes = 60, areas = 0;
    for (unsigned k = 0; k < scenes; k++) {
        tsup_mesh_t meshes[3];
        psc_model_t geoms[3];
        psc_3d_draw_t d[3];
        unsigned n = 1 + tsup_rng_below(&rng, 3);
        double yaw = tsup_rng_range(&rng, -180, 180), pitch = tsup_rng_range(&rng, -80, 80);
        double dist = tsup_rng_range(&rng, 0.0, 4.0); /* inside the shapes too: near-plane clipping */
        for (unsigned i = 0; i < n; i++) {
            tsup_shape_make((tsup_shape_t)tsup_rng_below(&rng, 4), &geoms[i]);
            psc_model_color_by_index(&geoms[i], i);
            assert_int_equal(tsup_mesh_from_geom(&meshes[i], &geoms[i], tsup_rng_below(&rng, 2)), 0);
            psc_3d_draw_defaults(&d[i], &meshes[i].mesh);
            psc_mat4_q16_t cam, obj, rot, tr;
            tsup_orbit_matrix(&cam, yaw, pitch, dist);
            psc_mat4_rotate_y(&rot, tsup_rng_u32(&rng));
            psc_mat4_translate(&tr, (psc_vec3_q16_t){(int32_t)tsup_rng_range(&rng, -65536, 65536),
                                                     (int32_t)tsup_rng_range(&rng, -65536, 65536),
                                                     (int32_t)tsup_rng_range(&rng, -65536, 65536)});
            psc_mat4_mul(&obj, &tr, &rot);
            psc_mat4_mul(&d[i].camera_from_object, &cam, &obj);
            d[i].shade = (psc_shade_t)tsup_rng_below(&rng, 3);
            if (tsup_rng_below(&rng, 4) == 0)
                d[i].shade = PSC_SHADE_PHONG;
            d[i].filter = (psc_tex_filter_t)tsup_rng_below(&rng, 2);
            d[i].cull_back = tsup_rng_below(&rng, 2);
            d[i].lit = tsup_rng_below(&rng, 2);
            d[i].light_dir = psc_vec3_normalize((psc_vec3_q16_t){-20000, 30000, -40000});
            d[i].texture = &tex.tex;
        }
        psc_3d_config_t cfg = config(&rng, tsup_rng_range(&rng, 30, 150), 3 * 40000);
        psc_3d_stats_t zs, as;
        compare("mesh scene", k, cfg, d, n, tsup_rng_below(&rng, 2) ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888, &zs, &as);
        areas += as.areas_whole + as.areas_leaf;
        for (unsigned i = 0; i < n; i++) {
            tsup_mesh_free(&meshes[i]);
            psc_model_free(&geoms[i]);
        }
    }
    print_message("  %u random mesh scenes: area subdivision = z-buffer bytes (colour and depth), %u areas\n", scenes,
                  areas);
    assert_true(areas > scenes * 10);
    tsup_texture_free(&tex);
}

/* A room seen from inside: six walls of two triangles each, two boxes in front of the far wall. */
static void test_large_polygons_save(void **state)
{
    (void)state;
    psc_model_t room, box;
    psc_model_cube(&room, 4.0);
    psc_model_cube(&box, 0.8);
    psc_model_color_by_index(&room, 0);
    psc_model_color_by_index(&box, 1);
    tsup_mesh_t mr, mb;
    assert_int_equal(tsup_mesh_from_geom(&mr, &room, 0), 0);
    assert_int_equal(tsup_mesh_from_geom(&mb, &box, 0), 0);
    psc_3d_draw_t d[3];
    psc_mat4_q16_t cam, tr, m;
    tsup_orbit_matrix(&cam, 25, 10, 0.5);
    psc_3d_draw_defaults(&d[0], &mr.mesh);
    d[0].cull_back = false; /* seen from inside */
    d[0].camera_from_object = cam;
    for (unsigned i = 1; i < 3; i++) {
        psc_3d_draw_defaults(&d[i], &mb.mesh);
        psc_mat4_translate(&tr, (psc_vec3_q16_t){i == 1 ? -40000 : 50000, -20000, i == 1 ? -80000 : -60000});
        psc_mat4_mul(&m, &cam, &tr);
        d[i].camera_from_object = m;
    }
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 5);
    for (unsigned bits = 16; bits <= 32; bits += 16) {
        psc_3d_config_t cfg = {320, 240, 0, 0, (uint8_t)bits, tsup_bam_from_deg(90), PSC_Q16_ONE / 16,
                               64 * PSC_Q16_ONE, 1000, PSC_3D_HSR_ZBUFFER};
        psc_3d_stats_t zs, as;
        compare("room", bits, cfg, d, 3, PSC_PIX_RGB565, &zs, &as);
        print_message("  room at %u-bit depth: depth tests %llu (z-buffer %llu), writes %llu (%llu); areas whole %u, "
                      "leaves %u\n", bits, (unsigned long long)as.depth_tests, (unsigned long long)zs.depth_tests,
                      (unsigned long long)as.pixels, (unsigned long long)zs.pixels, as.areas_whole, as.areas_leaf);
        assert_true(as.depth_tests * 2 < zs.depth_tests);
        assert_true(as.pixels < zs.pixels);
        assert_true(as.areas_whole > as.areas_leaf);
    }
    tsup_mesh_free(&mr);
    tsup_mesh_free(&mb);
    psc_model_free(&room);
    psc_model_free(&box);
}

/* With the A-buffer on, the frame is the z-buffer's (fragments' pool use is part of the result). */
static void test_abuffer_bytes(void **state)
{
    (void)state;
    psc_model_t g;
    tsup_shape_make(TSUP_TEAPOT, &g);
    tsup_mesh_t m;
    assert_int_equal(tsup_mesh_from_geom(&m, &g, 1), 0);
    psc_3d_draw_t d;
    psc_3d_draw_defaults(&d, &m.mesh);
    tsup_orbit_matrix(&d.camera_from_object, 30, -20, 2.2);
    psc_surface_t out[2];
    for (unsigned h = 0; h < 2; h++) {
        psc_3d_config_t cfg = {W, H, 32, 32, 16, tsup_bam_from_deg(60), PSC_Q16_ONE / 32, 16 * PSC_Q16_ONE,
                               m.mesh.vertex_count, (uint8_t)h};
        tsup_3d_t t;
        assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
        size_t bytes = psc_3d_abuffer_bytes(&cfg, 2000);
        void *mem = aligned_alloc(8, (bytes + 7u) & ~(size_t)7u);
        assert_int_equal(psc_3d_set_abuffer(&t.r, mem, bytes), PSC_OK);
        out[h] = tsup_surface_new(W, H, PSC_PIX_XRGB8888);
        uint32_t bg = 0x102030;
        assert_int_equal(psc_3d_render(&t.r, &d, 1, &bg, &out[h], NULL), PSC_OK);
        tsup_3d_free(&t);
        free(mem);
    }
    assert_memory_equal(out[0].pixels, out[1].pixels, (size_t)out[0].stride * H);
    tsup_surface_free(&out[0]);
    tsup_surface_free(&out[1]);
    tsup_mesh_free(&m);
    psc_model_free(&g);
}

static void test_config(void **state)
{
    (void)state;
    psc_3d_config_t c = {320, 240, 0, 0, 16, tsup_bam_from_deg(60), PSC_Q16_ONE, 8 * PSC_Q16_ONE, 3000,
                         PSC_3D_HSR_ZBUFFER};
    size_t z = psc_3d_workspace_size(&c);
    c.hsr = PSC_3D_HSR_AREA;
    size_t a = psc_3d_workspace_size(&c);
    /* the one row's list and the frame's (4 x 3000 + 256 entries each, the depth buffer's full screen has neither)
     * with its parts' counts and, for the first PSC_3D_AREA_TRIANGLES_MAX of them, what classification needs; the
     * clipped polygons */
    assert_int_equal(a - z, (size_t)(4u * 3000u + 256u) * (PSC_3D_BIN_BYTES + PSC_3D_LIST_BYTES) +
                                PSC_3D_FRAME_PARTS_MAX * 4u + (size_t)PSC_3D_AREA_TRIANGLES_MAX * PSC_3D_AREA_BYTES +
                                PSC_3D_AREA_CLIPPED_MAX * PSC_3D_AREA_CLIPPED_BYTES);
    c.hsr = 2;
    assert_int_equal(psc_3d_workspace_size(&c), 0);
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &c), PSC_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_soups_bytes),
        cmocka_unit_test(test_meshes_bytes),
        cmocka_unit_test(test_large_polygons_save),
        cmocka_unit_test(test_abuffer_bytes),
        cmocka_unit_test(test_config),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
