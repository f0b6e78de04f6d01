/* SPDX-License-Identifier: MIT */
/*
 * tiles - gigapixel panoramas in bounded memory (issue 30), side by side in
 * one run with the flat pack:
 *
 *   build/bench/tiles --out bench/results              the timed table (`make bench`)
 *   build/bench/tiles --callgrind --out bench/results  instructions per frame (`make bench-callgrind`)
 *
 * 1. A tiled frame against the flat frame of the same map and view (the
 *    bundled 4096x2048 sample, every tile resident, one core): the goal is
 *    at most 1.15 times. And a map 6000 wide (the sample stretched; most
 *    photographs' widths are not powers of two): the vector kernels against
 *    the scalar spans, the tiled frame against the flat one.
 * 2. A 32768x16384 panorama generated here (a baseline JPEG written row by
 *    row), packed with raw tiles and with JPEG tiles, each: periscope-pack's
 *    time, peak memory (its resident set) and pack size; a tile's read (and
 *    decode) into the cache; the
 *    time to the first, coarse frame (open, the coarsest level, one frame);
 *    periscope-render's and the device program's (`periscope --board sim`)
 *    resident sets with the default cache; and a pan across it as the
 *    device draws one from the scene's first frame (the loader thread
 *    reading while frames are drawn): the frame times' distribution, whose
 *    slowest should stay within twice the median.
 * Run from the repository root (it reads assets/ and boards/, and the
 * programs in build/bin). The generated files go to $TMPDIR (2 GB).
 */
#include "common/bench_callgrind.h"
#include "common/bench_cli.h"
#include "common/bench_time.h"
#include "psc_io_angle.h"
#include "psc_io_image.h"
#include "psc_io_load.h"
#include "psc_io_pack_build.h"
#include "psc_io_tiles.h"
#include "tsup_panorama.h"
#include "viewer/psc_viewer.h"

#include <dirent.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define SAMPLE "assets/pannellum-examplepano.jpg"
#define BIG_W 32768u
#define BIG_H 16384u
#define PASSES 5u
#define FRAMES 12u
#define PAN_FRAMES 240u
#define CG_ENV "PSC_BENCH_TILES_CASE"

typedef struct {
    psc_viewer_t v;
    void *ws;
    psc_envmap_t map;
    psc_surface_t out;
} view_t;

static char tmpdir[512];

static const char *tmp_file(const char *name)
{
    static char buf[8][800];   /* the directory (512) and a file name (255) */
    static unsigned k;
    char *p = buf[k++ & 7u];
    snprintf(p, sizeof buf[0], "%s/%s", tmpdir, name);
    return p;
}

static int make_tmpdir(void)
{
    const char *base = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    snprintf(tmpdir, sizeof tmpdir, "%s/periscope-bench-tiles-XXXXXX", base);
    return mkdtemp(tmpdir) ? 0 : -1;
}

/* The temporary directory and everything in it (the packs, the device program's frames and contact sheet). */
static void remove_tmpdir(void)
{
    DIR *d = opendir(tmpdir);
    for (struct dirent *e = d ? readdir(d) : NULL; e; e = readdir(d))
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0)
            unlink(tmp_file(e->d_name));
    if (d)
        closedir(d);
    rmdir(tmpdir);
}

/* ---- 1. a tiled frame against the flat frame -------------------------------------------------------------- */

typedef struct {
    psc_image_t img;
    uint8_t *flat_bytes;
    size_t flat_len;
    psc_pack_t flat;
    psc_io_tiled_t *tiled;
} packs_t;

/* The sample stretched to map_w x map_w / 2 (nearest texel: only the size matters here), or as it is (0). */
static int load_sample(psc_image_t *img, uint32_t map_w, char *err, size_t errlen)
{
    if (psc_io_image_load(SAMPLE, img, err, errlen) != 0)
        return -1;
    if (map_w == 0 || map_w == img->width)
        return 0;
    psc_image_t s = {map_w, map_w / 2u, malloc((size_t)map_w * (map_w / 2u) * 4u)};
    if (!s.xrgb) {
        snprintf(err, errlen, "out of memory for a %ux%u map", (unsigned)map_w, (unsigned)map_w / 2u);
        return -1;
    }
    for (uint32_t y = 0; y < s.height; y++)
        for (uint32_t x = 0; x < s.width; x++)
            s.xrgb[(size_t)y * s.width + x] = img->xrgb[(size_t)(y * img->height / s.height) * img->width +
                                                         x * img->width / s.width];
    psc_io_image_free(img);
    *img = s;
    return 0;
}

static int make_packs_of(packs_t *p, uint16_t w, uint16_t h, uint32_t map_w)
{
    char err[512];
    psc_pack_options_t o;
    psc_io_pack_options_default(&o);
    o.format = PSC_PIX_RGB565;   /* the figures before RGB888 was the default, compared with these */
    o.display_width = w;
    o.display_height = h;
    if (load_sample(&p->img, map_w, err, sizeof err) != 0 ||
        psc_io_pack_build(&p->img, &o, &p->flat_bytes, &p->flat_len, err, sizeof err) != 0 ||
        psc_io_tiles_write_image(tmp_file("tiled.pano"), &p->img, &o, err, sizeof err) != 0 ||
        psc_io_tiled_open(tmp_file("tiled.pano"), 256u << 20, &p->tiled, err, sizeof err) != 0) {
        fprintf(stderr, "tiles bench: %s\n", err);
        return -1;
    }
    psc_container_error_t e = {0};
    if (psc_pack_parse(p->flat_bytes, p->flat_len, &p->flat, &e) != PSC_OK)
        return -1;
    const psc_tiles_t *g = psc_io_tiled_tiles(p->tiled);
    uint32_t *all = malloc(g->tile_count * sizeof *all);
    for (uint32_t i = 0; all && i < g->tile_count; i++)
        all[i] = i;
    int rc = all ? psc_io_tiled_load(p->tiled, all, g->tile_count, err, sizeof err) : -1;
    free(all);
    return rc;
}

static int make_packs(packs_t *p, uint16_t w, uint16_t h)
{
    return make_packs_of(p, w, h, 0);
}

static void free_packs(packs_t *p)
{
    psc_io_tiled_close(p->tiled);
    free(p->flat_bytes);
    psc_io_image_free(&p->img);
}

static int open_view(view_t *vw, const psc_pack_t *flat, psc_io_tiled_t *tiled, uint16_t w, uint16_t h)
{
    const psc_pack_t *p = tiled ? psc_io_tiled_pack(tiled) : flat;
    vw->map = p->map;
    size_t n = tiled ? psc_viewer_workspace_size_tiled(w, h, &vw->map) : psc_viewer_workspace_size(w, h, &vw->map);
    vw->ws = aligned_alloc(64, (n + 63u) & ~(size_t)63u);
    vw->out = (psc_surface_t){w, h, (uint32_t)w * 2u, PSC_PIX_RGB565, aligned_alloc(64, (size_t)w * h * 2u)};
    if (!vw->ws || !vw->out.pixels)
        return -1;
    psc_status_t s = tiled ? psc_viewer_init_tiled(&vw->v, &vw->map, psc_io_tiled_tiles(tiled), p->luts,
                                                   p->lut_count, w, h, vw->ws, n)
                           : psc_viewer_init(&vw->v, &vw->map, p->luts, p->lut_count, w, h, vw->ws, n);
    if (s == PSC_OK && !tiled)
        s = psc_viewer_set_levels(&vw->v, p->levels, p->level_count);
    return s == PSC_OK ? 0 : -1;
}

static void close_view(view_t *vw)
{
    free(vw->ws);
    free(vw->out.pixels);
}

/* The best over passes of FRAMES frames of the view, ms per frame. */
static double frame_ms(view_t *vw, const psc_view_t *view)
{
    double best = 1e30;
    psc_viewer_render(&vw->v, view, &vw->out);   /* warm */
    for (unsigned p = 0; p < PASSES; p++) {
        double t0 = bench_now_ms();
        for (unsigned i = 0; i < FRAMES; i++)
            psc_viewer_render(&vw->v, view, &vw->out);
        double ms = (bench_now_ms() - t0) / FRAMES;
        best = ms < best ? ms : best;
    }
    return best;
}

typedef struct {
    uint16_t w, h;
    double yaw, pitch, hfov;
} case_t;

static const case_t cases[] = {
    {1024, 768, 30, 20, 75},   /* the cv::remap reference view (bench/viewer) */
    {800, 480, 120, 0, 60},
    {800, 480, 250, -35, 100},
};
static const psc_filter_t filters[] = {PSC_FILTER_NEAREST, PSC_FILTER_BILINEAR, PSC_FILTER_MIP};
static const char *const filter_names[] = {"nearest", "bilinear", "mip"};

static psc_view_t view_of(const case_t *c, psc_filter_t f)
{
    psc_view_t v = {psc_io_bam_from_deg(c->yaw), psc_io_sbam_from_deg(c->pitch), psc_io_bam_from_deg(c->hfov), f, 2};
    return v;
}

static int table_frames(void)
{
    printf("A tiled frame against the flat frame (%s, 4096x2048 RGB565, every tile resident; one core, the best of "
           "%u passes of %u frames; %s):\n", SAMPLE, PASSES, FRAMES, "RGB565 out");
    printf("  %-30s %-9s %10s %10s %8s\n", "view", "filter", "flat ms", "tiled ms", "tiled/flat");
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        packs_t p = {0};
        view_t a, b;
        if (make_packs(&p, cases[c].w, cases[c].h) != 0 || open_view(&a, &p.flat, NULL, cases[c].w, cases[c].h) != 0 ||
            open_view(&b, NULL, p.tiled, cases[c].w, cases[c].h) != 0)
            return -1;
        for (size_t f = 0; f < sizeof filters / sizeof *filters; f++) {
            psc_view_t view = view_of(&cases[c], filters[f]);
            double fa = frame_ms(&a, &view), fb = frame_ms(&b, &view);
            if (memcmp(a.out.pixels, b.out.pixels, (size_t)a.out.stride * a.out.height) != 0 &&
                (filters[f] == PSC_FILTER_MIP || cases[c].hfov <= 80))
                printf("  (the frames differ!)\n");
            char label[64];
            snprintf(label, sizeof label, "%ux%u yaw %.0f pitch %.0f hfov %.0f", cases[c].w, cases[c].h, cases[c].yaw,
                     cases[c].pitch, cases[c].hfov);
            printf("  %-30s %-9s %10.3f %10.3f %8.2fx\n", label, filter_names[f], fa, fb, fb / fa);
        }
        close_view(&a);
        close_view(&b);
        free_packs(&p);
    }
    return 0;
}

/* A map whose width is not a power of two (most photographs'): the vector kernels' columns by multiplying against
 * the scalar spans, and the tiled frame against the flat one. */
static int table_odd_width(void)
{
    const case_t c = {800, 480, 120, 0, 60};
    packs_t p = {0};
    view_t a, b;
    if (make_packs_of(&p, c.w, c.h, 6000) != 0 || open_view(&a, &p.flat, NULL, c.w, c.h) != 0 ||
        open_view(&b, NULL, p.tiled, c.w, c.h) != 0)
        return -1;
    printf("\nThe sample stretched to 6000x3000 (columns by multiplying; RGB565, %ux%u yaw %.0f pitch %.0f hfov %.0f):\n",
           c.w, c.h, c.yaw, c.pitch, c.hfov);
    printf("  %-9s %14s %14s %8s %10s %10s\n", "filter", "flat scalar ms", "flat vector ms", "ratio", "tiled ms",
           "tiled/flat");
    for (size_t f = 0; f < sizeof filters / sizeof *filters; f++) {
        psc_view_t view = view_of(&c, filters[f]);
        psc_viewer_set_simd(&a.v, PSC_SIMD_SCALAR);
        double fs = frame_ms(&a, &view);
        psc_viewer_set_simd(&a.v, PSC_SIMD_AUTO);
        double fa = frame_ms(&a, &view), fb = frame_ms(&b, &view);
        printf("  %-9s %14.3f %14.3f %7.2fx %10.3f %9.2fx\n", filter_names[f], fs, fa, fs / fa, fb, fb / fa);
    }
    close_view(&a);
    close_view(&b);
    free_packs(&p);
    return 0;
}

/* ---- 2. the gigapixel panorama ------------------------------------------------------------------------------ */

/* A running process's peak resident set so far (VmHWM, kB; 0 when gone). The kernel keeps it per address space,
 * so it starts afresh at exec, where getrusage's ru_maxrss keeps the forking parent's. */
static long vm_hwm_kb(pid_t pid, const char *prog)
{
    char path[64], line[256], name[32] = "";
    const char *base = strrchr(prog, '/') ? strrchr(prog, '/') + 1 : prog;
    snprintf(path, sizeof path, "/proc/%d/status", (int)pid);
    FILE *f = fopen(path, "r");
    long kb = 0;
    while (f && fgets(line, sizeof line, f)) {
        if (sscanf(line, "Name: %31s", name) == 1 && strncmp(name, base, 15) != 0)
            break;   /* not exec'ed yet: the forked copy of this bench, whose peak is ours */
        if (sscanf(line, "VmHWM: %ld", &kb) == 1)
            break;
    }
    if (f)
        fclose(f);
    return kb;
}

/* Run argv, its output to /dev/null: its wall time (s) and peak resident set (MiB, sampled every 2 ms), or -1. */
static int run_child(char *const argv[], double *seconds, double *rss_mb)
{
    double t0 = bench_now_s();
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr))
            _exit(127);
        execv(argv[0], argv);
        _exit(127);
    }
    int status;
    long peak = 0;
    for (;;) {
        pid_t got = waitpid(pid, &status, WNOHANG);
        if (got == pid)
            break;
        if (got < 0)
            return -1;
        long kb = vm_hwm_kb(pid, argv[0]);
        peak = kb > peak ? kb : peak;
        usleep(2000);
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return -1;
    *seconds = bench_now_s() - t0;
    *rss_mb = peak / 1024.0;
    return 0;
}

/* A pan across the big pack as the device draws it: loader thread, no waiting; each frame's time. */
static int pan(const char *path, bool prefetch, double *ms, unsigned *coarse, unsigned *slowest)
{
    char err[1024];
    psc_io_tiled_t *t;
    if (psc_io_tiled_open(path, 64u << 20, &t, err, sizeof err) != 0 ||
        psc_io_tiled_start_loader(t, err, sizeof err) != 0) {
        fprintf(stderr, "tiles bench: %s\n", err);
        return -1;
    }
    view_t vw;
    if (open_view(&vw, NULL, t, 800, 480) != 0)
        return -1;
    *coarse = 0;
    /* the scene's first frame, shown when it opens (timed above as the time to the first frame): the pan begins
     * from it, its tiles asked for */
    psc_view_t opening = {0, 0, psc_io_bam_from_deg(30), PSC_FILTER_MIP, 2};
    psc_viewer_render(&vw.v, &opening, &vw.out);
    const uint32_t *asked;
    unsigned na = psc_viewer_requests(&vw.v, &asked, NULL);
    psc_io_tiled_request(t, asked, na);
    for (unsigned i = 0; i < PAN_FRAMES; i++) {
        /* 45 degrees a second at 60 frames a second, a slow tilt, at the zoom of a visitor looking closely */
        psc_view_t view = {psc_io_bam_from_deg(0.75 * i), psc_io_sbam_from_deg(10.0 * (i % 120u) / 120.0),
                           psc_io_bam_from_deg(30), PSC_FILTER_MIP, 2};
        double t0 = bench_now_ms();
        psc_io_tiled_publish(t, err, sizeof err);
        psc_viewer_render(&vw.v, &view, &vw.out);
        const uint32_t *missed;
        unsigned n = psc_viewer_requests(&vw.v, &missed, NULL);
        uint32_t want[PSC_VIEWER_MAX_REQUESTS], ahead[256];
        memcpy(want, missed, n * sizeof *want);
        if (prefetch) {   /* as the device's tiled scene: 8 frames ahead, then the view's own, then the misses */
            psc_view_t next = view;
            next.yaw += psc_io_bam_from_deg(0.75 * 8);
            unsigned m = psc_viewer_view_tiles(&vw.v, &next, ahead, 256);
            psc_io_tiled_request(t, ahead, m);
            m = psc_viewer_view_tiles(&vw.v, &view, ahead, 256);
            psc_io_tiled_request(t, ahead, m);
        }
        if (n)
            psc_io_tiled_request(t, want, n);
        ms[i] = bench_now_ms() - t0;
        *slowest = i == 0 || ms[i] > ms[*slowest] ? i : *slowest;
        *coarse += n != 0;
        usleep(8000);   /* the rest of a 60 Hz frame: the loader reads meanwhile */
    }
    close_view(&vw);
    psc_io_tiled_close(t);
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Read n tiles of level 0 (from its middle row, the page cache warm from packing) into a fresh cache: ms a tile. */
static double tile_read_ms(const char *path, unsigned n)
{
    char err[1024];
    psc_io_tiled_t *t;
    if (psc_io_tiled_open(path, (size_t)(n + 8u) << 18, &t, err, sizeof err) != 0) {
        fprintf(stderr, "tiles bench: %s\n", err);
        return -1;
    }
    const psc_tiles_t *g = psc_io_tiled_tiles(t);
    uint32_t *ids = malloc(n * sizeof *ids);
    if (!ids)
        return -1;
    for (unsigned k = 0; k < n; k++)   /* the middle row's tiles, then the next row's */
        ids[k] = g->level[0].first + (g->level[0].tiles_y / 2u) * g->level[0].tiles_x + k;
    double t0 = bench_now_ms();
    int rc = psc_io_tiled_load(t, ids, n, err, sizeof err);
    double ms = (bench_now_ms() - t0) / n;
    free(ids);
    psc_io_tiled_close(t);
    return rc == 0 ? ms : -1;
}

static int table_gigapixel(void)
{
    printf("\nA %ux%u panorama generated here (baseline JPEG, quality 90), its tiles raw and JPEG side by side:\n",
           BIG_W, BIG_H);
    double t0 = bench_now_s();
    if (tsup_write_panorama_jpeg(tmp_file("big.jpg"), BIG_W, BIG_H, 90) != 0)
        return -1;
    printf("  written in %.1f s\n", bench_now_s() - t0);
    static const char *const codecs[] = {"raw", "jpeg"};
    for (unsigned c = 0; c < 2; c++) {
        char name[32];
        snprintf(name, sizeof name, "big-%s.pano", codecs[c]);
        const char *pano = tmp_file(name);
        double s, rss;
        char *pack[] = {"build/bin/periscope-pack", (char *)tmp_file("big.jpg"), "-o", (char *)pano, "--display",
                        "800x480", "--tile-codec", (char *)codecs[c], "--quiet", NULL};
        if (run_child(pack, &s, &rss) != 0)
            return -1;
        FILE *f = fopen(pano, "rb");
        long size = f && fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
        if (f)
            fclose(f);
        printf("\n  --tile-codec %s%s:\n  periscope-pack (tiled, streaming): %.1f s, peak resident %.1f MiB (goal: at "
               "most 1024), pack %.1f MiB\n", codecs[c], c ? " (the default for a JPEG image)" : "", s, rss,
               size / 1048576.0);
        printf("  a level-0 tile read (and decoded) into the cache, the page cache warm: %.2f ms\n",
               tile_read_ms(pano, 256));

        /* the first, coarse frame: open (the container, the coarsest level), a viewer, one frame that waits for
         * nothing */
        t0 = bench_now_ms();
        char err[1024];
        psc_io_tiled_t *t;
        if (psc_io_tiled_open(pano, 64u << 20, &t, err, sizeof err) != 0) {
            fprintf(stderr, "tiles bench: %s\n", err);
            return -1;
        }
        view_t vw;
        psc_view_t first = {0, 0, psc_io_bam_from_deg(90), PSC_FILTER_MIP, 2};
        if (open_view(&vw, NULL, t, 800, 480) != 0 || psc_viewer_render(&vw.v, &first, &vw.out) != PSC_OK)
            return -1;
        printf("  the first frame (open, the coarsest level, one coarse 800x480 frame): %.1f ms (goal: under 1000)\n",
               bench_now_ms() - t0);
        close_view(&vw);
        psc_io_tiled_close(t);

        char *render[] = {"build/bin/periscope-render", (char *)pano, "--yaw", "30", "--pitch", "20", "--hfov", "10",
                          "--size", "800x480", "--filter", "mip", "-o", (char *)tmp_file("render.png"), NULL};
        if (run_child(render, &s, &rss) != 0)
            return -1;
        printf("  periscope-render, 800x480 at hfov 10 (every tile it needs read): %.2f s, peak resident %.1f MiB "
               "(goal: at most 128)\n", s, rss);
        char *device[] = {"build/bin/periscope", "--board", "sim", "--scene", (char *)pano, "--out", (char *)tmpdir,
                          "--max-frames", "300", "--quiet", NULL};
        if (run_child(device, &s, &rss) != 0)
            return -1;
        printf("  periscope --board sim, 300 frames of its tour: peak resident %.1f MiB (goal: at most 128)\n", rss);

        for (int prefetch = 0; prefetch < 2; prefetch++) {
            double ms[PAN_FRAMES];
            unsigned coarse, slowest;
            if (pan(pano, prefetch, ms, &coarse, &slowest) != 0)
                return -1;
            const double first_ms = ms[0];
            qsort(ms, PAN_FRAMES, sizeof *ms, cmp_double);
            double med = ms[PAN_FRAMES / 2];
            printf("  a pan (45 degrees a second, hfov 30, mip, 800x480, 60 Hz, the loader reading meanwhile), %s: %u "
                   "frames, %u of them with tiles still on their way;\n    frame ms: min %.2f, median %.2f, 90th "
                   "%.2f, 99th %.2f, max %.2f (frame %u; the first %.2f); slowest / median %.2f (goal: at most 2)\n",
                   prefetch ? "prefetching 8 frames ahead" : "no prefetch", PAN_FRAMES, coarse, ms[0], med,
                   ms[PAN_FRAMES * 9 / 10], ms[PAN_FRAMES * 99 / 100], ms[PAN_FRAMES - 1], slowest, first_ms,
                   ms[PAN_FRAMES - 1] / med);
        }
        unlink(pano);
    }
    return 0;
}

static int run_table(const char *out_dir)
{
    (void)out_dir;
    if (make_tmpdir() != 0) {
        fprintf(stderr, "tiles bench: cannot make a temporary directory\n");
        return 1;
    }
    int rc = table_frames() == 0 && table_odd_width() == 0 && table_gigapixel() == 0 ? 0 : 1;
    remove_tmpdir();
    if (rc)
        fprintf(stderr, "tiles bench: failed\n");
    return rc;
}

/* ---- instruction counts --------------------------------------------------------------------------------- */

static view_t *cg_view;
static psc_view_t cg_v;

/* The counted frames (callgrind toggles on this function). */
__attribute__((noinline)) void cg_frames(void);
__attribute__((noinline)) void cg_frames(void)
{
    for (unsigned i = 0; i < 4; i++)
        psc_viewer_render(&cg_view->v, &cg_v, &cg_view->out);
}

static int cg_child(void)
{
    const char *c = getenv(CG_ENV);
    unsigned tiled = 0, f = 0;
    if (!c || sscanf(c, "%u %u", &tiled, &f) != 2 || f > 2 || make_tmpdir() != 0)
        return 1;
    packs_t p = {0};
    view_t vw;
    int rc = make_packs(&p, 1024, 768) == 0 && open_view(&vw, &p.flat, tiled ? p.tiled : NULL, 1024, 768) == 0 ? 0 : 1;
    if (rc == 0) {
        cg_view = &vw;
        cg_v = view_of(&cases[0], filters[f]);
        psc_viewer_render(&vw.v, &cg_v, &vw.out);
        cg_frames();
        close_view(&vw);
    }
    free_packs(&p);
    remove_tmpdir();
    return rc;
}

static int run_callgrind(const char *self, const char *out_dir)
{
    (void)out_dir;
    if (bench_callgrind_require("tiles") != 0)
        return 1;
    printf("A tiled frame against the flat frame under callgrind (1024x768, yaw 30 pitch 20 hfov 75, the sample, "
           "every tile resident): instructions per frame\n");
    for (unsigned f = 0; f < 3; f++) {
        double ir[2];
        for (unsigned tiled = 0; tiled < 2; tiled++) {
            char env[32];
            snprintf(env, sizeof env, "%u %u", tiled, f);
            setenv(CG_ENV, env, 1);
            static const char *const fn[] = {"cg_frames"};
            if (bench_callgrind_counts("tiles", self, fn, 1, &ir[tiled]) != 0)
                return 1;
        }
        printf("  %-9s flat %.0f, tiled %.0f: %.2fx\n", filter_names[f], ir[0] / 4, ir[1] / 4, ir[1] / ir[0]);
    }
    unsetenv(CG_ENV);
    return 0;
}

int main(int argc, char **argv)
{
    static const bench_cli_t cli = {"tiles", run_table, run_callgrind, cg_child};
    return bench_cli_main(&cli, argc, argv);
}
