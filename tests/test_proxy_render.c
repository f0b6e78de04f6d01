/* SPDX-License-Identifier: MIT */
/*
 * test_proxy_render.c - the proxy animator drawn (core/proxy/psc_proxy.h)
 * and its preprocessing (host_tools/lib/bake/proxy.h):
 *  - PSC_SHADE_VIEWS against a double-precision reference of its rule
 *    (three textures, weights, empty texels, coverage of one half) over
 *    random triangles, weights and textures;
 *  - the bundled truck (rigid), skinned bar and a held-out skinned human
 *    baked, and drawn as proxies against a double-precision reference of
 *    the pack's full mesh (posed in double, drawn by the tests' reference
 *    renderer; the product's own full mesh checked against it too) at views
 *    and poses that were never baked (between grid directions, between the
 *    animation's samples, and a bar bent far beyond its animation): the
 *    silhouettes' IoU (pixel centres), the PSNR over their union (each
 *    reference pixel the mean of 4 x 4 samples: what the pixel shows), and
 *    the front part (by bone) where both show one; the human's proxies at most a quarter of
 *    its triangles;
 *  - a generated machine of 120 960 triangles (ten rings, each with 240
 *    bolts) cut to 8 % of them, drawn at rest and turned, against its full
 *    mesh;
 *  - joint strips attached to the parts they join under extreme poses;
 *  - --views K: the grid grows past the smallest that gives K views while
 *    the texel density holds, within 2 K;
 *  - the billboard (the far level) against the full mesh, far away;
 *  - --lod auto: the billboard's threshold, the cost estimate's area and
 *    choice against what frames of both levels write over random views and
 *    poses, its range limits, no flicker at the crossing; the device's
 *    animated object scene zooming out;
 *  - tiles change no byte of proxies, full mesh or billboard;
 *  - mutated and truncated glTF files refused with the file named, or baked
 *    into packs that parse;
 *  - 3000 mutated and truncated proxy packs: refused with a message, or
 *    parsed and drawn without a fault.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "base/psc_crc32.h"
#include "base/psc_pixel.h"
#include "3d/psc_3d_orbit.h"
#include "import/gltf_model.h"
#include "proxy/psc_proxy.h"
#include "bake/proxy.h"
#include "bake/skin_split.h"
#include "render/proxy.h"
#include "psc_testsupport.h"
#include "tsup_3d.h"
#include "tsup_files.h"
#include "scene/scene_proxy.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define GLTF_DIR TSUP_DATA_GLTF
#define BG 0x30343Cu
#define W 320
#define H 240

/* ---- PSC_SHADE_VIEWS against its rule in double ---------------------------------------------- */

/* The affine shortcut's bound (psc_raster.c: a VIEWS triangle whose coordinates perspective moves by under 1/16
 * texel is interpolated without a division): every pixel samples the texel its perspective-correct coordinates fall
 * in wherever they lie more than 1/16 texel and a rounding from the texel's edge. 2 000 random triangles over a
 * 32 x 32 view whose texels each name themselves, the corners' q equal, within 3 % (where the shortcut is taken
 * across a few texels and not across many) and up to four times apart, against the double-precision rule. */
static void test_views_affine_bound(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 77);
    enum { T = 32, S = 64 };
    static uint16_t tex[T * T];
    static uint32_t out[S * S];
    for (unsigned y = 0; y < T; y++)
        for (unsigned x = 0; x < T; x++)
            tex[y * T + x] = (uint16_t)(x << 11 | y << 5 | 0x10u);   /* red the column, green the row; never empty */
    psc_texture_t t;
    assert_int_equal(psc_texture_init(&t, T, T, PSC_PIX_RGB565, T * 2, tex), PSC_OK);
    psc_raster_state_t st = {.shade = PSC_SHADE_VIEWS, .filter = PSC_TEX_NEAREST, .view_tex = {&t, &t, &t},
                             .view_w_q8 = {256, 0, 0}};
    psc_surface_t sf = {S, S, S * 4, PSC_PIX_XRGB8888, out};
    psc_raster_target_t tg = {&sf, NULL, 0, 0, 0, 0, S, S, NULL, NULL, 0, NULL, 0, 0};
    unsigned checked = 0, near_edge = 0, wrong = 0;
    for (unsigned trial = 0; trial < 2000; trial++) {
        psc_raster_vertex_t v[3];
        double p[3][2], q[3], uv[3][2];
        double spread = trial % 3 == 0 ? 0 : trial % 3 == 1 ? 0.03 : 3.0;   /* q's corners: equal, near, far apart */
        for (unsigned i = 0; i < 3; i++) {
            p[i][0] = tsup_rng_below(&r, S * 16) / 16.0, p[i][1] = tsup_rng_below(&r, S * 16) / 16.0;
            q[i] = 1.0 / (1.0 + spread * tsup_rng_below(&r, 1001) / 1000.0);
            uv[i][0] = 0.05 + 0.9 * tsup_rng_below(&r, 10001) / 10000.0;
            uv[i][1] = 0.05 + 0.9 * tsup_rng_below(&r, 10001) / 10000.0;
            v[i] = (psc_raster_vertex_t){.x_q4 = (int32_t)lround(p[i][0] * 16), .y_q4 = (int32_t)lround(p[i][1] * 16),
                                         .q_q28 = (int32_t)lround(q[i] * PSC_RASTER_Q_ONE),
                                         .u_q16 = (int32_t)lround(uv[i][0] * 65536),
                                         .v_q16 = (int32_t)lround(uv[i][1] * 65536)};
            q[i] = v[i].q_q28 / (double)PSC_RASTER_Q_ONE;   /* what the rasterizer is given */
            uv[i][0] = v[i].u_q16 / 65536.0, uv[i][1] = v[i].v_q16 / 65536.0;
        }
        for (unsigned i = 0; i < S * S; i++)
            out[i] = 0xFF000000u;
        psc_raster_triangle(&tg, &st, &v[0], &v[1], &v[2]);
        double x0 = v[0].x_q4 / 16.0, y0 = v[0].y_q4 / 16.0, x1 = v[1].x_q4 / 16.0, y1 = v[1].y_q4 / 16.0;
        double x2 = v[2].x_q4 / 16.0, y2 = v[2].y_q4 / 16.0;
        double area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
        if (fabs(area) < 4)
            continue;
        for (int y = 0; y < S; y++)
            for (int x = 0; x < S; x++) {
                double pxc = x + 0.5, pyc = y + 0.5;
                double b1 = ((pxc - x0) * (y2 - y0) - (x2 - x0) * (pyc - y0)) / area;
                double b2 = ((x1 - x0) * (pyc - y0) - (pxc - x0) * (y1 - y0)) / area, b0 = 1 - b1 - b2;
                if (b0 < 0.01 || b1 < 0.01 || b2 < 0.01)
                    continue;
                double den = b0 * q[0] + b1 * q[1] + b2 * q[2], texel[2];
                bool edge = false;
                for (unsigned a = 0; a < 2; a++) {
                    texel[a] = (b0 * q[0] * uv[0][a] + b1 * q[1] * uv[1][a] + b2 * q[2] * uv[2][a]) / den * T;
                    double f = texel[a] - floor(texel[a]);
                    edge |= f < 1.0 / 16 + 1.0 / 64 || f > 1 - 1.0 / 16 - 1.0 / 64;
                }
                if (edge) {
                    near_edge++;
                    continue;
                }
                uint32_t got = out[y * S + x];
                unsigned gx = (got >> 16 & 255u) >> 3, gy = (got >> 8 & 255u) >> 2;
                checked++;
                if (gx != (unsigned)floor(texel[0]) || gy != (unsigned)floor(texel[1]))
                    wrong++;
            }
    }
    print_message("  %u pixels sample the texel the perspective-correct coordinates give (%u within 1/16 texel of an "
                  "edge not checked), %u another\n", checked - wrong, near_edge, wrong);
    assert_true(checked > 300000u);
    assert_int_equal(wrong, 0);
}

static void test_views_rule(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 5);
    enum { T = 16 };
    static uint16_t tex[3][T * T];
    static uint32_t out[64 * 64];
    unsigned pixels = 0, coverage_off = 0, colour_off = 0;
    for (unsigned trial = 0; trial < 200; trial++) {
        psc_texture_t t[3];
        for (unsigned k = 0; k < 3; k++) {
            for (unsigned i = 0; i < T * T; i++)
                tex[k][i] = tsup_rng_below(&r, 3) == 0 ? PSC_VIEW_TEXEL_EMPTY : (uint16_t)(tsup_rng_u32(&r) | 0x20u);
            assert_int_equal(psc_texture_init(&t[k], T, T, PSC_PIX_RGB565, T * 2, tex[k]), PSC_OK);
        }
        uint32_t w0 = tsup_rng_below(&r, 257), w1 = tsup_rng_below(&r, 257 - w0);
        psc_raster_state_t st = {0};
        st.shade = PSC_SHADE_VIEWS;
        st.filter = tsup_rng_below(&r, 2) ? PSC_TEX_BILINEAR : PSC_TEX_NEAREST;
        st.view_tex[0] = &t[0], st.view_tex[1] = &t[1], st.view_tex[2] = &t[2];
        st.view_w_q8[0] = (uint16_t)w0, st.view_w_q8[1] = (uint16_t)w1, st.view_w_q8[2] = (uint16_t)(256 - w0 - w1);
        psc_surface_t sf = {64, 64, 64 * 4, PSC_PIX_XRGB8888, out};
        for (unsigned i = 0; i < 64 * 64; i++)
            out[i] = 0xFF000000u;
        psc_raster_target_t tg = {&sf, NULL, 0, 0, 0, 0, 64, 64, NULL, NULL, 0, NULL, 0, 0};
        /* a triangle with affine coordinates (q = 1): each view's (u, v) a different affine map of the pixel */
        psc_raster_vertex_t v[3];
        double uv[3][3][2];
        static const int32_t px[3][2] = {{2, 2}, {62, 5}, {8, 61}};
        for (unsigned i = 0; i < 3; i++) {
            v[i] = (psc_raster_vertex_t){.x_q4 = px[i][0] * 16, .y_q4 = px[i][1] * 16, .q_q28 = PSC_RASTER_Q_ONE};
            for (unsigned k = 0; k < 3; k++)
                for (unsigned a = 0; a < 2; a++)
                    uv[i][k][a] = tsup_rng_below(&r, 60000) / 65536.0 + 0.04;
            v[i].u_q16 = (int32_t)lround(uv[i][0][0] * 65536), v[i].v_q16 = (int32_t)lround(uv[i][0][1] * 65536);
            v[i].u1_q16 = (int32_t)lround(uv[i][1][0] * 65536), v[i].v1_q16 = (int32_t)lround(uv[i][1][1] * 65536);
            v[i].u2_q16 = (int32_t)lround(uv[i][2][0] * 65536), v[i].v2_q16 = (int32_t)lround(uv[i][2][1] * 65536);
        }
        psc_raster_triangle(&tg, &st, &v[0], &v[1], &v[2]);
        /* the reference, at pixel centres well inside the triangle */
        double x0 = 2, y0 = 2, x1 = 62, y1 = 5, x2 = 8, y2 = 61, area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
        for (int y = 0; y < 64; y++)
            for (int x = 0; x < 64; x++) {
                double pxc = x + 0.5, pyc = y + 0.5;
                double b1 = ((pxc - x0) * (y2 - y0) - (x2 - x0) * (pyc - y0)) / area;
                double b2 = ((x1 - x0) * (pyc - y0) - (pxc - x0) * (y1 - y0)) / area, b0 = 1 - b1 - b2;
                if (b0 < 0.02 || b1 < 0.02 || b2 < 0.02)
                    continue;
                double cov = 0, acc[3] = {0, 0, 0};
                for (unsigned k = 0; k < 3; k++) {
                    double wk = st.view_w_q8[k] / 256.0;
                    double u = b0 * uv[0][k][0] + b1 * uv[1][k][0] + b2 * uv[2][k][0];
                    double vv = b0 * uv[0][k][1] + b1 * uv[1][k][1] + b2 * uv[2][k][1];
                    double fx = u * T - (st.filter == PSC_TEX_BILINEAR ? 0.5 : 0), fy = vv * T - (st.filter == PSC_TEX_BILINEAR ? 0.5 : 0);
                    int ix = (int)floor(fx), iy = (int)floor(fy);
                    double ax = fx - ix, ay = fy - iy;
                    for (int j = 0; j < (st.filter == PSC_TEX_BILINEAR ? 2 : 1); j++)
                        for (int i = 0; i < (st.filter == PSC_TEX_BILINEAR ? 2 : 1); i++) {
                            int cx = ix + i < 0 ? 0 : ix + i > T - 1 ? T - 1 : ix + i;
                            int cy = iy + j < 0 ? 0 : iy + j > T - 1 ? T - 1 : iy + j;
                            double bw = st.filter == PSC_TEX_BILINEAR ? (i ? ax : 1 - ax) * (j ? ay : 1 - ay) : 1;
                            uint16_t c = tex[k][cy * T + cx];
                            if (c == PSC_VIEW_TEXEL_EMPTY)
                                continue;
                            uint32_t xr = psc_rgb565_to_xrgb(c);
                            cov += wk * bw;
                            acc[0] += wk * bw * (xr >> 16 & 255), acc[1] += wk * bw * (xr >> 8 & 255),
                                acc[2] += wk * bw * (xr & 255);
                        }
                }
                pixels++;
                uint32_t got = out[y * 64 + x];
                bool drawn = got != 0xFF000000u;
                if (fabs(cov - 0.5) < 0.01)
                    continue;   /* a rounding either way */
                if (drawn != (cov >= 0.5)) {
                    coverage_off++;
                    continue;
                }
                if (!drawn)
                    continue;
                for (unsigned a = 0; a < 3; a++) {
                    double ref = acc[a] / cov;
                    double g = (got >> (16 - 8 * a)) & 255;
                    if (fabs(g - ref) > 3.0)
                        colour_off++;
                }
            }
    }
    print_message("  %u pixels of 200 random triangles: coverage differs at %u, a channel by more than 3 at %u\n", pixels,
                  coverage_off, colour_off);
    assert_true(pixels > 100000);
    assert_true(coverage_off * 200u <= pixels);   /* <= 0.5 %: interpolation rounding at the cut */
    assert_true(colour_off * 200u <= pixels);
}

/* The coordinates' perspective: a pixel's (u, v) are the corners' weighted by b_i q_i / sum b_j q_j (b its screen
 * barycentric weights). Each texel of a view a colour of its own, one view weighing all: every pixel well inside the
 * triangle and away from a texel's border shows the texel the double-precision rule names. */
static void test_views_perspective(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 29);
    enum { T = 32 };
    static uint16_t tex[T * T];
    static uint32_t out[64 * 64];
    for (unsigned i = 0; i < T * T; i++)
        tex[i] = (uint16_t)(((i % T) << 11) | ((i / T) << 5) | 0x10u);   /* red the column, green the row */
    psc_texture_t t;
    assert_int_equal(psc_texture_init(&t, T, T, PSC_PIX_RGB565, T * 2, tex), PSC_OK);
    unsigned checked = 0, wrong = 0, perspective = 0;
    for (unsigned trial = 0; trial < 100; trial++) {
        psc_raster_state_t st = {.shade = PSC_SHADE_VIEWS, .filter = PSC_TEX_NEAREST, .view_tex = {&t, &t, &t},
                                 .view_w_q8 = {256, 0, 0}};
        psc_surface_t sf = {64, 64, 64 * 4, PSC_PIX_XRGB8888, out};
        for (unsigned i = 0; i < 64 * 64; i++)
            out[i] = 0;
        psc_raster_target_t tg = {&sf, NULL, 0, 0, 0, 0, 64, 64, NULL, NULL, 0, NULL, 0, 0};
        double px[3][2], q[3], uv[3][2];
        psc_raster_vertex_t v[3];
        for (unsigned i = 0; i < 3; i++) {
            px[i][0] = tsup_rng_below(&r, 64 * 16) / 16.0, px[i][1] = tsup_rng_below(&r, 64 * 16) / 16.0;
            /* a depth range of up to 8 to 1 across the triangle */
            int32_t qq = PSC_RASTER_Q_ONE / 8 + (int32_t)tsup_rng_below(&r, PSC_RASTER_Q_ONE - PSC_RASTER_Q_ONE / 8);
            q[i] = qq;
            uv[i][0] = tsup_rng_below(&r, 65536) / 65536.0, uv[i][1] = tsup_rng_below(&r, 65536) / 65536.0;
            v[i] = (psc_raster_vertex_t){.x_q4 = (int32_t)lround(px[i][0] * 16), .y_q4 = (int32_t)lround(px[i][1] * 16),
                                         .q_q28 = qq, .u_q16 = (int32_t)lround(uv[i][0] * 65536),
                                         .v_q16 = (int32_t)lround(uv[i][1] * 65536)};
            px[i][0] = v[i].x_q4 / 16.0, px[i][1] = v[i].y_q4 / 16.0;
            uv[i][0] = v[i].u_q16 / 65536.0, uv[i][1] = v[i].v_q16 / 65536.0;
        }
        double area = (px[1][0] - px[0][0]) * (px[2][1] - px[0][1]) - (px[2][0] - px[0][0]) * (px[1][1] - px[0][1]);
        if (fabs(area) < 40)
            continue;
        psc_raster_triangle(&tg, &st, &v[0], &v[1], &v[2]);
        for (int y = 0; y < 64; y++)
            for (int x = 0; x < 64; x++) {
                double cx = x + 0.5, cy = y + 0.5, b[3];
                b[1] = ((cx - px[0][0]) * (px[2][1] - px[0][1]) - (px[2][0] - px[0][0]) * (cy - px[0][1])) / area;
                b[2] = ((px[1][0] - px[0][0]) * (cy - px[0][1]) - (cx - px[0][0]) * (px[1][1] - px[0][1])) / area;
                b[0] = 1 - b[1] - b[2];
                if (b[0] < 0.02 || b[1] < 0.02 || b[2] < 0.02)
                    continue;
                double sum = b[0] * q[0] + b[1] * q[1] + b[2] * q[2], u = 0, vv = 0, ua = 0;
                for (unsigned i = 0; i < 3; i++) {
                    u += b[i] * q[i] / sum * uv[i][0], vv += b[i] * q[i] / sum * uv[i][1];
                    ua += b[i] * uv[i][0];
                }
                double fx = u * T, fy = vv * T;
                if (fabs(fx - lround(fx)) < 0.02 || fabs(fy - lround(fy)) < 0.02)
                    continue;   /* on a texel's border: a rounding either way */
                int ix = (int)floor(fx), iy = (int)floor(fy);
                ix = ix > T - 1 ? T - 1 : ix, iy = iy > T - 1 ? T - 1 : iy;
                uint32_t want = psc_rgb565_to_xrgb(tex[iy * T + ix]) & 0xFFFFFFu, got = out[y * 64 + x] & 0xFFFFFFu;
                checked++;
                wrong += got != want;
                perspective += (int)floor(ua * T) != ix;   /* where affine coordinates would have named another */
            }
    }
    print_message("  perspective: %u pixels checked, %u showing another texel (affine coordinates would at %u)\n",
                  checked, wrong, perspective);
    assert_true(checked > 20000 && perspective > checked / 10);
    assert_int_equal(wrong, 0);
}

/* ---- soft silhouettes (psc_raster.h) ------------------------------------------------------------ */

enum { SOFT_W = 64, SOFT_H = 8, SOFT_T = 16 };

/* A quad over the whole 64 x 8 target at depth z, its views' coordinates u = x / 64 (four pixels a texel of a
 * 16 x 16 view), drawn with state st into out (XRGB8888), depth and (NULL: none) coverage. */
static void soft_quad(const psc_raster_state_t *st, uint32_t z, uint32_t *out, uint16_t *depth, uint8_t *coverage)
{
    psc_surface_t sf = {SOFT_W, SOFT_H, SOFT_W * 4, PSC_PIX_XRGB8888, out};
    psc_raster_target_t tg = {&sf, depth, SOFT_W * 2, 16, 0, 0, SOFT_W, SOFT_H, NULL, NULL, 0, coverage, SOFT_W, BG};
    static const int32_t corner[4][2] = {{0, 0}, {SOFT_W, 0}, {SOFT_W, SOFT_H}, {0, SOFT_H}};
    psc_raster_vertex_t v[4];
    for (unsigned i = 0; i < 4; i++) {
        int32_t u = corner[i][0] * 65536 / SOFT_W, vv = 16384 + corner[i][1] * 1024;
        v[i] = (psc_raster_vertex_t){.x_q4 = corner[i][0] * 16, .y_q4 = corner[i][1] * 16, .depth_q32 = z,
                                     .q_q28 = PSC_RASTER_Q_ONE, .u_q16 = u, .v_q16 = vv, .u1_q16 = u, .v1_q16 = vv,
                                     .u2_q16 = u, .v2_q16 = vv};
    }
    psc_raster_triangle(&tg, st, &v[0], &v[1], &v[2]);
    psc_raster_triangle(&tg, st, &v[0], &v[2], &v[3]);
}

/* A view of colour c filled in its texel columns [0, filled). */
static void soft_view(uint16_t *tex, psc_texture_t *t, uint16_t c, unsigned filled)
{
    for (unsigned i = 0; i < SOFT_T * SOFT_T; i++)
        tex[i] = i % SOFT_T < filled ? c : PSC_VIEW_TEXEL_EMPTY;
    assert_int_equal(psc_texture_init(t, SOFT_T, SOFT_T, PSC_PIX_RGB565, SOFT_T * 2, tex), PSC_OK);
}

static void soft_clear(uint32_t *out, uint16_t *depth, uint8_t *coverage)
{
    for (unsigned i = 0; i < SOFT_W * SOFT_H; i++)
        out[i] = 0xFF000000u | BG, depth[i] = 0xFFFFu, coverage[i] = 0;
}

static int channel_off(uint32_t got, double want[3])
{
    int worst = 0;
    for (unsigned c = 0; c < 3; c++) {
        int d = abs((int)(got >> (16 - 8 * c) & 255u) - (int)lround(want[c]));
        worst = d > worst ? d : worst;
    }
    return worst;
}

/* Soft silhouettes against their rule in double: a view filled to its middle column on a quad four pixels a texel
 * ramps from the colour to the background over one and a half pixels about where its bilinear coverage is a half
 * (x = 32), within 2 levels; a surface behind drawn later fills the uncovered part of those pixels, not the
 * background (the order of the two draws changes a level at most); views that disagree over a wide region stay the
 * alpha test's; without the coverage plane the silhouette is the alpha test's, to the byte. */
static void test_soft_silhouettes(void **state)
{
    (void)state;
    static uint16_t tex_a[SOFT_T * SOFT_T], tex_b[SOFT_T * SOFT_T], tex_e[SOFT_T * SOFT_T];
    static uint32_t out[SOFT_W * SOFT_H], first[SOFT_W * SOFT_H];
    static uint16_t depth[SOFT_W * SOFT_H];
    static uint8_t coverage[SOFT_W * SOFT_H];
    const uint16_t ca = 0xF81Fu, cb = 0x07E0u;   /* magenta in front, green behind */
    psc_texture_t ta, tb, te;
    soft_view(tex_a, &ta, ca, SOFT_T / 2);
    soft_view(tex_b, &tb, cb, SOFT_T);
    soft_view(tex_e, &te, cb, 0);
    psc_raster_state_t front = {0};
    front.shade = PSC_SHADE_VIEWS;
    front.filter = PSC_TEX_EDGES;
    front.depth_test = true;
    front.view_tex[0] = front.view_tex[1] = front.view_tex[2] = &ta;
    front.view_w_q8[0] = 256;
    psc_raster_state_t behind = front;
    behind.view_tex[0] = behind.view_tex[1] = behind.view_tex[2] = &tb;
    const uint32_t xa = psc_rgb565_to_xrgb(ca), xb = psc_rgb565_to_xrgb(cb);
    int ramp_off = 0, under_off = 0, order_off = 0;
    unsigned partial = 0;
    for (int pass = 0; pass < 6; pass++) {
        /* bilinear, then the edges filter: a pixel whose nearest texels are filled is covered, the ramp outside */
        const bool edges = pass >= 3;
        front.filter = behind.filter = edges ? PSC_TEX_EDGES : PSC_TEX_BILINEAR;
        soft_clear(out, depth, coverage);
        if (pass % 3 == 2) /* behind first, then in front: blended over it */
            soft_quad(&behind, 0xC0000000u, out, depth, coverage);
        soft_quad(&front, 0x40000000u, out, depth, coverage);
        if (pass % 3 == 1) /* in front first, then behind: filling what the front leaves uncovered */
            soft_quad(&behind, 0xC0000000u, out, depth, coverage);
        for (int x = 0; x < SOFT_W; x++) {
            double a = 0.5 + (32.0 - (x + 0.5)) / 1.5;   /* the edge at x = 32, a texel of coverage 4 pixels */
            a = a < 1.0 / 32 || (edges && x >= 32) ? 0 : a > 31.0 / 32 || (edges && x < 32) ? 1 : a;
            if (edges && x == 32)   /* the first empty nearest texel's pixel: the ramp */
                a = 0.5 + (32.0 - (x + 0.5)) / 1.5;
            uint32_t under = pass % 3 ? xb : BG;
            double want[3];
            for (unsigned c = 0; c < 3; c++)
                want[c] = (under >> (16 - 8 * c) & 255u) + a * ((double)(xa >> (16 - 8 * c) & 255u) -
                                                                  (under >> (16 - 8 * c) & 255u));
            for (int y = 0; y < SOFT_H; y++) {
                uint32_t got = out[y * SOFT_W + x];
                int off = channel_off(got, want);
                if (pass % 3 == 0)
                    ramp_off = off > ramp_off ? off : ramp_off;
                else
                    under_off = off > under_off ? off : under_off;
                if (pass % 3 == 2) {
                    int d = channel_off(got, (double[3]){first[y * SOFT_W + x] >> 16 & 255u,
                                                         first[y * SOFT_W + x] >> 8 & 255u, first[y * SOFT_W + x] & 255u});
                    order_off = d > order_off ? d : order_off;
                }
                partial += pass % 3 == 0 && a > 0 && a < 1;
            }
        }
        if (pass % 3 == 1)
            memcpy(first, out, sizeof out);
    }
    print_message("  soft silhouette: %u pixels partly covered, %d levels off the ramp in double, %d off filled by "
                  "what lies behind, the two orders %d apart\n", partial, ramp_off, under_off, order_off);
    assert_int_equal(partial, 3 * SOFT_H);   /* two pixels a row bilinear, one with the edges filter */
    assert_true(ramp_off <= 2 && under_off <= 2 && order_off <= 1);
    /* without the plane: the alpha test, to the byte */
    soft_clear(out, depth, coverage);
    soft_quad(&front, 0x40000000u, out, depth, NULL);
    for (int y = 0; y < SOFT_H; y++)
        for (int x = 0; x < SOFT_W; x++)
            assert_int_equal(out[y * SOFT_W + x], 0xFF000000u | (x < 32 ? xa : BG));
    /* views that disagree, one filled and one empty, without an edge near: covered as the alpha test has it */
    for (int heavy_filled = 0; heavy_filled < 2; heavy_filled++) {
        psc_raster_state_t st = front;
        st.view_tex[0] = heavy_filled ? &tb : &te;
        st.view_tex[1] = heavy_filled ? &te : &tb;
        st.view_tex[2] = &te;
        st.view_w_q8[0] = 160, st.view_w_q8[1] = 96, st.view_w_q8[2] = 0;
        soft_clear(out, depth, coverage);
        soft_quad(&st, 0x40000000u, out, depth, coverage);
        for (int y = 0; y < SOFT_H; y++)
            for (int x = 4; x < SOFT_W - 4; x++)
                assert_int_equal(out[y * SOFT_W + x], 0xFF000000u | (heavy_filled ? xb : BG));
    }
}

/* The views' arithmetic at its range's limits (run under the sanitizers by `make check`): triangles from slivers to
 * the coordinates' bounds, q from PSC_RASTER_Q_MIN to one, coordinates outside [0, 1], each filter, with and
 * without the A-buffer and the depth offsets; every pixel drawn lies inside the target, and nothing overflows. */
static void test_views_limits(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 31);
    enum { T = 16, S = 48 };
    static uint16_t tex[3][T * T];
    static uint16_t depth[S * S];
    static uint32_t out[S * S];
    static int8_t offsets[(T / 2) * (T / 2)];
    static uint8_t abuf_mem[1 << 20];
    for (unsigned i = 0; i < (T / 2) * (T / 2); i++)
        offsets[i] = (int8_t)(tsup_rng_below(&r, 256) - 128);
    psc_texture_t t[3];
    for (unsigned k = 0; k < 3; k++) {
        for (unsigned i = 0; i < T * T; i++)
            tex[k][i] = tsup_rng_below(&r, 4) == 0 ? PSC_VIEW_TEXEL_EMPTY : (uint16_t)(tsup_rng_u32(&r) | 0x20u);
        assert_int_equal(psc_texture_init(&t[k], T, T, PSC_PIX_RGB565, T * 2, tex[k]), PSC_OK);
    }
    assert_true(psc_abuffer_bytes(S * S, 4096) <= sizeof abuf_mem);
    psc_abuffer_t ab;
    uint64_t drawn = 0;
    for (unsigned trial = 0; trial < 4000; trial++) {
        uint32_t w[3] = {tsup_rng_below(&r, 257), 0, 0};   /* heaviest first, summing to 256 */
        w[1] = tsup_rng_below(&r, 257 - w[0]), w[2] = 256 - w[0] - w[1];
        for (unsigned a = 0; a < 3; a++)
            for (unsigned b = a + 1; b < 3; b++)
                if (w[b] > w[a]) {
                    uint32_t x = w[a];
                    w[a] = w[b], w[b] = x;
                }
        static const psc_tex_filter_t filters[3] = {PSC_TEX_NEAREST, PSC_TEX_BILINEAR, PSC_TEX_EDGES};
        psc_raster_state_t st = {.shade = PSC_SHADE_VIEWS, .filter = filters[tsup_rng_below(&r, 3)],
                                 .view_tex = {&t[0], &t[1], &t[2]},
                                 .view_w_q8 = {(uint16_t)w[0], (uint16_t)w[1], (uint16_t)w[2]}, .depth_test = true};
        if (tsup_rng_below(&r, 2))
            st.view_depth = offsets, st.view_depth_side = T / 2;
        psc_surface_t sf = {S, S, S * 4, PSC_PIX_XRGB8888, out};
        bool aa = tsup_rng_below(&r, 2) != 0;
        if (aa)
            psc_abuffer_init(&ab, abuf_mem, S * S, 4096);
        for (unsigned i = 0; i < S * S; i++)
            depth[i] = 0xFFFFu;
        uint64_t steps[3] = {0, 1u << 20, UINT64_C(1) << 35};
        psc_raster_target_t tg = {&sf, depth, S * 2, 16, 0, 0, S, S, aa ? &ab : NULL, NULL,
                                  steps[tsup_rng_below(&r, 3)], NULL, 0, 0};
        psc_raster_vertex_t v[3];
        /* a third of the triangles reach the coordinates' bounds, a third are slivers, a third are small */
        unsigned kind = tsup_rng_below(&r, 3);
        for (unsigned i = 0; i < 3; i++) {
            int32_t lim = kind == 0 ? PSC_RASTER_COORD_MAX_Q4 : S * 16;
            int32_t x = (int32_t)tsup_rng_below(&r, 2u * (uint32_t)lim + 1u) - (kind == 0 ? lim : 0);
            int32_t y = (int32_t)tsup_rng_below(&r, 2u * (uint32_t)lim + 1u) - (kind == 0 ? lim : 0);
            if (kind == 1 && i == 2)   /* nearly on the line through the first two */
                x = (v[0].x_q4 + v[1].x_q4) / 2 + (int32_t)tsup_rng_below(&r, 3) - 1,
                y = (v[0].y_q4 + v[1].y_q4) / 2 + (int32_t)tsup_rng_below(&r, 3) - 1;
            int32_t qs[3] = {PSC_RASTER_Q_MIN, PSC_RASTER_Q_ONE, PSC_RASTER_Q_MIN + (int32_t)tsup_rng_below(&r, PSC_RASTER_Q_ONE)};
            v[i] = (psc_raster_vertex_t){.x_q4 = x, .y_q4 = y, .q_q28 = qs[tsup_rng_below(&r, 3)],
                                         .depth_q32 = tsup_rng_u32(&r)};
            int32_t *c[6] = {&v[i].u_q16, &v[i].v_q16, &v[i].u1_q16, &v[i].v1_q16, &v[i].u2_q16, &v[i].v2_q16};
            for (unsigned a = 0; a < 6; a++)   /* [-2, 3]: outside the views too */
                *c[a] = (int32_t)tsup_rng_below(&r, 5u * 65536u + 1u) - 2 * 65536;
        }
        uint32_t n = psc_raster_triangle(&tg, &st, &v[0], &v[1], &v[2]);
        assert_true(n <= S * S);
        drawn += n;
    }
    print_message("  %llu pixels drawn in 4000 triangles at the limits\n", (unsigned long long)drawn);
    assert_true(drawn > 100000);
}

/* ---- quality against the full mesh -------------------------------------------------------------- */

typedef struct {
    uint8_t *pack;
    size_t len;
    psc_proxy_model_t m;
    psc_proxy_t px;
    void *ws;
    psc_3d_t r;
    void *ws3d;
    psc_vec3_q16_t lo, hi;
} fixture_t;

static void bake_model(fixture_t *f, psc_gltf_t *g, const char *file, unsigned views, unsigned tex);
static void fixture_ready(fixture_t *f);

static void bake(fixture_t *f, const char *file, unsigned views, unsigned tex)
{
    psc_gltf_t g;
    char note[256], err[512];
    assert_int_equal(psc_gltf_load(file, &g, note, sizeof note, err, sizeof err), 0);
    bake_model(f, &g, file, views, tex);
}

/* Bake model g (freed) with the defaults but views and tex, parse it and ready it to draw. */
static void bake_model(fixture_t *f, psc_gltf_t *g, const char *file, unsigned views, unsigned tex)
{
    char note[256], err[512];
    psc_bake_proxy_opts_t o = {views, tex, 0, 0, 0, false};
    uint8_t *bytes;
    assert_int_equal(psc_bake_proxy(g, &o, file, &bytes, &f->len, note, sizeof note, err, sizeof err), 0);
    print_message("  %s: %s\n", file, note);
    psc_gltf_free(g);
    assert_int_equal(posix_memalign((void **)&f->pack, 64, f->len), 0);
    memcpy(f->pack, bytes, f->len);
    free(bytes);
    fixture_ready(f);
}

/* Parse f's pack and ready it to draw. */
static void fixture_ready(fixture_t *f)
{
    psc_container_error_t e = {0};
    assert_int_equal(psc_proxy_parse(f->pack, f->len, &f->m, &e), PSC_OK);
    size_t n = psc_proxy_workspace_size(&f->m);
    assert_int_equal(posix_memalign(&f->ws, 64, n), 0);
    assert_int_equal(psc_proxy_init(&f->px, &f->m, f->ws, n), PSC_OK);
    psc_proxy_rest_bounds(&f->m, &f->lo, &f->hi);
}

static void fixture_free(fixture_t *f)
{
    free(f->pack);
    free(f->ws);
}

/* The light the frames are lit by (toward it, model space, unit; the ambient share), or none: as baked. */
typedef struct {
    double az, el, ambient;
} light_t;

static const light_t *frame_light;

static void light_dir(const light_t *l, double out[3])
{
    double az = l->az * M_PI / 180, el = l->el * M_PI / 180;
    out[0] = cos(el) * sin(az), out[1] = sin(el), out[2] = cos(el) * cos(az);
}

/* The product's: frame_light (or as baked) on the pack's drawing state. */
static void set_frame_light(fixture_t *f)
{
    if (!frame_light) {
        assert_int_equal(psc_proxy_set_light(&f->px, NULL, 0), PSC_OK);
        return;
    }
    double d[3];
    light_dir(frame_light, d);
    int32_t l[3] = {(int32_t)lround(d[0] * 65536), (int32_t)lround(d[1] * 65536), (int32_t)lround(d[2] * 65536)};
    assert_int_equal(psc_proxy_set_light(&f->px, l, (uint16_t)lround(frame_light->ambient * 16384)), PSC_OK);
}

/* The reference's decoding of a normal code (psc_oct.h's map, in double). */
static void oct_decode_ref(uint16_t c, double n[3])
{
    double x = (c & 255u) / 127.5 - 1, y = (c >> 8) / 127.5 - 1, z = 1 - fabs(x) - fabs(y);
    if (z < 0) {
        double fx = (1 - fabs(y)) * (x < 0 ? -1 : 1), fy = (1 - fabs(x)) * (y < 0 ? -1 : 1);
        x = fx, y = fy;
    }
    double l = sqrt(x * x + y * y + z * z);
    n[0] = x / l, n[1] = y / l, n[2] = z / l;
}

/* The reference's colour of vertex v lit by frame_light: the pack's colour (lit at rest by the bake's light,
 * 0.45 + 0.55 max(0, n.L0), L0 = (0.4, 0.8, 0.45) normalised) divided by that and times the new light's term for
 * the normal posed in double (its joints' linear parts, weighted, renormalised). */
static uint32_t relit_ref(const psc_proxy_model_t *m, uint32_t v, const psc_mat4_q16_t *skin, bool rigid, unsigned joint)
{
    static const double l0[3] = {0.4 / 1.00124922, 0.8 / 1.00124922, 0.45 / 1.00124922};
    double n[3], np[3] = {0, 0, 0}, l[3];
    oct_decode_ref(m->vertex_normals[v], n);
    for (unsigned k = 0; k < 4; k++) {
        unsigned j = rigid ? joint : m->skin[v].joint[k];
        double w = rigid ? (k == 0 ? 1.0 : 0.0) : m->skin[v].weight_q15[k] / 32768.0;
        for (unsigned r = 0; r < 3 && w != 0; r++)
            np[r] += w * (skin[j].m[r][0] * n[0] + skin[j].m[r][1] * n[1] + skin[j].m[r][2] * n[2]) / 65536.0;
    }
    double ln = sqrt(np[0] * np[0] + np[1] * np[1] + np[2] * np[2]);
    light_dir(frame_light, l);
    double d = ln > 0 ? (np[0] * l[0] + np[1] * l[1] + np[2] * l[2]) / ln : 0, d0 = n[0] * l0[0] + n[1] * l0[1] + n[2] * l0[2];
    double gain = (frame_light->ambient + (1 - frame_light->ambient) * fmax(d, 0)) / (0.45 + 0.55 * fmax(d0, 0));
    uint32_t c = 0;
    for (int sh = 16; sh >= 0; sh -= 8)
        c = c << 8 | (uint32_t)lround(fmin(255, ((m->color[v] >> sh) & 255u) * gain));
    return c;
}

/* Draw the pack posed by skin from orbit (yaw, pitch, dist) into rgb and ids (each W x H XRGB). */
static void render(fixture_t *f, const psc_mat4_q16_t *skin, double yaw, double pitch, double dist,
                   psc_proxy_lod_t lod, uint32_t *rgb, uint32_t *ids)
{
    psc_mat4_q16_t cam;
    psc_3d_config_t cfg = {W, H, 0, 0, 32, tsup_bam_from_deg(50), 0, 0, psc_proxy_max_vertices(&f->m), PSC_3D_HSR_ZBUFFER};
    assert_int_equal(psc_3d_orbit(f->lo, f->hi, tsup_bam_from_deg(yaw),
                                  (int32_t)tsup_bam_from_deg(pitch),
                                  (int32_t)lround(dist * 65536), &cam, &cfg.near_q16, &cfg.far_q16),
                     PSC_OK);
    size_t n = psc_3d_workspace_size(&cfg);
    void *ws3d;
    assert_int_equal(posix_memalign(&ws3d, 64, n), 0);
    psc_3d_t r;
    assert_int_equal(psc_3d_init(&r, &cfg, ws3d, n), PSC_OK);
    psc_proxy_set_focal(&f->px, psc_proxy_focal_px_q16(W, cfg.hfov));
    set_frame_light(f);
    for (int pass = 0; pass < 2; pass++) {
        const psc_3d_draw_t *d;
        unsigned nd;
        assert_int_equal(psc_proxy_frame(&f->px, skin, &cam, lod, pass == 1, &d, &nd), PSC_OK);
        psc_surface_t sf = {W, H, W * 4, PSC_PIX_XRGB8888, pass ? ids : rgb};
        uint32_t bg = pass ? 0u : BG;
        assert_int_equal(psc_3d_render(&r, d, nd, &bg, &sf, NULL), PSC_OK);
    }
    free(ws3d);
}

/* The reference the quality is measured against: the pack's full mesh posed in double precision by skin (each
 * vertex its joints' matrices, read exactly, weighted as the pack weighs them; a rigid part its joint's), its
 * positions then rounded to Q16.16 (2^-16 R), drawn by the tests' double-precision renderer (tsup_3d.h: exact
 * projection, 1/z depth, Gouraud colours), and once more with each part flat in colour index + 1 for the ids.
 * Nothing of the product's fixed-point skinning or rasterizer. The ids are the pixel centres' (the silhouettes);
 * each colour is the mean of REF_SS x REF_SS samples spread over its pixel, what the pixel shows of the scene: a
 * seam or an edge narrower than a pixel is a paler band, not there at one pixel and gone at the next (a view's
 * texels are such means, and so are the A-buffer's edges; against centre samples alone the truck lost 2-3 dB on
 * its seams whatever its texels, four times as many measured the same). */
#define REF_SS 4u
static void reference_full(fixture_t *f, const psc_mat4_q16_t *skin, double yaw, double pitch, double dist,
                           uint32_t *rgb, uint32_t *ids)
{
    const psc_proxy_model_t *m = &f->m;
    psc_mat4_q16_t cam;
    psc_3d_config_t cfg = {W, H, 0, 0, 32, tsup_bam_from_deg(50), 0, 0, psc_proxy_max_vertices(m), PSC_3D_HSR_ZBUFFER};
    assert_int_equal(psc_3d_orbit(f->lo, f->hi, tsup_bam_from_deg(yaw), (int32_t)tsup_bam_from_deg(pitch),
                                  (int32_t)lround(dist * 65536), &cam, &cfg.near_q16, &cfg.far_q16),
                     PSC_OK);
    int32_t *posed = malloc((size_t)m->vertex_count * 3 * sizeof *posed);
    uint32_t *colors = malloc((size_t)m->vertex_count * sizeof *colors);
    psc_mesh_t *meshes = calloc(m->part_count, sizeof *meshes);
    psc_3d_draw_t *draws = calloc(m->part_count, sizeof *draws);
    double *out = malloc((size_t)W * H * 3 * sizeof *out), *fine = malloc((size_t)W * H * 3 * REF_SS * REF_SS *
                                                                           sizeof *fine);
    assert_true(posed && colors && meshes && draws && out && fine);
    unsigned nd = 0;
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *pr = &m->parts[i];
        if (pr->triangle_count == 0)
            continue;
        bool rigid = pr->kind == PSC_PROXY_KIND_PART && (pr->flags & PSC_PROXY_RIGID) != 0;
        for (uint32_t v = pr->first_vertex; v < pr->first_vertex + pr->vertex_count; v++) {
            const int32_t *p = &m->position_q16[3u * v];
            double acc[3] = {0, 0, 0};
            for (unsigned k = 0; k < 4; k++) {
                unsigned j = rigid ? pr->joint : m->skin[v].joint[k];
                double w = rigid ? (k == 0 ? 1.0 : 0.0) : m->skin[v].weight_q15[k] / 32768.0;
                if (w == 0)
                    continue;
                const psc_mat4_q16_t *sm = &skin[j];
                for (unsigned r = 0; r < 3; r++)
                    acc[r] += w * ((sm->m[r][0] * (double)p[0] + sm->m[r][1] * (double)p[1] +
                                    sm->m[r][2] * (double)p[2]) / 65536.0 + sm->m[r][3]);
            }
            for (unsigned r = 0; r < 3; r++)
                posed[3u * v + r] = (int32_t)lround(acc[r]);
            colors[v] = frame_light ? relit_ref(m, v, skin, rigid, pr->joint) : m->color[v];
        }
        meshes[nd] = (psc_mesh_t){.vertex_count = pr->vertex_count, .triangle_count = pr->triangle_count,
                                  .position_q16 = posed + 3u * (size_t)pr->first_vertex,
                                  .color = colors + pr->first_vertex,
                                  .index = m->index + 3u * (size_t)pr->first_triangle};
        psc_3d_draw_defaults(&draws[nd], &meshes[nd]);
        draws[nd].camera_from_object = cam;
        draws[nd].color = i + 1u;   /* (the ids' pass: the mesh's colours taken away) */
        nd++;
    }
    for (int pass = 0; pass < 2; pass++) {
        for (unsigned k = 0; k < nd; k++) {
            meshes[k].color = pass ? NULL : colors + (meshes[k].position_q16 - posed) / 3;
            draws[k].shade = pass ? PSC_SHADE_FLAT : draws[k].shade;
        }
        if (pass) {
            tsup_ref_render3d(&cfg, draws, nd, 0u, out, NULL);
        } else {   /* REF_SS times the pixels (the same field of view), each pixel its samples' mean */
            psc_3d_config_t fine_cfg = cfg;
            fine_cfg.width = (uint16_t)(W * REF_SS);
            fine_cfg.height = (uint16_t)(H * REF_SS);
            tsup_ref_render3d(&fine_cfg, draws, nd, BG, fine, NULL);
            for (unsigned y = 0; y < H; y++)
                for (unsigned x = 0; x < W; x++)
                    for (unsigned k = 0; k < 3; k++) {
                        double sum = 0;
                        for (unsigned j = 0; j < REF_SS; j++)
                            for (unsigned i = 0; i < REF_SS; i++)
                                sum += fmin(255, fmax(0, fine[3 * ((size_t)(REF_SS * y + j) * REF_SS * W +
                                                                    REF_SS * x + i) + k]));
                        out[3 * (y * W + x) + k] = sum / (REF_SS * REF_SS);
                    }
        }
        uint32_t *dst = pass ? ids : rgb;
        for (unsigned i = 0; i < W * H; i++) {
            uint32_t c = 0;
            for (unsigned k = 0; k < 3; k++)
                c = c << 8 | (uint32_t)lround(fmin(255, fmax(0, out[3 * i + k])));
            dst[i] = c;
        }
    }
    free(posed), free(colors), free(meshes), free(draws), free(out), free(fine);
}

typedef struct {
    double iou, psnr, ids;
    double hole;      /* share of the full silhouette the proxies leave uncovered */
    double psnr_both; /* the PSNR over the pixels both cover: the shading alone, without the silhouettes' mismatch */
} quality_t;

/* Whether part ids pa and pb (part index + 1) follow the same joint or joints at most two steps apart in the
 * skeleton: the parts and joint strips cut from the simplified mesh end where its triangles end, not where the
 * model's do, so a pixel near a border may show the neighbour's proxy over the model's own part. */
static bool same_bone(const psc_proxy_model_t *m, uint32_t pa, uint32_t pb)
{
    if (pa == pb)
        return true;
    if (pa == 0 || pb == 0 || pa > m->part_count || pb > m->part_count)
        return false;
    int32_t ja = m->parts[pa - 1].joint, jb = m->parts[pb - 1].joint;
    for (int up = 0; up <= 2 && ja >= 0; up++, ja = m->joints[ja].parent) {
        int32_t j = jb;
        for (int k = 0; k + up <= 2 && j >= 0; k++, j = m->joints[j].parent)
            if (j == ja)
                return true;
    }
    return false;
}

static quality_t compare(const psc_proxy_model_t *m, const uint32_t *a, const uint32_t *ia, const uint32_t *b,
                         const uint32_t *ib)
{
    unsigned inter = 0, uni = 0, both = 0, same = 0, full = 0, holes = 0;
    double se = 0, se_both = 0;
    for (unsigned i = 0; i < W * H; i++) {
        bool pa = (ia[i] & 0xFFFFu) != 0, pb = (ib[i] & 0xFFFFu) != 0;
        inter += pa && pb;
        uni += pa || pb;
        full += pb;
        holes += pb && !pa;
        if (pa || pb)
            for (unsigned s = 0; s < 24; s += 8) {
                double d = (double)((a[i] >> s) & 255u) - ((b[i] >> s) & 255u);
                se += d * d;
                se_both += pa && pb ? d * d : 0;
            }
        if (pa && pb) {
            both++;
            same += same_bone(m, ia[i] & 0xFFFFu, ib[i] & 0xFFFFu);
        }
    }
    double mse = uni ? se / (3.0 * uni) : 0, mse_both = both ? se_both / (3.0 * both) : 0;
    return (quality_t){uni ? (double)inter / uni : 1, mse > 0 ? 10 * log10(255.0 * 255.0 / mse) : 99,
                       both ? (double)same / both : 1, full ? (double)holes / full : 0,
                       mse_both > 0 ? 10 * log10(255.0 * 255.0 / mse_both) : 99};
}

typedef struct {
    double yaw, pitch, dist, t;   /* t < 0: rest */
    int bend;                     /* > 0: the bar bent at every third joint by this many degrees */
    psc_proxy_lod_t lod;          /* what is measured against the full mesh: the proxies (0) or the billboard */
} shot_t;

static quality_t measure(fixture_t *f, const shot_t *s, const char *name)
{
    static uint32_t a[W * H], ia[W * H], b[W * H], ib[W * H];
    psc_mat4_q16_t *skin = malloc(f->m.joint_count * sizeof *skin);
    assert_non_null(skin);
    if (s->bend) {
        double(*pre)[12] = calloc(f->m.joint_count, sizeof *pre), (*post)[12] = calloc(f->m.joint_count, sizeof *post);
        double c = cos(s->bend * M_PI / 180), sn = sin(s->bend * M_PI / 180);
        for (uint32_t j = 0; j < f->m.joint_count; j++) {
            const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, rz[12] = {c, -sn, 0, 0, sn, c, 0, 0, 0, 0, 1, 0};
            memcpy(pre[j], id, sizeof id);
            memcpy(post[j], j > 2 && j % 3 == 0 ? rz : id, sizeof id);
        }
        assert_int_equal(psc_render_proxy_pose(&f->m, s->t, (const double(*)[12])pre, (const double(*)[12])post, skin),
                         0);
        free(pre), free(post);
    } else {
        psc_proxy_pose_at(&f->m, s->t < 0 ? -1 : (int64_t)llround(s->t * 1e6), skin);
    }
    static uint32_t c[W * H], ic[W * H];
    render(f, skin, s->yaw, s->pitch, s->dist, s->lod, a, ia);
    reference_full(f, skin, s->yaw, s->pitch, s->dist, b, ib);
    /* the product's own full mesh against the same reference: what the comparison itself allows */
    render(f, skin, s->yaw, s->pitch, s->dist, PSC_PROXY_LOD_FULL, c, ic);
    quality_t own = compare(&f->m, c, ic, b, ib);
    free(skin);
    if (s->lod == PSC_PROXY_LOD_BILLBOARD)   /* one id for the whole: compare silhouettes, not parts */
        for (unsigned i = 0; i < W * H; i++)
            ib[i] = ib[i] & 0xFFFFu ? 1u : 0u, ia[i] = ia[i] & 0xFFFFu ? 1u : 0u;
    quality_t q = compare(&f->m, a, ia, b, ib);
    if (getenv("PSC_PROXY_SAVE")) {   /* the frames, to look at: proxies, reference, own full mesh */
        char path[96];
        static int shot;
        psc_surface_t sa = {W, H, W * 4, PSC_PIX_XRGB8888, a}, sb = {W, H, W * 4, PSC_PIX_XRGB8888, b};
        snprintf(path, sizeof path, "proxy-%s-%d-proxies.png", name, shot);
        tsup_save_png(&sa, path);
        snprintf(path, sizeof path, "proxy-%s-%d-full.png", name, shot);
        tsup_save_png(&sb, path);
        psc_surface_t sc = {W, H, W * 4, PSC_PIX_XRGB8888, c};
        snprintf(path, sizeof path, "proxy-%s-%d-own.png", name, shot);
        tsup_save_png(&sc, path);
        static uint32_t diff[W * H];   /* both grey, the proxies' alone red, the full mesh's alone blue */
        for (unsigned i = 0; i < W * H; i++) {
            bool pa = (ia[i] & 0xFFFFu) != 0, pb = (ib[i] & 0xFFFFu) != 0;
            diff[i] = pa && pb ? 0x808080u : pa ? 0xFF0000u : pb ? 0x0000FFu : 0u;
        }
        psc_surface_t sd = {W, H, W * 4, PSC_PIX_XRGB8888, diff};
        snprintf(path, sizeof path, "proxy-%s-%d-diff.png", name, shot++);
        tsup_save_png(&sd, path);
    }
    char pose[32];
    if (s->bend && s->t < 0)
        snprintf(pose, sizeof pose, "rest+%d", s->bend);
    else if (s->bend)
        snprintf(pose, sizeof pose, "t=%.2f+%d", s->t, s->bend);
    else if (s->t < 0)
        snprintf(pose, sizeof pose, "rest");
    else
        snprintf(pose, sizeof pose, "t=%.2f", s->t);
    print_message("  %-6s %-9s orbit %5.0f,%4.0f,%4.1f pose %-10s  IoU %.3f  PSNR %5.1f dB  front part %.3f  holes %.3f"
                  "  (the full mesh: IoU %.3f, %.1f dB)\n",
                  name, s->lod == PSC_PROXY_LOD_BILLBOARD ? "billboard" : "proxies", s->yaw, s->pitch, s->dist, pose,
                  q.iou, q.psnr, q.ids, q.hole, own.iou, own.psnr);
    /* the product's full mesh is the reference but for the rasterizer's sub-pixel rounding and Q16 skinning */
    assert_true(own.iou >= 0.97);
    assert_true(own.ids >= 0.995);
    return q;
}

static void relight_quality(fixture_t *f, const shot_t *shots, unsigned n, const char *name, double both_db,
                            double union_db);

/* --views K: the smallest odd grid of at least K views, or a larger one while the texture budget holds the same texel
 * density (or one of at least PSC_BAKE_PROXY_DENSITY_ENOUGH) and the views stay within 2 K. */
static void test_views_grid(void **state)
{
    (void)state;
    static const struct {
        unsigned views, tex, side;
    } cases[] = {
        {64, PSC_BAKE_PROXY_TEX, 11},   /* 81 and 121 views both hold 137 texels per R: 121 (169 would not) */
        {25, PSC_BAKE_PROXY_TEX, 5},    /* 49 views would take the body from 256 to 128 texels a side */
        {9, 16, 3},                     /* 25 views hold 16 texels a side, but are more than twice 9 */
    };
    for (unsigned k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        fixture_t f = {0};
        bake(&f, GLTF_DIR "CesiumMilkTruck.gltf", cases[k].views, cases[k].tex);
        assert_int_equal(f.m.view_side, cases[k].side);
        fixture_free(&f);
    }
}

static void test_truck_quality(void **state)
{
    (void)state;
    fixture_t f = {0};
    bake(&f, GLTF_DIR "CesiumMilkTruck.gltf", PSC_BAKE_PROXY_VIEWS, PSC_BAKE_PROXY_TEX);
    static const shot_t shots[] = {
        {15, 10, 3, -1, 0, 0}, {50, 25, 3, -1, 0, 0}, {100, -15, 3, -1, 0, 0}, {200, 35, 3, -1, 0, 0},
        {300, 5, 3, -1, 0, 0},
    };
    double iou = 0, psnr = 0, ids = 0;
    for (unsigned k = 0; k < sizeof shots / sizeof shots[0]; k++) {
        quality_t q = measure(&f, &shots[k], "truck");
        iou += q.iou / 5, psnr += q.psnr / 5, ids += q.ids / 5;
        /* the issue's goal at every view: the default --views 64, 121 views at 137 texels per R (measured IoU
         * 0.984..0.992, 24.9..34.2 dB with soft silhouettes, 24.7..32.6 alpha-tested) */
        assert_true(q.iou >= 0.97);
        assert_true(q.psnr >= 24.0);
        assert_true(q.ids >= 0.99);
    }
    print_message("  truck mean: IoU %.3f, PSNR %.1f dB, front part %.3f\n", iou, psnr, ids);
    assert_true(iou >= 0.98);   /* measured 0.989 */
    assert_true(psnr >= 27.0);  /* measured 28.6 dB with soft silhouettes (27.8 alpha-tested) */
    /* the billboard, far: its rest-pose views on a quad facing the camera */
    static const shot_t far[] = {{40, 15, 12, -1, 0, PSC_PROXY_LOD_BILLBOARD}, {230, -10, 12, -1, 0, PSC_PROXY_LOD_BILLBOARD}};
    for (unsigned k = 0; k < 2; k++) {
        quality_t q = measure(&f, &far[k], "truck");
        assert_true(q.iou >= 0.78);   /* measured 0.83, 0.85 */
    }
    /* the issue's 24 dB over the union under every light (measured 24.57..26.60; 25.67..26.97 where both cover;
     * alpha-tested 24.01..26.31 and 25.47..26.86) */
    relight_quality(&f, shots, sizeof shots / sizeof shots[0], "truck", 25.0, 24.0);
    relight_quality(&f, far, 2, "truck", 14.5, 12.5);   /* the billboard: measured 15.7..17.0, 13.8..16.0 */
    fixture_free(&f);
}

static void test_bar_quality(void **state)
{
    (void)state;
    fixture_t f = {0};
    bake(&f, GLTF_DIR "animation_with_skeleton.gltf", PSC_BAKE_PROXY_VIEWS, PSC_BAKE_PROXY_TEX);
    /* 121 views at 239 texels per R rather than 81 at 256: past a texel a pixel where proxies are drawn, closer views
     * are worth more than density (81 views: IoU 0.918 at the first pose below) */
    assert_int_equal(f.m.view_side, 11);
    /* its long triangles split where the skin changes along them (skin_split.h), to a quarter of the model's */
    assert_true(f.m.proxy_triangle_count * 4u <= f.m.triangle_count && f.m.proxy_triangle_count > 400);   /* 528; 266 unsplit */
    static const shot_t shots[] = {
        {20, 15, 2.2, 0.11, 0, 0},  {75, 30, 2.2, 0.37, 0, 0},  {140, -10, 2.2, 0.62, 0, 0}, {250, 20, 2.2, -1, 0, 0},
        {35, 25, 2.2, 0.2, 0, 0},   {35, 25, 2.2, 0.2, 20, 0},  {35, 25, 2.2, 0.2, 45, 0},
    };
    for (unsigned k = 0; k < sizeof shots / sizeof shots[0]; k++) {
        quality_t q = measure(&f, &shots[k], "bar");
        /* the floor of what they give (the default --views 64: 121 views at 239 texels per R; IoU measured
         * 0.941..0.956 at the animation's poses, 0.894 bent 20 degrees past it and 0.826 bent 45, holes
         * 0.016..0.045 and 0.103 bent 45, front part 0.99..0.997; unsplit, 0.928..0.953, 0.868 and 0.790, holes up to
         * 0.125): the bar is 32 times longer than thick, 8 pixels across here, and a pixel's shift at its edges costs
         * 0.1 of IoU */
        assert_true(q.iou >= (shots[k].bend > 30 ? 0.81 : shots[k].bend ? 0.87 : 0.93));
        assert_true(q.hole <= (shots[k].bend > 30 ? 0.12 : 0.06));
        assert_true(q.ids >= 0.98);
    }
    fixture_free(&f);
}

/* A generated machine of 120 960 triangles: ten rings on nodes of their own, each with 240 bolts (closed pieces of
 * 12 triangles), baked with the defaults at 64 views and drawn as proxies at rest and with every third ring turned,
 * against its full mesh: its proxies cut to 8 % of its triangles (every bolt kept whole by the edge collapses, so
 * the parts are made coarser whatever their topology), the pack within 16 MB. */
static void test_machine_quality(void **state)
{
    (void)state;
    fixture_t f = {0};
    psc_gltf_t g;
    assert_int_equal(psc_gltf_machine(&g, 10, 240), 0);
    uint32_t triangles = g.mesh.triangle_count;
    assert_true(triangles >= 100000);
    bake_model(&f, &g, "generated machine", 64, PSC_BAKE_PROXY_TEX);
    assert_true(f.m.proxy_triangle_count <= triangles * 8u / 100u);
    assert_true(f.len <= 16u * 1000u * 1000u);
    static const shot_t shots[] = {
        {20, 25, 6, -1, 0, 0}, {110, -15, 6, -1, 0, 0}, {200, 40, 4, -1, 0, 0}, {290, 10, 6, -1, 40, 0},
        {60, 30, 4, -1, 90, 0},
    };
    double iou = 0;
    for (unsigned k = 0; k < sizeof shots / sizeof shots[0]; k++) {
        quality_t q = measure(&f, &shots[k], "machine");
        iou += q.iou / 5;
        assert_true(q.iou >= 0.945);   /* measured 0.953..0.962 */
    }
    print_message("  machine mean: IoU %.3f\n", iou);
    assert_true(iou >= 0.95);          /* measured 0.958 */
    fixture_free(&f);
}

/* The view textures of pack f: one run of texels per part, one after another, exactly the XTEX section (a part's
 * texture side or levels changed is refused); sides in proportion to the proxies' sizes (one texel density, within
 * the factor 2 of rounding to powers of two either way); each mip level the 2 x 2 reduction of the one before. */
/* The view textures' coverage rule (psc_bake_proxy_mips), on shapes whose area is known: a disc's covered texels
 * weigh its area at every mip level, neither grown nor shrunk (the rule a quarter of the samples gave grew each
 * silhouette by a quarter texel, and compounded level by level); a line a third of a texel wide keeps a line of
 * texels; a region whose samples show the model but are not kept (a neighbour's surface) stays empty; a texel's colour
 * is its kept samples' mean. */
static void test_mip_coverage(void **state)
{
    (void)state;
    enum { SIDE = 64, LEVELS = 5, SUB = 4 };
    static uint16_t raw[SIDE * SIDE], chain[SIDE * SIDE * 2];
    static psc_bake_cover_t cov[SIDE * SIDE];
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 4242u);
    double bias[LEVELS] = {0}, worst[LEVELS] = {0};
    const unsigned discs = 200;
    for (unsigned n = 0; n < discs; n++) {
        double cx = 20 + 24 * tsup_rng_unit(&rng), cy = 20 + 24 * tsup_rng_unit(&rng), r = 4 + 14 * tsup_rng_unit(&rng);
        /* the left third of some discs shows a neighbour's surface: seen, not kept */
        double cut = n % 4 == 0 ? cx - r / 3 : -1;
        uint16_t grey = (uint16_t)(0x0841u * (1u + n % 30u));
        for (unsigned y = 0; y < SIDE; y++)
            for (unsigned x = 0; x < SIDE; x++) {
                unsigned seen = 0, kept = 0;
                for (unsigned j = 0; j < SUB; j++)
                    for (unsigned i = 0; i < SUB; i++) {
                        double sx = x + (i + 0.5) / SUB, sy = y + (j + 0.5) / SUB;
                        bool in = (sx - cx) * (sx - cx) + (sy - cy) * (sy - cy) < r * r;
                        seen += in;
                        kept += in && sx >= cut;
                    }
                cov[y * SIDE + x] = (psc_bake_cover_t){(uint8_t)seen, (uint8_t)kept};
                raw[y * SIDE + x] = kept ? grey : PSC_VIEW_TEXEL_EMPTY;
            }
        assert_int_equal(psc_bake_proxy_mips(raw, cov, SIDE, LEVELS, chain), 0);
        const uint16_t *lv = chain;
        for (unsigned l = 0; l < LEVELS; l++) {
            unsigned side = SIDE >> l;
            double t = (double)(1u << l), area = 0, exact = 0;
            for (unsigned y = 0; y < side; y++)
                for (unsigned x = 0; x < side; x++) {
                    uint16_t c = lv[y * side + x];
                    double px = (x + 0.5) * t, py = (y + 0.5) * t;   /* its centre, in level-0 texels */
                    if (c != PSC_VIEW_TEXEL_EMPTY) {
                        assert_int_equal(c, grey);   /* every kept sample the same colour: their mean */
                        area += t * t;
                        /* nothing where no sample is kept: outside the disc or left of the cut by a texel */
                        assert_true(hypot(px - cx, py - cy) < r + t && px > cut - t);
                    }
                }
            lv += (size_t)side * side;
            if (cut >= 0)
                continue;   /* the area: whole discs only */
            exact = M_PI * r * r;
            double err = (area - exact) / (2 * M_PI * r * t);   /* in that level's texels across the silhouette */
            bias[l] += err / (discs - discs / 4);
            worst[l] = fmax(worst[l], fabs(err));
        }
    }
    for (unsigned l = 0; l < LEVELS; l++) {
        print_message("  mip level %u: a disc's covered area against its own, %+.3f texels across its silhouette on "
                      "average, %.3f at worst\n", l, bias[l], worst[l]);
        assert_true(fabs(bias[l]) <= 0.06);   /* unbiased (the quarter rule: +0.25 at level 0, more above) */
        assert_true(worst[l] <= 0.6);   /* (level 4 is 4 x 4 texels of 16) */
    }
    /* a line half a texel wide, at random slopes under 42 degrees: a texel in every column along it */
    for (unsigned n = 0; n < 50; n++) {
        double y0 = 16 + 32 * tsup_rng_unit(&rng), slope = tsup_rng_range(&rng, -0.9, 0.9), half = 0.25;
        double norm = sqrt(1 + slope * slope);
        for (unsigned y = 0; y < SIDE; y++)
            for (unsigned x = 0; x < SIDE; x++) {
                unsigned in = 0;
                for (unsigned j = 0; j < SUB; j++)
                    for (unsigned i = 0; i < SUB; i++) {
                        double sx = x + (i + 0.5) / SUB, sy = y + (j + 0.5) / SUB;
                        in += fabs(sy - (y0 + slope * (sx - 32))) / norm < half;
                    }
                cov[y * SIDE + x] = (psc_bake_cover_t){(uint8_t)in, (uint8_t)in};
                raw[y * SIDE + x] = in ? 0xFFFFu : PSC_VIEW_TEXEL_EMPTY;
            }
        assert_int_equal(psc_bake_proxy_mips(raw, cov, SIDE, 1, chain), 0);
        unsigned columns = 0;
        for (unsigned x = 8; x < SIDE - 8; x++) {
            bool any = false;
            for (unsigned y = 0; y < SIDE; y++)
                any = any || chain[y * SIDE + x] != PSC_VIEW_TEXEL_EMPTY;
            columns += any;
        }
        assert_true(columns >= (SIDE - 16) * 9 / 10);
    }
}

static void check_atlas(fixture_t *f)
{
    const psc_proxy_model_t *m = &f->m;
    assert_true(m->atlas);
    double dens[PSC_PROXY_MAX_PARTS];
    unsigned nd = 0, runs = 0;
    size_t texels = 0;
    for (uint32_t i = 0; i < m->part_count; i++) {
        psc_proxy_tex_t t = psc_proxy_part_tex(m, i);
        assert_true((t.side == 0) == (m->parts[i].proxy_triangle_count == 0));
        texels += (size_t)t.chain * m->view_count;
        runs += t.side != 0;
        if (t.side > PSC_PROXY_TEX_MIN && t.side < m->tex_size)
            dens[nd++] = t.side / (2.04 * m->parts[i].radius_q16 / 65536.0);
    }
    assert_true(runs > 0 && nd > 0);
    assert_ptr_equal((const uint8_t *)(m->texels + texels), (const uint8_t *)m->texels + texels * 2u);
    /* one density: every part within a factor 3 of the median */
    for (unsigned a = 0; a < nd; a++)
        for (unsigned b = a + 1; b < nd; b++)
            if (dens[b] < dens[a]) {
                double t = dens[a];
                dens[a] = dens[b], dens[b] = t;
            }
    double med = dens[nd / 2];
    print_message("  atlas: %u proxies' runs, %.1f MB with mips; %.0f texels per R (median of %u), %.0f..%.0f\n", runs,
                  texels * 2.0 / 1048576.0, med, nd, dens[0], dens[nd - 1]);
    assert_true(dens[0] >= med / 3 && dens[nd - 1] <= med * 3);
    /* a part's side doubled, or a level too many: refused */
    uint32_t k = 0;
    while (m->parts[k].proxy_triangle_count == 0)
        k++;
    for (int change = 0; change < 3; change++) {
        uint8_t *b = malloc(f->len);
        assert_non_null(b);
        memcpy(b, f->pack, f->len);
        psc_proxy_part_raw_t *pr = (psc_proxy_part_raw_t *)(void *)(b + ((const uint8_t *)&m->parts[k] - f->pack));
        if (change == 0)
            pr->tex_size = (uint16_t)(pr->tex_size == m->tex_size ? pr->tex_size / 2u : pr->tex_size * 2u);
        else if (change == 1)
            pr->tex_levels = (uint8_t)(pr->tex_levels + 1u);
        else
            pr->tex_levels = 200;   /* a shift past the word, were it not refused first */
        tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, 0);
        tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, b, f->len));
        psc_proxy_model_t bad;
        psc_container_error_t e = {NULL, 0};
        assert_int_equal(psc_proxy_parse(b, f->len, &bad, &e), PSC_ERR_CORRUPT);
        print_message("  part %u's %s changed: %s\n", k, change ? "levels" : "side", e.what);
        free(b);
    }
}

/* Relit (psc_proxy_set_light) under three lights other than the bake's, against the reference lit the same way
 * (relit_ref): the mean PSNR over the pixels both cover (the shading) at least both_db, over the silhouettes' union at
 * least union_db, and the silhouettes unchanged. (A light brighter than the bake's shows the same relative errors
 * larger, and the silhouettes' mismatch against the background with more contrast: the baked figures printed beside
 * are not the bound.) */
static void relight_quality(fixture_t *f, const shot_t *shots, unsigned n, const char *name, double both_db,
                            double union_db)
{
    static const light_t lights[] = {{-90, 10, 0.45}, {180, 30, 0.45}, {60, -25, 0.25}};
    double base = 0, base_both = 0, base_iou = 0;
    for (unsigned k = 0; k < n; k++) {
        quality_t q = measure(f, &shots[k], name);
        base += q.psnr / n, base_both += q.psnr_both / n, base_iou += q.iou / n;
    }
    for (unsigned l = 0; l < sizeof lights / sizeof lights[0]; l++) {
        frame_light = &lights[l];
        double psnr = 0, both = 0, iou = 0;
        for (unsigned k = 0; k < n; k++) {
            quality_t q = measure(f, &shots[k], name);
            psnr += q.psnr / n, both += q.psnr_both / n, iou += q.iou / n;
        }
        frame_light = NULL;
        print_message("  %s relit toward %.0f,%.0f (ambient %.2f): PSNR %.2f dB (where both cover %.2f dB), IoU %.3f; "
                      "as baked: %.1f dB (%.1f dB), %.3f\n",
                      name, lights[l].az, lights[l].el, lights[l].ambient, psnr, both, iou, base, base_both, base_iou);
        assert_true(both >= both_db);
        assert_true(psnr >= union_db);
        assert_true(fabs(iou - base_iou) < 0.002);
    }
}

/* A held-out model baked as the issue measured them (--views 64, the default textures): its proxies at most a quarter
 * of its triangles, its pack at most 16 MB, its atlas checked. */
static void bake_held_out(fixture_t *f, const char *path)
{
    bake(f, path, 64, PSC_BAKE_PROXY_TEX);
    assert_true(f->m.proxy_triangle_count * 4u <= f->m.triangle_count);
    assert_true(f->len <= 16u * 1048576u);
    check_atlas(f);
}

/* The held-out characters' views and poses, none baked: near (2.5 R: the model fills the view, R about 137 pixels)
 * and at a middle distance (6 R: a third of it, where the level of detail draws the proxies), at times of their
 * animation (or at rest, t < 0). */
#define HELD_OUT_SHOTS 10u
static const shot_t held_out_shots[HELD_OUT_SHOTS] = {
    {20, 10, 2.5, 0.2, 0, 0}, {95, 25, 2.5, 0.8, 0, 0}, {170, -10, 2.5, 1.6, 0, 0}, {260, 15, 2.5, 2.5, 0, 0},
    {330, 40, 2.5, -1, 0, 0}, {50, 5, 6, 0.5, 0, 0},  {140, 20, 6, 1.3, 0, 0},  {230, -5, 6, 2.1, 0, 0},
    {300, 30, 6, 2.9, 0, 0},  {10, -20, 6, -1, 0, 0},
};

/* A held-out skinned human (tests/data/assimp: 5 126 triangles, 58 nodes; nobody tuned the proxies on it) at
 * poses and views never baked. */
static void test_human_quality(void **state)
{
    (void)state;
    fixture_t f = {0};
    bake_held_out(&f, TSUP_DATA_ASSIMP "BCN_Epileptic.X");
    const shot_t *shots = held_out_shots;
    double iou[2] = {0, 0}, psnr[2] = {0, 0};
    for (unsigned k = 0; k < HELD_OUT_SHOTS; k++) {
        quality_t q = measure(&f, &shots[k], "human");
        unsigned far = shots[k].dist > 3;
        iou[far] += q.iou / 5, psnr[far] += q.psnr / 5;
        assert_true(q.iou >= 0.94);    /* measured 0.953..0.968 (the goal: 0.92 at every view, 0.95 on average) */
        assert_true(q.psnr >= 30.5);   /* measured 31.7..41.3 dB with soft silhouettes (31.0..40.6 alpha-tested) */
        assert_true(q.ids >= 0.98);
    }
    print_message("  human mean: near IoU %.3f, PSNR %.1f dB; middle distance IoU %.3f, PSNR %.1f dB\n", iou[0], psnr[0],
                  iou[1], psnr[1]);
    assert_true(iou[0] >= 0.95 && iou[1] >= 0.95);     /* measured 0.960, 0.958 */
    assert_true(psnr[0] >= 34.5 && psnr[1] >= 34.5);   /* measured 35.5, 36.0 dB (34.4, 34.1 alpha-tested) */
    /* the goal, 32 dB over the union as baked, under each light: measured 33.32..34.77 and 32.10..33.14 dB (32.51..34.30
     * and 30.59..31.64 alpha-tested, whose jagged silhouettes against the background the relit contrast shows) */
    relight_quality(&f, shots, HELD_OUT_SHOTS, "human", 33.0, 32.0);
    fixture_free(&f);
}

/* Another held-out character: three.js's RobotExpressive (CC0, tests/data/gltf/SOURCES.md; 3 237 triangles on 4
 * skins, 19 meshes of three flat colours, its first animation), at views and poses never baked. The issue's PSNR goals
 * name a one-material character (32 dB) and textured CAD colours (24 dB); this one lies between: its orange, grey and
 * black meet at hard edges, each a pixel's error wherever a view places it a pixel off. */
static void test_robot_quality(void **state)
{
    (void)state;
    fixture_t f = {0};
    bake_held_out(&f, GLTF_DIR "RobotExpressive.glb");
    const shot_t *shots = held_out_shots;
    const unsigned n = HELD_OUT_SHOTS;
    double iou = 0, psnr = 0;
    for (unsigned k = 0; k < n; k++) {
        quality_t q = measure(&f, &shots[k], "robot");
        iou += q.iou / n, psnr += q.psnr / n;
        assert_true(q.iou >= 0.92);   /* the goal at every view; measured 0.939..0.964 */
        assert_true(q.psnr >= 27.0);  /* measured 28.2..32.3 dB */
        assert_true(q.ids >= 0.95);   /* the part in front: measured 0.969..0.995 */
    }
    print_message("  robot mean: IoU %.4f, PSNR %.2f dB\n", iou, psnr);
    assert_true(iou >= 0.95);    /* the goal; measured 0.952 */
    assert_true(psnr >= 30.0);   /* measured 30.8 dB */
    /* relit: measured 30.95..31.53 dB where both cover, 29.31..29.85 dB over the union */
    relight_quality(&f, shots, n, "robot", 30.0, 28.5);
    fixture_free(&f);
}

/* Depth offsets (XTDP): each proxy pixel takes the depth of the surface its views show, not its proxy's. The depth
 * the human's proxies leave in the buffer against the full mesh's (the same projection: its depth is the surface's
 * to the buffer's rounding), over the pixels both cover, at the quality shots' views and poses: with the offsets
 * and with them taken away. A proxy pushed out over a bulge, or cutting a hollow, is as deep as that surface. */
static void test_depth_offsets(void **state)
{
    (void)state;
    fixture_t f = {0};
    bake(&f, TSUP_DATA_ASSIMP "BCN_Epileptic.X", 64, PSC_BAKE_PROXY_TEX);
    assert_non_null(f.m.tex_depth);
    const int8_t *offsets = f.m.tex_depth;
    size_t nonzero = 0, n = 0;
    for (uint32_t i = 0; i < f.m.part_count; i++) {
        uint32_t half = PSC_PROXY_HALF_SIDE(psc_proxy_part_tex(&f.m, i).side);
        n += (size_t)half * half * f.m.view_count;
    }
    for (size_t i = 0; i < n; i++)
        nonzero += offsets[i] != 0;
    assert_true(nonzero > n / 4);   /* the surface is seldom exactly on its proxy */
    static const struct {
        double yaw, pitch, dist, t;
    } shots[] = {{20, 10, 2.5, 0.2}, {95, 25, 2.5, 0.8}, {170, -10, 2.5, 1.6}, {260, 15, 2.5, 2.5}, {50, 5, 6, 0.5},
                 {140, 20, 6, 1.3}};
    static uint16_t dp[W * H], df[W * H];
    static uint32_t rgb[W * H];
    psc_mat4_q16_t *skin = malloc(f.m.joint_count * sizeof *skin), cam;
    assert_non_null(skin);
    double err[2] = {0, 0};
    for (int with = 1; with >= 0; with--) {
        f.m.tex_depth = with ? offsets : NULL;   /* (psc_proxy_t reads the model it was given each frame) */
        unsigned count = 0;
        double sum = 0;
        for (unsigned k = 0; k < sizeof shots / sizeof shots[0]; k++) {
            psc_3d_config_t cfg = {W, H, 0, 0, 32, tsup_bam_from_deg(50), 0, 0, psc_proxy_max_vertices(&f.m),
                                   PSC_3D_HSR_ZBUFFER};
            assert_int_equal(psc_3d_orbit(f.lo, f.hi, tsup_bam_from_deg(shots[k].yaw),
                                          (int32_t)tsup_bam_from_deg(shots[k].pitch),
                                          (int32_t)lround(shots[k].dist * 65536), &cam, &cfg.near_q16, &cfg.far_q16),
                             PSC_OK);
            psc_proxy_pose_at(&f.m, (int64_t)llround(shots[k].t * 1e6), skin);
            size_t wn = psc_3d_workspace_size(&cfg);
            void *ws3d;
            assert_int_equal(posix_memalign(&ws3d, 64, wn), 0);
            psc_3d_t r;
            assert_int_equal(psc_3d_init(&r, &cfg, ws3d, wn), PSC_OK);
            psc_proxy_set_focal(&f.px, psc_proxy_focal_px_q16(W, cfg.hfov));
            for (int full = 0; full < 2; full++) {
                const psc_3d_draw_t *d;
                unsigned nd;
                uint32_t bg = 0;
                psc_surface_t sf = {W, H, W * 4, PSC_PIX_XRGB8888, rgb};
                r.depth_out = full ? df : dp;
                assert_int_equal(psc_proxy_frame(&f.px, skin, &cam, full ? PSC_PROXY_LOD_FULL : PSC_PROXY_LOD_PROXIES,
                                                 false, &d, &nd), PSC_OK);
                assert_int_equal(psc_3d_render(&r, d, nd, &bg, &sf, NULL), PSC_OK);
            }
            /* the buffer's depth D (of 65536) is (1 - near/z) far/(far - near): z = near / (1 - D (far - near)/far) */
            double near = cfg.near_q16 / 65536.0, far = cfg.far_q16 / 65536.0;
            for (unsigned i = 0; i < W * H; i++) {
                if (dp[i] == 0xFFFFu || df[i] == 0xFFFFu)
                    continue;
                double zp = near / (1 - (dp[i] + 0.5) / 65536.0 * (far - near) / far);
                double zf = near / (1 - (df[i] + 0.5) / 65536.0 * (far - near) / far);
                sum += fabs(zp - zf);
                count++;
            }
            free(ws3d);
        }
        err[with] = sum / count;
    }
    f.m.tex_depth = offsets;
    print_message("  the proxies' depth against the full mesh's where both cover: %.4f R on average with the depth "
                  "offsets, %.4f R without\n", err[1], err[0]);
    assert_true(err[1] <= 0.6 * err[0]);
    free(skin);
    fixture_free(&f);
}

/* The bar baked coarse (9 views, 16 texels) into f, posed at 0.4 s and bent 90 degrees more at every third joint:
 * its skin matrices (malloc'd), and a camera 4 R in front of it into *cam. */
static psc_mat4_q16_t *bar_bent_90(fixture_t *f, psc_mat4_q16_t *cam)
{
    bake(f, GLTF_DIR "animation_with_skeleton.gltf", 9, 16);
    const psc_proxy_model_t *m = &f->m;
    psc_mat4_q16_t *skin = malloc(m->joint_count * sizeof *skin);
    double(*pre)[12] = calloc(m->joint_count, sizeof *pre), (*post)[12] = calloc(m->joint_count, sizeof *post);
    assert_true(skin && pre && post);
    for (uint32_t j = 0; j < m->joint_count; j++) {
        const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, rz[12] = {0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0};
        memcpy(pre[j], id, sizeof id);
        memcpy(post[j], j % 3 == 0 ? rz : id, sizeof id);
    }
    assert_int_equal(psc_render_proxy_pose(m, 0.4, (const double(*)[12])pre, (const double(*)[12])post, skin), 0);
    free(pre), free(post);
    psc_mat4_identity(cam);
    cam->m[2][3] = 4 * PSC_Q16_ONE;
    return skin;
}

/* Joint strips stay attached to both parts they join, however far the pose bends them: every joint proxy corner
 * that sits on a part proxy's vertex at rest sits on it posed (both are cut from one simplified mesh and skinned by
 * its vertices' weights), at the animation's time and bent 90 degrees at every third joint. */
static void test_joints_attached(void **state)
{
    (void)state;
    fixture_t f = {0};
    psc_mat4_q16_t cam, *skin = bar_bent_90(&f, &cam);
    const psc_proxy_model_t *m = &f.m;
    /* the parts' proxies as drawn: their posed vertices, by their rest positions */
    const psc_3d_draw_t *d;
    unsigned nd;
    assert_int_equal(psc_proxy_frame(&f.px, skin, &cam, PSC_PROXY_LOD_PROXIES, false, &d, &nd), PSC_OK);
    uint32_t nv = 0;
    for (uint32_t i = 0; i < m->part_count; i++)
        nv += m->parts[i].kind == PSC_PROXY_KIND_PART ? m->parts[i].proxy_vertex_count : 0;
    int32_t(*rest)[3] = malloc((nv + 1u) * sizeof *rest), (*posed)[3] = malloc((nv + 1u) * sizeof *posed);
    assert_true(rest && posed);
    uint32_t at = 0;
    unsigned k = 0;
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *pr = &m->parts[i];
        if (pr->kind != PSC_PROXY_KIND_PART || pr->proxy_triangle_count == 0)
            continue;
        const psc_mesh_t *mesh = d[k++].mesh;
        assert_false(pr->flags & PSC_PROXY_RIGID);   /* the bar's parts all bend */
        for (uint32_t v = 0; v < pr->proxy_vertex_count; v++, at++)
            for (unsigned a = 0; a < 3; a++) {
                rest[at][a] = m->proxy_position_q16[3u * (pr->first_proxy_vertex + v) + a];
                posed[at][a] = mesh->position_q16[3u * v + a];
            }
    }
    /* the joint strips as drawn (after the parts, as the pack orders them), one draw each */
    unsigned attached = 0;
    double worst = 0;
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *pr = &m->parts[i];
        if (pr->kind != PSC_PROXY_KIND_JOINT || pr->proxy_triangle_count == 0)
            continue;
        assert_true(k < nd);
        const psc_mesh_t *mesh = d[k++].mesh;
        assert_int_equal(mesh->vertex_count, pr->proxy_vertex_count);
        for (uint32_t c = 0; c < pr->proxy_vertex_count; c++) {
            const int32_t *r = &m->proxy_position_q16[3u * (pr->first_proxy_vertex + c)];
            for (uint32_t q = 0; q < at; q++) {
                int64_t d2 = 0;
                for (unsigned a = 0; a < 3; a++)
                    d2 += ((int64_t)r[a] - rest[q][a]) * ((int64_t)r[a] - rest[q][a]);
                if (d2 > (int64_t)66 * 66)   /* within 0.001 R at rest: the same vertex of the simplified mesh */
                    continue;
                double e2 = 0;
                for (unsigned a = 0; a < 3; a++) {
                    double e = (mesh->position_q16[3u * c + a] - posed[q][a]) / 65536.0;
                    e2 += e * e;
                }
                worst = fmax(worst, sqrt(e2));
                attached++;
            }
        }
    }
    print_message("  bent 90 degrees at every third joint: %u joint corners on a part's proxy vertex, %.5f R apart at "
                  "most\n", attached, worst);
    assert_true(attached > 20);
    assert_int_equal(k, nd);   /* a draw per part and per joint strip with a proxy, nothing else */
    assert_true(worst < 0.001);   /* the push (0.0005 R) turned with the surface, and rounding */
    free(rest), free(posed), free(skin);
    fixture_free(&f);
}

/* Splitting a simplified skinned mesh's long edges (skin_split.h), on a flat ribbon 10 long and 1 wide whose skin
 * goes from one bone to another along it, given as the two triangles a simplifier would leave: the pieces still tile
 * the ribbon (the same area, each edge inside it shared by two triangles the other way round, none folded), every
 * vertex added is the middle of two others with the mean of their skins, every edge left is within the rule (or
 * the budget stopped it), and a model without skin, or no budget, leaves the triangles as they were. */
static void test_skin_split(void **state)
{
    (void)state;
    double pos[4 * 3] = {0, 0, 0, 10, 0, 0, 10, 1, 0, 0, 1, 0}, nrm[4 * 3], weight[4][PSC_GLTF_WEIGHTS];
    uint16_t joint[4][PSC_GLTF_WEIGHTS];
    for (unsigned i = 0; i < 4; i++) {
        nrm[3 * i] = 0, nrm[3 * i + 1] = 0, nrm[3 * i + 2] = 1;
        memset(weight[i], 0, sizeof weight[i]);
        memset(joint[i], 0, sizeof joint[i]);
        bool far = pos[3 * i] > 5;   /* bone 1 at x = 10, bone 3 at x = 0 */
        joint[i][0] = far ? 1 : 3, joint[i][1] = far ? 3 : 1;
        weight[i][0] = 1;
    }
    psc_gltf_t g;
    memset(&g, 0, sizeof g);
    g.mesh.pos = pos, g.mesh.normal = nrm, g.mesh.vertex_count = 4;
    g.joint = joint, g.weight = weight, g.joint_count = 4;
    for (int run = 0; run < 4; run++) {
        /* run 0: the rule alone; 1: a budget of 6 triangles; 2: no skin; 3: a budget of 2 (none to spend) */
        uint32_t *idx = malloc(6 * sizeof *idx), *reg = malloc(2 * sizeof *reg), nt = 2;
        const uint32_t start[6] = {0, 1, 2, 0, 2, 3};
        memcpy(idx, start, sizeof start);
        reg[0] = 7, reg[1] = 9;
        g.weight = run == 2 ? NULL : weight;
        uint32_t budget = run == 1 ? 6 : run == 3 ? 2 : 100000;
        psc_bake_skin_vertices_t sv;
        long added = psc_bake_skin_split(&g, 5.0, PSC_BAKE_SKIN_SPLIT_TOL, budget, &idx, &reg, &nt, &sv);
        assert_true(added >= 0 && nt == 2u + (uint32_t)added && nt <= budget);
        if (run >= 2) {
            assert_int_equal(added, 0);
            assert_memory_equal(idx, start, sizeof start);
            assert_null(sv.pos);
            free(idx), free(reg);
            continue;
        }
        assert_true(added > 0 && sv.count > 4);
        assert_memory_equal(sv.pos, pos, sizeof pos);   /* the model's own vertices first, as they were */
        for (uint32_t v = 4; v < sv.count; v++) {   /* each new one the middle of two before it, their skins' mean */
            bool found = false;
            for (uint32_t a = 0; a < v && !found; a++)
                for (uint32_t b = a + 1; b < v && !found; b++) {
                    found = true;
                    for (unsigned k = 0; k < 3; k++)
                        found = found && fabs(sv.pos[3 * v + k] - (sv.pos[3 * a + k] + sv.pos[3 * b + k]) / 2) < 1e-12;
                    for (uint16_t j = 0; j < 4 && found; j++) {
                        double wv = 0, wa = 0, wb = 0;
                        for (unsigned k = 0; k < PSC_GLTF_WEIGHTS; k++) {
                            wv += sv.joint[v][k] == j ? sv.weight[v][k] : 0;
                            wa += sv.joint[a][k] == j ? sv.weight[a][k] : 0;
                            wb += sv.joint[b][k] == j ? sv.weight[b][k] : 0;
                        }
                        found = fabs(wv - (wa + wb) / 2) < 1e-12;
                    }
                }
            assert_true(found);
            assert_true(sv.normal[3 * v + 2] == 1 && sv.weight[v][0] >= sv.weight[v][1]);
        }
        double area = 0, worst = 0;
        unsigned inner = 0;
        for (uint32_t t = 0; t < nt; t++) {
            const uint32_t *v = &idx[3 * t];
            const double *a = &sv.pos[3 * v[0]], *b = &sv.pos[3 * v[1]], *c = &sv.pos[3 * v[2]];
            double z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            assert_true(z > 0);   /* the ribbon's winding, nothing folded or flat */
            area += z / 2;
            assert_true(reg[t] == (t < nt / 2 ? 7u : 9u) || reg[t] == 7 || reg[t] == 9);
            for (unsigned k = 0; k < 3; k++) {
                uint32_t p = v[k], q = v[(k + 1) % 3];
                double len = hypot(sv.pos[3 * p] - sv.pos[3 * q], sv.pos[3 * p + 1] - sv.pos[3 * q + 1]) / 5.0, wp = 0,
                       wq = 0;
                for (unsigned j = 0; j < PSC_GLTF_WEIGHTS; j++)
                    wp += sv.joint[p][j] == 1 ? sv.weight[p][j] : 0, wq += sv.joint[q][j] == 1 ? sv.weight[q][j] : 0;
                worst = fmax(worst, len * 2 * fabs(wp - wq));
                unsigned twins = 0;   /* the edge the other way round, in another triangle */
                for (uint32_t u = 0; u < nt; u++)
                    for (unsigned j = 0; j < 3; j++)
                        twins += idx[3 * u + j] == q && idx[3 * u + (j + 1) % 3] == p;
                const double *pp = &sv.pos[3 * p], *pq = &sv.pos[3 * q];
                bool border = (pp[1] == pq[1] && (pp[1] == 0 || pp[1] == 1)) || (pp[0] == pq[0] && (pp[0] == 0 || pp[0] == 10));
                assert_int_equal(twins, border ? 0u : 1u);
                inner += twins;
            }
        }
        assert_true(fabs(area - 10) < 1e-9);
        print_message("  skin split, run %d: %u triangles, %u vertices (%u inner edges' sides), the worst edge's length x "
                      "skin change %.3f\n", run, nt, sv.count, inner, worst);
        if (run == 0)
            assert_true(worst <= PSC_BAKE_SKIN_SPLIT_TOL);
        psc_bake_skin_vertices_free(&sv);
        free(idx), free(reg);
    }
}

/* A joint strip relit: each of its vertices lit by its own bones (their rotations' transposes on the light, blended
 * as its skin weighs them, made unit), not by one rotation for the whole strip, whose ends follow different bones:
 * against that blend in double, and across a strip of the bar bent 90 degrees the ends' lights part. */
static void test_strip_light(void **state)
{
    (void)state;
    fixture_t f = {0};
    psc_mat4_q16_t cam, *skin = bar_bent_90(&f, &cam);
    const psc_proxy_model_t *m = &f.m;
    const double lm[3] = {0.48, 0.6, 0.64};   /* toward the light, model space, unit */
    const int32_t l[3] = {(int32_t)lround(lm[0] * 65536), (int32_t)lround(lm[1] * 65536), (int32_t)lround(lm[2] * 65536)};
    assert_int_equal(psc_proxy_set_light(&f.px, l, 7373), PSC_OK);
    const psc_3d_draw_t *d;
    unsigned nd;
    assert_int_equal(psc_proxy_frame(&f.px, skin, &cam, PSC_PROXY_LOD_PROXIES, false, &d, &nd), PSC_OK);
    unsigned strips = 0, corners = 0, k = 0;
    double worst = 0, widest = 0;
    for (uint32_t i = 0; i < m->part_count; i++) {
        const psc_proxy_part_raw_t *pr = &m->parts[i];
        if (pr->proxy_triangle_count == 0)
            continue;
        const psc_3d_draw_t *dk = &d[k++];
        if (pr->kind != PSC_PROXY_KIND_JOINT) {
            assert_null(dk->view_light_q14);   /* a part's light is its joint's, one for the draw */
            continue;
        }
        assert_non_null(dk->view_light_q14);
        strips++;
        double lo = 1;   /* the least cosine between two of its vertices' lights */
        for (uint32_t v = 0; v < pr->proxy_vertex_count; v++, corners++) {
            const psc_proxy_skin_raw_t *sk = &m->proxy_skin[pr->first_proxy_vertex + v];
            double b[3] = {0, 0, 0}, len = 0;
            for (unsigned q = 0; q < 4; q++)
                for (unsigned a = 0; a < 3; a++)   /* R^T L: column a of the joint's rotation on the light */
                    b[a] += sk->weight_q15[q] / 32768.0 *
                            (skin[sk->joint[q]].m[0][a] * lm[0] + skin[sk->joint[q]].m[1][a] * lm[1] +
                             skin[sk->joint[q]].m[2][a] * lm[2]) / 65536.0;
            len = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
            for (unsigned a = 0; a < 3; a++)
                worst = fmax(worst, fabs(dk->view_light_q14[3u * v + a] / 16384.0 - b[a] / len));
            for (uint32_t u = 0; u < v; u++) {
                double c = 0;
                for (unsigned a = 0; a < 3; a++)
                    c += dk->view_light_q14[3u * v + a] / 16384.0 * (dk->view_light_q14[3u * u + a] / 16384.0);
                lo = fmin(lo, c);
            }
        }
        widest = fmax(widest, acos(fmax(-1.0, fmin(1.0, lo))) * 180 / M_PI);
    }
    print_message("  bent 90 degrees at every third joint, relit: %u strips' %u vertices each lit by its bones, %.5f off "
                  "their blend in double at most; a strip's ends' lights %.1f degrees apart at most\n",
                  strips, corners, worst, widest);
    assert_true(strips >= 3 && corners > 20);
    assert_true(worst < 0.0005);   /* Q2.14 and the skin's Q16 rounding */
    assert_true(widest > 10 && widest < 100);   /* measured 20.1: the skin blends across the strip, no vertex wholly one bone */
    free(skin);
    fixture_free(&f);
}

/* ---- levels of detail and the device's scene ----------------------------------------------------------- */

/* One frame at level lod seen from orbit (yaw, pitch, dist) on the W x H screen, posed by skin: what the pipeline
 * wrote. */
static psc_3d_stats_t draw_counted(fixture_t *f, const psc_mat4_q16_t *skin, const psc_mat4_q16_t *cam,
                                   const psc_3d_config_t *cfg, psc_proxy_lod_t lod, uint32_t *rgb)
{
    size_t n = psc_3d_workspace_size(cfg);
    void *ws3d;
    assert_int_equal(posix_memalign(&ws3d, 64, n), 0);
    psc_3d_t r;
    assert_int_equal(psc_3d_init(&r, cfg, ws3d, n), PSC_OK);
    const psc_3d_draw_t *d;
    unsigned nd;
    assert_int_equal(psc_proxy_frame(&f->px, skin, cam, lod, false, &d, &nd), PSC_OK);
    psc_surface_t sf = {W, H, W * 4, PSC_PIX_XRGB8888, rgb};
    uint32_t bg = BG;
    psc_3d_stats_t st;
    assert_int_equal(psc_3d_render(&r, d, nd, &bg, &sf, &st), PSC_OK);
    free(ws3d);
    return st;
}

/* --lod auto: the billboard's threshold and its hysteresis, a caller's full-mesh limit, the cost estimate's area
 * against what frames write over random views and poses (after the first frame corrected it), and a model at the
 * crossing of the two costs keeping its level. */
static void test_lod_auto(void **state)
{
    (void)state;
    static const char *const files[2] = {GLTF_DIR "CesiumMilkTruck.gltf", GLTF_DIR "animation_with_skeleton.gltf"};
    uint32_t *rgb = malloc(W * H * 4);
    assert_non_null(rgb);
    for (unsigned mi = 0; mi < 2; mi++) {
        fixture_t f = {0};
        bake(&f, files[mi], 9, 16);
        psc_proxy_set_screen(&f.px, W, H);
        /* the billboard below 40 pixels of radius, left 10 % beyond it; z = 1 R, so the focal length is the radius */
        psc_mat4_q16_t cam;
        psc_mat4_identity(&cam);
        cam.m[2][3] = PSC_Q16_ONE;
        static const struct {
            int32_t r_px;
            bool billboard;
        } steps[] = {{60, false}, {37, false}, {35, true}, {43, true}, {45, false}, {5, true}, {60, false}};
        for (unsigned k = 0; k < sizeof steps / sizeof steps[0]; k++) {
            psc_proxy_lod_t got = psc_proxy_lod_pick(&f.px, &cam, steps[k].r_px * 65536);
            if ((got == PSC_PROXY_LOD_BILLBOARD) != steps[k].billboard)
                print_message("  step %u: radius %d px gave level %d\n", k, steps[k].r_px, got);
            assert_int_equal(got == PSC_PROXY_LOD_BILLBOARD, steps[k].billboard);
        }
        /* the range limits: the camera all but at the centre, far off to a side, or behind; the longest focal length
         * (the sanitizer builds run this too) */
        static const int32_t tz[] = {1, 2, 65536, INT32_MAX, 0, -65536};
        static const int32_t tx[] = {0, INT32_MAX, INT32_MIN, 12345};
        for (unsigned a = 0; a < sizeof tz / sizeof tz[0]; a++)
            for (unsigned b2 = 0; b2 < sizeof tx / sizeof tx[0]; b2++) {
                psc_mat4_q16_t far = cam;
                far.m[2][3] = tz[a];
                far.m[0][3] = far.m[1][3] = tx[b2];
                psc_proxy_cost_t c = psc_proxy_cost(&f.px, &far, INT32_MAX);
                assert_true(c.area_px <= W * H);
                assert_true(c.full >= (uint64_t)PSC_PROXY_COST_FULL_VERTEX * f.m.vertex_count);
                psc_proxy_lod_t l = psc_proxy_lod_pick(&f.px, &far, INT32_MAX);
                assert_true(l == PSC_PROXY_LOD_FULL || l == PSC_PROXY_LOD_PROXIES || l == PSC_PROXY_LOD_BILLBOARD);
            }
        /* the first frame, before any has said what a level writes: the level whose cost against the other's is
         * least at the worse of the gains 1.1 and 1.6 (the rule in double, from psc_proxy_cost at either end), over
         * random views that reach both levels; once a frame has been seen, the cheaper by the estimate */
        unsigned firsts[2] = {0, 0};
        tsup_rng_t frng;
        tsup_rng_seed(&frng, 3u + mi);
        for (unsigned k = 0; k < 200; k++) {
            psc_proxy_init(&f.px, &f.m, f.ws, psc_proxy_workspace_size(&f.m));
            psc_proxy_set_screen(&f.px, W, H);
            psc_mat4_q16_t view;
            psc_3d_config_t cfg = {W, H, 0, 0, 32, tsup_bam_from_deg(50), 0, 0, psc_proxy_max_vertices(&f.m), PSC_3D_HSR_ZBUFFER};
            assert_int_equal(psc_3d_orbit(f.lo, f.hi, tsup_bam_from_deg(tsup_rng_unit(&frng) * 360),
                                          (int32_t)tsup_bam_from_deg(-30 + tsup_rng_unit(&frng) * 90),
                                          (int32_t)lround((1.2 + tsup_rng_unit(&frng) * 8.8) * 65536), &view,
                                          &cfg.near_q16, &cfg.far_q16),
                             PSC_OK);
            int32_t focal = (int32_t)(psc_proxy_focal_px_q16(W, cfg.hfov) * (0.5 + tsup_rng_unit(&frng) * 1.5));
            psc_proxy_t lo = f.px, hi = f.px;
            lo.area_gain_q8 = lo.proxy_gain_q8 = 282, hi.area_gain_q8 = hi.proxy_gain_q8 = 410;
            psc_proxy_cost_t cl = psc_proxy_cost(&lo, &view, focal), ch = psc_proxy_cost(&hi, &view, focal);
            double worse_p = fmax((double)cl.proxies / cl.full, (double)ch.proxies / ch.full);
            double worse_f = fmax((double)cl.full / cl.proxies, (double)ch.full / ch.proxies);
            psc_proxy_lod_t l = psc_proxy_lod_pick(&f.px, &view, focal);
            if (l == PSC_PROXY_LOD_BILLBOARD)
                continue;
            if (fabs(log(worse_p / worse_f)) > 1e-3)   /* (a tie within the integer rule's rounding either way) */
                assert_int_equal(l, worse_p <= worse_f ? PSC_PROXY_LOD_PROXIES : PSC_PROXY_LOD_FULL);
            firsts[l == PSC_PROXY_LOD_FULL]++;
            /* a frame seen: the estimate's cheaper, the other only 5 % cheaper */
            f.px.gains_seen = 3;
            psc_proxy_cost_t c = psc_proxy_cost(&f.px, &view, focal);
            psc_proxy_lod_t was = f.px.lod, now = psc_proxy_lod_pick(&f.px, &view, focal);
            uint64_t keep = was == PSC_PROXY_LOD_FULL ? c.full : c.proxies, other = was == PSC_PROXY_LOD_FULL ? c.proxies : c.full;
            assert_int_equal(now, other < keep - keep / 20 ? (was == PSC_PROXY_LOD_FULL ? PSC_PROXY_LOD_PROXIES : PSC_PROXY_LOD_FULL) : was);
        }
        print_message("  first frames of 200 random views: %u proxies, %u full mesh\n", firsts[0], firsts[1]);
        assert_true(firsts[0] >= 8 && firsts[1] >= 8);   /* both levels reached */
        psc_proxy_init(&f.px, &f.m, f.ws, psc_proxy_workspace_size(&f.m));
        psc_proxy_set_screen(&f.px, W, H);
        f.px.lod = PSC_PROXY_LOD_PROXIES;
        /* a caller's limit: the full mesh beyond it whatever it costs; 0 (psc_proxy_init's): by the costs alone */
        assert_int_equal(f.px.full_px, 0);
        f.px.full_px = 200;
        assert_int_equal(psc_proxy_lod_pick(&f.px, &cam, 221 * 65536), PSC_PROXY_LOD_FULL);
        f.px.full_px = 0;

        /* the area estimated against the pixels frames write, and the level picked from it against the one the cost
         * model picks from the pixels both levels wrote: along a camera wandering as a visitor's stick moves it (the
         * view a few degrees a frame, zooming from 7.8 R to 1.8 R and back, the animation playing) the area's error must not
         * make the choice more than 10 % dearer; with every frame a random view, distance and pose of its own (the
         * estimate learning from a frame unlike the next), not more than 25 % */
        psc_mat4_q16_t *skin = malloc(f.m.joint_count * sizeof *skin);
        assert_non_null(skin);
        for (int walk = 1; walk >= 0; walk--) {
            tsup_rng_t rng;
            tsup_rng_seed(&rng, 77u + mi);
            double worst_area = 1.0, worst_cost = 1.0, sum_log = 0;
            double yaw = 30, pitch = 15, dist = 0, t = 0;
            unsigned n = 0, levels[3] = {0, 0, 0};
            psc_proxy_init(&f.px, &f.m, f.ws, psc_proxy_workspace_size(&f.m));   /* nothing learnt yet */
            psc_proxy_set_screen(&f.px, W, H);
            for (unsigned k = 0; k < 60; k++) {
                if (walk) {
                    yaw += tsup_rng_range(&rng, -8, 8);
                    pitch = fmin(60, fmax(-30, pitch + tsup_rng_range(&rng, -4, 4)));
                    dist = 4.8 - 3.0 * cos(2 * M_PI * k / 60.0);   /* zooming in and out: through both levels */
                    t += 1.0 / 30;
                } else {
                    yaw = tsup_rng_unit(&rng) * 360.0, pitch = -30 + tsup_rng_unit(&rng) * 90.0;
                    dist = 1.8 + tsup_rng_unit(&rng) * 6.0;
                    t = tsup_rng_unit(&rng) * (double)psc_proxy_duration_us(&f.m) / 1e6;
                }
                psc_3d_config_t cfg = {W, H, 0, 0, 32, tsup_bam_from_deg(50), 0, 0, psc_proxy_max_vertices(&f.m), PSC_3D_HSR_ZBUFFER};
                assert_int_equal(psc_3d_orbit(f.lo, f.hi, tsup_bam_from_deg(yaw), (int32_t)tsup_bam_from_deg(pitch),
                                              (int32_t)lround(dist * 65536), &cam, &cfg.near_q16, &cfg.far_q16),
                                 PSC_OK);
                int32_t focal = psc_proxy_focal_px_q16(W, cfg.hfov);
                psc_proxy_pose_at(&f.m, (int64_t)(t * 1e6), skin);
                psc_proxy_cost_t c = psc_proxy_cost(&f.px, &cam, focal);
                psc_proxy_lod_t lod = psc_proxy_lod_pick(&f.px, &cam, focal);
                levels[lod]++;
                if (lod == PSC_PROXY_LOD_BILLBOARD)
                    continue;
                /* both levels drawn: the one picked tells the estimate what it wrote */
                psc_3d_stats_t st = draw_counted(&f, skin, &cam, &cfg, lod, rgb);
                psc_3d_stats_t other = draw_counted(&f, skin, &cam, &cfg,
                                                    lod == PSC_PROXY_LOD_FULL ? PSC_PROXY_LOD_PROXIES : PSC_PROXY_LOD_FULL,
                                                    rgb);
                if (k > 0 && st.pixels > 0) {   /* the first frame is the one that corrects it */
                    double ratio = c.area_px / (double)st.pixels;
                    double pf = (double)(lod == PSC_PROXY_LOD_FULL ? st.pixels : other.pixels);
                    double pp = (double)(lod == PSC_PROXY_LOD_FULL ? other.pixels : st.pixels);
                    double full = PSC_PROXY_COST_FULL_VERTEX * (double)f.m.vertex_count +
                                  PSC_PROXY_COST_FULL_BLEND * (double)f.px.blended_vertices +
                                  PSC_PROXY_COST_FULL_TRIANGLE * (double)f.m.triangle_count +
                                  PSC_PROXY_COST_FULL_ROW * sqrt(pf * f.m.triangle_count / 2);
                    double prox = PSC_PROXY_COST_VERTEX * (double)f.m.proxy_vertex_count +
                                  PSC_PROXY_COST_TRIANGLE * (double)f.m.proxy_triangle_count +
                                  PSC_PROXY_COST_ROW * sqrt(pp * f.m.proxy_triangle_count / 2) +
                                  PSC_PROXY_COST_PIXEL * pp;
                    double picked = lod == PSC_PROXY_LOD_FULL ? full : prox;
                    if (st.pixels >= 500) {   /* (a few hundred pixels of a thin bar are mostly its edges) */
                        worst_area = fmax(worst_area, fmax(ratio, 1 / ratio));
                        sum_log += log(ratio);
                        n++;
                    }
                    worst_cost = fmax(worst_cost, picked / fmin(full, prox));
                }
                psc_proxy_observe(&f.px, &st);
            }
            print_message("  %s, %s: %u proxies, %u full mesh, %u billboard; the estimated area against the pixels "
                          "written: within a factor %.2f (%u frames of 500 pixels or more), %.3f on average; the level "
                          "picked at most %.3fx the cheaper by the cost model on the pixels written\n",
                          files[mi], walk ? "60 frames of a wandering camera" : "60 random views and poses",
                          levels[PSC_PROXY_LOD_PROXIES], levels[PSC_PROXY_LOD_FULL], levels[PSC_PROXY_LOD_BILLBOARD],
                          worst_area, n, exp(sum_log / n), worst_cost);
            /* the truck within 1.5 (1.33 measured jumping), 15 % on average; the bar, bending and 8 pixels thick at
             * 7 R, within 2.5 (2.30) and 35 % (0.767; 0.811 before the views' edges were filtered: its rest billboard's
             * silhouette is not its bent pose's) */
            assert_true(n >= 10);
            assert_true(worst_area <= (mi == 0 ? 1.5 : 2.5));
            assert_true(fabs(sum_log / n) <= log(mi == 0 ? 1.15 : 1.35));
            /* (walking in from the full mesh's side, the truck's proxies write 7 % fewer pixels than its full mesh
             * before any frame of theirs has shown it: 1.112 once, at the crossing) */
            assert_true(worst_cost <= (walk ? 1.12 : 1.25));
        }

        /* at the crossing of the two estimates the level holds: the radius swept 2 % either way keeps it */
        psc_mat4_identity(&cam);
        cam.m[2][3] = PSC_Q16_ONE;
        int32_t cross = 0;
        for (int32_t r = 45; r < 2000 && cross == 0; r++) {
            psc_proxy_cost_t c = psc_proxy_cost(&f.px, &cam, r * 65536);
            if (c.full <= c.proxies)
                cross = r;
        }
        if (cross != 0) {
            unsigned changes = 0;
            psc_proxy_lod_t was = psc_proxy_lod_pick(&f.px, &cam, cross * 65536);
            for (unsigned k = 0; k < 20; k++) {
                psc_proxy_lod_t l = psc_proxy_lod_pick(&f.px, &cam, (k & 1 ? cross * 102 / 100 : cross * 98 / 100) * 65536);
                changes += l != was;
                was = l;
            }
            print_message("  the costs cross at a radius of %d px: %u changes of level as it moves 2 %% either way 20 "
                          "times\n", cross, changes);
            assert_true(changes <= 1);
            /* well past the crossing either way, each level is the estimate's cheaper */
            assert_int_equal(psc_proxy_lod_pick(&f.px, &cam, cross * 3 / 2 * 65536), PSC_PROXY_LOD_FULL);
            if (cross * 2 / 3 > 50)
                assert_int_equal(psc_proxy_lod_pick(&f.px, &cam, cross * 2 / 3 * 65536), PSC_PROXY_LOD_PROXIES);
        } else {
            print_message("  the proxies stay the cheaper up to a radius of 2000 px\n");
        }
        free(skin);
        fixture_free(&f);
    }
    free(rgb);
}

static void test_scene_draw(void **state)
{
    (void)state;
    fixture_t f = {0};
    bake(&f, GLTF_DIR "animation_with_skeleton.gltf", 9, 16);
    size_t n = psc_scene_proxy_workspace_size(&f.m, 160, 120, NULL);
    void *ws;
    assert_int_equal(posix_memalign(&ws, 64, n), 0);
    static uint16_t px[160 * 120];
    psc_surface_t sf = {160, 120, 320, PSC_PIX_RGB565, px};
    psc_view_t v = {0};
    v.yaw = tsup_bam_from_deg(30), v.pitch = (int32_t)tsup_bam_from_deg(20), v.hfov = tsup_bam_from_deg(50);
    uint16_t bg = psc_xrgb_to_rgb565(BG);
    unsigned seen[3] = {0, 0, 0};
    for (unsigned k = 0; k < 40; k++) {   /* zooming out as it plays: full, then proxies, then the billboard */
        psc_proxy_lod_t lod;
        v.hfov = tsup_bam_from_deg(15 + 2.2 * k);   /* the object scenes' zoom range, 15..100 degrees */
        assert_int_equal(psc_scene_proxy_draw(&f.m, k * 33333u, &v, k == 0, ws, n, &sf, &lod, NULL), PSC_OK);
        seen[lod]++;
        unsigned drawn = 0;
        for (unsigned i = 0; i < 160 * 120; i++)
            drawn += px[i] != bg;
        if (drawn <= 20)
            print_message("  frame %u (level %d): %u pixels drawn\n", k, lod, drawn);
        assert_true(drawn > 20);
    }
    print_message("  the scene, zooming out: %u frames full, %u proxies, %u billboard\n", seen[PSC_PROXY_LOD_FULL],
                  seen[PSC_PROXY_LOD_PROXIES], seen[PSC_PROXY_LOD_BILLBOARD]);
    /* (the bar's proxies cost less than its mesh at every size on this display, and it stays over the billboard's
     * 8 % of the height) */
    assert_true(seen[PSC_PROXY_LOD_PROXIES] > 0);
    assert_int_equal(psc_scene_proxy_draw(&f.m, 0, &v, true, ws, n - 1, &sf, NULL, NULL), PSC_ERR_NOMEM);
    /* the board's light (render3d_relight): a light from the side changes the frame; turning at 36 degrees a second
     * it is back where it started after 10 s, the same direction to the bit; as baked it is the default */
    psc_scene3d_look_t look = psc_scene3d_look(NULL);   /* the defaults: soft silhouettes */
    look.relight = true, look.light_azimuth_mdeg = -90000, look.light_elevation_mdeg = 10000;
    look.light_ambient_q14 = 7373, look.light_turn_mdeg = 36000;
    static uint16_t a[160 * 120], b[160 * 120];
    v.hfov = tsup_bam_from_deg(60);
    psc_surface_t sa = {160, 120, 320, PSC_PIX_RGB565, a};
    assert_int_equal(psc_scene_proxy_draw(&f.m, 0, &v, true, ws, n, &sf, NULL, NULL), PSC_OK);
    assert_int_equal(psc_scene_proxy_draw(&f.m, 0, &v, false, ws, n, &sa, NULL, &look), PSC_OK);
    assert_memory_not_equal(px, a, sizeof a);
    int32_t l0[3], l1[3], l2[3];
    psc_scene3d_light_at(&look, 0, l0);
    psc_scene3d_light_at(&look, 10000000, l1);
    psc_scene3d_light_at(&look, 2500000, l2);
    assert_memory_equal(l0, l1, sizeof l0);
    assert_true(l0[0] < -60000 && abs(l0[2]) < 100 && l2[2] > 60000);   /* -90 degrees (toward -x), then 0 (+z) */
    psc_surface_t sb = {160, 120, 320, PSC_PIX_RGB565, b};
    assert_int_equal(psc_scene_proxy_draw(&f.m, 2500000, &v, false, ws, n, &sb, NULL, &look), PSC_OK);
    look.light_turn_mdeg = 0;
    assert_int_equal(psc_scene_proxy_draw(&f.m, 2500000, &v, false, ws, n, &sa, NULL, &look), PSC_OK);
    assert_memory_not_equal(a, b, sizeof a);   /* the turn, not the pose alone */
    look.relight = false;
    assert_int_equal(psc_scene_proxy_draw(&f.m, 0, &v, false, ws, n, &sa, NULL, &look), PSC_OK);
    assert_memory_equal(px, a, sizeof a);
    /* render3d_soft_edges = no: the silhouettes alpha-tested, every pixel the background or a part's colour */
    look.soft_edges = false;
    assert_int_equal(psc_scene_proxy_draw(&f.m, 0, &v, false, ws, n, &sa, NULL, &look), PSC_OK);
    unsigned changed = 0;
    for (unsigned i = 0; i < 160 * 120; i++)
        changed += px[i] != a[i];
    print_message("  render3d_soft_edges = no: %u pixels of the silhouettes changed\n", changed);
    assert_true(changed > 20);
    free(ws);
    /* on two threads (render_threads): the same bytes */
    char err[256];
    psc_scene3d_look_t threaded = psc_scene3d_look(NULL);
    threaded.pool = psc_io_bands_start(2, 160, err, sizeof err);
    assert_non_null(threaded.pool);
    size_t tn = psc_scene_proxy_workspace_size(&f.m, 160, 120, &threaded);
    assert_int_equal(posix_memalign(&ws, 64, tn), 0);
    assert_int_equal(psc_scene_proxy_draw(&f.m, 0, &v, true, ws, tn, &sa, NULL, &threaded), PSC_OK);
    assert_memory_equal(px, a, sizeof a);
    free(ws);
    psc_io_bands_stop(threaded.pool);
    fixture_free(&f);
}

/* The hidden-surface method render_lod draws with. */
static uint8_t render_hsr = PSC_3D_HSR_ZBUFFER;

/* One frame of the bar at level lod into px (W x H RGB565): tiles or not, the A-buffer or not, or the part ids. */
static void render_lod(fixture_t *f, const psc_mat4_q16_t *skin, int lod, bool tiled, bool aa, bool ids,
                       uint16_t *px)
{
    psc_mat4_q16_t cam;
    psc_3d_config_t cfg = {W, H, tiled ? 32 : 0, tiled ? 32 : 0, 16, tsup_bam_from_deg(50), 0, 0,
                           psc_proxy_max_vertices(&f->m), render_hsr};
    assert_int_equal(psc_3d_orbit(f->lo, f->hi, tsup_bam_from_deg(75), (int32_t)tsup_bam_from_deg(30),
                                  lod == 2 ? 5 * 65536 : 144179, &cam, &cfg.near_q16, &cfg.far_q16),
                     PSC_OK);
    size_t n = psc_3d_workspace_size(&cfg), nb = psc_3d_abuffer_bytes(&cfg, 8192);
    void *ws, *abuf;
    assert_int_equal(posix_memalign(&ws, 64, n), 0);
    assert_int_equal(posix_memalign(&abuf, 64, nb), 0);
    psc_3d_t r;
    assert_int_equal(psc_3d_init(&r, &cfg, ws, n), PSC_OK);
    if (aa)
        assert_int_equal(psc_3d_set_abuffer(&r, abuf, nb), PSC_OK);
    const psc_3d_draw_t *d;
    unsigned nd;
    assert_int_equal(psc_proxy_frame(&f->px, skin, &cam, (psc_proxy_lod_t)lod, ids, &d, &nd), PSC_OK);
    static psc_3d_draw_t by_draw[8192];
    if (ids) {   /* each draw its own colour: a joint's triangles are draws of their own, with views of their own */
        assert_true(nd <= 8192);
        for (unsigned k = 0; k < nd; k++) {
            by_draw[k] = d[k];
            by_draw[k].color = k + 1u;
        }
        d = by_draw;
    }
    psc_surface_t sf = {W, H, W * 2, PSC_PIX_RGB565, px};
    uint32_t bg = BG;
    psc_3d_stats_t st;
    assert_int_equal(psc_3d_render(&r, d, nd, &bg, &sf, &st), PSC_OK);
    assert_int_equal(st.fragments_overflow, 0);
    free(ws);
    free(abuf);
}

/* Whether pixel (x, y) lies within 2 pixels of a change of value in px. */
static bool near_change(const uint16_t *px, int x, int y)
{
    for (int j = -2; j <= 2; j++)
        for (int i = -2; i <= 2; i++) {
            int xx = x + i, yy = y + j;
            if (xx < 0 || yy < 0 || xx >= (int)W || yy >= (int)H)
                continue;
            if ((xx + 1 < (int)W && px[yy * (int)W + xx] != px[yy * (int)W + xx + 1]) ||
                (yy + 1 < (int)H && px[yy * (int)W + xx] != px[(yy + 1) * (int)W + xx]))
                return true;
        }
    return false;
}

/* Tiles change nothing: proxies, full mesh and billboard in 32 x 32 tiles give the full-buffer frame's bytes, with
 * the A-buffer too (its view textures' coverage turned into samples, alpha to coverage), and the soft silhouettes
 * (each tile's coverage plane) without it. The A-buffer changes the frame near edges: within 2 pixels of where the
 * draw (or background) a pixel shows changes, by the draws' ids without it; beyond, by two RGB565 steps at most
 * (inside a part, where two of its triangles meet, their texels averaged), but for at most 2 pixels in 100 drawn:
 * this coarse pack's 9 views leave the bar's bend in slivers, where the A-buffer and the soft silhouettes each give
 * faint pixels a little further out. */
static void test_tiles_exact(void **state)
{
    (void)state;
    fixture_t f = {0};
    bake(&f, GLTF_DIR "animation_with_skeleton.gltf", 9, 32);
    psc_mat4_q16_t *skin = malloc(f.m.joint_count * sizeof *skin);
    assert_non_null(skin);
    psc_proxy_pose_at(&f.m, 370000, skin);
    static uint16_t plain[W * H], aa[W * H], tiled[W * H], ids[W * H];
    for (int lod = 0; lod < 3; lod++) {
        render_lod(&f, skin, lod, false, false, false, plain);
        render_lod(&f, skin, lod, true, false, false, tiled);
        assert_memory_equal(plain, tiled, sizeof plain);
        render_lod(&f, skin, lod, false, true, false, aa);
        render_lod(&f, skin, lod, true, true, false, tiled);
        assert_memory_equal(aa, tiled, sizeof aa);
        render_hsr = PSC_3D_HSR_AREA; /* area subdivision: the same bytes (view textures are never hidden early) */
        render_lod(&f, skin, lod, false, false, false, tiled);
        assert_memory_equal(plain, tiled, sizeof plain);
        render_lod(&f, skin, lod, true, false, false, tiled);
        assert_memory_equal(plain, tiled, sizeof plain);
        render_hsr = PSC_3D_HSR_ZBUFFER;
        render_lod(&f, skin, lod, false, false, true, ids);
        unsigned drawn = 0, changed = 0, far = 0;
        for (int y = 0; y < (int)H; y++)
            for (int x = 0; x < (int)W; x++) {
                drawn += plain[y * (int)W + x] != psc_xrgb_to_rgb565(BG);
                if (plain[y * (int)W + x] == aa[y * (int)W + x])
                    continue;
                changed++;
                int p = plain[y * (int)W + x], q = aa[y * (int)W + x];
                bool faint = abs((p >> 11) - (q >> 11)) <= 2 && abs((p >> 5 & 63) - (q >> 5 & 63)) <= 2 &&
                             abs((p & 31) - (q & 31)) <= 2;
                if (!faint && !near_change(ids, x, y) && far++ < 3)
                    print_message("  level %d: the A-buffer changed pixel (%d, %d) from %04X to %04X, away from the "
                                  "edges\n", lod, x, y, (unsigned)p, (unsigned)q);
            }
        print_message("  level %d: %u pixels drawn, tiled and full-buffer alike, by area subdivision too, with the "
                      "A-buffer too; it changed %u, %u away from the edges\n", lod, drawn, changed, far);
        assert_true(far * 50u <= drawn);   /* measured 22 of 1629 at level 0 (its soft silhouettes drawn), none at the others */
        /* (the billboard: one view, its texels sampled whole or not at all, on a quad wider than the model) */
        assert_true(drawn > 100 && (changed > 20 || lod == 2));
    }
    free(skin);
    fixture_free(&f);
}

/* Mutated and truncated model files: refused by the importer with the file named, or baked into a pack that parses. */
static void test_model_fuzz(void **state)
{
    (void)state;
    size_t n;
    char *orig = (char *)tsup_read_bytes(GLTF_DIR "animation_with_skeleton.gltf", &n), *buf = malloc(n);
    assert_true(orig && buf);
    char path[] = "/tmp/periscope-proxy-fuzz-XXXXXX.gltf";
    int fd = mkstemps(path, 5);
    assert_true(fd >= 0);
    close(fd);
    tsup_rng_t r;
    tsup_rng_seed(&r, 29);
    unsigned refused = 0, baked = 0;
    for (unsigned round = 0; round < 24; round++) {
        memcpy(buf, orig, n);
        size_t len = n;
        if (round % 3 == 0)
            len = tsup_rng_below(&r, (uint32_t)n);   /* truncated */
        else
            for (unsigned k = 0; k < 1u + round % 5u; k++)   /* bytes changed, in the JSON or the data */
                buf[tsup_rng_below(&r, (uint32_t)n)] = (char)tsup_rng_u32(&r);
        FILE *fp = fopen(path, "wb");
        assert_non_null(fp);
        assert_true(fwrite(buf, 1, len, fp) == len);
        fclose(fp);
        psc_gltf_t g;
        char err[512], note[256] = "";
        if (psc_gltf_load(path, &g, note, sizeof note, err, sizeof err) != 0) {
            assert_non_null(strstr(err, path));
            refused++;
            continue;
        }
        psc_bake_proxy_opts_t o = {9, 8, 0, 0, 0, false};
        uint8_t *pack = NULL;
        size_t plen = 0;
        if (psc_bake_proxy(&g, &o, path, &pack, &plen, note, sizeof note, err, sizeof err) == 0) {
            void *al;
            assert_int_equal(posix_memalign(&al, 64, plen), 0);
            memcpy(al, pack, plen);
            psc_proxy_model_t m;
            psc_container_error_t e = {0};
            assert_int_equal(psc_proxy_parse(al, plen, &m, &e), PSC_OK);
            free(al);
            baked++;
        } else {
            assert_non_null(strstr(err, path));
            refused++;
        }
        free(pack);
        psc_gltf_free(&g);
    }
    print_message("  24 mutated or truncated glTF files: %u refused with a message, %u baked into packs that parse\n",
                  refused, baked);
    assert_true(refused > 0 && baked > 0);
    remove(path);
    free(orig), free(buf);
}

/* ---- fuzzing ------------------------------------------------------------------------------------- */

/* A pack's normals (1.3) and depth offsets (1.4) come with XINF's flags or not at all: a flag without its sections,
 * or sections without the flag, are refused with a message; a pack of an earlier layout parses; --no-normals bakes
 * no normals, which draws as baked and refuses a light. */
static void test_normals_sections(void **state)
{
    (void)state;
    fixture_t f = {0};
    bake(&f, GLTF_DIR "animation_with_skeleton.gltf", 9, 8);
    assert_non_null(f.m.vertex_normals);
    assert_non_null(f.m.tex_normals);
    assert_non_null(f.m.bb_normals);
    assert_int_equal(f.m.normal_shift, 0);   /* (1.5) at the textures' side */
    psc_container_t c;
    psc_container_error_t e = {NULL, 0};
    assert_int_equal(psc_container_open(f.pack, f.len, &psc_proxy_format, &c, &e), PSC_OK);
    static const uint32_t types[4] = {PSC_SECTION_PROXY_INFO, PSC_SECTION_PROXY_VNORMALS, PSC_SECTION_PROXY_TEX_NORMALS,
                                      PSC_SECTION_PROXY_BB_NORMALS};
    psc_section_t sec[4];
    bool present[4];
    assert_int_equal(psc_container_collect(&c, types, 4, sec, present, &e), PSC_OK);
    assert_true(present[0] && present[1] && present[2] && present[3]);
    for (unsigned k = 0; k < 6; k++) {   /* k 0: the flag cleared; 1..3: a section renamed away; 4: the
                                           * 1.5 flag cleared (XTNM four times the size then expected); 5: that flag
                                           * alone, without normals */
        uint8_t *b;
        assert_int_equal(posix_memalign((void **)&b, 64, f.len), 0);
        memcpy(b, f.pack, f.len);
        uint8_t *flags = &b[sec[0].offset + offsetof(psc_proxy_info_raw_t, flags)];
        if (k == 0 || k == 5)
            *flags &= (uint8_t)~PSC_PROXY_NORMALS;
        else if (k == 4)
            *flags &= (uint8_t)~PSC_PROXY_NORMALS_FULL;
        else
            b[sec[k].entry] = 'Z';   /* its type's first letter: an unknown section, skipped */
        if (k == 5)   /* the normals' sections renamed away too */
            for (unsigned s = 1; s < 4; s++)
                b[sec[s].entry] = 'Z';
        tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, 0);
        tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, b, f.len));
        psc_proxy_model_t m;
        e = (psc_container_error_t){NULL, 0};
        assert_int_equal(psc_proxy_parse(b, f.len, &m, &e), PSC_ERR_CORRUPT);
        assert_non_null(e.what);
        print_message("  normals %s: %s\n",
                      k == 0 ? "without the flag" : k == 4 ? "of 1.5 in a 1.4 pack" : k == 5 ? "1.5's flag alone"
                                                                                        : "flag without a section",
                      e.what);
        free(b);
    }
    /* the depth offsets (1.4) the same way; both taken away, the 1.3 layout: drawn at the proxies' own depth */
    static const uint32_t dtypes[2] = {PSC_SECTION_PROXY_INFO, PSC_SECTION_PROXY_TEX_DEPTH};
    assert_int_equal(psc_container_collect(&c, dtypes, 2, sec, present, &e), PSC_OK);
    assert_true(present[0] && present[1]);
    for (unsigned k = 0; k < 3; k++) {   /* 0: the flag cleared; 1: the section renamed away; 2: both */
        uint8_t *b;
        assert_int_equal(posix_memalign((void **)&b, 64, f.len), 0);
        memcpy(b, f.pack, f.len);
        if (k != 1)
            b[sec[0].offset + offsetof(psc_proxy_info_raw_t, flags)] &= (uint8_t)~PSC_PROXY_DEPTH;
        if (k != 0)
            b[sec[1].entry] = 'Z';
        tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, 0);
        tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, b, f.len));
        psc_proxy_model_t m;
        e = (psc_container_error_t){NULL, 0};
        psc_status_t st = psc_proxy_parse(b, f.len, &m, &e);
        if (k < 2) {
            assert_int_equal(st, PSC_ERR_CORRUPT);
            print_message("  depth offsets %s: %s\n", k == 0 ? "without the flag" : "flag without the section", e.what);
        } else {
            assert_int_equal(st, PSC_OK);
            assert_null(m.tex_depth);
        }
        free(b);
    }
    fixture_free(&f);
    {   /* a 1.2 pack of an earlier build (the fuzz corpus' seed) still parses */
        size_t n;
        uint8_t *b = tsup_read_bytes("tests/fuzz/corpus/proxy/two-cubes-atlas.ppx", &n);   /* (malloc: aligned) */
        assert_non_null(b);
        psc_proxy_model_t m;
        assert_int_equal(psc_proxy_parse(b, n, &m, NULL), PSC_OK);
        assert_true(m.atlas && !m.tex_normals && !m.tex_depth);
        free(b);
    }
    {   /* a 1.4 pack (its normals at half their textures' side: the corpus' seed) parses and draws relit: another
         * light changes its pixels, none of them outside its silhouette as baked */
        fixture_t old = {0};
        old.pack = tsup_read_bytes("tests/fuzz/corpus/proxy/cross-depth.ppx", &old.len);
        assert_non_null(old.pack);
        fixture_ready(&old);
        assert_true(old.m.tex_normals && old.m.normal_shift == 1);
        psc_mat4_q16_t *skin = malloc(old.m.joint_count * sizeof *skin);
        assert_non_null(skin);
        psc_proxy_pose_at(&old.m, -1, skin);
        static uint32_t rgb[2][W * H], ids[2][W * H];
        static const light_t side = {-90, 10, 0.45};
        for (unsigned k = 0; k < 2; k++) {
            frame_light = k ? &side : NULL;
            render(&old, skin, 30, 20, 3, PSC_PROXY_LOD_PROXIES, rgb[k], ids[k]);
        }
        frame_light = NULL;
        unsigned drawn = 0, changed = 0;
        for (unsigned i = 0; i < W * H; i++) {
            drawn += (ids[0][i] & 0xFFFFu) != 0;
            changed += rgb[0][i] != rgb[1][i];
            assert_int_equal(ids[0][i], ids[1][i]);
        }
        print_message("  a 1.4 pack relit: %u of its %u pixels changed\n", changed, drawn);
        assert_true(drawn > 1000 && changed > drawn / 4);
        free(skin);
        fixture_free(&old);
    }
    /* --no-normals: no normals */
    psc_gltf_t g;
    char note[256], err[512];
    assert_int_equal(psc_gltf_load(GLTF_DIR "animation_with_skeleton.gltf", &g, note, sizeof note, err, sizeof err), 0);
    psc_bake_proxy_opts_t o = {9, 8, 0, 0, 0, true};
    uint8_t *bytes;
    size_t len;
    assert_int_equal(psc_bake_proxy(&g, &o, "skeleton", &bytes, &len, note, sizeof note, err, sizeof err), 0);
    psc_gltf_free(&g);
    uint8_t *b;
    assert_int_equal(posix_memalign((void **)&b, 64, len), 0);
    memcpy(b, bytes, len);
    free(bytes);
    psc_proxy_model_t m;
    assert_int_equal(psc_proxy_parse(b, len, &m, NULL), PSC_OK);
    assert_null(m.vertex_normals);
    assert_null(m.tex_normals);
    size_t wn = psc_proxy_workspace_size(&m);
    void *ws;
    assert_int_equal(posix_memalign(&ws, 64, wn), 0);
    psc_proxy_t p;
    assert_int_equal(psc_proxy_init(&p, &m, ws, wn), PSC_OK);
    const int32_t l[3] = {0, 65536, 0};
    assert_int_equal(psc_proxy_set_light(&p, l, 7373), PSC_ERR_UNSUPPORTED);
    assert_int_equal(psc_proxy_set_light(&p, NULL, 0), PSC_OK);
    free(ws), free(b);
    /* the rasterizer refuses a relit state whose normal texture is not usable (no pixels, a side not a power of
     * two), drawing nothing rather than reading it */
    static uint16_t tex[16 * 16], nrm[8 * 8], px[32 * 32];
    for (unsigned i = 0; i < 16 * 16; i++)
        tex[i] = 0x7BEFu;
    psc_texture_t vt, nt_ok, nt_bad = {6, 8, 0, 3, PSC_PIX_RGB565, 12, nrm}, nt_null;
    assert_int_equal(psc_texture_init(&vt, 16, 16, PSC_PIX_RGB565, 32, tex), PSC_OK);
    assert_int_equal(psc_texture_init(&nt_ok, 8, 8, PSC_PIX_RGB565, 16, nrm), PSC_OK);
    nt_null = nt_ok;
    nt_null.pixels = NULL;
    psc_surface_t sf = {32, 32, 64, PSC_PIX_RGB565, px};
    psc_raster_target_t t = {&sf, NULL, 0, 0, 0, 0, 32, 32, NULL, NULL, 0, NULL, 0, 0};
    psc_raster_vertex_t v[3] = {{.x_q4 = 16, .y_q4 = 16, .q_q28 = PSC_RASTER_Q_ONE},
                                {.x_q4 = 500, .y_q4 = 16, .q_q28 = PSC_RASTER_Q_ONE, .u1_q16 = 65536, .u2_q16 = 65536,
                                 .u_q16 = 65536},
                                {.x_q4 = 16, .y_q4 = 500, .q_q28 = PSC_RASTER_Q_ONE, .v_q16 = 65536, .v1_q16 = 65536,
                                 .v2_q16 = 65536}};
    const psc_texture_t *cases[3] = {&nt_ok, &nt_null, &nt_bad};
    for (unsigned k = 0; k < 3; k++) {
        psc_raster_state_t st = {.shade = PSC_SHADE_VIEWS, .view_tex = {&vt, &vt, &vt}, .view_w_q8 = {128, 64, 64},
                                 .view_normals = {cases[k], cases[k], cases[k]},
                                 .view_light = {{0, 16384, 0}, 4096}, .view_bake_light = {{0, 0, 16384}, 7373}};
        uint32_t drawn = psc_raster_triangle(&t, &st, &v[0], &v[1], &v[2]);
        assert_true(k == 0 ? drawn > 100 : drawn == 0);
    }
}

static void test_pack_fuzz(void **state)
{
    (void)state;
    fixture_t f = {0};
    bake(&f, GLTF_DIR "animation_with_skeleton.gltf", 9, 8);
    tsup_rng_t r;
    tsup_rng_seed(&r, 13);
    unsigned parsed = 0, refused = 0;
    static uint32_t px[64 * 48];
    for (unsigned k = 0; k < 3000; k++) {
        size_t n = f.len;
        uint8_t *b;
        assert_int_equal(posix_memalign((void **)&b, 64, n), 0);
        memcpy(b, f.pack, n);
        unsigned muts = 1 + tsup_rng_below(&r, 4);
        for (unsigned j = 0; j < muts; j++) {
            size_t at = tsup_rng_below(&r, (uint32_t)n);
            switch (tsup_rng_below(&r, 4)) {
            case 0: b[at] ^= (uint8_t)(1u << tsup_rng_below(&r, 8)); break;
            case 1: b[at] = (uint8_t)tsup_rng_u32(&r); break;
            case 2: b[tsup_rng_below(&r, 1600)] = (uint8_t)tsup_rng_u32(&r); break;   /* header, table, XINF, XJNT */
            default: n = tsup_rng_below(&r, (uint32_t)n) + 1; break;
            }
        }
        if (tsup_rng_below(&r, 8) != 0 && n >= 24) {
            tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, 0);
            tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, b, n));
        }
        psc_proxy_model_t m;
        psc_container_error_t e = {NULL, 0};
        if (psc_proxy_parse(b, n, &m, &e) == PSC_OK) {
            parsed++;
            size_t wn = psc_proxy_workspace_size(&m);
            void *ws = NULL;
            psc_proxy_t p;
            psc_mat4_q16_t *skin = malloc(m.joint_count * sizeof *skin);
            assert_int_equal(posix_memalign(&ws, 64, wn ? wn : 8), 0);
            assert_int_equal(psc_proxy_init(&p, &m, ws, wn), PSC_OK);
            psc_proxy_pose_at(&m, (int64_t)tsup_rng_below(&r, 2000000), skin);
            psc_3d_config_t cfg = {64, 48, 0, 0, 16, tsup_bam_from_deg(60), PSC_Q16_ONE, 8 * PSC_Q16_ONE,
                                   psc_proxy_max_vertices(&m), PSC_3D_HSR_ZBUFFER};
            void *ws3d = NULL;
            size_t n3 = psc_3d_workspace_size(&cfg);
            assert_int_equal(posix_memalign(&ws3d, 64, n3), 0);
            psc_3d_t r3;
            assert_int_equal(psc_3d_init(&r3, &cfg, ws3d, n3), PSC_OK);
            psc_mat4_q16_t cam;
            psc_mat4_identity(&cam);
            cam.m[2][3] = 3 * PSC_Q16_ONE;
            if (k & 1) {   /* relit: the normals (any code is a direction) */
                const int32_t l[3] = {-40000, 30000, 20000};
                psc_status_t ls = psc_proxy_set_light(&p, l, 6000);
                assert_true(ls == (m.tex_normals ? PSC_OK : PSC_ERR_UNSUPPORTED));
            }
            for (int lod = 0; lod < 3; lod++) {
                const psc_3d_draw_t *d;
                unsigned nd;
                assert_int_equal(psc_proxy_frame(&p, skin, &cam, (psc_proxy_lod_t)lod, false, &d, &nd), PSC_OK);
                psc_surface_t sf = {64, 48, 64 * 4, PSC_PIX_XRGB8888, px};
                uint32_t bg = BG;
                psc_3d_render(&r3, d, nd, &bg, &sf, NULL);
            }
            free(ws3d), free(ws), free(skin);
        } else {
            assert_non_null(e.what);
            refused++;
        }
        free(b);
    }
    print_message("  3000 mutated proxy packs: %u parsed and drawn, %u refused with a message\n", parsed, refused);
    assert_true(refused > 0);
    fixture_free(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_views_rule),
        cmocka_unit_test(test_views_affine_bound),
        cmocka_unit_test(test_views_perspective),
        cmocka_unit_test(test_soft_silhouettes),
        cmocka_unit_test(test_views_limits),
        cmocka_unit_test(test_mip_coverage),
        cmocka_unit_test(test_views_grid),
        cmocka_unit_test(test_truck_quality),
        cmocka_unit_test(test_bar_quality),
        cmocka_unit_test(test_human_quality),
        cmocka_unit_test(test_robot_quality),
        cmocka_unit_test(test_depth_offsets),
        cmocka_unit_test(test_machine_quality),
        cmocka_unit_test(test_joints_attached),
        cmocka_unit_test(test_strip_light),
        cmocka_unit_test(test_skin_split),
        cmocka_unit_test(test_lod_auto),
        cmocka_unit_test(test_scene_draw),
        cmocka_unit_test(test_tiles_exact),
        cmocka_unit_test(test_model_fuzz),
        cmocka_unit_test(test_normals_sections),
        cmocka_unit_test(test_pack_fuzz),
    };
    if (getenv("PSC_PROXY_ONLY"))   /* one test while working on it, e.g. test_human_quality */
        cmocka_set_test_filter(getenv("PSC_PROXY_ONLY"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
