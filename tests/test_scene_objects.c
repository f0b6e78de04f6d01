/* SPDX-License-Identifier: MIT */
/*
 * test_scene_objects.c - objects standing in a panorama on the device: a sim
 * board whose panorama scene (out/sample.pano) has Thom (out/thom.ppk, with
 * his shadow tables) standing in it, waving (board.conf's scene.ID.object).
 *  - The frames the device presents equal periscope-render's with --object
 *    for the same view and time, byte for byte (frames 0 and 30: 0 s and 1 s
 *    into his action; RGB565, dithered from 8 bits as the display does), both
 *    lighting him as the panorama does (no scene.ID.light, no --light).
 *  - The same in a tiled panorama (periscope-pack --tiled, RGB565), once its
 *    tiles are resident (frame 30, 1 s: the sim board's storage answers at
 *    once).
 *  - A tap on him follows his hotspot to his own scene; a tap on the sky
 *    beside him does not.
 *  - With title=Thom his name is drawn in a band just above his head, and
 *    nowhere else.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "app.h"
#include "psc_io_image.h"
#include "sim/psc_hal_sim.h"
#include "tsup_files.h"
#include "tsup_tool.h"

#define W 320u
#define H 240u

static char root[256], board_dir[300], cwd[256];
static char scene_file[1024];   /* the panorama the board shows (absolute) */
static const char *title = "";   /* " title=..." on Thom's line, or "" */

static void write_text(const char *path, const char *text)
{
    assert_int_equal(tsup_write_bytes(path, text, strlen(text)), 0);
}

static void write_board(void)
{
    char path[400], conf[4096];
    snprintf(path, sizeof path, "%s/board.conf", board_dir);
    snprintf(conf, sizeof conf,
             "display = sim\ndisplay_size = %ux%u\ndisplay_format = rgb565\nframe_rate = 30\n"
             "input = sim\nclock = sim\nwatchdog = sim\nquality = fixed\n"
             "scene.rocks = %s\nscene.rocks.view = 15 -8 70\n"
             "scene.thom = %s/out/thom.ppk\n"
             "scene.rocks.object = %s/out/thom.ppk yaw=15 pitch=-12 dist=3.2 action=Wave shadow=%s/out/thom.pao "
             "hotspot=thom%s\n",
             W, H, scene_file, cwd, cwd, cwd, title);
    write_text(path, conf);
}

static int setup(void **state)
{
    (void)state;
    const char *tmp = getenv("PSC_TEST_TMPDIR");
    snprintf(root, sizeof root, "%s/test_scene_objects_%ld", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    snprintf(board_dir, sizeof board_dir, "%s/rocks", root);
    mkdir(root, 0755);
    mkdir(board_dir, 0755);
    assert_non_null(getcwd(cwd, sizeof cwd));
    return 0;
}

/* The board with the sample panorama (a flat pack). */
static void sample_board(void)
{
    snprintf(scene_file, sizeof scene_file, "%s/out/sample.pano", cwd);
    write_board();
}

/* Run the board with tour text; the stats, and the output folder in out. */
static psc_app_stats_t run_board(const char *tour, int64_t every, char *out, size_t outlen)
{
    char tourf[400], err[1024];
    snprintf(tourf, sizeof tourf, "%s/tour.txt", root);
    write_text(tourf, tour);
    snprintf(out, outlen, "%s/out", root);
    psc_cli_options_t opt;
    memset(&opt, 0, sizeof opt);
    opt.board = "rocks";
    opt.boards_dir = root;
    opt.out_dir = out;
    opt.tour = tourf;
    opt.frames_every = every;
    opt.quiet = true;
    psc_app_t *app = NULL;
    if (psc_app_open(&opt, &app, err, sizeof err) != 0)
        fail_msg("psc_app_open: %s", err);
    psc_app_stats_t st;
    memset(&st, 0, sizeof st);
    if (psc_app_run(app, &st, err, sizeof err) != 0)
        fail_msg("psc_app_run: %s", err);
    psc_app_close(app);
    return st;
}

/* How many of the two frames' pixels differ (the first in *first). */
static unsigned count_differ(const psc_image_t *a, const psc_image_t *b, unsigned *first)
{
    unsigned n = 0;
    *first = W * H;
    for (unsigned i = 0; i < W * H; i++)
        if ((a->xrgb[i] & 0xFFFFFFu) != (b->xrgb[i] & 0xFFFFFFu) && n++ == 0)
            *first = i;
    return n;
}

static psc_image_t load_png(const char *path)
{
    psc_image_t im;
    char err[512];
    if (psc_io_image_load(path, &im, err, sizeof err) != 0)
        fail_msg("%s", err);
    return im;
}

/* periscope-render's frame of the same scene at t seconds into the action, and its ids. */
static void render_tool(double t, const char *png, const char *ids)
{
    char object[1024];
    snprintf(object, sizeof object, "out/thom.ppk,yaw=15,pitch=-12,dist=3.2,play=Wave,shadow=out/thom.pao,time=%.3f", t);
    const char *args[] = {scene_file, "--yaw", "15", "--pitch", "-8", "--hfov", "70", "--size", "320x240",
                          "--filter", "mip", "--object", object, "--ids", ids, "-o", png, NULL};
    tsup_tool_run_t r = tsup_run_tool("test_scene_objects", "periscope-render", args);
    if (r.status != 0)
        print_message("%s", r.output);
    assert_int_equal(r.status, 0);
    free(r.output);
}

/* The device's frame `frame` (30 a second) from the board's output folder out, in *dev, and periscope-render's of the
 * same moment, in *tool, written as NAME.png with its ids as NAME.pgm (the path in ids). */
static void frame_pair(const char *out, unsigned frame, const char *name, psc_image_t *dev, psc_image_t *tool,
                       char *ids, size_t idslen)
{
    char cap[600], png[600], file[64];
    assert_int_equal(psc_sim_capture_path(cap, sizeof cap, out, frame), 0);
    snprintf(file, sizeof file, "%s.png", name);
    tsup_tmp_path(png, sizeof png, "test_scene_objects", file);
    snprintf(file, sizeof file, "%s.pgm", name);
    tsup_tmp_path(ids, idslen, "test_scene_objects", file);
    render_tool(frame / 30.0, png, ids);
    *dev = load_png(cap);
    *tool = load_png(png);
    unlink(cap);
}

static void test_frames_equal_render(void **state)
{
    (void)state;
    sample_board();
    char out[400];
    psc_app_stats_t st = run_board("wait 1.05s\nend\n", 30, out, sizeof out);
    assert_true(st.frames >= 31);
    static const unsigned frames[2] = {0, 30};
    for (unsigned k = 0; k < 2; k++) {
        char ids[600];
        psc_image_t a, b;
        frame_pair(out, frames[k], "tool", &a, &b, ids, sizeof ids);
        assert_int_equal(a.width, W);
        assert_int_equal(b.width, W);
        unsigned first, differ = count_differ(&a, &b, &first);
        size_t len;
        uint8_t *pgm = tsup_read_bytes(ids, &len);
        unsigned thom = 0;
        for (size_t i = 17; i + 1 < len; i += 2)
            thom += pgm[i] << 8 | pgm[i + 1];
        free(pgm);
        print_message("  frame %u (%.1f s into the wave): %u of %u pixels differ from periscope-render's; Thom "
                      "covers %u\n", frames[k], frames[k] / 30.0, differ, W * H, thom);
        if (differ)
            print_message("  first at %u,%u: device %06x, tool %06x\n", first % W, first / W,
                          a.xrgb[first] & 0xFFFFFFu, b.xrgb[first] & 0xFFFFFFu);
        assert_int_equal(differ, 0);
        assert_true(thom > 500);   /* he is in the frame */
        psc_io_image_free(&a);
        psc_io_image_free(&b);
    }
}

static void test_tiled_frames_equal_render(void **state)
{
    (void)state;
    static char tiled[512];
    tsup_tmp_path(tiled, sizeof tiled, "test_scene_objects", "tiled.pano");
    const char *pack[] = {"assets/pannellum-examplepano.jpg", "-o", tiled, "--display", "320x240", "--format",
                          "rgb565", "--tiled", "--quiet", NULL};
    tsup_tool_run_t r = tsup_run_tool("test_scene_objects", "periscope-pack", pack);
    if (r.status != 0)
        print_message("%s", r.output);
    assert_int_equal(r.status, 0);
    free(r.output);
    if (tiled[0] == '/')
        snprintf(scene_file, sizeof scene_file, "%s", tiled);
    else
        snprintf(scene_file, sizeof scene_file, "%s/%s", cwd, tiled);
    write_board();
    char out[400], ids[600];
    psc_app_stats_t st = run_board("wait 1.05s\nend\n", 30, out, sizeof out);
    assert_true(st.frames >= 31);
    psc_image_t a, b;
    frame_pair(out, 30, "tiled", &a, &b, ids, sizeof ids);
    unsigned first, differ = count_differ(&a, &b, &first);
    (void)first;
    print_message("  a tiled panorama, frame 30: %u of %u pixels differ from periscope-render's\n", differ, W * H);
    assert_int_equal(differ, 0);
    psc_io_image_free(&a);
    psc_io_image_free(&b);
}

/* With title=Thom, the device draws his name above him: the frame differs from the tool's (which draws no overlay)
 * only in a band just above his head, centred on him. */
static void test_title_label(void **state)
{
    (void)state;
    title = " title=Thom";
    sample_board();
    title = "";
    char out[400], ids[600];
    psc_app_stats_t st = run_board("wait 0.2s\nend\n", 1, out, sizeof out);
    assert_true(st.frames >= 1);
    psc_image_t a, b;
    frame_pair(out, 0, "title", &a, &b, ids, sizeof ids);
    size_t len;
    uint8_t *pgm = tsup_read_bytes(ids, &len);
    assert_non_null(pgm);
    int top = H, lo = W, hi = -1;
    for (unsigned i = 0; i < W * H; i++)
        if (pgm[17 + 2 * i + 1] == 1) {
            top = (int)(i / W) < top ? (int)(i / W) : top;
            lo = (int)(i % W) < lo ? (int)(i % W) : lo;
            hi = (int)(i % W) > hi ? (int)(i % W) : hi;
        }
    unsigned differ = 0, outside = 0;
    for (unsigned i = 0; i < W * H; i++)
        if ((a.xrgb[i] & 0xFFFFFFu) != (b.xrgb[i] & 0xFFFFFFu)) {
            int x = (int)(i % W), y = (int)(i / W);
            differ++;
            outside += !(y < top && y > top - 30 && x > (lo + hi) / 2 - 40 && x < (lo + hi) / 2 + 40);
        }
    print_message("  title=Thom: %u pixels of a label above him (his top row %d), %u elsewhere\n", differ, top, outside);
    assert_true(differ > 50);
    assert_int_equal(outside, 0);
    free(pgm);
    psc_io_image_free(&a);
    psc_io_image_free(&b);
    sample_board();
}

/* A pixel of his (from periscope-render's ids, the pixel nearest their centroid) and one of the sky beside him. */
static void thom_pixels(int *tx, int *ty, int *sx, int *sy)
{
    char png[600], ids[600];
    tsup_tmp_path(png, sizeof png, "test_scene_objects", "tap.png");
    tsup_tmp_path(ids, sizeof ids, "test_scene_objects", "tap.pgm");
    render_tool(0.5, png, ids);
    size_t len;
    uint8_t *pgm = tsup_read_bytes(ids, &len);
    assert_non_null(pgm);
    double cx = 0, cy = 0, n = 0;
    int top = H;
    for (unsigned i = 0; i < W * H; i++)
        if (pgm[17 + 2 * i + 1] == 1) {
            cx += i % W, cy += i / W, n++;
            top = (int)(i / W) < top ? (int)(i / W) : top;
        }
    assert_true(n > 100);
    cx /= n, cy /= n;
    double best = 1e9;
    for (unsigned i = 0; i < W * H; i++)
        if (pgm[17 + 2 * i + 1] == 1 && hypot(i % W - cx, i / W - cy) < best)
            best = hypot(i % W - cx, i / W - cy), *tx = (int)(i % W), *ty = (int)(i / W);
    *sx = (int)lround(cx), *sy = top - 40;   /* well above his head: the sky */
    assert_true(*sy > 0 && pgm[17 + 2 * (*sy * W + *sx) + 1] == 0);
    free(pgm);
}

static void test_tap_follows(void **state)
{
    (void)state;
    sample_board();
    int tx = -1, ty = -1, sx = -1, sy = -1;
    thom_pixels(&tx, &ty, &sx, &sy);
    char tour[256], out[400];
    snprintf(tour, sizeof tour, "at 0.5s tap %d %d\nat 1s end\n", sx, sy);
    psc_app_stats_t st = run_board(tour, 0, out, sizeof out);
    print_message("  a tap on the sky at %d,%d: %u scene switches\n", sx, sy, st.scene_switches);
    assert_int_equal(st.scene_switches, 0);
    snprintf(tour, sizeof tour, "at 0.5s tap %d %d\nat 1s end\n", tx, ty);
    st = run_board(tour, 0, out, sizeof out);
    print_message("  a tap on Thom at %d,%d: %u scene switches, %u hotspots followed\n", tx, ty, st.scene_switches,
                  st.hotspot_follows);
    assert_int_equal(st.scene_switches, 1);
    assert_int_equal(st.hotspot_follows, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frames_equal_render),
        cmocka_unit_test(test_tiled_frames_equal_render),
        cmocka_unit_test(test_tap_follows),
        cmocka_unit_test(test_title_label),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
