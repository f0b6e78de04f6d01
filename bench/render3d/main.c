/* SPDX-License-Identifier: MIT */
/*
 * render3d - how fast Periscope's integer 3D pipeline draws a textured model
 * and a character, side by side in one run with Mesa's OSMesa software
 * rasterizers (issues 3 and 15).
 *
 *   build/bench/render3d --out bench/results              the timed table (`make bench`)
 *   build/bench/render3d --callgrind --out bench/results  instructions per triangle and pixel
 *                                                         under callgrind (`make bench-callgrind`)
 *
 * Scenes: the Utah teapot, 10816 triangles from a mesh pack, bilinear 256x256
 * RGB565 texture modulated by per-vertex Lambert light; Thom's tessellated
 * patch mesh (thom.c) with his vertex colours, lit. Both: 16-bit depth, back
 * faces culled, RGB565 output, the model turning a full circle over the
 * frames. Rows: Periscope full-screen, in 64x64 tiles, with the A-buffer
 * (its extra cost is the ratio to the first row), Phong on Thom; Mesa
 * softpipe and llvmpipe on one thread. Triangles/s counts submitted
 * triangles; Mpixels/s counts output pixels (width x height per frame), as
 * the viewer bench does.
 */
#include "render3d.h"
#include "common/bench_callgrind.h"
#include "common/bench_self.h"
#include "base/psc_pixel.h"
#include "psc_io_image.h"
#include "psc_io_png.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define FRAMES 36u
#define ROUNDS 9u /* the rows compared with each other most (one and two threads, llvmpipe) take them all */
#define CG_FRAMES 4u

#define ABUF_BYTES (4u << 20)

typedef struct {
    const char *label;
    const char *driver;  /* NULL: Periscope */
    r3d_options_t o;
    unsigned passes;
    bool thom_only;
} row_spec_t;

static const row_spec_t rows[] = {
    {"periscope", NULL, {0, 0, false, PSC_3D_HSR_ZBUFFER, 1}, 9, false},
    {"periscope tiles 64x64", NULL, {64, 0, false, PSC_3D_HSR_ZBUFFER, 1}, 5, false},
    {"periscope area subdivision", NULL, {0, 0, false, PSC_3D_HSR_AREA, 1}, 5, false},
    {"periscope area, tiles 64", NULL, {64, 0, false, PSC_3D_HSR_AREA, 1}, 5, false},
    {"periscope A-buffer 4 MB", NULL, {0, ABUF_BYTES, false, PSC_3D_HSR_ZBUFFER, 1}, 5, false},
    {"periscope A-buf tiles 64", NULL, {64, 256u << 10, false, PSC_3D_HSR_ZBUFFER, 1}, 5, false},
    {"periscope phong", NULL, {0, 0, true, PSC_3D_HSR_ZBUFFER, 1}, 5, true},
    {"periscope 2 threads", NULL, {0, 0, false, PSC_3D_HSR_ZBUFFER, 2}, 9, false},
    {"periscope A-buf t64 2 thr", NULL, {64, 256u << 10, false, PSC_3D_HSR_ZBUFFER, 2}, 5, false},
    {"mesa softpipe", "softpipe", {0, 0, false, PSC_3D_HSR_ZBUFFER, 1}, 2, false},
    {"mesa llvmpipe 1 thread", "llvmpipe", {0, 0, false, PSC_3D_HSR_ZBUFFER, 1}, 9, false},
    {"mesa llvmpipe 2 threads", "llvmpipe", {0, 0, false, PSC_3D_HSR_ZBUFFER, 2}, 9, false},
};
#define NROWS (sizeof rows / sizeof rows[0])

static const uint16_t sizes[][2] = {{320, 240}, {800, 480}};
#define NSIZES (sizeof sizes / sizeof sizes[0])

/* PSNR of b against a (RGB565 frames), 8-bit channels. */
static double frame_psnr(const uint16_t *a, const uint16_t *b, size_t n)
{
    double se = 0;
    for (size_t i = 0; i < n; i++) {
        uint32_t x = psc_rgb565_to_xrgb(a[i]), y = psc_rgb565_to_xrgb(b[i]);
        for (int s = 0; s < 24; s += 8) {
            double d = (double)((x >> s) & 255) - (double)((y >> s) & 255);
            se += d * d;
        }
    }
    return se == 0 ? 99.0 : 10 * log10(255.0 * 255.0 * 3 * n / se);
}

/* One scene's rows at every size: printed, and appended to the JSON rows. */
static int run_scene(const char *self, const char *out_dir, r3d_kind_t kind, FILE *json, bool *first_json)
{
    r3d_scene_t s;
    if (r3d_scene_make(&s, kind) != 0)
        return 1;
    unsigned tris = s.mesh.triangle_count;
    r3d_result_t res[NSIZES][NROWS];
    double psnr[NSIZES][NROWS];
    uint16_t *ours = malloc((size_t)800 * 480 * 2), *theirs = malloc((size_t)800 * 480 * 2);
    if (kind == R3D_TEAPOT)
        printf("\nUtah teapot: %u triangles, %u vertices, bilinear %ux%u RGB565 texture, lit", tris,
               (unsigned)s.mesh.vertex_count, (unsigned)s.mesh.texture.width, (unsigned)s.mesh.texture.height);
    else if (kind == R3D_BLOCKS)
        printf("\nLarge polygons: %u boxes of many sizes hiding one another, %u triangles, %u vertices, vertex colours, "
               "lit", R3D_BLOCKS_COUNT, tris, (unsigned)s.mesh.vertex_count);
    else
        printf("\nThom (assets/thom, 1.1 s into Wave, patches tessellated for an 800-pixel view): %u triangles, %u "
               "vertices, vertex colours, lit", tris, (unsigned)s.mesh.vertex_count);
    printf(", 16-bit depth,\nback faces culled, RGB565 output, %u frames of a full turn, best of the rounds; one core.\n",
           FRAMES);
    /* Rounds interleave the rows (each row one pass a round, its best kept): the machine's slow and fast
     * moments fall on every row alike. */
    for (size_t z = 0; z < NSIZES; z++) {
        uint16_t w = sizes[z][0], h = sizes[z][1];
        for (size_t r = 0; r < NROWS; r++) {
            res[z][r] = (r3d_result_t){0, 0, 0, false};
            psnr[z][r] = 0;
        }
        for (unsigned round = 0; round < ROUNDS; round++)
            for (size_t r = 0; r < NROWS; r++) {
                if ((rows[r].thom_only && kind != R3D_THOM) || round >= rows[r].passes)
                    continue;
                uint16_t *dst = r == 0 ? ours : theirs;
                r3d_result_t x = rows[r].driver ? r3d_run_mesa(self, rows[r].driver, kind, w, h, rows[r].o.threads,
                                                               FRAMES, 1, dst)
                                                : r3d_run_periscope(&s, w, h, &rows[r].o, FRAMES, 1, dst);
                if (!x.ok) {
                    fprintf(stderr, "render3d bench: %s at %ux%u did not run\n", rows[r].label, (unsigned)w,
                            (unsigned)h);
                    continue;
                }
                if (!res[z][r].ok || x.ms_per_frame < res[z][r].ms_per_frame)
                    res[z][r] = x;
                if (round + 1u < rows[r].passes && round + 1u < ROUNDS)
                    continue;
                /* the row's last pass: its frame against Periscope's, and the picture */
                psnr[z][r] = r == 0 ? 99.0 : frame_psnr(ours, dst, (size_t)w * h);
                if (rows[r].o.tile == 0 && rows[r].o.hsr == PSC_3D_HSR_ZBUFFER && rows[r].o.threads <= 1) {
                    char png[1024], err[512];
                    psc_surface_t sf = {w, h, (uint32_t)w * 2, PSC_PIX_RGB565, dst};
                    const char *who = rows[r].driver ? rows[r].driver
                                      : rows[r].o.abuffer_bytes ? "periscope-abuffer"
                                      : rows[r].o.phong         ? "periscope-phong"
                                                                : "periscope";
                    snprintf(png, sizeof png, "%s/render3d-%s-%s-%ux%u.png", out_dir, s.name, who, (unsigned)w,
                             (unsigned)h);
                    if (psc_io_png_write(png, &sf, err, sizeof err) != 0)
                        fprintf(stderr, "render3d bench: %s\n", err);
                }
            }
    }
    printf("%-9s %-26s %10s %10s %10s %12s %13s %11s\n", "size", "renderer", "ms/frame", "Mtri/s", "Mpix/s",
           "vs periscope", "same image dB", "z-tests/px");
    for (size_t z = 0; z < NSIZES; z++) {
        uint16_t w = sizes[z][0], h = sizes[z][1];
        char size[16];
        snprintf(size, sizeof size, "%ux%u", (unsigned)w, (unsigned)h);
        for (size_t r = 0; r < NROWS; r++) {
            const r3d_result_t *x = &res[z][r];
            if (rows[r].thom_only && kind != R3D_THOM)
                continue;
            if (!x->ok) {
                printf("%-9s %-26s %10s\n", size, rows[r].label, "n/a");
                continue;
            }
            double ratio = res[z][0].ok ? x->ms_per_frame / res[z][0].ms_per_frame : 0;
            char tests[16] = "-";
            if (!rows[r].driver)
                snprintf(tests, sizeof tests, "%.2f", x->depth_tests / ((double)w * h));
            printf("%-9s %-26s %10.3f %10.3f %10.2f %11.2fx %13.1f %11s\n", size, rows[r].label, x->ms_per_frame,
                   tris / x->ms_per_frame / 1e3, (double)w * h / x->ms_per_frame / 1e3, ratio, psnr[z][r], tests);
            fprintf(json, "%s    {\"scene\": \"%s\", \"size\": \"%ux%u\", \"renderer\": \"%s\", \"ms_per_frame\": %.4f, "
                          "\"triangles_per_s\": %.0f, \"mpixels_per_s\": %.3f, \"time_vs_periscope\": %.3f, "
                          "\"psnr_vs_periscope_db\": %.2f, \"depth_tests_per_frame\": %.0f}",
                    *first_json ? "" : ",\n", s.name, (unsigned)w, (unsigned)h, rows[r].label, x->ms_per_frame,
                    tris / x->ms_per_frame * 1e3, (double)w * h / x->ms_per_frame / 1e3, ratio, psnr[z][r],
                    x->depth_tests);
            *first_json = false;
        }
    }
    free(ours);
    free(theirs);
    r3d_scene_free(&s);
    return 0;
}

static int run_table(const char *self, const char *out_dir)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/render3d.json", out_dir);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "render3d bench: cannot write %s\n", path);
        return 1;
    }
    time_t now = time(NULL);
    char date[32];
    strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", gmtime(&now));
    fprintf(f, "{\n  \"benchmark\": \"render3d\",\n  \"date\": \"%s\",\n  \"frames\": %u,\n  \"rows\": [\n", date, FRAMES);
    printf("3D pipeline against Mesa's software rasterizers, one run.\n");
    bool first = true;
    int rc = 0;
    for (unsigned k = 0; k < R3D_KINDS && rc == 0; k++)
        rc = run_scene(self, out_dir, (r3d_kind_t)k, f, &first);
    printf("(vs periscope: the row's time per frame over Periscope's full-buffer time; > 1 means Periscope is faster;\n"
           " for Periscope's own rows it is their extra cost. same image: PSNR of the row's last frame against\n"
           " Periscope's - the scenes match; the A-buffer's and Phong's differ by what they change, area\n"
           " subdivision's is the same bytes (99 dB). z-tests/px: pixels depth-tested per output pixel.)\n");

    /* Memory: what the device hands the renderer. */
    printf("\nMemory (psc_3d_workspace_size; the A-buffer's is a budget of its own):\n");
    printf("%-9s %-28s %12s %12s %12s\n", "size", "mode", "depth bytes", "cache, lists", "total");
    fprintf(f, "\n  ],\n  \"memory\": [\n");
    bool fm = true;
    for (size_t z = 0; z < NSIZES; z++)
        for (int t = 0; t < 4; t++) {
            uint16_t tile = t < 2 ? 0 : 64;
            uint8_t bits = t % 2 ? 32 : 16;
            psc_3d_config_t cfg = {sizes[z][0], sizes[z][1], tile, tile, bits, PSC_BAM_FROM_MDEG(60000),
                                   PSC_Q16_ONE, 4 * PSC_Q16_ONE, 10816, PSC_3D_HSR_ZBUFFER};
            size_t depth = psc_3d_depth_bytes(&cfg), total = psc_3d_workspace_size(&cfg);
            char mode[40];
            snprintf(mode, sizeof mode, "%s, %u-bit depth", tile ? "tiles 64x64" : "full screen", (unsigned)bits);
            printf("%4ux%-4u %-28s %12zu %12zu %12zu\n", (unsigned)sizes[z][0], (unsigned)sizes[z][1], mode, depth,
                   total - depth, total);
            fprintf(f, "%s    {\"size\": \"%ux%u\", \"tile\": %u, \"depth_bits\": %u, \"depth_bytes\": %zu, "
                       "\"vertex_cache_bytes\": %zu}",
                    fm ? "" : ",\n", (unsigned)sizes[z][0], (unsigned)sizes[z][1], (unsigned)tile, (unsigned)bits, depth,
                    total - depth);
            fm = false;
        }
    printf("(for up to 10816 vertices a frame: the vertex cache, %u bytes a vertex, and in tiles the rows' triangle lists;\n"
           " the colour buffer is the display's; A-buffer: %u bytes a pixel of a tile plus %u a fragment)\n",
           PSC_3D_VERTEX_CACHE_BYTES, PSC_ABUF_HEAD_BYTES, PSC_ABUF_FRAGMENT_BYTES);
    fprintf(f, "\n  ]\n}\n");
    fclose(f);
    printf("\nwrote %s\n", path);
    return rc;
}

/* ---- callgrind ---------------------------------------------------------------- */

/* The workload counted: CG_FRAMES frames at 320x240, full buffer. noinline: callgrind toggles on it. */
__attribute__((noinline)) static void cg_workload(r3d_scene_t *s, uint16_t *frame, double *pixels)
{
    r3d_options_t o = {0, 0, false, PSC_3D_HSR_ZBUFFER, 1};
    r3d_result_t r = r3d_run_periscope(s, 320, 240, &o, CG_FRAMES, 1, frame);
    *pixels = r.pixels_written;
}

static int cg_child(void)
{
    r3d_scene_t s;
    if (r3d_scene_make(&s, R3D_TEAPOT) != 0)
        return 1;
    uint16_t *frame = malloc(320 * 240 * 2);
    double px;
    cg_workload(&s, frame, &px);
    printf("written %.0f\n", px);
    free(frame);
    r3d_scene_free(&s);
    return 0;
}

static int run_callgrind(const char *self, const char *out_dir)
{
    if (bench_callgrind_require("render3d") != 0)
        return 1;
    /* the child prints the pixels it wrote: read back from a file of its stdout */
    char *child[] = {(char *)self, "--callgrind-child", NULL};
    FILE *p = tmpfile();
    long long count = -1;
    if (!p || bench_callgrind_count("psc_3d_render", child, p, &count) != 0) {
        fprintf(stderr, "render3d bench: the callgrind run failed\n");
        if (p)
            fclose(p);
        return 1;
    }
    rewind(p);
    double written = 0;
    char line[256];
    while (fgets(line, sizeof line, p))
        sscanf(line, "written %lf", &written);
    fclose(p);
    double ir = (double)count;
    if (ir <= 0) {
        fprintf(stderr, "render3d bench: no instruction count in the callgrind output\n");
        return 1;
    }
    double per_frame = ir / CG_FRAMES, tris = 10816;
    printf("3D pipeline under callgrind (psc_3d_render only): teapot, %u frames of 320x240, textured, lit,\n"
           "16-bit depth: %.0f instructions per frame, %.0f per submitted triangle, %.1f per output pixel,\n"
           "%.1f per pixel written (%.0f written per frame).\n",
           CG_FRAMES, per_frame, per_frame / tris, per_frame / (320.0 * 240), written > 0 ? per_frame / written : 0,
           written);
    char path[1024];
    snprintf(path, sizeof path, "%s/render3d-callgrind.json", out_dir);
    FILE *j = fopen(path, "w");
    if (j) {
        fprintf(j, "{\n  \"benchmark\": \"render3d-callgrind\",\n  \"frames\": %u,\n  \"size\": \"320x240\",\n"
                   "  \"instructions_per_frame\": %.0f,\n  \"instructions_per_triangle\": %.1f,\n"
                   "  \"instructions_per_output_pixel\": %.2f,\n  \"pixels_written_per_frame\": %.0f\n}\n",
                CG_FRAMES, per_frame, per_frame / tris, per_frame / (320.0 * 240), written);
        fclose(j);
        printf("wrote %s\n", path);
    }
    return 0;
}

/* Periscope alone, `frames` frames of scene kind at w x h (with an A-buffer of abuf bytes, hidden surfaces by hsr):
 * for `perf record` and callgrind. */
static int profile_run(r3d_kind_t kind, uint16_t w, uint16_t h, size_t abuf, uint8_t hsr, unsigned frames,
                       unsigned threads)
{
    r3d_scene_t s;
    if (r3d_scene_make(&s, kind) != 0 || w == 0 || h == 0 || w > 4096 || h > 4096)
        return 1;
    uint16_t *frame = malloc((size_t)w * h * 2);
    r3d_options_t o = {0, abuf, false, hsr, threads};
    r3d_result_t r = r3d_run_periscope(&s, w, h, &o, frames, 1, frame);
    printf("%.3f ms per frame\n", r.ms_per_frame);
    free(frame);
    r3d_scene_free(&s);
    return r.ok ? 0 : 1;
}

int main(int argc, char **argv)
{
    const char *out = "bench/results";
    bool callgrind = false;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--mesa-child") == 0 && i + 6 < argc)
            return r3d_mesa_child((r3d_kind_t)atoi(argv[i + 1]), (uint16_t)atoi(argv[i + 2]),
                                  (uint16_t)atoi(argv[i + 3]), (unsigned)atoi(argv[i + 4]), (unsigned)atoi(argv[i + 5]),
                                  argv[i + 6]);
        if (strcmp(argv[i], "--callgrind-child") == 0)
            return cg_child();
        if (strcmp(argv[i], "--profile") == 0 && i + 4 < argc) /* Periscope alone: SCENE W H ABUF_KB [HSR [FRAMES [THREADS]]] */
            return profile_run((r3d_kind_t)atoi(argv[i + 1]), (uint16_t)atoi(argv[i + 2]), (uint16_t)atoi(argv[i + 3]),
                               (size_t)atoi(argv[i + 4]) * 1024u, i + 5 < argc ? (uint8_t)atoi(argv[i + 5]) : 0,
                               i + 6 < argc ? (unsigned)atoi(argv[i + 6]) : 360u,
                               i + 7 < argc ? (unsigned)atoi(argv[i + 7]) : 1u);
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) {
            out = argv[++i];
        } else if (strcmp(argv[i], "--callgrind") == 0) {
            callgrind = true;
        } else {
            fprintf(stderr, "usage: build/bench/render3d [--out DIR] [--callgrind]\n");
            return 2;
        }
    }
    char self[1024];
    if (bench_self_path(self, sizeof self) != 0) {
        fprintf(stderr, "render3d bench: cannot find its own executable\n");
        return 1;
    }
    return callgrind ? run_callgrind(self, out) : run_table(self, out);
}
