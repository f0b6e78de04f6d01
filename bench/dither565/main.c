/* SPDX-License-Identifier: MIT */
/*
 * dither565 - what display_dither costs on an RGB565 display, and what it buys
 * (issue 17, item 5), side by side in one run with the frames before it.
 *
 *   build/bench/dither565 --out bench/results              the timed table and the banding (`make bench`)
 *   build/bench/dither565 --callgrind --out bench/results  instructions per frame under callgrind
 *                                                          (`make bench-callgrind`)
 *
 * The bundled sample packed for an 800x480 display three times, as periscope-pack
 * does: with RGB565 maps (the default before RGB888), XRGB8888 maps and RGB888
 * maps (the default). Per frame, one core, mip, span 4, four views, best of
 * PASSES passes:
 *   565 pack -> 565          the viewer straight into RGB565: the frames before the key, and what the
 *                            device still draws for an RGB565 pack (the scene fits RGB565)
 *   565 pack -> 8888 + dither  what dithering an RGB565 pack would cost (the device does not: it buys nothing)
 *   8888 pack -> 565         an 8-bit pack with display_dither = none (rounded to nearest)
 *   8888 pack -> 8888 + dither an 8-bit pack with the default: the viewer into the XRGB8888 draw frame, then
 *                            psc_dither_row_rgb565; the sky's 8 bits reach the screen
 *   888 pack -> 8888 + dither  the same from the default RGB888 pack (three bytes a texel)
 *   the pass alone            ordered, and the same pass rounding (none), over a drawn frame
 * Banding, on a real sky (yaw 200, pitch 50, hfov 90: sky over the whole
 * frame): each RGB565 frame against the 8-bit frame the 8-bit pack renders,
 * the error low-passed by a Gaussian of sigma 1.5 px (tests/test_dither.c's
 * metric): RMS, the largest low-passed luma step between neighbours, the mean.
 */
#include "measure/banding.h"
#include "common/bench_callgrind.h"
#include "common/bench_cli.h"
#include "common/bench_time.h"
#include "psc_io_file.h"
#include "psc_io_image.h"
#include "psc_io_pack_build.h"
#include "base/psc_pixel.h"
#include "dither/psc_dither.h"
#include "pack/psc_pack.h"
#include "viewer/psc_viewer.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 800u
#define H 480u
#define VIEWS 4u
#define PASSES 5u
#define REPEAT 4u
#define SAMPLE "assets/pannellum-examplepano.jpg"

typedef struct {
    uint8_t *buf;
    size_t len;
    psc_pack_t pack;
    psc_viewer_t v;
    void *ws;
} pack_t;

typedef struct {
    pack_t p565, p8888, p888;
    uint16_t *out;   /* the RGB565 back buffer */
    uint32_t *draw;  /* the XRGB8888 draw frame */
    psc_dither_565_t t;
} bench_t;

static const double view_deg[VIEWS][3] = {{0, 0, 90}, {120, 25, 70}, {240, -10, 100}, {200, 50, 90}};

static psc_bam_t bam(double deg)
{
    return (psc_bam_t)(int64_t)llround(deg / 360.0 * 4294967296.0);
}

static psc_view_t view_of(const pack_t *p, unsigned i)
{
    psc_view_t v = {.yaw = bam(view_deg[i][0]), .pitch = (int32_t)bam(view_deg[i][1]), .hfov = bam(view_deg[i][2]),
                    .filter = PSC_FILTER_MIP, .span_log2 = 2};
    psc_viewer_clamp(&p->v, &v, p->pack.hfov_min);
    return v;
}

static int pack_make(const psc_image_t *img, psc_pixfmt_t fmt, pack_t *p)
{
    psc_pack_options_t opt;
    char err[512];
    psc_io_pack_options_default(&opt);
    opt.format = fmt;
    opt.display_width = W;
    opt.display_height = H;
    *p = (pack_t){0};
    if (psc_io_pack_build(img, &opt, &p->buf, &p->len, err, sizeof err) != 0) {
        fprintf(stderr, "dither565 bench: psc_io_pack_build: %s\n", err);
        return -1;
    }
    psc_container_error_t perr = {0};
    size_t ws_size;
    if (psc_pack_parse(p->buf, p->len, &p->pack, &perr) != PSC_OK ||
        (ws_size = psc_viewer_workspace_size(W, H, &p->pack.map)) == 0 || posix_memalign(&p->ws, 64, ws_size) != 0 ||
        psc_viewer_init(&p->v, &p->pack.map, p->pack.luts, p->pack.lut_count, W, H, p->ws, ws_size) != PSC_OK ||
        psc_viewer_set_levels(&p->v, p->pack.levels, p->pack.level_count) != PSC_OK) {
        fprintf(stderr, "dither565 bench: the pack does not open\n");
        return -1;
    }
    return 0;
}

static int setup(bench_t *b)
{
    psc_image_t img;
    char err[512];
    memset(b, 0, sizeof *b);
    if (psc_io_image_load(SAMPLE, &img, err, sizeof err) != 0) {
        fprintf(stderr, "dither565 bench: %s (run from the repository root)\n", err);
        return -1;
    }
    int rc = pack_make(&img, PSC_PIX_RGB565, &b->p565) | pack_make(&img, PSC_PIX_XRGB8888, &b->p8888) |
             pack_make(&img, PSC_PIX_RGB888, &b->p888);
    free(img.xrgb);
    if (rc != 0 || posix_memalign((void **)&b->out, 64, W * H * 2) != 0 ||
        posix_memalign((void **)&b->draw, 64, W * H * 4) != 0)
        return -1;
    psc_dither_565_init(&b->t);
    return 0;
}

static void teardown(bench_t *b)
{
    pack_t *p[3] = {&b->p565, &b->p8888, &b->p888};
    for (unsigned i = 0; i < 3; i++) {
        free(p[i]->buf);
        free(p[i]->ws);
    }
    free(b->out);
    free(b->draw);
}

/* ---- the paths, one frame each (noinline: callgrind toggles on them) ---- */

__attribute__((noinline)) static void pass_dither(bench_t *b, psc_dither_method_t m)
{
    for (unsigned y = 0; y < H; y++)
        psc_dither_row_rgb565(&b->t, m, b->draw + y * W, W, 0, y, b->out + y * W);
}

__attribute__((noinline)) static void frame_direct(bench_t *b, pack_t *p, unsigned i)
{
    psc_view_t v = view_of(p, i);
    psc_surface_t s = {W, H, W * 2, PSC_PIX_RGB565, b->out};
    psc_viewer_render(&p->v, &v, &s);
}

__attribute__((noinline)) static void frame_dithered(bench_t *b, pack_t *p, unsigned i)
{
    psc_view_t v = view_of(p, i);
    psc_surface_t s = {W, H, W * 4, PSC_PIX_XRGB8888, b->draw};
    psc_viewer_render(&p->v, &v, &s);
    pass_dither(b, PSC_DITHER_ORDERED);
}

__attribute__((noinline)) static void pass_ordered(bench_t *b)
{
    pass_dither(b, PSC_DITHER_ORDERED);
}

__attribute__((noinline)) static void pass_none(bench_t *b)
{
    pass_dither(b, PSC_DITHER_NONE);
}

/* ---- banding: host_tools/lib/measure/banding.h, test_dither's metric ---- */

static void run_banding(bench_t *b, FILE *j)
{
    unsigned sky = VIEWS - 1u;
    uint32_t *ref = malloc(W * H * 4);
    uint16_t *shown[5];
    static const char *const name[5] = {"565 pack -> 565 (before)", "565 pack -> dither",
                                        "8888 pack -> 565", "8888 pack -> dither", "888 pack -> dither (default)"};
    if (!ref) {
        fprintf(stderr, "dither565 bench: out of memory\n");
        exit(1);
    }
    frame_dithered(b, &b->p8888, sky);
    memcpy(ref, b->draw, W * H * 4);
    for (unsigned k = 0; k < 5; k++) {
        pack_t *p = k < 2 ? &b->p565 : k < 4 ? &b->p8888 : &b->p888;
        if (k & 1u || k == 4)
            frame_dithered(b, p, sky);
        else
            frame_direct(b, p, sky);
        shown[k] = malloc(W * H * 2);
        if (!shown[k]) {
            fprintf(stderr, "dither565 bench: out of memory\n");
            exit(1);
        }
        memcpy(shown[k], b->out, W * H * 2);
    }
    printf("\nBanding on the sample's sky (yaw 200, pitch 50, hfov 90, %ux%u, mip): each RGB565 frame against the\n"
           "8-bit frame of the XRGB8888 pack, error low-passed by a Gaussian of sigma %.1f px (8-bit units)\n"
           "(max step: of the low-passed luma, the picture's own %.3f; error step: of the low-passed luma error)\n"
           "%-28s %8s %9s %11s %22s\n", W, H, PSC_MEASURE_BANDING_SIGMA, psc_measure_banding_step(ref, W, H), "path", "RMS", "max step", "error step",
           "mean error R/G/B");
    fprintf(j, "  \"banding\": {\n");
    for (unsigned k = 0; k < 5; k++) {
        psc_measure_banding_t r;
        if (psc_measure_banding(ref, shown[k], W, H, &r) != 0) {
            fprintf(stderr, "dither565 bench: out of memory\n");
            exit(1);
        }
        printf("%-28s %8.3f %9.3f %11.3f %+7.3f %+7.3f %+7.3f\n", name[k], r.rms, r.step, r.estep, r.bias[0],
               r.bias[1], r.bias[2]);
        fprintf(j, "    \"%s\": {\"rms\": %.4f, \"max_step\": %.4f, \"error_step\": %.4f, \"bias\": [%.4f, %.4f, %.4f]}%s\n",
                name[k], r.rms, r.step, r.estep, r.bias[0], r.bias[1], r.bias[2], k + 1u < 5u ? "," : "");
        free(shown[k]);
    }
    fprintf(j, "  }\n");
    free(ref);
}

/* ---- the timed table ---- */

/* best of PASSES passes of REPEAT rounds of the four views: ms per frame */
static double time_path(bench_t *b, unsigned path)
{
    double best = 1e30;
    for (unsigned pass = 0; pass < PASSES; pass++) {
        double t0 = bench_now_s();
        for (unsigned r = 0; r < REPEAT; r++)
            for (unsigned i = 0; i < VIEWS; i++)
                switch (path) {
                case 0: frame_direct(b, &b->p565, i); break;
                case 1: frame_dithered(b, &b->p565, i); break;
                case 2: frame_direct(b, &b->p8888, i); break;
                case 3: frame_dithered(b, &b->p8888, i); break;
                case 4: frame_dithered(b, &b->p888, i); break;
                case 5: pass_ordered(b); break;
                default: pass_none(b); break;
                }
        double t = (bench_now_s() - t0) / (REPEAT * VIEWS);
        best = t < best ? t : best;
    }
    return best * 1e3;
}

static const char *const path_name[7] = {"565 pack -> 565 (none)", "565 pack -> 8888 + dither",
                                         "8888 pack -> 565 (none)", "8888 pack -> 8888 + dither",
                                         "888 pack -> 8888 + dither", "the pass alone, ordered",
                                         "the pass alone, none"};

static int run_table(const char *out_dir)
{
    bench_t b;
    if (setup(&b) != 0)
        return 1;
    char path[512];
    snprintf(path, sizeof path, "%s/dither565.json", out_dir);
    FILE *j = fopen(path, "w");
    if (!j) {
        fprintf(stderr, "dither565 bench: cannot write %s\n", path);
        return 1;
    }
    printf("RGB565 output at %ux%u, one core, mip span 4, four views, best of %u: ms per frame (ns per pixel)\n", W, H,
           PASSES);
    fprintf(j, "{\n  \"benchmark\": \"dither565\",\n  \"width\": %u, \"height\": %u,\n  \"ms_per_frame\": {\n", W, H);
    double base = 0.0;
    for (unsigned k = 0; k < 7; k++) {
        double ms = time_path(&b, k);
        if (k == 0)
            base = ms;
        printf("%-30s %8.3f ms (%5.2f ns/pixel)  x%.2f\n", path_name[k], ms, ms * 1e6 / (W * H), ms / base);
        fprintf(j, "    \"%s\": %.4f%s\n", path_name[k], ms, k < 6 ? "," : "");
    }
    fprintf(j, "  },\n");
    size_t map565 = (size_t)b.p565.pack.map.stride * b.p565.pack.map.height;
    size_t map8888 = (size_t)b.p8888.pack.map.stride * b.p8888.pack.map.height;
    size_t map888 = (size_t)b.p888.pack.map.stride * b.p888.pack.map.height;
    printf("\nMemory: the draw frame %u KiB (%ux%u XRGB8888; none with display_dither = none), the tables %zu bytes;\n"
           "packs %zu KiB (RGB565 maps, map %zu KiB), %zu KiB (XRGB8888 maps, map %zu KiB) and %zu KiB (RGB888\n"
           "maps, map %zu KiB: %.3fx the RGB565 map), pyramids included\n",
           W * H * 4u / 1024u, W, H, sizeof b.t, b.p565.len / 1024u, map565 / 1024u, b.p8888.len / 1024u,
           map8888 / 1024u, b.p888.len / 1024u, map888 / 1024u, (double)map888 / (double)map565);
    fprintf(j, "  \"bytes\": {\"draw_frame\": %u, \"tables\": %zu, \"pack_rgb565\": %zu, \"pack_xrgb8888\": %zu, "
            "\"pack_rgb888\": %zu},\n", W * H * 4u, sizeof b.t, b.p565.len, b.p8888.len, b.p888.len);
    run_banding(&b, j);
    fprintf(j, "}\n");
    fclose(j);
    teardown(&b);
    return 0;
}

/* ---- callgrind ---- */

__attribute__((noinline)) static void cg_direct565(bench_t *b)
{
    for (unsigned i = 0; i < VIEWS; i++)
        frame_direct(b, &b->p565, i);
}

__attribute__((noinline)) static void cg_dither565(bench_t *b)
{
    for (unsigned i = 0; i < VIEWS; i++)
        frame_dithered(b, &b->p565, i);
}

__attribute__((noinline)) static void cg_direct8888(bench_t *b)
{
    for (unsigned i = 0; i < VIEWS; i++)
        frame_direct(b, &b->p8888, i);
}

__attribute__((noinline)) static void cg_dither8888(bench_t *b)
{
    for (unsigned i = 0; i < VIEWS; i++)
        frame_dithered(b, &b->p8888, i);
}

__attribute__((noinline)) static void cg_dither888(bench_t *b)
{
    for (unsigned i = 0; i < VIEWS; i++)
        frame_dithered(b, &b->p888, i);
}

__attribute__((noinline)) static void cg_pass_ordered(bench_t *b)
{
    for (unsigned i = 0; i < VIEWS; i++)
        pass_ordered(b);
}

__attribute__((noinline)) static void cg_pass_none(bench_t *b)
{
    for (unsigned i = 0; i < VIEWS; i++)
        pass_none(b);
}

static int cg_child(void)
{
    bench_t b;
    if (setup(&b) != 0)
        return 1;
    /* the first frame of each pack warms nothing callgrind counts; every path draws the same four views */
    cg_direct565(&b);
    cg_dither565(&b);
    cg_direct8888(&b);
    cg_dither8888(&b);
    cg_dither888(&b);
    cg_pass_ordered(&b);
    cg_pass_none(&b);
    teardown(&b);
    return 0;
}

static int run_callgrind(const char *self, const char *out_dir)
{
    if (bench_callgrind_require("dither565") != 0)
        return 1;
    static const char *const fns[] = {"cg_direct565", "cg_dither565", "cg_direct8888", "cg_dither8888", "cg_dither888",
                                      "cg_pass_ordered", "cg_pass_none"};
    double ir[7];
    if (bench_callgrind_counts("dither565", self, fns, 7, ir) != 0)
        return 1;
    printf("RGB565 output under callgrind at %ux%u, mip span 4, the same %u views: instructions per frame\n", W, H,
           VIEWS);
    char path[512];
    snprintf(path, sizeof path, "%s/dither565-callgrind.json", out_dir);
    FILE *j = fopen(path, "w");
    if (j)
        fprintf(j, "{\n  \"benchmark\": \"dither565-callgrind\",\n  \"per_frame\": {\n");
    for (unsigned i = 0; i < 7; i++) {
        double per = ir[i] / VIEWS;
        printf("%-30s %12.0f (%5.2f a pixel)  x%.2f\n", path_name[i], per, per / (W * H), per / (ir[0] / VIEWS));
        if (j)
            fprintf(j, "    \"%s\": %.0f%s\n", path_name[i], per, i < 6 ? "," : "");
    }
    if (j) {
        fprintf(j, "  }\n}\n");
        fclose(j);
    }
    return 0;
}

int main(int argc, char **argv)
{
    static const bench_cli_t cli = {"dither565", run_table, run_callgrind, cg_child};
    return bench_cli_main(&cli, argc, argv);
}
