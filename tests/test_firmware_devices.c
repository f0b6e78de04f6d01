/* SPDX-License-Identifier: MIT */
/*
 * test_firmware_devices.c - the firmware's side of the real devices: the
 * missing-device indication (state, text, the pixels drawn), the 5x7 font,
 * raw frame dumps, frame pacing with late frames skipped, and whole runs of
 * the device program: a camera scene fed by the sim camera (the frame shown
 * is exactly the camera's map through the scene pack's tables), and a board
 * whose V4L2 camera is absent (it runs, shows the pack's picture and says
 * NO CAMERA in the corner), and an RGB565 display with display_dither on (the
 * default: an 8-bit pack's frame drawn at 8 bits, then the 8 x 8 ordered
 * dither; an RGB565 pack's straight) and off (exactly the frame rendered
 * straight into RGB565, as before the key).
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "app.h"
#include "app_internal.h"
#include "board_config.h"
#include "board_file.h"
#include "camera_feed.h"
#include "cli.h"
#include "device_status.h"
#include "frame_dump.h"
#include "frame_pacer.h"
#include "psc_io_image.h"
#include "overlay_font.h"
#include "psc_io_pack_build.h"
#include "base/psc_pixel.h"
#include "psc_testsupport.h"
#include "tsup_pack.h"
#include "viewer/psc_viewer.h"
#include "sim/psc_hal_sim.h"
#include "tsup_files.h"
#include "psc_io_load.h"

/* ---- device status ------------------------------------------------------------- */

static void test_device_status_states(void **state)
{
    psc_device_status_t st;
    char lines[PSC_DEVICE_STATUS_MAX_LINES][PSC_DEVICE_STATUS_LINE_MAX], text[160];
    psc_hal_input_event_t leave = { .type = PSC_HAL_INPUT_DEVICE_LEAVE, .device = 2 };
    psc_hal_input_event_t arrive = { .type = PSC_HAL_INPUT_DEVICE_ARRIVE, .device = 2 };
    psc_hal_input_event_t button = { .type = PSC_HAL_INPUT_BUTTON_DOWN, .device = 2, .code = 1, .value = 1 };
    (void)state;

    psc_device_status_init(&st, true);
    assert_true(psc_device_status_all_present(&st));
    psc_device_status_text(&st, text, sizeof text);
    assert_string_equal(text, "all devices present");
    /* a camera that was never seen is absent; one that delivered, then failed, is lost */
    assert_true(psc_device_status_camera(&st, -ENODEV, false));
    assert_false(psc_device_status_camera(&st, -ENODEV, false));
    assert_int_equal(psc_device_status_lines(&st, lines), 1);
    assert_string_equal(lines[0], "NO CAMERA");
    assert_true(psc_device_status_camera(&st, 0, true));
    assert_false(psc_device_status_camera(&st, -EAGAIN, true));   /* no new frame is not a problem */
    assert_true(psc_device_status_all_present(&st));
    assert_true(psc_device_status_camera(&st, -ENODEV, true));
    assert_int_equal(psc_device_status_lines(&st, lines), 1);
    assert_string_equal(lines[0], "CAMERA LOST");
    /* input devices leave and come back; other events change nothing */
    assert_false(psc_device_status_input_event(&st, &button));
    assert_true(psc_device_status_input_event(&st, &leave));
    assert_false(psc_device_status_input_event(&st, &leave));
    assert_true(psc_device_status_input_failed(&st, true));
    assert_int_equal(psc_device_status_lines(&st, lines), 3);
    assert_string_equal(lines[1], "INPUT FAILED");
    assert_string_equal(lines[2], "INPUT 3 LOST"); /* device slot 2, counted from 1 */
    psc_device_status_text(&st, text, sizeof text);
    assert_string_equal(text, "camera lost, input failed, input 3 lost");
    leave.device = 5;
    psc_device_status_input_event(&st, &leave);
    assert_int_equal(psc_device_status_lines(&st, lines), 3);
    assert_string_equal(lines[2], "2 INPUTS LOST");
    assert_true(psc_device_status_input_event(&st, &arrive));
    assert_true(psc_device_status_input_failed(&st, false));
    leave.device = 200;   /* out of range: ignored */
    assert_false(psc_device_status_input_event(&st, &leave));
    assert_int_equal(psc_device_status_lines(&st, lines), 2);
    assert_string_equal(lines[1], "INPUT 6 LOST");
    /* a board without a camera never reports one */
    psc_device_status_init(&st, false);
    assert_false(psc_device_status_camera(&st, -ENODEV, false));
    assert_true(psc_device_status_all_present(&st));
}

static void test_device_status_drawing(void **state)
{
    enum { W = 640, H = 480 };
    uint16_t *px = malloc((size_t)W * H * 2);
    psc_surface_t s = { W, H, W * 2, PSC_PIX_RGB565, px };
    psc_device_status_t st;
    const uint16_t bg = 0x1234, amber = psc_xrgb_to_rgb565(0xFFC000u);
    uint32_t changed = 0, amber_count = 0;
    (void)state;

    for (size_t i = 0; i < (size_t)W * H; i++)
        px[i] = bg;
    psc_device_status_init(&st, true);
    psc_device_status_draw(&st, &s);   /* everything present: not a pixel changes */
    for (size_t i = 0; i < (size_t)W * H; i++)
        changed += px[i] != bg;
    assert_int_equal(changed, 0);

    psc_device_status_camera(&st, -ENODEV, true);
    psc_device_status_draw(&st, &s);
    /* scale 480/240 = 2: "CAMERA LOST" is 11 cells of 12 px = 132, box 140 x 22
     * at 8 px from the top and right edges: x 492..631, y 8..29 */
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            uint16_t p = px[y * W + x];
            bool inside = x >= 492 && x < 632 && y >= 8 && y < 30;
            if (!inside)
                assert_int_equal(p, bg);
            else
                assert_true(p == 0 || p == amber);
            amber_count += p == amber;
        }
    /* 'C' starts at (492 + 4 + 2, 8 + 4): its top row ".###." lights x 500..505 */
    assert_int_equal(px[12 * W + 498], 0);
    assert_int_equal(px[12 * W + 500], amber);
    assert_int_equal(px[13 * W + 505], amber);
    assert_int_equal(px[12 * W + 506], 0);
    /* lit pixels: 4 per font pixel, font pixels counted from the glyphs */
    uint32_t font_pixels = 0;
    for (const char *c = "CAMERA LOST"; *c; c++)
        for (unsigned r = 0; r < PSC_FONT_GLYPH_H; r++)
            font_pixels += (uint32_t)__builtin_popcount(psc_font_glyph(*c)[r]);
    assert_int_equal(amber_count, 4 * font_pixels);

    /* a tiny XRGB surface: clipped, never written outside */
    uint32_t small[20 * 10 + 20];
    for (unsigned i = 0; i < 220; i++)
        small[i] = 0xDEADBEEFu;
    psc_surface_t t = { 20, 10, 20 * 4, PSC_PIX_XRGB8888, small };
    psc_device_status_draw(&st, &t);
    for (unsigned i = 200; i < 220; i++)
        assert_int_equal(small[i], 0xDEADBEEFu);
    assert_int_equal(small[4 * 20 + 0], 0xFF000000u);   /* the box reaches the left edge, clipped */
    free(px);
}

static void test_font(void **state)
{
    const char *all = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 -:./!?,'&()";
    (void)state;

    /* every glyph distinct, lower case drawn as upper, unknown as '?' */
    for (const char *a = all; *a; a++)
        for (const char *b = a + 1; *b; b++)
            assert_memory_not_equal(psc_font_glyph(*a), psc_font_glyph(*b), PSC_FONT_GLYPH_H);
    assert_ptr_equal(psc_font_glyph('q'), psc_font_glyph('Q'));
    assert_ptr_equal(psc_font_glyph('#'), psc_font_glyph('?'));
    assert_ptr_equal(psc_font_glyph('\x7f'), psc_font_glyph('?'));
    for (const char *a = all; *a; a++)
        for (unsigned r = 0; r < PSC_FONT_GLYPH_H; r++)
            assert_true(psc_font_glyph(*a)[r] < 32u);
    assert_int_equal(psc_font_text_width("NO CAMERA", 3), 9 * 6 * 3);
}

/* ---- frame dumps and pacing ------------------------------------------------------- */

static void test_frame_dump(void **state)
{
    uint16_t px[2 * 4] = { 0x0102, 0x0304, 0x0506, 0xFFFF, 0x0708, 0x090A, 0x0B0C, 0xFFFF };
    psc_surface_t s = { 3, 2, 8, PSC_PIX_RGB565, px };
    char path[400], err[300];
    const char *p;
    uint32_t frame;
    size_t len;
    uint8_t *data;
    (void)state;

    tsup_tmp_path(path, sizeof path, "dump", "frame.raw");
    assert_int_equal(psc_frame_dump_write(path, &s, err, sizeof err), 0);
    data = tsup_read_bytes(path, &len);
    assert_non_null(data);
    assert_int_equal(len, 12);   /* stride padding dropped */
    const uint8_t want[12] = { 2, 1, 4, 3, 6, 5, 8, 7, 10, 9, 12, 11 };
    assert_memory_equal(data, want, 12);
    free(data);
    unlink(path);
    assert_int_equal(psc_frame_dump_write("/nonexistent-dir/frame.raw", &s, err, sizeof err), -1);
    assert_non_null(strstr(err, "/nonexistent-dir/frame.raw: cannot create a temporary file beside it"));

    assert_int_equal(psc_frame_dump_parse("30:/tmp/a.raw", &frame, &p), 0);
    assert_int_equal(frame, 30);
    assert_string_equal(p, "/tmp/a.raw");
    assert_int_equal(psc_frame_dump_parse("0:x", &frame, &p), 0);
    assert_int_equal(frame, 0);
    assert_int_equal(psc_frame_dump_parse("30:", &frame, &p), -1);
    assert_int_equal(psc_frame_dump_parse(":x", &frame, &p), -1);
    assert_int_equal(psc_frame_dump_parse("3a:x", &frame, &p), -1);
    assert_int_equal(psc_frame_dump_parse("99999999999:x", &frame, &p), -1);

    /* on the command line, up to 8 of them */
    psc_cli_options_t o;
    char *argv[] = { "periscope", "--board", "sim", "--dump-frame", "5:/tmp/f5.raw", "--dump-frame", "9:/tmp/f9.raw",
                     NULL };
    assert_int_equal(psc_cli_parse(7, argv, &o, err, sizeof err), 0);
    assert_int_equal(o.dump_count, 2);
    assert_int_equal(o.dumps[1].frame, 9);
    assert_string_equal(o.dumps[1].path, "/tmp/f9.raw");
    char *bad[] = { "periscope", "--board", "sim", "--dump-frame", "five:/tmp/f.raw", NULL };
    assert_int_equal(psc_cli_parse(5, bad, &o, err, sizeof err), -1);
    assert_non_null(strstr(err, "--dump-frame needs FRAME:PATH"));
}

static void test_frame_pacer(void **state)
{
    psc_frame_pacer_t p;
    (void)state;

    psc_frame_pacer_init(&p, 1000, 30000);
    assert_int_equal(psc_frame_pacer_next(&p, 1000), 1000 + 33333);
    assert_int_equal(psc_frame_pacer_next(&p, 1000 + 33333), 1000 + 66666);
    assert_int_equal(psc_frame_pacer_next(&p, 1000 + 70000), 1000 + 100000);   /* a little late: no skip */
    assert_int_equal(p.skipped, 0);
    /* finished at 0.2 s, when frame 4 was due at 0.133 s: resume at 0.2333 s */
    assert_int_equal(psc_frame_pacer_next(&p, 1000 + 200000), 1000 + 233333);
    assert_int_equal(p.skipped, 3);
    /* exactly on a boundary while late: the next one */
    assert_int_equal(psc_frame_pacer_next(&p, 1000 + 300000), 1000 + 333333);
    assert_int_equal(p.skipped, 5);
    /* 30 fps stays exact over a long run (no accumulated rounding) */
    psc_frame_pacer_init(&p, 0, 30000);
    uint64_t t = 0;
    for (unsigned i = 0; i < 108000; i++)
        t = psc_frame_pacer_next(&p, t);
    assert_int_equal(t, 3600000000u);
    assert_int_equal(p.skipped, 0);
}

/* ---- whole runs ---------------------------------------------------------------- */

static char root[300];

static void write_text(const char *path, const char *text)
{
    assert_int_equal(tsup_write_bytes(path, text, strlen(text)), 0);
}

/* A small pack for a 160x120 display, of the smooth synthetic scene. */
static void make_pack(const char *path)
{
    char err[300];
    if (tsup_write_synth_pack(path, 128, 64, 160, 120, 32, 128, err, sizeof err) != 0)
        fail_msg("pack: %s", err);
}

/* Run board NAME (in root) for frames frames, dumping frame dump_at. */
static void run_board(const char *name, uint32_t frames, uint32_t dump_at, const char *dump_path)
{
    psc_cli_options_t opt;
    psc_app_stats_t st;
    psc_app_t *app = NULL;
    char err[600];

    memset(&opt, 0, sizeof opt);
    opt.board = name;
    opt.boards_dir = root;
    opt.frames_every = 0;
    opt.max_frames = frames;
    opt.quiet = true;
    opt.dumps[0] = (psc_cli_dump_t){ dump_at, dump_path };
    opt.dump_count = 1;
    if (psc_app_open(&opt, &app, err, sizeof err) != 0)
        fail_msg("psc_app_open %s: %s", name, err);
    if (psc_app_run(app, &st, err, sizeof err) != 0)
        fail_msg("psc_app_run %s: %s", name, err);
    assert_int_equal(st.frames, frames);
    psc_app_close(app);
}

/* The frame the viewer makes of map with the pack's tables at its default view, calm quality, in format fmt. */
static void *expected_frame_as(const psc_pack_t *pk, const psc_envmap_t *map, psc_pixfmt_t fmt)
{
    psc_viewer_t v;
    size_t ws_size = psc_viewer_workspace_size(160, 120, map);
    void *ws = aligned_alloc(64, (ws_size + 63) & ~(size_t)63);
    void *px = malloc(160 * 120 * 4);
    psc_surface_t out = { 160, 120, 160 * psc_pixfmt_bytes(fmt), fmt, px };
    psc_view_t view = { .yaw = pk->default_yaw, .pitch = pk->default_pitch, .hfov = pk->default_hfov,
                        .filter = PSC_FILTER_MIP, .span_log2 = 2 };

    assert_int_equal(psc_viewer_init(&v, map, pk->luts, pk->lut_count, 160, 120, ws, ws_size), PSC_OK);
    psc_viewer_clamp(&v, &view, pk->hfov_min);
    assert_int_equal(psc_viewer_render(&v, &view, &out), PSC_OK);
    free(ws);
    return px;
}

static uint32_t *expected_frame(const psc_pack_t *pk, const psc_envmap_t *map)
{
    return expected_frame_as(pk, map, PSC_PIX_XRGB8888);
}

static void test_camera_scene_run(void **state)
{
    char dir[400], pack[400], conf[1200], path[500], dump[400], tour[400], err[300];
    psc_io_pack_t pf;
    size_t len;
    uint8_t *got;
    (void)state;

    snprintf(pack, sizeof pack, "%s/cam.pano", root);
    make_pack(pack);
    assert_int_equal(psc_io_pack_load(pack, &pf, err, sizeof err), 0);

    /* the sim camera (a test pattern at 15 Hz) as the live map of the camera
     * scene; a tour that only waits, so nothing moves */
    snprintf(tour, sizeof tour, "%s/still.txt", root);
    write_text(tour, "wait 10s\nend\n");
    snprintf(dir, sizeof dir, "%s/camboard", root);
    mkdir(dir, 0755);
    snprintf(path, sizeof path, "%s/board.conf", dir);
    snprintf(conf, sizeof conf,
             "display = sim\ndisplay_size = 160x120\ndisplay_format = xrgb8888\nframe_rate = 30\n"
             "input = sim\ntour = %s\nclock = sim\ncamera = sim\ncamera_size = 256x128\ncamera_rate = 15\n"
             "camera_scene = %s\nquality = fixed\n", tour, pack);
    write_text(path, conf);
    snprintf(dump, sizeof dump, "%s/cam9.raw", root);
    run_board("camboard", 10, 9, dump);

    /* frame 9 is drawn at 9/30 s: the camera's frame 4 (15 Hz) through the pack's tables */
    uint32_t *map = malloc(256 * 128 * 4);
    psc_sim_pattern_fill(map, 256 * 4, 256, 128, PSC_PIX_XRGB8888, 4);
    psc_envmap_t cam = psc_camera_feed_map_shape(256, 128, PSC_PIX_XRGB8888);
    cam.pixels = map;
    uint32_t *want = expected_frame(&pf.pack, &cam);
    got = tsup_read_bytes(dump, &len);
    assert_non_null(got);
    assert_int_equal(len, 160 * 120 * 4);
    assert_memory_equal(got, want, len);
    /* and it is not the pack's own picture */
    uint32_t *own = expected_frame(&pf.pack, &pf.pack.map);
    assert_memory_not_equal(got, own, len);
    free(own);
    free(want);
    free(got);
    free(map);
    unlink(dump);
    psc_io_pack_free(&pf);
}

static void test_absent_camera_run(void **state)
{
    char dir[400], pack[400], conf[1200], path[500], dump[400], tour[400], err[300];
    psc_io_pack_t pf;
    size_t len;
    uint32_t *got, *want;
    (void)state;

    snprintf(pack, sizeof pack, "%s/cam.pano", root);
    assert_int_equal(psc_io_pack_load(pack, &pf, err, sizeof err), 0);
    snprintf(tour, sizeof tour, "%s/still.txt", root);
    snprintf(dir, sizeof dir, "%s/nocam", root);
    mkdir(dir, 0755);
    snprintf(path, sizeof path, "%s/board.conf", dir);
    snprintf(conf, sizeof conf,
             "display = sim\ndisplay_size = 160x120\ndisplay_format = xrgb8888\nframe_rate = 30\n"
             "input = sim\ntour = %s\nclock = sim\ncamera = v4l2\ncamera.device = /dev/periscope-no-such-video\n"
             "camera_size = 256x128\ncamera_scene = %s\nquality = fixed\n", tour, pack);
    write_text(path, conf);
    snprintf(dump, sizeof dump, "%s/nocam.raw", root);
    run_board("nocam", 40, 39, dump);   /* 1.3 s: the camera is retried and still absent */

    /* the pack's own picture, with NO CAMERA in the top-right corner */
    want = expected_frame(&pf.pack, &pf.pack.map);
    psc_device_status_t st;
    psc_device_status_init(&st, true);
    psc_device_status_camera(&st, -ENODEV, false);
    psc_device_status_draw(&st, &(psc_surface_t){ 160, 120, 160 * 4, PSC_PIX_XRGB8888, want });
    got = (uint32_t *)(void *)tsup_read_bytes(dump, &len);
    assert_non_null(got);
    assert_int_equal(len, 160 * 120 * 4);
    assert_memory_equal(got, want, len);
    assert_int_equal(got[10 * 160 + 100], 0xFF000000u);   /* inside the box */
    free(got);
    free(want);
    unlink(dump);
    psc_io_pack_free(&pf);

    /* camera_scene without a camera is a board mistake */
    snprintf(conf, sizeof conf, "display = sim\ndisplay_size = 160x120\ninput = sim\nclock = sim\ncamera_scene = %s\n",
             pack);
    write_text(path, conf);
    psc_cli_options_t opt = { .board = "nocam", .boards_dir = root, .frames_every = -1, .quiet = true };
    psc_app_t *app = NULL;
    assert_int_not_equal(psc_app_open(&opt, &app, err, sizeof err), 0);
    assert_non_null(strstr(err, "camera_scene is set but camera = none"));
}

/* A pack of the synthetic scene for a 160x120 display whose map is in format fmt (tsup_write_synth_pack's, RGB565). */
static void make_pack_as(const char *path, psc_pixfmt_t fmt)
{
    psc_image_t img = { 128, 64, malloc(128 * 64 * 4) };
    psc_pack_options_t o;
    uint8_t *buf;
    size_t len;
    char err[300];

    assert_non_null(img.xrgb);
    for (uint32_t y = 0; y < 64; y++)
        for (uint32_t x = 0; x < 128; x++) {
            double rgb[3];
            tsup_synth_color(((x + 0.5) / 128 - 0.5) * 2 * TSUP_PI, (0.5 - (y + 0.5) / 64) * TSUP_PI, rgb);
            img.xrgb[y * 128 + x] = 0xFF000000u | ((uint32_t)rgb[0] << 16) | ((uint32_t)rgb[1] << 8) | (uint32_t)rgb[2];
        }
    psc_io_pack_options_default(&o);
    o.format = fmt;
    o.display_width = 160;
    o.display_height = 120;
    o.lut_rows = 32;
    o.lut_cols = 128;
    if (psc_io_pack_build(&img, &o, &buf, &len, err, sizeof err) != 0)
        fail_msg("pack: %s", err);
    assert_int_equal(tsup_write_bytes(path, buf, len), 0);
    free(buf);
    free(img.xrgb);
}

/*
 * An RGB565 display (the default format), settled (mip blends texels into 8-bit values), with display_dither
 * absent (on), ordered and none:
 *  - an XRGB8888 pack: on, the viewer's XRGB8888 frame through psc_dither_row_rgb565, the matrix fixed to the
 *    screen; none, exactly what the viewer renders into RGB565 (the frames before the key);
 *  - an RGB565 pack (the scene fits RGB565): drawn straight into RGB565 whatever the key, the frames before it.
 */
static void test_display_dither_run(void **state)
{
    char dir[400], pack[400], conf[1200], path[500], dump[400], tour[400], err[300];
    static psc_dither_565_t t;
    static uint16_t ordered[160 * 120];
    size_t len;
    (void)state;

    psc_dither_565_init(&t);
    snprintf(tour, sizeof tour, "%s/dither-still.txt", root);
    write_text(tour, "wait 10s\nend\n");
    for (unsigned f = 0; f < 2; f++) {
        psc_pixfmt_t fmt = f == 0 ? PSC_PIX_XRGB8888 : PSC_PIX_RGB565;
        psc_io_pack_t pf;
        snprintf(pack, sizeof pack, "%s/dither%u.pano", root, f);
        make_pack_as(pack, fmt);
        assert_int_equal(psc_io_pack_load(pack, &pf, err, sizeof err), 0);
        assert_int_equal(pf.pack.map.format, fmt);
        uint16_t *none = expected_frame_as(&pf.pack, &pf.pack.map, PSC_PIX_RGB565);
        uint32_t *full = expected_frame(&pf.pack, &pf.pack.map);
        for (unsigned y = 0; y < 120; y++)
            psc_dither_row_rgb565(&t, PSC_DITHER_ORDERED, full + y * 160, 160, 0, y, ordered + y * 160);
        assert_memory_not_equal(none, ordered, sizeof ordered);
        for (unsigned k = 0; k < 3; k++) {
            static const char *const key[] = { "", "display_dither = ordered\n", "display_dither = none\n" };
            snprintf(dir, sizeof dir, "%s/dither%u%u", root, f, k);
            mkdir(dir, 0755);
            snprintf(path, sizeof path, "%s/board.conf", dir);
            snprintf(conf, sizeof conf, "display = sim\ndisplay_size = 160x120\nframe_rate = 30\ninput = sim\n"
                     "tour = %s\nclock = sim\nscene = %s\nquality = fixed\n%s", tour, pack, key[k]);
            write_text(path, conf);
            snprintf(dump, sizeof dump, "%s/dither%u%u.raw", root, f, k);
            snprintf(path, sizeof path, "dither%u%u", f, k);
            run_board(path, 3, 2, dump);
            uint8_t *got = tsup_read_bytes(dump, &len);
            assert_non_null(got);
            assert_int_equal(len, sizeof ordered);
            assert_memory_equal(got, f == 0 && k < 2 ? ordered : none, len);
            free(got);
            unlink(dump);
        }
        free(none);
        free(full);
        psc_io_pack_free(&pf);
    }
}

/* root/NAME/board.conf: a 160x120 sim display with the sim tour and clock showing pack (and extra lines). */
static void write_sim_board(const char *name, const char *pack, const char *tour, const char *extra)
{
    char dir[400], path[500], conf[1400];

    snprintf(dir, sizeof dir, "%s/%s", root, name);
    mkdir(dir, 0755);
    snprintf(path, sizeof path, "%s/board.conf", dir);
    snprintf(conf, sizeof conf, "display = sim\ndisplay_size = 160x120\ninput = sim\ntour = %s\nclock = sim\n"
             "scene = %s\n%s", tour, pack, extra);
    write_text(path, conf);
}

static void test_stop_request(void **state)
{
    char pack[400], tour[400], err[300];
    psc_app_stats_t st;
    psc_app_t *app = NULL;
    (void)state;

    snprintf(pack, sizeof pack, "%s/cam.pano", root);
    snprintf(tour, sizeof tour, "%s/still.txt", root);
    write_sim_board("stop", pack, tour, "");
    psc_cli_options_t opt = { .board = "stop", .boards_dir = root, .frames_every = -1, .quiet = true };
    assert_int_equal(psc_app_open(&opt, &app, err, sizeof err), 0);
    psc_app_request_stop();   /* what SIGTERM does */
    assert_int_equal(psc_app_run(app, &st, err, sizeof err), 0);
    assert_int_equal(st.frames, 0);
    opt.max_frames = 3;       /* the request was used up: the next run runs */
    psc_app_close(app);
    assert_int_equal(psc_app_open(&opt, &app, err, sizeof err), 0);
    assert_int_equal(psc_app_run(app, &st, err, sizeof err), 0);
    assert_int_equal(st.frames, 3);
    psc_app_close(app);
}

/*
 * --dump-frame on a full disk (issue 16: it printed an error, exited 0 and
 * left a truncated file): a file-size limit makes every write past 4 KiB fail
 * with EFBIG, as a full disk fails with ENOSPC. The run ends non-zero naming
 * the dump and the reason, the earlier dump at that path is untouched, and no
 * temporary is left beside it.
 */
static void test_frame_dump_full_disk(void **state)
{
    char dir[400], pack[400], tour[400], dump[500], err[600];
    struct rlimit old, small;
    psc_app_stats_t st;
    psc_app_t *app = NULL;
    size_t len;
    uint8_t *data;
    (void)state;

    snprintf(pack, sizeof pack, "%s/cam.pano", root);
    snprintf(tour, sizeof tour, "%s/still.txt", root);
    write_sim_board("fulldisk", pack, tour, "");
    snprintf(dir, sizeof dir, "%s/fulldisk", root);
    snprintf(dump, sizeof dump, "%s/frame2.raw", dir);
    write_text(dump, "the dump of an earlier run");

    psc_cli_options_t opt = { .board = "fulldisk", .boards_dir = root, .frames_every = -1, .quiet = true,
                              .max_frames = 4, .dump_count = 1 };
    opt.dumps[0] = (psc_cli_dump_t){ 2, dump };
    assert_int_equal(psc_app_open(&opt, &app, err, sizeof err), 0);
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    small = old;
    small.rlim_cur = 4096;
    signal(SIGXFSZ, SIG_IGN);   /* EFBIG instead of the signal */
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
    int rc = psc_app_run(app, &st, err, sizeof err);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
    signal(SIGXFSZ, SIG_DFL);
    psc_app_close(app);
    printf("  %s\n", err);
    assert_int_equal(rc, -1);
    assert_int_equal(st.frames, 4);   /* the kiosk kept showing */
    assert_non_null(strstr(err, "a frame dump failed: "));
    assert_non_null(strstr(err, dump));
    assert_non_null(strstr(err, "File too large"));
    data = tsup_read_bytes(dump, &len);
    assert_non_null(data);
    assert_int_equal(len, strlen("the dump of an earlier run"));
    free(data);
    assert_int_equal(tsup_count_names(dir, "", ".tmp"), 0);

    /* with room, the same run succeeds and replaces it: 160 x 120 RGB565 */
    assert_int_equal(psc_app_open(&opt, &app, err, sizeof err), 0);
    assert_int_equal(psc_app_run(app, &st, err, sizeof err), 0);
    psc_app_close(app);
    data = tsup_read_bytes(dump, &len);
    assert_non_null(data);
    assert_int_equal(len, 160 * 120 * 2);
    free(data);
    assert_int_equal(tsup_count_names(dir, "", ".tmp"), 0);
}

/* Dump frame 0 of the next run to path (the app's own list: app_internal.h). */
static void app_set_dump(psc_app_t *app, const char *path)
{
    app->dumps[0] = (psc_cli_dump_t){ 0, path };
    app->dump_count = 1;
}

/* Run app for one frame, dumping it to dump. */
static void run_one_frame(psc_app_t *app, const char *dump, psc_app_stats_t *st)
{
    char err[600];
    app_set_dump(app, dump);
    if (psc_app_run(app, st, err, sizeof err) != 0)
        fail_msg("psc_app_run: %s", err);
    assert_int_equal(st->frames, 1);
}

/*
 * SIGHUP and SIGUSR1 (issue 16: both killed the program without its summary):
 * the reload loads the board's scenes beside the current ones while frames go
 * on (every run below draws its one frame), and the new pack is on screen once
 * it has taken over - the same frame a fresh start on it draws; a corrupt pack
 * is refused and the scene before it stays; a status request is answered with
 * one line.
 */
static void test_reload_and_status(void **state)
{
    char dir[400], pack[500], tour[400], err[600];
    char dump_a[500], dump_b[500], dump_fresh[500], dump_kept[500];
    psc_app_stats_t st;
    psc_app_t *app = NULL;
    (void)state;

    snprintf(tour, sizeof tour, "%s/still.txt", root);
    snprintf(dir, sizeof dir, "%s/reload", root);
    mkdir(dir, 0755);
    snprintf(pack, sizeof pack, "%s/scene.pano", dir);
    if (tsup_write_synth_pack(pack, 128, 64, 160, 120, 32, 128, err, sizeof err) != 0)
        fail_msg("pack: %s", err);
    write_sim_board("reload", pack, tour, "quality = fixed\n");
    snprintf(dump_a, sizeof dump_a, "%s/a.raw", dir);
    snprintf(dump_b, sizeof dump_b, "%s/b.raw", dir);
    snprintf(dump_fresh, sizeof dump_fresh, "%s/fresh.raw", dir);
    snprintf(dump_kept, sizeof dump_kept, "%s/kept.raw", dir);

    psc_cli_options_t opt = { .board = "reload", .boards_dir = root, .frames_every = -1, .quiet = true,
                              .max_frames = 1 };
    assert_int_equal(psc_app_open(&opt, &app, err, sizeof err), 0);
    run_one_frame(app, dump_a, &st);

    /* the author replaces the pack (a finer map of the same scene) and sends SIGHUP */
    if (tsup_write_synth_pack(pack, 256, 128, 160, 120, 32, 128, err, sizeof err) != 0)
        fail_msg("pack: %s", err);
    psc_app_request_reload();
    unsigned runs = 0;
    do {   /* the load runs on its own thread: a bounded wait, frame by frame */
        run_one_frame(app, dump_b, &st);
        if (st.reloads == 0)
            usleep(1000);
    } while (st.reloads == 0 && ++runs < 20000);
    printf("  the reload took over after %u one-frame runs\n", runs + 1);
    assert_int_equal(st.reloads, 1);
    assert_int_equal(st.reload_failures, 0);
    assert_false(tsup_same_file(dump_a, dump_b));

    /* a corrupt pack: refused, the scene on screen stays */
    write_text(pack, "not a pack any more");
    psc_app_request_reload();
    runs = 0;
    do {
        run_one_frame(app, dump_kept, &st);
        if (st.reload_failures == 0)
            usleep(1000);
    } while (st.reload_failures == 0 && ++runs < 20000);
    assert_int_equal(st.reload_failures, 1);
    assert_int_equal(st.reloads, 1);   /* the one before */
    assert_true(tsup_same_file(dump_b, dump_kept));

    /* status: one line, the frames go on */
    psc_app_request_status();
    run_one_frame(app, dump_kept, &st);
    assert_int_equal(st.status_reports, 1);
    psc_app_close(app);

    /* what a fresh start on the finer pack draws: the reloaded frame */
    if (tsup_write_synth_pack(pack, 256, 128, 160, 120, 32, 128, err, sizeof err) != 0)
        fail_msg("pack: %s", err);
    assert_int_equal(psc_app_open(&opt, &app, err, sizeof err), 0);
    run_one_frame(app, dump_fresh, &st);
    psc_app_close(app);
    assert_true(tsup_same_file(dump_b, dump_fresh));
}

/* Wait (up to 30 s) until the file at path contains text. */
static bool wait_for_text(const char *path, const char *text)
{
    for (int i = 0; i < 3000; i++) {
        size_t len;
        char *got = (char *)tsup_read_bytes(path, &len);
        bool found = got && strstr(got, text) != NULL;
        free(got);
        if (found)
            return true;
        usleep(10000);
    }
    return false;
}

/*
 * The same through real signals to the device program: SIGUSR1 logs a status
 * line, SIGHUP reloads, and SIGTERM still ends it with its summary and exit 0.
 */
static void test_signals_to_the_program(void **state)
{
    char exe[400], dir[400], pack[500], tour[400], log[500], err[300];
    const char *bin = getenv("PSC_BIN_DIR");
    (void)state;

    snprintf(exe, sizeof exe, "%s/periscope", bin && *bin ? bin : "build/bin");
    if (access(exe, X_OK) != 0)
        fail_msg("%s is not there: make all first", exe);
    snprintf(tour, sizeof tour, "%s/long.txt", root);
    write_text(tour, "wait 80000s\nend\n");
    snprintf(dir, sizeof dir, "%s/signals", root);
    mkdir(dir, 0755);
    snprintf(pack, sizeof pack, "%s/scene.pano", dir);
    if (tsup_write_synth_pack(pack, 128, 64, 160, 120, 32, 128, err, sizeof err) != 0)
        fail_msg("pack: %s", err);
    write_sim_board("signals", pack, tour, "");
    snprintf(log, sizeof log, "%s/periscope.log", dir);

    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd < 0 || dup2(fd, 1) < 0 || dup2(fd, 2) < 0)
            _exit(126);
        execl(exe, exe, "--board", "signals", "--boards-dir", root, "--frames-every", "0", (char *)NULL);
        _exit(127);
    }
    if (!wait_for_text(log, "frame")) {   /* running (a failure must not leave it running) */
        kill(pid, SIGKILL);
        waitpid(pid, NULL, 0);
        fail_msg("the program did not start; see %s", log);
    }
    kill(pid, SIGUSR1);
    bool status = wait_for_text(log, "status: scene 1 of 1");
    kill(pid, SIGHUP);
    bool reload = wait_for_text(log, "reload: 1 scene loaded again");
    kill(pid, SIGTERM);
    int ws;
    while (waitpid(pid, &ws, 0) < 0)
        assert_int_equal(errno, EINTR);
    size_t len;
    char *out = (char *)tsup_read_bytes(log, &len);
    assert_non_null(out);
    if (!status || !reload || !WIFEXITED(ws) || WEXITSTATUS(ws) != 0 || !strstr(out, "frames rendered") ||
        !strstr(out, "reloads (SIGHUP): 1 taken, 0 refused"))
        fail_msg("status %d reload %d, exit 0x%x; the program said:\n%s", status, reload, ws, out);
    free(out);
}

/* What scripts/board-key prints for a key of a board (the build's reader). */
static void board_key_output(const char *board, const char *key, char *out, size_t len)
{
    char cmd[300];
    FILE *p;

    snprintf(cmd, sizeof cmd, "sh scripts/board-key %s %s", board, key);
    p = popen(cmd, "r");
    assert_non_null(p);
    out[0] = '\0';
    if (fgets(out, (int)len, p) == NULL)
        out[0] = '\0';
    out[strcspn(out, "\n")] = '\0';
    assert_int_equal(pclose(p), 0);
}

/* Every board file in boards/ (found by walking the folder, run from the
 * repository root) is read the way its builds read it: a board the device
 * runs parses with the device's parser, and the build's reader
 * (scripts/board-key) agrees with it; a core-only board (a microcontroller:
 * no device program) is well-formed for the build's reader. */
static void test_board_files(void **state)
{
    DIR *dir = opendir("boards");
    struct dirent *e;
    unsigned device_boards = 0, core_boards = 0;
    (void)state;

    assert_non_null(dir);
    while ((e = readdir(dir)) != NULL) {
        char path[300], err[400], build[64], size[64], want[64];
        psc_board_config_t cfg;
        struct stat st;

        snprintf(path, sizeof path, "boards/%s/board.conf", e->d_name);
        if (e->d_name[0] == '.' || stat(path, &st) != 0)
            continue;
        int has_build = psc_board_file_value(path, "build", build, sizeof build, err, sizeof err);
        if (has_build < 0)
            fail_msg("%s", err);
        board_key_output(e->d_name, "display_size", size, sizeof size);
        if (has_build == 1 && strcmp(build, "core-only") == 0) {
            core_boards++;
            continue;
        }
        if (psc_board_config_load(path, &cfg, err, sizeof err) != 0)
            fail_msg("%s", err);
        snprintf(want, sizeof want, "%ux%u", (unsigned)cfg.display_width, (unsigned)cfg.display_height);
        if (strcmp(size, want) != 0)
            fail_msg("%s: scripts/board-key reads display_size '%s', the device %s", path, size, want);
        device_boards++;
    }
    closedir(dir);
    printf("  %u device boards parse, %u core-only boards are well-formed\n", device_boards, core_boards);
    assert_true(device_boards >= 15);
    assert_true(core_boards >= 1);
}

/* The VM boards differ from their simulated reference in the display only,
 * so a frame from vfb or bochs-drm can be compared with the reference's. */
static void test_vm_boards_match_reference(void **state)
{
    psc_board_config_t ref, vm;
    char err[400];
    (void)state;

    assert_int_equal(psc_board_config_load("boards/vm-reference/board.conf", &ref, err, sizeof err), 0);
    assert_string_equal(ref.display_backend, "sim");
    for (unsigned i = 0; i < 2; i++) {
        assert_int_equal(psc_board_config_load(i ? "boards/vm-drm/board.conf" : "boards/vm-fbdev/board.conf", &vm,
                                               err, sizeof err), 0);
        assert_string_not_equal(vm.display_backend, "sim");
        memcpy(vm.file, ref.file, sizeof vm.file);
        memcpy(vm.display_backend, ref.display_backend, sizeof vm.display_backend);
        memcpy(vm.tour_origin, ref.tour_origin, sizeof vm.tour_origin);
        /* relative paths are each board's folder's: the same files by another way */
        char a[PATH_MAX], b[PATH_MAX];
        assert_non_null(realpath(vm.tour, a));
        assert_non_null(realpath(ref.tour, b));
        assert_string_equal(a, b);
        memcpy(vm.tour, ref.tour, sizeof vm.tour);
        assert_int_equal(vm.scene_count, ref.scene_count);
        for (unsigned k = 0; k < vm.scene_count; k++) {
            if (realpath(vm.scenes[k], a) != NULL && realpath(ref.scenes[k], b) != NULL)
                assert_string_equal(a, b);
            memcpy(vm.scenes[k], ref.scenes[k], sizeof vm.scenes[k]);
        }
        memcpy(vm.options, ref.options, sizeof vm.options);
        vm.option_count = ref.option_count;
        assert_memory_equal(&vm, &ref, sizeof vm);
    }
}

static int group_setup(void **state)
{
    const char *tmp = getenv("PSC_TEST_TMPDIR");
    (void)state;
    snprintf(root, sizeof root, "%s/test_fwdev_%ld", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    return mkdir(root, 0755);
}

static int group_teardown(void **state)
{
    char cmd[400];
    (void)state;
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
    return system(cmd) == 0 ? 0 : -1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_device_status_states),
        cmocka_unit_test(test_device_status_drawing),
        cmocka_unit_test(test_font),
        cmocka_unit_test(test_frame_dump),
        cmocka_unit_test(test_frame_pacer),
        cmocka_unit_test(test_camera_scene_run),
        cmocka_unit_test(test_absent_camera_run),
        cmocka_unit_test(test_display_dither_run),
        cmocka_unit_test(test_stop_request),
        cmocka_unit_test(test_frame_dump_full_disk),
        cmocka_unit_test(test_reload_and_status),
        cmocka_unit_test(test_signals_to_the_program),
        cmocka_unit_test(test_board_files),
        cmocka_unit_test(test_vm_boards_match_reference),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
