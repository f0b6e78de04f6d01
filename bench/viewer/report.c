/* SPDX-License-Identifier: MIT */
/*
 * report.c - the benchmark's one table, the notes under it (table memory,
 * zoom-out against zoom-in, the goals) and the same as JSON.
 */
#include "bench_support.h"

#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>

#define KIB 1024.0
#define TABLE_GOAL_BYTES (512u * 1024u)
#define SPEEDUP_GOAL 2.0
/* Zoom-out counts as "no slower" within this much: the timing noise of a shared 2-core machine. */
#define ZOOM_TOLERANCE 1.05

void bv_results_add(bv_results_t *r, const bv_row_t *row)
{
    if (r->count == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 256;
        bv_row_t *rows = realloc(r->rows, cap * sizeof *rows);
        if (!rows) {
            fprintf(stderr, "viewer bench: out of memory for results\n");
            exit(1);
        }
        r->rows = rows;
        r->cap = cap;
    }
    r->rows[r->count++] = *row;
}

static bool same_setup(const bv_row_t *a, const bv_row_t *b)
{
    return a->map_w == b->map_w && a->out_w == b->out_w && a->out_h == b->out_h && a->hfov == b->hfov;
}

/* mip and the naive renderer are compared with bilinear remap. */
static const char *remap_filter(const char *filter)
{
    return strcmp(filter, "nearest") == 0 ? "nearest" : "bilinear";
}

static const bv_row_t *remap_reference(const bv_results_t *r, const bv_row_t *row)
{
    for (size_t i = 0; i < r->count; i++) {
        const bv_row_t *c = &r->rows[i];
        bool remap = strcmp(c->renderer, "cv::remap") == 0 || strcmp(c->renderer, "cv::remap x2") == 0;
        if (remap && (c->threads > 1) == (row->threads > 1) && same_setup(c, row) && c->family == row->family &&
            strcmp(c->views, row->views) == 0 && strcmp(c->filter, remap_filter(row->filter)) == 0)
            return c;
    }
    return NULL;
}

void bv_results_ratios(bv_results_t *r)
{
    for (size_t i = 0; i < r->count; i++) {
        const bv_row_t *ref = remap_reference(r, &r->rows[i]);
        r->rows[i].ratio = ref ? ref->ns_per_px / r->rows[i].ns_per_px : 0.0;
    }
}

void bv_meta_machine(bv_meta_t *m)
{
    struct utsname u;
    snprintf(m->machine, sizeof m->machine, "%s", uname(&u) == 0 ? u.machine : "unknown");
    snprintf(m->cpu, sizeof m->cpu, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        char *colon = strchr(line, ':');
        if (strncmp(line, "model name", 10) == 0 && colon) {
            colon += strspn(colon + 1, " \t") + 1;
            colon[strcspn(colon, "\n")] = '\0';
            snprintf(m->cpu, sizeof m->cpu, "%s", colon);
            break;
        }
    }
    if (f)
        fclose(f);
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    size_t n = strlen(m->cpu);
    snprintf(m->cpu + n, sizeof m->cpu - n, ", %ld cores", cores);
    time_t t = time(NULL);
    struct tm tm;
    gmtime_r(&t, &tm);
    strftime(m->date, sizeof m->date, "%Y-%m-%dT%H:%M:%SZ", &tm);
}

/* ---- summaries derived from the rows --------------------------------------------- */

/* Min, median and max of the ratios of Periscope rows (filter, span, format, views). */
typedef struct {
    double min, med, max;
    unsigned n;
} spread_t;

static spread_t renderer_ratio_spread(const bv_results_t *r, const char *renderer, const char *filter, unsigned span,
                                      const char *format, const char *views)
{
    double v[64];
    spread_t s = {0};
    for (size_t i = 0; i < r->count && s.n < 64; i++) {
        const bv_row_t *c = &r->rows[i];
        if (strcmp(c->renderer, renderer) == 0 && strcmp(c->filter, filter) == 0 && c->span == span &&
            strcmp(c->format, format) == 0 && strcmp(c->views, views) == 0 && c->ratio > 0.0)
            v[s.n++] = c->ratio;
    }
    if (s.n == 0)
        return s;
    for (unsigned i = 1; i < s.n; i++) /* insertion sort: a dozen values */
        for (unsigned j = i; j > 0 && v[j - 1] > v[j]; j--) {
            double t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
    s.min = v[0];
    s.max = v[s.n - 1];
    s.med = s.n % 2 ? v[s.n / 2] : 0.5 * (v[s.n / 2 - 1] + v[s.n / 2]);
    return s;
}

static spread_t ratio_spread(const bv_results_t *r, const char *filter, unsigned span, const char *format,
                             const char *views)
{
    return renderer_ratio_spread(r, "periscope", filter, span, format, views);
}

/* The row of `renderer` in the setup, filter, span, format and views of `row` (or NULL). */
static const bv_row_t *partner(const bv_results_t *r, const bv_row_t *row, const char *renderer, const char *views,
                               const char *format)
{
    for (size_t i = 0; i < r->count; i++) {
        const bv_row_t *c = &r->rows[i];
        if (same_setup(c, row) && strcmp(c->renderer, renderer) == 0 && strcmp(c->filter, row->filter) == 0 &&
            c->span == row->span && strcmp(c->views, views) == 0 && strcmp(c->format, format) == 0)
            return c;
    }
    return NULL;
}

/*
 * Min and max over every setup of (partner time / time) for the Periscope
 * rows of a filter, span and format: how many times faster Periscope is than
 * the partner (or, with invert, the partner than Periscope).
 */
static spread_t speed_spread(const bv_results_t *r, const char *filter, unsigned span, const char *format,
                             const char *partner_renderer, const char *partner_views, const char *partner_format,
                             bool invert)
{
    spread_t s = {0};
    for (size_t i = 0; i < r->count; i++) {
        const bv_row_t *c = &r->rows[i], *p;
        if (strcmp(c->renderer, "periscope") != 0 || strcmp(c->filter, filter) != 0 || c->span != span ||
            strcmp(c->format, format) != 0 || strcmp(c->views, "static") != 0)
            continue;
        bv_row_t key = *c;
        key.span = strcmp(partner_renderer, "periscope") == 0 || strcmp(partner_renderer, "periscope x2") == 0 ? span : 0;
        if (!(p = partner(r, &key, partner_renderer, partner_views, partner_format)))
            continue;
        double q = invert ? c->ns_per_px / p->ns_per_px : p->ns_per_px / c->ns_per_px;
        s.min = s.n == 0 || q < s.min ? q : s.min;
        s.max = s.n == 0 || q > s.max ? q : s.max;
        s.n++;
    }
    return s;
}

/* The row like `row` but at another field of view (or NULL). */
static const bv_row_t *at_hfov(const bv_results_t *r, const bv_row_t *row, double hfov)
{
    for (size_t i = 0; i < r->count; i++) {
        const bv_row_t *c = &r->rows[i];
        if (c->hfov == hfov && c->map_w == row->map_w && c->out_w == row->out_w && c->out_h == row->out_h &&
            strcmp(c->renderer, row->renderer) == 0 && strcmp(c->filter, row->filter) == 0 && c->span == row->span &&
            strcmp(c->format, row->format) == 0 && strcmp(c->views, row->views) == 0)
            return c;
    }
    return NULL;
}

/* Zoom-out rows: Periscope or cv::remap, static views, the largest map, hfov 120 (with a hfov 30 partner). */
static bool is_zoom_out(const bv_results_t *r, const bv_row_t *c)
{
    return (strcmp(c->renderer, "periscope") == 0 || strcmp(c->renderer, "cv::remap") == 0) &&
           strcmp(c->views, "static") == 0 && c->map_w == 8192 && c->hfov == 120.0 && at_hfov(r, c, 30.0);
}

/* The cv::remap+maps row a moving Periscope row competes with (or NULL). */
static const bv_row_t *rebuild_reference(const bv_results_t *r, const bv_row_t *row)
{
    for (size_t i = 0; i < r->count; i++) {
        const bv_row_t *c = &r->rows[i];
        if (strcmp(c->renderer, "cv::remap+maps") == 0 && same_setup(c, row) && c->family == row->family &&
            strcmp(c->filter, remap_filter(row->filter)) == 0)
            return c;
    }
    return NULL;
}

/* ---- text -------------------------------------------------------------------------- */

static void print_row(FILE *f, const bv_row_t *c)
{
    char span[12] = "-", map[24], out[24], ratio[32] = "-";
    if (c->span)
        snprintf(span, sizeof span, "%u", c->span);
    snprintf(map, sizeof map, "%ux%u", c->map_w, c->map_h);
    snprintf(out, sizeof out, "%ux%u", c->out_w, c->out_h);
    if (c->ratio > 0.0)
        snprintf(ratio, sizeof ratio, "%.2f", c->ratio);
    fprintf(f, "%-15s %-9s %4s  %-7s %-9s %-10s %-9s %4.0f %8.2f %8.1f %8s\n", c->renderer, c->filter, span, c->views,
            c->format, map, out, c->hfov, c->ns_per_px, 1e3 / c->ns_per_px, ratio);
}

static void print_speedups(FILE *f, const bv_results_t *r)
{
    static const char *const filters[] = {"nearest", "bilinear", "mip"};
    static const char *const fmts[] = {"rgb565", "xrgb8888"};
    static const char *const views[] = {"static", "moving"};
    fprintf(f, "\nSpeed-up over cv::remap (same filter, prebuilt maps; mip against bilinear), over all map sizes,\n"
               "output sizes and fields of view: min / median / max\n");
    for (unsigned v = 0; v < 2; v++)
        for (unsigned fi = 0; fi < 3; fi++)
            for (unsigned span = 1; span <= 8; span *= 2)
                for (unsigned k = 0; k < 2; k++) {
                    spread_t s = ratio_spread(r, filters[fi], span, fmts[k], views[v]);
                    if (s.n)
                        fprintf(f, "  periscope %-8s N=%u %-8s %-6s views: %5.2f / %5.2f / %5.2f  (%u setups)\n",
                                filters[fi], span, fmts[k], views[v], s.min, s.med, s.max, s.n);
                }
}

static void print_zoom(FILE *f, const bv_results_t *r, double *worst)
{
    fprintf(f, "\nZoom-out against zoom-in (8192x4096 map, static views): ns/pixel at hfov 120 / at hfov 30\n");
    *worst = 0.0;
    for (int periscope = 1; periscope >= 0; periscope--) {
        for (size_t i = 0; i < r->count; i++) {
            const bv_row_t *c = &r->rows[i];
            if (!is_zoom_out(r, c) || (strcmp(c->renderer, "periscope") == 0) != periscope)
                continue;
            double q = c->ns_per_px / at_hfov(r, c, 30.0)->ns_per_px;
            char span[16] = "";
            if (c->span)
                snprintf(span, sizeof span, "N=%u", c->span);
            if (periscope && q > *worst)
                *worst = q;
            fprintf(f, "  %-10s %-8s %-4s %-8s %4ux%-4u  %5.2f  %s\n", c->renderer, c->filter, span, c->format,
                    c->out_w, c->out_h, q,
                    !periscope ? "(for comparison)" : q <= 1.0 ? "no slower" : q <= ZOOM_TOLERANCE ? "within noise" : "SLOWER");
        }
    }
}

static const char *verdict(bool met)
{
    return met ? "met" : "NOT met";
}

#define SECOND_CORE_GOAL 1.8

static void print_goals(FILE *f, const bv_results_t *r, const bv_meta_t *m, double zoom_worst)
{
    static const char *const filters[] = {"nearest", "bilinear"};
    static const char *const fmts[] = {"rgb565", "xrgb8888"}, *const cv_fmts[] = {"8UC3", "8UC4"};
    fprintf(f, "\nGoals (issues 4 and 14), N=4, static views, over every map, output size and hfov (min..max):\n");
    for (unsigned fi = 0; fi < 2; fi++) {
        spread_t s[2] = {ratio_spread(r, filters[fi], 4, fmts[0], "static"),
                         ratio_spread(r, filters[fi], 4, fmts[1], "static")};
        fprintf(f, "  one core, %-8s >= %.0fx cv::remap: rgb565 vs 8UC3 %.2f..%.2fx, xrgb8888 vs 8UC4 %.2f..%.2fx: %s\n",
                filters[fi], SPEEDUP_GOAL, s[0].min, s[0].max, s[1].min, s[1].max,
                verdict(s[0].n && s[1].n && s[0].min >= SPEEDUP_GOAL && s[1].min >= SPEEDUP_GOAL));
    }
    for (unsigned fi = 0; fi < 2; fi++) {
        spread_t s[2], cv[2];
        for (unsigned k = 0; k < 2; k++) { /* one thread's time over two threads' */
            s[k] = speed_spread(r, filters[fi], 4, fmts[k], "periscope x2", "static", fmts[k], true);
            cv[k] = renderer_ratio_spread(r, "periscope x2", filters[fi], 4, fmts[k], "static");
        }
        fprintf(f, "  second core, %-8s >= %.1fx one core: rgb565 %.2f..%.2fx, xrgb8888 %.2f..%.2fx: %s\n"
                   "    (two threads against cv::remap on two threads: %.2f..%.2fx, %.2f..%.2fx)\n",
                filters[fi], SECOND_CORE_GOAL, s[0].min, s[0].max, s[1].min, s[1].max,
                verdict(s[0].n && s[1].n && s[0].min >= SECOND_CORE_GOAL && s[1].min >= SECOND_CORE_GOAL),
                cv[0].min, cv[0].max, cv[1].min, cv[1].max);
    }
    for (unsigned fi = 0; fi < 2; fi++) {
        spread_t s = speed_spread(r, filters[fi], 4, fmts[0], "ffmpeg v360", "static", cv_fmts[0], false);
        if (s.n)
            fprintf(f, "  FFmpeg v360 (one thread, tables built once), %-8s: Periscope rgb565 %.2f..%.2fx as fast\n",
                    filters[fi], s.min, s.max);
        else if (fi == 0)
            fprintf(f, "  FFmpeg v360: ffmpeg is not installed (bench/packages.txt lists it): no rows\n");
    }
    /* Pitch every frame: Periscope keeps no per-view state, so its frame costs the same whether or not the
     * pitch moved, while a remap user rebuilds the maps. Compared on the moving views. */
    double lo = 0.0, hi = 0.0, plo = 0.0, phi = 0.0;
    for (size_t i = 0; i < r->count; i++) {
        const bv_row_t *c = &r->rows[i], *rb;
        if (strcmp(c->renderer, "periscope") != 0 || strcmp(c->views, "moving") != 0 || !(rb = rebuild_reference(r, c)))
            continue;
        double q = rb->ns_per_px / c->ns_per_px;
        lo = lo == 0.0 || q < lo ? q : lo;
        hi = q > hi ? q : hi;
        plo = plo == 0.0 || c->ratio < plo ? c->ratio : plo;
        phi = c->ratio > phi ? c->ratio : phi;
    }
    if (hi > 0.0)
        fprintf(f, "  pitch change every frame: Periscope has no per-view state, nothing to rebuild. On the moving views\n"
                   "    it is %.2f..%.2fx as fast as cv::remap rebuilding its maps each frame (cv::remap+maps),\n"
                   "    %.2f..%.2fx as fast as remap with maps prebuilt for those very views\n",
                lo, hi, plo, phi);
    /* Periscope's own cost when the pitch moves every frame: moving over static time, same filter and span. */
    for (unsigned fi = 0; fi < 2; fi++) {
        unsigned span = fi == 0 ? 8u : 4u; /* the moving rows: the firmware's adaptive-quality modes */
        spread_t sp = speed_spread(r, filters[fi], span, fmts[0], "periscope", "moving", fmts[0], false);
        if (sp.n)
            fprintf(f, "  pitch moving every frame, %-8s N=%u: Periscope's moving time / static time %.2f..%.2f "
                       "(1 = unchanged; the moving views reach nearer the poles)\n",
                    filters[fi], span, sp.min, sp.max);
    }
    size_t total = m->table_lut_bytes + m->table_ws_bytes;
    fprintf(f, "  table memory <= 512 KiB (800x480 display, default tables): %.1f KiB: %s\n", total / KIB,
            verdict(total <= TABLE_GOAL_BYTES));
    if (zoom_worst > 0.0)
        fprintf(f, "  zoom-out (hfov 120, 8192x4096) no slower than zoom-in (hfov 30): worst ratio %.2f: %s\n",
                zoom_worst, verdict(zoom_worst <= ZOOM_TOLERANCE));
    fprintf(f, "  instructions per pixel (<= 12 nearest, <= 32 bilinear, <= 48 mip): see `make bench-callgrind`\n");
}

void bv_report_print(FILE *f, const bv_results_t *r, const bv_meta_t *m)
{
    fprintf(f, "\nViewer speed: %s (%s), OpenCV %s, one thread (\"x2\" rows: two), %s\n", m->machine, m->cpu, m->opencv,
            m->date);
    fprintf(f, "%-15s %-9s %4s  %-7s %-9s %-10s %-9s %4s %8s %8s %8s\n", "renderer", "filter", "span", "views", "format",
            "map", "output", "hfov", "ns/px", "Mpx/s", "vs remap");
    for (size_t i = 0; i < r->count; i++) {
        if (i > 0 && !same_setup(&r->rows[i], &r->rows[i - 1]))
            fputc('\n', f);
        print_row(f, &r->rows[i]);
    }
    fprintf(f,
            "\nformat: map and output pixels. rgb565 / xrgb8888: Periscope (core psc_viewer_render); 8UC3 / 8UC4: BGR /\n"
            "  BGRA for cv::remap and the naive renderer, compared with rgb565 and xrgb8888 respectively.\n"
            "views: %u per sequence, yaw round the full turn; static: pitch 0/+25/0/-25, cv::remap maps prebuilt per\n"
            "  view (untimed); moving: pitch changes every frame (+-60), cv::remap+maps = float map (atan2/asin per\n"
            "  pixel, as the naive renderer) + convertMaps + remap, all timed. BORDER_WRAP joins the seam.\n"
            "vs remap: time of cv::remap (same filter, prebuilt maps, same views and sizes, same threads) / this row's time:\n"
            "  above 1 = faster than remap. Median of the passes; one warm-up frame; %.0f s in all.\n",
            m->views_per_seq, m->seconds);
    fprintf(f, "Agreement with the naive renderer (static view 0, 4096x2048 -> 800x480, hfov 75): cv::remap bilinear "
               "%.1f dB, periscope bilinear N=4 %.1f dB PSNR\n",
            m->agree_cv_db, m->agree_psc_db);
    fprintf(f, "Table memory (800x480 display pack, default tables: %s LUTs %.1f KiB + viewer workspace %.1f KiB): "
               "%.1f KiB\n",
            m->table_luts, m->table_lut_bytes / KIB, m->table_ws_bytes / KIB,
            (m->table_lut_bytes + m->table_ws_bytes) / KIB);
    if (!m->have_mip)
        fprintf(f, "mip: core has no PSC_FILTER_MIP yet; no mip rows\n");
    print_speedups(f, r);
    double zoom_worst;
    print_zoom(f, r, &zoom_worst);
    print_goals(f, r, m, zoom_worst);
}

/* ---- JSON -------------------------------------------------------------------------- */

void bv_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"' || *s == '\\')
            fputc('\\', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

/* Written to path.tmp and renamed when complete: a failed run leaves no half-written results. */
FILE *bv_json_begin(const char *path, const char *benchmark, const bv_meta_t *m, char tmp[BV_JSON_TMP_LEN])
{
    snprintf(tmp, BV_JSON_TMP_LEN, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        perror(tmp);
        return NULL;
    }
    fprintf(f, "{\n  \"benchmark\": \"%s\",\n  \"date\": \"%s\",\n  \"machine\": {\"arch\": ", benchmark, m->date);
    bv_json_string(f, m->machine);
    fprintf(f, ", \"cpu\": ");
    bv_json_string(f, m->cpu);
    fprintf(f, "}");
    return f;
}

int bv_json_end(FILE *f, const char *tmp, const char *path)
{
    if (fclose(f) != 0 || rename(tmp, path) != 0) {
        perror(path);
        return -1;
    }
    return 0;
}

/* Periscope's span, or null where it does not apply. */
static void json_span(FILE *f, unsigned span)
{
    if (span)
        fprintf(f, "%u", span);
    else
        fprintf(f, "null");
}

static void json_row(FILE *f, const bv_row_t *c)
{
    fprintf(f, "{\"renderer\": ");
    bv_json_string(f, c->renderer);
    fprintf(f, ", \"filter\": \"%s\", \"span\": ", c->filter);
    json_span(f, c->span);
    fprintf(f, ", \"threads\": %u, \"views\": \"%s\", \"format\": \"%s\", ", c->threads > 1 ? c->threads : 1u,
            c->views, c->format);
    fprintf(f, "\"map\": \"%ux%u\", \"output\": \"%ux%u\", \"hfov\": %g, \"ns_per_pixel\": %.4f, "
               "\"mpixel_per_s\": %.3f, \"ratio_to_remap\": ",
            c->map_w, c->map_h, c->out_w, c->out_h, c->hfov, c->ns_per_px, 1e3 / c->ns_per_px);
    if (c->ratio > 0.0)
        fprintf(f, "%.4f", c->ratio);
    else
        fprintf(f, "null");
    fprintf(f, ", \"passes\": %u}", c->reps);
}

int bv_report_json(const char *path, const bv_results_t *r, const bv_meta_t *m)
{
    char tmp[BV_JSON_TMP_LEN];
    FILE *f = bv_json_begin(path, "viewer", m, tmp);
    if (!f)
        return -1;
    fprintf(f, ",\n  \"opencv\": \"%s\",\n  \"views_per_sequence\": %u,\n  \"seconds\": %.1f,\n",
            m->opencv, m->views_per_seq, m->seconds);
    fprintf(f, "  \"ratio_to_remap\": \"cv::remap time (same filter, prebuilt maps, same views, sizes and format "
               "class: rgb565~8UC3, xrgb8888~8UC4) / this row's time\",\n");
    fprintf(f, "  \"agreement_psnr_db\": {\"cv_remap_bilinear\": %.2f, \"periscope_bilinear_n4\": %.2f},\n",
            m->agree_cv_db, m->agree_psc_db);
    fprintf(f, "  \"table_memory\": {\"display\": \"800x480\", \"luts\": \"%s\", \"lut_bytes\": %zu, "
               "\"workspace_bytes\": %zu, \"total_bytes\": %zu, \"goal_bytes\": %u},\n",
            m->table_luts, m->table_lut_bytes, m->table_ws_bytes, m->table_lut_bytes + m->table_ws_bytes,
            TABLE_GOAL_BYTES);
    fprintf(f, "  \"zoom_out_over_zoom_in\": [");
    bool first = true;
    for (size_t i = 0; i < r->count; i++) {
        const bv_row_t *c = &r->rows[i];
        if (!is_zoom_out(r, c))
            continue;
        fprintf(f, "%s\n    {\"renderer\": \"%s\", \"filter\": \"%s\", \"span\": ", first ? "" : ",", c->renderer,
                c->filter);
        json_span(f, c->span);
        fprintf(f, ", \"format\": \"%s\", \"output\": \"%ux%u\", \"ratio\": %.4f}", c->format, c->out_w, c->out_h,
                c->ns_per_px / at_hfov(r, c, 30.0)->ns_per_px);
        first = false;
    }
    fprintf(f, "\n  ],\n  \"rows\": [");
    for (size_t i = 0; i < r->count; i++) {
        fprintf(f, "%s\n    ", i ? "," : "");
        json_row(f, &r->rows[i]);
    }
    fprintf(f, "\n  ]\n}\n");
    return bv_json_end(f, tmp, path);
}
