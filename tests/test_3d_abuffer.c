/* SPDX-License-Identifier: MIT */
/*
 * test_3d_abuffer.c - the A-buffer (core/raster/psc_abuffer.h) against the
 * double-precision reference supersampled 16 times (4 x 4 samples a pixel,
 * at the A-buffer's sample positions, box-filtered: tsup_ref_render3d_ss).
 *
 * Metric, per view: the RMS error over the 8-bit channels of the pixels
 * along the silhouettes, with the A-buffer and without it. Those pixels:
 * where the reference covers some of the 16 samples but not all. The
 * A-buffer must cut the error by MIN_GAIN; the printed table gives the
 * factors. Interior pixels are unchanged within INTERIOR_LEVELS: all but
 * the silhouettes' and those where the supersampled reference differs from
 * the one sampled at pixel centres by more than EDGE_LEVELS (edges where a
 * part hides another, sharp shading), with their 8 neighbours (core snaps
 * vertices to 1/16 pixel, so a sample within 1/32 pixel of an edge may fall
 * either way). At most MAX_INTERIOR_MOVED of the interior pixels may move further, and none by more than
 * MAX_INTERIOR_LEVELS: a pixel on an edge between two triangles of a mesh gets merged fragments that average the
 * triangles' colours at the pixel centre (a level or two, but one step of RGB565's 5-bit red and blue is 8 levels:
 * 414 of the teapot's 27 806 interior pixels in RGB565, 1.5 %), and where two surfaces lie within the depth
 * precision of each other (the sphere's 16-bit depth: 138 pixels; the teapot's lid in the body's rim), a fragment
 * taking its depth at a sample may order differently from a centre (measured: at most 1.5 %, 13 levels).
 * Also: tiles give the frame of the full screen byte for byte; a budget too
 * small degrades to the plain frame's edges and counts what did not fit;
 * alpha-tested view textures get smooth silhouettes too.
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

#define EDGE_LEVELS 8.0
#define MIN_GAIN 2.5
#define INTERIOR_LEVELS 3
#define MAX_INTERIOR_RMS 1.0
#define MAX_INTERIOR_MOVED 0.02   /* share of the interior pixels moved by more than INTERIOR_LEVELS */
#define MAX_INTERIOR_LEVELS 16    /* no interior pixel moves further (two RGB565 steps) */

typedef struct {
    const char *name;
    tsup_shape_t shape;
    psc_shade_t shade;
    double yaw, pitch, dist, hfov;
    psc_pixfmt_t fmt;
    uint8_t depth_bits;
    uint16_t tile;
} view_t;

static const view_t views[] = {
    {"cube flat", TSUP_CUBE, PSC_SHADE_FLAT, 30, -25, 3.0, 60, PSC_PIX_XRGB8888, 32, 0},
    {"sphere gouraud, 16-bit depth", TSUP_SPHERE, PSC_SHADE_GOURAUD, 10, 20, 3.0, 50, PSC_PIX_XRGB8888, 16, 0},
    {"torus texture, tiles", TSUP_TORUS, PSC_SHADE_TEXTURE, 0, -35, 2.0, 65, PSC_PIX_XRGB8888, 32, 32},
    {"teapot phong", TSUP_TEAPOT, PSC_SHADE_PHONG, -40, -30, 2.0, 60, PSC_PIX_XRGB8888, 32, 0},
    {"teapot gouraud, rgb565", TSUP_TEAPOT, PSC_SHADE_GOURAUD, 150, -10, 1.8, 60, PSC_PIX_RGB565, 32, 48},
};

/* A renderer with the A-buffer on (fragments a tile; 0: off) and what it drew. */
typedef struct {
    tsup_3d_t t;
    void *abuf;
    psc_surface_t s;
    psc_3d_stats_t stats;
} frame_t;

static void render(frame_t *f, const psc_3d_config_t *cfg, const psc_3d_draw_t *d, unsigned n, uint32_t fragments,
                   psc_pixfmt_t fmt)
{
    uint32_t bg = 0x283040;
    assert_int_equal(tsup_3d_init(&f->t, cfg), PSC_OK);
    f->abuf = NULL;
    if (fragments) {
        size_t bytes = psc_3d_abuffer_bytes(cfg, fragments);
        assert_true(bytes > 0);
        f->abuf = aligned_alloc(8, (bytes + 7u) & ~(size_t)7u);
        assert_int_equal(psc_3d_set_abuffer(&f->t.r, f->abuf, bytes), PSC_OK);
    }
    f->s = tsup_surface_new(cfg->width, cfg->height, fmt);
    assert_int_equal(psc_3d_render(&f->t.r, d, n, &bg, &f->s, &f->stats), PSC_OK);
}

static void frame_free(frame_t *f)
{
    tsup_surface_free(&f->s);
    tsup_3d_free(&f->t);
    free(f->abuf);
}

static double max_channel_diff(const double *a, const double *b)
{
    double e = 0;
    for (int k = 0; k < 3; k++)
        e = fmax(e, fabs(a[k] - b[k]));
    return e;
}

/* RMS over the edge pixels of the surface against the supersampled reference. */
static double edge_rms(const psc_surface_t *s, const double *ss, const uint8_t *edge)
{
    double sum = 0;
    size_t n = 0;
    for (unsigned y = 0; y < s->height; y++)
        for (unsigned x = 0; x < s->width; x++) {
            size_t i = (size_t)y * s->width + x;
            if (!edge[i])
                continue;
            uint8_t got[3];
            tsup_surface_rgb(s, x, y, got);
            for (int k = 0; k < 3; k++) {
                double e = got[k] - ss[i * 3 + (size_t)k];
                sum += e * e;
            }
            n += 3;
        }
    return n ? sqrt(sum / (double)n) : 0;
}

/* out = in and its 8 neighbours; returns the pixels set. */
static size_t dilate(const uint8_t *in, uint8_t *out, unsigned w, unsigned h)
{
    size_t n = 0;
    for (unsigned y = 0; y < h; y++)
        for (unsigned x = 0; x < w; x++) {
            uint8_t e = 0;
            for (int j = -1; j <= 1; j++)
                for (int i = -1; i <= 1; i++) {
                    int xx = (int)x + i, yy = (int)y + j;
                    if (xx >= 0 && yy >= 0 && xx < (int)w && yy < (int)h && in[(size_t)yy * w + (size_t)xx])
                        e = 1;
                }
            out[(size_t)y * w + x] = e;
            n += e;
        }
    return n;
}

static void setup_draw(psc_3d_draw_t *d, const tsup_mesh_t *m, const view_t *v, const psc_texture_t *tex)
{
    psc_3d_draw_defaults(d, &m->mesh);
    tsup_orbit_matrix(&d->camera_from_object, v->yaw, v->pitch, v->dist);
    d->shade = v->shade;
    d->lit = true;
    d->light_dir = psc_vec3_normalize((psc_vec3_q16_t){-26000, 39000, -45000});
    d->ambient_q8 = 72;
    d->specular_q8 = 96;
    d->shininess = 24;
    d->texture = tex;
}

static void test_silhouettes_against_supersampled(void **state)
{
    (void)state;
    tsup_texture_t tex;
    assert_int_equal(tsup_texture_make(&tex, 64, 64, PSC_PIX_RGB565), 0);
    const uint16_t W = 200, H = 150;
    size_t np = (size_t)W * H;
    double *ss = malloc(np * 3 * sizeof(double)), *one = malloc(np * 3 * sizeof(double));
    uint8_t *edge = malloc(np), *sil = malloc(np), *near = malloc(np), *covered = malloc(np);
    print_message("  %-30s %6s %10s %10s %6s %8s\n", "view", "edges", "rms plain", "rms abuf", "gain", "frags");
    for (size_t vi = 0; vi < sizeof views / sizeof views[0]; vi++) {
        const view_t *v = &views[vi];
        psc_model_t g;
        tsup_shape_make(v->shape, &g);
        if (v->shade != PSC_SHADE_TEXTURE && v->shape != TSUP_TEAPOT)
            psc_model_color_by_index(&g, (uint32_t)vi);
        tsup_mesh_t m;
        assert_int_equal(tsup_mesh_from_geom(&m, &g, 1), 0);
        m.mesh.base_color = 0xD0C0A0;
        psc_3d_draw_t d;
        setup_draw(&d, &m, v, &tex.tex);
        psc_3d_config_t cfg = {W, H, v->tile, v->tile, v->depth_bits, tsup_bam_from_deg(v->hfov), PSC_Q16_ONE / 32,
                               16 * PSC_Q16_ONE, m.mesh.vertex_count, PSC_3D_HSR_ZBUFFER};
        tsup_ref_render3d_ss(&cfg, &d, 1, 0x283040, 4, ss, covered);
        tsup_ref_render3d(&cfg, &d, 1, 0x283040, one, NULL);
        for (size_t i = 0; i < np; i++)
            near[i] = covered[i] > 0 && covered[i] < 16;
        size_t edges = 0;
        for (size_t i = 0; i < np; i++) {
            sil[i] = near[i];
            edges += near[i];
        }
        for (size_t i = 0; i < np; i++)
            near[i] |= max_channel_diff(&ss[i * 3], &one[i * 3]) > EDGE_LEVELS;
        dilate(near, edge, W, H);
        frame_t plain, aa;
        render(&plain, &cfg, &d, 1, 0, v->fmt);
        render(&aa, &cfg, &d, 1, 65536, v->fmt);
        double e0 = edge_rms(&plain.s, ss, sil), e1 = edge_rms(&aa.s, ss, sil);
        print_message("  %-30s %6zu %10.2f %10.2f %6.2f %8u\n", v->name, edges, e0, e1, e0 / e1,
                      (unsigned)aa.stats.fragments_peak);
        char fn[64];
        snprintf(fn, sizeof fn, "3d_abuffer_%02zu.png", vi);
        tsup_save_png(&aa.s, fn);
        assert_int_equal(aa.stats.fragments_overflow, 0);
        if (e0 / e1 < MIN_GAIN)
            fail_msg("%s: silhouette RMS %.2f with the A-buffer, %.2f without: gain %.2f < %.1f", v->name, e1, e0,
                     e0 / e1, MIN_GAIN);
        /* Interior pixels unchanged: a pixel drawn differently is on an edge, or within INTERIOR_LEVELS. */
        size_t moved = 0, interior = 0;
        double isum = 0;
        int imax = 0;
        for (unsigned y = 0; y < H; y++)
            for (unsigned x = 0; x < W; x++) {
                uint8_t a[3], b[3];
                tsup_surface_rgb(&plain.s, x, y, a);
                tsup_surface_rgb(&aa.s, x, y, b);
                int dmax = 0;
                for (int k = 0; k < 3; k++)
                    dmax = abs(a[k] - b[k]) > dmax ? abs(a[k] - b[k]) : dmax;
                if (!edge[(size_t)y * W + x]) {
                    interior++;
                    for (int k = 0; k < 3; k++)
                        isum += (double)(a[k] - b[k]) * (a[k] - b[k]);
                    imax = dmax > imax ? dmax : imax;
                }
                if (dmax > INTERIOR_LEVELS && !edge[(size_t)y * W + x]) {
                    moved++;
                    if (moved < 4 && getenv("PSC_TEST_VERBOSE"))
                        print_message("    interior pixel (%u, %u) moved by %d levels (plain %d %d %d, abuf %d %d %d, covered %d)\n", x, y, dmax, a[0], a[1], a[2], b[0], b[1], b[2], covered[(size_t)y * W + x]);
                }
            }
        print_message("    interior: %zu pixels, RMS change %.3f, largest %d, %zu beyond %d levels\n", interior,
                      sqrt(isum / (3.0 * (double)interior)), imax, moved, INTERIOR_LEVELS);
        for (size_t i = 0; i < np; i++)
            near[i] = !edge[i];
        double ri0 = edge_rms(&plain.s, ss, near), ri1 = edge_rms(&aa.s, ss, near);
        print_message("    against the reference there: RMS %.3f plain, %.3f A-buffer\n", ri0, ri1);
        if ((double)moved > MAX_INTERIOR_MOVED * (double)interior || imax > MAX_INTERIOR_LEVELS)
            fail_msg("%s: %zu of %zu interior pixels moved by more than %d levels (at most %.0f %%), the largest by %d "
                     "(at most %d)", v->name, moved, interior, INTERIOR_LEVELS, 100 * MAX_INTERIOR_MOVED, imax,
                     MAX_INTERIOR_LEVELS);
        if (sqrt(isum / (3.0 * (double)interior)) > MAX_INTERIOR_RMS || ri1 > ri0 * 1.02)
            fail_msg("%s: interior RMS change %.3f (max %.1f), error against the reference %.3f (plain %.3f)", v->name,
                     sqrt(isum / (3.0 * (double)interior)), MAX_INTERIOR_RMS, ri1, ri0);
        frame_free(&plain);
        frame_free(&aa);
        tsup_mesh_free(&m);
        psc_model_free(&g);
    }
    free(ss);
    free(one);
    free(edge);
    free(near);
    free(sil);
    free(covered);
    tsup_texture_free(&tex);
}

/* Two objects, the sphere in front of the cube: the cube's edges behind the sphere's silhouette and its own. */
static void test_two_objects_and_tiles(void **state)
{
    (void)state;
    const uint16_t W = 160, H = 120;
    size_t np = (size_t)W * H;
    psc_model_t gc, gs;
    psc_model_cube(&gc, 1.0);
    psc_model_sphere(&gs, 0.6, 32, 17);
    tsup_mesh_t mc, ms;
    assert_int_equal(tsup_mesh_from_geom(&mc, &gc, 0), 0);
    assert_int_equal(tsup_mesh_from_geom(&ms, &gs, 0), 0);
    mc.mesh.base_color = 0x40A0E0;
    ms.mesh.base_color = 0xE0A040;
    view_t v = {"two", TSUP_CUBE, PSC_SHADE_GOURAUD, 25, -20, 3.2, 60, PSC_PIX_XRGB8888, 32, 0};
    psc_3d_draw_t d[2];
    setup_draw(&d[0], &mc, &v, NULL);
    setup_draw(&d[1], &ms, &v, NULL);
    d[1].shade = PSC_SHADE_PHONG;
    /* the sphere 0.9 nearer the camera than the cube's centre, a little to the right */
    d[1].camera_from_object.m[0][3] += PSC_Q16_ONE / 3;
    d[1].camera_from_object.m[2][3] -= PSC_Q16_ONE * 9 / 10;
    psc_3d_config_t cfg = {W, H, 0, 0, 32, tsup_bam_from_deg(v.hfov), PSC_Q16_ONE / 32, 16 * PSC_Q16_ONE,
                           mc.mesh.vertex_count + ms.mesh.vertex_count, PSC_3D_HSR_ZBUFFER};
    double *ss = malloc(np * 3 * sizeof(double)), *one = malloc(np * 3 * sizeof(double));
    uint8_t *covered = malloc(np), *edge = malloc(np);
    tsup_ref_render3d_ss(&cfg, d, 2, 0x283040, 4, ss, covered);
    tsup_ref_render3d(&cfg, d, 2, 0x283040, one, NULL);
    size_t edges = 0;
    for (size_t i = 0; i < np; i++) {
        edge[i] = (covered[i] > 0 && covered[i] < 16) || max_channel_diff(&ss[i * 3], &one[i * 3]) > EDGE_LEVELS;
        edges += edge[i];
    }
    frame_t plain, aa, tiled;
    render(&plain, &cfg, d, 2, 0, v.fmt);
    render(&aa, &cfg, d, 2, 65536, v.fmt);
    double e0 = edge_rms(&plain.s, ss, edge), e1 = edge_rms(&aa.s, ss, edge);
    print_message("  silhouettes and the edges the sphere hides: %zu pixels, RMS %.2f plain, %.2f A-buffer (gain %.2f)\n",
                  edges, e0, e1, e0 / e1);
    tsup_save_png(&aa.s, "3d_abuffer_two.png");
    assert_true(e0 / e1 >= MIN_GAIN);
    /* Tiles of 32 x 24 with a tile's budget: the same bytes. */
    psc_3d_config_t tc = cfg;
    tc.tile_width = 32;
    tc.tile_height = 24;
    render(&tiled, &tc, d, 2, 4096, v.fmt);
    assert_int_equal(tiled.stats.fragments_overflow, 0);
    assert_memory_equal(tiled.s.pixels, aa.s.pixels, (size_t)aa.s.stride * H);
    print_message("  32x24 tiles: the same frame with %zu bytes of A-buffer (%u fragments at most in a tile); "
                  "the full screen used %u\n", psc_3d_abuffer_bytes(&tc, 4096), (unsigned)tiled.stats.fragments_peak,
                  (unsigned)aa.stats.fragments_peak);
    frame_free(&tiled);
    /* A budget far too small: no failure, the overflow counted, and the edges no worse than without the A-buffer. */
    render(&tiled, &tc, d, 2, 8, v.fmt);
    double e2 = edge_rms(&tiled.s, ss, edge);
    print_message("  8 fragments a tile: %u did not fit, RMS %.2f\n", (unsigned)tiled.stats.fragments_overflow, e2);
    assert_true(tiled.stats.fragments_overflow > 0);
    assert_true(e2 <= e0 * 1.05);
    frame_free(&tiled);
    frame_free(&plain);
    frame_free(&aa);
    free(ss);
    free(one);
    free(covered);
    free(edge);
    tsup_mesh_free(&mc);
    tsup_mesh_free(&ms);
    psc_model_free(&gc);
    psc_model_free(&gs);
}

/* The resolve against a per-sample reading of the same fragments: each sample shows the nearest fragment covering
 * it, else the stored colour; the pixel is the mean. Random fragments of distinct surfaces (no merging), up to
 * PSC_ABUF_RESOLVE_MAX visible a pixel, some hidden behind the stored depth. */
static void test_resolve_matches_samples(void **state)
{
    (void)state;
    enum { PX = 64 };
    static uint8_t mem[PX * PSC_ABUF_HEAD_BYTES + 1024 * PSC_ABUF_FRAGMENT_BYTES] __attribute__((aligned(8)));
    uint32_t pixels[PX], zbuf[PX];
    psc_surface_t s = {PX, 1, PX * 4, PSC_PIX_XRGB8888, pixels};
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 15);
    for (int round = 0; round < 500; round++) {
        psc_abuffer_t a;
        psc_abuffer_init(&a, mem, PX, 1024);
        uint32_t frag_z[PX][12], frag_c[PX][12], nfrag[PX];
        uint16_t frag_m[PX][12];
        for (unsigned p = 0; p < PX; p++) {
            pixels[p] = 0xFF000000u | (tsup_rng_u32(&rng) & 0xFFFFFFu);
            zbuf[p] = tsup_rng_u32(&rng) | 0x80000000u;
            nfrag[p] = 0;
            unsigned n = tsup_rng_below(&rng, PSC_ABUF_RESOLVE_MAX + 1);
            for (unsigned k = 0; k < n; k++) {
                uint16_t m = (uint16_t)tsup_rng_u32(&rng);
                if (m == 0 || m == PSC_ABUF_FULL)
                    m = 0x0F0F;
                uint32_t z = tsup_rng_u32(&rng), c = tsup_rng_u32(&rng) & 0xFFFFFFu, zz = z, cc = c;
                a.surface = (uint16_t)(k + 1);
                assert_false(psc_abuffer_add(&a, p, m, false, zbuf[p], 0, &zz, &cc));
                if (z < zbuf[p]) {
                    frag_z[p][nfrag[p]] = z;
                    frag_c[p][nfrag[p]] = c;
                    frag_m[p][nfrag[p]++] = m;
                }
            }
        }
        uint32_t stored[PX];
        memcpy(stored, pixels, sizeof stored);
        psc_abuffer_resolve(&a, &s, 0, 0, PX, 1, zbuf, PX * 4, 32);
        for (unsigned p = 0; p < PX; p++) {
            double sum[3] = {0, 0, 0};
            for (unsigned b = 0; b < 16; b++) {
                uint32_t best = UINT32_MAX, c = stored[p] & 0xFFFFFFu;
                for (unsigned k = 0; k < nfrag[p]; k++)
                    if ((frag_m[p][k] >> b & 1u) && frag_z[p][k] < best) {
                        best = frag_z[p][k];
                        c = frag_c[p][k];
                    }
                for (int k = 0; k < 3; k++)
                    sum[k] += c >> (16 - 8 * k) & 255u;
            }
            for (int k = 0; k < 3; k++) {
                double got = pixels[p] >> (16 - 8 * k) & 255u;
                if (fabs(got - sum[k] / 16.0) > 0.5 + 1e-9)
                    fail_msg("round %d pixel %u channel %d: %.0f, the samples say %.3f", round, p, k, got, sum[k] / 16);
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_silhouettes_against_supersampled),
        cmocka_unit_test(test_two_objects_and_tiles),
        cmocka_unit_test(test_resolve_matches_samples),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
