/* SPDX-License-Identifier: MIT */
/*
 * test_3d_golden.c - rendered 3D views against the double-precision
 * reference renderer (tests/support/tsup_3d_ref.c): generated meshes (cube,
 * sphere, torus, a closed sphere seen from outside and from inside) and the
 * Utah teapot, in every shading, both texture filters and both output
 * formats, full-buffer and tiled, 16- and 32-bit depth.
 *
 * Metrics, over the 8-bit RGB channels, against the reference quantised as a
 * perfect renderer would store it in the output format:
 *  - PSNR = 10 log10(255^2 / MSE) >= MIN_PSNR_DB (34 dB);
 *  - the fraction of pixels whose largest channel error exceeds 24 levels
 *    <= MAX_BAD_FRACTION (0.6%).
 * Where the two differ is along silhouettes and depth crossings: core snaps
 * vertices to 1/16 pixel, so a pixel centre within 1/32 pixel of an edge may
 * fall on the other side, and such a pixel takes a wholly different colour;
 * the interiors agree within rounding (Gouraud, lighting) and within a
 * texel's 8-bit bilinear weight (textures). The printed table gives the
 * measured figures (38..52 dB, at most 0.21% bad pixels when written); a
 * systematic error fails: moving the reference camera by half a pixel
 * gives about 20 dB (test_golden_detects_offset).
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

#define MIN_PSNR_DB 34.0
#define MAX_BAD_FRACTION 0.006
#define BAD_LEVELS 24.0

typedef struct {
    const char *name;
    tsup_shape_t shape;
    psc_shade_t shade;
    psc_tex_filter_t filter;
    bool lit, cull, normalised;
    double yaw, pitch, dist, hfov;
    psc_pixfmt_t fmt;
    uint8_t depth_bits;
    uint16_t tile;
} view_t;

static const view_t views[] = {
    {"cube flat", TSUP_CUBE, PSC_SHADE_FLAT, PSC_TEX_NEAREST, false, true, false, 30, -25, 3.0, 60, PSC_PIX_RGB565, 32, 0},
    {"cube gouraud lit", TSUP_CUBE, PSC_SHADE_GOURAUD, PSC_TEX_NEAREST, true, true, true, -50, 35, 2.6, 70, PSC_PIX_XRGB8888, 16, 0},
    {"cube texture bilinear", TSUP_CUBE, PSC_SHADE_TEXTURE, PSC_TEX_BILINEAR, false, true, false, 20, -30, 2.2, 75, PSC_PIX_XRGB8888, 32, 32},
    {"cube texture nearest", TSUP_CUBE, PSC_SHADE_TEXTURE, PSC_TEX_NEAREST, false, true, false, 200, 10, 2.4, 60, PSC_PIX_RGB565, 32, 0},
    {"sphere outside gouraud", TSUP_SPHERE, PSC_SHADE_GOURAUD, PSC_TEX_NEAREST, true, true, true, 10, 20, 3.0, 50, PSC_PIX_RGB565, 32, 0},
    {"sphere outside texture lit", TSUP_SPHERE, PSC_SHADE_TEXTURE, PSC_TEX_BILINEAR, true, true, false, -70, -15, 2.5, 60, PSC_PIX_XRGB8888, 32, 16},
    {"sphere inside texture", TSUP_SPHERE, PSC_SHADE_TEXTURE, PSC_TEX_BILINEAR, false, false, false, 35, 10, 0.3, 100, PSC_PIX_XRGB8888, 32, 0},
    {"sphere inside gouraud", TSUP_SPHERE, PSC_SHADE_GOURAUD, PSC_TEX_NEAREST, false, false, false, -120, -40, 0.0625, 120, PSC_PIX_RGB565, 16, 0},
    {"torus texture bilinear", TSUP_TORUS, PSC_SHADE_TEXTURE, PSC_TEX_BILINEAR, true, true, false, 0, -35, 2.0, 65, PSC_PIX_RGB565, 32, 0},
    {"torus flat", TSUP_TORUS, PSC_SHADE_FLAT, PSC_TEX_NEAREST, true, true, true, 75, -60, 2.5, 60, PSC_PIX_XRGB8888, 32, 24},
    {"teapot gouraud lit", TSUP_TEAPOT, PSC_SHADE_GOURAUD, PSC_TEX_NEAREST, true, true, true, -40, -30, 2.0, 60, PSC_PIX_RGB565, 32, 0},
    {"teapot texture lit", TSUP_TEAPOT, PSC_SHADE_TEXTURE, PSC_TEX_BILINEAR, true, true, true, 150, -10, 1.8, 60, PSC_PIX_XRGB8888, 32, 0},
    {"teapot close, no culling", TSUP_TEAPOT, PSC_SHADE_GOURAUD, PSC_TEX_NEAREST, true, false, true, 90, -5, 0.9, 90, PSC_PIX_RGB565, 16, 40},
    {"sphere phong", TSUP_SPHERE, PSC_SHADE_PHONG, PSC_TEX_NEAREST, true, true, true, 25, 15, 3.0, 50, PSC_PIX_XRGB8888, 32, 0},
    {"teapot phong", TSUP_TEAPOT, PSC_SHADE_PHONG, PSC_TEX_NEAREST, true, true, true, -40, -30, 2.0, 60, PSC_PIX_XRGB8888, 32, 0},
    {"torus phong tiled", TSUP_TORUS, PSC_SHADE_PHONG, PSC_TEX_NEAREST, true, true, true, 0, -35, 2.0, 65, PSC_PIX_RGB565, 16, 32},
    {"cube phong (flat normals)", TSUP_CUBE, PSC_SHADE_PHONG, PSC_TEX_NEAREST, true, true, false, -50, 35, 2.6, 70, PSC_PIX_XRGB8888, 32, 0},
};

static void test_golden_views(void **state)
{
    (void)state;
    tsup_texture_t tex565, tex8888;
    assert_int_equal(tsup_texture_make(&tex565, 64, 64, PSC_PIX_RGB565), 0);
    assert_int_equal(tsup_texture_make(&tex8888, 128, 32, PSC_PIX_XRGB8888), 0);
    const uint16_t W = 240, H = 180;
    double *ref = malloc((size_t)W * H * 3 * sizeof(double));
    print_message("  %-28s %8s %8s\n", "view", "PSNR dB", "bad %");
    double worst_psnr = 1e9, worst_bad = 0;
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) {
        const view_t *v = &views[i];
        psc_model_t g;
        tsup_shape_make(v->shape, &g);
        if (v->shade != PSC_SHADE_TEXTURE && v->shape != TSUP_TEAPOT)
            psc_model_color_by_index(&g, (uint32_t)i);
        tsup_mesh_t m;
        assert_int_equal(tsup_mesh_from_geom(&m, &g, v->normalised), 0);
        m.mesh.base_color = 0xD0C0A0;
        psc_3d_draw_t d;
        psc_3d_draw_defaults(&d, &m.mesh);
        tsup_orbit_matrix(&d.camera_from_object, v->yaw, v->pitch, v->dist);
        d.shade = v->shade;
        d.filter = v->filter;
        d.lit = v->lit;
        d.cull_back = v->cull;
        d.light_dir = psc_vec3_normalize((psc_vec3_q16_t){-26000, 39000, -45000});
        d.ambient_q8 = 72;
        d.texture = i % 2 ? &tex565.tex : &tex8888.tex;
        d.specular_q8 = v->shade == PSC_SHADE_PHONG ? (uint16_t)(64 + 32 * (i % 4)) : 0;
        d.shininess = (uint8_t)(8u << (i % 4));
        psc_3d_config_t cfg = {W, H, v->tile, v->tile, v->depth_bits, tsup_bam_from_deg(v->hfov), PSC_Q16_ONE / 32,
                               16 * PSC_Q16_ONE, m.mesh.vertex_count, PSC_3D_HSR_ZBUFFER};
        tsup_3d_t t;
        assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
        psc_surface_t s = tsup_surface_new(W, H, v->fmt);
        uint32_t bg = 0x283040;
        assert_int_equal(psc_3d_render(&t.r, &d, 1, &bg, &s, NULL), PSC_OK);
        tsup_ref_render3d(&cfg, &d, 1, bg, ref, NULL);
        double psnr = tsup_psnr(tsup_mse_surface(&s, ref)), bad = tsup_frac_differing(&s, ref, BAD_LEVELS);
        print_message("  %-28s %8.2f %8.3f\n", v->name, psnr, bad * 100);
        char fn[96];
        snprintf(fn, sizeof fn, "3d_golden_%02zu.png", i);
        tsup_save_png(&s, fn);
        if (psnr < MIN_PSNR_DB || bad > MAX_BAD_FRACTION)
            fail_msg("%s: PSNR %.2f dB (min %.1f), %.3f%% bad pixels (max %.2f%%); image in %s", v->name, psnr,
                     MIN_PSNR_DB, bad * 100, MAX_BAD_FRACTION * 100, fn);
        worst_psnr = fmin(worst_psnr, psnr);
        worst_bad = fmax(worst_bad, bad);
        tsup_surface_free(&s);
        tsup_3d_free(&t);
        tsup_mesh_free(&m);
        psc_model_free(&g);
    }
    print_message("  worst: %.2f dB, %.3f%% of pixels beyond %g levels\n", worst_psnr, worst_bad * 100, BAD_LEVELS);
    free(ref);
    tsup_texture_free(&tex565);
    tsup_texture_free(&tex8888);
}

/* The metric can fail: a half-pixel shift of the camera must drop below the bound. */
static void test_golden_detects_offset(void **state)
{
    (void)state;
    psc_model_t g;
    psc_model_teapot(&g, 6);
    tsup_mesh_t m;
    assert_int_equal(tsup_mesh_from_geom(&m, &g, 1), 0);
    const uint16_t W = 200, H = 150;
    psc_3d_config_t cfg = {W, H, 0, 0, 32, tsup_bam_from_deg(60), PSC_Q16_ONE / 32, 16 * PSC_Q16_ONE,
                           m.mesh.vertex_count, PSC_3D_HSR_ZBUFFER};
    psc_3d_draw_t d;
    psc_3d_draw_defaults(&d, &m.mesh);
    tsup_texture_t tex;
    assert_int_equal(tsup_texture_make(&tex, 64, 64, PSC_PIX_XRGB8888), 0);
    d.texture = &tex.tex;
    d.shade = PSC_SHADE_TEXTURE;
    tsup_orbit_matrix(&d.camera_from_object, 20, -20, 2.0);
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
    psc_surface_t s = tsup_surface_new(W, H, PSC_PIX_XRGB8888);
    uint32_t bg = 0;
    assert_int_equal(psc_3d_render(&t.r, &d, 1, &bg, &s, NULL), PSC_OK);
    /* The reference with the camera moved by half a pixel sideways at the model's distance. */
    double *ref = malloc((size_t)W * H * 3 * sizeof(double));
    psc_3d_draw_t shifted = d;
    double f = W / 2.0 / tan(30 * TSUP_DEG), dist = 2.0; /* the orbit centre is the teapot's */
    shifted.camera_from_object.m[0][3] += (int32_t)lround(0.5 * dist / f * 65536.0);
    tsup_ref_render3d(&cfg, &shifted, 1, bg, ref, NULL);
    double psnr = tsup_psnr(tsup_mse_surface(&s, ref)), bad = tsup_frac_differing(&s, ref, BAD_LEVELS);
    print_message("  half-pixel offset: %.2f dB, %.2f%% bad\n", psnr, bad * 100);
    assert_true(psnr < MIN_PSNR_DB || bad > MAX_BAD_FRACTION);
    free(ref);
    tsup_surface_free(&s);
    tsup_3d_free(&t);
    tsup_texture_free(&tex);
    tsup_mesh_free(&m);
    psc_model_free(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_golden_views),
        cmocka_unit_test(test_golden_detects_offset),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
