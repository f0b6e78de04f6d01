/* SPDX-License-Identifier: MIT */
/*
 * test_gestures.c - the picture under the finger: pixel -> direction against
 * a double-precision reference, the grab solve, the gestures (drag, flick,
 * tap, pinch, wheel), scenes with ids, titles, starting views and labelled
 * hotspots in board files, and on the sim board a tapped hotspot, the back
 * action and the cross-fade between scenes.
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
#include "board_config.h"
#include "gestures.h"
#include "hotspots.h"
#include "kiosk.h"
#include "motion.h"
#include "view_geometry.h"
#include "psc_testsupport.h"
#include "tsup_files.h"
#include "tsup_pack.h"

#define DEG(d) ((int64_t)llround((d) / 360.0 * 4294967296.0))
#define TO_DEG(b) ((double)(int32_t)(b) * 360.0 / 4294967296.0)
#define W 640
#define H 480

/* The viewer's conventions in double: the direction of pixel (x, y)'s centre. */
static void ref_unproject(double yaw, double pitch, double hfov, double x, double y, double *ryaw, double *rpitch)
{
    double d = W / tan(hfov / 2.0);
    double cx = 2 * x + 1 - W, cy = H - 1 - 2 * y, cz = d;
    double wy = cy * cos(pitch) + cz * sin(pitch), wz = cz * cos(pitch) - cy * sin(pitch);
    *ryaw = yaw + atan2(cx, wz);
    *rpitch = atan2(wy, hypot(cx, wz));
}

static double angle_diff_deg(double a, double b)
{
    double d = fmod(a - b, 360.0);
    return fabs(d > 180 ? d - 360 : d < -180 ? d + 360 : d);
}

static tsup_rng_t rng;

static double rand_range(double lo, double hi)
{
    return lo + (hi - lo) * tsup_rng_unit(&rng);
}

static psc_view_t random_view(void)
{
    return (psc_view_t){ .yaw = (psc_bam_t)DEG(rand_range(-180, 180)),
                         .pitch = (int32_t)DEG(rand_range(-80, 80)),
                         .hfov = (psc_bam_t)DEG(rand_range(20, 120)) };
}

/* 20 000 random views and pixels: the direction within 0.005 degrees of double's. */
static void test_unproject_matches_double(void **state)
{
    double worst = 0;
    (void)state;

    tsup_rng_seed(&rng, 17);
    for (int i = 0; i < 20000; i++) {
        psc_view_t v = random_view();
        int32_t x = (int32_t)rand_range(-50, W + 50), y = (int32_t)rand_range(-50, H + 50);
        psc_bam_t yaw;
        int32_t pitch;
        double ry, rp;

        psc_view_unproject(&v, W, H, x, y, &yaw, &pitch);
        ref_unproject(TO_DEG(v.yaw) * M_PI / 180, TO_DEG(v.pitch) * M_PI / 180,
                      (double)v.hfov * 2 * M_PI / 4294967296.0, x, y, &ry, &rp);
        double e = fmax(angle_diff_deg(TO_DEG(yaw), ry * 180 / M_PI) * cos(rp),
                        angle_diff_deg(TO_DEG(pitch), rp * 180 / M_PI));
        worst = fmax(worst, e);
        if (e > 0.005)
            fail_msg("view %.3f %.3f %.3f pixel (%d, %d): %.4f %.4f, double %.4f %.4f", TO_DEG(v.yaw),
                     TO_DEG(v.pitch), (double)v.hfov * 360 / 4294967296.0, x, y, TO_DEG(yaw), TO_DEG(pitch),
                     ry * 180 / M_PI, rp * 180 / M_PI);
    }
    printf("  unproject: worst %.2g degrees over 20000 cases\n", worst);
}

/* The grab solve puts the grabbed direction back under the new pixel (the inverse of unproject). */
static void test_grab_keeps_direction_under_pixel(void **state)
{
    unsigned exact = 0;
    double worst = 0;
    (void)state;

    tsup_rng_seed(&rng, 23);
    for (int i = 0; i < 20000; i++) {
        psc_view_t v = random_view(), to;
        int32_t x0 = (int32_t)rand_range(0, W - 1), y0 = (int32_t)rand_range(0, H - 1);
        int32_t x1 = (int32_t)rand_range(0, W - 1), y1 = (int32_t)rand_range(0, H - 1);
        psc_bam_t yaw, yaw1;
        int32_t pitch, pitch1;

        psc_view_unproject(&v, W, H, x0, y0, &yaw, &pitch);
        if (!psc_view_grab(&v, W, H, x1, y1, yaw, pitch, &to))
            continue;   /* a point near the pole cannot reach that row */
        exact++;
        assert_int_equal(to.hfov, v.hfov);
        assert_true(to.pitch >= -(int32_t)PSC_BAM_90 && to.pitch <= (int32_t)PSC_BAM_90);
        psc_view_unproject(&to, W, H, x1, y1, &yaw1, &pitch1);
        double e = fmax(angle_diff_deg(TO_DEG(yaw1), TO_DEG(yaw)) * cos(TO_DEG(pitch) * M_PI / 180),
                        fabs(TO_DEG(pitch1) - TO_DEG(pitch)));
        worst = fmax(worst, e);
        if (e > 0.01)
            fail_msg("case %d: grabbed %.4f %.4f, under the pixel after %.4f %.4f", i, TO_DEG(yaw), TO_DEG(pitch),
                     TO_DEG(yaw1), TO_DEG(pitch1));
    }
    printf("  grab: %u of 20000 solvable, worst %.2g degrees\n", exact, worst);
    assert_true(exact > 15000);
}

static psc_motion_t motion_at(double hfov)
{
    psc_motion_config_t c = { .yaw_rate_max = DEG(90), .pitch_rate_max = DEG(60), .hfov_rate_max = DEG(45),
                              .accel = DEG(360), .inertia_half_life_us = 120000, .home_half_life_us = 150000,
                              .pitch_min = -(int32_t)PSC_BAM_90, .pitch_max = (int32_t)PSC_BAM_90,
                              .hfov_min = (psc_bam_t)DEG(10), .hfov_max = (psc_bam_t)DEG(120) };
    psc_motion_t m;

    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(hfov));
    return m;
}

static void send(psc_gestures_t *g, const psc_motion_t *m, psc_hal_input_type_t type, uint16_t id, int x, int y,
                 int32_t value, uint64_t t)
{
    psc_hal_input_event_t ev = { .type = type, .code = id, .x = (int16_t)x, .y = (int16_t)y, .value = value,
                                 .time_us = t };
    assert_true(psc_gestures_event(g, &ev, m));
}

/* Drag: the point under the pointer stays there; let go moving: a flick; held still: none. */
static void test_drag_and_flick(void **state)
{
    psc_gestures_t g;
    psc_motion_t m = motion_at(90);
    psc_view_t v0 = { .yaw = m.yaw, .pitch = m.pitch, .hfov = m.hfov };
    psc_bam_t gy;
    int32_t gp;
    uint64_t t = 1000000;
    (void)state;

    psc_gestures_init(&g, W, H);
    psc_view_unproject(&v0, W, H, 100, 200, &gy, &gp);
    send(&g, &m, PSC_HAL_INPUT_POINTER_DOWN, 0, 100, 200, 0, t);
    for (int k = 1; k <= 10; k++) {
        t += 16667;
        send(&g, &m, PSC_HAL_INPUT_POINTER_MOVE, 0, 100 + 30 * k, 200 - 5 * k, 0, t);
        assert_true(psc_gestures_apply(&g, &m, t));
        psc_view_t v = { .yaw = m.yaw, .pitch = m.pitch, .hfov = m.hfov };
        psc_bam_t y;
        int32_t p;
        psc_view_unproject(&v, W, H, 100 + 30 * k, 200 - 5 * k, &y, &p);
        assert_true(angle_diff_deg(TO_DEG(y), TO_DEG(gy)) < 0.01 && fabs(TO_DEG(p) - TO_DEG(gp)) < 0.01);
        assert_true(m.yaw_rate == 0 && m.pitch_rate == 0);
    }
    /* dragged right: the view turned left */
    assert_true((int32_t)m.yaw < 0);
    assert_int_equal(g.drags, 1);
    send(&g, &m, PSC_HAL_INPUT_POINTER_UP, 0, 400, 150, 0, t + 1000);
    psc_gestures_apply(&g, &m, t + 16667);
    assert_int_equal(g.flicks, 1);
    assert_true(m.yaw_rate < -DEG(30));   /* about 40 deg/s, the drag's own speed, coasting on */
    psc_motion_input_t none = { 0, 0, 0 };
    int64_t r0 = m.yaw_rate;
    psc_motion_step(&m, &none, 120000);   /* one inertia half-life */
    assert_true(llabs(m.yaw_rate - r0 / 2) < llabs(r0) / 50);

    /* held still 200 ms before letting go: it stays */
    m = motion_at(90);
    psc_gestures_init(&g, W, H);
    send(&g, &m, PSC_HAL_INPUT_POINTER_DOWN, 0, 100, 200, 0, t);
    send(&g, &m, PSC_HAL_INPUT_POINTER_MOVE, 0, 300, 200, 0, t + 20000);
    psc_gestures_apply(&g, &m, t + 20000);
    psc_gestures_apply(&g, &m, t + 220000);
    send(&g, &m, PSC_HAL_INPUT_POINTER_UP, 0, 300, 200, 0, t + 220000);
    psc_gestures_apply(&g, &m, t + 240000);
    assert_int_equal(g.flicks, 0);
    assert_true(m.yaw_rate == 0);
    int32_t x, y;
    assert_false(psc_gestures_take_tap(&g, &x, &y));   /* a drag is no tap */
}

/* Tap, pinch, wheel, a device leaving mid-drag. */
static void test_tap_pinch_wheel(void **state)
{
    psc_gestures_t g;
    psc_motion_t m = motion_at(90);
    int32_t x, y;
    (void)state;

    psc_gestures_init(&g, W, H);
    send(&g, &m, PSC_HAL_INPUT_POINTER_DOWN, 0, 320, 240, 0, 1000000);
    send(&g, &m, PSC_HAL_INPUT_POINTER_MOVE, 0, 325, 243, 0, 1050000);   /* within the slop */
    send(&g, &m, PSC_HAL_INPUT_POINTER_UP, 0, 325, 243, 0, 1100000);
    assert_true(psc_gestures_take_tap(&g, &x, &y));
    assert_true(x == 325 && y == 243);
    assert_false(psc_gestures_take_tap(&g, &x, &y));
    /* too long a press is no tap */
    send(&g, &m, PSC_HAL_INPUT_POINTER_DOWN, 0, 10, 10, 0, 2000000);
    send(&g, &m, PSC_HAL_INPUT_POINTER_UP, 0, 10, 10, 0, 2000000 + PSC_GESTURE_TAP_MS * 1000u + 1);
    assert_false(psc_gestures_take_tap(&g, &x, &y));

    /* pinch: fingers 60 -> 180 pixels apart: a third of the field of view */
    send(&g, &m, PSC_HAL_INPUT_POINTER_DOWN, 3, 290, 240, 0, 3000000);
    send(&g, &m, PSC_HAL_INPUT_POINTER_DOWN, 4, 350, 240, 0, 3000000);
    psc_gestures_apply(&g, &m, 3000000);
    send(&g, &m, PSC_HAL_INPUT_POINTER_MOVE, 3, 230, 240, 0, 3100000);
    send(&g, &m, PSC_HAL_INPUT_POINTER_MOVE, 4, 410, 240, 0, 3100000);
    psc_gestures_apply(&g, &m, 3100000);
    assert_true(fabs(TO_DEG(m.hfov) - 30.0) < 0.01);
    assert_int_equal(g.pinches, 1);
    send(&g, &m, PSC_HAL_INPUT_POINTER_UP, 4, 410, 240, 0, 3200000);
    assert_true(g.grabbing);   /* the finger left down grabs */
    send(&g, &m, PSC_HAL_INPUT_POINTER_UP, 3, 230, 240, 0, 3200000);
    assert_false(psc_gestures_take_tap(&g, &x, &y));

    /* wheel: four notches halve the field of view, four out double it back; the limits hold */
    m = motion_at(80);
    send(&g, &m, PSC_HAL_INPUT_WHEEL, 0, 0, 0, 4, 4000000);
    psc_gestures_apply(&g, &m, 4000000);
    assert_true(fabs(TO_DEG(m.hfov) - 40.0) < 0.01);
    send(&g, &m, PSC_HAL_INPUT_WHEEL, 0, 0, 0, -4, 4000000);
    psc_gestures_apply(&g, &m, 4000000);
    assert_true(fabs(TO_DEG(m.hfov) - 80.0) < 0.02);
    send(&g, &m, PSC_HAL_INPUT_WHEEL, 0, 0, 0, 30, 4000000);
    psc_gestures_apply(&g, &m, 4000000);
    assert_int_equal(m.hfov, (psc_bam_t)DEG(10));

    /* the touch screen unplugged mid-drag: the grab ends, no tap, no fling */
    m = motion_at(90);
    send(&g, &m, PSC_HAL_INPUT_POINTER_DOWN, 0, 100, 100, 0, 5000000);
    send(&g, &m, PSC_HAL_INPUT_POINTER_MOVE, 0, 300, 100, 0, 5016000);
    psc_gestures_apply(&g, &m, 5016000);
    psc_hal_input_event_t leave = { .type = PSC_HAL_INPUT_DEVICE_LEAVE, .time_us = 5020000 };
    assert_false(psc_gestures_event(&g, &leave, &m));
    psc_gestures_apply(&g, &m, 5030000);
    assert_false(g.grabbing);
    assert_true(m.yaw_rate == 0);
    assert_false(psc_gestures_take_tap(&g, &x, &y));
    /* contacts beyond the limit are ignored, not stored */
    send(&g, &m, PSC_HAL_INPUT_POINTER_DOWN, PSC_HAL_POINTER_MAX, 1, 1, 0, 6000000);
    assert_int_equal(g.down_count, 0);
}

#define MIN_BOARD "display = sim\ndisplay_size = 96x64\ninput = sim\nclock = sim\n"

static int parse(const char *body, psc_board_config_t *cfg, char *err, size_t errlen)
{
    char text[4096];

    snprintf(text, sizeof text, "%s%s", MIN_BOARD, body);
    psc_board_config_defaults(cfg);
    err[0] = '\0';
    return psc_board_config_parse(text, strlen(text), "t/board.conf", cfg, err, errlen);
}

static void expect_error(const char *body, const char *line, const char *mention)
{
    psc_board_config_t cfg;
    char err[512];

    if (parse(body, &cfg, err, sizeof err) == 0)
        fail_msg("accepted: %s", body);
    if (strstr(err, line) == NULL || strstr(err, mention) == NULL)
        fail_msg("error '%s' should name '%s' and '%s'", err, line, mention);
}

static void test_board_scene_ids_and_labels(void **state)
{
    psc_board_config_t cfg;
    char err[512];
    (void)state;

    if (parse("scene.lobby = a.pano\n"
              "scene.lobby.title = The Lobby\n"
              "scene = b.pano\n"
              "scene.garden_2 = c.pano\n"
              "scene.garden_2.title = Garden\n"
              "scene.garden_2.view = -30.5 10 75\n"
              "hotspot = lobby 10 0 5 -> garden_2 180 0 80\n"
              "hotspot = garden_2 170 0 5 -> lobby 0 0 90 \"Back inside\"\n"
              "hotspot = 1 0 0 5 -> 0 0 0 90 To the lobby, please\n"
              "hotspot = 0 0 0 5 -> 1 0 0 90\n"
              "scene_fade_ms = 400\n",
              &cfg, err, sizeof err) != 0)
        fail_msg("refused: %s", err);
    assert_int_equal(cfg.scene_count, 3);
    assert_string_equal(cfg.scene_ids[0], "lobby");
    assert_string_equal(cfg.scene_ids[1], "");
    assert_string_equal(cfg.scenes[2], "c.pano");
    assert_string_equal(cfg.scene_titles[0], "The Lobby");
    assert_false(cfg.scene_has_view[0]);
    assert_true(cfg.scene_has_view[2]);
    assert_int_equal(cfg.scene_view_mdeg[2][0], -30500);
    assert_int_equal(cfg.scene_view_mdeg[2][2], 75000);
    assert_int_equal(cfg.scene_fade_ms, 400);
    assert_int_equal(cfg.hotspots[0].from_scene, 0);
    assert_int_equal(cfg.hotspots[0].to_scene, 2);
    assert_string_equal(cfg.hotspots[0].label, "Garden");   /* the target's title */
    assert_int_equal(cfg.hotspots[1].from_scene, 2);
    assert_int_equal(cfg.hotspots[1].to_scene, 0);
    assert_string_equal(cfg.hotspots[1].label, "Back inside");
    assert_string_equal(cfg.hotspots[2].label, "To the lobby, please");
    assert_string_equal(cfg.hotspots[3].label, "");   /* scene 1 has no title */

    /* lines 1-4 are MIN_BOARD */
    expect_error("hotspot = lobby 0 0 5 -> hall 0 0 90\nscene.lobby = a.pano\n", "t/board.conf:5:", "'hall'");
    expect_error("scene.9lobby = a.pano\n", "t/board.conf:5:", "lower-case letter");
    expect_error("scene.lobby.title = x\n", "t/board.conf:5:", "no scene 'lobby' declared above");
    expect_error("scene.a = a.pano\nscene.a = b.pano\n", "t/board.conf:6:", "declared twice");
    expect_error("scene.a = a.pano\nscene.a.view = 0 95 90\n", "t/board.conf:6:", "YAW PITCH HFOV");
    expect_error("scene.a = a.pano\nscene.a.view = 0 0\n", "t/board.conf:6:", "YAW PITCH HFOV");
    expect_error("scene.a = a.pano\nscene.a.zoom = 1\n", "t/board.conf:6:", "unknown key 'scene.a.zoom'");
    expect_error("hotspot = 0 0 0 5 -> 1 0 0 90 This label is far too long to fit beside a marker at all\n",
                 "t/board.conf:5:", "longer than 47");
    expect_error("scene_fade_ms = 6000\n", "t/board.conf:5:", "scene_fade_ms");
}

/* A tap near a marker picks it; far from every one, nothing. */
static void test_pick_at(void **state)
{
    psc_board_config_t cfg;
    char err[512];
    psc_view_t v = { .yaw = 0, .pitch = 0, .hfov = (psc_bam_t)DEG(90) };
    int32_t x, y;
    (void)state;

    assert_int_equal(parse("scene = a\nscene = b\nhotspot = 0 20 0 3 -> 1 0 0 90\nhotspot = 0 -20 5 3 -> 1 0 0 90\n",
                           &cfg, err, sizeof err), 0);
    assert_true(psc_hotspot_project(&v, W, H, cfg.hotspots[1].yaw, cfg.hotspots[1].pitch, &x, &y));
    assert_int_equal(psc_hotspot_pick_at(cfg.hotspots, 2, 0, &v, W, H, x + 10, y - 10, 30), 1);
    assert_int_equal(psc_hotspot_pick_at(cfg.hotspots, 2, 0, &v, W, H, W / 2, H / 2, 30), -1);
    assert_int_equal(psc_hotspot_pick_at(cfg.hotspots, 2, 1, &v, W, H, x, y, 30), -1);   /* scene 1 has none */
}

static void write_text(const char *path, const char *text)
{
    assert_int_equal(tsup_write_bytes(path, text, strlen(text)), 0);
}

/* The sim board: tap the marker -> scene 1 (fading), back -> scene 0 at the view it had. */
static void test_sim_board_tap_back_fade(void **state)
{
    const char *tmp = getenv("PSC_TEST_TMPDIR");
    char root[256], dir[300], conf[2048], path[400], pack[400], tourf[400], dumps[4][400], err[512];
    static const unsigned frames[4] = { 10, 16, 40, 75 };
    (void)state;

    snprintf(root, sizeof root, "%s/test_gestures_%ld", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    mkdir(root, 0755);
    snprintf(dir, sizeof dir, "%s/b", root);
    mkdir(dir, 0755);
    snprintf(pack, sizeof pack, "%s/tiny.pano", root);
    if (tsup_write_synth_pack(pack, 256, 128, 96, 64, 32, 24, err, sizeof err) != 0)
        fail_msg("pack: %s", err);
    /* the hotspot sits at the home view's centre: a tap there at 0.4 s follows it; back at 2 s */
    snprintf(tourf, sizeof tourf, "%s/tour.txt", root);
    write_text(tourf, "at 0.4s tap 48 32\nat 2s back\nat 3s end\n");
    snprintf(path, sizeof path, "%s/board.conf", dir);
    snprintf(conf, sizeof conf,
             "display = sim\ndisplay_size = 96x64\ndisplay_format = xrgb8888\nframe_rate = 30\n"
             "input = sim\nclock = sim\nquality = fixed\n"
             "scene.hall = %s\nscene.hall.view = 15 0 90\nscene.yard = %s\nscene.yard.title = Yard\n"
             "scene_fade_ms = 300\n"
             "hotspot = hall 15 0 4 -> yard 100 0 60\n",
             pack, pack);
    write_text(path, conf);

    psc_cli_options_t opt;
    memset(&opt, 0, sizeof opt);
    opt.board = "b";
    opt.boards_dir = root;
    opt.tour = tourf;
    opt.frames_every = 0;
    opt.quiet = true;
    for (unsigned i = 0; i < 4; i++) {
        snprintf(dumps[i], sizeof dumps[i], "%s/f%u.raw", root, frames[i]);
        opt.dumps[i] = (psc_cli_dump_t){ frames[i], dumps[i] };
    }
    opt.dump_count = 4;
    psc_app_t *app = NULL;
    psc_app_stats_t st;
    if (psc_app_open(&opt, &app, err, sizeof err) != 0)
        fail_msg("psc_app_open: %s", err);
    memset(&st, 0, sizeof st);
    if (psc_app_run(app, &st, err, sizeof err) != 0)
        fail_msg("psc_app_run: %s", err);
    psc_app_close(app);
    assert_int_equal(st.hotspot_follows, 1);   /* the tap, not select */
    assert_int_equal(st.scene_switches, 2);    /* there and back */

    size_t n[4];
    uint8_t *f[4];
    for (unsigned i = 0; i < 4; i++) {
        f[i] = tsup_read_bytes(dumps[i], &n[i]);
        assert_non_null(f[i]);
        assert_int_equal(n[i], 96 * 64 * 4);
    }
    /* frame 10: the hall before the tap (its marker and label drawn); frame 75: back in the hall,
     * the fade over, the view it had: the same bytes */
    assert_memory_equal(f[0], f[3], n[0]);
    /* frame 16, 0.13 s into the 0.3 s fade: neither the hall nor the yard (frame 40) but between them */
    assert_true(memcmp(f[1], f[0], n[0]) != 0 && memcmp(f[1], f[2], n[0]) != 0);
    unsigned between = 0, total = 0;
    for (size_t k = 0; k < n[0]; k++) {
        if (k % 4 == 3 || f[0][k] == f[2][k])
            continue;
        int lo = f[0][k] < f[2][k] ? f[0][k] : f[2][k], hi = f[0][k] ^ f[2][k] ^ lo;
        total++;
        between += f[1][k] >= lo - 1 && f[1][k] <= hi + 1;
    }
    printf("  fade: %u of %u changing channels between the two scenes' values at frame 16\n", between, total);
    assert_true(total > 1000 && between * 100u >= total * 97u);
    for (unsigned i = 0; i < 4; i++) {
        free(f[i]);
        unlink(dumps[i]);
    }
    unlink(path);
    unlink(pack);
    unlink(tourf);
    rmdir(dir);
    rmdir(root);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_unproject_matches_double),
        cmocka_unit_test(test_grab_keeps_direction_under_pixel),
        cmocka_unit_test(test_drag_and_flick),
        cmocka_unit_test(test_tap_pinch_wheel),
        cmocka_unit_test(test_board_scene_ids_and_labels),
        cmocka_unit_test(test_pick_at),
        cmocka_unit_test(test_sim_board_tap_back_fade),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
