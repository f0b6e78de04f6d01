/* SPDX-License-Identifier: MIT */
/*
 * pano.c - periscope-render's panorama mode (pano.h): one view of a scene
 * pack, or of a JPEG or PNG packed as the device packs one, through core's
 * psc_viewer_render on threads (io/psc_io_bands.h), the code path the device
 * runs.
 */
#include "render/pano.h"
#include "render/modes.h"
#include "render/target.h"
#include "util/cli_values.h"
#include "psc_io_angle.h"
#include "psc_io_bands.h"
#include "psc_io_cli.h"
#include "psc_io_image.h"
#include "psc_io_levels.h"
#include "psc_io_load.h"
#include "psc_io_pack_build.h"
#include "psc_io_pack_image.h"
#include "psc_io_png.h"
#include "psc_io_tiles.h"
#include "viewer/psc_viewer.h"
#include "dither/psc_dither.h"
#include "render/pano_objects.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char *pano_prog = "periscope-render";   /* the program's name, for its messages */

#define MAX_REPEAT 100000ul
#define PSC_RENDER_CACHE_MB_DEFAULT 64u   /* as the device's map_cache_mb */
#define CACHE_MB_MAX 65536ul
#define usage_error(...) psc_io_cli_usage_error(pano_prog, __VA_ARGS__)

static void print_usage(const char *prog, FILE *f)
{
    psc_render_modes_usage(prog, f);
    fprintf(f,
            "\n"
            "Render a perspective view of a scene pack with the device's renderer.\n"
            "\n"
            "  --yaw Y             degrees, > 0 turns right (default: the pack's default view)\n"
            "  --pitch P           degrees, -90..90, > 0 looks up (default: the pack's)\n"
            "  --hfov F            horizontal field of view in degrees (default: the pack's);\n"
            "                      brought inside the pack's zoom range if needed\n"
            "  --filter F          nearest, bilinear (default) or mip (the map pyramid, trilinear)\n"
            "  --span N            read the LUT every N pixels: 1, 2, 4 (default), 8 or 16\n"
            "  --repeat K          render K times and report the time per frame (default 1)\n"
            "  --threads N         render on N threads, bands of rows each (default: the processors online);\n"
            "                      the bytes are the same for any N\n"
            "  --simd S            code path: auto (default: the fastest this CPU has), scalar, vector\n"
            "                      (SSE2/NEON) or avx2; the bytes are the same for each\n"
            "  --size WxH          output size (default: the pack's display size)\n"
            "  --dither T[:M]      show the frame as a display with few levels does: T mono (1 bit),\n"
            "                      grey4 (16 greys) or pal8 (the 6x7x6 colour cube); M ordered (8x8 Bayer,\n"
            "                      default), halftone (4x4 clustered dot) or none (nearest level)\n"
            "  --format F          output surface: rgb565 (default) or xrgb8888\n"
            "  --display-dither D  an rgb565 output of a map with more colours (xrgb8888, pal8) is drawn at\n"
            "                      8 bits and dithered as the device's display_dither does: ordered\n"
            "                      (default, the device's) or none (rounded)\n"
            "  --cache-mb N        a tiled pack's tile cache, megabytes (default %u); the view waits for\n"
            "                      every tile it needs, so the output is exact whatever the cache\n"
            "  --object FILE,yaw=Y,pitch=P,dist=D[,scale=S][,turn=T][,time=T][,play=NAME][,shadow=F.pao]\n"
            "                      an object standing in the panorama (repeat for more, up to %u): a\n"
            "                      character (.ppk, .mdl, .bpt), a mesh (.pmesh, .obj; a glTF model at rest)\n"
            "                      or a proxy pack (.ppx, for an animated glTF model: periscope-proxy bake),\n"
            "                      its centre toward yaw Y, pitch P (degrees) at D times its R (half its rest\n"
            "                      box's diagonal), S times its size, turned T degrees about its vertical;\n"
            "                      time: seconds into its action (play: which one), shadow: its .pao\n"
            "  --light AZ,EL       the objects' light: toward azimuth AZ (from yaw 0 toward the right) and\n"
            "                      elevation EL, degrees (default: the panorama's brightest region, as the\n"
            "                      device lights them; 41.6,53 for a map that is not a full-turn equirect)\n"
            "  --ambient A         the objects' ambient light, 0..1 (default: the panorama's mean over its\n"
            "                      brightest region, 0.25..0.75; else 0.45)\n"
            "  --light-colour RRGGBB  the light's colour, hex (default: the panorama's mean colour, half way\n"
            "                      from white; else FFFFFF)\n"
            "  --ids I.pgm         also write a 16-bit PGM: 0 where the pixel is the panorama's alone, k where\n"
            "                      the k-th object covers it even in part\n"
            "  -o view.png         output PNG\n"
            "  --version           the program's version\n"
            "  --help              this text\n"
            "Options take their value as --opt VALUE or --opt=VALUE, before or after the pack.\n",
            PSC_RENDER_CACHE_MB_DEFAULT, PSC_IO_OBJECTS_MAX);
}


typedef struct {
    const char *pack, *out;
    bool have_yaw, have_pitch, have_hfov, have_size;
    double yaw, pitch, hfov;
    psc_filter_t filter;
    uint8_t span_log2;
    unsigned long repeat, threads;
    uint16_t width, height;
    psc_pixfmt_t format;
    psc_simd_t simd;
    psc_io_levels_t levels;   /* --dither */
    unsigned long cache_mb;   /* a tiled pack's cache */
    bool no_display_dither;   /* --display-dither none */
    const char *objects[PSC_IO_OBJECTS_MAX];   /* --object, checked, loaded after the arguments */
    unsigned object_count;
    const char *ids;          /* --ids */
    bool have_light;
    double light_az, light_el, ambient;
    const char *light_colour;   /* --light-colour RRGGBB */
} args_t;

static int span_to_log2(const char *v, uint8_t *log2)
{
    unsigned long n;
    if (psc_cli_parse_uint(v, 1, 16, &n) != 0 || (n & (n - 1)) != 0)
        return -1;
    uint8_t l = 0;
    while ((1ul << l) < n)
        l++;
    *log2 = l;
    return 0;
}

static int parse_value(args_t *a, const char *name, const char *v)
{
    if (strcmp(name, "-o") == 0) {
        a->out = v;
    } else if (strcmp(name, "--yaw") == 0) {
        if (psc_cli_parse_double(v, &a->yaw) != 0)
            return usage_error("--yaw '%s': expected degrees", v);
        a->have_yaw = true;
    } else if (strcmp(name, "--pitch") == 0) {
        if (psc_cli_parse_double(v, &a->pitch) != 0 || a->pitch < -90.0 || a->pitch > 90.0)
            return usage_error("--pitch '%s': expected degrees in -90..90", v);
        a->have_pitch = true;
    } else if (strcmp(name, "--hfov") == 0) {
        if (psc_cli_parse_double(v, &a->hfov) != 0 || !(a->hfov > 0.0 && a->hfov < 180.0))
            return usage_error("--hfov '%s': expected degrees between 0 and 180", v);
        a->have_hfov = true;
    } else if (strcmp(name, "--filter") == 0) {
        if (strcmp(v, "nearest") == 0)
            a->filter = PSC_FILTER_NEAREST;
        else if (strcmp(v, "bilinear") == 0)
            a->filter = PSC_FILTER_BILINEAR;
        else if (strcmp(v, "mip") == 0)
            a->filter = PSC_FILTER_MIP;
        else
            return usage_error("--filter '%s': expected nearest, bilinear or mip", v);
    } else if (strcmp(name, "--span") == 0) {
        if (span_to_log2(v, &a->span_log2) != 0 || a->span_log2 > PSC_SPAN_LOG2_MAX)
            return usage_error("--span '%s': expected 1, 2, 4, 8 or 16", v);
    } else if (strcmp(name, "--repeat") == 0) {
        if (psc_cli_parse_uint(v, 1, MAX_REPEAT, &a->repeat) != 0)
            return usage_error("--repeat '%s': expected a count of 1..%lu", v, MAX_REPEAT);
    } else if (strcmp(name, "--threads") == 0) {
        if (psc_cli_parse_uint(v, 1, PSC_IO_BANDS_MAX_THREADS, &a->threads) != 0)
            return usage_error("--threads '%s': expected 1..%u", v, PSC_IO_BANDS_MAX_THREADS);
    } else if (strcmp(name, "--simd") == 0) {
        psc_simd_t k;
        for (k = PSC_SIMD_AUTO; k <= PSC_SIMD_AVX2 && strcmp(v, psc_simd_name(k)) != 0; k++)
            ;
        if (k > PSC_SIMD_AVX2)
            return usage_error("--simd '%s': expected auto, scalar, vector or avx2", v);
        a->simd = k;
    } else if (strcmp(name, "--dither") == 0) {
        if (psc_io_levels_parse(v, &a->levels) != 0)
            return usage_error("--dither '%s': expected mono, grey4 or pal8, optionally :ordered, :halftone or :none", v);
    } else if (strcmp(name, "--size") == 0) {
        if (psc_cli_parse_size(v, PSC_MAX_OUT_DIM, &a->width, &a->height) != 0)
            return usage_error("--size '%s': expected WxH, each 1..%u", v, (unsigned)PSC_MAX_OUT_DIM);
        a->have_size = true;
    } else if (strcmp(name, "--display-dither") == 0) {
        if (strcmp(v, "ordered") != 0 && strcmp(v, "none") != 0)
            return usage_error("--display-dither '%s': expected ordered or none", v);
        a->no_display_dither = strcmp(v, "none") == 0;
    } else if (strcmp(name, "--cache-mb") == 0) {
        if (psc_cli_parse_uint(v, 1, CACHE_MB_MAX, &a->cache_mb) != 0)
            return usage_error("--cache-mb '%s': expected megabytes, 1..%lu", v, CACHE_MB_MAX);
    } else if (strcmp(name, "--object") == 0) {
        psc_io_object_spec_t spec;
        char err[640];
        if (a->object_count >= PSC_IO_OBJECTS_MAX)
            return usage_error("--object: at most %u objects", PSC_IO_OBJECTS_MAX);
        if (psc_io_object_spec_parse(v, ',', "--object", &spec, err, sizeof err) != 0)
            return usage_error("%s", err);
        a->objects[a->object_count++] = v;
    } else if (strcmp(name, "--ids") == 0) {
        a->ids = v;
    } else if (strcmp(name, "--light") == 0) {
        char *end;
        a->light_az = strtod(v, &end);
        if (end == v || *end != ',' || (a->light_el = strtod(end + 1, &end), *end != '\0') ||
            !(a->light_az >= -360 && a->light_az <= 360 && a->light_el >= -90 && a->light_el <= 90))
            return usage_error("--light '%s': expected AZ,EL in degrees (-360..360, -90..90)", v);
        a->have_light = true;
    } else if (strcmp(name, "--light-colour") == 0) {
        uint16_t c[3];
        if (psc_io_objects_colour_parse(v, c) != 0)
            return usage_error("--light-colour '%s': expected RRGGBB in hex (FFFFFF: white)", v);
        a->light_colour = v;
    } else if (strcmp(name, "--ambient") == 0) {
        if (psc_cli_parse_double(v, &a->ambient) != 0 || !(a->ambient >= 0.0 && a->ambient <= 1.0))
            return usage_error("--ambient '%s': expected 0..1", v);
    } else if (strcmp(name, "--format") == 0) {
        if (strcmp(v, "rgb565") == 0)
            a->format = PSC_PIX_RGB565;
        else if (strcmp(v, "xrgb8888") == 0)
            a->format = PSC_PIX_XRGB8888;
        else
            return usage_error("--format '%s': expected rgb565 or xrgb8888", v);
    }
    return 0;
}

static const struct option render_options[] = {
    {"yaw", required_argument, NULL, 1},    {"pitch", required_argument, NULL, 1},
    {"hfov", required_argument, NULL, 1},   {"filter", required_argument, NULL, 1},
    {"span", required_argument, NULL, 1},   {"repeat", required_argument, NULL, 1},
    {"size", required_argument, NULL, 1},   {"format", required_argument, NULL, 1},
    {"threads", required_argument, NULL, 1}, {"simd", required_argument, NULL, 1}, {"dither", required_argument, NULL, 1},
    {"cache-mb", required_argument, NULL, 1}, {"display-dither", required_argument, NULL, 1},
    {"object", required_argument, NULL, 1},  {"ids", required_argument, NULL, 1},
    {"light", required_argument, NULL, 1},  {"ambient", required_argument, NULL, 1},
    {"light-colour", required_argument, NULL, 1},
    PSC_IO_CLI_COMMON_OPTIONS,
};

static int parse_args(int argc, char **argv, args_t *a)
{
    psc_io_cli_t c;
    int opt;

    psc_io_cli_begin(&c, argc, argv, "ho:", render_options);
    while ((opt = psc_io_cli_next_option(&c, pano_prog, "", print_usage)) > 0) {
        int rc = parse_value(a, c.name, c.arg);
        if (rc != 0)
            return rc;
    }
    if (opt < 0)
        return -opt;   /* the mistake, said */
    int rc = psc_io_cli_one_file(&c, pano_prog, "pack", &a->pack);
    if (rc != 0)
        return rc;
    if (!a->out)
        return usage_error("no output given (-o view.png)");
    return 0;
}

/* Aligned, zeroed memory for the workspace and the frame. */
static void *alloc_aligned(size_t size)
{
    void *p = NULL;
    if (size == 0 || posix_memalign(&p, 64, size) != 0)
        return NULL;
    memset(p, 0, size);
    return p;
}

static void note_clamped(const psc_view_t *want, const psc_view_t *got)
{
    if (want->yaw == got->yaw && want->pitch == got->pitch && want->hfov == got->hfov)
        return;
    fprintf(stderr, "%s" ": note: view brought inside the pack's limits: yaw %.3f, pitch %.3f, hfov %.3f degrees\n", pano_prog,
            psc_io_deg_from_bam(got->yaw), psc_io_deg_from_sbam(got->pitch), psc_io_deg_from_bam(got->hfov));
}

static int render_frames(psc_viewer_t *viewer, psc_io_bands_t *bands, const psc_view_t *view,
                         const psc_surface_t *out, unsigned long repeat)
{
    double best = 0.0, total = 0.0;
    for (unsigned long k = 0; k < repeat; k++) {
        double t0 = psc_render_seconds();
        psc_status_t s = psc_io_bands_render(bands, viewer, view, out);
        double dt = psc_render_seconds() - t0;
        if (s != PSC_OK) {
            fprintf(stderr, "%s" ": rendering failed: %s\n", pano_prog, psc_status_str(s));
            return -1;
        }
        total += dt;
        if (k == 0 || dt < best)
            best = dt;
    }
    if (repeat > 1) {
        double mean = total / (double)repeat, mpix = (double)out->width * out->height / 1e6;
        fprintf(stderr, "%s" ": %lu frames of %ux%u on %u thread%s (%s): %.3f ms per frame (best %.3f ms), %.1f Mpixel/s\n", pano_prog,
                repeat, (unsigned)out->width, (unsigned)out->height, psc_io_bands_threads(bands),
                psc_io_bands_threads(bands) == 1 ? "" : "s", psc_simd_name(psc_viewer_simd(viewer)), mean * 1e3, best * 1e3, mpix / mean);
    }
    return 0;
}

/*
 * The pack, or a JPEG or PNG packed as the device packs one given directly
 * (io/psc_io_pack_image.h): for the output size (default 640x480) and
 * format, through the same cache.
 */
static int load_scene(const args_t *a, psc_io_pack_t *pf, char *err, size_t errlen)
{
    if (!psc_io_image_sniff(a->pack))
        return psc_io_pack_load(a->pack, pf, err, errlen);
    psc_io_pack_image_request_t rq = {
        .display_width = a->have_size ? a->width : 640,
        .display_height = a->have_size ? a->height : 480,
        /* as the device packs an image for the display: 8-bit (RGB888) where an RGB565 frame is dithered */
        .format = a->format == PSC_PIX_RGB565 && !a->no_display_dither && !a->levels.on ? PSC_PIX_RGB888 : a->format,
    };
    psc_io_pack_image_result_t res;
    char notes[1024] = "";
    int rc = psc_io_pack_image_load(a->pack, &rq, pf, &res, notes, sizeof notes, err, errlen);
    for (const char *n = notes; *n != '\0';) {
        size_t k = strcspn(n, "\n");
        fprintf(stderr, "%s" ": %.*s\n", pano_prog, (int)k, n);
        n += k + (n[k] == '\n');
    }
    if (rc == 0 && res.cache_off)
        fprintf(stderr, "%s" ": note: no pack cache: %s\n", pano_prog, res.cache_problem);
    if (rc == 0)
        fprintf(stderr, "%s" ": %s\n", pano_prog, res.line);
    return rc;
}

/* Whether the view is drawn at 8 bits and dithered to the RGB565 output, as the device's display_dither does for
 * a scene whose frames hold more than RGB565's colours (a map that is not RGB565). */
static bool display_dithers(const args_t *a, psc_pixfmt_t map_format)
{
    return a->format == PSC_PIX_RGB565 && map_format != PSC_PIX_RGB565 && !a->no_display_dither && !a->levels.on;
}

/* The drawn frame as shown (--dither's levels, or display_dither's RGB565), written. 0, or -1 said. */
static int write_view(const args_t *a, const psc_surface_t *drawn, bool dither)
{
    char err[512];
    psc_surface_t shown = *drawn;
    if (dither) {
        static psc_dither_565_t table;
        psc_dither_565_init(&table);
        shown = (psc_surface_t){drawn->width, drawn->height, drawn->width * 2u, PSC_PIX_RGB565,
                                malloc((size_t)drawn->width * drawn->height * 2u)};
        if (!shown.pixels) {
            fprintf(stderr, "%s: out of memory\n", pano_prog);
            return -1;
        }
        for (unsigned y = 0; y < drawn->height; y++)   /* the matrix fixed to the output, as to the screen */
            psc_dither_row_rgb565(&table, PSC_DITHER_ORDERED,
                                  (const uint32_t *)(const void *)((const uint8_t *)drawn->pixels +
                                                                   (size_t)y * drawn->stride),
                                  drawn->width, 0, y, (uint16_t *)(void *)((uint8_t *)shown.pixels + (size_t)y * shown.stride));
    } else {
        psc_io_levels_apply(&a->levels, &shown);
    }
    int rc = psc_io_png_write(a->out, &shown, err, sizeof err);
    if (rc != 0)
        fprintf(stderr, "%s: %s\n", pano_prog, err);
    if (dither)
        free(shown.pixels);
    return rc;
}

/* The --object files loaded, with the scene's light. 0, or -1 said. */
static int objects_load(const args_t *a, psc_render_objects_t *o)
{
    char err[1024];
    psc_render_objects_init(o);
    if (a->have_light) {
        o->light_az_mdeg = (int32_t)lround(a->light_az * 1000.0);
        o->light_el_mdeg = (int32_t)lround(a->light_el * 1000.0);
        o->light_given = true;
    }
    if (a->ambient >= 0.0) {
        o->ambient_q8 = (uint16_t)lround(a->ambient * 256.0);
        o->ambient_given = true;
    }
    if (a->light_colour) {
        (void)psc_io_objects_colour_parse(a->light_colour, o->colour_q8);
        o->colour_given = true;
    }
    for (unsigned i = 0; i < a->object_count; i++)
        if (psc_render_objects_add(o, a->objects[i], err, sizeof err) != 0) {
            fprintf(stderr, "%s: %s\n", pano_prog, err);
            psc_render_objects_free(o);
            return -1;
        }
    return 0;
}

/* The objects over the view drawn, and the ids. 0, or -1 said. */
static int objects_draw(const args_t *a, psc_render_objects_t *o, const psc_view_t *view, const psc_surface_t *out)
{
    char err[1024];
    if (psc_render_objects_draw(o, view, out, 0, a->ids, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", pano_prog, err);
        return -1;
    }
    return 0;
}

/* A tiled pack's view: drawn, the tiles it found absent read, drawn again, until every tile it needs is resident
 * (the output exact whatever the cache); then the frames timed. */
#define MAX_FILL_PASSES 64u

static int fill_tiles(psc_io_tiled_t *t, psc_viewer_t *viewer, psc_io_bands_t *bands, const psc_view_t *view,
                      const psc_surface_t *out, const char *path)
{
    uint32_t want[PSC_IO_BANDS_MAX_THREADS * PSC_VIEWER_MAX_REQUESTS];
    char err[1024];
    for (unsigned pass = 0; pass < MAX_FILL_PASSES; pass++) {
        psc_status_t s = psc_io_bands_render(bands, viewer, view, out);
        if (s != PSC_OK) {
            fprintf(stderr, "%s: rendering failed: %s\n", pano_prog, psc_status_str(s));
            return -1;
        }
        bool more;
        unsigned n = psc_io_bands_requests(bands, want, sizeof want / sizeof *want, &more);
        if (n == 0)
            return 0;
        if (psc_io_tiled_load(t, want, n, err, sizeof err) != 0) {
            fprintf(stderr, "%s: %s\n", pano_prog, err);
            return -1;
        }
    }
    fprintf(stderr, "%s: %s: the view still lacks tiles after %u passes: its cache of %u tiles is too small for "
            "it (raise --cache-mb)\n", pano_prog, path, MAX_FILL_PASSES, psc_io_tiled_slots(t));
    return -1;
}

static int render_tiled(const args_t *a, psc_render_objects_t *objects)
{
    psc_render_objects_light(objects, NULL, 0);   /* (a tiled pack's pyramid is in its tiles: the default light) */
    char err[1024];
    psc_io_tiled_t *t;
    size_t budget = (size_t)(a->cache_mb ? a->cache_mb : PSC_RENDER_CACHE_MB_DEFAULT) << 20;
    if (psc_io_tiled_open(a->pack, budget, &t, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", pano_prog, err);
        return 1;
    }
    const psc_pack_t *pack = psc_io_tiled_pack(t);
    psc_envmap_t map = pack->map;
    uint16_t w = a->have_size ? a->width : pack->display_width;
    uint16_t h = a->have_size ? a->height : pack->display_height;
    size_t ws_size = psc_viewer_workspace_size_tiled(w, h, &map);
    bool dither = display_dithers(a, map.format);
    psc_pixfmt_t draw_format = dither ? PSC_PIX_XRGB8888 : a->format;
    psc_surface_t out = {.width = w, .height = h, .stride = (uint32_t)w * psc_pixfmt_bytes(draw_format),
                         .format = draw_format};
    void *ws = alloc_aligned(ws_size);
    out.pixels = alloc_aligned((size_t)out.stride * h);
    int rc = 1;
    psc_viewer_t viewer;
    psc_status_t s;
    psc_io_bands_t *bands = NULL;
    if (!ws || !out.pixels) {
        fprintf(stderr, "%s: out of memory for a %ux%u view\n", pano_prog, (unsigned)w, (unsigned)h);
    } else if ((s = psc_viewer_init_tiled(&viewer, &map, psc_io_tiled_tiles(t), pack->luts, pack->lut_count, w, h,
                                          ws, ws_size)) != PSC_OK) {
        fprintf(stderr, "%s: %s: cannot set up a %ux%u viewer: %s\n", pano_prog, a->pack, (unsigned)w,
                (unsigned)h, psc_status_str(s));
    } else if (psc_viewer_set_simd(&viewer, a->simd) != PSC_OK) {
        fprintf(stderr, "%s: --simd %s: this build or this processor does not have it\n", pano_prog,
                psc_simd_name(a->simd));
    } else if (!(bands = psc_io_bands_start(a->threads ? (unsigned)a->threads : psc_io_online_cpus(), w, err,
                                            sizeof err))) {
        fprintf(stderr, "%s: %s\n", pano_prog, err);
    } else {
        psc_view_t want = {
            .yaw = a->have_yaw ? psc_io_bam_from_deg(a->yaw) : pack->default_yaw,
            .pitch = a->have_pitch ? psc_io_sbam_from_deg(a->pitch) : pack->default_pitch,
            .hfov = a->have_hfov ? psc_io_bam_from_deg(a->hfov) : pack->default_hfov,
            .filter = a->filter,
            .span_log2 = a->span_log2,
        };
        psc_view_t view = want;
        psc_viewer_clamp(&viewer, &view, pack->hfov_min);
        note_clamped(&want, &view);
        if (fill_tiles(t, &viewer, bands, &view, &out, a->pack) == 0 &&
            render_frames(&viewer, bands, &view, &out, a->repeat) == 0 && objects_draw(a, objects, &view, &out) == 0) {
            uint64_t loaded;
            psc_io_tiled_counts(t, &loaded, NULL);
            if (a->repeat > 1)
                fprintf(stderr, "%s: %llu tiles read into a cache of %u (%.1f MB)\n", pano_prog,
                        (unsigned long long)loaded, psc_io_tiled_slots(t), psc_io_tiled_bytes(t) / 1048576.0);
            rc = write_view(a, &out, dither) == 0 ? 0 : 1;
        }
    }
    psc_io_bands_stop(bands);
    free(out.pixels);
    free(ws);
    psc_io_tiled_close(t);
    return rc;
}

bool psc_render_pano_wanted(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    return true;   /* the mode of every file the others do not take */
}

int psc_render_pano_main(const char *prog, int argc, char **argv)
{
    pano_prog = prog;
    args_t a = {.filter = PSC_FILTER_BILINEAR, .span_log2 = PSC_SPAN_LOG2_DEFAULT, .repeat = 1,
                .format = PSC_PIX_RGB565, .ambient = -1.0};
    int rc = parse_args(argc, argv, &a);
    if (rc != 0)
        return rc;

    char err[512];
    psc_io_pack_t pf;
    if (a.levels.on)
        a.format = PSC_PIX_XRGB8888; /* dithered from the full colours */
    psc_render_objects_t objects;
    if (objects_load(&a, &objects) != 0)
        return 1;
    if (!psc_io_image_sniff(a.pack) && psc_io_tiled_sniff(a.pack)) {
        rc = render_tiled(&a, &objects);
        psc_render_objects_free(&objects);
        return rc;
    }
    if (load_scene(&a, &pf, err, sizeof err) != 0) {
        fprintf(stderr, "%s" ": %s\n", pano_prog, err);
        psc_render_objects_free(&objects);
        return 1;
    }
    const psc_pack_t *pack = &pf.pack;
    uint16_t w = a.have_size ? a.width : pack->display_width;
    uint16_t h = a.have_size ? a.height : pack->display_height;
    size_t ws_size = psc_viewer_workspace_size(w, h, &pack->map);
    bool dither = display_dithers(&a, pack->map.format);
    psc_pixfmt_t draw_format = dither ? PSC_PIX_XRGB8888 : a.format;
    uint32_t bpp = psc_pixfmt_bytes(draw_format);
    psc_surface_t out = {.width = w, .height = h, .stride = (uint32_t)w * bpp, .format = draw_format};
    void *ws = alloc_aligned(ws_size);
    out.pixels = alloc_aligned((size_t)out.stride * h);
    rc = 1;
    psc_viewer_t viewer;
    psc_status_t s;
    if (!ws || !out.pixels) {
        fprintf(stderr, "%s" ": out of memory for a %ux%u view\n", pano_prog, (unsigned)w, (unsigned)h);
    } else if ((s = psc_viewer_init(&viewer, &pack->map, pack->luts, pack->lut_count, w, h, ws, ws_size)) !=
                   PSC_OK ||
               (s = psc_viewer_set_levels(&viewer, pack->levels, pack->level_count)) != PSC_OK) {
        fprintf(stderr, "%s" ": %s: cannot set up a %ux%u viewer: %s\n", pano_prog, a.pack, (unsigned)w, (unsigned)h,
                psc_status_str(s));
    } else if (psc_viewer_set_simd(&viewer, a.simd) != PSC_OK) {
        fprintf(stderr, "%s" ": --simd %s: this build or this processor does not have it\n", pano_prog, psc_simd_name(a.simd));
    } else {
        psc_view_t want = {
            .yaw = a.have_yaw ? psc_io_bam_from_deg(a.yaw) : pack->default_yaw,
            .pitch = a.have_pitch ? psc_io_sbam_from_deg(a.pitch) : pack->default_pitch,
            .hfov = a.have_hfov ? psc_io_bam_from_deg(a.hfov) : pack->default_hfov,
            .filter = a.filter,
            .span_log2 = a.span_log2,
        };
        psc_view_t view = want;
        psc_viewer_clamp(&viewer, &view, pack->hfov_min);
        note_clamped(&want, &view);
        psc_render_objects_light(&objects, pack->levels, pack->level_count);   /* the panorama's own */
        psc_io_bands_t *bands =
            psc_io_bands_start(a.threads ? (unsigned)a.threads : psc_io_online_cpus(), w, err, sizeof err);
        if (!bands) {
            fprintf(stderr, "%s" ": %s\n", pano_prog, err);
        } else if (render_frames(&viewer, bands, &view, &out, a.repeat) == 0 &&
                   objects_draw(&a, &objects, &view, &out) == 0) {
            rc = write_view(&a, &out, dither) == 0 ? 0 : 1;
        }
        psc_io_bands_stop(bands);
    }
    free(out.pixels);
    free(ws);
    psc_io_pack_free(&pf);
    psc_render_objects_free(&objects);
    return rc;
}
