/* SPDX-License-Identifier: MIT */
/*
 * speed.c - the timed sweep behind `make bench`: every map size, output size
 * and field of view, each renderer over the same sequences of views.
 *
 * Two sequences of BV_NVIEWS views each, yaw stepping round the full turn:
 *  - "static": pitch 0, +25, 0, -25, ...; each view stands for a camera at
 *    rest, so cv::remap gets maps built beforehand (untimed) and only the
 *    remap is timed;
 *  - "moving": the pitch changes every frame (+-60 degrees, poles in view at
 *    wide angles), so a remap user must rebuild the maps every frame
 *    ("cv::remap+maps": float map, convertMaps and remap, all timed).
 * Periscope has no per-view state, so it is timed the same way on both.
 * A row's time is the median over passes of one pass through its sequence,
 * after one warm-up frame; everything runs on one thread.
 */
#include "bench_support.h"
#include "common/bench_time.h"
#include "psc_io_angle.h"
#include "psc_io_bands.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define BV_NVIEWS 8u /* (and the reference view's frames a pass) */
#define MAX_REPS 15u

enum { SEQ_STATIC, SEQ_MOVING, SEQ_COUNT };
static const char *const seq_name[SEQ_COUNT] = {"static", "moving"};

typedef struct {
    psc_pixfmt_t fmt;
    const char *name, *cv_name;
    int channels;
    bv_family_t family;
} format_t;

/* Each Periscope format is paired with the OpenCV layout of its size class. */
static const format_t formats[] = {
    {PSC_PIX_RGB565, "rgb565", "8UC3", 3, BV_FAMILY_SMALL},
    {PSC_PIX_XRGB8888, "xrgb8888", "8UC4", 4, BV_FAMILY_32BIT},
};
#define NFORMATS (sizeof formats / sizeof formats[0])

typedef struct {
    psc_filter_t filter;
    const char *name;
    uint8_t span_log2;
} render_mode_t;

static const render_mode_t static_modes[] = {
    {PSC_FILTER_NEAREST, "nearest", 0},  {PSC_FILTER_NEAREST, "nearest", 2},  {PSC_FILTER_NEAREST, "nearest", 3},
    {PSC_FILTER_BILINEAR, "bilinear", 0}, {PSC_FILTER_BILINEAR, "bilinear", 2}, {PSC_FILTER_BILINEAR, "bilinear", 3},
#if BV_HAVE_MIP /* N=1 left out to keep the run short: the per-pixel-LUT cost shows in the other filters */
    {PSC_FILTER_MIP, "mip", 2},          {PSC_FILTER_MIP, "mip", 3},
#endif
};
/* While moving, the firmware's two adaptive-quality modes (and the mip default). */
static const render_mode_t moving_modes[] = {
    {PSC_FILTER_NEAREST, "nearest", 3},
    {PSC_FILTER_BILINEAR, "bilinear", 2},
#if BV_HAVE_MIP
    {PSC_FILTER_MIP, "mip", 2},
#endif
};

/* ---- timing ---------------------------------------------------------------- */

typedef int (*frame_fn)(void *ctx, unsigned k);

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/*
 * Median seconds of one pass over views 0..n-1, after one warm-up frame.
 * reps passes, more (up to MAX_REPS) when a pass is short: cheap rows get a
 * steadier median at little cost. -1 if a frame fails.
 */
static int measure(frame_fn fn, void *ctx, unsigned n, unsigned reps, double *median, unsigned *done)
{
    double t[MAX_REPS];
    if (fn(ctx, 0) != 0)
        return -1;
    unsigned want = reps;
    for (unsigned r = 0; r < want; r++) {
        double t0 = bench_now_s();
        for (unsigned k = 0; k < n; k++)
            if (fn(ctx, k) != 0)
                return -1;
        t[r] = bench_now_s() - t0;
        if (r == 0 && t[0] < 0.03)
            want = 2 * reps + 1 < MAX_REPS ? 2 * reps + 1 : MAX_REPS;
    }
    qsort(t, want, sizeof t[0], cmp_double);
    *median = t[want / 2];
    *done = want;
    return 0;
}

/* ---- the renderers as frame functions ---------------------------------------- */

typedef struct {
    psc_viewer_t *viewer;
    const psc_view_t *views;
    const psc_surface_t *out;
    render_mode_t mode;
    psc_io_bands_t *bands;        /* NULL: psc_viewer_render on this thread */
} periscope_job_t;

static int periscope_frame(void *p, unsigned k)
{
    const periscope_job_t *j = p;
    psc_view_t v = j->views[k];
    v.filter = j->mode.filter;
    v.span_log2 = j->mode.span_log2;
    psc_status_t s =
        j->bands ? psc_io_bands_render(j->bands, j->viewer, &v, j->out) : psc_viewer_render(j->viewer, &v, j->out);
    if (s != PSC_OK) {
        fprintf(stderr, "viewer bench: psc_viewer_render (%s, N=%u): %s\n", j->mode.name, 1u << j->mode.span_log2,
                psc_status_str(s));
        return -1;
    }
    return 0;
}

typedef struct {
    const bv_image_t *src;
    bv_image_t *dst;
    int nearest;
    bv_cv_maps_t *const *maps;    /* prebuilt, one per view (cv::remap) */
    const bv_view_t *views;       /* per-frame maps (cv::remap+maps) and the naive renderer */
    float *mapx, *mapy;           /* scratch float maps, out_w x out_h */
    bv_cv_maps_t *scratch;        /* per-frame fixed-point maps */
} cv_job_t;

static int cv_static_frame(void *p, unsigned k)
{
    const cv_job_t *j = p;
    return bv_cv_remap(j->src, j->maps[k], j->dst, j->nearest);
}

/* Float maps of view v for an out_w x out_h output of src: what every remap user computes. */
static void float_maps(const bv_view_t *v, const bv_image_t *src, int out_w, int out_h, float *mapx, float *mapy)
{
    bv_ref_frame_t f;
    bv_ref_frame_init(&f, v, out_w, out_h, src->width, src->height);
    for (int y = 0; y < out_h; y++)
        bv_ref_map_row(&f, y, mapx + (size_t)y * out_w, mapy + (size_t)y * out_w);
}

static int cv_rebuild_frame(void *p, unsigned k)
{
    const cv_job_t *j = p;
    float_maps(&j->views[k], j->src, j->dst->width, j->dst->height, j->mapx, j->mapy);
    if (bv_cv_maps_convert(j->scratch, j->mapx, j->mapy, j->dst->width, j->dst->height, j->nearest) != 0)
        return -1;
    return bv_cv_remap(j->src, j->scratch, j->dst, j->nearest);
}

static int naive_frame(void *p, unsigned k)
{
    const cv_job_t *j = p;
    bv_naive_render(j->src, &j->views[k], j->dst);
    return 0;
}

/* ---- one block: a map size, an output size and a field of view ------------------- */

typedef struct {
    const bv_image_t *src[NFORMATS];      /* BGR, BGRA */
    bv_pack_t *pack[NFORMATS];
    psc_viewer_t *viewer[NFORMATS];
    uint16_t out_w, out_h;
    double hfov;
    psc_view_t pviews[SEQ_COUNT][BV_NVIEWS];
    bv_view_t fviews[SEQ_COUNT][BV_NVIEWS];
    bv_cv_maps_t *maps[SEQ_COUNT][2][BV_NVIEWS]; /* [seq][nearest][view] */
    psc_surface_t surf[NFORMATS];
    bv_image_t dst[NFORMATS];
    float *mapx, *mapy;
    bv_cv_maps_t *scratch;
    unsigned reps;
    bv_results_t *results;
    const char *ffmpeg_map; /* the map as a PPM file for ffmpeg, or NULL */
} block_t;

/* The two sequences at hfov, brought inside the pack's limits by the viewer's
 * own clamp; the float renderers get exactly the clamped angles. */
static void make_views(block_t *b)
{
    for (unsigned s = 0; s < SEQ_COUNT; s++) {
        for (unsigned k = 0; k < BV_NVIEWS; k++) {
            double yaw = 5.0 + 360.0 * k / BV_NVIEWS, pitch;
            if (s == SEQ_STATIC)
                pitch = k % 2 == 0 ? 0.0 : k % 4 == 1 ? 25.0 : -25.0;
            else
                pitch = 60.0 * sin(2.0 * M_PI * (k + 0.5) / BV_NVIEWS);
            psc_view_t v = {.yaw = psc_io_bam_from_deg(yaw), .pitch = psc_io_sbam_from_deg(pitch),
                            .hfov = psc_io_bam_from_deg(b->hfov), .filter = PSC_FILTER_BILINEAR,
                            .span_log2 = PSC_SPAN_LOG2_DEFAULT};
            psc_viewer_clamp(b->viewer[0], &v, b->pack[0]->pack.hfov_min);
            b->pviews[s][k] = v;
            b->fviews[s][k] = (bv_view_t){psc_io_deg_from_bam(v.yaw), psc_io_deg_from_sbam(v.pitch),
                                          psc_io_deg_from_bam(v.hfov)};
        }
    }
}

/* Fixed-point maps of every view, built before timing (the static rows). */
static int build_maps(block_t *b)
{
    for (unsigned s = 0; s < SEQ_COUNT; s++) {
        for (unsigned k = 0; k < BV_NVIEWS; k++) {
            float_maps(&b->fviews[s][k], b->src[0], b->out_w, b->out_h, b->mapx, b->mapy);
            for (int nearest = 0; nearest < 2; nearest++) {
                bv_cv_maps_t *m = b->maps[s][nearest][k] = bv_cv_maps_new();
                if (!m || bv_cv_maps_convert(m, b->mapx, b->mapy, b->out_w, b->out_h, nearest) != 0)
                    return -1;
            }
        }
    }
    return 0;
}

static void free_maps(block_t *b)
{
    for (unsigned s = 0; s < SEQ_COUNT; s++)
        for (unsigned n = 0; n < 2; n++)
            for (unsigned k = 0; k < BV_NVIEWS; k++) {
                bv_cv_maps_free(b->maps[s][n][k]);
                b->maps[s][n][k] = NULL;
            }
}

/* Time one job and append its row. */
static int add_row(block_t *b, frame_fn fn, void *ctx, bv_row_t row)
{
    double t;
    if (measure(fn, ctx, BV_NVIEWS, b->reps, &t, &row.reps) != 0)
        return -1;
    row.map_w = (unsigned)b->src[0]->width;
    row.map_h = (unsigned)b->src[0]->height;
    row.out_w = b->out_w;
    row.out_h = b->out_h;
    row.hfov = b->hfov;
    row.ns_per_px = t * 1e9 / ((double)BV_NVIEWS * b->out_w * b->out_h);
    bv_results_add(b->results, &row);
    return 0;
}

static int periscope_rows(block_t *b, unsigned f, unsigned seq, const render_mode_t *modes, size_t nmodes)
{
    for (size_t i = 0; i < nmodes; i++) {
        periscope_job_t job = {b->viewer[f], b->pviews[seq], &b->surf[f], modes[i], NULL};
        bv_row_t row = {.renderer = "periscope", .filter = modes[i].name, .span = 1u << modes[i].span_log2,
                        .views = seq_name[seq], .format = formats[f].name, .family = formats[f].family};
        if (add_row(b, periscope_frame, &job, row) != 0)
            return -1;
    }
    return 0;
}

static int cv_rows(block_t *b, unsigned f, unsigned seq)
{
    for (int nearest = 1; nearest >= 0; nearest--) {
        cv_job_t job = {b->src[f], &b->dst[f], nearest, b->maps[seq][nearest], b->fviews[seq], b->mapx, b->mapy,
                        b->scratch};
        bv_row_t row = {.renderer = "cv::remap", .filter = nearest ? "nearest" : "bilinear", .views = seq_name[seq],
                        .format = formats[f].cv_name, .family = formats[f].family};
        if (add_row(b, cv_static_frame, &job, row) != 0)
            return -1;
        if (seq == SEQ_MOVING) {
            row.renderer = "cv::remap+maps";
            if (add_row(b, cv_rebuild_frame, &job, row) != 0)
                return -1;
        }
    }
    return 0;
}

/* The second core: Periscope's bands on a pool of two threads against cv::remap on two threads (static views). */
static const render_mode_t two_thread_modes[] = {
    {PSC_FILTER_NEAREST, "nearest", 2},
    {PSC_FILTER_BILINEAR, "bilinear", 2},
};

static int two_thread_rows(block_t *b, unsigned f)
{
    char err[128];
    psc_io_bands_t *pool = psc_io_bands_start(2, b->out_w, err, sizeof err);
    if (!pool) {
        fprintf(stderr, "viewer bench: %s\n", err);
        return -1;
    }
    int rc = 0;
    for (size_t i = 0; i < sizeof two_thread_modes / sizeof two_thread_modes[0] && rc == 0; i++) {
        periscope_job_t job = {b->viewer[f], b->pviews[SEQ_STATIC], &b->surf[f], two_thread_modes[i], pool};
        bv_row_t row = {.renderer = "periscope x2", .threads = 2, .filter = two_thread_modes[i].name,
                        .span = 1u << two_thread_modes[i].span_log2, .views = seq_name[SEQ_STATIC],
                        .format = formats[f].name, .family = formats[f].family};
        rc = add_row(b, periscope_frame, &job, row);
    }
    psc_io_bands_stop(pool);
    bv_cv_threads(2);
    for (int nearest = 1; nearest >= 0 && rc == 0; nearest--) {
        cv_job_t job = {b->src[f], &b->dst[f], nearest, b->maps[SEQ_STATIC][nearest], b->fviews[SEQ_STATIC], b->mapx,
                        b->mapy, b->scratch};
        bv_row_t row = {.renderer = "cv::remap x2", .threads = 2, .filter = nearest ? "nearest" : "bilinear",
                        .views = seq_name[SEQ_STATIC], .format = formats[f].cv_name, .family = formats[f].family};
        rc = add_row(b, cv_static_frame, &job, row);
    }
    bv_cv_threads(1);
    return rc;
}

/* FFmpeg's v360 on one static view (its per-frame remap; tables built once), one and two threads. */
static int ffmpeg_rows(block_t *b)
{
    const bv_view_t *v = &b->fviews[SEQ_STATIC][1]; /* pitch 25 */
    for (int threads = 1; threads <= 2; threads++)
        for (int nearest = 1; nearest >= 0; nearest--) {
            double ns = bv_ffmpeg_v360_ns(b->ffmpeg_map, v, b->out_w, b->out_h, nearest, threads);
            if (ns <= 0.0) {
                fprintf(stderr, "viewer bench: ffmpeg v360 failed; no v360 rows\n");
                return 0;
            }
            bv_row_t row = {.renderer = threads == 1 ? "ffmpeg v360" : "ffmpeg v360 x2", .threads = (unsigned)threads,
                            .filter = nearest ? "nearest" : "bilinear", .views = seq_name[SEQ_STATIC],
                            .format = formats[0].cv_name, .family = formats[0].family, .reps = 1};
            row.map_w = (unsigned)b->src[0]->width;
            row.map_h = (unsigned)b->src[0]->height;
            row.out_w = b->out_w;
            row.out_h = b->out_h;
            row.hfov = b->hfov;
            row.ns_per_px = ns;
            bv_results_add(b->results, &row);
        }
    return 0;
}

static int naive_row(block_t *b, unsigned f, unsigned seq)
{
    cv_job_t job = {b->src[f], &b->dst[f], 0, NULL, b->fviews[seq], NULL, NULL, NULL};
    bv_row_t row = {.renderer = "naive float", .filter = "bilinear", .views = seq_name[seq],
                    .format = formats[f].cv_name, .family = formats[f].family};
    return add_row(b, naive_frame, &job, row);
}

/*
 * The reference view of issues 14 and 30: 1024x768 from the 4096x2048 map, yaw 30 pitch 20 hfov 75, the same view
 * over and over (its maps warm), XRGB8888 against 8UC4 on one core: Periscope nearest and bilinear at the default
 * span against cv::remap through maps built once. Rows with views "fixed".
 */
#define REF_VIEW_FRAMES 8u
static int reference_view_rows(block_t *b)
{
    const unsigned f = 1; /* xrgb8888 / 8UC4 */
    psc_view_t pv[REF_VIEW_FRAMES];
    bv_view_t fv[REF_VIEW_FRAMES];
    bv_cv_maps_t *maps[2][REF_VIEW_FRAMES] = {{NULL}};
    psc_view_t v = {.yaw = psc_io_bam_from_deg(30.0), .pitch = psc_io_sbam_from_deg(20.0),
                    .hfov = psc_io_bam_from_deg(75.0), .filter = PSC_FILTER_BILINEAR, .span_log2 = PSC_SPAN_LOG2_DEFAULT};
    psc_viewer_clamp(b->viewer[f], &v, b->pack[f]->pack.hfov_min);
    bv_view_t bvv = {psc_io_deg_from_bam(v.yaw), psc_io_deg_from_sbam(v.pitch), psc_io_deg_from_bam(v.hfov)};
    int rc = 0;
    float_maps(&bvv, b->src[f], b->out_w, b->out_h, b->mapx, b->mapy);
    for (int nearest = 0; nearest < 2 && rc == 0; nearest++) {
        maps[nearest][0] = bv_cv_maps_new();
        if (!maps[nearest][0] ||
            bv_cv_maps_convert(maps[nearest][0], b->mapx, b->mapy, b->out_w, b->out_h, nearest) != 0)
            rc = -1;
    }
    for (unsigned k = 0; k < REF_VIEW_FRAMES; k++) {   /* one view, its maps shared */
        pv[k] = v;
        fv[k] = bvv;
        maps[0][k] = maps[0][0];
        maps[1][k] = maps[1][0];
    }
    for (int nearest = 1; nearest >= 0 && rc == 0; nearest--) {
        cv_job_t job = {b->src[f], &b->dst[f], nearest, maps[nearest], fv, NULL, NULL, NULL};
        bv_row_t row = {.renderer = "cv::remap", .filter = nearest ? "nearest" : "bilinear", .views = "fixed",
                        .format = formats[f].cv_name, .family = formats[f].family};
        rc = add_row(b, cv_static_frame, &job, row);
        if (rc == 0) {
            render_mode_t mode = {nearest ? PSC_FILTER_NEAREST : PSC_FILTER_BILINEAR, nearest ? "nearest" : "bilinear",
                                  PSC_SPAN_LOG2_DEFAULT};
            periscope_job_t pj = {b->viewer[f], pv, &b->surf[f], mode, NULL};
            bv_row_t pr = {.renderer = "periscope", .filter = mode.name, .span = 1u << mode.span_log2,
                           .views = "fixed", .format = formats[f].name, .family = formats[f].family};
            rc = add_row(b, periscope_frame, &pj, pr);
        }
    }
    for (int nearest = 0; nearest < 2; nearest++)
        bv_cv_maps_free(maps[nearest][0]);
    return rc;
}

/* ---- agreement: do the renderers draw the same picture? --------------------------- */

/* PSNR over B, G, R of two 4-channel images of the same size. */
static double psnr_bgra(const uint8_t *a, const uint8_t *b, size_t pixels)
{
    double se = 0.0;
    for (size_t i = 0; i < pixels; i++)
        for (unsigned c = 0; c < 3; c++) {
            double d = (double)a[4 * i + c] - (double)b[4 * i + c];
            se += d * d;
        }
    double mse = se / (3.0 * (double)pixels);
    return mse > 0.0 ? 10.0 * log10(255.0 * 255.0 / mse) : 99.0;
}

/* Static view 0 through the naive renderer, cv::remap bilinear and Periscope
 * bilinear N=4 (all 32-bit output): a timing is only worth quoting if the
 * pictures agree. */
static int agreement(block_t *b, bv_meta_t *meta)
{
    size_t px = (size_t)b->out_w * b->out_h;
    bv_image_t ref = b->dst[1];
    ref.data = malloc(px * 4);
    if (!ref.data)
        return -1;
    int rc = -1;
    bv_naive_render(b->src[1], &b->fviews[SEQ_STATIC][0], &ref);
    if (bv_cv_remap(b->src[1], b->maps[SEQ_STATIC][0][0], &b->dst[1], 0) == 0) {
        meta->agree_cv_db = psnr_bgra(ref.data, b->dst[1].data, px);
        periscope_job_t job = {b->viewer[1], b->pviews[SEQ_STATIC], &b->surf[1], {PSC_FILTER_BILINEAR, "bilinear", 2},
                               NULL};
        if (periscope_frame(&job, 0) == 0) {
            meta->agree_psc_db = psnr_bgra(ref.data, b->surf[1].pixels, px);
            rc = 0;
        }
    }
    free(ref.data);
    return rc;
}

/* All rows of one block; with meta, also the agreement check on its maps. */
static int run_block(block_t *b, bv_meta_t *meta)
{
    make_views(b);
    if (build_maps(b) != 0)
        return -1;
    int rc = meta ? agreement(b, meta) : 0;
    for (unsigned f = 0; f < NFORMATS && rc == 0; f++) {
        rc = cv_rows(b, f, SEQ_STATIC);
        if (rc == 0)
            rc = periscope_rows(b, f, SEQ_STATIC, static_modes, sizeof static_modes / sizeof static_modes[0]);
        if (rc == 0)
            rc = two_thread_rows(b, f);
        if (rc == 0 && f == 0 && b->ffmpeg_map)
            rc = ffmpeg_rows(b);
        if (rc == 0)
            rc = naive_row(b, f, SEQ_STATIC);
        if (rc == 0)
            rc = cv_rows(b, f, SEQ_MOVING);
        if (rc == 0)
            rc = periscope_rows(b, f, SEQ_MOVING, moving_modes, sizeof moving_modes / sizeof moving_modes[0]);
    }
    free_maps(b);
    return rc;
}

/* ---- the sweep -------------------------------------------------------------------- */

typedef struct {
    uint16_t w, h;
} size2_t;

static const size2_t out_sizes[] = {{800, 480}, {1024, 768}};
static const double hfovs[] = {30.0, 75.0, 120.0};
#define NOUTS (sizeof out_sizes / sizeof out_sizes[0])
#define NHFOVS (sizeof hfovs / sizeof hfovs[0])

typedef struct {
    bool quick;
    unsigned reps;
    double t_start;
    unsigned blocks_done, blocks_total;
} sweep_t;

/* Output buffers, packs and viewers for one map at one output size, then its three fields of view. */
static int run_output_size(sweep_t *sw, const psc_image_t *img, const bv_image_t *src3, const bv_image_t *src4,
                           const char *ffmpeg_map, size2_t out, bv_results_t *res, bv_meta_t *meta)
{
    bv_pack_t packs[NFORMATS] = {{0}};
    psc_viewer_t viewers[NFORMATS];
    void *ws[NFORMATS] = {NULL};
    block_t *b = calloc(1, sizeof *b);
    size_t px = (size_t)out.w * out.h;
    int rc = b ? 0 : -1;
    if (rc == 0) {
        b->src[0] = src3;
        b->src[1] = src4;
        b->out_w = out.w;
        b->out_h = out.h;
        b->reps = sw->reps;
        b->results = res;
        b->ffmpeg_map = ffmpeg_map;
        b->mapx = malloc(px * sizeof(float));
        b->mapy = malloc(px * sizeof(float));
        b->scratch = bv_cv_maps_new();
        if (!b->mapx || !b->mapy || !b->scratch)
            rc = -1;
    }
    for (unsigned f = 0; f < NFORMATS && rc == 0; f++) {
        fprintf(stderr, "viewer bench: packing %ux%u %s for %ux%u\n", img->width, img->height, formats[f].name,
                out.w, out.h);
        b->pack[f] = &packs[f];
        b->viewer[f] = &viewers[f];
        uint32_t bpp = psc_pixfmt_bytes(formats[f].fmt);
        b->surf[f] = (psc_surface_t){out.w, out.h, out.w * bpp, formats[f].fmt, calloc(px, bpp)};
        b->dst[f] = (bv_image_t){calloc(px, (size_t)formats[f].channels), out.w, out.h, formats[f].channels,
                                 (size_t)out.w * formats[f].channels};
        if (!b->surf[f].pixels || !b->dst[f].data || bv_pack_make(img, formats[f].fmt, out.w, out.h, &packs[f]) != 0 ||
            bv_viewer_open(&viewers[f], &packs[f], out.w, out.h, &ws[f]) != 0)
            rc = -1;
    }
    /* Table memory: the 800x480 display pack of the bundled sample, RGB565. */
    if (rc == 0 && img->width == 4096 && out.w == 800 && out.h == 480) {
        const psc_pack_t *p = &packs[0].pack;
        meta->table_lut_bytes = bv_pack_lut_bytes(&packs[0]);
        meta->table_ws_bytes = psc_viewer_workspace_size(out.w, out.h, &p->map);
        meta->table_lut_count = p->lut_count;
        size_t at = 0;
        for (unsigned i = 0; i < p->lut_count; i++)
            at += (size_t)snprintf(meta->table_luts + at, sizeof meta->table_luts - at, "%s%ux%u", i ? " + " : "",
                                   (unsigned)p->luts[i].rows, (unsigned)p->luts[i].cols);
    }
    if (rc == 0 && img->width == 4096 && out.w == 1024 && out.h == 768) {
        fprintf(stderr, "viewer bench: the reference view (1024x768, yaw 30 pitch 20 hfov 75) ... ");
        b->hfov = 75.0;
        rc = reference_view_rows(b);
        fprintf(stderr, "%.0f s elapsed\n", bench_now_s() - sw->t_start);
    }
    for (unsigned h = 0; h < NHFOVS && rc == 0; h++) {
        if (sw->quick && (hfovs[h] != 75.0 || out.w != 800))
            continue;
        b->hfov = hfovs[h];
        fprintf(stderr, "viewer bench: [%2u/%u] map %ux%u, output %ux%u, hfov %g ... ", ++sw->blocks_done,
                sw->blocks_total, img->width, img->height, out.w, out.h, hfovs[h]);
        bool check = img->width == 4096 && out.w == 800 && hfovs[h] == 75.0;
        rc = run_block(b, check ? meta : NULL);
        fprintf(stderr, "%.0f s elapsed\n", bench_now_s() - sw->t_start);
    }
    for (unsigned f = 0; f < NFORMATS; f++) {
        if (b) {
            free(b->surf[f].pixels);
            free(b->dst[f].data);
        }
        free(ws[f]);
        bv_pack_free(&packs[f]);
    }
    if (b) {
        free(b->mapx);
        free(b->mapy);
        bv_cv_maps_free(b->scratch);
    }
    free(b);
    return rc;
}

/* Every output size for one map (the sample, or its 2x upscale). */
static int run_map(sweep_t *sw, const psc_image_t *img, bv_results_t *res, bv_meta_t *meta)
{
    bv_image_t src3;
    if (bv_image_bgr(img, &src3) != 0)
        return -1;
    bv_image_t src4 = bv_image_bgra(img);
    /* FFmpeg reads the map from a file */
    char dir[] = "/tmp/periscope-bench-XXXXXX", map[sizeof dir + 16];
    const char *ffmpeg_map = NULL;
    if (bv_ffmpeg_available() && mkdtemp(dir)) {
        snprintf(map, sizeof map, "%s/map.ppm", dir);
        if (bv_ffmpeg_write_map(&src3, map) == 0)
            ffmpeg_map = map;
        else
            fprintf(stderr, "viewer bench: cannot write %s: no ffmpeg rows\n", map);
    }
    int rc = 0;
    for (unsigned o = 0; o < NOUTS && rc == 0; o++)   /* --quick: 800x480 at hfov 75, and the reference view */
        rc = run_output_size(sw, img, &src3, &src4, ffmpeg_map, out_sizes[o], res, meta);
    if (dir[sizeof dir - 2] != 'X') { /* mkdtemp made it */
        unlink(map);
        rmdir(dir);
    }
    free(src3.data);
    return rc;
}

int bv_speed_main(const char *out_dir, bool quick, unsigned reps)
{
    sweep_t sw = {quick, reps, bench_now_s(), 0, quick ? 1u : 2u * NOUTS * NHFOVS};
    bv_meta_t meta = {0};
    bv_results_t res = {0};
    bv_meta_machine(&meta);
    meta.views_per_seq = BV_NVIEWS;
    meta.have_mip = BV_HAVE_MIP;
    if (bv_cv_init(meta.opencv, sizeof meta.opencv) != 0)
        return 1;
    fprintf(stderr, "viewer bench: %s, %s, OpenCV %s one thread (x2 rows: two); %u views per sequence, median of >= %u passes\n",
            meta.machine, meta.cpu, meta.opencv, BV_NVIEWS, reps);

    psc_image_t sample = {0}, big = {0};
    int rc = bv_load_sample(BV_SAMPLE, &sample) == 0 ? 0 : -1;
    if (rc == 0)
        rc = run_map(&sw, &sample, &res, &meta);
    if (rc == 0 && !quick) {
        fprintf(stderr, "viewer bench: upscaling the sample to %ux%u\n", 2 * sample.width, 2 * sample.height);
        rc = bv_upscale2x(&sample, &big);
        /* The sample is no longer needed: keep the peak memory down. */
        psc_io_image_free(&sample);
        if (rc == 0)
            rc = run_map(&sw, &big, &res, &meta);
    }
    psc_io_image_free(&sample);
    psc_io_image_free(&big);
    if (rc != 0) {
        free(res.rows);
        return 1;
    }
    meta.seconds = bench_now_s() - sw.t_start;
    bv_results_ratios(&res);
    bv_report_print(stdout, &res, &meta);
    char path[4096];
    snprintf(path, sizeof path, "%s/viewer.json", out_dir);
    rc = bv_report_json(path, &res, &meta);
    if (rc == 0)
        printf("\nwritten: %s\n", path);
    free(res.rows);
    return rc == 0 ? 0 : 1;
}
