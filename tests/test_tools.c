/* SPDX-License-Identifier: MIT */
/*
 * test_tools.c - the command-line tools as a user runs them: periscope-pack,
 * periscope-render and periscope-contact, started as programs (posix_spawn)
 * from $PSC_BIN_DIR (default build/bin, relative to the repository root the
 * tests run from).
 *
 *  - a synthetic equirectangular PNG (tests/support's scene) packs to rgb565,
 *    xrgb8888 and pal8 scene packs whose maps hold the image (exactly for
 *    xrgb8888, rounded to nearest for rgb565, within a bound for pal8);
 *  - periscope-render's PNG is bit-exact with an in-process render of the same
 *    pack through the device's path (psc_io_pack_load, psc_viewer_init,
 *    psc_viewer_set_levels, psc_viewer_clamp, psc_viewer_render, as
 *    firmware/app.c), for views at yaw 180, pitch +-90, spans 1 and 16,
 *    nearest, bilinear and mip, both output formats, an odd size and clamped
 *    zooms; and the picture is the right one (the scene's markers at the
 *    centre: lon 0 green, lon 180 cyan, north pole red, south pole blue);
 *  - exit status 2 and a message for bad arguments, 1 and a message naming
 *    the file for a missing input or a corrupt pack, and no output file then;
 *  - periscope-contact tiles frames into a sheet of the documented size whose
 *    thumbnails are the frames' exact 2x2 box averages.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "psc_io_angle.h"
#include "psc_io_image.h"
#include "psc_io_pack_build.h"
#include "viewer/psc_viewer.h"
#include "dither/psc_dither.h"
#include "psc_testsupport.h"
#include "tsup_files.h"
#include "tsup_tool.h"
#include "psc_io_load.h"


#define MAP_W 256
#define MAP_H 128
#define DISP_W 160
#define DISP_H 120

/* ---- running the tools --------------------------------------------------------------------- */

static void tmp_path(char *buf, size_t n, const char *name)
{
    tsup_tmp_path(buf, n, "test_tools", name);
}


/* Run $PSC_BIN_DIR/tool with args (NULL-terminated); it must exit. */
static tsup_tool_run_t run_tool(const char *tool, const char *const *args)
{
    return tsup_run_tool("test_tools", tool, args);
}

/* Run and require exit status `status` and output containing each of the NULL-terminated mentions. */
static void expect_run(const char *tool, const char *const *args, int status, const char *const *mentions)
{
    tsup_tool_run_t r = run_tool(tool, args);
    char cmd[1024];
    size_t n = (size_t)snprintf(cmd, sizeof cmd, "%s", tool);
    for (size_t i = 0; args[i] && n < sizeof cmd; i++)
        n += (size_t)snprintf(cmd + n, sizeof cmd - n, " %s", args[i]);
    if (r.status != status)
        fail_msg("`%s` exited with %d, expected %d; its output:\n%s", cmd, r.status, status, r.output);
    for (size_t i = 0; mentions && mentions[i]; i++)
        if (!strstr(r.output, mentions[i]))
            fail_msg("`%s`: the output should mention \"%s\":\n%s", cmd, mentions[i], r.output);
    if (status != 0) {
        /* A failure always says something, starting with the tool's name. */
        char prefix[64];
        snprintf(prefix, sizeof prefix, "%s: ", tool);
        if (strncmp(r.output, prefix, strlen(prefix)) != 0)
            fail_msg("`%s`: the message should begin with \"%s\":\n%s", cmd, prefix, r.output);
        /* Show the last line: the error (progress lines may come before it). */
        size_t end = strlen(r.output);
        while (end > 0 && r.output[end - 1] == '\n')
            end--;
        size_t start = end;
        while (start > 0 && r.output[start - 1] != '\n')
            start--;
        printf("  exit %d: %s\n      %.*s\n", status, cmd, (int)(end - start), r.output + start);
    }
    free(r.output);
}

/* ---- the synthetic panorama and its packs ----------------------------------------------------------- */

static struct {
    int ready;
    char png[512];
    char pack[3][512];
    psc_image_t img;
} fx;

static const psc_pixfmt_t pack_formats[3] = {PSC_PIX_RGB565, PSC_PIX_XRGB8888, PSC_PIX_PAL8};
static const char *const pack_format_names[3] = {"rgb565", "xrgb8888", "pal8"};

/* The synthetic scene as a MAP_W x MAP_H equirectangular PNG, packed in the three formats. */
static void need_packs(void)
{
    if (fx.ready)
        return;
    psc_envmap_t geom = {0};
    geom.projection = PSC_PROJ_EQUIRECT;
    geom.format = PSC_PIX_XRGB8888;
    geom.width = MAP_W;
    geom.height = MAP_H;
    tsup_map_t m;
    assert_int_equal(tsup_synth_map(&m, &geom, 1, 0), 0);
    fx.img.width = MAP_W;
    fx.img.height = MAP_H;
    fx.img.xrgb = malloc(MAP_W * MAP_H * 4);
    assert_non_null(fx.img.xrgb);
    for (int r = 0; r < MAP_H; r++)
        for (int c = 0; c < MAP_W; c++)
            fx.img.xrgb[r * MAP_W + c] = 0xFF000000u | tsup_map_texel(&m.map, r, c);
    tsup_map_free(&m);
    tmp_path(fx.png, sizeof fx.png, "scene.png");
    char err[512];
    if (psc_io_image_write_png(fx.png, &fx.img, err, sizeof err) != 0)
        fail_msg("%s", err);
    for (int f = 0; f < 3; f++) {
        char name[64];
        snprintf(name, sizeof name, "scene-%s.pano", pack_format_names[f]);
        tmp_path(fx.pack[f], sizeof fx.pack[f], name);
        unlink(fx.pack[f]);
        const char *args[] = {fx.png, "-o", fx.pack[f], "--display", "160x120", "--format", pack_format_names[f],
                              "--quiet", NULL};
        tsup_tool_run_t r = run_tool("periscope-pack", args);
        if (r.status != 0)
            fail_msg("periscope-pack --format %s exited with %d:\n%s", pack_format_names[f], r.status, r.output);
        /* --quiet means no output at all on success. */
        if (r.output[0] != '\0')
            fail_msg("periscope-pack --quiet printed:\n%s", r.output);
        free(r.output);
    }
    fx.ready = 1;
}

static void test_pack(void **state)
{
    (void)state;
    need_packs();
    for (int f = 0; f < 3; f++) {
        psc_io_pack_t pf;
        char err[512];
        if (psc_io_pack_load(fx.pack[f], &pf, err, sizeof err) != 0)
            fail_msg("%s", err);
        const psc_envmap_t *m = &pf.pack.map;
        assert_int_equal(m->format, pack_formats[f]);
        assert_int_equal(m->projection, PSC_PROJ_EQUIRECT);
        assert_int_equal(m->width, MAP_W);
        assert_int_equal(m->height, MAP_H);
        assert_int_equal(pf.pack.display_width, DISP_W);
        assert_int_equal(pf.pack.display_height, DISP_H);
        assert_int_equal(pf.pack.lut_count, 2);
        /* The default pyramid of a full-turn equirect map: 256x128 down to 1 row at least. */
        assert_true(pf.pack.level_count >= 2);
        for (unsigned l = 1; l < pf.pack.level_count; l++) {
            assert_int_equal(pf.pack.levels[l].width, MAP_W >> l);
            assert_int_equal(pf.pack.levels[l].height, MAP_H >> l);
        }
        int max_err = 0;
        for (int r = 0; r < MAP_H; r++)
            for (int c = 0; c < MAP_W; c++) {
                uint32_t src = fx.img.xrgb[r * MAP_W + c], got = tsup_map_texel(m, r, c);
                uint32_t want = src & 0xFFFFFFu;
                if (f == 0) /* rgb565: each channel rounded to nearest, then widened */
                    want = tsup_rgb565_to_rgb888(
                        tsup_rgb888_to_rgb565(src >> 16 & 0xFF, src >> 8 & 0xFF, src & 0xFF));
                for (int k = 0; k < 3; k++) {
                    int d = abs((int)(got >> (8 * k) & 0xFF) - (int)(want >> (8 * k) & 0xFF));
                    max_err = d > max_err ? d : max_err;
                }
            }
        printf("  %s pack: map %ux%u, max channel error against the PNG %d\n", pack_format_names[f],
               (unsigned)m->width, (unsigned)m->height, max_err);
        /* Exact for xrgb8888 and rgb565 (after the documented rounding); the 256-colour median-cut
         * palette of this scene comes within 32 (measured: 22). */
        assert_true(max_err <= (f == 2 ? 32 : 0));
        psc_io_pack_free(&pf);
    }
    /* Without --quiet the tool says what it wrote. */
    char out[512];
    tmp_path(out, sizeof out, "loud.pano");
    const char *args[] = {fx.png, "-o", out, "--display", "160x120", "--format", "pal8", NULL};
    const char *mentions[] = {"wrote", out, "pal8", "256x128", NULL};
    expect_run("periscope-pack", args, 0, mentions);
    unlink(out);
}

/* ---- render: the tool against the device path in process -------------------------------------------------- */

typedef struct {
    const char *name;
    const char *args[12];   /* view arguments given to periscope-render */
    int have_yaw, have_pitch, have_hfov;
    double yaw, pitch, hfov;
    psc_filter_t filter;
    uint8_t span_log2;
    psc_pixfmt_t format;
    uint16_t w, h;          /* 0: the pack's display */
    int marker;             /* tsup_marker_t expected at the centre, or -1 */
} view_case_t;

static const view_case_t views[] = {
    {"default view", {NULL}, 0, 0, 0, 0, 0, 0, PSC_FILTER_BILINEAR, 2, PSC_PIX_RGB565, 0, 0, TSUP_MARK_LON0},
    {"yaw 30 pitch 10 hfov 75", {"--yaw", "30", "--pitch", "10", "--hfov", "75", NULL}, 1, 1, 1, 30, 10, 75,
     PSC_FILTER_BILINEAR, 2, PSC_PIX_RGB565, 0, 0, -1},
    {"pitch 90 nearest", {"--pitch", "90", "--hfov", "100", "--filter", "nearest", NULL}, 0, 1, 1, 0, 90, 100,
     PSC_FILTER_NEAREST, 2, PSC_PIX_RGB565, 0, 0, TSUP_MARK_NORTH},
    {"pitch -90 span 16", {"--pitch", "-90", "--span", "16", NULL}, 0, 1, 0, 0, -90, 0, PSC_FILTER_BILINEAR, 4,
     PSC_PIX_RGB565, 0, 0, TSUP_MARK_SOUTH},
    {"yaw 180 span 1", {"--yaw", "180", "--span", "1", NULL}, 1, 0, 0, 180, 0, 0, PSC_FILTER_BILINEAR, 0,
     PSC_PIX_RGB565, 0, 0, TSUP_MARK_LON180},
    {"yaw -90 span 16 nearest xrgb8888",
     {"--yaw", "-90", "--span", "16", "--filter", "nearest", "--format", "xrgb8888", NULL}, 1, 0, 0, -90, 0, 0,
     PSC_FILTER_NEAREST, 4, PSC_PIX_XRGB8888, 0, 0, TSUP_MARK_LON90W},
    {"97x61 yaw 90 pitch -30 span 1 xrgb8888",
     {"--size", "97x61", "--yaw", "90", "--pitch", "-30", "--span", "1", "--format", "xrgb8888", NULL}, 1, 1, 0, 90,
     -30, 0, PSC_FILTER_BILINEAR, 0, PSC_PIX_XRGB8888, 97, 61, -1},
    {"hfov 5 (clamped to the pack's 20)", {"--hfov", "5", "--yaw", "90", NULL}, 1, 0, 1, 90, 0, 5,
     PSC_FILTER_BILINEAR, 2, PSC_PIX_RGB565, 0, 0, TSUP_MARK_LON90E},
    {"hfov 170 (clamped to the widest table)", {"--hfov", "170", "--pitch", "45", NULL}, 0, 1, 1, 0, 45, 170,
     PSC_FILTER_BILINEAR, 2, PSC_PIX_RGB565, 0, 0, -1},
    /* Small outputs at wide zoom: each pixel covers several map texels, so mip reads the pyramid. */
    {"mip 32x24 hfov 120 yaw 180", {"--filter", "mip", "--size", "32x24", "--hfov", "120", "--yaw", "180", NULL},
     1, 0, 1, 180, 0, 120, PSC_FILTER_MIP, 2, PSC_PIX_RGB565, 32, 24, -1},
    {"mip 40x30 pitch 60 span 16 xrgb8888",
     {"--filter", "mip", "--size", "40x30", "--pitch", "60", "--span", "16", "--format", "xrgb8888", NULL}, 0, 1,
     0, 0, 60, 0, PSC_FILTER_MIP, 4, PSC_PIX_XRGB8888, 40, 30, -1},
};

/* The same view rendered in this process, exactly as the device does, as an image. */
static psc_image_t render_in_process(const char *pack_path, const view_case_t *vc, psc_view_t *used)
{
    psc_io_pack_t pf;
    char err[512];
    if (psc_io_pack_load(pack_path, &pf, err, sizeof err) != 0)
        fail_msg("%s", err);
    const psc_pack_t *p = &pf.pack;
    uint16_t w = vc->w ? vc->w : p->display_width, h = vc->h ? vc->h : p->display_height;
    size_t ws_size = psc_viewer_workspace_size(w, h, &p->map);
    void *ws = NULL;
    assert_int_equal(posix_memalign(&ws, 64, ws_size), 0);
    /* an RGB565 display shows a map of more colours drawn at 8 bits and dithered (display_dither) */
    bool dither = vc->format == PSC_PIX_RGB565 && p->map.format != PSC_PIX_RGB565;
    psc_pixfmt_t draw = dither ? PSC_PIX_XRGB8888 : vc->format;
    psc_surface_t out = {w, h, (uint32_t)w * psc_pixfmt_bytes(draw), draw, NULL};
    out.pixels = calloc(1, (size_t)out.stride * h);
    assert_non_null(out.pixels);
    psc_viewer_t v;
    assert_int_equal(psc_viewer_init(&v, &p->map, p->luts, p->lut_count, w, h, ws, ws_size), PSC_OK);
    assert_int_equal(psc_viewer_set_levels(&v, p->levels, p->level_count), PSC_OK);
    psc_view_t view = {
        .yaw = vc->have_yaw ? psc_io_bam_from_deg(vc->yaw) : p->default_yaw,
        .pitch = vc->have_pitch ? psc_io_sbam_from_deg(vc->pitch) : p->default_pitch,
        .hfov = vc->have_hfov ? psc_io_bam_from_deg(vc->hfov) : p->default_hfov,
        .filter = vc->filter,
        .span_log2 = vc->span_log2,
    };
    psc_viewer_clamp(&v, &view, p->hfov_min);
    assert_int_equal(psc_viewer_render(&v, &view, &out), PSC_OK);
    *used = view;
    if (dither) {
        static psc_dither_565_t table;
        psc_dither_565_init(&table);
        psc_surface_t shown = {w, h, (uint32_t)w * 2u, PSC_PIX_RGB565, calloc(1, (size_t)w * h * 2u)};
        assert_non_null(shown.pixels);
        for (unsigned y = 0; y < h; y++)
            psc_dither_row_rgb565(&table, PSC_DITHER_ORDERED, (const uint32_t *)out.pixels + (size_t)y * w, w, 0, y,
                                  (uint16_t *)shown.pixels + (size_t)y * w);
        free(out.pixels);
        out = shown;
    }
    psc_image_t img;
    assert_int_equal(psc_io_surface_to_image(&out, &img), 0);
    free(out.pixels);
    free(ws);
    psc_io_pack_free(&pf);
    return img;
}

static void test_render_matches_device_path(void **state)
{
    (void)state;
    need_packs();
    char png[512];
    tmp_path(png, sizeof png, "view.png");
    for (int f = 0; f < 3; f++)
        for (size_t k = 0; k < sizeof views / sizeof views[0]; k++) {
            const view_case_t *vc = &views[k];
            const char *args[20];
            size_t n = 0;
            args[n++] = fx.pack[f];
            args[n++] = "-o";
            args[n++] = png;
            for (size_t i = 0; vc->args[i]; i++)
                args[n++] = vc->args[i];
            args[n] = NULL;
            unlink(png);
            tsup_tool_run_t r = run_tool("periscope-render", args);
            if (r.status != 0)
                fail_msg("periscope-render %s (%s pack) exited with %d:\n%s", vc->name, pack_format_names[f],
                         r.status, r.output);
            psc_view_t used;
            psc_image_t want = render_in_process(fx.pack[f], vc, &used);
            if (vc->filter == PSC_FILTER_MIP) {
                /* The view must really use the pyramid: mip differs from bilinear there. */
                view_case_t bl = *vc;
                bl.filter = PSC_FILTER_BILINEAR;
                psc_image_t b = render_in_process(fx.pack[f], &bl, &used);
                assert_true(memcmp(b.xrgb, want.xrgb, (size_t)b.width * b.height * 4) != 0);
                psc_io_image_free(&b);
            }
            /* A view brought inside the pack's limits is reported; one that was not, is not. */
            int clamped = vc->have_hfov && (vc->hfov < 20.0 || vc->hfov > 120.0);
            assert_int_equal(strstr(r.output, "view brought inside") != NULL, clamped);
            free(r.output);

            psc_image_t got;
            char err[512];
            if (psc_io_image_load(png, &got, err, sizeof err) != 0)
                fail_msg("%s", err);
            char what[160];
            snprintf(what, sizeof what, "periscope-render %s, %s pack", vc->name, pack_format_names[f]);
            assert_int_equal(got.width, want.width);
            assert_int_equal(got.height, want.height);
            size_t diff = 0, first = 0;
            for (size_t i = 0; i < (size_t)got.width * got.height; i++)
                if (got.xrgb[i] != want.xrgb[i] && diff++ == 0)
                    first = i;
            if (diff)
                fail_msg("%s: %zu pixels differ from the in-process render, first (%zu, %zu): %08X vs %08X", what,
                         diff, first % got.width, first / got.width, (unsigned)got.xrgb[first],
                         (unsigned)want.xrgb[first]);

            /* And it is the right picture: the scene's marker at the centre of the view. */
            if (vc->marker >= 0) {
                uint32_t mc;
                tsup_marker((tsup_marker_t)vc->marker, NULL, NULL, &mc);
                uint32_t px = got.xrgb[(size_t)(got.height / 2) * got.width + got.width / 2];
                int tol = f == 2 ? 40 : 12;
                for (int c = 0; c < 3; c++)
                    if (abs((int)(px >> (8 * c) & 0xFF) - (int)(mc >> (8 * c) & 0xFF)) > tol)
                        fail_msg("%s: the centre is %06X, expected the marker colour %06X", what,
                                 (unsigned)(px & 0xFFFFFF), (unsigned)mc);
            }
            psc_io_image_free(&got);
            psc_io_image_free(&want);
        }
    printf("  %zu views x 3 packs: periscope-render is bit-exact with the in-process device path\n",
           sizeof views / sizeof views[0]);

    /* --dither: only the display's levels, the frame's brightness kept (the mean luma within 2%) */
    static const char *const targets[] = {"mono", "mono:halftone", "grey4", "pal8"};
    const char *plain_args[] = {fx.pack[0], "-o", png, "--format", "xrgb8888", NULL};
    tsup_tool_run_t pr = run_tool("periscope-render", plain_args);
    assert_int_equal(pr.status, 0);
    free(pr.output);
    psc_image_t plain;
    char err[512];
    if (psc_io_image_load(png, &plain, err, sizeof err) != 0)
        fail_msg("%s", err);
    for (size_t t = 0; t < sizeof targets / sizeof targets[0]; t++) {
        const char *args[] = {fx.pack[0], "-o", png, "--dither", targets[t], NULL};
        tsup_tool_run_t r = run_tool("periscope-render", args);
        if (r.status != 0)
            fail_msg("periscope-render --dither %s exited with %d:\n%s", targets[t], r.status, r.output);
        free(r.output);
        psc_image_t got;
        if (psc_io_image_load(png, &got, err, sizeof err) != 0)
            fail_msg("%s", err);
        double a = 0.0, b = 0.0;
        for (size_t i = 0; i < (size_t)got.width * got.height; i++) {
            uint32_t p = got.xrgb[i] & 0xFFFFFFu, q = plain.xrgb[i];
            if (strncmp(targets[t], "mono", 4) == 0 && p != 0 && p != 0xFFFFFFu)
                fail_msg("--dither %s: pixel %zu is %06X, not black or white", targets[t], i, (unsigned)p);
            if (strcmp(targets[t], "grey4") == 0 && ((p & 255u) % 17u != 0 || p != (p & 255u) * 0x010101u))
                fail_msg("--dither grey4: pixel %zu is %06X, not one of 16 greys", i, (unsigned)p);
            a += 0.299 * (p >> 16) + 0.587 * ((p >> 8) & 255u) + 0.114 * (p & 255u);
            b += 0.299 * ((q >> 16) & 255u) + 0.587 * ((q >> 8) & 255u) + 0.114 * (q & 255u);
        }
        if (fabs(a - b) > 0.02 * b)
            fail_msg("--dither %s: mean luma %.1f against %.1f undithered", targets[t], a / (double)(got.width * got.height),
                     b / (double)(got.width * got.height));
        psc_io_image_free(&got);
    }
    psc_io_image_free(&plain);
    const char *bad[] = {fx.pack[0], "-o", png, "--dither", "mono:fancy", NULL};
    tsup_tool_run_t br = run_tool("periscope-render", bad);
    assert_int_equal(br.status, 2);
    assert_non_null(strstr(br.output, "--dither 'mono:fancy'"));
    free(br.output);
    printf("  --dither mono, mono:halftone, grey4, pal8: the display's levels only, the mean luma kept\n");
    unlink(png);
}

/* ---- exit status and messages ------------------------------------------------------------------------------ */

/* Temporaries left beside path: names in its folder that begin with its own name and contain ".tmp". */
static unsigned temporaries_beside(const char *path)
{
    char dir[512];
    const char *slash = strrchr(path, '/');
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) : 1, slash ? path : ".");
    return tsup_count_names(dir, slash ? slash + 1 : path, ".tmp");
}

/*
 * Limits and nothing half-written (issue 16), as a user meets them:
 *  - a tiny PNG declaring 16384 x 16384 is more than a flat pack holds: it is
 *    packed tiled, from its rows as they are decoded, and refused at its first
 *    missing row with nothing written (it used to peak at 3.5 GB and write a
 *    716 MB pack); --max-pixels below an image's size refuses it from its
 *    header, naming the budget;
 *  - a FIFO given as the input is refused at once (no waiting for a writer);
 *  - periscope-pack stopped by a fatal signal while writing (here SIGXFSZ
 *    from a 16 KiB file-size limit, deterministic where a timed SIGTERM is
 *    not: the same handler serves SIGINT, SIGTERM, SIGHUP and SIGQUIT) dies
 *    of that signal, leaves no OUT.tmpPID.N beside the output, and an
 *    earlier output there stays as it was.
 */
static void test_limits_and_interrupted_writes(void **state)
{
    (void)state;
    need_packs();
    char png[512], out[512];
    tmp_path(png, sizeof png, "declares-16384x16384.png");
    tmp_path(out, sizeof out, "never.pano");
    unlink(out);
    /* PNG signature, IHDR 16384 x 16384 8-bit grey, an IDAT of one zlib-compressed byte, IEND */
    static const uint8_t bomb[] = {
        0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R', 0, 0, 0x40, 0, 0, 0, 0x40, 0,
        8, 0, 0, 0, 0, 0x8C, 0xA3, 0x4F, 0x58, 0, 0, 0, 9, 'I', 'D', 'A', 'T', 0x78, 0x9C, 0x63, 0, 0, 0, 1, 0, 1,
        0x5E, 0xFF, 0x7D, 0xF9, 0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    assert_int_equal(tsup_write_bytes(png, bomb, sizeof bomb), 0);
    const char *bomb_args[] = {png, "-o", out, "--display", "160x120", NULL};
    const char *bomb_says[] = {"is 16384x16384, more than a flat pack holds", "packing it tiled",
                               "truncated PNG at row 0 of 16384", NULL};
    expect_run("periscope-pack", bomb_args, 1, bomb_says);
    assert_false(tsup_file_exists(out));
    const char *small_args[] = {fx.png, "-o", out, "--display", "160x120", "--max-pixels", "1000", NULL};
    const char *small_says[] = {"more than the budget of 1000 pixels", NULL};
    expect_run("periscope-pack", small_args, 1, small_says);
    assert_false(tsup_file_exists(out));

    char fifo[512];
    tmp_path(fifo, sizeof fifo, "input-fifo.png");
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    const char *fifo_args[] = {fifo, "-o", out, "--display", "160x120", NULL};
    const char *fifo_says[] = {"not a regular file (a FIFO)", NULL};
    alarm(60);
    expect_run("periscope-pack", fifo_args, 1, fifo_says);
    alarm(0);
    unlink(fifo);

    /* interrupted while writing: an earlier pack at OUT survives whole */
    char exe[512], log[512];
    snprintf(exe, sizeof exe, "%s/periscope-pack", tsup_bin_dir());
    tmp_path(out, sizeof out, "interrupted.pano");
    tmp_path(log, sizeof log, "interrupted.log");
    static const char earlier[] = "an earlier pack";
    assert_int_equal(tsup_write_bytes(out, earlier, sizeof earlier), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        struct rlimit lim = {16384, 16384};
        int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0 || dup2(fd, 1) < 0 || dup2(fd, 2) < 0 || setrlimit(RLIMIT_FSIZE, &lim) != 0)
            _exit(126);
        execl(exe, exe, fx.png, "-o", out, "--display", "160x120", "--quiet", (char *)NULL);
        _exit(127);
    }
    int ws;
    while (waitpid(pid, &ws, 0) < 0)
        assert_int_equal(errno, EINTR);
    size_t len;
    char *said = (char *)tsup_read_bytes(log, &len);
    if (!WIFSIGNALED(ws) || WTERMSIG(ws) != SIGXFSZ)
        fail_msg("periscope-pack under a 16 KiB file limit should die of SIGXFSZ; status 0x%x, output:\n%s", ws,
                 said ? said : "");
    free(said);
    unlink(log);
    printf("  periscope-pack killed by signal %d while writing: %u temporaries left beside %s\n", WTERMSIG(ws),
           temporaries_beside(out), out);
    assert_int_equal(temporaries_beside(out), 0);
    char *kept = (char *)tsup_read_bytes(out, &len);
    assert_non_null(kept);
    assert_int_equal(len, sizeof earlier);
    assert_memory_equal(kept, earlier, sizeof earlier);
    free(kept);
    unlink(out);
    unlink(png);
}

/*
 * A partial panorama packed tiled (issue 30: a gigapixel of one wall is seldom a full turn) renders as its flat
 * pack does: periscope-pack --tiled --lon-range --lat-range, then periscope-render zoomed in (the tiled viewer at
 * level 0) gives the flat pack's bytes, nearest and bilinear; a wide view draws from the pyramid.
 */
static void test_partial_tiled(void **state)
{
    (void)state;
    char png[512], flat[512], tiled[512], a[512], b[512], err[512];
    tmp_path(png, sizeof png, "wall.png");
    tmp_path(flat, sizeof flat, "wall-flat.pano");
    tmp_path(tiled, sizeof tiled, "wall-tiled.pano");
    tmp_path(a, sizeof a, "wall-flat.png");
    tmp_path(b, sizeof b, "wall-tiled.png");
    psc_image_t img = {1280, 512, malloc(1280u * 512u * 4u)};   /* 120 x 48 degrees */
    assert_non_null(img.xrgb);
    for (uint32_t y = 0; y < img.height; y++)
        for (uint32_t x = 0; x < img.width; x++)
            img.xrgb[(size_t)y * img.width + x] = 0xFF000000u | (x * 255u / img.width) << 16 |
                                                  (y * 255u / img.height) << 8 | ((x ^ y) % 29u == 0 ? 255u : 64u);
    if (psc_io_image_write_png(png, &img, err, sizeof err) != 0)
        fail_msg("%s", err);
    free(img.xrgb);
    const char *pack_flat[] = {png, "-o", flat, "--display", "160x120", "--lon-range", "-70:50", "--lat-range",
                               "30:-18", "--format", "xrgb8888", "--quiet", NULL};
    expect_run("periscope-pack", pack_flat, 0, NULL);
    const char *pack_tiled[] = {png, "-o", tiled, "--display", "160x120", "--lon-range", "-70:50", "--lat-range",
                                "30:-18", "--format", "xrgb8888", "--tiled", NULL};
    const char *tiled_says[] = {"tiled", NULL};
    expect_run("periscope-pack", pack_tiled, 0, tiled_says);
    static const char *const filters[] = {"nearest", "bilinear"};
    for (int f = 0; f < 2; f++) {
        /* 20 degrees over 160 pixels: 1.3 texels a pixel, level 0 (the flat pack of a partial map has no pyramid) */
        const char *view_flat[] = {flat, "-o", a, "--yaw", "-25", "--pitch", "8", "--hfov", "20", "--filter",
                                   filters[f], "--format", "xrgb8888", NULL};
        const char *view_tiled[] = {tiled, "-o", b, "--yaw", "-25", "--pitch", "8", "--hfov", "20", "--filter",
                                    filters[f], "--format", "xrgb8888", "--cache-mb", "1", NULL};
        expect_run("periscope-render", view_flat, 0, NULL);
        expect_run("periscope-render", view_tiled, 0, NULL);
        psc_image_t ia, ib;
        assert_int_equal(psc_io_image_load(a, &ia, err, sizeof err), 0);
        assert_int_equal(psc_io_image_load(b, &ib, err, sizeof err), 0);
        assert_int_equal(ia.width * ia.height, ib.width * ib.height);
        if (memcmp(ia.xrgb, ib.xrgb, (size_t)ia.width * ia.height * 4u) != 0)
            fail_msg("periscope-render --filter %s: the tiled partial pack differs from the flat one", filters[f]);
        psc_io_image_free(&ia);
        psc_io_image_free(&ib);
    }
    /* wide, past the map's edge: brought inside it, drawn from the pyramid */
    const char *wide[] = {tiled, "-o", b, "--yaw", "80", "--hfov", "110", "--filter", "mip", NULL};
    const char *wide_says[] = {"view brought inside", NULL};
    expect_run("periscope-render", wide, 0, wide_says);
    printf("  a partial panorama (120 x 48 degrees) packed tiled: periscope-render gives the flat pack's bytes\n");
    unlink(png);
    unlink(flat);
    unlink(tiled);
    unlink(a);
    unlink(b);
}

/*
 * A tiled pack's tile codec (periscope-pack --tile-codec): a JPEG image's tiles are JPEG by default (the summary says
 * so, the pack a tenth of raw tiles'), a PNG's raw (the partial panorama above: the flat pack's bytes);
 * --tile-codec raw and jpeg:QUALITY are taken, a bad one refused naming the option; periscope-render draws a JPEG-tiled
 * pack within a stated PSNR of the raw one.
 */
static void test_tile_codec(void **state)
{
    (void)state;
    char jpeg[512], raw[512], low[512], a[512], b[512], err[512];
    tmp_path(jpeg, sizeof jpeg, "photo-jpeg.pano");
    tmp_path(raw, sizeof raw, "photo-raw.pano");
    tmp_path(low, sizeof low, "photo-q40.pano");
    tmp_path(a, sizeof a, "photo-raw.png");
    tmp_path(b, sizeof b, "photo-jpeg.png");
    const char *photo = "assets/pannellum-examplepano.jpg";
    const char *by_default[] = {photo, "-o", jpeg, "--display", "320x240", "--tiled", NULL};
    const char *says_jpeg[] = {"tiled", "JPEG,", "each on average", NULL};
    expect_run("periscope-pack", by_default, 0, says_jpeg);
    const char *as_raw[] = {photo, "-o", raw, "--display", "320x240", "--tile-codec", "raw", "--quiet", NULL};
    expect_run("periscope-pack", as_raw, 0, NULL);
    const char *q40[] = {photo, "-o", low, "--display", "320x240", "--tile-codec=jpeg:40", "--quiet", NULL};
    expect_run("periscope-pack", q40, 0, NULL);
    const char *bad[] = {photo, "-o", low, "--display", "320x240", "--tile-codec", "jpeg:0", NULL};
    const char *bad_says[] = {"--tile-codec 'jpeg:0'", NULL};
    expect_run("periscope-pack", bad, 2, bad_says);
    const char *webp[] = {photo, "-o", low, "--display", "320x240", "--tile-codec", "webp", NULL};
    const char *webp_says[] = {"--tile-codec 'webp': expected raw, jpeg or jpeg:QUALITY", NULL};
    expect_run("periscope-pack", webp, 2, webp_says);
    long sizes[3];
    const char *paths[3] = {raw, jpeg, low};
    for (int k = 0; k < 3; k++) {
        FILE *f = fopen(paths[k], "rb");
        assert_non_null(f);
        assert_int_equal(fseek(f, 0, SEEK_END), 0);
        sizes[k] = ftell(f);
        fclose(f);
    }
    /* measured: 34.9 MB raw, 3.5 MB at quality 90, 1.4 MB at 40 */
    assert_true(sizes[1] * 8 < sizes[0]);
    assert_true(sizes[2] < sizes[1]);
    const char *view_raw[] = {raw, "-o", a, "--yaw", "30", "--pitch", "10", "--hfov", "40", "--filter", "bilinear",
                              "--format", "xrgb8888", NULL};
    const char *view_jpeg[] = {jpeg, "-o", b, "--yaw", "30", "--pitch", "10", "--hfov", "40", "--filter", "bilinear",
                               "--format", "xrgb8888", NULL};
    expect_run("periscope-render", view_raw, 0, NULL);
    expect_run("periscope-render", view_jpeg, 0, NULL);
    psc_image_t ia, ib;
    assert_int_equal(psc_io_image_load(a, &ia, err, sizeof err), 0);
    assert_int_equal(psc_io_image_load(b, &ib, err, sizeof err), 0);
    assert_int_equal(ia.width * ia.height, ib.width * ib.height);
    double sq = 0;
    for (size_t i = 0; i < (size_t)ia.width * ia.height; i++)
        for (int sh = 0; sh < 24; sh += 8) {
            double d = (double)((ia.xrgb[i] >> sh) & 255u) - (double)((ib.xrgb[i] >> sh) & 255u);
            sq += d * d;
        }
    double psnr = sq > 0 ? 10 * log10(255.0 * 255.0 * 3.0 * ia.width * ia.height / sq) : 99;
    printf("  periscope-pack --tile-codec: the sample photograph %.1f MB in raw tiles, %.1f MB in JPEG tiles (the "
           "default for a JPEG), %.1f MB at quality 40; a view of the JPEG-tiled pack %.1f dB against the raw one\n",
           sizes[0] / 1e6, sizes[1] / 1e6, sizes[2] / 1e6, psnr);
    assert_true(psnr >= 40.0);   /* measured 45.7 dB */
    psc_io_image_free(&ia);
    psc_io_image_free(&ib);
    unlink(jpeg);
    unlink(raw);
    unlink(low);
    unlink(a);
    unlink(b);
}

static void test_exit_codes(void **state)
{
    (void)state;
    need_packs();
    char out[512], missing[512], bad[512];
    tmp_path(out, sizeof out, "never-written");
    unlink(out);
    const char *help[] = {"--help", NULL}, *usage[] = {"usage:", NULL};

    /* Bad arguments: 2, a message, nothing written. */
    struct {
        const char *tool;
        const char *args[12];
        const char *mention;
    } usage_cases[] = {
        {"periscope-pack", {NULL}, "no input image"},
        {"periscope-pack", {fx.png, "-o", out, NULL}, "--display"},
        {"periscope-pack", {fx.png, "-o", out, "--display", "0x10", NULL}, "--display"},
        {"periscope-pack", {fx.png, "-o", out, "--display", "160x120", "--format", "rgb666", NULL}, "rgb666"},
        {"periscope-pack", {fx.png, "-o", out, "--display", "160x120", "--bogus", NULL}, "--bogus"},
        {"periscope-pack", {fx.png, "-o", out, "--display", "160x120", "--hfov-min", "90", NULL}, "--hfov-min"},
        {"periscope-pack", {fx.png, "-o", fx.png, "--display", "160x120", NULL}, "overwrite"},
        {"periscope-pack", {fx.png, "-o", NULL}, "-o"},
        {"periscope-render", {fx.pack[0], NULL}, "-o"},
        {"periscope-render", {fx.pack[0], "-o", out, "--span", "3", NULL}, "--span"},
        {"periscope-render", {fx.pack[0], "-o", out, "--pitch", "91", NULL}, "--pitch"},
        {"periscope-render", {fx.pack[0], "-o", out, "--hfov", "180", NULL}, "--hfov"},
        {"periscope-render", {fx.pack[0], "-o", out, "--size", "5000x10", NULL}, "--size"},
        {"periscope-render", {fx.pack[0], "-o", out, "--yaw", "east", NULL}, "--yaw"},
        {"periscope-render", {fx.pack[0], fx.pack[1], "-o", out, NULL}, "more than one"},
        {"periscope-contact", {fx.png, NULL}, "-o"},
        {"periscope-contact", {"-o", out, NULL}, "no frames"},
        {"periscope-contact", {"-o", out, "--columns", "0", fx.png, NULL}, "--columns"},
        {"periscope-contact", {"-o", out, "--thumb-width", "4", fx.png, NULL}, "--thumb-width"},
    };
    for (size_t i = 0; i < sizeof usage_cases / sizeof usage_cases[0]; i++) {
        const char *mentions[] = {usage_cases[i].mention, NULL};
        expect_run(usage_cases[i].tool, usage_cases[i].args, 2, mentions);
        assert_false(tsup_file_exists(out));
    }
    expect_run("periscope-pack", help, 0, usage);
    expect_run("periscope-render", help, 0, usage);
    expect_run("periscope-contact", help, 0, usage);

    /* A missing input: 1 and the file named ("PATH: problem"). */
    char named[600];
    tmp_path(missing, sizeof missing, "missing.png");
    unlink(missing);
    snprintf(named, sizeof named, "%s: ", missing);
    {
        const char *a[] = {missing, "-o", out, "--display", "160x120", NULL}, *m[] = {named, NULL};
        expect_run("periscope-pack", a, 1, m);
        assert_false(tsup_file_exists(out));
    }
    tmp_path(missing, sizeof missing, "missing.pano");
    snprintf(named, sizeof named, "%s: ", missing);
    {
        const char *a[] = {missing, "-o", out, NULL}, *m[] = {named, NULL};
        expect_run("periscope-render", a, 1, m);
        assert_false(tsup_file_exists(out));
    }
    tmp_path(missing, sizeof missing, "missing-frame.png");
    snprintf(named, sizeof named, "%s: ", missing);
    {
        const char *a[] = {"-o", out, fx.png, missing, NULL}, *m[] = {named, NULL};
        expect_run("periscope-contact", a, 1, m);
        assert_false(tsup_file_exists(out));
    }

    /* A corrupt image given to periscope-pack: 1 and the file named. */
    size_t len;
    uint8_t *png = tsup_read_bytes(fx.png, &len);
    assert_non_null(png);
    tmp_path(bad, sizeof bad, "cut.png");
    assert_int_equal(tsup_write_bytes(bad, png, len / 2), 0);
    free(png);
    snprintf(named, sizeof named, "%s: ", bad);
    {
        const char *a[] = {bad, "-o", out, "--display", "160x120", NULL}, *m[] = {named, "truncated", NULL};
        expect_run("periscope-pack", a, 1, m);
        assert_false(tsup_file_exists(out));
    }
    unlink(bad);

    /* Corrupt packs given to periscope-render: 1 and the file named. */
    uint8_t *pack = tsup_read_bytes(fx.pack[0], &len);
    assert_non_null(pack);
    tmp_path(bad, sizeof bad, "bad.pano");
    snprintf(named, sizeof named, "%s: ", bad);
    struct {
        const char *what, *mention;
        size_t len;
        size_t flip;   /* byte to invert, or SIZE_MAX */
    } packs[] = {
        {"a flipped byte in the map", "CRC", len, len / 2},
        {"cut in half", "trunc", len / 2, SIZE_MAX},
        {"the first 40 bytes", "trunc", 40, SIZE_MAX},
        {"a flipped magic byte", "magic", len, 3},
        {"empty", "empty", 0, SIZE_MAX},
    };
    for (size_t i = 0; i < sizeof packs / sizeof packs[0]; i++) {
        if (packs[i].flip != SIZE_MAX)
            pack[packs[i].flip] ^= 0xFF;
        assert_int_equal(tsup_write_bytes(bad, pack, packs[i].len), 0);
        if (packs[i].flip != SIZE_MAX)
            pack[packs[i].flip] ^= 0xFF;
        const char *a[] = {bad, "-o", out, NULL}, *m[] = {named, packs[i].mention, NULL};
        expect_run("periscope-render", a, 1, m);
        assert_false(tsup_file_exists(out));
    }
    /* An image is packed first, as the device packs one for the RGB565 output it dithers (tests/test_open_image.c:
     * RGB888); no cache here. */
    snprintf(named, sizeof named, "%s: packed for 640x480 rgb888 in ", fx.png);
    {
        const char *a[] = {fx.png, "-o", out, NULL}, *m[] = {named, "not cached", NULL};
        assert_int_equal(setenv("PERISCOPE_CACHE_DIR", "", 1), 0);
        expect_run("periscope-render", a, 0, m);
        assert_int_equal(unsetenv("PERISCOPE_CACHE_DIR"), 0);
        assert_true(tsup_file_exists(out));
        unlink(out);
    }
    free(pack);
    unlink(bad);
}

/* ---- one command-line convention ---------------------------------------------------------------------------- */

#define MAX_PROGRAMS 64

/* The programs Periscope ships: the build's list, $PSC_BIN_DIR/../programs.txt (the Makefile's PROGRAMS, written by
 * make all), one name a line, into names (pointers into *text, which the caller frees). Returns how many. */
static size_t program_list(char **text, const char *names[MAX_PROGRAMS])
{
    char path[600];
    size_t len, n = 0;
    snprintf(path, sizeof path, "%s/../programs.txt", tsup_bin_dir());
    *text = (char *)tsup_read_bytes(path, &len);
    if (!*text)
        fail_msg("no program list %s: make all writes it", path);
    for (char *line = strtok(*text, "\n"); line; line = strtok(NULL, "\n")) {
        if (line[0] < 'a' || line[0] > 'z' || strspn(line, "abcdefghijklmnopqrstuvwxyz0123456789-") != strlen(line))
            fail_msg("%s: '%s' is not a program name", path, line);
        if (n == MAX_PROGRAMS)
            fail_msg("%s: more than %d programs", path, MAX_PROGRAMS);
        names[n++] = line;
    }
    int device = 0;
    for (size_t i = 0; i < n; i++)
        device |= strcmp(names[i], "periscope") == 0;
    if (!device)
        fail_msg("%s does not list the device program periscope", path);
    return n;
}

/* Every program of the build's list, the device's and the tools': --help, --version, --opt=value
 * and --opt value alike, options after files, and one wording for mistakes. */
static void test_command_line_convention(void **state)
{
    (void)state;
    need_packs();
    char *list;
    const char *programs[MAX_PROGRAMS];
    size_t n_programs = program_list(&list, programs);
    char version[64], said[96];
    size_t vlen;
    char *v = (char *)tsup_read_bytes("VERSION", &vlen);
    assert_non_null(v);
    snprintf(version, sizeof version, "%.*s", (int)strcspn(v, " \n"), v);
    free(v);
    snprintf(said, sizeof said, "(Periscope) %s\n", version);
    for (size_t i = 0; i < n_programs; i++) {
        const char *help[] = {"--help", NULL}, *usage[] = {"usage:", NULL};
        const char *ver[] = {"--version", NULL}, *ver_said[] = {said, NULL};
        const char *bogus[] = {"--bogus-option", NULL}, *unknown[] = {"unknown option '--bogus-option'", NULL};
        expect_run(programs[i], help, 0, usage);
        expect_run(programs[i], ver, 0, ver_said);
        expect_run(programs[i], bogus, 2, unknown);
    }
    printf("test_tools: %zu programs of %s/../programs.txt answer --help, --version and a wrong option\n", n_programs,
           tsup_bin_dir());
    free(list);

    /* a typo is not taken for the option it resembles */
    const char *typo[] = {"--board", "sim", "--scen", fx.pack[0], NULL};
    const char *typo_said[] = {"unknown option '--scen' (did you mean '--scene'?)", NULL};
    expect_run("periscope", typo, 2, typo_said);
    const char *typo2[] = {fx.png, "--displ", "160x120", NULL};
    const char *typo2_said[] = {"unknown option '--displ' (did you mean '--display'?)", NULL};
    expect_run("periscope-pack", typo2, 2, typo2_said);
    const char *novalue[] = {"--board", NULL}, *novalue_said[] = {"option '--board' needs a value", NULL};
    expect_run("periscope", novalue, 2, novalue_said);
    const char *flagvalue[] = {fx.png, "--quiet=yes", NULL}, *flagvalue_said[] = {"option '--quiet' takes no value", NULL};
    expect_run("periscope-pack", flagvalue, 2, flagvalue_said);

    /* --board=sim and --board sim are one thing */
    const char *key_eq[] = {"--board=sim", "--print-key=display_size", NULL};
    const char *key_sp[] = {"--print-key", "display_size", "--board", "sim", NULL}, *size[] = {"640x480", NULL};
    expect_run("periscope", key_eq, 0, size);
    expect_run("periscope", key_sp, 0, size);

    /* the same view asked for both ways renders the same bytes */
    char a_png[512], b_png[512];
    tmp_path(a_png, sizeof a_png, "view-eq.png");
    tmp_path(b_png, sizeof b_png, "view-sp.png");
    const char *eq[] = {"--yaw=30", "--pitch=-10", "--size=80x60", "--filter=nearest", fx.pack[0], "-o", a_png, NULL};
    const char *sp[] = {fx.pack[0], "--yaw", "30", "--pitch", "-10", "--size", "80x60", "--filter", "nearest",
                        "-o", b_png, NULL};
    expect_run("periscope-render", eq, 0, NULL);
    expect_run("periscope-render", sp, 0, NULL);
    size_t la, lb;
    uint8_t *pa = tsup_read_bytes(a_png, &la), *pb = tsup_read_bytes(b_png, &lb);
    assert_non_null(pa);
    assert_non_null(pb);
    assert_int_equal(la, lb);
    assert_memory_equal(pa, pb, la);
    free(pa);
    free(pb);
    unlink(a_png);
    unlink(b_png);
}

/* ---- characters -------------------------------------------------------------------------------------------- */

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    assert_true(fputs(text, f) >= 0);
    assert_int_equal(fclose(f), 0);
}

/* The look options of the 3D modes on Thom (reference plain.png from the same view): Phong and the A-buffer change
 * the frame; the A-buffer in 32-pixel tiles with a tile's budget gives the full screen's bytes; a budget too small
 * for the heads is refused, one too small for the edges is said and drawn; --dither leaves only the display's
 * levels; mistakes get their messages. */
static void check_patch_look(const char *ppk, const char *plain, const char *out)
{
    char full[512];
    tmp_path(full, sizeof full, "thom-aa.png");
#define VIEW ppk, "--play", "Wave", "--time", "1.1", "--orbit", "200,10,2.5", "--size", "160x120"
    const char *phong[] = {VIEW, "--shade", "phong", "-o", out, NULL};
    expect_run("periscope-render", phong, 0, NULL);
    assert_false(tsup_same_file(plain, out));
    const char *aa[] = {VIEW, "--aa", "abuffer", "-o", full, NULL};
    expect_run("periscope-render", aa, 0, NULL);
    assert_false(tsup_same_file(plain, full));
    const char *aa_tiles[] = {VIEW, "--aa", "abuffer:64", "--tiles", "32", "-o", out, NULL};
    expect_run("periscope-render", aa_tiles, 0, NULL);
    assert_true(tsup_same_file(full, out));
    const char *heads_only[] = {VIEW, "--aa", "abuffer:4", "--tiles", "32", "-o", out, NULL};
    const char *heads_said[] = {"--aa abuffer:4 is too small", NULL};
    expect_run("periscope-render", heads_only, 1, heads_said);
    const char *tight[] = {VIEW, "--aa", "abuffer:5", "--tiles", "32", "-o", out, NULL};
    const char *tight_said[] = {"drawn aliased", NULL};
    expect_run("periscope-render", tight, 0, tight_said);
    const char *mono[] = {VIEW, "--aa", "abuffer", "--dither", "mono:halftone", "-o", out, NULL};
    expect_run("periscope-render", mono, 0, NULL);
    psc_image_t got;
    char err[512];
    if (psc_io_image_load(out, &got, err, sizeof err) != 0)
        fail_msg("%s", err);
    for (size_t i = 0; i < (size_t)got.width * got.height; i++)
        if ((got.xrgb[i] & 0xFFFFFFu) != 0 && (got.xrgb[i] & 0xFFFFFFu) != 0xFFFFFFu)
            fail_msg("--dither mono:halftone: pixel %zu is %06X", i, (unsigned)got.xrgb[i]);
    psc_io_image_free(&got);
    const char *bad_aa[] = {VIEW, "--aa", "msaa", "-o", out, NULL}, *bad_aa_said[] = {"--aa 'msaa'", NULL};
    expect_run("periscope-render", bad_aa, 2, bad_aa_said);
    const char *bad_shade[] = {VIEW, "--shade", "toon", "-o", out, NULL}, *bad_shade_said[] = {"--shade 'toon'", NULL};
    expect_run("periscope-render", bad_shade, 2, bad_shade_said);
    const char *area[] = {VIEW, "--hsr", "area", "-o", out, NULL};
    expect_run("periscope-render", area, 0, NULL);
    assert_true(tsup_same_file(plain, out));
    const char *area_tiles[] = {VIEW, "--hsr", "area", "--tiles", "32", "-o", out, NULL};
    expect_run("periscope-render", area_tiles, 0, NULL);
    assert_true(tsup_same_file(plain, out));
    const char *bad_hsr[] = {VIEW, "--hsr", "painter", "-o", out, NULL}, *bad_hsr_said[] = {"--hsr 'painter'", NULL};
    expect_run("periscope-render", bad_hsr, 2, bad_hsr_said);
    const char *threads[] = {VIEW, "--threads", "3", "-o", out, NULL};
    expect_run("periscope-render", threads, 0, NULL);
    assert_true(tsup_same_file(plain, out));
    const char *threads_aa[] = {VIEW, "--threads", "2", "--aa", "abuffer:64", "--tiles", "32", "-o", out, NULL};
    expect_run("periscope-render", threads_aa, 0, NULL);
    assert_true(tsup_same_file(full, out));
    const char *bad_threads[] = {VIEW, "--threads", "17", "-o", out, NULL},
               *bad_threads_said[] = {"--threads '17'", NULL};
    expect_run("periscope-render", bad_threads, 2, bad_threads_said);
#undef VIEW
    printf("  3D looks: --shade phong, --aa abuffer (tiles give the same bytes; a small budget is said), --dither, "
           "--hsr area and --threads (the same bytes)\n");
    unlink(full);
}

/* periscope-patch writes the pack periscope-render draws; the model drawn directly gives the same bytes; the
 * stats line is there and says no crack; mistakes get their messages. */
static void test_patch_tools(void **state)
{
    (void)state;
    char ppk[512], a_png[512], b_png[512];
    tmp_path(ppk, sizeof ppk, "thom.ppk");
    tmp_path(a_png, sizeof a_png, "thom-pack.png");
    tmp_path(b_png, sizeof b_png, "thom-model.png");
    const char *build[] = {"assets/thom/Thom.mdl", "--skin-from", "assets/thom/Thom2.mdl", "--action",
                           "assets/thom/ResoluteWalk.act", "--action=assets/thom/Wave.act", "-o", ppk, NULL};
    const char *built[] = {"392 patches", "52 bones", "2 actions", NULL};
    expect_run("periscope-patch", build, 0, built);
    const char *from_pack[] = {ppk, "--play", "Wave", "--time", "1.1", "--orbit", "200,10,2.5", "--size", "160x120",
                               "--stats", "-o", a_png, NULL};
    const char *stats[] = {"patches=", "triangles=", "max_chord_err=", "crack_edges=0 ", "culled=", NULL};
    expect_run("periscope-render", from_pack, 0, stats);
    const char *from_model[] = {"assets/thom/Thom.mdl", "--skin-from", "assets/thom/Thom2.mdl", "--action",
                                "assets/thom/ResoluteWalk.act", "--action", "assets/thom/Wave.act", "--play=Wave",
                                "--time=1.1", "--orbit=200,10,2.5", "--size=160x120", "-o", b_png, NULL};
    expect_run("periscope-render", from_model, 0, NULL);
    size_t la, lb;
    uint8_t *pa = tsup_read_bytes(a_png, &la), *pb = tsup_read_bytes(b_png, &lb);
    assert_non_null(pa);
    assert_non_null(pb);
    assert_int_equal(la, lb);
    assert_memory_equal(pa, pb, la);
    free(pa);
    free(pb);
    /* --pose t=T and a pose file with that time draw the same bytes as --time; a bone turned by the file does not */
    char json[512], c_png[512];
    tmp_path(json, sizeof json, "pose.json");
    tmp_path(c_png, sizeof c_png, "thom-posed.png");
    const char *by_pose[] = {ppk, "--play", "Wave", "--pose", "t=1.1", "--orbit", "200,10,2.5", "--size", "160x120",
                             "-o", b_png, NULL};
    expect_run("periscope-render", by_pose, 0, NULL);
    assert_true(tsup_same_file(a_png, b_png));
    write_text(json, "{\"time\": 1.1}");
    const char *by_file[] = {ppk, "--play", "Wave", "--pose", json, "--orbit", "200,10,2.5", "--size", "160x120",
                             "-o", b_png, NULL};
    expect_run("periscope-render", by_file, 0, NULL);
    assert_true(tsup_same_file(a_png, b_png));
    write_text(json, "{\"time\": 1.1, \"nodes\": {\"14\": {\"rotate\": [1, 0, 0, 40]}}}");
    const char *turned[] = {ppk, "--play", "Wave", "--pose", json, "--orbit", "200,10,2.5", "--size", "160x120",
                            "-o", c_png, NULL};
    expect_run("periscope-render", turned, 0, NULL);
    assert_false(tsup_same_file(a_png, c_png));
    write_text(json, "{\"nodes\": {\"Thigh\": {\"rotate\": [1, 0, 0, 40]}}}");
    const char *by_name_said[] = {json, "node 'Thigh'", "given by number", NULL};
    expect_run("periscope-render", turned, 1, by_name_said);
    unlink(json);
    unlink(c_png);
    check_patch_look(ppk, a_png, b_png);
    const char *no_action[] = {ppk, "--play", "Dance", "-o", a_png, NULL};
    const char *no_action_said[] = {"has no action named 'Dance'", NULL};
    expect_run("periscope-render", no_action, 1, no_action_said);
    const char *missing[] = {"no/such/model.mdl", "-o", ppk, NULL}, *missing_said[] = {"no/such/model.mdl", NULL};
    expect_run("periscope-patch", missing, 1, missing_said);
    const char *act_on_pack[] = {ppk, "--action", "assets/thom/Wave.act", "-o", a_png, NULL};
    const char *act_on_pack_said[] = {"carries its actions", NULL};
    expect_run("periscope-render", act_on_pack, 1, act_on_pack_said);
    unlink(ppk);
    unlink(a_png);
    unlink(b_png);
}

/* periscope-proxy bakes a model; periscope-render draws the pack as proxies or full (--ids, --depth, --repeat,
 * a pose file on the pack's skeleton); mistakes get their messages. */
static void test_proxy_tools(void **state)
{
    (void)state;
    const char *bar = TSUP_DATA_GLTF "animation_with_skeleton.gltf";
    char ppx[512], a_png[512], b_png[512], ids[512], depth[512], json[512];
    tmp_path(ppx, sizeof ppx, "bar.ppx");
    tmp_path(a_png, sizeof a_png, "bar-a.png");
    tmp_path(b_png, sizeof b_png, "bar-b.png");
    tmp_path(ids, sizeof ids, "bar-ids.pgm");
    tmp_path(depth, sizeof depth, "bar-depth.pgm");
    tmp_path(json, sizeof json, "bar.json");
    const char *bake[] = {"bake", bar, "-o", ppx, "--views", "9", "--tex", "32", "--tex-mb", "0.4", NULL};
    const char *baked[] = {"11 parts and 11 joints", "528 proxy triangles for 2112", "9 views", "texels per R (",
                           "to 32x32", "with mips: 0.4 MB",
                           "26 animation samples", NULL};
    expect_run("periscope-proxy", bake, 0, baked);
    const char *proxies[] = {ppx, "--pose", "t=0.4", "--size", "160x120", "--ids", ids, "--depth", depth,
                             "--repeat", "2", "-o", a_png, NULL};
    const char *timed[] = {"ms per frame", "proxies", NULL};
    expect_run("periscope-render", proxies, 0, timed);
    size_t len;
    uint8_t *pgm = tsup_read_bytes(ids, &len);
    assert_non_null(pgm);
    assert_true(len == 17 + 160 * 120 * 2 && memcmp(pgm, "P5\n160 120\n65535\n", 17) == 0);
    unsigned shown = 0;
    for (size_t i = 17; i + 1 < len; i += 2)
        shown += pgm[i] != 0 || pgm[i + 1] != 0;
    assert_true(shown > 100);   /* part ids where the bar is */
    free(pgm);
    assert_true(tsup_file_exists(depth));
    const char *full[] = {ppx, "--pose", "t=0.4", "--size", "160x120", "--full", "--tiles", "32", "-o", b_png, NULL};
    expect_run("periscope-render", full, 0, NULL);
    assert_false(tsup_same_file(a_png, b_png));
    write_text(json, "{\"time\": 0.4, \"nodes\": {\"5\": {\"rotate\": [0, 0, 1, 60]}}}");
    const char *posed[] = {ppx, "--pose", json, "--size", "160x120", "-o", b_png, NULL};
    expect_run("periscope-render", posed, 0, NULL);
    assert_false(tsup_same_file(a_png, b_png));
    /* relit: another light changes the frame, the bake's own at rest does not; a bad light is said */
    const char *rest[] = {ppx, "--size", "160x120", "--format", "xrgb8888", "-o", a_png, NULL};
    expect_run("periscope-render", rest, 0, NULL);
    const char *same[] = {ppx, "--size", "160x120", "--format", "xrgb8888", "--light", "41.634,53.043", "-o", b_png, NULL};
    expect_run("periscope-render", same, 0, NULL);
    assert_true(tsup_same_file(a_png, b_png));
    const char *side[] = {ppx, "--size", "160x120", "--format", "xrgb8888", "--light", "-90,10", "--ambient", "0.3",
                          "-o", b_png, NULL};
    expect_run("periscope-render", side, 0, NULL);
    assert_false(tsup_same_file(a_png, b_png));
    const char *badlight[] = {ppx, "--light", "90", "-o", b_png, NULL}, *badlight_said[] = {"--light '90'", NULL};
    expect_run("periscope-render", badlight, 2, badlight_said);
    const char *amb[] = {ppx, "--ambient", "0.3", "-o", b_png, NULL}, *amb_said[] = {"--ambient needs --light", NULL};
    expect_run("periscope-render", amb, 2, amb_said);
    const char *plain[] = {"bake", bar, "-o", ppx, "--views", "9", "--tex", "32", "--no-normals", NULL};
    const char *plain_said[] = {"not relightable (--no-normals)", NULL};
    expect_run("periscope-proxy", plain, 0, plain_said);
    const char *unlit[] = {ppx, "--light", "-90,10", "-o", b_png, NULL}, *unlit_said[] = {"the pack has no normals", NULL};
    expect_run("periscope-render", unlit, 1, unlit_said);
    const char *tex48[] = {"bake", bar, "-o", ppx, "--tex", "48", NULL}, *tex48_said[] = {"--tex '48'", NULL};
    expect_run("periscope-proxy", tex48, 2, tex48_said);
    const char *verb[] = {"make", bar, "-o", ppx, NULL}, *verb_said[] = {"expected the command 'bake'", NULL};
    expect_run("periscope-proxy", verb, 2, verb_said);
    /* an OBJ: its groups are rigid parts */
    char obj[512];
    tmp_path(obj, sizeof obj, "slab.obj");
    write_text(obj, "g slab\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nv -2 -0.2 -2\nv 2 -0.2 -2\nv 2 -0.2 2\n"
                    "v -2 -0.2 2\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
                    "g post\nv -0.2 0 -0.2\nv 0.2 0 -0.2\nv 0.2 2 -0.2\nv -0.2 2 -0.2\nv -0.2 0 0.2\nv 0.2 0 0.2\n"
                    "v 0.2 2 0.2\nv -0.2 2 0.2\nf 9 10 11 12\nf 16 15 14 13\nf 9 13 14 10\nf 10 14 15 11\n"
                    "f 11 15 16 12\nf 12 16 13 9\n");
    const char *obj_bake[] = {"bake", obj, "-o", ppx, NULL}, *obj_baked[] = {"2 parts and 0 joints", NULL};
    expect_run("periscope-proxy", obj_bake, 0, obj_baked);
    const char *obj_render[] = {ppx, "--size", "160x120", "--ids", ids, "-o", a_png, NULL};
    expect_run("periscope-render", obj_render, 0, NULL);
    pgm = tsup_read_bytes(ids, &len);
    assert_non_null(pgm);
    unsigned part[3] = {0, 0, 0};
    for (size_t i = 17; i + 1 < len; i += 2)
        part[pgm[i + 1] < 3 && pgm[i] == 0 ? pgm[i + 1] : 0]++;
    assert_true(part[1] > 100 && part[2] > 100);   /* the slab and the post */
    free(pgm);
    unlink(obj);
    write_text(ppx, "not a pack at all, but long enough to be read as one.............");
    const char *bad[] = {ppx, "-o", a_png, NULL}, *bad_said[] = {"not a usable proxy pack", NULL};
    expect_run("periscope-render", bad, 1, bad_said);
    unlink(ppx), unlink(a_png), unlink(b_png), unlink(ids), unlink(depth), unlink(json);
}

/* periscope-shadow builds a glTF model's tables; periscope-render poses it (rest, t=, a pose file naming a node)
 * and shades it, --dump-ao writing a line a vertex; an OBJ's groups as parts; a patch model's tessellation dumped
 * to a file named .obj (not taken for the model); mistakes get their messages. */
static void test_gltf_tools(void **state)
{
    (void)state;
    const char *bar = TSUP_DATA_GLTF "animation_with_skeleton.gltf";
    const char *truck = TSUP_DATA_GLTF "CesiumMilkTruck.gltf";
    char pao[512], a_png[512], b_png[512], csv[512], json[512];
    tmp_path(pao, sizeof pao, "bar.pao");
    tmp_path(a_png, sizeof a_png, "bar-a.png");
    tmp_path(b_png, sizeof b_png, "bar-b.png");
    tmp_path(csv, sizeof csv, "bar.csv");
    tmp_path(json, sizeof json, "truck.json");
    const char *build[] = {"build", bar, "-o", pao, NULL}, *built[] = {"2464 surface samples", "spheres", NULL};
    expect_run("periscope-shadow", build, 0, built);
    const char *shaded[] = {bar, "--pose", "t=0.4", "--shadow", pao, "--dump-ao", csv, "--size", "160x120", "-o", a_png,
                            NULL};
    expect_run("periscope-render", shaded, 0, NULL);
    size_t len;
    char *text = (char *)tsup_read_bytes(csv, &len);
    assert_non_null(text);
    unsigned lines = 0;
    for (size_t i = 0; i < len; i++)
        lines += text[i] == '\n';
    assert_int_equal(lines, 1 + 2464);   /* the header and a line a vertex */
    assert_memory_equal(text, "x,y,z,nx,ny,nz,occlusion\n", 25);
    free(text);
    const char *plain[] = {bar, "--pose", "t=0.4", "--size", "160x120", "-o", b_png, NULL};
    expect_run("periscope-render", plain, 0, NULL);
    assert_false(tsup_same_file(a_png, b_png));   /* the shading shows */
    /* a node turned by a pose file moves it */
    const char *rest[] = {truck, "--size", "160x120", "-o", a_png, NULL};
    expect_run("periscope-render", rest, 0, NULL);
    write_text(json, "{\"nodes\": {\"Geometry-mesh001Node\": {\"translate\": [0, 0.6, 0]}}}");
    const char *posed[] = {truck, "--pose", json, "--size", "160x120", "-o", b_png, NULL};
    expect_run("periscope-render", posed, 0, NULL);
    assert_false(tsup_same_file(a_png, b_png));
    write_text(json, "{\"nodes\": {\"NoSuchNode\": {\"translate\": [0, 1, 0]}}}");
    const char *no_node_said[] = {json, "node 'NoSuchNode'", NULL};
    expect_run("periscope-render", posed, 1, no_node_said);
    const char *other[] = {truck, "--shadow", pao, "-o", a_png, NULL}, *other_said[] = {"made for another model", NULL};
    expect_run("periscope-render", other, 1, other_said);
    const char *missing[] = {"build", "no/such.gltf", "-o", pao, NULL}, *missing_said[] = {"no/such.gltf", NULL};
    expect_run("periscope-shadow", missing, 1, missing_said);
    /* an OBJ with groups: a box on a slab, shaded through the same importer */
    char obj[512];
    tmp_path(obj, sizeof obj, "boxes.obj");
    write_text(obj, "g slab\nv -2 0 -2\nv 2 0 -2\nv 2 0 2\nv -2 0 2\nv -2 -0.2 -2\nv 2 -0.2 -2\nv 2 -0.2 2\n"
                    "v -2 -0.2 2\nf 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
                    "g box\nv -0.5 0 -0.5\nv 0.5 0 -0.5\nv 0.5 1 -0.5\nv -0.5 1 -0.5\nv -0.5 0 0.5\nv 0.5 0 0.5\n"
                    "v 0.5 1 0.5\nv -0.5 1 0.5\nf 9 12 11 10\nf 13 14 15 16\nf 9 10 14 13\nf 10 11 15 14\n"
                    "f 11 12 16 15\nf 12 9 13 16\n");
    const char *obj_build[] = {"build", obj, "-o", pao, NULL}, *obj_built[] = {"16 surface samples", NULL};
    expect_run("periscope-shadow", obj_build, 0, obj_built);
    const char *obj_shaded[] = {obj, "--shadow", pao, "--dump-ao", csv, "--size", "160x120", "-o", a_png, NULL};
    expect_run("periscope-render", obj_shaded, 0, NULL);
    text = (char *)tsup_read_bytes(csv, &len);
    assert_non_null(text);
    lines = 0;
    for (size_t i = 0; i < len; i++)
        lines += text[i] == '\n';
    assert_int_equal(lines, 1 + 16);
    free(text);
    /* a patch model shaded, its tessellation dumped to a .obj: the output's name does not pick the OBJ mode */
    const char *torus_build[] = {"build", TSUP_DATA_AM "Torus.mdl", "--no-rest", "-o", pao, NULL};
    expect_run("periscope-shadow", torus_build, 0, NULL);
    const char *torus_shaded[] = {TSUP_DATA_AM "Torus.mdl", "--shadow", pao, "--dump-obj", obj, "--size", "160x120",
                                  "-o", a_png, NULL};
    expect_run("periscope-render", torus_shaded, 0, NULL);
    text = (char *)tsup_read_bytes(obj, &len);
    assert_non_null(text);
    assert_true(len > 40 && strncmp(text, "# Hash patch tessellation", 25) == 0);
    free(text);
    unlink(obj);
    unlink(pao);
    unlink(a_png);
    unlink(b_png);
    unlink(csv);
    unlink(json);
}

/* ---- contact sheets ---------------------------------------------------------------------------------------- */

static void render_frame(const char *png, const char *yaw)
{
    const char *a[] = {fx.pack[1], "-o", png, "--yaw", yaw, "--format", "xrgb8888", NULL};
    expect_run("periscope-render", a, 0, NULL);
}

static void test_contact(void **state)
{
    (void)state;
    need_packs();
    char f[3][512], sheet[512], err[512];
    static const char *const yaws[3] = {"0", "120", "240"};
    for (int i = 0; i < 3; i++) {
        char name[32];
        snprintf(name, sizeof name, "frame%d.png", i);
        tmp_path(f[i], sizeof f[i], name);
        render_frame(f[i], yaws[i]);
    }
    tmp_path(sheet, sizeof sheet, "sheet.png");

    /* Two 160x120 frames, 80 px thumbnails, 2 columns: 4 + 2 x (80 + 4) = 172 wide, 4 + 60 + 4 = 68 high. */
    const char *a2[] = {"-o", sheet, "--thumb-width", "80", "--columns", "2", f[0], f[1], NULL};
    expect_run("periscope-contact", a2, 0, NULL);
    psc_image_t s;
    if (psc_io_image_load(sheet, &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.width, 172);
    assert_int_equal(s.height, 68);
    /* The gaps are the background; each thumbnail pixel is the rounded mean of a 2x2 block of its frame. */
    assert_int_equal(s.xrgb[0], 0xFF202020u);
    assert_int_equal(s.xrgb[(size_t)30 * s.width + 85], 0xFF202020u);
    assert_int_equal(s.xrgb[(size_t)66 * s.width + 100], 0xFF202020u);
    for (int i = 0; i < 2; i++) {
        psc_image_t fr;
        if (psc_io_image_load(f[i], &fr, err, sizeof err) != 0)
            fail_msg("%s", err);
        assert_int_equal(fr.width, DISP_W);
        assert_int_equal(fr.height, DISP_H);
        for (uint32_t y = 0; y < 60; y++)
            for (uint32_t x = 0; x < 80; x++) {
                uint32_t want = 0xFF000000u;
                for (int c = 0; c < 3; c++) {
                    unsigned sum = 0;
                    for (uint32_t dy = 0; dy < 2; dy++)
                        for (uint32_t dx = 0; dx < 2; dx++)
                            sum += fr.xrgb[(2 * y + dy) * fr.width + 2 * x + dx] >> (8 * c) & 0xFFu;
                    want |= ((sum + 2) / 4) << (8 * c);
                }
                uint32_t got = s.xrgb[(4 + y) * s.width + 4 + (uint32_t)i * 84 + x];
                if (got != want)
                    fail_msg("sheet thumbnail %d pixel (%u, %u) is %08X, expected %08X", i, (unsigned)x,
                             (unsigned)y, (unsigned)got, (unsigned)want);
            }
        psc_io_image_free(&fr);
    }
    psc_io_image_free(&s);

    /* Three frames in two columns make two rows: 172 x (4 + 60 + 4 + 60 + 4). */
    const char *a3[] = {"-o", sheet, "--thumb-width", "80", "--columns", "2", f[0], f[1], f[2], NULL};
    expect_run("periscope-contact", a3, 0, NULL);
    if (psc_io_image_load(sheet, &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.width, 172);
    assert_int_equal(s.height, 132);
    psc_io_image_free(&s);

    /* The defaults: 320 px thumbnails, up to 4 columns: 4 + 2 x 324 = 652 by 4 + 240 + 4 = 248. */
    const char *ad[] = {"-o", sheet, f[0], f[1], NULL};
    expect_run("periscope-contact", ad, 0, NULL);
    if (psc_io_image_load(sheet, &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.width, 652);
    assert_int_equal(s.height, 248);
    psc_io_image_free(&s);

    unlink(sheet);
    for (int i = 0; i < 3; i++)
        unlink(f[i]);
}

static int teardown_all(void **state)
{
    (void)state;
    if (fx.ready) {
        unlink(fx.png);
        for (int f = 0; f < 3; f++)
            unlink(fx.pack[f]);
    }
    free(fx.img.xrgb);
    return 0;
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pack),
        cmocka_unit_test(test_render_matches_device_path),
        cmocka_unit_test(test_exit_codes),
        cmocka_unit_test(test_limits_and_interrupted_writes),
        cmocka_unit_test(test_partial_tiled),
        cmocka_unit_test(test_tile_codec),
        cmocka_unit_test(test_command_line_convention),
        cmocka_unit_test(test_patch_tools),
        cmocka_unit_test(test_gltf_tools),
        cmocka_unit_test(test_proxy_tools),
        cmocka_unit_test(test_contact),
    };
    return cmocka_run_group_tests(tests, NULL, teardown_all);
}
