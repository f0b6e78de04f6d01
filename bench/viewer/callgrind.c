/* SPDX-License-Identifier: MIT */
/*
 * callgrind.c - `make bench-callgrind`: instructions per output pixel for each
 * Periscope mode, counted by valgrind's callgrind (repeatable where timings
 * are not).
 *
 * The parent builds the 800x480 RGB565 pack of the bundled sample, writes it
 * to a temporary file and runs this program again under
 *     valgrind --tool=callgrind --collect-atstart=no --toggle-collect=<mode function>
 * once per mode. Each mode is its own function that renders the same three
 * views, so callgrind counts exactly that mode's rendering (loading, set-up
 * and a warm-up frame stay outside). The parent reads the "totals:" line of
 * each output file.
 */
#include "bench_support.h"
#include "common/bench_callgrind.h"
#include "psc_io_angle.h"
#include "psc_io_pack_build.h"
#include "psc_io_load.h"
#include "psc_io_file.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define CG_VIEWS 3u
#define CG_W 800u
#define CG_H 480u
#define CG_HFOV 75.0
#define CG_PARALLEL 2u /* counts do not depend on it; the machine has 2 cores */
#define NEAREST_GOAL 12.0
#define BILINEAR_GOAL 32.0

/* ---- the child: one mode's rendering ---------------------------------------------- */

typedef struct {
    psc_viewer_t viewer;
    psc_view_t views[CG_VIEWS];
    psc_surface_t out565, out8888;
    psc_status_t status;
} cg_ctx_t;

static void cg_render(cg_ctx_t *c, psc_filter_t filter, uint8_t span_log2, psc_pixfmt_t fmt)
{
    for (unsigned k = 0; k < CG_VIEWS; k++) {
        psc_view_t v = c->views[k];
        v.filter = filter;
        v.span_log2 = span_log2;
        psc_status_t s = psc_viewer_render(&c->viewer, &v, fmt == PSC_PIX_RGB565 ? &c->out565 : &c->out8888);
        if (s != PSC_OK)
            c->status = s;
    }
}

/* X(filter name, filter, N, log2 N, format name, format): one line per mode. */
#define CG_BASE_MODES(X)                                                                                   \
    X(nearest, PSC_FILTER_NEAREST, 1, 0, rgb565, PSC_PIX_RGB565)                                           \
    X(nearest, PSC_FILTER_NEAREST, 4, 2, rgb565, PSC_PIX_RGB565)                                           \
    X(nearest, PSC_FILTER_NEAREST, 8, 3, rgb565, PSC_PIX_RGB565)                                           \
    X(nearest, PSC_FILTER_NEAREST, 1, 0, xrgb8888, PSC_PIX_XRGB8888)                                       \
    X(nearest, PSC_FILTER_NEAREST, 4, 2, xrgb8888, PSC_PIX_XRGB8888)                                       \
    X(nearest, PSC_FILTER_NEAREST, 8, 3, xrgb8888, PSC_PIX_XRGB8888)                                       \
    X(bilinear, PSC_FILTER_BILINEAR, 1, 0, rgb565, PSC_PIX_RGB565)                                         \
    X(bilinear, PSC_FILTER_BILINEAR, 4, 2, rgb565, PSC_PIX_RGB565)                                         \
    X(bilinear, PSC_FILTER_BILINEAR, 8, 3, rgb565, PSC_PIX_RGB565)                                         \
    X(bilinear, PSC_FILTER_BILINEAR, 1, 0, xrgb8888, PSC_PIX_XRGB8888)                                     \
    X(bilinear, PSC_FILTER_BILINEAR, 4, 2, xrgb8888, PSC_PIX_XRGB8888)                                     \
    X(bilinear, PSC_FILTER_BILINEAR, 8, 3, xrgb8888, PSC_PIX_XRGB8888)
#if BV_HAVE_MIP
#define CG_MIP_MODES(X)                                                                                    \
    X(mip, PSC_FILTER_MIP, 1, 0, rgb565, PSC_PIX_RGB565)                                                   \
    X(mip, PSC_FILTER_MIP, 4, 2, rgb565, PSC_PIX_RGB565)                                                   \
    X(mip, PSC_FILTER_MIP, 8, 3, rgb565, PSC_PIX_RGB565)                                                   \
    X(mip, PSC_FILTER_MIP, 1, 0, xrgb8888, PSC_PIX_XRGB8888)                                               \
    X(mip, PSC_FILTER_MIP, 4, 2, xrgb8888, PSC_PIX_XRGB8888)                                               \
    X(mip, PSC_FILTER_MIP, 8, 3, xrgb8888, PSC_PIX_XRGB8888)
#else
#define CG_MIP_MODES(X)
#endif
#define CG_MODES(X) CG_BASE_MODES(X) CG_MIP_MODES(X)

/* noipa: callgrind must find each mode under its own name, neither inlined nor cloned.
 * clang has no noipa: noinline there (cg_modes takes each one's address, so each keeps its symbol). */
#if defined(__clang__)
#define CG_NOIPA __attribute__((noinline))
#else
#define CG_NOIPA __attribute__((noipa))
#endif
#define CG_DEFINE(fname, filter, n, log2, fmtname, fmt)                                                    \
    static CG_NOIPA void cg_##fname##_n##n##_##fmtname(cg_ctx_t *c)                                       \
    {                                                                                                      \
        cg_render(c, filter, log2, fmt);                                                                   \
    }
CG_MODES(CG_DEFINE)

typedef struct {
    const char *func, *filter, *format;
    unsigned span;
    void (*run)(cg_ctx_t *c);
    psc_filter_t f;
    uint8_t log2;
    psc_pixfmt_t fmt;
} cg_mode_t;

#define CG_ENTRY(fname, filter, n, log2, fmtname, fmt)                                                     \
    {"cg_" #fname "_n" #n "_" #fmtname, #fname, #fmtname, n, cg_##fname##_n##n##_##fmtname, filter, log2, fmt},
static const cg_mode_t cg_modes[] = {CG_MODES(CG_ENTRY)};
#define CG_NMODES (sizeof cg_modes / sizeof cg_modes[0])

/* The three views, clamped as the device would. */
static void cg_views(cg_ctx_t *c, psc_bam_t hfov_min)
{
    static const double yaw[CG_VIEWS] = {5.0, 125.0, 245.0}, pitch[CG_VIEWS] = {0.0, 25.0, -25.0};
    for (unsigned k = 0; k < CG_VIEWS; k++) {
        psc_view_t v = {.yaw = psc_io_bam_from_deg(yaw[k]), .pitch = psc_io_sbam_from_deg(pitch[k]),
                        .hfov = psc_io_bam_from_deg(CG_HFOV)};
        psc_viewer_clamp(&c->viewer, &v, hfov_min);
        c->views[k] = v;
    }
}

int bv_callgrind_child(const char *pack_path, const char *mode)
{
    const cg_mode_t *m = NULL;
    for (size_t i = 0; i < CG_NMODES && !m; i++)
        if (strcmp(cg_modes[i].func, mode) == 0)
            m = &cg_modes[i];
    if (!m) {
        fprintf(stderr, "viewer bench: no mode %s\n", mode);
        return 2;
    }
    char err[512];
    psc_io_pack_t pf;
    if (psc_io_pack_load(pack_path, &pf, err, sizeof err) != 0) {
        fprintf(stderr, "viewer bench: %s\n", err);
        return 1;
    }
    bv_pack_t p = {.pack = pf.pack};
    static cg_ctx_t c;
    void *ws = NULL;
    c.out565 = (psc_surface_t){CG_W, CG_H, CG_W * 2, PSC_PIX_RGB565, calloc(CG_W * CG_H, 2)};
    c.out8888 = (psc_surface_t){CG_W, CG_H, CG_W * 4, PSC_PIX_XRGB8888, calloc(CG_W * CG_H, 4)};
    int rc = 1;
    if (c.out565.pixels && c.out8888.pixels && bv_viewer_open(&c.viewer, &p, CG_W, CG_H, &ws) == 0) {
        cg_views(&c, pf.pack.hfov_min);
        cg_render(&c, m->f, m->log2, m->fmt); /* warm-up outside the count: the zoom table is built here */
        m->run(&c);
        if (c.status == PSC_OK)
            rc = 0;
        else
            fprintf(stderr, "viewer bench: %s: psc_viewer_render: %s\n", mode, psc_status_str(c.status));
    }
    free(ws);
    free(c.out565.pixels);
    free(c.out8888.pixels);
    psc_io_pack_free(&pf);
    return rc;
}

/* ---- the parent: one valgrind run per mode ------------------------------------------- */

static pid_t spawn_mode(const char *self, const char *pack, const char *dir, const cg_mode_t *m)
{
    char outfile[4200];
    snprintf(outfile, sizeof outfile, "%s/%s.out", dir, m->func);
    char *argv[] = {(char *)self, "--callgrind-child", (char *)pack, (char *)m->func, NULL};
    return bench_callgrind_spawn(m->func, outfile, argv, -1);
}

/* Run every mode, CG_PARALLEL at a time; counts[i] = instructions of mode i. */
static int run_modes(const char *self, const char *pack, const char *dir, long long *counts)
{
    pid_t pids[CG_NMODES];
    size_t started = 0, finished = 0;
    int rc = 0;
    while (finished < CG_NMODES) {
        while (rc == 0 && started < CG_NMODES && started - finished < CG_PARALLEL) {
            fprintf(stderr, "viewer bench: callgrind %s\n", cg_modes[started].func);
            if ((pids[started] = spawn_mode(self, pack, dir, &cg_modes[started])) < 0) {
                fprintf(stderr, "viewer bench: cannot run valgrind\n");
                rc = -1;
                break;
            }
            started++;
        }
        if (finished == started)
            break;
        if (bench_callgrind_wait(pids[finished]) != 0) {
            fprintf(stderr, "viewer bench: callgrind run of %s failed\n", cg_modes[finished].func);
            rc = -1;
        }
        char path[4200];
        snprintf(path, sizeof path, "%s/%s.out", dir, cg_modes[finished].func);
        counts[finished] = bench_callgrind_total(path);
        if (rc == 0 && counts[finished] < 0) {
            fprintf(stderr, "viewer bench: no totals in %s\n", path);
            rc = -1;
        }
        unlink(path);
        finished++;
    }
    return rc;
}

static double goal_of(const cg_mode_t *m)
{
    if (m->span != 4 || m->fmt != PSC_PIX_RGB565)
        return 0.0;
    return m->f == PSC_FILTER_NEAREST ? NEAREST_GOAL : m->f == PSC_FILTER_BILINEAR ? BILINEAR_GOAL : 0.0;
}

static void print_counts(const long long *counts, const bv_meta_t *meta, const char *vg)
{
    double px = (double)CG_VIEWS * CG_W * CG_H;
    printf("\nInstructions per output pixel (%s, callgrind Ir, %s): %u views of %ux%u at hfov %g from the\n"
           "4096x2048 RGB565 map (800x480 display pack), only psc_viewer_render counted\n",
           vg, meta->machine, CG_VIEWS, CG_W, CG_H, CG_HFOV);
    printf("%-9s %4s  %-9s %14s %10s  %s\n", "filter", "span", "output", "instructions", "per pixel", "goal");
    for (size_t i = 0; i < CG_NMODES; i++) {
        const cg_mode_t *m = &cg_modes[i];
        double g = goal_of(m), per = (double)counts[i] / px;
        char goal[32] = "";
        if (g > 0.0)
            snprintf(goal, sizeof goal, "<= %.0f: %s", g, per <= g ? "met" : "NOT met");
        printf("%-9s %4u  %-9s %14lld %10.1f  %s\n", m->filter, m->span, m->format, counts[i], per, goal);
    }
}

static int write_counts(const char *path, const long long *counts, const bv_meta_t *meta, const char *vg)
{
    char tmp[BV_JSON_TMP_LEN];
    FILE *f = bv_json_begin(path, "viewer-callgrind", meta, tmp);
    if (!f)
        return -1;
    double px = (double)CG_VIEWS * CG_W * CG_H;
    fprintf(f, ",\n  \"valgrind\": ");
    bv_json_string(f, vg);
    fprintf(f, ",\n  \"workload\": {\"map\": \"4096x2048\", \"map_format\": \"rgb565\", \"output\": \"%ux%u\", "
               "\"views\": %u, \"hfov\": %g, \"pixels\": %.0f},\n  \"modes\": [",
            CG_W, CG_H, CG_VIEWS, CG_HFOV, px);
    for (size_t i = 0; i < CG_NMODES; i++) {
        const cg_mode_t *m = &cg_modes[i];
        fprintf(f, "%s\n    {\"filter\": \"%s\", \"span\": %u, \"output\": \"%s\", \"instructions\": %lld, "
                   "\"per_pixel\": %.3f, \"goal_per_pixel\": ",
                i ? "," : "", m->filter, m->span, m->format, counts[i], (double)counts[i] / px);
        if (goal_of(m) > 0.0)
            fprintf(f, "%.0f}", goal_of(m));
        else
            fprintf(f, "null}");
    }
    fprintf(f, "\n  ]\n}\n");
    return bv_json_end(f, tmp, path);
}

int bv_callgrind_main(const char *self, const char *out_dir)
{
    char vg[64];
    if (bench_callgrind_version(vg, sizeof vg) != 0) {
        fprintf(stderr, "viewer bench: valgrind is not installed. Install it with\n"
                        "    sh scripts/install-deps.sh valgrind      (as root, or with sudo)\n"
                        "or run `make bench-callgrind`, which installs it first.\n");
        return 1;
    }
    bv_meta_t meta = {0};
    bv_meta_machine(&meta);
    psc_image_t img = {0};
    bv_pack_t pack = {0};
    char dir[] = "/tmp/periscope-callgrind-XXXXXX", pack_path[sizeof dir + 16], err[512];
    long long counts[CG_NMODES];
    int rc = 1;
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    snprintf(pack_path, sizeof pack_path, "%s/sample.pano", dir);
    fprintf(stderr, "viewer bench: packing the sample for %ux%u (RGB565)\n", CG_W, CG_H);
    if (bv_load_sample(BV_SAMPLE, &img) == 0 && bv_pack_make(&img, PSC_PIX_RGB565, CG_W, CG_H, &pack) == 0) {
        psc_io_image_free(&img);
        if (psc_io_write_atomic(pack_path, pack.buf, pack.len, err, sizeof err) != 0)
            fprintf(stderr, "viewer bench: %s\n", err);
        else if (run_modes(self, pack_path, dir, counts) == 0)
            rc = 0;
    }
    unlink(pack_path);
    rmdir(dir);
    psc_io_image_free(&img);
    bv_pack_free(&pack);
    if (rc != 0)
        return rc;
    print_counts(counts, &meta, vg);
    char path[4200];
    snprintf(path, sizeof path, "%s/viewer-callgrind.json", out_dir);
    if (write_counts(path, counts, &meta, vg) != 0)
        return 1;
    printf("\nwritten: %s\n", path);
    return 0;
}
