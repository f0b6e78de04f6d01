/* SPDX-License-Identifier: MIT */
/*
 * periscope-pack - build a scene pack (.pano) from a JPEG or PNG panorama.
 *
 *   periscope-pack IN.{jpg,png} -o OUT.pano --display WxH [options]
 *
 * Exit status: 0 done, 1 the work failed, 2 bad arguments.
 */
#include "psc_io_angle.h"
#include "util/cli_values.h"
#include "psc_io_image.h"
#include "psc_io_pack_build.h"
#include "psc_io_image_rows.h"
#include "psc_io_tiles.h"
#include "psc_io_pack_image.h"
#include "psc_io_pixfmt.h"
#include "psc_io_cli.h"
#include "psc_io_file.h"
#include "psc_io_png.h"

#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PROG "periscope-pack"

static void print_usage(const char *prog, FILE *f)
{
    (void)prog;   /* the same as PROG */
    fprintf(f,
            "usage: " PROG " IN.{jpg,png} -o OUT.pano --display WxH [options]\n"
            "\n"
            "Build a Periscope scene pack: the panorama as an environment map plus the\n"
            "look-up tables the viewer needs for one display size.\n"
            "\n"
            "  -o OUT.pano                 output file (written atomically)\n"
            "  --display WxH               display the tables are built for, e.g. 640x480\n"
            "  --format F                  map pixels: rgb888 (default: 8 bits a channel, no bands in\n"
            "                              a smooth sky), rgb565 (two thirds of the memory, faster on\n"
            "                              an RGB565 display), xrgb8888, pal8\n"
            "  --projection P              equirect (default), cylinder, sine, elliptical, diamond\n"
            "  --lon-range MIN:MAX         longitudes the image covers, degrees (partial panoramas;\n"
            "                              default the full turn, -180:180)\n"
            "  --lat-range TOP:BOTTOM      latitudes of the image's top and bottom edges, degrees\n"
            "                              (default: the projection's full coverage); a partial\n"
            "                              panorama opens looking at the middle of its ranges.\n"
            "                              Without them, an equirectangular image's GPano XMP\n"
            "                              (photo-sphere metadata) gives its crop, if it has one\n"
            "  --hfov-min D                narrowest zoom the viewer allows (default 20; a tiled pack:\n"
            "                              two display pixels a texel, at least 1)\n"
            "  --lut-switch D              widest view served by the narrow table (default 60)\n"
            "  --hfov-max D                widest view served by the wide table (default 120, max 170)\n"
            "  --lut-size ROWSxCOLS        table size (default: chosen from the display width)\n"
            "  --levels N                  map pyramid levels incl. the map, for --filter mip\n"
            "                              (default: as many as the size allows; 1: none)\n"
            "  --tiled                     a tiled pack: the map as 256x256 tiles of every level,\n"
            "                              read one by one into a bounded cache (the viewer's, the\n"
            "                              board's map_cache_mb); made from the image's rows as\n"
            "                              they are decoded, never the whole image\n"
            "                              in memory. The default for an image larger than a flat\n"
            "                              pack holds (16384 a side, or --max-pixels); up to 65536x32768\n"
            "  --tile-codec C              a tiled pack's tiles (implies --tiled): raw (exact, read\n"
            "                              straight into the cache) or jpeg[:QUALITY] (1..100, default\n"
            "                              90: about a tenth of raw's bytes for a photograph, each\n"
            "                              tile decoded as it is read). Default: jpeg for a JPEG\n"
            "                              image, raw for any other\n"
            "  --max-pixels N              refuse a larger image before decoding it (default\n"
            "                              2147483648 = 65536x32768, the largest tiled map); an image\n"
            "                              over 134217728 = 16384x8192 pixels is packed tiled\n"
            "  --quiet                     no progress or summary\n"
            "  --version                   the program's version\n"
            "  --help                      this text\n"
            "Options take their value as --opt VALUE or --opt=VALUE, before or after the image.\n");
}

#define usage_error(...) psc_io_cli_usage_error(PROG, __VA_ARGS__)

static bool parse_projection(const char *s, psc_projection_t *p)
{
    for (int i = PSC_PROJ_EQUIRECT; i <= PSC_PROJ_DIAMOND; i++) {
        if (strcmp(s, psc_projection_name((psc_projection_t)i)) == 0) {
            *p = (psc_projection_t)i;
            return true;
        }
    }
    return false;
}

/* ---- progress on stderr -------------------------------------------------- */

typedef struct {
    bool quiet;
    bool tty;            /* redraw one line in place */
    const char *stage;   /* last stage shown */
    bool line_open;      /* a tty line awaits its newline */
} progress_t;

static void progress_show(const char *stage, unsigned percent, void *ctx)
{
    progress_t *p = ctx;
    if (p->quiet)
        return;
    if (p->tty) {
        fprintf(stderr, "\r" PROG ": %-22s %3u%%", stage, percent);
        p->line_open = true;
    } else if (!p->stage || strcmp(p->stage, stage) != 0) {
        /* Logs get one line per stage, not a line per percent. */
        fprintf(stderr, PROG ": %s\n", stage);
    }
    p->stage = stage;
}

/* Close the tty line: "done" on success; on failure the line keeps the stage that failed. */
static void progress_end(progress_t *p, bool ok)
{
    if (p->line_open && ok)
        fprintf(stderr, "\r" PROG ": %-27s\n", "done");
    else if (p->line_open)
        fprintf(stderr, "\n");
    p->line_open = false;
}

/* Notes on the image, a line each: warnings always, the rest unless --quiet. */
static void print_notes(progress_t *p, const char *notes)
{
    while (*notes != '\0') {
        size_t n = strcspn(notes, "\n");
        if (!p->quiet || strncmp(notes, "warning:", 8) == 0) {
            if (p->line_open)
                fprintf(stderr, "\n");
            p->line_open = false;
            fprintf(stderr, PROG ": %.*s\n", (int)n, notes);
        }
        notes += n + (notes[n] == '\n');
    }
}

/* ---- summary --------------------------------------------------------------- */

static void print_size(FILE *f, double bytes)
{
    if (bytes >= 1024.0 * 1024.0)
        fprintf(f, "%.1f MiB", bytes / (1024.0 * 1024.0));
    else if (bytes >= 1024.0)
        fprintf(f, "%.1f KiB", bytes / 1024.0);
    else
        fprintf(f, "%.0f bytes", bytes);
}

static double lon_deg(psc_bam_t a)
{
    double d = psc_io_deg_from_bam(a);
    return d >= 180.0 ? d - 360.0 : d;
}

/* The longitudes and latitudes a map covers (a partial panorama's, or the full sphere). */
static void print_coverage(const psc_envmap_t *m)
{
    double lon0 = lon_deg(m->lon_min), span = m->lon_span ? psc_io_deg_from_bam(m->lon_span) : 360.0;
    fprintf(stderr, "  covers   longitude %.2f..%.2f, latitude %.2f..%.2f degrees\n", lon0, lon0 + span,
            psc_io_deg_from_sbam(m->lat_top), psc_io_deg_from_sbam(m->lat_bottom));
}

static void print_summary(const char *out_path, const psc_pack_t *p, size_t len)
{
    const psc_envmap_t *m = &p->map;
    fprintf(stderr, PROG ": wrote %s, %zu bytes (", out_path, len);
    print_size(stderr, (double)len);
    fprintf(stderr, ")\n  map      %ux%u %s, %s projection, ", (unsigned)m->width, (unsigned)m->height,
            psc_io_pixfmt_name(m->format), psc_projection_name(m->projection));
    print_size(stderr, (double)m->stride * m->height);
    fprintf(stderr, "\n");
    print_coverage(m);
    if (p->level_count > 1) {
        double bytes = 0;
        for (unsigned k = 1; k < p->level_count; k++)
            bytes += (double)p->levels[k].stride * p->levels[k].height;
        fprintf(stderr, "  levels   %u more, down to %ux%u, ", (unsigned)p->level_count - 1u,
                (unsigned)p->levels[p->level_count - 1].width, (unsigned)p->levels[p->level_count - 1].height);
        print_size(stderr, bytes);
        fprintf(stderr, "\n");
    }
    if (m->format == PSC_PIX_PAL8)
        fprintf(stderr, "  palette  256 entries, 1.0 KiB\n");
    for (unsigned i = 0; i < p->lut_count; i++) {
        const psc_lut_t *t = &p->luts[i];
        fprintf(stderr, "  LUT %u    up to %.2f degrees, %ux%u entries, ", i + 1, psc_io_deg_from_bam(t->hfov_max),
                (unsigned)t->rows, (unsigned)t->cols);
        print_size(stderr, (double)(sizeof(psc_pack_lut_raw_t) + psc_lut_bytes(t->rows, t->cols)));
        fprintf(stderr, "\n");
    }
    fprintf(stderr, "  display  %ux%u, zoom %.1f..%.1f degrees, default view yaw %.1f pitch %.1f hfov %.1f\n",
            (unsigned)p->display_width, (unsigned)p->display_height, psc_io_deg_from_bam(p->hfov_min),
            psc_io_deg_from_bam(p->luts[p->lut_count - 1].hfov_max), psc_io_deg_from_bam(p->default_yaw),
            psc_io_deg_from_sbam(p->default_pitch), psc_io_deg_from_bam(p->default_hfov));
}

/* ---- arguments --------------------------------------------------------------- */

typedef struct {
    const char *in, *out;
    uint64_t max_pixels;
    bool have_display, quiet, tiled;
    bool tiles_given;   /* --tile-codec: else the image's kind chooses */
    bool hfov_min_given;
    bool lon_given, lat_given;   /* --lon-range, --lat-range: they override the image's GPano XMP */
    psc_pack_options_t opt;
} args_t;

/* Parse a degree value for option name into *deg. */
static int take_degrees(const char *name, const char *value, double *deg)
{
    if (psc_cli_parse_double(value, deg) != 0)
        return usage_error("%s needs a number of degrees", name);
    return 0;
}

static int parse_lon_range(const char *v, args_t *a)
{
    double lo, hi;
    if (psc_cli_parse_pair(v, &lo, &hi) != 0 || psc_io_pack_options_set_lon_range(&a->opt, lo, hi) != 0)
        return usage_error("--lon-range '%s': expected MIN:MAX in degrees with MIN < MAX and MAX - MIN <= 360", v);
    a->lon_given = true;
    return 0;
}

static int parse_lat_range(const char *v, args_t *a)
{
    double top, bottom;
    if (psc_cli_parse_pair(v, &top, &bottom) != 0 || psc_io_pack_options_set_lat_range(&a->opt, top, bottom) != 0)
        return usage_error("--lat-range '%s': expected TOP:BOTTOM in degrees with 90 >= TOP > BOTTOM >= -90", v);
    a->lat_given = true;
    return 0;
}

static const struct option pack_options[] = {
    {"display", required_argument, NULL, 1},   {"format", required_argument, NULL, 1},
    {"projection", required_argument, NULL, 1}, {"lon-range", required_argument, NULL, 1},
    {"lat-range", required_argument, NULL, 1},  {"hfov-min", required_argument, NULL, 1},
    {"lut-switch", required_argument, NULL, 1}, {"hfov-max", required_argument, NULL, 1},
    {"lut-size", required_argument, NULL, 1},   {"levels", required_argument, NULL, 1},
    {"max-pixels", required_argument, NULL, 1},
    {"tiled", no_argument, NULL, 1},           {"tile-codec", required_argument, NULL, 1},
    {"quiet", no_argument, NULL, 'q'},          PSC_IO_CLI_COMMON_OPTIONS,
};

static int parse_args(int argc, char **argv, args_t *a)
{
    psc_io_cli_t c;
    int opt;

    psc_io_cli_begin(&c, argc, argv, "ho:", pack_options);
    while ((opt = psc_io_cli_next_option(&c, PROG, "", print_usage)) > 0) {
        const char *name = c.name, *v = c.arg;
        if (opt == 'q') {
            a->quiet = true;
            continue;
        }
        psc_pack_options_t *o = &a->opt;
        int rc = 0;
        if (strcmp(name, "-o") == 0) {
            a->out = v;
        } else if (strcmp(name, "--display") == 0) {
            if (psc_cli_parse_size(v, PSC_MAX_OUT_DIM, &o->display_width, &o->display_height) != 0)
                return usage_error("--display '%s': expected WxH, each 1..4096", v);
            a->have_display = true;
        } else if (strcmp(name, "--format") == 0) {
            if (psc_io_pixfmt_parse(v, &o->format) != 0)
                return usage_error("--format '%s': expected rgb888, rgb565, xrgb8888 or pal8", v);
        } else if (strcmp(name, "--projection") == 0) {
            if (!parse_projection(v, &o->projection))
                return usage_error("--projection '%s': expected equirect, cylinder, sine, elliptical or diamond", v);
        } else if (strcmp(name, "--lon-range") == 0) {
            rc = parse_lon_range(v, a);
        } else if (strcmp(name, "--lat-range") == 0) {
            rc = parse_lat_range(v, a);
        } else if (strcmp(name, "--hfov-min") == 0) {
            rc = take_degrees(name, v, &o->hfov_min_deg);
            a->hfov_min_given = true;
        } else if (strcmp(name, "--lut-switch") == 0) {
            rc = take_degrees(name, v, &o->hfov_switch_deg);
        } else if (strcmp(name, "--hfov-max") == 0) {
            rc = take_degrees(name, v, &o->hfov_max_deg);
        } else if (strcmp(name, "--lut-size") == 0) {
            if (psc_cli_parse_size(v, PSC_MAX_LUT_DIM, &o->lut_rows, &o->lut_cols) != 0 || o->lut_rows < 2 ||
                o->lut_cols < 2)
                return usage_error("--lut-size '%s': expected ROWSxCOLS, each 2..2048", v);
        } else if (strcmp(name, "--levels") == 0) {
            unsigned long n;
            if (psc_cli_parse_uint(v, 1, PSC_PACK_MAX_LEVELS, &n) != 0)
                return usage_error("--levels '%s': expected 1..%u", v, PSC_PACK_MAX_LEVELS);
            o->map_levels = (unsigned)n;
        } else if (strcmp(name, "--tiled") == 0) {
            a->tiled = true;
        } else if (strcmp(name, "--tile-codec") == 0) {
            unsigned long q = PSC_IO_TILE_JPEG_QUALITY;
            if (strcmp(v, "raw") == 0)
                o->tile_codec = PSC_TILE_CODEC_RAW;
            else if (strcmp(v, "jpeg") == 0 ||
                     (strncmp(v, "jpeg:", 5) == 0 && psc_cli_parse_uint(v + 5, 1, 100, &q) == 0))
                o->tile_codec = PSC_TILE_CODEC_JPEG, o->tile_quality = (uint8_t)q;
            else
                return usage_error("--tile-codec '%s': expected raw, jpeg or jpeg:QUALITY (1..100)", v);
            a->tiled = a->tiles_given = true;
        } else if (strcmp(name, "--max-pixels") == 0) {
            unsigned long n;
            if (psc_cli_parse_uint(v, 1, (unsigned long)PSC_TILES_MAX_WIDTH * PSC_TILES_MAX_HEIGHT, &n) != 0)
                return usage_error("--max-pixels '%s': expected 1..%lu", v,
                                   (unsigned long)PSC_TILES_MAX_WIDTH * PSC_TILES_MAX_HEIGHT);
            a->max_pixels = n;
        }
        if (rc != 0)
            return rc;
    }
    if (opt < 0)
        return -opt;   /* the mistake, said */
    int rc = psc_io_cli_one_file(&c, PROG, "input image", &a->in);
    if (rc != 0)
        return rc;
    if (!a->out)
        return usage_error("%s", "no output given (-o OUT.pano)");
    if (!a->have_display)
        return usage_error("%s", "no display size given (--display WxH)");
    if (strcmp(a->in, a->out) == 0)
        return usage_error("the output %s would overwrite the input", a->out);
    /* The view limits are checked together here so the message can name options. */
    const psc_pack_options_t *o = &a->opt;
    if (!(o->hfov_min_deg > 0.0 && o->hfov_min_deg <= o->hfov_switch_deg &&
          o->hfov_switch_deg <= o->hfov_max_deg && o->hfov_max_deg <= 170.0))
        return usage_error("%s", "fields of view must satisfy 0 < --hfov-min <= --lut-switch <= --hfov-max <= 170");
    return 0;
}

static void print_tiled_summary(const char *out_path, const psc_pack_t *p, uint64_t bytes, uint64_t peak)
{
    const psc_tiles_t *t = &p->tiles;
    fprintf(stderr, PROG ": wrote %s, %llu bytes (", out_path, (unsigned long long)bytes);
    print_size(stderr, (double)bytes);
    fprintf(stderr, "), tiled\n  map      %ux%u %s, %s projection, %u levels down to %ux%u, %u tiles of %ux%u (",
            (unsigned)t->level[0].width, (unsigned)t->level[0].height, psc_io_pixfmt_name(t->format),
            psc_projection_name(p->map.projection), (unsigned)t->level_count,
            (unsigned)t->level[t->level_count - 1u].width, (unsigned)t->level[t->level_count - 1u].height,
            (unsigned)t->tile_count, PSC_TILE_SIDE, PSC_TILE_SIDE);
    if (p->tile_codec == PSC_TILE_CODEC_JPEG) {   /* the store's mean tile, against what a raw tile holds */
        fprintf(stderr, "JPEG, ");
        print_size(stderr, (double)p->store_size / t->tile_count);
        fprintf(stderr, " each on average, ");
        print_size(stderr, (double)t->tile_bytes);
        fprintf(stderr, " decoded)\n");
    } else {
        print_size(stderr, (double)t->tile_bytes);
        fprintf(stderr, " each)\n");
    }
    print_coverage(&p->map);
    fprintf(stderr, "  packing  at most ");
    print_size(stderr, (double)peak);
    fprintf(stderr, " of rows and bands in memory\n");
    for (unsigned i = 0; i < p->lut_count; i++)
        fprintf(stderr, "  LUT %u    up to %.2f degrees, %ux%u entries\n", i + 1,
                psc_io_deg_from_bam(p->luts[i].hfov_max), (unsigned)p->luts[i].rows, (unsigned)p->luts[i].cols);
    fprintf(stderr, "  display  %ux%u, zoom %.1f..%.1f degrees\n", (unsigned)p->display_width,
            (unsigned)p->display_height, psc_io_deg_from_bam(p->hfov_min),
            psc_io_deg_from_bam(p->luts[p->lut_count - 1].hfov_max));
}

/* The tiled pack, from the image's rows as they are decoded: never the whole image in memory. */
static int pack_tiled(args_t *a, progress_t *prog, psc_io_image_rows_t *rows)
{
    char err[1024];
    uint32_t w, h;
    psc_io_image_rows_size(rows, &w, &h);
    char notes[1024] = "";
    if (!a->tiles_given && psc_io_image_rows_is_jpeg(rows))   /* a photograph: JPEG tiles (--tile-codec raw: exact) */
        a->opt.tile_codec = PSC_TILE_CODEC_JPEG;
    psc_io_pack_image_coverage(a->in, w, h, a->lon_given, a->lat_given, &a->opt, notes, sizeof notes);
    print_notes(prog, notes);
    /* a map this large is for zooming in: by default down to two display pixels a texel (at least 1 degree) */
    if (!a->hfov_min_given) {
        double deep = 360.0 * a->opt.display_width / (2.0 * w);
        a->opt.hfov_min_deg = deep < 1.0 ? 1.0 : deep < a->opt.hfov_min_deg ? deep : a->opt.hfov_min_deg;
    }
    psc_io_tiles_writer_t *wr;
    uint32_t *row = malloc((size_t)w * sizeof *row);
    if (!row || psc_io_tiles_writer_open(a->out, w, h, &a->opt, &wr, err, sizeof err) != 0) {
        progress_end(prog, false);
        fprintf(stderr, PROG ": %s: %s\n", a->in, row ? err : "out of memory for a row");
        free(row);
        return 1;
    }
    for (uint32_t y = 0; y < h; y++)
        if (psc_io_image_rows_next(rows, row, err, sizeof err) != 0 ||
            psc_io_tiles_writer_row(wr, row, err, sizeof err) != 0) {
            progress_end(prog, false);
            fprintf(stderr, PROG ": %s\n", err);
            psc_io_tiles_writer_abort(wr);
            free(row);
            return 1;
        }
    free(row);
    uint64_t peak = psc_io_tiles_writer_peak(wr) + (uint64_t)w * 4u;
    if (psc_io_tiles_writer_finish(wr, err, sizeof err) != 0) {
        progress_end(prog, false);
        fprintf(stderr, PROG ": %s\n", err);
        return 1;
    }
    /* read back as the device will, the coarsest level's tiles checked too */
    progress_show("verifying", 0, prog);
    psc_io_tiled_t *t;
    if (psc_io_tiled_open(a->out, 0, &t, err, sizeof err) != 0) {
        progress_end(prog, false);
        fprintf(stderr, PROG ": internal error: the tiled pack built from %s does not read back: %s\n", a->in, err);
        return 1;
    }
    progress_end(prog, true);
    if (!a->quiet) {
        const psc_pack_t *p = psc_io_tiled_pack(t);
        print_tiled_summary(a->out, p, p->store_offset + p->store_size, peak);
    }
    psc_io_tiled_close(t);
    return 0;
}

int main(int argc, char **argv)
{
    args_t a = {.max_pixels = (uint64_t)PSC_TILES_MAX_WIDTH * PSC_TILES_MAX_HEIGHT};
    psc_io_pack_options_default(&a.opt);
    int rc = parse_args(argc, argv, &a);
    if (rc != 0)
        return rc;
    /* The default view must lie inside the zoom range the options allow. */
    if (a.opt.default_hfov_deg > a.opt.hfov_max_deg)
        a.opt.default_hfov_deg = a.opt.hfov_max_deg;
    if (a.opt.default_hfov_deg < a.opt.hfov_min_deg)
        a.opt.default_hfov_deg = a.opt.hfov_min_deg;

    progress_t prog = {.quiet = a.quiet, .tty = isatty(STDERR_FILENO) != 0};
    a.opt.progress = progress_show;
    a.opt.progress_ctx = &prog;

    char err[512];
    psc_image_t img;
    /* a flat pack unless asked for tiles, or unless the image (its header says) is more than a flat pack holds:
     * more than PSC_MAX_MAP_DIM a side or PSC_IMAGE_MAX_PIXELS; more than --max-pixels is refused */
    uint32_t img_w, img_h;
    if (psc_io_image_probe(a.in, &img_w, &img_h, err, sizeof err) != 0) {
        fprintf(stderr, PROG ": %s\n", err);
        return 1;
    }
    if ((uint64_t)img_w * img_h > a.max_pixels) {
        fprintf(stderr, PROG ": %s: image is %ux%u (%llu pixels), more than the budget of %llu pixels (checked "
                "before decoding)\n" PROG ": --max-pixels N raises the budget, if the image is meant to be that "
                "large\n", a.in, (unsigned)img_w, (unsigned)img_h, (unsigned long long)img_w * img_h,
                (unsigned long long)a.max_pixels);
        return 1;
    }
    bool too_big = img_w > PSC_MAX_MAP_DIM || img_h > PSC_MAX_MAP_DIM || (uint64_t)img_w * img_h > PSC_IMAGE_MAX_PIXELS;
    if (!a.tiled && !too_big) {
        progress_show("loading image", 0, &prog);
        if (psc_io_image_load_within(a.in, a.max_pixels, &img, err, sizeof err) != 0) {
            progress_end(&prog, false);
            fprintf(stderr, PROG ": %s\n", err);
            return 1;
        }
    }
    if (a.tiled || too_big) {
        psc_io_image_rows_t *rows;
        if (psc_io_image_rows_open(a.in, PSC_TILES_MAX_WIDTH, PSC_TILES_MAX_HEIGHT, &rows, err, sizeof err) != 0) {
            progress_end(&prog, false);
            fprintf(stderr, PROG ": %s\n", err);
            return 1;
        }
        if (too_big && !a.tiled && !a.quiet) {
            fprintf(stderr, PROG ": %s is %ux%u, more than a flat pack holds (%u a side, %llu pixels): "
                    "packing it tiled\n", a.in, (unsigned)img_w, (unsigned)img_h, (unsigned)PSC_MAX_MAP_DIM,
                    (unsigned long long)PSC_IMAGE_MAX_PIXELS);
        }
        rc = pack_tiled(&a, &prog, rows);
        psc_io_image_rows_close(rows);
        return rc;
    }
    /* the image's GPano XMP for the axes the options leave open; the 2:1 warning */
    char notes[1024] = "";
    psc_io_pack_image_coverage(a.in, img.width, img.height, a.lon_given, a.lat_given, &a.opt, notes, sizeof notes);
    print_notes(&prog, notes);
    uint8_t *pack = NULL;
    size_t len = 0;
    rc = psc_io_pack_build(&img, &a.opt, &pack, &len, err, sizeof err);
    psc_io_image_free(&img);
    if (rc != 0) {
        progress_end(&prog, false);
        fprintf(stderr, PROG ": %s: %s\n", a.in, err);
        return 1;
    }

    /* Read the result back exactly as the device will: a pack this tool
     * cannot parse must never reach a device. */
    progress_show("verifying", 0, &prog);
    psc_pack_t parsed;
    psc_container_error_t perr = {0};
    psc_status_t s = psc_pack_parse(pack, len, &parsed, &perr);
    if (s != PSC_OK) {
        progress_end(&prog, false);
        fprintf(stderr, PROG ": internal error: the pack built from %s does not parse: %s (offset %u): %s\n", a.in,
                perr.what ? perr.what : "?", (unsigned)perr.offset, psc_status_str(s));
        free(pack);
        return 1;
    }
    progress_show("writing", 0, &prog);
    rc = psc_io_write_atomic(a.out, pack, len, err, sizeof err);
    progress_end(&prog, rc == 0);
    if (rc != 0) {
        fprintf(stderr, PROG ": %s\n", err);
        free(pack);
        return 1;
    }
    if (!a.quiet)
        print_summary(a.out, &parsed, len);
    free(pack);
    return 0;
}
