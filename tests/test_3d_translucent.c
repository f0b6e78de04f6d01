/* SPDX-License-Identifier: MIT */
/*
 * test_3d_translucent.c - translucent surfaces in the A-buffer (PSC_BLEND_ALPHA, core/raster/psc_abuffer.h)
 * against sorted alpha compositing in double.
 *
 *  - Scenes of screen-aligned quads (their edges on pixel edges, or
 *    halfway, so every sample is inside or outside beyond doubt) at distinct
 *    depths, opaque and translucent, flat colours, random opacities: each
 *    pixel of the A-buffer's frame against the reference (per sample: the
 *    quads covering it sorted near to far, each adding what light is left
 *    times its opacity - kept to 1/128 - times its colour; the background
 *    behind; the 16 samples averaged) within 1 level a channel.
 *  - The order does not matter: the same quads drawn in reverse give the same
 *    bytes, in tiles too.
 *  - Without the A-buffer, drawn far to near, translucent quads blend over
 *    the pixel within 2 levels of the reference at pixels whole inside.
 *  - A budget too small degrades (counted) and never fails; translucent
 *    surfaces write no depth.
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

#define W 128
#define H 96
#define MAXQ 8
#define BG 0x102030u

/* A quad in pixel coordinates [x0, x1) x [y0, y1) at camera depth z. */
typedef struct {
    double x0, y0, x1, y1, z;
    uint32_t color;
    uint16_t opacity_q8; /* 256: opaque */
} sheet_t;

typedef struct {
    int32_t pos[MAXQ][4][3];
    uint32_t col[MAXQ][4];
    uint16_t idx[MAXQ][6];
    psc_mesh_t mesh[MAXQ];
    psc_3d_draw_t draw[MAXQ];
} scene_t;

/* hfov 90 degrees: f = W / 2, so pixel x = W/2 + (W/2) X / Z. */
static void build(scene_t *sc, const sheet_t *q, unsigned n, const unsigned *order)
{
    memset(sc, 0, sizeof *sc);
    for (unsigned k = 0; k < n; k++) {
        const sheet_t *a = &q[order[k]];
        double xs[4] = {a->x0, a->x1, a->x1, a->x0}, ys[4] = {a->y0, a->y0, a->y1, a->y1};
        for (unsigned v = 0; v < 4; v++) {
            double X = (xs[v] - W / 2.0) / (W / 2.0) * a->z, Y = (H / 2.0 - ys[v]) / (W / 2.0) * a->z;
            sc->pos[k][v][0] = (int32_t)lround(X * 65536);
            sc->pos[k][v][1] = (int32_t)lround(Y * 65536);
            sc->pos[k][v][2] = (int32_t)lround(a->z * 65536);
            sc->col[k][v] = a->color;
        }
        uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
        memcpy(sc->idx[k], idx, sizeof idx);
        sc->mesh[k] = (psc_mesh_t){.vertex_count = 4, .triangle_count = 2, .position_q16 = &sc->pos[k][0][0],
                                   .color = sc->col[k], .index = sc->idx[k]};
        psc_3d_draw_defaults(&sc->draw[k], &sc->mesh[k]);
        sc->draw[k].shade = PSC_SHADE_FLAT;
        sc->draw[k].cull_back = false;
        if (a->opacity_q8 < 256) {
            sc->draw[k].blend = PSC_BLEND_ALPHA;
            sc->draw[k].opacity_q8 = a->opacity_q8;
        }
    }
}

/* The reference at pixel (px, py): 16 samples at (2i + 1) / 8, each composited front to back. */
static void reference(const sheet_t *q, unsigned n, unsigned px, unsigned py, double out[3])
{
    out[0] = out[1] = out[2] = 0;
    for (unsigned j = 0; j < 4; j++)
        for (unsigned i = 0; i < 4; i++) {
            double sx = px + (2 * i + 1) / 8.0, sy = py + (2 * j + 1) / 8.0;
            const sheet_t *cover[MAXQ];
            unsigned m = 0;
            for (unsigned k = 0; k < n; k++)
                if (sx >= q[k].x0 && sx < q[k].x1 && sy >= q[k].y0 && sy < q[k].y1) {
                    unsigned at = m++;
                    for (; at > 0 && cover[at - 1]->z > q[k].z; at--)
                        cover[at] = cover[at - 1];
                    cover[at] = &q[k];
                }
            double t = 1, c[3] = {0, 0, 0};
            for (unsigned k = 0; k < m && t > 0; k++) {
                /* the A-buffer keeps opacity to 1/128 */
                double o = cover[k]->opacity_q8 >= 256 ? 1.0 : ((cover[k]->opacity_q8 + 1) >> 1) / 128.0;
                for (unsigned ch = 0; ch < 3; ch++)
                    c[ch] += t * o * (cover[k]->color >> (16 - 8 * ch) & 255);
                t *= 1 - o;
            }
            for (unsigned ch = 0; ch < 3; ch++)
                out[ch] += (c[ch] + t * (BG >> (16 - 8 * ch) & 255)) / 16.0;
        }
}

static void render(const scene_t *sc, unsigned n, uint16_t tile, size_t abuf_fragments, psc_surface_t *out,
                   psc_3d_stats_t *st, uint16_t *depth)
{
    psc_3d_config_t cfg = {W, H, tile, tile, 32, tsup_bam_from_deg(90), PSC_Q16_ONE / 8, 64 * PSC_Q16_ONE,
                           4 * MAXQ, PSC_3D_HSR_ZBUFFER};
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
    t.r.depth_out = depth;
    void *abuf = NULL;
    if (abuf_fragments) {
        size_t bytes = psc_3d_abuffer_bytes(&cfg, (uint32_t)abuf_fragments);
        abuf = aligned_alloc(8, (bytes + 7u) & ~(size_t)7u);
        assert_int_equal(psc_3d_set_abuffer(&t.r, abuf, bytes), PSC_OK);
    }
    uint32_t bg = BG;
    assert_int_equal(psc_3d_render(&t.r, sc->draw, n, &bg, out, st), PSC_OK);
    tsup_3d_free(&t);
    free(abuf);
}

static void random_quads(tsup_rng_t *rng, sheet_t *q, unsigned n)
{
    for (unsigned k = 0; k < n; k++) {
        double half = tsup_rng_below(rng, 3) == 0 ? 0.5 : 0; /* some edges halfway across pixels */
        double x0 = tsup_rng_below(rng, W - 20), y0 = tsup_rng_below(rng, H - 20);
        q[k] = (sheet_t){x0 + half, y0, x0 + 10 + tsup_rng_below(rng, W - x0 - 10) + half, y0 + 10 +
                        tsup_rng_below(rng, H - y0 - 10), 1.0 + k * 0.37 + tsup_rng_unit(rng) * 0.3,
                        tsup_rng_u32(rng) & 0xFFFFFFu, (uint16_t)(tsup_rng_below(rng, 3) == 0 ? 256
                                                                  : 20 + tsup_rng_below(rng, 220))};
        /* snap x to the grid the projection holds exactly: 1/2 pixel */
    }
}

static void test_against_sorted_compositing(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 42);
    static scene_t sc, rev;
    double worst = 0;
    unsigned translucent_pixels = 0;
    for (unsigned s = 0; s < 40; s++) {
        unsigned n = 2 + tsup_rng_below(&rng, MAXQ - 1);
        sheet_t q[MAXQ];
        random_quads(&rng, q, n);
        unsigned order[MAXQ], back[MAXQ];
        for (unsigned k = 0; k < n; k++) {
            order[k] = k;
            back[k] = n - 1 - k;
        }
        build(&sc, q, n, order);
        build(&rev, q, n, back);
        psc_surface_t a = tsup_surface_new(W, H, PSC_PIX_XRGB8888), b = tsup_surface_new(W, H, PSC_PIX_XRGB8888);
        psc_3d_stats_t st;
        render(&sc, n, 0, 20000, &a, &st, NULL);
        assert_int_equal(st.fragments_overflow, 0);
        render(&rev, n, 32, 8000, &b, &st, NULL);
        if (memcmp(a.pixels, b.pixels, (size_t)a.stride * H) != 0)
            fail_msg("scene %u: drawn in reverse (in tiles) the translucent frame differs", s);
        for (unsigned y = 0; y < H; y++)
            for (unsigned x = 0; x < W; x++) {
                double ref[3];
                reference(q, n, x, y, ref);
                uint32_t got = ((const uint32_t *)a.pixels)[y * W + x];
                for (unsigned ch = 0; ch < 3; ch++) {
                    double e = fabs((double)(got >> (16 - 8 * ch) & 255) - ref[ch]);
                    if (e > worst)
                        worst = e;
                    if (e > 1.0)
                        fail_msg("scene %u pixel (%u, %u) channel %u: %u against %.2f", s, x, y, ch,
                                 (unsigned)(got >> (16 - 8 * ch) & 255), ref[ch]);
                }
                for (unsigned k = 0; k < n; k++)
                    translucent_pixels += q[k].opacity_q8 < 256 && x >= q[k].x0 && x < q[k].x1 && y >= q[k].y0 &&
                                          y < q[k].y1;
            }
        tsup_surface_free(&a);
        tsup_surface_free(&b);
    }
    print_message("  40 random scenes of opaque and translucent quads: within %.2f levels of sorted alpha "
                  "compositing in double (bound 1); %u translucent pixels; the reverse order, in tiles, the same "
                  "bytes\n", worst, translucent_pixels);
    assert_true(translucent_pixels > 10000);
}

static void test_without_abuffer_and_overflow(void **state)
{
    (void)state;
    /* an opaque wall at the back, two translucent sheets before it, drawn far to near */
    sheet_t q[3] = {{10, 10, 110, 80, 5.0, 0x80C040u, 256},
                   {20, 20, 90, 70, 3.0, 0xFF0000u, 128},
                   {40, 15, 100, 60, 2.0, 0x0000FFu, 77}};
    unsigned order[3] = {0, 1, 2};
    static scene_t sc;
    build(&sc, q, 3, order);
    psc_surface_t s = tsup_surface_new(W, H, PSC_PIX_XRGB8888);
    static uint16_t depth[W * H];
    psc_3d_stats_t st;
    render(&sc, 3, 0, 0, &s, &st, depth);
    double worst = 0;
    for (unsigned y = 0; y < H; y++)
        for (unsigned x = 0; x < W; x++) {
            double ref[3];
            sheet_t q8[3];
            memcpy(q8, q, sizeof q8);
            reference(q8, 3, x, y, ref);
            uint32_t got = ((const uint32_t *)s.pixels)[y * W + x];
            for (unsigned ch = 0; ch < 3; ch++) {
                double e = fabs((double)(got >> (16 - 8 * ch) & 255) - ref[ch]);
                worst = e > worst ? e : worst;
            }
        }
    /* (the blend keeps opacity to 1/256, the reference to 1/128: 77/256 against 39/128) */
    print_message("  without the A-buffer, far to near: within %.2f levels; depth is the wall's where sheets "
                  "cover it\n", worst);
    assert_true(worst <= 2.0);
    /* the sheets wrote no depth: at (50, 40) the depth is the wall's (z = 5), the same as where no sheet is */
    assert_int_equal(depth[40 * W + 50], depth[75 * W + 15]);
    /* a budget of a handful of fragments: degraded, counted, drawn */
    psc_3d_config_t cfg = {W, H, 0, 0, 32, tsup_bam_from_deg(90), PSC_Q16_ONE / 8, 64 * PSC_Q16_ONE, 12,
                           PSC_3D_HSR_ZBUFFER};
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
    size_t bytes = psc_3d_abuffer_bytes(&cfg, 16);
    void *abuf = aligned_alloc(8, (bytes + 7u) & ~(size_t)7u);
    assert_int_equal(psc_3d_set_abuffer(&t.r, abuf, bytes), PSC_OK);
    uint32_t bg = BG;
    assert_int_equal(psc_3d_render(&t.r, sc.draw, 3, &bg, &s, &st), PSC_OK);
    print_message("  a budget of 16 fragments: %u translucent pixels found no room (drawn blended over)\n",
                  (unsigned)st.fragments_overflow);
    assert_true(st.fragments_overflow > 1000);
    tsup_3d_free(&t);
    free(abuf);
    tsup_surface_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_against_sorted_compositing),
        cmocka_unit_test(test_without_abuffer_and_overflow),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
