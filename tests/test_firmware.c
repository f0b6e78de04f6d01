/* SPDX-License-Identifier: MIT */
/*
 * test_firmware.c - the device program's logic: board files
 * (firmware/board_config.h), tour scripts (hal/sim/psc_sim_tour.h), the
 * camera's motion model (firmware/motion.h), adaptive quality
 * (firmware/quality.h), and the whole sim board end to end on a tiny pack
 * (firmware/app.h).
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
#include "board_config.h"
#include "3d/psc_3d_render.h"
#include "motion.h"
#include "psc_io_pack_build.h"
#include "sim/psc_hal_sim.h"
#include "sim/psc_sim_tour.h"
#include "quality.h"
#include "psc_testsupport.h"
#include "tsup_pack.h"

#define DEG(d) ((int64_t)llround((d) / 360.0 * 4294967296.0)) /* degrees -> bam, any sign */

/* ---- board files ---------------------------------------------------------------- */

static int parse_board(const char *text, psc_board_config_t *cfg, char *err, size_t errlen)
{
    psc_board_config_defaults(cfg);
    err[0] = 0;
    return psc_board_config_parse(text, strlen(text), "t/board.conf", cfg, err, errlen);
}

static const char *const MIN_BOARD = "display = sim\ndisplay_size = 320x240\ninput = sim\nclock = sim\n";

static void test_board_valid(void **state)
{
    (void)state;
    psc_board_config_t cfg;
    char err[512];
    /* The repository's own sim board. */
    if (psc_board_config_load("boards/sim/board.conf", &cfg, err, sizeof(err)) != 0)
        fail_msg("boards/sim/board.conf: %s", err);
    assert_string_equal(cfg.display_backend, "sim");
    assert_string_equal(cfg.input_backend, "sim");
    assert_true(cfg.display_width >= 16 && cfg.display_height >= 16);
    assert_true(cfg.frame_rate_mhz >= 1000);
    assert_true(cfg.scene_count >= 1);
    assert_int_equal(cfg.display_dither, PSC_DITHER_ORDERED);   /* on unless a board says none */

    /* Units, comments, CRLF, decimals, backend options with their origin. */
    const char *text = "# a board\r\n"
                       "display = sim   # the simulator\r\n"
                       "display_size = 320x240\n"
                       "display_format = xrgb8888\n"
                       "frame_rate = 29.97\n"
                       "input = sim\n"
                       "clock = sim\n"
                       "\n"
                       "   \t\n"
                       "pitch_min = -45.5\n"
                       "pitch_max = 60\n"
                       "quality = fixed\n"
                       "pan_follows_zoom = off\n"
                       "scene = a.pano\n"
                       "scene = dir#1/b.pano\n"
                       "display.capture_dir = out/x\n"
                       "input.script = tours/t.txt\n"
                       /* build-time keys (cross build, boot image): read by the scripts, skipped here */
                       "toolchain = aarch64-linux-gnu-\n"
                       "debian_arch = arm64\n"
                       "backends = drm fbdev usb gpio\n"
                       "image.kernel = linux-image-arm64\n"
                       "image.modules = vc4 bochs\n"
                       "render3d_tile = 64\n"
                       "render3d_hsr = area\n"
                       "render3d_abuffer_kb = 256\n"
                       "render3d_relight = yes\n"
                       "render3d_soft_edges = no\n"
                       "render3d_light_azimuth = -90\n"
                       "render3d_light_elevation = 12.5\n"
                       "render3d_light_turn = -20\n"
                       "render3d_light_ambient = 0.3\n"
                       "display_levels = grey4:halftone\n"
                       "display_dither = none\n";
    if (parse_board(text, &cfg, err, sizeof(err)) != 0)
        fail_msg("valid board refused: %s", err);
    assert_int_equal(cfg.display_format, PSC_PIX_XRGB8888);
    assert_int_equal(cfg.frame_rate_mhz, 29970);
    assert_int_equal(cfg.pitch_min_mdeg, -45500);
    assert_int_equal(cfg.render3d_tile, 64);
    assert_int_equal(cfg.render3d_hsr, PSC_3D_HSR_AREA);
    assert_int_equal(cfg.render3d_abuffer_kb, 256);
    assert_true(cfg.render3d_relight);
    assert_false(cfg.render3d_soft_edges);
    assert_int_equal(cfg.render3d_light_azimuth_mdeg, -90000);
    assert_int_equal(cfg.render3d_light_elevation_mdeg, 12500);
    assert_int_equal(cfg.render3d_light_turn_mdeg, -20000);
    assert_int_equal(cfg.render3d_light_ambient_milli, 300);
    assert_true(cfg.display_levels.on);
    assert_int_equal(cfg.display_levels.target, PSC_DITHER_GREY4);
    assert_int_equal(cfg.display_levels.method, PSC_DITHER_HALFTONE);
    assert_int_equal(cfg.display_dither, PSC_DITHER_NONE);
    assert_int_equal(cfg.pitch_max_mdeg, 60000);
    assert_false(cfg.quality_adaptive);
    assert_false(cfg.pan_follows_zoom);
    assert_int_equal(cfg.scene_count, 2);
    assert_string_equal(cfg.scenes[0], "a.pano");
    assert_string_equal(cfg.scenes[1], "dir#1/b.pano"); /* '#' not after a space is not a comment */
    assert_int_equal(cfg.long_press_ms, 800);          /* a default */
    psc_hal_option_t items[8];
    size_t n = psc_board_config_options(&cfg, PSC_BOARD_DEV_DISPLAY, items, 8);
    assert_int_equal(n, 1);
    assert_string_equal(items[0].key, "capture_dir");
    assert_string_equal(items[0].value, "out/x");
    assert_non_null(strstr(items[0].origin, "t/board.conf:16"));
    n = psc_board_config_options(&cfg, PSC_BOARD_DEV_INPUT, items, 8);
    assert_int_equal(n, 1);
    assert_string_equal(items[0].key, "script");
    assert_int_equal(psc_board_config_options(&cfg, PSC_BOARD_DEV_CAMERA, items, 8), 0);
}

static void expect_board_error(const char *body, const char *where, const char *mention)
{
    psc_board_config_t cfg;
    char err[512], text[2048];
    snprintf(text, sizeof(text), "%s%s", MIN_BOARD, body);
    if (parse_board(text, &cfg, err, sizeof(err)) == 0)
        fail_msg("accepted: \"%s\"", body);
    if (!strstr(err, where) || (mention && !strstr(err, mention)))
        fail_msg("board error \"%s\" should contain \"%s\" and \"%s\"", err, where, mention ? mention : "");
}

static void test_board_errors(void **state)
{
    (void)state;
    /* Lines 1-4 are MIN_BOARD: the first line of body is line 5. */
    expect_board_error("frame_rate = fast\n", "t/board.conf:5:", "frame_rate");
    expect_board_error("\nframe_rate = 0\n", "t/board.conf:6:", "frame_rate");
    expect_board_error("frame_rate = 300\n", "t/board.conf:5:", "frame_rate");
    expect_board_error("colour = blue\n", "t/board.conf:5:", "colour");
    expect_board_error("# ok\nyaw_rate_max\n", "t/board.conf:6:", NULL);
    expect_board_error("= 5\n", "t/board.conf:5:", NULL);
    expect_board_error("frame_rate =\n", "t/board.conf:5:", "frame_rate");
    expect_board_error("Frame_Rate = 30\n", "t/board.conf:5:", NULL);
    expect_board_error("display_format = yuv\n", "t/board.conf:5:", "display_format");
    expect_board_error("display_buffers = 4\n", "t/board.conf:5:", "display_buffers");
    expect_board_error("quality_fast_filter = cubic\n", "t/board.conf:5:", "quality_fast_filter");
    expect_board_error("pan_follows_zoom = maybe\n", "t/board.conf:5:", "pan_follows_zoom");
    expect_board_error("quality_span_log2 = 5\n", "t/board.conf:5:", "quality_span_log2");
    expect_board_error("camera = warp9\n", "t/board.conf:5:", "warp9");
    expect_board_error("display_size = 320x\n", "t/board.conf:5:", "display_size");
    expect_board_error("long_press_ms = 800\nlong_press_ms = 900\n", "t/board.conf:6:", "line 5");
    expect_board_error("pitch_min = 10\npitch_max = -10\n", "t/board.conf", "pitch_min");
    expect_board_error("hfov_min = 100\nhfov_max = 50\n", "t/board.conf", "hfov_min");
    expect_board_error("display_size = 8x8\n", "t/board.conf:5:", "display_size"); /* duplicate and too small */
    expect_board_error("image. = x\n", "t/board.conf:5:", "image.");    /* the build prefix alone */
    expect_board_error("imagekernel = x\n", "t/board.conf:5:", "imagekernel");
    expect_board_error("display_levels = sepia\n", "t/board.conf:5:", "display_levels");
    expect_board_error("display_levels = mono:fancy\n", "t/board.conf:5:", "mono:fancy");
    expect_board_error("display_dither = halftone\n", "t/board.conf:5:", "display_dither must be ordered or none");
    expect_board_error("render3d_hsr = painter\n", "t/board.conf:5:", "render3d_hsr must be zbuffer or area");

    /* A missing required key names the file and the key. */
    psc_board_config_t cfg;
    char err[512];
    assert_int_not_equal(parse_board("display = sim\ninput = sim\nclock = sim\n", &cfg, err, sizeof(err)), 0);
    assert_non_null(strstr(err, "t/board.conf"));
    assert_non_null(strstr(err, "display_size"));
    /* A NUL byte in the text. */
    static const char nul[] = "display = sim\nin\0put = sim\n";
    psc_board_config_defaults(&cfg);
    assert_true(cfg.render3d_soft_edges);   /* proxies' silhouettes anti-aliased unless a board says no */
    assert_int_not_equal(psc_board_config_parse(nul, sizeof(nul) - 1, "nul.conf", &cfg, err, sizeof(err)), 0);
    assert_non_null(strstr(err, "nul.conf:2:"));
    /* An unreadable file names the path. */
    assert_int_not_equal(psc_board_config_load("no/such/board.conf", &cfg, err, sizeof(err)), 0);
    assert_non_null(strstr(err, "no/such/board.conf"));
}

/* ---- tour scripts ----------------------------------------------------------------------- */

static int tour(const char *text, psc_sim_tour_t *t, char *err, size_t errlen)
{
    err[0] = 0;
    return psc_sim_tour_parse(text, strlen(text), "t.tour", 800, t, err, errlen);
}

/* The first event of a kind/code at or after index from; -1 if none. */
static long find_event(const psc_sim_tour_t *t, size_t from, psc_hal_input_type_t type, unsigned code)
{
    for (size_t i = from; i < t->count; i++)
        if (t->events[i].type == type && t->events[i].code == code)
            return (long)i;
    return -1;
}

static void test_tour_events(void **state)
{
    (void)state;
    psc_sim_tour_t t;
    char err[512];
    const char *text = "# demo\n"
                       "hold 4s axis yaw 1.0\n"   /* 0 .. 4 s */
                       "press home\n"             /* 4 s, up 4.1 s */
                       "wait 1s\n"                /* cursor 5 s */
                       "hold 1.5s axis pitch -1.0\n" /* 5 .. 6.5 s */
                       "hold 2s zoom_in\n"        /* 6.5 .. 8.5 s, long press at 7.3 s */
                       "at 9000 pitch 0.5   # at 9 s\n"
                       "wait 250ms\n"
                       "plug 1\n"
                       "device 1\n"
                       "next_scene\n"
                       "wait 0.5s\n"
                       "unplug 1\n"
                       "end\n";
    if (tour(text, &t, err, sizeof(err)) != 0)
        fail_msg("tour refused: %s", err);
    for (size_t i = 1; i < t.count; i++)
        assert_true(t.events[i].time_us >= t.events[i - 1].time_us); /* sorted */
    long i = find_event(&t, 0, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_YAW);
    assert_true(i >= 0);
    assert_int_equal(t.events[i].time_us, 0);
    assert_int_equal(t.events[i].value, PSC_HAL_AXIS_MAX);
    i = find_event(&t, (size_t)i + 1, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_YAW);
    assert_true(i >= 0);
    assert_int_equal(t.events[i].time_us, 4000000);
    assert_int_equal(t.events[i].value, 0);
    i = find_event(&t, 0, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_HOME);
    assert_true(i >= 0);
    assert_int_equal(t.events[i].time_us, 4000000);
    i = find_event(&t, 0, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_HOME);
    assert_true(i >= 0);
    assert_int_equal(t.events[i].time_us, 4000000 + PSC_SIM_TOUR_PRESS_MS * 1000);
    assert_int_equal(find_event(&t, 0, PSC_HAL_INPUT_BUTTON_LONG, PSC_HAL_ACTION_HOME), -1); /* short press */
    i = find_event(&t, 0, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_PITCH);
    assert_true(i >= 0);
    assert_int_equal(t.events[i].time_us, 5000000);
    assert_true(t.events[i].value <= -32767);
    i = find_event(&t, 0, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_ZOOM_IN);
    assert_true(i >= 0);
    assert_int_equal(t.events[i].time_us, 6500000);
    i = find_event(&t, 0, PSC_HAL_INPUT_BUTTON_LONG, PSC_HAL_ACTION_ZOOM_IN);
    assert_true(i >= 0);
    assert_int_equal(t.events[i].time_us, 7300000);
    i = find_event(&t, 0, PSC_HAL_INPUT_BUTTON_UP, PSC_HAL_ACTION_ZOOM_IN);
    assert_true(i >= 0);
    assert_int_equal(t.events[i].time_us, 8500000);
    i = find_event(&t, 0, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_PITCH);
    i = find_event(&t, (size_t)i + 1, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_PITCH); /* back to 0 at 6.5 s */
    i = find_event(&t, (size_t)i + 1, PSC_HAL_INPUT_AXIS, PSC_HAL_AXIS_PITCH); /* 0.5 at 9 s */
    assert_true(i >= 0);
    assert_int_equal(t.events[i].time_us, 9000000);
    assert_true(abs(t.events[i].value - 16384) <= 1);
    i = find_event(&t, 0, PSC_HAL_INPUT_DEVICE_ARRIVE, 0);
    while (i >= 0 && t.events[i].device != 1)
        i = find_event(&t, (size_t)i + 1, PSC_HAL_INPUT_DEVICE_ARRIVE, 0);
    assert_true(i >= 0);
    assert_int_equal(t.events[i].time_us, 9250000);
    i = find_event(&t, 0, PSC_HAL_INPUT_BUTTON_DOWN, PSC_HAL_ACTION_NEXT_SCENE);
    assert_true(i >= 0);
    assert_int_equal(t.events[i].device, 1);
    assert_int_equal(t.events[i].time_us, 9250000);
    assert_true(find_event(&t, 0, PSC_HAL_INPUT_DEVICE_LEAVE, 0) >= 0);
    assert_int_equal(t.end_us, 9750000);
    psc_sim_tour_free(&t);
    psc_sim_tour_free(&t); /* safe twice */

    /* The repository's demonstration tour parses (its length is its author's business: printed). */
    if (psc_sim_tour_load("boards/sim/tour.txt", 800, &t, err, sizeof(err)) != 0)
        fail_msg("boards/sim/tour.txt: %s", err);
    printf("  boards/sim/tour.txt: %zu events, ends at %.3f s\n", t.count, t.end_us / 1e6);
    assert_true(t.count > 0 && t.end_us > 0);
    psc_sim_tour_free(&t);
}

static void expect_tour_error(const char *text, const char *where)
{
    psc_sim_tour_t t;
    char err[512];
    memset(&t, 0x5A, sizeof(t));
    if (tour(text, &t, err, sizeof(err)) == 0)
        fail_msg("tour accepted: \"%s\"", text);
    if (!strstr(err, where))
        fail_msg("tour error \"%s\" should name \"%s\"", err, where);
    assert_int_equal(t.count, 0); /* *tour empty on failure */
    psc_sim_tour_free(&t);
}

static void test_tour_errors(void **state)
{
    (void)state;
    expect_tour_error("jump 3\n", "t.tour:1:");
    expect_tour_error("wait 1s\npress launch\n", "t.tour:2:");
    expect_tour_error("axis yaw 1.5\n", "t.tour:1:");
    expect_tour_error("axis roll 0.5\n", "t.tour:1:");
    expect_tour_error("at 5s\nat 3s\n", "t.tour:2:");
    expect_tour_error("up home\n", "t.tour:1:");
    expect_tour_error("down home\ndown home\n", "t.tour:2:");
    expect_tour_error("device 3\npress home\n", "t.tour:2:");
    expect_tour_error("device 8\n", "t.tour:1:");
    expect_tour_error("end\nwait 1s\n", "t.tour:2:");
    expect_tour_error("wait -1s\n", "t.tour:1:");
    expect_tour_error("wait 1x\n", "t.tour:1:");
    expect_tour_error("# fine\n\nhold 2s\n", "t.tour:3:");
    expect_tour_error("wait 25h\n", "t.tour:1:");
    char err[256];
    psc_sim_tour_t t;
    assert_int_not_equal(psc_sim_tour_load("no/such/tour.txt", 800, &t, err, sizeof(err)), 0);
    assert_non_null(strstr(err, "no/such/tour.txt"));
}

/* ---- motion ------------------------------------------------------------------------------ */

static psc_motion_config_t motion_cfg(void)
{
    psc_motion_config_t c;
    memset(&c, 0, sizeof(c));
    c.yaw_rate_max = DEG(90);
    c.pitch_rate_max = DEG(60);
    c.hfov_rate_max = DEG(45);
    c.accel = DEG(360);
    c.inertia_half_life_us = 120000;
    c.home_half_life_us = 150000;
    c.pitch_min = -(int32_t)PSC_BAM_90;
    c.pitch_max = (int32_t)PSC_BAM_90;
    c.hfov_min = (psc_bam_t)DEG(20);
    c.hfov_max = (psc_bam_t)DEG(120);
    c.pan_follows_zoom = false;
    return c;
}

static void run(psc_motion_t *m, int32_t yaw, int32_t pitch, int32_t zoom, uint32_t total_us, uint32_t dt_us)
{
    psc_motion_input_t in = {yaw, pitch, zoom};
    for (uint32_t t = 0; t < total_us; t += dt_us)
        psc_motion_step(m, &in, dt_us);
}

#define FRAME_US 33333u

static void test_motion_rates_and_limits(void **state)
{
    (void)state;
    psc_motion_config_t c = motion_cfg();
    psc_motion_t m;
    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(90));
    /* At rest, no input: nothing moves; dt 0 changes nothing. */
    run(&m, 0, 0, 0, 1000000, FRAME_US);
    assert_int_equal(m.yaw, 0);
    assert_int_equal(m.pitch, 0);
    assert_int_equal(m.hfov, (psc_bam_t)DEG(90));
    psc_motion_input_t full = {PSC_HAL_AXIS_MAX, 0, 0};
    psc_motion_step(&m, &full, 0);
    assert_int_equal(m.yaw, 0);
    assert_int_equal(m.yaw_rate, 0);

    /* Full stick: the rate rises by accel * dt, reaching rate_max after rate_max / accel = 0.25 s. */
    psc_motion_step(&m, &full, 100000);
    double r = (double)m.yaw_rate / DEG(1);
    if (fabs(r - 36.0) > 0.5)
        fail_msg("yaw rate after 0.1 s at full stick: %.3f deg/s, expected 36", r);
    run(&m, PSC_HAL_AXIS_MAX, 0, 0, 200000, FRAME_US);
    assert_true(llabs(m.yaw_rate - DEG(90)) <= DEG(90) / 300); /* full stick is 32767/32768 */
    /* Yaw after one second from rest: 11.25 deg of ramp + 67.5 at full rate. */
    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(90));
    run(&m, PSC_HAL_AXIS_MAX, 0, 0, 1000000, 10000);
    double yaw = tsup_bam_to_rad(m.yaw) / TSUP_DEG;
    if (fabs(yaw - 78.75) > 1.5)
        fail_msg("yaw after 1 s at full stick: %.3f deg, expected about 78.75", yaw);
    /* A full turn and more wraps. */
    run(&m, PSC_HAL_AXIS_MAX, 0, 0, 4000000, 10000);
    yaw = tsup_bam_to_rad(m.yaw) / TSUP_DEG; /* 78.75 + 360 = 438.75 -> 78.75 */
    assert_true(fabs(yaw - 78.75) < 2.0);
    /* Left turns decrease yaw. */
    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(90));
    run(&m, PSC_HAL_AXIS_MIN, 0, 0, 500000, FRAME_US);
    assert_true((int32_t)m.yaw < 0);

    /* Pitch stops exactly at its limit, its rate zeroed. */
    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(90));
    run(&m, 0, PSC_HAL_AXIS_MAX, 0, 3000000, FRAME_US);
    assert_int_equal(m.pitch, (int32_t)PSC_BAM_90);
    assert_int_equal(m.pitch_rate, 0);
    run(&m, 0, PSC_HAL_AXIS_MIN, 0, 5000000, FRAME_US);
    assert_int_equal(m.pitch, -(int32_t)PSC_BAM_90);
    assert_int_equal(m.pitch_rate, 0);
    c.pitch_min = -(int32_t)DEG(10);
    c.pitch_max = (int32_t)DEG(45);
    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(90));
    run(&m, 0, PSC_HAL_AXIS_MAX, 0, 3000000, FRAME_US);
    assert_int_equal(m.pitch, (int32_t)DEG(45));
    run(&m, 0, PSC_HAL_AXIS_MIN, 0, 3000000, FRAME_US);
    assert_int_equal(m.pitch, -(int32_t)DEG(10));

    /* Zoom in (positive) narrows hfov down to hfov_min; out widens to hfov_max. */
    c = motion_cfg();
    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(90));
    run(&m, 0, 0, PSC_HAL_AXIS_MAX, 300000, FRAME_US);
    assert_true(m.hfov < (psc_bam_t)DEG(90));
    run(&m, 0, 0, PSC_HAL_AXIS_MAX, 3000000, FRAME_US);
    assert_int_equal(m.hfov, (psc_bam_t)DEG(20));
    assert_int_equal(m.hfov_rate, 0);
    run(&m, 0, 0, PSC_HAL_AXIS_MIN, 4000000, FRAME_US);
    assert_int_equal(m.hfov, (psc_bam_t)DEG(120));

    /* Init brings the view inside the limits. */
    c.pitch_max = (int32_t)DEG(45);
    psc_motion_init(&m, &c, 0, (int32_t)PSC_BAM_90, (psc_bam_t)DEG(5));
    assert_int_equal(m.pitch, (int32_t)DEG(45));
    assert_int_equal(m.hfov, (psc_bam_t)DEG(20));
}

static void test_motion_inertia_home_and_steps(void **state)
{
    (void)state;
    psc_motion_config_t c = motion_cfg();
    psc_motion_t m;
    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(90));
    run(&m, PSC_HAL_AXIS_MAX, 0, 0, 1000000, 10000);
    int64_t r0 = m.yaw_rate;
    /* Released: the rate halves every half-life (120 ms) ... */
    run(&m, 0, 0, 0, 120000, 10000);
    double ratio = (double)m.yaw_rate / r0;
    if (fabs(ratio - 0.5) > 0.01)
        fail_msg("rate after one half-life of coasting: %.4f of the start, expected 0.5", ratio);
    run(&m, 0, 0, 0, 120000, 10000);
    assert_true(fabs((double)m.yaw_rate / r0 - 0.25) < 0.01);
    /* ... and stops below the stop rate; the view then stays put. */
    run(&m, 0, 0, 0, 3000000, FRAME_US);
    assert_int_equal(m.yaw_rate, 0);
    psc_bam_t y = m.yaw;
    run(&m, 0, 0, 0, 1000000, FRAME_US);
    assert_int_equal(m.yaw, y);

    /* Home glides back exactly and ends; stick input cancels it. */
    psc_motion_init(&m, &c, (psc_bam_t)DEG(10), (int32_t)DEG(5), (psc_bam_t)DEG(70));
    run(&m, PSC_HAL_AXIS_MAX, PSC_HAL_AXIS_MAX, PSC_HAL_AXIS_MIN, 800000, FRAME_US);
    run(&m, 0, 0, 0, 2000000, FRAME_US);
    assert_true(m.yaw != (psc_bam_t)DEG(10));
    psc_motion_home(&m);
    assert_true(m.homing);
    run(&m, 0, 0, 0, 4000000, FRAME_US);
    assert_false(m.homing);
    assert_int_equal(m.yaw, (psc_bam_t)DEG(10));
    assert_int_equal(m.pitch, (int32_t)DEG(5));
    assert_int_equal(m.hfov, (psc_bam_t)DEG(70));
    run(&m, PSC_HAL_AXIS_MAX, 0, 0, 300000, FRAME_US);
    psc_motion_home(&m);
    run(&m, 0, PSC_HAL_AXIS_MAX, 0, FRAME_US, FRAME_US);
    assert_false(m.homing);

    /* Home takes the short way round: from yaw 350 to home 10 goes through 0. */
    psc_motion_init(&m, &c, (psc_bam_t)DEG(10), 0, (psc_bam_t)DEG(90));
    psc_motion_set_view(&m, (psc_bam_t)DEG(350), 0, (psc_bam_t)DEG(90));
    psc_motion_home(&m);
    psc_motion_step(&m, &(psc_motion_input_t){0, 0, 0}, FRAME_US);
    double yd = tsup_sbam_to_rad((int32_t)m.yaw) / TSUP_DEG; /* started at -10 */
    if (!(yd > -10.0 && yd <= 10.0))
        fail_msg("homing from yaw 350 to 10: after one frame yaw is %.3f deg, not on the short way (-10..10)", yd);

    /* Steps longer than a second count as one second. */
    psc_motion_t a, b;
    psc_motion_init(&a, &c, 0, 0, (psc_bam_t)DEG(90));
    psc_motion_init(&b, &c, 0, 0, (psc_bam_t)DEG(90));
    psc_motion_input_t in = {PSC_HAL_AXIS_MAX, PSC_HAL_AXIS_MAX / 2, 0};
    psc_motion_step(&a, &in, 1000000);
    psc_motion_step(&b, &in, 7000000);
    assert_int_equal(a.yaw, b.yaw);
    assert_int_equal(a.pitch, b.pitch);
    assert_int_equal(a.yaw_rate, b.yaw_rate);
    assert_int_equal(a.pitch_rate, b.pitch_rate);

    /* pan_follows_zoom: at 45 deg hfov the steady pan rate is half the configured one. */
    c.pan_follows_zoom = true;
    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(45));
    run(&m, PSC_HAL_AXIS_MAX, 0, 0, 2000000, FRAME_US);
    ratio = (double)m.yaw_rate / DEG(90);
    if (fabs(ratio - 0.5) > 0.01)
        fail_msg("pan_follows_zoom at hfov 45: yaw rate %.4f of yaw_rate_max, expected 0.5", ratio);
    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(90));
    run(&m, PSC_HAL_AXIS_MAX, 0, 0, 2000000, FRAME_US);
    assert_true(fabs((double)m.yaw_rate / DEG(90) - 1.0) < 0.01);
}

static void test_motion_set_view(void **state)
{
    (void)state;
    psc_motion_config_t c = motion_cfg();
    psc_motion_t m;
    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(90));
    run(&m, PSC_HAL_AXIS_MAX, PSC_HAL_AXIS_MAX, 0, 300000, FRAME_US);
    assert_true(m.pitch_rate > 0 && m.yaw_rate > 0);
    /* The clamp pulled pitch down and yaw back: the rates pushing that way stop. */
    psc_motion_set_view(&m, m.yaw - (psc_bam_t)DEG(1), m.pitch - (int32_t)DEG(1), m.hfov);
    assert_int_equal(m.pitch_rate, 0);
    assert_int_equal(m.yaw_rate, 0);
    /* A correction the rate moves away from leaves it alone. */
    run(&m, 0, PSC_HAL_AXIS_MIN, 0, 300000, FRAME_US);
    int64_t pr = m.pitch_rate;
    assert_true(pr < 0);
    psc_motion_set_view(&m, m.yaw, m.pitch - (int32_t)DEG(1), m.hfov);
    assert_true(m.pitch_rate < 0);
    /* An unchanged view changes nothing. */
    psc_motion_t before = m;
    psc_motion_set_view(&m, m.yaw, m.pitch, m.hfov);
    assert_int_equal(m.pitch_rate, before.pitch_rate);
    assert_int_equal(m.yaw_rate, before.yaw_rate);
}

static void test_motion_decay(void **state)
{
    (void)state;
    assert_int_equal(psc_motion_decay_q16(0, 120000), 65536);
    assert_true(abs((int)psc_motion_decay_q16(120000, 120000) - 32768) <= 1);
    assert_true(abs((int)psc_motion_decay_q16(240000, 120000) - 16384) <= 1);
    assert_int_equal(psc_motion_decay_q16(16 * 120000, 120000), 0);
    assert_int_equal(psc_motion_decay_q16(UINT32_MAX, 1), 0);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 71);
    double worst = 0.0;
    for (int i = 0; i < 200000; i++) {
        uint32_t hl = 1 + tsup_rng_below(&rng, 2000000);
        uint32_t dt = tsup_rng_below(&rng, 16u * hl < 16u * 2000000u ? 16u * hl : 16u * 2000000u);
        double want = 65536.0 * exp2(-(double)dt / hl);
        double e = fabs(psc_motion_decay_q16(dt, hl) - want);
        if (e > worst)
            worst = e;
        if (e > 2.0)
            fail_msg("psc_motion_decay_q16(%u, %u) = %u, expected %.3f", dt, hl, psc_motion_decay_q16(dt, hl), want);
    }
    printf("  psc_motion_decay_q16: max error %.3f units of 2^-16 over 200000 random (dt, half-life)\n", worst);
}

/* ---- adaptive quality ---------------------------------------------------------------------- */

static void test_quality(void **state)
{
    (void)state;
    psc_view_t a = tsup_view_deg(0.0, 0.0, 90.0, PSC_FILTER_BILINEAR, 2), b = a;
    /* 9 degrees of yaw in 0.1 s at hfov 90: a whole view width per second. */
    b.yaw = tsup_bam_from_deg(9.0);
    assert_true(abs((int)psc_quality_speed(&a, &b, 100000) - 1000) <= 1);
    assert_true(abs((int)psc_quality_speed(&b, &a, 100000) - 1000) <= 1); /* direction does not matter */
    /* The same pan zoomed in to 45 degrees crosses twice as many view widths. */
    psc_view_t a45 = a, b45 = b;
    a45.hfov = b45.hfov = tsup_bam_from_deg(45.0);
    assert_true(abs((int)psc_quality_speed(&a45, &b45, 100000) - 2000) <= 2);
    /* Across the seam: 359 -> 1 degree is 2 degrees. */
    a.yaw = tsup_bam_from_deg(359.0);
    b.yaw = tsup_bam_from_deg(1.0);
    assert_true(abs((int)psc_quality_speed(&a, &b, 1000000) - 22) <= 1); /* 2/90 view widths in 1 s */
    /* Pitch counts too; no motion and no time are 0. */
    a = tsup_view_deg(0.0, 0.0, 90.0, PSC_FILTER_BILINEAR, 2);
    b = tsup_view_deg(0.0, -18.0, 90.0, PSC_FILTER_BILINEAR, 2);
    assert_true(abs((int)psc_quality_speed(&a, &b, 1000000) - 200) <= 1);
    assert_int_equal(psc_quality_speed(&a, &a, 33333), 0);
    assert_int_equal(psc_quality_speed(&a, &b, 0), 0);
    b.hfov = tsup_bam_from_deg(60.0);
    assert_true(psc_quality_speed(&a, &b, 1000000) > 0);
    b = a;
    b.yaw = tsup_bam_from_deg(180.0);
    b.hfov = 1;
    assert_int_equal(psc_quality_speed(&a, &b, 1), UINT32_MAX); /* saturates */

    /* Hysteresis: fast at once, calm only after settle_frames calm frames in a row. */
    psc_quality_config_t cfg = {true, 500, 3, PSC_FILTER_NEAREST, 3, PSC_FILTER_BILINEAR, 2};
    psc_quality_t q;
    psc_quality_init(&q);
    psc_view_t v = a;
    psc_quality_apply(&q, &cfg, &v);
    assert_int_equal(v.filter, PSC_FILTER_BILINEAR);
    assert_int_equal(v.span_log2, 2);
    assert_false(psc_quality_update(&q, &cfg, 499));
    assert_true(psc_quality_update(&q, &cfg, 500)); /* at the threshold: fast */
    psc_quality_apply(&q, &cfg, &v);
    assert_int_equal(v.filter, PSC_FILTER_NEAREST);
    assert_int_equal(v.span_log2, 3);
    assert_false(psc_quality_update(&q, &cfg, 100));
    assert_false(psc_quality_update(&q, &cfg, 100));
    assert_false(psc_quality_update(&q, &cfg, 900)); /* fast again: the calm count restarts */
    assert_false(psc_quality_update(&q, &cfg, 100));
    assert_false(psc_quality_update(&q, &cfg, 100));
    assert_true(psc_quality_update(&q, &cfg, 100)); /* third calm frame in a row */
    psc_quality_apply(&q, &cfg, &v);
    assert_int_equal(v.filter, PSC_FILTER_BILINEAR);
    assert_int_equal(v.span_log2, 2);
    assert_int_equal(q.switches, 2);
    assert_int_equal(q.fast_frames_total, 6); /* 500, 100, 100, 900, 100, 100 */
    /* Fixed quality never switches. */
    cfg.adaptive = false;
    psc_quality_init(&q);
    for (int i = 0; i < 10; i++)
        assert_false(psc_quality_update(&q, &cfg, 1000000));
    psc_quality_apply(&q, &cfg, &v);
    assert_int_equal(v.filter, PSC_FILTER_BILINEAR);
}

/* ---- the sim board end to end ----------------------------------------------------------------- */

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void test_sim_board_end_to_end(void **state)
{
    (void)state;
    const char *tmp = getenv("PSC_TEST_TMPDIR");
    char root[256], dir[300], path[400], pack[400], tourf[400], out[400], err[512];
    snprintf(root, sizeof(root), "%s/test_firmware_%ld", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    mkdir(root, 0755);
    snprintf(dir, sizeof(dir), "%s/tiny", root);
    mkdir(dir, 0755);

    /* A tiny pack of the synthetic scene. */
    snprintf(pack, sizeof(pack), "%s/tiny.pano", root);
    if (tsup_write_synth_pack(pack, 128, 64, 96, 64, 32, 24, err, sizeof(err)) != 0)
        fail_msg("pack: %s", err);

    /* 3 s of tour at 30 frames/s: a whip pan (fast quality), a look up, home. */
    snprintf(tourf, sizeof(tourf), "%s/tour.txt", root);
    write_text(tourf, "wait 0.2s\nhold 1s axis yaw 1.0\nhold 0.5s axis pitch 1.0\npress home\nwait 1s\nend\n");
    snprintf(path, sizeof(path), "%s/board.conf", dir);
    char conf[1024];
    snprintf(conf, sizeof(conf),
             "display = sim\ndisplay_size = 96x64\ndisplay_format = xrgb8888\nframe_rate = 30\n"
             "input = sim\nclock = sim\nwatchdog = sim\nwatchdog_timeout_ms = 500\n"
             "scene = %s\nquality = adaptive\nquality_fast_speed = 0.5\n",
             pack);
    write_text(path, conf);
    snprintf(out, sizeof(out), "%s/out", root);

    psc_cli_options_t opt;
    memset(&opt, 0, sizeof(opt));
    opt.board = "tiny";
    opt.boards_dir = root;
    opt.out_dir = out;
    opt.tour = tourf;
    opt.frames_every = 30;
    opt.quiet = true;
    psc_app_t *app = NULL;
    if (psc_app_open(&opt, &app, err, sizeof(err)) != 0)
        fail_msg("psc_app_open: %s", err);
    psc_app_stats_t st;
    memset(&st, 0, sizeof(st));
    if (psc_app_run(app, &st, err, sizeof(err)) != 0)
        fail_msg("psc_app_run: %s", err);
    printf("  sim board: %u frames, %.3f s board time, %u fast frames, %u quality switches, watchdog %u kicks, "
           "longest gap %.1f ms\n",
           st.frames, st.sim_time_us / 1e6, st.fast_frames, st.quality_switches, st.watchdog.kicks,
           st.watchdog.longest_gap_us / 1e3);
    /* The tour ends at 2.7 s + 0.1 s press: frames at 30 Hz until QUIT. */
    assert_true(st.frames >= 80 && st.frames <= 90);
    assert_true(st.sim_time_us >= 2700000 && st.sim_time_us <= 3100000);
    assert_true(st.fast_frames > 0 && st.fast_frames < st.frames); /* the whip pan went fast, the rest calm */
    assert_true(st.quality_switches >= 2);
    assert_int_equal(st.capture_every, 30);
    assert_true(st.watchdog_known);
    assert_true(st.watchdog.kicks >= st.frames);
    assert_false(st.watchdog.would_have_fired);
    /* Captured frames exist: 0, 30, 60. */
    for (uint32_t f = 0; f < st.frames; f += 30) {
        char cap[600];
        assert_int_equal(psc_sim_capture_path(cap, sizeof(cap), psc_app_out_dir(app), f), 0);
        struct stat sb;
        if (stat(cap, &sb) != 0 || sb.st_size < 100)
            fail_msg("capture of frame %u missing: %s", f, cap);
        unlink(cap);
    }
    psc_app_close(app);

    /* The same board as a 1-bit display (display_levels): the frames it presents hold black and white only, and
     * about the scene's brightness. */
    snprintf(conf, sizeof(conf),
             "display = sim\ndisplay_size = 96x64\ndisplay_format = xrgb8888\nframe_rate = 30\n"
             "input = sim\nclock = sim\nscene = %s\ndisplay_levels = mono:halftone\n",
             pack);
    write_text(path, conf);
    opt.max_frames = 2;
    opt.frames_every = 1;
    if (psc_app_open(&opt, &app, err, sizeof(err)) != 0)
        fail_msg("psc_app_open (display_levels): %s", err);
    if (psc_app_run(app, &st, err, sizeof(err)) != 0)
        fail_msg("psc_app_run (display_levels): %s", err);
    char cap[600];
    assert_int_equal(psc_sim_capture_path(cap, sizeof(cap), psc_app_out_dir(app), 1), 0);
    psc_image_t img;
    if (psc_io_image_load(cap, &img, err, sizeof(err)) != 0)
        fail_msg("%s", err);
    size_t white = 0;
    for (size_t i = 0; i < (size_t)img.width * img.height; i++) {
        uint32_t c = img.xrgb[i] & 0xFFFFFFu;
        if (c != 0 && c != 0xFFFFFFu)
            fail_msg("display_levels = mono: pixel %zu of %s is %06X", i, cap, (unsigned)c);
        white += c != 0;
    }
    printf("  display_levels = mono:halftone: a presented frame holds black and white only (%.0f%% white)\n",
           100.0 * (double)white / ((double)img.width * img.height));
    assert_true(white > 0 && white < (size_t)img.width * img.height);
    psc_io_image_free(&img);
    unlink(cap);
    psc_app_close(app);

    /* A board whose scene is missing fails to open, naming the file. */
    snprintf(conf, sizeof(conf), "display = sim\ndisplay_size = 96x64\ninput = sim\nclock = sim\nscene = %s/nope.pano\n",
             root);
    write_text(path, conf);
    app = NULL;
    err[0] = 0;
    assert_int_not_equal(psc_app_open(&opt, &app, err, sizeof(err)), 0);
    assert_non_null(strstr(err, "nope.pano"));
    /* A board file with a mistake names file and line. */
    write_text(path, "display = sim\ndisplay_size = 96x64\ninput = sim\nclock = sim\nframe_rate = soon\n");
    err[0] = 0;
    assert_int_not_equal(psc_app_open(&opt, &app, err, sizeof(err)), 0);
    assert_non_null(strstr(err, "board.conf:5:"));

    unlink(path);
    unlink(pack);
    unlink(tourf);
    rmdir(out);
    rmdir(dir);
    rmdir(root);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_board_valid),
        cmocka_unit_test(test_board_errors),
        cmocka_unit_test(test_tour_events),
        cmocka_unit_test(test_tour_errors),
        cmocka_unit_test(test_motion_rates_and_limits),
        cmocka_unit_test(test_motion_inertia_home_and_steps),
        cmocka_unit_test(test_motion_set_view),
        cmocka_unit_test(test_motion_decay),
        cmocka_unit_test(test_quality),
        cmocka_unit_test(test_sim_board_end_to_end),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
