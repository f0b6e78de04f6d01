/* SPDX-License-Identifier: MIT */
/*
 * test_tiles.c - tiled packs (issue 30): written from rows, read tile by tile.
 *
 *  - the tiles hold the flat pack's pixels, every level (the same filter and rounding);
 *  - once its tiles are resident, a tiled frame is the flat frame's bytes: random views (the poles and the seam
 *    included), every filter, span and map and output format;
 *  - a starved cache (its fewest slots) draws every frame, coarser where tiles are absent, and the frames
 *    sharpen to the flat bytes as the tiles they ask for are loaded;
 *  - a corrupt tile gives a message naming the file and the tile, and the coarser level there; a truncated
 *    pack is refused at opening;
 *  - the streaming writer's memory does not grow with the image's height (counted, not timed);
 *  - JPEG tiles: each tile and each frame within a stated PSNR of the raw tiles' (the JPEG's error alone), a
 *    fraction of their bytes; the loader thread's decoder and the cache's give the same bytes; a tile that does
 *    not decode (its CRC right) names the file and the tile and leaves the coarser level.
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
#include <unistd.h>

#include "psc_io_pack_build.h"
#include "psc_io_pixfmt.h"
#include "psc_io_tiles.h"
#include "base/psc_crc32.h"
#include "pack/psc_pack.h"
#include "viewer/psc_viewer.h"
#include "psc_testsupport.h"

#define MAP_W 2048u
#define MAP_H 1024u
#define OUT_W 320u
#define OUT_H 240u

/* A map with detail at every scale: smooth colours, a fine hash, sharp lines every 37 pixels. */
static psc_image_t test_image(uint32_t w, uint32_t h, uint64_t seed)
{
    psc_image_t img = {w, h, malloc((size_t)w * h * sizeof(uint32_t))};
    assert_non_null(img.xrgb);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, seed);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            uint32_t r = (x * 255u) / w, g = (y * 255u) / h, b = (uint32_t)(tsup_rng_u32(&rng) & 63u) + 96u;
            if (x % 37u == 0 || y % 37u == 0)
                r = g = b = 255u;
            img.xrgb[(size_t)y * w + x] = 0xFF000000u | r << 16 | g << 8 | b;
        }
    return img;
}

static char *temp_path(const char *name)
{
    static char buf[4][256];
    static unsigned k;
    char *p = buf[k++ & 3u];
    snprintf(p, 256, "%s/psc-test-tiles-%d-%s", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (int)getpid(), name);
    return p;
}

typedef struct {
    uint8_t *flat_bytes;
    size_t flat_len;
    psc_pack_t flat;
    psc_io_tiled_t *tiled;
    char path[256];
} packs_t;

/* The tests' pack options: a full turn (unless a test sets a coverage), zoom down to 2 degrees. */
static psc_pack_options_t pack_options(psc_pixfmt_t format)
{
    psc_pack_options_t o;
    psc_io_pack_options_default(&o);
    o.format = format;
    o.display_width = OUT_W;
    o.display_height = OUT_H;
    o.hfov_min_deg = 2.0;
    return o;
}

/* A flat and a tiled pack of img with options o (the flat one in memory, the tiled one in a file, opened with a
 * cache of `budget` bytes). */
static void make_packs_with(packs_t *p, const psc_image_t *img, const psc_pack_options_t *opt, size_t budget,
                            const char *name)
{
    psc_pack_options_t o = *opt;
    char err[512];
    assert_int_equal(psc_io_pack_build(img, &o, &p->flat_bytes, &p->flat_len, err, sizeof err), 0);
    psc_container_error_t e = {0};
    assert_int_equal(psc_pack_parse(p->flat_bytes, p->flat_len, &p->flat, &e), PSC_OK);
    snprintf(p->path, sizeof p->path, "%s", temp_path(name));
    if (psc_io_tiles_write_image(p->path, img, &o, err, sizeof err) != 0)
        fail_msg("%s", err);
    if (psc_io_tiled_open(p->path, budget, &p->tiled, err, sizeof err) != 0)
        fail_msg("%s", err);
}

static void make_packs(packs_t *p, const psc_image_t *img, psc_pixfmt_t format, size_t budget, const char *name)
{
    psc_pack_options_t o = pack_options(format);
    make_packs_with(p, img, &o, budget, name);
}

static void free_packs(packs_t *p)
{
    psc_io_tiled_close(p->tiled);
    free(p->flat_bytes);
    unlink(p->path);
}

/* Every tile loaded (the cache holds them all). */
static void load_all(psc_io_tiled_t *t)
{
    const psc_tiles_t *g = psc_io_tiled_tiles(t);
    uint32_t *all = malloc(g->tile_count * sizeof *all);
    for (uint32_t i = 0; i < g->tile_count; i++)
        all[i] = i;
    char err[512];
    assert_int_equal(psc_io_tiled_load(t, all, g->tile_count, err, sizeof err), 0);
    free(all);
}

/* The tiles hold the flat pack's levels, pixel for pixel. */
static void test_tiles_are_the_flat_levels(void **state)
{
    (void)state;
    psc_image_t img = test_image(MAP_W, MAP_H, 1);
    static const psc_pixfmt_t fmts[] = {PSC_PIX_RGB565, PSC_PIX_XRGB8888, PSC_PIX_RGB888};
    for (int f = 0; f < 3; f++) {
        packs_t p;
        psc_pixfmt_t fmt = fmts[f];
        make_packs(&p, &img, fmt, 256u << 20, "levels.pano");
        load_all(p.tiled);
        const psc_tiles_t *g = psc_io_tiled_tiles(p.tiled);
        assert_int_equal(g->level_count, p.flat.level_count);
        const uint32_t bpp = psc_pixfmt_bytes(fmt);
        for (uint32_t k = 0; k < g->level_count; k++) {
            const psc_envmap_t *l = &p.flat.levels[k];
            assert_int_equal(g->level[k].width, l->width);
            assert_int_equal(g->level[k].height, l->height);
            for (uint32_t r = 0; r < l->height; r++) {
                const uint8_t *flat = (const uint8_t *)l->pixels + (size_t)r * l->stride;
                for (uint32_t c0 = 0; c0 < l->width; c0 += PSC_TILE_SIDE) {
                    const uint8_t *tile = g->resident[psc_tiles_at(g, k, r, c0)];
                    assert_non_null(tile);
                    uint32_t n = l->width - c0 < PSC_TILE_SIDE ? l->width - c0 : PSC_TILE_SIDE;
                    assert_memory_equal(tile + (r % PSC_TILE_SIDE) * g->tile_stride, flat + (size_t)c0 * bpp,
                                        n * bpp);
                }
            }
        }
        print_message("  %s: %u levels, %u tiles, identical to the flat pack's levels\n", psc_io_pixfmt_name(fmt),
                      (unsigned)g->level_count, (unsigned)g->tile_count);
        free_packs(&p);
    }
    free(img.xrgb);
}

typedef struct {
    psc_viewer_t v;
    void *ws;
    psc_envmap_t map;
} viewer_t;

/* What a test comparing a flat and a tiled viewer's frames frees at its end. */
static void free_frames(psc_surface_t *sa, psc_surface_t *sb, viewer_t *a, viewer_t *b, packs_t *p, psc_image_t *img)
{
    free(sa->pixels);
    free(sb->pixels);
    free(a->ws);
    free(b->ws);
    free_packs(p);
    free(img->xrgb);
}

static void flat_viewer(viewer_t *vw, const psc_pack_t *p)
{
    size_t n = psc_viewer_workspace_size(OUT_W, OUT_H, &p->map);
    vw->ws = aligned_alloc(64, (n + 63u) & ~(size_t)63u);
    assert_int_equal(psc_viewer_init(&vw->v, &p->map, p->luts, p->lut_count, OUT_W, OUT_H, vw->ws, n), PSC_OK);
    assert_int_equal(psc_viewer_set_levels(&vw->v, p->levels, p->level_count), PSC_OK);
}

static void tiled_viewer(viewer_t *vw, psc_io_tiled_t *t)
{
    const psc_pack_t *p = psc_io_tiled_pack(t);
    vw->map = p->map;
    size_t n = psc_viewer_workspace_size_tiled(OUT_W, OUT_H, &vw->map);
    vw->ws = aligned_alloc(64, (n + 63u) & ~(size_t)63u);
    assert_int_equal(psc_viewer_init_tiled(&vw->v, &vw->map, psc_io_tiled_tiles(t), p->luts, p->lut_count, OUT_W,
                                           OUT_H, vw->ws, n),
                     PSC_OK);
}

static psc_view_t random_view(tsup_rng_t *rng, const psc_viewer_t *v)
{
    psc_view_t view = {0};
    view.yaw = tsup_rng_u32(rng);
    unsigned kind = tsup_rng_below(rng, 6);
    double pitch = kind == 0 ? 90.0 : kind == 1 ? -90.0 : kind == 2 ? tsup_rng_range(rng, 75, 90)
                                                                    : tsup_rng_range(rng, -89, 89);
    view.pitch = (int32_t)tsup_bam_from_deg(pitch);
    view.filter = (psc_filter_t)tsup_rng_below(rng, 3);
    /* nearest and bilinear read level 0 while it has at most two texels a pixel (here up to about 85 degrees at
     * 320 pixels: a 2048-wide map); wider, a tiled map reads a coarser level (test_wide_views_read_few_tiles) */
    double widest = view.filter == PSC_FILTER_MIP ? 118 : 80;
    double hfov = tsup_rng_below(rng, 3) == 0 ? tsup_rng_range(rng, 2, 10) : tsup_rng_range(rng, 10, widest);
    view.hfov = tsup_bam_from_deg(hfov);
    view.span_log2 = (uint8_t)tsup_rng_below(rng, PSC_SPAN_LOG2_MAX + 1u);
    if (view.hfov > psc_viewer_hfov_max(v))
        view.hfov = psc_viewer_hfov_max(v);
    return view;
}

static psc_surface_t surface(psc_pixfmt_t fmt)
{
    psc_surface_t s = {OUT_W, OUT_H, OUT_W * psc_pixfmt_bytes(fmt), fmt, calloc(OUT_W * OUT_H, 4)};
    assert_non_null(s.pixels);
    return s;
}

/* A pack pair's viewers: the flat pack's, the tiled pack's. */
static void both_viewers(packs_t *p, viewer_t *a, viewer_t *b)
{
    flat_viewer(a, &p->flat);
    tiled_viewer(b, p->tiled);
}

/* Two output surfaces of one format, their pixels apart. */
static void surface_pair(psc_pixfmt_t fmt, psc_surface_t *sa, psc_surface_t *sb)
{
    *sa = surface(fmt);
    *sb = surface(fmt);
}

/* A random view of the sphere at least PSC_HFOV_MIN wide; of a 120 x 7.5 degree strip, brought inside it. */
static psc_view_t sphere_view(tsup_rng_t *rng, const psc_viewer_t *v)
{
    psc_view_t view = random_view(rng, v);
    view.hfov = view.hfov < PSC_HFOV_MIN ? PSC_HFOV_MIN : view.hfov;
    return view;
}

static psc_view_t strip_view(tsup_rng_t *rng, const psc_viewer_t *v)
{
    psc_view_t view = {tsup_bam_from_deg(tsup_rng_range(rng, -80, 80)),
                       (int32_t)tsup_bam_from_deg(tsup_rng_range(rng, -5, 5)),
                       tsup_bam_from_deg(tsup_rng_range(rng, 0.5, 10)), (psc_filter_t)tsup_rng_below(rng, 3), 2};
    psc_viewer_clamp(v, &view, PSC_HFOV_MIN);
    return view;
}

/* `views` views (view_of's) of an RGB565 tiled map of `levels` levels drawn with its coarsest tile alone resident:
 * every frame draws and asks only for absent tiles that exist, the tiles of every view exist. Returns the tiles
 * asked for; *count, the map's tiles. */
static unsigned draw_from_coarsest(const psc_envmap_t *map, uint32_t levels, unsigned views, tsup_rng_t *rng,
                                   psc_view_t (*view_of)(tsup_rng_t *, const psc_viewer_t *), uint32_t *count)
{
    psc_tiles_t t;
    assert_int_equal(psc_tiles_init(&t, map->width, map->height, levels, PSC_PIX_RGB565, NULL), PSC_OK);
    const void **resident = calloc(t.tile_count, sizeof *resident);
    uint16_t *slot = malloc(t.tile_bytes);
    assert_true(resident && slot);
    for (uint32_t i = 0; i < PSC_TILE_SIDE * PSC_TILE_SIDE; i++)
        slot[i] = (uint16_t)(i * 2654435761u >> 16);
    resident[t.tile_count - 1u] = slot;   /* the coarsest level's one tile */
    t.resident = resident;
    psc_pack_options_t o = pack_options(PSC_PIX_RGB565);
    uint8_t *bytes;
    size_t len;
    char err[256];
    psc_image_t tiny = {16, 8, calloc(16 * 8, 4)};
    assert_int_equal(psc_io_pack_build(&tiny, &o, &bytes, &len, err, sizeof err), 0);   /* (for its tables) */
    psc_pack_t tables;
    psc_container_error_t e = {0};
    assert_int_equal(psc_pack_parse(bytes, len, &tables, &e), PSC_OK);
    size_t n = psc_viewer_workspace_size_tiled(OUT_W, OUT_H, map);
    void *ws = aligned_alloc(64, (n + 63u) & ~(size_t)63u);
    psc_viewer_t v;
    assert_int_equal(psc_viewer_init_tiled(&v, map, &t, tables.luts, tables.lut_count, OUT_W, OUT_H, ws, n), PSC_OK);
    psc_surface_t out = surface(PSC_PIX_RGB565);
    unsigned asked = 0;
    for (unsigned i = 0; i < views; i++) {
        psc_view_t view = view_of(rng, &v);
        assert_int_equal(psc_viewer_render(&v, &view, &out), PSC_OK);
        const uint32_t *want;
        unsigned k = psc_viewer_requests(&v, &want, NULL);
        for (unsigned j = 0; j < k; j++)
            assert_true(want[j] < t.tile_count && resident[want[j]] == NULL);
        asked += k;
        uint32_t ahead[256];
        unsigned m = psc_viewer_view_tiles(&v, &view, ahead, 256);
        for (unsigned j = 0; j < m; j++)
            assert_true(ahead[j] < t.tile_count);
    }
    *count = t.tile_count;
    free(out.pixels);
    free(ws);
    free(bytes);
    free(tiny.xrgb);
    free(slot);
    free(resident);
    return asked;
}

/* The range limits: the largest tiled map's geometry, sizes past it refused, and frames of it drawn - its rows reach
 * 2^31 in Q16.16 - with only its coarsest tile resident: every view draws, asks for tiles that exist. */
static void test_range_limits(void **state)
{
    (void)state;
    psc_tiles_t t;
    assert_int_equal(psc_tiles_level_count(PSC_TILES_MAX_WIDTH, PSC_TILES_MAX_HEIGHT), 12);
    assert_int_equal(psc_tiles_level_count(30000, 15000), 4);   /* 3750 x 1875: no exact half */
    assert_int_equal(psc_tiles_init(&t, PSC_TILES_MAX_WIDTH, PSC_TILES_MAX_HEIGHT, 12, PSC_PIX_RGB565, NULL), PSC_OK);
    assert_int_equal(t.tile_count, PSC_TILES_MAX_COUNT);
    assert_int_equal(psc_tiles_init(&t, PSC_TILES_MAX_WIDTH + 1u, 100, 1, PSC_PIX_RGB565, NULL), PSC_ERR_TOO_LARGE);
    assert_int_equal(psc_tiles_init(&t, 100, PSC_TILES_MAX_HEIGHT + 1u, 1, PSC_PIX_RGB565, NULL), PSC_ERR_TOO_LARGE);
    assert_int_equal(psc_tiles_init(&t, 4096, 2048, 13, PSC_PIX_RGB565, NULL), PSC_ERR_ARG);
    assert_int_equal(psc_tiles_init(&t, 4096, 2048, 0, PSC_PIX_RGB565, NULL), PSC_ERR_ARG);
    assert_int_equal(psc_tiles_init(&t, 4096, 2048, 1, PSC_PIX_PAL8, NULL), PSC_ERR_ARG);

    tsup_rng_t rng;
    tsup_rng_seed(&rng, 34);
    psc_envmap_t map = {PSC_PROJ_EQUIRECT, PSC_PIX_RGB565, PSC_TILES_MAX_WIDTH, PSC_TILES_MAX_HEIGHT, 0, NULL, NULL,
                        0, 0, (int32_t)PSC_BAM_90, -(int32_t)PSC_BAM_90};
    uint32_t count;
    unsigned asked = draw_from_coarsest(&map, 12, 48, &rng, sphere_view, &count);
    print_message("  65536 x 32768, %u tiles: 48 random views drawn from the coarsest tile alone, %u tiles asked for\n",
                  (unsigned)count, asked);
    assert_true(asked > 48);
}

/* Resident, a tiled frame is the flat frame's bytes. */
static void test_tiled_frames_are_flat_bytes(void **state)
{
    (void)state;
    /* the last map 1536 wide: columns by multiplying, not shifting (most photographs' widths) */
    psc_image_t img = test_image(MAP_W, MAP_H, 2), odd = test_image(1536, 768, 9);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 30);
    unsigned frames = 0, filters[3] = {0, 0, 0}, simd_used[4] = {0, 0, 0, 0};
    static const psc_pixfmt_t fmts[] = {PSC_PIX_RGB565, PSC_PIX_XRGB8888, PSC_PIX_RGB888, PSC_PIX_RGB565};
    for (int f = 0; f < 4; f++) {
        packs_t p;
        make_packs(&p, f == 3 ? &odd : &img, fmts[f], 256u << 20, "bytes.pano");
        load_all(p.tiled);
        viewer_t a, b;
        both_viewers(&p, &a, &b);
        for (int out = 0; out < 2; out++) {
            psc_surface_t sa, sb;
            surface_pair(out ? PSC_PIX_XRGB8888 : PSC_PIX_RGB565, &sa, &sb);
            for (unsigned i = 0; i < 40; i++) {
                psc_view_t view = random_view(&rng, &a.v);
                /* the tiled map through each path this build has: the scalar spans, the baseline vectors' kernel,
                 * and AUTO's (AVX2 where the CPU has it) */
                static const psc_simd_t paths[] = {PSC_SIMD_SCALAR, PSC_SIMD_VECTOR, PSC_SIMD_AUTO};
                psc_simd_t path = paths[i % 3u];
                if (psc_viewer_set_simd(&b.v, path) != PSC_OK)
                    assert_int_equal(psc_viewer_set_simd(&b.v, path = PSC_SIMD_AUTO), PSC_OK);
                simd_used[psc_viewer_simd(&b.v)]++;
                assert_int_equal(psc_viewer_render(&a.v, &view, &sa), PSC_OK);
                assert_int_equal(psc_viewer_render(&b.v, &view, &sb), PSC_OK);
                if (memcmp(sa.pixels, sb.pixels, (size_t)sa.stride * OUT_H) != 0)
                    fail_msg("map %d output %d view %u (yaw %u pitch %d hfov %u filter %d span %u, %s) differs", f,
                             out, i, (unsigned)view.yaw, (int)view.pitch, (unsigned)view.hfov, (int)view.filter,
                             (unsigned)view.span_log2, psc_simd_name(path));
                assert_int_equal(psc_viewer_requests(&b.v, NULL, NULL), 0);
                frames++;
                filters[view.filter]++;
            }
            free(sa.pixels);
            free(sb.pixels);
        }
        free(a.ws);
        free(b.ws);
        free_packs(&p);
    }
    print_message("  %u random views of 2048- and 1536-wide maps (nearest %u, bilinear %u, mip %u; the tiled map drawn "
                  "scalar %u, vector %u, avx2 %u times): tiled = flat, byte for byte\n", frames, filters[0], filters[1],
                  filters[2], simd_used[PSC_SIMD_SCALAR], simd_used[PSC_SIMD_VECTOR], simd_used[PSC_SIMD_AVX2]);
#if defined(__SSE2__) || defined(__ARM_NEON)
    assert_true(simd_used[PSC_SIMD_VECTOR] > 0);   /* this target has baseline vectors: their tiled kernels drew */
#endif
    assert_true(simd_used[PSC_SIMD_SCALAR] > 0);
    free(img.xrgb);
    free(odd.xrgb);
}

/* Levels narrower than a tile (a 128x64 map: every level one tile, its right half unused): at the seam a bilinear
 * sample's right texel wraps to column 0 of the same tile, which the vector kernels must not read as the next
 * column. Views across the seam, every path, RGB565 (whose kernels read a texel's right neighbour with it). */
static void test_narrow_levels_at_the_seam(void **state)
{
    (void)state;
    psc_image_t img = test_image(128, 64, 9);
    packs_t p;
    make_packs(&p, &img, PSC_PIX_RGB565, 256u << 20, "narrow.pano");
    load_all(p.tiled);
    viewer_t a, b;
    flat_viewer(&a, &p.flat);
    tiled_viewer(&b, p.tiled);
    psc_surface_t sa = surface(PSC_PIX_RGB565), sb = sa;
    sb.pixels = calloc(OUT_W * OUT_H, 4);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 128);
    static const psc_simd_t paths[] = {PSC_SIMD_SCALAR, PSC_SIMD_VECTOR, PSC_SIMD_AUTO};
    for (unsigned i = 0; i < 36; i++) {
        psc_view_t view = tsup_view_deg(tsup_rng_range(&rng, 150, 210), tsup_rng_range(&rng, -50, 50),
                                        tsup_rng_range(&rng, 20, 120), i % 2u ? PSC_FILTER_MIP : PSC_FILTER_BILINEAR,
                                        tsup_rng_below(&rng, 4));
        psc_viewer_clamp(&a.v, &view, 0);
        if (psc_viewer_set_simd(&b.v, paths[i % 3u]) != PSC_OK)
            assert_int_equal(psc_viewer_set_simd(&b.v, PSC_SIMD_AUTO), PSC_OK);
        assert_int_equal(psc_viewer_render(&a.v, &view, &sa), PSC_OK);
        assert_int_equal(psc_viewer_render(&b.v, &view, &sb), PSC_OK);
        if (memcmp(sa.pixels, sb.pixels, (size_t)sa.stride * OUT_H) != 0)
            fail_msg("view %u (yaw %u pitch %d hfov %u filter %d, %s) differs", i, (unsigned)view.yaw,
                     (int)view.pitch, (unsigned)view.hfov, (int)view.filter, psc_simd_name(psc_viewer_simd(&b.v)));
    }
    print_message("  a 128x64 map, every level one tile: 36 views across the seam, tiled = flat, every path\n");
    free_frames(&sa, &sb, &a, &b, &p, &img);
}

/* Every path draws a tiled map's frames alike, whatever is resident: random views (every filter, zoomed out to the
 * pyramid's levels too, where nearest and bilinear read a level of their own), with every tile, with a random
 * half of them and with the coarsest level alone; the scalar spans against the baseline vector kernel and AUTO's. */
static void test_paths_agree_at_any_residency(void **state)
{
    (void)state;
    psc_image_t img = test_image(MAP_W, MAP_H, 5);
    static const psc_simd_t paths[] = {PSC_SIMD_SCALAR, PSC_SIMD_VECTOR, PSC_SIMD_AUTO};
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 77);
    unsigned frames = 0;
    for (int fmt = 0; fmt < 2; fmt++) {
        for (int residency = 0; residency < 3; residency++) {
            packs_t p;
            make_packs(&p, &img, fmt ? PSC_PIX_RGB888 : PSC_PIX_RGB565, 256u << 20, "agree.pano");
            const psc_tiles_t *g = psc_io_tiled_tiles(p.tiled);
            uint32_t *some = malloc(g->tile_count * sizeof *some);
            assert_non_null(some);
            unsigned n = 0;
            for (uint32_t i = 0; i < g->tile_count; i++)
                if (residency == 0 || (residency == 1 && tsup_rng_below(&rng, 2)))
                    some[n++] = i;
            char err[256];
            assert_int_equal(psc_io_tiled_load(p.tiled, some, n, err, sizeof err), 0);
            free(some);
            viewer_t b;
            tiled_viewer(&b, p.tiled);
            psc_surface_t s[3];
            for (int k = 0; k < 3; k++)
                s[k] = surface(fmt ? PSC_PIX_XRGB8888 : PSC_PIX_RGB565);
            for (unsigned i = 0; i < 12; i++, frames++) {
                psc_view_t view = random_view(&rng, &b.v);
                view.hfov = tsup_bam_from_deg(tsup_rng_range(&rng, 20, 120));
                psc_viewer_clamp(&b.v, &view, 0);
                for (int k = 0; k < 3; k++) {
                    if (psc_viewer_set_simd(&b.v, paths[k]) != PSC_OK)
                        assert_int_equal(psc_viewer_set_simd(&b.v, PSC_SIMD_SCALAR), PSC_OK);
                    assert_int_equal(psc_viewer_render(&b.v, &view, &s[k]), PSC_OK);
                }
                for (int k = 1; k < 3; k++) {
                    size_t bytes = (size_t)s[0].stride * OUT_H, at = 0;
                    while (at < bytes && ((uint8_t *)s[0].pixels)[at] == ((uint8_t *)s[k].pixels)[at])
                        at++;
                    if (at < bytes)
                        fail_msg("%s map, residency %d, view %u (yaw %u pitch %d hfov %u filter %d span %u): %s "
                                 "differs from scalar at pixel (%zu, %zu)", fmt ? "rgb888" : "rgb565", residency, i,
                                 (unsigned)view.yaw, (int)view.pitch, (unsigned)view.hfov, (int)view.filter,
                                 (unsigned)view.span_log2, psc_simd_name(paths[k]), at % s[0].stride / (fmt ? 4u : 2u),
                                 at / s[0].stride);
                }
            }
            for (int k = 0; k < 3; k++)
                free(s[k].pixels);
            free(b.ws);
            free_packs(&p);
        }
    }
    print_message("  %u random views (every tile, a random half, the coarsest level): the scalar spans' bytes through "
                  "every path\n", frames);
    free(img.xrgb);
}

/* PSNR (8-bit RGB) of two RGB565 frames. */
static double psnr565(const psc_surface_t *a, const psc_surface_t *b)
{
    double se = 0;
    for (unsigned y = 0; y < OUT_H; y++)
        for (unsigned x = 0; x < OUT_W; x++) {
            uint8_t p[3], q[3];
            tsup_surface_rgb(a, x, y, p);
            tsup_surface_rgb(b, x, y, q);
            for (int c = 0; c < 3; c++)
                se += (double)(p[c] - q[c]) * (p[c] - q[c]);
        }
    return 10.0 * log10(255.0 * 255.0 / (se / (3.0 * OUT_W * OUT_H) + 1e-12));
}

/* Zoomed out, nearest and bilinear read the finest level with at most two texels a pixel: a wide view of a tiled map
 * asks for about as many texels as it has pixels (not the whole map), and shows what the flat pyramid shows. */
static void test_wide_views_read_few_tiles(void **state)
{
    (void)state;
    psc_image_t img = test_image(MAP_W * 2u, MAP_H * 2u, 6);   /* 4096 x 2048: level 0 is 128 tiles */
    packs_t p;
    make_packs(&p, &img, PSC_PIX_RGB565, 256u << 20, "wide.pano");
    viewer_t a, b;
    flat_viewer(&a, &p.flat);
    tiled_viewer(&b, p.tiled);
    psc_surface_t sa = surface(PSC_PIX_RGB565), sb = sa;
    sb.pixels = calloc(OUT_W * OUT_H, 4);
    for (int filter = 0; filter < 2; filter++) {
        psc_view_t view = {tsup_bam_from_deg(40), (int32_t)tsup_bam_from_deg(15), tsup_bam_from_deg(115),
                           (psc_filter_t)filter, 2};
        unsigned asked = 0;
        for (;;) {
            assert_int_equal(psc_viewer_render(&b.v, &view, &sb), PSC_OK);
            const uint32_t *want;
            unsigned n = psc_viewer_requests(&b.v, &want, NULL);
            if (n == 0)
                break;
            asked += n;
            char err[256];
            assert_int_equal(psc_io_tiled_load(p.tiled, want, n, err, sizeof err), 0);
            for (unsigned k = 0; k < n; k++)
                assert_true(psc_tiles_level_of(psc_io_tiled_tiles(p.tiled), want[k]) > 0);   /* never level 0 */
        }
        view.filter = PSC_FILTER_MIP;
        assert_int_equal(psc_viewer_render(&a.v, &view, &sa), PSC_OK);
        double db = psnr565(&sa, &sb);
        print_message("  hfov 115 at %ux%u, %s: %u tiles read (level 0 has %u), %.1f dB against the flat mip frame\n",
                      OUT_W, OUT_H, filter ? "bilinear" : "nearest", asked,
                      (unsigned)(psc_io_tiled_tiles(p.tiled)->level[1].first), db);
        assert_true(db >= (filter ? 32.0 : 28.0));   /* measured 37.8 and 33.2 */
        assert_true(asked <= 40u);                    /* (bilinear finds nearest's tiles resident) */
    }
    free_frames(&sa, &sb, &a, &b, &p, &img);
}

/* A starved cache draws every frame (coarser), asks for its tiles, and sharpens to the flat bytes. */
static void test_starved_cache_sharpens(void **state)
{
    (void)state;
    psc_image_t img = test_image(MAP_W, MAP_H, 3);
    packs_t p;
    make_packs(&p, &img, PSC_PIX_RGB565, 0, "starved.pano");   /* budget 0: the fewest slots */
    assert_int_equal(psc_io_tiled_slots(p.tiled), PSC_IO_TILES_MIN_SLOTS);
    viewer_t a, b;
    flat_viewer(&a, &p.flat);
    tiled_viewer(&b, p.tiled);
    psc_surface_t sa = surface(PSC_PIX_RGB565), sb = sa, sc = sa;
    sb.pixels = calloc(OUT_W * OUT_H, 4);
    sc.pixels = calloc(OUT_W * OUT_H, 4);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 31);
    unsigned coarse = 0;
    for (unsigned i = 0; i < 12; i++) {
        psc_view_t view = {tsup_rng_u32(&rng), (int32_t)tsup_bam_from_deg(tsup_rng_range(&rng, -60, 60)),
                           tsup_bam_from_deg(tsup_rng_range(&rng, 20, 60)), (psc_filter_t)(i % 3u), 2};   /* level 0 */
        if (i % 3u == 2u)   /* the pyramid, zoomed out to its levels */
            view.hfov = tsup_bam_from_deg(tsup_rng_range(&rng, 60, 110));
        assert_int_equal(psc_viewer_render(&a.v, &view, &sa), PSC_OK);
        unsigned passes = 0, first = 0;
        for (;; passes++) {
            /* a coarser frame is the same bytes through the scalar spans as through the vector kernels */
            assert_int_equal(psc_viewer_set_simd(&b.v, PSC_SIMD_SCALAR), PSC_OK);
            assert_int_equal(psc_viewer_render(&b.v, &view, &sc), PSC_OK);
            assert_int_equal(psc_viewer_set_simd(&b.v, PSC_SIMD_AUTO), PSC_OK);
            assert_int_equal(psc_viewer_render(&b.v, &view, &sb), PSC_OK);
            assert_memory_equal(sb.pixels, sc.pixels, (size_t)sb.stride * OUT_H);
            const uint32_t *want;
            uint32_t dropped;
            unsigned n = psc_viewer_requests(&b.v, &want, &dropped);
            if (passes == 0)
                first = n;
            if (n == 0)
                break;
            coarse++;
            assert_true(passes < 8);
            char err[256];
            assert_int_equal(psc_io_tiled_load(p.tiled, want, n, err, sizeof err), 0);
        }
        if (i == 0)   /* the first frame had only the coarsest level: level 0, cold, asked for one tile of it */
            assert_int_equal(first, 1);
        assert_memory_equal(sa.pixels, sb.pixels, (size_t)sa.stride * OUT_H);
    }
    uint64_t loaded;
    psc_io_tiled_counts(p.tiled, &loaded, NULL);
    print_message("  a cache of %u slots: every frame drawn (%u coarser ones, the same bytes scalar and %s), sharpened "
                  "to the flat bytes; %llu tiles read\n", psc_io_tiled_slots(p.tiled), coarse,
                  psc_simd_name(psc_viewer_simd(&b.v)), (unsigned long long)loaded);
    assert_true(coarse >= 12);
    free(sa.pixels);
    free(sb.pixels);
    free(sc.pixels);
    free(a.ws);
    free(b.ws);
    free_packs(&p);
    free(img.xrgb);
}

/* Columns [x0, x0 + w) and rows [y0, y0 + h) of img. */
static psc_image_t crop(const psc_image_t *img, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h)
{
    psc_image_t c = {w, h, malloc((size_t)w * h * sizeof(uint32_t))};
    assert_non_null(c.xrgb);
    for (uint32_t y = 0; y < h; y++)
        memcpy(&c.xrgb[(size_t)y * w], &img->xrgb[(size_t)(y0 + y) * img->width + x0], w * sizeof(uint32_t));
    return c;
}

/* Draw a view through the tiled viewer until it asks for no tile, loading what it asks for after each frame (the
 * cache's slots permitting); returns the frames drawn before the last. */
static unsigned render_sharp(viewer_t *b, psc_io_tiled_t *t, const psc_view_t *view, psc_surface_t *out)
{
    for (unsigned passes = 0;; passes++) {
        assert_int_equal(psc_viewer_render(&b->v, view, out), PSC_OK);
        const uint32_t *want;
        unsigned n = psc_viewer_requests(&b->v, &want, NULL);
        if (n == 0)
            return passes;
        assert_true(passes < 8);
        char err[256];
        assert_int_equal(psc_io_tiled_load(t, want, n, err, sizeof err), 0);
    }
}

/*
 * Partial panoramas (part of a turn: a gigapixel of one wall of a hall) tile as full turns do:
 *  - where the tiled viewer reads level 0 (nearest and bilinear zoomed in to at most two texels a pixel), its
 *    frames are the flat map's bytes, every map and output format, from a starved cache too;
 *  - a partial map cut from a full turn at tile-aligned edges draws the full turn's bytes, every filter and
 *    level (its columns clamp at its edges where the full turn's wrap; the views here stay inside it);
 *  - the largest partial map (65536 columns over 120 degrees) draws from its coarsest tile alone.
 */
static void test_partial_panoramas(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 35);
    static const psc_pixfmt_t fmts[] = {PSC_PIX_RGB565, PSC_PIX_XRGB8888, PSC_PIX_RGB888};
    psc_image_t img = test_image(1536, 640, 11);   /* 135 x 56.25 degrees, 11.4 texels a degree */
    unsigned frames = 0, coarse = 0;
    for (int f = 0; f < 3; f++) {
        psc_pack_options_t o = pack_options(fmts[f]);
        assert_int_equal(psc_io_pack_options_set_lon_range(&o, -75.0, 60.0), 0);
        assert_int_equal(psc_io_pack_options_set_lat_range(&o, 30.0, -26.25), 0);
        packs_t p;
        make_packs_with(&p, &img, &o, f == 0 ? 0u : 256u << 20, "partial.pano");   /* RGB565: the fewest slots */
        viewer_t a, b;
        both_viewers(&p, &a, &b);
        for (int out = 0; out < 2; out++) {
            psc_surface_t sa, sb;
            surface_pair(out ? PSC_PIX_XRGB8888 : PSC_PIX_RGB565, &sa, &sb);
            for (unsigned i = 0; i < 16; i++) {
                psc_view_t view = {tsup_bam_from_deg(tsup_rng_range(&rng, -100, 85)),
                                   (int32_t)tsup_bam_from_deg(tsup_rng_range(&rng, -40, 40)),
                                   tsup_bam_from_deg(tsup_rng_range(&rng, 3, 50)), (psc_filter_t)(i % 2u),
                                   (uint8_t)tsup_rng_below(&rng, PSC_SPAN_LOG2_MAX + 1u)};
                psc_viewer_clamp(&a.v, &view, tsup_bam_from_deg(2));   /* inside the map, as the device keeps it */
                assert_int_equal(psc_viewer_render(&a.v, &view, &sa), PSC_OK);
                coarse += render_sharp(&b, p.tiled, &view, &sb);
                if (memcmp(sa.pixels, sb.pixels, (size_t)sa.stride * OUT_H) != 0)
                    fail_msg("partial map %d output %d view %u (yaw %u pitch %d hfov %u filter %d) differs", f, out, i,
                             (unsigned)view.yaw, (int)view.pitch, (unsigned)view.hfov, (int)view.filter);
                frames++;
            }
            free(sa.pixels);
            free(sb.pixels);
        }
        free(a.ws);
        free(b.ws);
        free_packs(&p);
    }
    free(img.xrgb);
    print_message("  a partial panorama, %u random views zoomed in (nearest and bilinear, 3 map and 2 output formats; "
                  "%u coarser frames first): tiled = flat, byte for byte\n", frames, coarse);
    assert_true(coarse > 0);

    /* a quarter of a full turn's area cut at its tiles' edges: its levels are the full turn's inside (the pyramid's
     * filter reaches one texel past a level's edge) */
    psc_image_t full = test_image(MAP_W, MAP_H, 12), part = crop(&full, MAP_W / 4u, MAP_H / 4u, MAP_W / 2u, MAP_H / 2u);
    unsigned same = 0, filters[3] = {0, 0, 0};
    for (int f = 0; f < 2; f++) {
        packs_t pf, pp;
        make_packs(&pf, &full, fmts[f], 256u << 20, "turn.pano");
        psc_pack_options_t o = pack_options(fmts[f]);
        assert_int_equal(psc_io_pack_options_set_lon_range(&o, -90.0, 90.0), 0);
        assert_int_equal(psc_io_pack_options_set_lat_range(&o, 45.0, -45.0), 0);
        make_packs_with(&pp, &part, &o, 256u << 20, "cut.pano");
        load_all(pf.tiled);
        load_all(pp.tiled);
        viewer_t a, b;
        tiled_viewer(&a, pf.tiled);
        tiled_viewer(&b, pp.tiled);
        psc_surface_t sa = surface(PSC_PIX_XRGB8888), sb = sa;
        sb.pixels = calloc(OUT_W * OUT_H, 4);
        for (unsigned i = 0; i < 24; i++) {   /* up to 40 degrees from the middle: 50 inside the cut's edges */
            psc_view_t view = {tsup_bam_from_deg(tsup_rng_range(&rng, -25, 25)),
                               (int32_t)tsup_bam_from_deg(tsup_rng_range(&rng, -10, 10)),
                               tsup_bam_from_deg(tsup_rng_range(&rng, 5, 60)), (psc_filter_t)(i % 3u), 2};
            assert_int_equal(psc_viewer_render(&a.v, &view, &sa), PSC_OK);
            assert_int_equal(psc_viewer_render(&b.v, &view, &sb), PSC_OK);
            if (memcmp(sa.pixels, sb.pixels, (size_t)sa.stride * OUT_H) != 0)
                fail_msg("map %d view %u (yaw %u pitch %d hfov %u filter %d): the cut differs from the full turn", f, i,
                         (unsigned)view.yaw, (int)view.pitch, (unsigned)view.hfov, (int)view.filter);
            same++;
            filters[view.filter]++;
        }
        free(sa.pixels);
        free(sb.pixels);
        free(a.ws);
        free(b.ws);
        free_packs(&pf);
        free_packs(&pp);
    }
    free(full.xrgb);
    free(part.xrgb);
    print_message("  a partial map cut from a full turn: %u views (nearest %u, bilinear %u, mip %u) the full turn's "
                  "bytes\n", same, filters[0], filters[1], filters[2]);

    /* the largest partial map, 65536 x 4096 over 120 x 7.5 degrees, its coarsest tile alone resident */
    psc_envmap_t strip = {PSC_PROJ_EQUIRECT, PSC_PIX_RGB565, PSC_TILES_MAX_WIDTH, 4096, 0, NULL, NULL,
                          tsup_bam_from_deg(-60), tsup_bam_from_deg(120), (int32_t)tsup_bam_from_deg(3.75),
                          -(int32_t)tsup_bam_from_deg(3.75)};
    uint32_t count;
    unsigned asked = draw_from_coarsest(&strip, psc_tiles_level_count(PSC_TILES_MAX_WIDTH, 4096), 32, &rng, strip_view,
                                        &count);
    print_message("  65536 x 4096 over 120 degrees, %u tiles: 32 views drawn from the coarsest tile alone, %u tiles "
                  "asked for\n", (unsigned)count, asked);
    assert_true(asked > 32);
}

/* The device's way: a loader thread reads the tiles a frame missed while the next frames are drawn (coarser where
 * they are absent); once it has published them the frames are the flat bytes. */
static void test_loader_thread_sharpens(void **state)
{
    (void)state;
    psc_image_t img = test_image(MAP_W, MAP_H, 5);
    packs_t p;
    make_packs(&p, &img, PSC_PIX_XRGB8888, 48u * 256u * 1024u, "loader.pano");
    char err[512];
    assert_int_equal(psc_io_tiled_start_loader(p.tiled, err, sizeof err), 0);
    viewer_t a, b;
    flat_viewer(&a, &p.flat);
    tiled_viewer(&b, p.tiled);
    psc_surface_t sa = surface(PSC_PIX_RGB565), sb = sa;
    sb.pixels = calloc(OUT_W * OUT_H, 4);
    unsigned frames = 0, coarse = 0;
    for (unsigned i = 0; i < 16; i++) {   /* a pan: each view 25 degrees on */
        psc_view_t view = {tsup_bam_from_deg(25.0 * i), (int32_t)tsup_bam_from_deg(10), tsup_bam_from_deg(50),
                           (psc_filter_t)(i % 3u), 2};
        assert_int_equal(psc_viewer_render(&a.v, &view, &sa), PSC_OK);
        for (;;) {
            err[0] = '\0';
            psc_io_tiled_publish(p.tiled, err, sizeof err);
            assert_string_equal(err, "");
            assert_int_equal(psc_viewer_render(&b.v, &view, &sb), PSC_OK);
            frames++;
            const uint32_t *want;
            unsigned n = psc_viewer_requests(&b.v, &want, NULL);
            if (n == 0)
                break;
            coarse++;
            assert_true(memcmp(sa.pixels, sb.pixels, (size_t)sa.stride * OUT_H) != 0);   /* coarser meanwhile */
            psc_io_tiled_request(p.tiled, want, n);
            for (;;) {   /* (the test waits for them; a device draws on) */
                unsigned left = psc_io_tiled_pending(p.tiled);
                if (psc_io_tiled_publish(p.tiled, err, sizeof err) >= left)
                    break;
                usleep(1000);
            }
            assert_string_equal(err, "");
        }
        assert_memory_equal(sa.pixels, sb.pixels, (size_t)sa.stride * OUT_H);
    }
    uint64_t loaded;
    psc_io_tiled_counts(p.tiled, &loaded, NULL);
    print_message("  loader thread, a cache of %u slots: %u frames, %u of them coarser while tiles were read; %llu "
                  "tiles read; every view sharpened to the flat bytes\n", psc_io_tiled_slots(p.tiled), frames, coarse,
                  (unsigned long long)loaded);
    assert_true(coarse > 0);
    free_frames(&sa, &sb, &a, &b, &p, &img);
}

/* Golden views of a tiled pack against the double-precision reference of its map (PSNR over 8-bit RGB of the
 * XRGB8888 output): zoomed in to a few degrees (level 0, bilinear, against bilinear), and a wide view through the
 * pyramid (mip, against a 4 x 4 supersampled reference). */
static void test_golden_deep_and_wide(void **state)
{
    (void)state;
    psc_image_t img = test_image(MAP_W * 2u, MAP_H * 2u, 8);
    packs_t p;
    make_packs(&p, &img, PSC_PIX_XRGB8888, 256u << 20, "golden.pano");
    load_all(p.tiled);
    viewer_t b;
    tiled_viewer(&b, p.tiled);
    psc_envmap_t ref_map = p.flat.map;   /* the image itself, as the reference samples it */
    ref_map.format = PSC_PIX_XRGB8888;
    ref_map.pixels = img.xrgb;
    ref_map.stride = img.width * 4u;
    psc_surface_t sb = surface(PSC_PIX_XRGB8888);
    double *ref = malloc(OUT_W * OUT_H * 3u * sizeof *ref);
    assert_non_null(ref);
    static const struct {
        double yaw, pitch, hfov;
        psc_filter_t filter;
        unsigned ss;
        double bound;
    } g[] = {
        {37.5, 12, 3, PSC_FILTER_BILINEAR, 1, 50.0},   /* about 11 screen pixels a texel (measured 57.1) */
        {-120, -55, 2.5, PSC_FILTER_BILINEAR, 1, 50.0},  /* (57.8) */
        {200, 30, 110, PSC_FILTER_MIP, 4, 30.0},       /* about 3 texels a pixel: levels 1 and 2 (32.4) */
        {10, -80, 100, PSC_FILTER_MIP, 4, 30.0},       /* a pole in view (33.6) */
    };
    for (size_t i = 0; i < sizeof g / sizeof *g; i++) {
        psc_view_t view = {tsup_bam_from_deg(g[i].yaw), (int32_t)tsup_bam_from_deg(g[i].pitch),
                           tsup_bam_from_deg(g[i].hfov), g[i].filter, 2};
        assert_int_equal(psc_viewer_render(&b.v, &view, &sb), PSC_OK);
        psc_view_t rv = view;
        rv.filter = PSC_FILTER_BILINEAR;
        tsup_ref_render(&ref_map, &rv, OUT_W, OUT_H, g[i].ss, ref);
        double db = tsup_psnr(tsup_mse_surface(&sb, ref));
        print_message("  yaw %.1f pitch %.1f hfov %.1f %s: %.1f dB against the double-precision reference%s (at "
                      "least %.0f)\n", g[i].yaw, g[i].pitch, g[i].hfov, g[i].filter == PSC_FILTER_MIP ? "mip" : "bilinear",
                      db, g[i].ss > 1 ? ", 4x4 supersampled" : "", g[i].bound);
        assert_true(db >= g[i].bound);
    }
    free(ref);
    free(sb.pixels);
    free(b.ws);
    free_packs(&p);
    free(img.xrgb);
}

/* The tiles of a view (for prefetching where the view is going): the tiles a frame of the view reads at the level
 * the view's middle takes, found from exact directions on a grid of its pixels. Zoomed in (level 0 everywhere),
 * nearly every tile the frame asks for from a cache all but empty (measured 211 of 213: a frame's positions come
 * from the look-up table, within a fraction of a texel of the exact ones, and a tile's corner can fall between). */
static void test_view_tiles_cover_the_frame(void **state)
{
    (void)state;
    psc_image_t img = test_image(MAP_W * 2u, MAP_H * 2u, 7);
    packs_t p;
    make_packs(&p, &img, PSC_PIX_RGB565, 256u << 20, "view.pano");
    viewer_t b;
    tiled_viewer(&b, p.tiled);
    /* a tile of each of the two finest levels resident (at a corner): a level with none asks for one tile alone */
    const psc_tiles_t *g = psc_io_tiled_tiles(p.tiled);
    const uint32_t corner[2] = {g->level[0].first, g->level[1].first};
    char err[256];
    assert_int_equal(psc_io_tiled_load(p.tiled, corner, 2, err, sizeof err), 0);
    psc_surface_t sb = surface(PSC_PIX_RGB565);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 33);
    unsigned asked = 0, covered = 0;
    for (unsigned i = 0; i < 40; i++) {
        psc_view_t view = {tsup_rng_u32(&rng), (int32_t)tsup_bam_from_deg(tsup_rng_range(&rng, -80, 80)),
                           tsup_bam_from_deg(tsup_rng_range(&rng, 10, 40)), (psc_filter_t)(i % 2u), 2};
        uint32_t v[256];
        unsigned nv = psc_viewer_view_tiles(&b.v, &view, v, 256);
        assert_true(nv > 0 && nv < 256);
        assert_int_equal(psc_viewer_render(&b.v, &view, &sb), PSC_OK);   /* nothing resident but the coarsest */
        const uint32_t *want;
        uint32_t dropped;
        unsigned n = psc_viewer_requests(&b.v, &want, &dropped);
        for (unsigned k = 0; k < n; k++) {
            bool in = false;
            for (unsigned j = 0; j < nv && !in; j++)
                in = v[j] == want[k];
            covered += in;
        }
        asked += n;
    }
    print_message("  40 views zoomed in, a tile of the two finest levels resident: the views' tiles hold %u of the %u "
                  "tiles their frames asked for\n", covered, asked);
    assert_true(asked > 40);
    assert_true(covered * 100u >= asked * 97u);
    free(sb.pixels);
    free(b.ws);
    free_packs(&p);
    free(img.xrgb);
}

/* A corrupt tile: a message, and the coarser level there; a truncated pack: refused at opening. */
static void test_corrupt_and_truncated(void **state)
{
    (void)state;
    psc_image_t img = test_image(MAP_W, MAP_H, 4);
    packs_t p;
    make_packs(&p, &img, PSC_PIX_RGB565, 256u << 20, "corrupt.pano");
    const psc_pack_t *pk = psc_io_tiled_pack(p.tiled);
    uint64_t at = pk->store_offset + pk->tile_index[5].offset + 100u, size = pk->store_offset + pk->store_size;
    psc_io_tiled_close(p.tiled);
    FILE *f = fopen(p.path, "r+b");
    assert_non_null(f);
    assert_int_equal(fseek(f, (long)at, SEEK_SET), 0);
    int c = fgetc(f);
    assert_int_equal(fseek(f, (long)at, SEEK_SET), 0);
    fputc(c ^ 0x5A, f);
    fclose(f);
    char err[512];
    assert_int_equal(psc_io_tiled_open(p.path, 256u << 20, &p.tiled, err, sizeof err), 0);
    uint32_t five = 5;
    assert_int_equal(psc_io_tiled_load(p.tiled, &five, 1, err, sizeof err), -1);
    assert_non_null(strstr(err, p.path));
    assert_non_null(strstr(err, "tile 5"));
    print_message("  %s\n", err);
    assert_null(psc_io_tiled_tiles(p.tiled)->resident[5]);
    psc_io_tiled_close(p.tiled);
    /* truncated: the store ends past the file */
    assert_int_equal(truncate(p.path, (off_t)(size - 1000u)), 0);
    assert_int_equal(psc_io_tiled_open(p.path, 256u << 20, &p.tiled, err, sizeof err), -1);
    assert_non_null(strstr(err, "truncated"));
    print_message("  %s\n", err);
    p.tiled = NULL;
    free_packs(&p);
    free(img.xrgb);
}

/* ---- JPEG tiles ---------------------------------------------------------------------------------------------- */

/* A texel of a tile in format fmt as 0xRRGGBB (RGB565 widened by bit replication, as a display shows it). */
static uint32_t texel_rgb(const uint8_t *row, uint32_t c, psc_pixfmt_t fmt)
{
    if (fmt == PSC_PIX_RGB565) {
        uint32_t v = (uint32_t)row[2 * c] | (uint32_t)row[2 * c + 1] << 8;
        uint32_t r = v >> 11, g = (v >> 5) & 63u, b = v & 31u;
        return (r << 3 | r >> 2) << 16 | (g << 2 | g >> 4) << 8 | (b << 3 | b >> 2);
    }
    const uint8_t *p = row + (size_t)c * (fmt == PSC_PIX_RGB888 ? 3u : 4u);
    return (uint32_t)p[2] << 16 | (uint32_t)p[1] << 8 | p[0];
}

static double psnr_of(double sq, double n)
{
    return sq > 0 ? 10.0 * log10(255.0 * 255.0 / (sq / n)) : 99.0;
}

/* A JPEG-tiled pack of img at path (quality q), opened with a cache of budget bytes. */
static psc_io_tiled_t *jpeg_pack(const psc_image_t *img, psc_pixfmt_t fmt, unsigned q, const char *path, size_t budget)
{
    psc_pack_options_t o = pack_options(fmt);
    o.tile_codec = PSC_TILE_CODEC_JPEG;
    o.tile_quality = (uint8_t)q;
    char err[512];
    psc_io_tiled_t *t = NULL;
    if (psc_io_tiles_write_image(path, img, &o, err, sizeof err) != 0 ||
        psc_io_tiled_open(path, budget, &t, err, sizeof err) != 0)
        fail_msg("%s", err);
    return t;
}

/* Every level's pixels of two tilings of one map (all resident): the PSNR of b against a over 8-bit RGB. */
static double tiles_psnr(const psc_tiles_t *a, const psc_tiles_t *b)
{
    double sq = 0, n = 0;
    for (uint32_t k = 0; k < a->level_count; k++)
        for (uint32_t r = 0; r < a->level[k].height; r++)
            for (uint32_t c = 0; c < a->level[k].width; c++) {
                uint32_t i = psc_tiles_at(a, k, r, c), row = r % PSC_TILE_SIDE, col = c % PSC_TILE_SIDE;
                uint32_t x = texel_rgb((const uint8_t *)a->resident[i] + (size_t)row * a->tile_stride, col, a->format);
                uint32_t y = texel_rgb((const uint8_t *)b->resident[i] + (size_t)row * b->tile_stride, col, b->format);
                for (int sh = 0; sh < 24; sh += 8) {
                    double d = (double)((x >> sh) & 255u) - (double)((y >> sh) & 255u);
                    sq += d * d;
                }
                n += 3;
            }
    return psnr_of(sq, n);
}

/* Two frames of one format: PSNR over 8-bit RGB. */
static double frame_psnr(const psc_surface_t *a, const psc_surface_t *b)
{
    double sq = 0;
    for (uint32_t y = 0; y < OUT_H; y++)
        for (uint32_t x = 0; x < OUT_W; x++) {
            uint32_t p = texel_rgb((const uint8_t *)a->pixels + (size_t)y * a->stride, x, a->format);
            uint32_t q = texel_rgb((const uint8_t *)b->pixels + (size_t)y * b->stride, x, b->format);
            for (int sh = 0; sh < 24; sh += 8) {
                double d = (double)((p >> sh) & 255u) - (double)((q >> sh) & 255u);
                sq += d * d;
            }
        }
    return psnr_of(sq, 3.0 * OUT_W * OUT_H);
}

/* The sample panorama (a photograph, assets/), halved to 2048 x 1024 by 2 x 2 means. */
static psc_image_t photo(void)
{
    psc_image_t full, half = {MAP_W, MAP_H, malloc((size_t)MAP_W * MAP_H * sizeof(uint32_t))};
    char err[512];
    if (psc_io_image_load("assets/pannellum-examplepano.jpg", &full, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(full.width, 2u * MAP_W);
    assert_non_null(half.xrgb);
    for (uint32_t y = 0; y < MAP_H; y++)
        for (uint32_t x = 0; x < MAP_W; x++) {
            uint32_t acc[3] = {0, 0, 0};
            for (uint32_t k = 0; k < 4; k++) {
                uint32_t p = full.xrgb[(size_t)(2u * y + k / 2u) * full.width + 2u * x + k % 2u];
                for (int c = 0; c < 3; c++)
                    acc[c] += (p >> (16 - 8 * c)) & 255u;
            }
            half.xrgb[(size_t)y * MAP_W + x] = 0xFF000000u | ((acc[0] + 2u) / 4u) << 16 | ((acc[1] + 2u) / 4u) << 8 |
                                                ((acc[2] + 2u) / 4u);
        }
    psc_io_image_free(&full);
    return half;
}

typedef struct {
    double tiles, frame_lo, frame_sum, share;
    unsigned frames;
} jpeg_figures_t;

/* One map's JPEG tiles against its raw ones in format fmt: every level's pixels, 20 random frames, the store's
 * share. */
static jpeg_figures_t jpeg_against_raw(const psc_image_t *img, psc_pixfmt_t fmt, tsup_rng_t *rng)
{
    packs_t p;
    make_packs(&p, img, fmt, 256u << 20, "raw.pano");
    psc_io_tiled_t *j = jpeg_pack(img, fmt, PSC_IO_TILE_JPEG_QUALITY, temp_path("jpeg.pano"), 256u << 20);
    load_all(p.tiled);
    load_all(j);
    const psc_pack_t *pr = psc_io_tiled_pack(p.tiled), *pj = psc_io_tiled_pack(j);
    assert_int_equal(pj->tile_codec, PSC_TILE_CODEC_JPEG);
    assert_int_equal(pr->tile_codec, PSC_TILE_CODEC_RAW);
    /* the memory the cache says it holds counts the decoder's buffer */
    assert_true(psc_io_tiled_bytes(j) >= psc_io_tiled_bytes(p.tiled) + PSC_TILE_JPEG_MAX_BYTES(pj->tiles.tile_bytes));
    jpeg_figures_t r = {tiles_psnr(psc_io_tiled_tiles(p.tiled), psc_io_tiled_tiles(j)), 99, 0,
                        (double)pj->store_size / (double)pr->store_size, 0};
    viewer_t a, b;
    tiled_viewer(&a, p.tiled);
    tiled_viewer(&b, j);
    psc_surface_t sa, sb;
    surface_pair(fmt == PSC_PIX_RGB565 ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888, &sa, &sb);
    for (unsigned i = 0; i < 20; i++) {
        psc_view_t view = random_view(rng, &a.v);
        assert_int_equal(psc_viewer_render(&a.v, &view, &sa), PSC_OK);
        assert_int_equal(psc_viewer_render(&b.v, &view, &sb), PSC_OK);
        assert_int_equal(psc_viewer_requests(&b.v, NULL, NULL), 0);
        double fp = frame_psnr(&sa, &sb);
        r.frame_lo = fmin(r.frame_lo, fp);
        r.frame_sum += fp;
        r.frames++;
    }
    print_message("  %s: the store %.1f %% of raw tiles' (%.1f KB a tile on average), every level's pixels %.1f dB "
                  "against the raw tiles', 20 random frames %.1f dB at least (mean %.1f)\n", psc_io_pixfmt_name(fmt),
                  100.0 * r.share, pj->store_size / 1024.0 / pj->tiles.tile_count, r.tiles, r.frame_lo,
                  r.frame_sum / r.frames);
    free(sa.pixels);
    free(sb.pixels);
    free(a.ws);
    free(b.ws);
    psc_io_tiled_close(j);
    unlink(temp_path("jpeg.pano"));
    free_packs(&p);
    return r;
}

/* JPEG tiles (the default quality) against raw ones of the same map: the sample photograph in each map format,
 * and the test image (a hash of noise and one-pixel lines: the worst case for JPEG), each within a stated PSNR
 * (over 8-bit RGB; measured figures beside the bounds) and a share of the raw tiles' bytes. */
static void test_jpeg_tiles(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 31);
    psc_image_t img = photo();
    static const psc_pixfmt_t fmts[] = {PSC_PIX_RGB888, PSC_PIX_XRGB8888, PSC_PIX_RGB565};
    print_message("  the sample photograph, 2048x1024, JPEG quality %u:\n", PSC_IO_TILE_JPEG_QUALITY);
    for (int f = 0; f < 3; f++) {
        jpeg_figures_t r = jpeg_against_raw(&img, fmts[f], &rng);
        /* measured: 7.5 (xrgb8888), 10.0 (rgb888) and 15.0 % (rgb565) of the bytes; levels 38.6 dB (rgb565 36.6, its
         * own rounding counted), frames 36.2, 39.9 and 34.1 dB at least (means 48.0, 51.5, 41.9) */
        bool r565 = fmts[f] == PSC_PIX_RGB565;
        assert_true(r.share <= (r565 ? 0.2 : 0.12));
        assert_true(r.tiles >= (r565 ? 35.5 : 37.5));
        assert_true(r.frame_lo >= (r565 ? 33.0 : 35.0));
    }
    free(img.xrgb);
    img = test_image(MAP_W, MAP_H, 11);
    print_message("  the test image (noise and one-pixel lines):\n");
    jpeg_figures_t r = jpeg_against_raw(&img, PSC_PIX_RGB888, &rng);
    /* measured: 13.2 % of the bytes, 33.5 dB, frames 32.2 dB and up */
    assert_true(r.share <= 0.2);
    assert_true(r.tiles >= 32.0);
    assert_true(r.frame_lo >= 30.0);
    free(img.xrgb);
}

/* The loader thread decoding JPEG tiles (its own decoder) while frames are drawn, from a starved cache: every
 * frame draws, coarser while tiles are on their way, and sharpens to the bytes of a cache that loaded every tile
 * itself (the cache's decoder). Small (a 1024 x 512 map), so that `make check-memcheck` runs it under helgrind. */
static void test_jpeg_loader_thread(void **state)
{
    (void)state;
    psc_image_t img = test_image(1024, 512, 13);
    psc_io_tiled_t *full = jpeg_pack(&img, PSC_PIX_RGB888, PSC_IO_TILE_JPEG_QUALITY, temp_path("jpeg-full.pano"),
                                     256u << 20);
    psc_io_tiled_t *s = jpeg_pack(&img, PSC_PIX_RGB888, PSC_IO_TILE_JPEG_QUALITY, temp_path("jpeg-starved.pano"), 0);
    load_all(full);
    char err[512];
    assert_int_equal(psc_io_tiled_start_loader(s, err, sizeof err), 0);
    viewer_t a, b;
    tiled_viewer(&a, full);
    tiled_viewer(&b, s);
    psc_surface_t sa = surface(PSC_PIX_XRGB8888), sb = surface(PSC_PIX_XRGB8888);
    unsigned coarse = 0;
    for (unsigned i = 0; i < 6; i++) {
        psc_view_t view = {tsup_bam_from_deg(60.0 * i), (int32_t)tsup_bam_from_deg(15), tsup_bam_from_deg(40),
                           (psc_filter_t)(i % 3u), 2};
        assert_int_equal(psc_viewer_render(&a.v, &view, &sa), PSC_OK);
        for (unsigned round = 0;; round++) {
            assert_true(round < 64);
            err[0] = '\0';
            psc_io_tiled_publish(s, err, sizeof err);
            assert_string_equal(err, "");
            assert_int_equal(psc_viewer_render(&b.v, &view, &sb), PSC_OK);
            const uint32_t *want;
            unsigned n = psc_viewer_requests(&b.v, &want, NULL);
            if (n == 0)
                break;
            coarse++;
            psc_io_tiled_request(s, want, n);
            psc_io_tiled_drain(s);   /* (the test waits for them; a device draws on) */
        }
        assert_memory_equal(sa.pixels, sb.pixels, (size_t)sa.stride * OUT_H);
    }
    print_message("  the loader thread decoding JPEG tiles: %u coarser frames, then every view the bytes of a cache "
                  "that decoded its own\n", coarse);
    assert_true(coarse > 0);
    free(sa.pixels);
    free(sb.pixels);
    free(a.ws);
    free(b.ws);
    psc_io_tiled_close(full);
    psc_io_tiled_close(s);
    unlink(temp_path("jpeg-full.pano"));
    unlink(temp_path("jpeg-starved.pano"));
    free(img.xrgb);
}

/* Tile i of the tiled pack at path rewritten by change (its bytes and size), its CRC-32 and the container's CRC made
 * right again: a tile that reads and checks but does not decode. */
static void rewrite_tile(const char *path, uint32_t i, void (*change)(uint8_t *bytes, uint32_t *size))
{
    FILE *f = fopen(path, "r+b");
    assert_non_null(f);
    uint8_t head[PSC_CONTAINER_HEADER_SIZE];
    assert_int_equal(fread(head, 1, sizeof head, f), sizeof head);
    const uint8_t *at = head + PSC_CONTAINER_FILE_SIZE_OFFSET;   /* little-endian */
    uint32_t len = (uint32_t)at[0] | (uint32_t)at[1] << 8 | (uint32_t)at[2] << 16 | (uint32_t)at[3] << 24;
    uint8_t *c = aligned_alloc(64, (len + 63u) & ~63u);
    assert_non_null(c);
    assert_int_equal(fseek(f, 0, SEEK_SET), 0);
    assert_int_equal(fread(c, 1, len, f), len);
    psc_pack_t pk;
    psc_container_error_t e = {0};
    assert_int_equal(psc_pack_parse(c, len, &pk, &e), PSC_OK);
    psc_pack_tile_raw_t *entry = (psc_pack_tile_raw_t *)(uintptr_t)&pk.tile_index[i];
    uint8_t *bytes = malloc(entry->size);
    assert_non_null(bytes);
    assert_int_equal(fseek(f, (long)(pk.store_offset + entry->offset), SEEK_SET), 0);
    assert_int_equal(fread(bytes, 1, entry->size, f), entry->size);
    uint32_t size = entry->size;
    change(bytes, &size);
    assert_int_equal(fseek(f, (long)(pk.store_offset + entry->offset), SEEK_SET), 0);
    assert_int_equal(fwrite(bytes, 1, size, f), size);
    entry->size = size;   /* (a little-endian host, as the container) */
    entry->crc32 = psc_crc32(0, bytes, size);
    uint32_t crc = psc_container_crc(c, len);
    for (unsigned k = 0; k < 4; k++)
        c[PSC_CONTAINER_CRC_OFFSET + k] = (uint8_t)(crc >> (8 * k));
    assert_int_equal(fseek(f, 0, SEEK_SET), 0);
    assert_int_equal(fwrite(c, 1, len, f), len);
    assert_int_equal(fclose(f), 0);
    free(bytes);
    free(c);
}

static void not_a_jpeg(uint8_t *bytes, uint32_t *size)
{
    (void)size;
    bytes[0] = 0x00;   /* no SOI marker */
}

static void cut_short(uint8_t *bytes, uint32_t *size)
{
    (void)bytes;
    *size /= 3;   /* the entropy-coded data ends a third of the way in */
}

static void wrong_size(uint8_t *bytes, uint32_t *size)
{
    /* the SOF0 frame header's height (two bytes after its length and precision) made 128 */
    for (uint32_t k = 0; k + 8 < *size; k++)
        if (bytes[k] == 0xFF && bytes[k + 1] == 0xC0) {
            bytes[k + 5] = 0;
            bytes[k + 6] = 128;
            return;
        }
    fail_msg("no SOF0 marker in the tile");
}

/* A JPEG tile that does not decode, its CRC right (a writer's bug, a tool's): the message names the file, the tile
 * and the problem, the tile stays absent and the frame shows the coarser level; the other tiles load. */
static void test_jpeg_tile_does_not_decode(void **state)
{
    (void)state;
    psc_image_t img = test_image(1024, 512, 12);
    static void (*const changes[])(uint8_t *, uint32_t *) = {not_a_jpeg, cut_short, wrong_size};
    static const char *const says[] = {"Not a JPEG file", "not a JPEG tile that decodes", "not a 256x256 tile"};
    const char *path = temp_path("bad-jpeg.pano");
    for (unsigned m = 0; m < 3; m++) {
        psc_io_tiled_close(jpeg_pack(&img, PSC_PIX_RGB888, 80, path, 0));
        rewrite_tile(path, 3, changes[m]);
        char err[512];
        psc_io_tiled_t *t;
        if (psc_io_tiled_open(path, 256u << 20, &t, err, sizeof err) != 0)
            fail_msg("%s", err);
        uint32_t want[3] = {2, 3, 4};
        assert_int_equal(psc_io_tiled_load(t, want, 3, err, sizeof err), -1);
        print_message("  %s\n", err);
        assert_non_null(strstr(err, path));
        assert_non_null(strstr(err, "tile 3 "));
        assert_non_null(strstr(err, says[m]));
        assert_non_null(strstr(err, "the coarser level shows there"));
        const psc_tiles_t *g = psc_io_tiled_tiles(t);
        assert_null(g->resident[3]);
        assert_non_null(g->resident[2]);
        assert_non_null(g->resident[4]);
        /* a view of tile 3's place draws, from the coarser level there */
        viewer_t v;
        tiled_viewer(&v, t);
        psc_surface_t s = surface(PSC_PIX_XRGB8888);
        psc_view_t view = {tsup_bam_from_deg(-180.0 + 3.5 * 256.0 * 360.0 / 1024.0), (int32_t)tsup_bam_from_deg(45),
                           tsup_bam_from_deg(20), PSC_FILTER_BILINEAR, 2};
        assert_int_equal(psc_viewer_render(&v.v, &view, &s), PSC_OK);
        free(s.pixels);
        free(v.ws);
        psc_io_tiled_close(t);
    }
    unlink(path);
    free(img.xrgb);
}

/* The streaming writer's memory: the same for an image four times as tall. */
static void test_writer_memory_bounded(void **state)
{
    (void)state;
    psc_pack_options_t o;
    psc_io_pack_options_default(&o);
    o.format = PSC_PIX_XRGB8888;
    o.projection = PSC_PROJ_CYLINDER;   /* any height: a cylinder's coverage follows its proportions */
    o.map_levels = 4;                   /* the same levels for both heights */
    uint64_t peak[4];
    uint32_t *row = malloc(4096u * sizeof *row);
    for (uint32_t i = 0; i < 4096u; i++)
        row[i] = 0xFF000000u | i * 2654435761u;
    for (int k = 0; k < 4; k++) {
        uint32_t w = 4096u, h = k & 1 ? 4096u : 1024u;
        o.tile_codec = k >= 2 ? PSC_TILE_CODEC_JPEG : PSC_TILE_CODEC_RAW;   /* JPEG tiles: XRGB8888 bands too */
        psc_io_tiles_writer_t *wr;
        char err[512];
        if (psc_io_tiles_writer_open(temp_path("memory.pano"), w, h, &o, &wr, err, sizeof err) != 0)
            fail_msg("%s", err);
        for (uint32_t y = 0; y < h; y++)
            assert_int_equal(psc_io_tiles_writer_row(wr, row, err, sizeof err), 0);
        peak[k] = psc_io_tiles_writer_peak(wr);
        assert_int_equal(psc_io_tiles_writer_finish(wr, err, sizeof err), 0);
        unlink(temp_path("memory.pano"));
    }
    free(row);
    /* bands of 256 rows for each level (a halving series: under twice level 0's, and at least a tile each), four
     * rows of filter sums for each (under twice level 0's: 4 x 2048 x 3 x 4 bytes), the index */
    uint64_t bound = 2u * 256u * 4096u * 4u + PSC_TILES_MAX_LEVELS * (256u * 256u * 4u) + 2u * 4u * 2048u * 12u +
                     (64u << 10);
    print_message("  streaming writer, 4096 wide: %llu bytes at most for 1024 rows, %llu for 4096 (bound %llu); with "
                  "JPEG tiles %llu and %llu\n", (unsigned long long)peak[0], (unsigned long long)peak[1],
                  (unsigned long long)bound, (unsigned long long)peak[2], (unsigned long long)peak[3]);
    assert_true(peak[1] <= bound);
    assert_true(peak[1] <= peak[0] + (64u << 10));   /* the index grows with the height, nothing else */
    /* JPEG tiles add one tile's pixels and its encoding's buffer */
    uint64_t jpeg_extra = 256u * 256u * 4u + PSC_TILE_JPEG_MAX_BYTES(256u * 256u * 4u);
    assert_true(peak[3] <= bound + jpeg_extra);
    assert_true(peak[3] <= peak[2] + (64u << 10));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_range_limits),
        cmocka_unit_test(test_tiles_are_the_flat_levels),
        cmocka_unit_test(test_tiled_frames_are_flat_bytes),
        cmocka_unit_test(test_narrow_levels_at_the_seam),
        cmocka_unit_test(test_paths_agree_at_any_residency),
        cmocka_unit_test(test_wide_views_read_few_tiles),
        cmocka_unit_test(test_golden_deep_and_wide),
        cmocka_unit_test(test_starved_cache_sharpens),
        cmocka_unit_test(test_partial_panoramas),
        cmocka_unit_test(test_loader_thread_sharpens),
        cmocka_unit_test(test_view_tiles_cover_the_frame),
        cmocka_unit_test(test_corrupt_and_truncated),
        cmocka_unit_test(test_writer_memory_bounded),
        cmocka_unit_test(test_jpeg_tiles),
        cmocka_unit_test(test_jpeg_loader_thread),
        cmocka_unit_test(test_jpeg_tile_does_not_decode),
    };
    if (getenv("PSC_TILES_ONLY"))   /* one test, e.g. the loader's under helgrind (make check-memcheck) */
        cmocka_set_test_filter(getenv("PSC_TILES_ONLY"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
