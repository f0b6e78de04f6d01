/* SPDX-License-Identifier: MIT */
/*
 * objects - what a character standing in a panorama costs: the sample
 * panorama (assets/pannellum-examplepano.jpg, packed for an 800x480 RGB565
 * display) with Thom (assets/thom) waving in it, as the device draws a
 * panorama scene with an object (firmware/scene/scene_objects.c), side by
 * side in one run with its two parts drawn alone: the panorama's frame, and
 * Thom's own frame (the same placement and camera over a cleared screen).
 *
 *   build/bench/objects --out bench/results              the timed table (`make bench`)
 *   build/bench/objects --callgrind --out bench/results  instructions per frame under callgrind
 *
 * Goal (issue 32): the frame with both at most 1.1x the panorama's frame
 * plus the object's own; 60 frames/s at 800x480 on one core. Per frame: the
 * view pans 0.5 degree, the action steps at 60 Hz; one core, best of PASSES.
 */
#include "common/bench_callgrind.h"
#include "common/bench_cli.h"
#include "common/bench_time.h"
#include "bake/patch_any.h"
#include "psc_io_object.h"
#include "psc_io_pack_image.h"
#include "viewer/psc_viewer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 800u
#define H 480u
#define FRAMES 120u
#define PASSES 3u
#define CG_FRAMES 8u
#define PANO "assets/pannellum-examplepano.jpg"

typedef struct {
    psc_io_pack_t pack;
    psc_viewer_t viewer;
    psc_io_object_t *thom;
    psc_3d_config_t cfg;
    void *viewer_ws, *ws3d, *pixels, *object_ws;
    psc_3d_draw_t *draws;
    unsigned max_draws;
    size_t ws3d_size, abuf_size;
    uint64_t triangles;
} bench_t;

static void teardown(bench_t *b)
{
    psc_io_object_free(b->thom);
    psc_io_pack_free(&b->pack);
    free(b->viewer_ws), free(b->ws3d), free(b->pixels), free(b->draws), free(b->object_ws);
}

static int setup(bench_t *b)
{
    char err[1024], notes[1024];
    memset(b, 0, sizeof *b);
    psc_io_pack_image_request_t rq = {W, H, PSC_PIX_RGB565, ""};
    psc_io_pack_image_result_t res;
    if (psc_io_pack_image_load(PANO, &rq, &b->pack, &res, notes, sizeof notes, err, sizeof err) != 0) {
        fprintf(stderr, "objects bench: %s (run from the repository)\n", err);
        return -1;
    }
    psc_bake_patch_opts_t o = {.actions = {"assets/thom/ResoluteWalk.act", "assets/thom/Wave.act"},
                               .action_count = 2, .skin_from = "assets/thom/Thom2.mdl", .quiet = true};
    psc_io_patch_t pf;
    psc_io_object_spec_t spec;
    if (psc_bake_patch_any("assets/thom/Thom.mdl", &o, &pf, err, sizeof err) != 0 ||
        psc_io_object_spec_parse("Thom.mdl yaw=15 pitch=-12 dist=3.2 action=Wave", ' ', "bench", &spec, err,
                                 sizeof err) != 0 ||
        psc_io_object_from_patch(&spec, &pf, &b->thom, err, sizeof err) != 0) {
        fprintf(stderr, "objects bench: %s\n", err);
        teardown(b);
        return -1;
    }
    const psc_pack_t *pk = &b->pack.pack;
    size_t vn = psc_viewer_workspace_size(W, H, &pk->map);
    b->cfg = psc_io_objects_config(&b->thom, 1, W, H, PSC_BAM_90);
    b->ws3d_size = psc_3d_workspace_size(&b->cfg);
    b->abuf_size = psc_io_objects_abuffer_bytes(&b->cfg);
    b->max_draws = psc_io_objects_max_draws(&b->thom, 1);
    if (posix_memalign(&b->viewer_ws, 64, vn) != 0 || posix_memalign(&b->ws3d, 64, b->ws3d_size + b->abuf_size) != 0 ||
        posix_memalign(&b->pixels, 64, (size_t)W * H * 2) != 0 ||
        !(b->draws = malloc(b->max_draws * sizeof *b->draws)) ||
        posix_memalign(&b->object_ws, 64, psc_io_object_workspace_size(b->thom)) != 0 ||
        psc_io_object_start(b->thom, b->object_ws, psc_io_object_workspace_size(b->thom)) != PSC_OK ||
        psc_viewer_init(&b->viewer, &pk->map, pk->luts, pk->lut_count, W, H, b->viewer_ws, vn) != PSC_OK ||
        psc_viewer_set_levels(&b->viewer, pk->levels, pk->level_count) != PSC_OK) {
        fprintf(stderr, "objects bench: out of memory, or the viewer refused the pack\n");
        teardown(b);
        return -1;
    }
    return 0;
}

/* Frame k's view: panning half a degree a frame across Thom. */
static psc_view_t view_at(unsigned k)
{
    int32_t mdeg = 15000 - (int32_t)(FRAMES / 4u) * 500 + (int32_t)(k % FRAMES) * 500;
    return (psc_view_t){PSC_BAM_FROM_MDEG(mdeg), (int32_t)PSC_BAM_FROM_MDEG(-8000), PSC_BAM_FROM_MDEG(70000),
                        PSC_FILTER_BILINEAR, PSC_SPAN_LOG2_DEFAULT};
}

static psc_surface_t surface(bench_t *b)
{
    return (psc_surface_t){W, H, W * 2u, PSC_PIX_RGB565, b->pixels};
}

__attribute__((noinline)) static void draw_pano(bench_t *b, unsigned k)
{
    psc_view_t v = view_at(k);
    psc_surface_t s = surface(b);
    psc_viewer_render(&b->viewer, &v, &s);
}

/* Thom's frame: over what the surface holds (clear NULL), or over a cleared screen. */
__attribute__((noinline)) static void draw_thom(bench_t *b, unsigned k, const uint32_t *clear)
{
    psc_view_t v = view_at(k);
    psc_io_objects_view_t ov = {v.yaw, v.pitch, v.hfov, W, H, {0, 0, 0}, PSC_IO_OBJECT_AMBIENT_Q8};
    psc_io_objects_light(PSC_IO_OBJECT_LIGHT_AZ_MDEG, PSC_IO_OBJECT_LIGHT_EL_MDEG, ov.light_q16);
    psc_3d_config_t c = b->cfg;
    c.hfov = v.hfov;
    unsigned n;
    psc_3d_t r;
    psc_surface_t s = surface(b);
    psc_3d_stats_t st;
    if (psc_io_objects_frame(&b->thom, 1, &ov, (uint64_t)k * 1000000u / 60u, false, b->draws, b->max_draws, &n, NULL,
                             &c) != PSC_OK ||
        psc_3d_init(&r, &c, b->ws3d, b->ws3d_size) != PSC_OK ||
        psc_3d_set_abuffer(&r, (uint8_t *)b->ws3d + b->ws3d_size, b->abuf_size) != PSC_OK ||
        psc_3d_render(&r, b->draws, n, clear, &s, &st) != PSC_OK)
        abort();
    b->triangles += st.triangles;
}

__attribute__((noinline)) static void draw_alone(bench_t *b, unsigned k)
{
    static const uint32_t bg = 0x30343Cu;
    draw_thom(b, k, &bg);
}

__attribute__((noinline)) static void draw_both(bench_t *b, unsigned k)
{
    draw_pano(b, k);
    draw_thom(b, k, NULL);
}

static int run_table(const char *out_dir)
{
    bench_t b;
    if (setup(&b) != 0)
        return 1;
    double best[3] = {1e30, 1e30, 1e30};
    for (unsigned pass = 0; pass < PASSES; pass++)
        for (unsigned what = 0; what < 3; what++) {
            double t0 = bench_now_ms();
            for (unsigned k = 0; k < FRAMES; k++)
                what == 0 ? draw_pano(&b, k) : what == 1 ? draw_alone(&b, k) : draw_both(&b, k);
            double ms = (bench_now_ms() - t0) / FRAMES;
            best[what] = ms < best[what] ? ms : best[what];
        }
    double parts = best[0] + best[1], ratio = best[2] / parts;
    printf("Objects in a panorama: the sample panorama at %ux%u (RGB565 map, bilinear) with Thom waving in it, "
           "one core,\n%u frames panning 0.5 degree a frame, best of %u passes (ms per frame):\n\n"
           "| frame | ms | frames/s |\n|---|---|---|\n"
           "| the panorama alone | %.3f | %.0f |\n| Thom alone (his own frame, cleared screen) | %.3f | %.0f |\n"
           "| **both: Thom standing in the panorama** | **%.3f** | **%.0f** |\n\n"
           "Both against the parts' sum: %.3f / %.3f = **%.2fx** (goal: at most 1.1x); %.0f frames/s (goal: 60).\n"
           "Thom's triangles a frame: %.0f. Memory beside the viewer's: the 3D workspace %zu bytes, the A-buffer "
           "%zu bytes, Thom's state %zu bytes.\n",
           W, H, FRAMES, PASSES, best[0], 1e3 / best[0], best[1], 1e3 / best[1], best[2], 1e3 / best[2], best[2],
           parts, ratio, 1e3 / best[2], (double)b.triangles / (2.0 * PASSES * FRAMES), b.ws3d_size, b.abuf_size,
           psc_io_object_workspace_size(b.thom));
    char path[512];
    snprintf(path, sizeof path, "%s/objects.json", out_dir);
    FILE *j = fopen(path, "w");
    if (j) {
        fprintf(j, "{\n  \"benchmark\": \"objects\",\n  \"size\": \"%ux%u\",\n  \"frames\": %u,\n  \"pano_ms\": %.4f,\n"
                   "  \"object_ms\": %.4f,\n  \"both_ms\": %.4f,\n  \"ratio\": %.4f\n}\n",
                W, H, FRAMES, best[0], best[1], best[2], ratio);
        fclose(j);
    }
    teardown(&b);
    return 0;
}

/* ---- callgrind -------------------------------------------------------------------------------------------- */

__attribute__((noinline)) static void cg_pano(bench_t *b)
{
    for (unsigned k = 0; k < CG_FRAMES; k++)
        draw_pano(b, k);
}

__attribute__((noinline)) static void cg_alone(bench_t *b)
{
    for (unsigned k = 0; k < CG_FRAMES; k++)
        draw_alone(b, k);
}

__attribute__((noinline)) static void cg_both(bench_t *b)
{
    for (unsigned k = 0; k < CG_FRAMES; k++)
        draw_both(b, k);
}

static int cg_child(void)
{
    bench_t b;
    if (setup(&b) != 0)
        return 1;
    cg_pano(&b);
    cg_alone(&b);
    cg_both(&b);
    teardown(&b);
    return 0;
}

static int run_callgrind(const char *self, const char *out_dir)
{
    if (bench_callgrind_require("objects") != 0)
        return 1;
    static const char *const fns[] = {"cg_pano", "cg_alone", "cg_both"};
    double ir[3];
    if (bench_callgrind_counts("objects", self, fns, 3, ir) != 0)
        return 1;
    printf("Objects in a panorama under callgrind: %ux%u, %u frames, instructions per frame: the panorama %.0f, "
           "Thom alone %.0f, both %.0f: %.3fx the parts' sum (goal: at most 1.1x)\n",
           W, H, CG_FRAMES, ir[0] / CG_FRAMES, ir[1] / CG_FRAMES, ir[2] / CG_FRAMES, ir[2] / (ir[0] + ir[1]));
    char path[512];
    snprintf(path, sizeof path, "%s/objects-callgrind.json", out_dir);
    FILE *j = fopen(path, "w");
    if (j) {
        fprintf(j, "{\n  \"benchmark\": \"objects-callgrind\",\n  \"frames\": %u,\n  \"per_frame\": {\"pano\": %.0f, "
                   "\"object\": %.0f, \"both\": %.0f}\n}\n",
                CG_FRAMES, ir[0] / CG_FRAMES, ir[1] / CG_FRAMES, ir[2] / CG_FRAMES);
        fclose(j);
    }
    return 0;
}

int main(int argc, char **argv)
{
    static const bench_cli_t cli = {"objects", run_table, run_callgrind, cg_child};
    return bench_cli_main(&cli, argc, argv);
}
