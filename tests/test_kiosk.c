/* SPDX-License-Identifier: MIT */
/*
 * test_kiosk.c - the kiosk behaviours: attract mode (firmware/attract.h) and
 * hotspots linking scenes (firmware/hotspots.h): timing on a deterministic
 * clock, the hand-back without a jump, hotspot lines and their errors, the
 * select geometry (yaw wrap-around, poles), where markers land and what they
 * draw, and the sim board following a hotspot to the target view, bit-exact.
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
#include "attract.h"
#include "board_config.h"
#include "hotspots.h"
#include "motion.h"
#include "psc_io_pack_build.h"
#include "base/psc_pixel.h"
#include "psc_testsupport.h"
#include "tsup_pack.h"
#include "psc_io_load.h"

#define DEG(d) ((int64_t)llround((d) / 360.0 * 4294967296.0)) /* degrees -> bam, any sign */
#define BAM_TO_DEG(b) ((double)(int32_t)(b) * 360.0 / 4294967296.0)

/* ---- attract mode ---------------------------------------------------------------- */

static void test_attract_timing_and_rate(void **state)
{
    (void)state;
    psc_attract_t a;
    psc_bam_t yaw;
    int32_t pitch;
    const uint64_t t0 = 1234567;

    /* 5 s idle, 6 deg/s: not a microsecond early, exactly on time */
    psc_attract_init(&a, 5000, DEG(6), t0);
    assert_false(psc_attract_update(&a, t0 + 4999999, 0, 0));
    assert_false(a.active);
    assert_true(psc_attract_update(&a, t0 + 5000000, (psc_bam_t)DEG(30), (int32_t)DEG(20)));
    assert_int_equal(a.start_us, t0 + 5000000);
    /* the start is the view on screen: no jump when attract takes over */
    psc_attract_view(&a, t0 + 5000000, 0, &yaw, &pitch);
    assert_int_equal(yaw, (psc_bam_t)DEG(30));
    assert_int_equal(pitch, (int32_t)DEG(20));
    /* the rate: 10 s later 60 degrees further - exactly 10 x the rate in bam/s
     * (so within half a bam per second of the decimal degrees) */
    psc_attract_view(&a, t0 + 15000000, 0, &yaw, &pitch);
    assert_int_equal(yaw, (psc_bam_t)(DEG(30) + 10 * DEG(6)));
    assert_true(llabs((int64_t)(int32_t)(yaw - (psc_bam_t)DEG(90))) <= 5);
    psc_attract_view(&a, t0 + 5250000, 0, &yaw, &pitch);   /* a quarter second: 1.5 degrees, rounded */
    assert_int_equal(yaw, (psc_bam_t)(DEG(30) + (DEG(6) + 2) / 4));
    /* the pitch eases toward the default: half-way after one half-life */
    psc_attract_view(&a, t0 + 5000000 + PSC_ATTRACT_PITCH_HALF_LIFE_US, 0, &yaw, &pitch);
    assert_true(llabs(pitch - DEG(10)) <= DEG(0.001));
    psc_attract_view(&a, t0 + 5000000 + PSC_ATTRACT_PITCH_HALF_LIFE_US, (int32_t)DEG(-10), &yaw, &pitch);
    assert_true(llabs(pitch - DEG(5)) <= DEG(0.001));
    /* 3 days of attract (rate x t is 2^62 bam): no overflow, no drift from the rate */
    psc_attract_view(&a, t0 + 5000000 + 259200ull * 1000000u + 500000u, 0, &yaw, &pitch);
    assert_int_equal(yaw, (psc_bam_t)(uint64_t)(DEG(30) + 259200ll * DEG(6) + DEG(6) / 2));
    assert_int_equal(pitch, 0);
    /* frame by frame at 30 Hz the steps are all 0.2 degrees, +-1 bam */
    psc_bam_t prev;
    psc_attract_view(&a, t0 + 5000000, 0, &prev, &pitch);
    for (unsigned f = 1; f <= 90; f++) {
        psc_attract_view(&a, t0 + 5000000 + f * 1000000ull / 30, 0, &yaw, &pitch);
        assert_true(llabs((int64_t)(int32_t)(yaw - prev) - DEG(0.2)) <= 80);   /* frame times are whole us */
        prev = yaw;
    }

    /* input stops it and restarts the idle time */
    assert_true(psc_attract_input(&a, t0 + 20000000));
    assert_false(a.active);
    assert_false(psc_attract_input(&a, t0 + 20000001));   /* already stopped */
    assert_false(psc_attract_update(&a, t0 + 25000000, 0, 0));
    assert_true(psc_attract_update(&a, t0 + 25000001, 0, 0));

    /* a negative rate turns left; idle time 0 never starts */
    psc_attract_init(&a, 1000, -DEG(10), 0);
    assert_true(psc_attract_update(&a, 1000000, 0, 0));
    psc_attract_view(&a, 4000000, 0, &yaw, &pitch);
    assert_true(llabs((int64_t)(int32_t)yaw + DEG(30)) <= 1);
    psc_attract_init(&a, 0, DEG(10), 0);
    assert_false(psc_attract_update(&a, UINT64_MAX / 2, 0, 0));
}

/* The firmware's per-frame camera step (app.c app_step_camera) on the motion model. */
static void kiosk_frame(psc_attract_t *a, psc_motion_t *m, const psc_motion_input_t *in, uint64_t now, uint32_t dt)
{
    if (in->yaw != 0 || in->pitch != 0 || in->zoom != 0)
        psc_attract_input(a, now);
    else
        psc_attract_update(a, now, m->yaw, m->pitch);
    if (!a->active) {
        psc_motion_step(m, in, dt);
        return;
    }
    psc_bam_t yaw;
    int32_t pitch;
    psc_attract_view(a, now, m->home_pitch, &yaw, &pitch);
    m->yaw_rate = m->pitch_rate = m->hfov_rate = 0;
    psc_motion_set_view(m, yaw, pitch, m->hfov);
}

static void test_attract_hands_back_without_jump(void **state)
{
    (void)state;
    psc_motion_config_t c = {
        .yaw_rate_max = DEG(90), .pitch_rate_max = DEG(60), .hfov_rate_max = DEG(45), .accel = DEG(360),
        .inertia_half_life_us = 120000, .home_half_life_us = 150000, .pitch_min = -(int32_t)DEG(90),
        .pitch_max = (int32_t)DEG(90), .hfov_min = (psc_bam_t)DEG(20), .hfov_max = (psc_bam_t)DEG(120),
    };
    psc_motion_t m;
    psc_attract_t a;
    psc_motion_input_t none = { 0, 0, 0 }, left = { -32768, 0, 0 };
    const uint32_t dt = 33333;
    uint64_t now = 0;
    unsigned f, started = 0;

    psc_motion_init(&m, &c, 0, 0, (psc_bam_t)DEG(90));
    psc_attract_init(&a, 2000, DEG(8), 0);
    /* look up for half a second, then leave it: attract starts 2 s after the release */
    for (f = 0; f < 15; f++, now += dt)
        kiosk_frame(&a, &m, &(psc_motion_input_t){ 0, 32767, 0 }, now, dt);
    uint64_t released = now - dt;   /* the last frame with the stick up */
    int32_t pitch_up = 0;
    for (; f < 150; f++, now += dt) {
        bool was = a.active;
        kiosk_frame(&a, &m, &none, now, dt);
        if (!was && a.active) {
            started = f;
            assert_true(now >= released + 2000000 && now < released + 2000000 + dt);
            pitch_up = m.pitch;
        }
    }
    assert_true(started > 0);
    assert_true(pitch_up > DEG(15));
    assert_true(m.pitch < pitch_up && m.pitch > 0);   /* easing down toward the default 0 */
    assert_true((int32_t)m.yaw > DEG(8 * 2));          /* turning right */

    /* a full stick to the left: the first frame continues from the attract view;
     * the only change is the motion model's first step from rest */
    psc_bam_t yaw_before = m.yaw;
    int32_t pitch_before = m.pitch;
    kiosk_frame(&a, &m, &left, now, dt);
    now += dt;
    assert_false(a.active);
    int64_t step = (int32_t)(m.yaw - yaw_before);
    assert_true(step <= 0 && step >= -DEG(0.45));     /* accel x dt^2 = 0.4 deg */
    assert_int_equal(m.pitch, pitch_before);
    /* released: it coasts to a stop and stays (no attract spin left behind) */
    for (f = 0; f < 30; f++, now += dt)
        kiosk_frame(&a, &m, &none, now, dt);
    assert_false(a.active);
    assert_int_equal(m.yaw_rate, 0);
    psc_bam_t rest = m.yaw;
    kiosk_frame(&a, &m, &none, now, dt);
    assert_int_equal(m.yaw, rest);
}

/* ---- hotspot lines --------------------------------------------------------------- */

static const char *const MIN_BOARD = "display = sim\ndisplay_size = 320x240\ninput = sim\nclock = sim\n"
                                     "scene = a.pano\nscene = b.pano\n";

static int parse_board(const char *body, psc_board_config_t *cfg, char *err, size_t errlen)
{
    char text[2048];

    snprintf(text, sizeof text, "%s%s", MIN_BOARD, body);
    psc_board_config_defaults(cfg);
    err[0] = 0;
    return psc_board_config_parse(text, strlen(text), "t/board.conf", cfg, err, errlen);
}

static void expect_board_error(const char *body, const char *where, const char *mention)
{
    psc_board_config_t cfg;
    char err[512];

    if (parse_board(body, &cfg, err, sizeof err) == 0)
        fail_msg("accepted: \"%s\"", body);
    if (!strstr(err, where) || (mention && !strstr(err, mention)))
        fail_msg("board error \"%s\" should contain \"%s\" and \"%s\"", err, where, mention ? mention : "");
}

static void test_hotspot_lines(void **state)
{
    (void)state;
    psc_board_config_t cfg;
    char err[512];

    if (parse_board("attract_idle_s = 2.5\nattract_rate = -7.5\n"
                    "hotspot = 0 45 -5.5 10 -> 1 -180 0 90   # a door\n"
                    "hotspot\t=\t1\t350\t89.9\t0.1\t->\t0\t0.001\t-90\t170\n",
                    &cfg, err, sizeof err) != 0)
        fail_msg("valid hotspots refused: %s", err);
    assert_int_equal(cfg.attract_idle_ms, 2500);
    assert_int_equal(cfg.attract_rate_mdeg, -7500);
    assert_int_equal(cfg.hotspot_count, 2);
    const psc_hotspot_t *h = &cfg.hotspots[0];
    assert_int_equal(h->from_scene, 0);
    assert_int_equal(h->yaw, (psc_bam_t)DEG(45));
    assert_int_equal(h->pitch, (int32_t)DEG(-5.5));
    assert_int_equal(h->radius, (psc_bam_t)DEG(10));
    assert_int_equal(h->to_scene, 1);
    assert_int_equal(h->to_yaw, (psc_bam_t)DEG(180));
    assert_int_equal(h->to_pitch, 0);
    assert_int_equal(h->to_hfov, (psc_bam_t)DEG(90));
    assert_int_equal(h->line, 9);
    h = &cfg.hotspots[1];
    assert_int_equal(h->yaw, (psc_bam_t)DEG(-10));
    assert_int_equal(h->pitch, (int32_t)DEG(89.9));
    assert_int_equal(h->to_pitch, (int32_t)DEG(-90));
    assert_int_equal(h->to_hfov, (psc_bam_t)DEG(170));
    assert_int_equal(h->line, 10);

    /* defaults: attract off, 5 deg/s; no hotspots */
    assert_int_equal(parse_board("", &cfg, err, sizeof err), 0);
    assert_int_equal(cfg.attract_idle_ms, 0);
    assert_int_equal(cfg.attract_rate_mdeg, 5000);
    assert_int_equal(cfg.hotspot_count, 0);

    /* Lines 1-6 are MIN_BOARD: the first line of body is line 7. */
    expect_board_error("hotspot = 0 45 -5 10 1 180 0 90\n", "t/board.conf:7:", "FROM YAW PITCH RADIUS -> TO");
    expect_board_error("\nhotspot = 0 45 -5 10 ->\n", "t/board.conf:8:", "->");
    /* words after HFOV are the label (test_gestures.c checks labels and ids) */
    assert_int_equal(parse_board("scene = a\nscene = b\nhotspot = 0 45 -5 10 -> 1 180 0 90 7\n", &cfg, err, sizeof err), 0);
    assert_string_equal(cfg.hotspots[0].label, "7");
    expect_board_error("hotspot = 0 45 95 10 -> 1 180 0 90\n", "t/board.conf:7:", "pitch");
    expect_board_error("hotspot = 0 45 5 0 -> 1 180 0 90\n", "t/board.conf:7:", "radius");
    expect_board_error("hotspot = 0 45 5 91 -> 1 180 0 90\n", "t/board.conf:7:", "radius");
    expect_board_error("hotspot = 0 400 5 10 -> 1 180 0 90\n", "t/board.conf:7:", "yaw");
    expect_board_error("hotspot = 0 east 5 10 -> 1 180 0 90\n", "t/board.conf:7:", "'east'");
    expect_board_error("hotspot = 0 45 5 10 -> 1 180 0 0.5\n", "t/board.conf:7:", "target hfov");
    expect_board_error("hotspot = 0 45 5 10 -> 1 180 -91 90\n", "t/board.conf:7:", "target pitch");
    expect_board_error("hotspot = -1 45 5 10 -> 1 180 0 90\n", "t/board.conf:7:", "FROM scene");
    expect_board_error("hotspot = 0.5 45 5 10 -> 1 180 0 90\n", "t/board.conf:7:", "FROM scene");
    expect_board_error("hotspot = 0 45 5 10 => 1 180 0 90\n", "t/board.conf:7:", "->");
    expect_board_error("hotspot =\n", "t/board.conf:7:", "hotspot");
    expect_board_error("attract_idle_s = soon\n", "t/board.conf:7:", "attract_idle_s");
    expect_board_error("attract_rate = 100\n", "t/board.conf:7:", "attract_rate");
    /* scene numbers are checked against the scene lines, naming the hotspot's line
     * even when the scenes come later in the file */
    expect_board_error("# two scenes above\nhotspot = 0 45 5 10 -> 2 180 0 90\n", "t/board.conf:8:", "scene 2");
    expect_board_error("hotspot = 3 45 5 10 -> 0 180 0 90\nscene = c.pano\n", "t/board.conf:7:", "3 scenes");
    assert_int_equal(parse_board("hotspot = 0 45 5 10 -> 2 180 0 90\nscene = c.pano\n", &cfg, err, sizeof err), 0);
    /* truncated and corrupt values of every length never crash and never pass */
    const char *full = "0 45 -5.5 10 -> 1 180 0 90";
    psc_hotspot_t hs;
    char why[200], cut[64];
    for (size_t n = 0; n < strlen(full); n++) {
        memcpy(cut, full, n);
        cut[n] = '\0';
        if (n + 1 < strlen(full)) {   /* (cut inside the last number, "9" is a valid hfov) */
            why[0] = '\0';
            assert_int_not_equal(psc_hotspot_parse(cut, &hs, why, sizeof why), 0);
            assert_true(why[0] != '\0');
        }
        strcpy(cut, full);
        cut[n] = (char)(n % 2 ? 'x' : 0x7F);
        if (cut[n] != full[n] && full[n] != ' ' && psc_hotspot_parse(cut, &hs, why, sizeof why) == 0)
            fail_msg("corrupt hotspot accepted: '%s'", cut);
    }
    assert_int_equal(psc_hotspot_parse(full, &hs, why, sizeof why), 0);
    char longer[400];
    memset(longer, '1', sizeof longer - 1);
    longer[sizeof longer - 1] = '\0';
    assert_int_not_equal(psc_hotspot_parse(longer, &hs, why, sizeof why), 0);
}

/* ---- select geometry ------------------------------------------------------------- */

static psc_hotspot_t spot(unsigned from, double yaw, double pitch, double radius, unsigned to)
{
    return (psc_hotspot_t){ .from_scene = (uint8_t)from, .yaw = (psc_bam_t)DEG(yaw), .pitch = (int32_t)DEG(pitch),
                            .radius = (psc_bam_t)DEG(radius), .to_scene = (uint8_t)to,
                            .to_hfov = (psc_bam_t)DEG(90) };
}

static void test_hotspot_selection_geometry(void **state)
{
    (void)state;
    /* the edge of the radius, along yaw at the horizon and along pitch */
    psc_hotspot_t h = spot(0, 30, 0, 10, 1);
    assert_true(psc_hotspot_contains(&h, (psc_bam_t)DEG(39.9), 0));
    assert_false(psc_hotspot_contains(&h, (psc_bam_t)DEG(40.1), 0));
    assert_true(psc_hotspot_contains(&h, (psc_bam_t)DEG(30), (int32_t)DEG(-9.9)));
    assert_false(psc_hotspot_contains(&h, (psc_bam_t)DEG(30), (int32_t)DEG(10.1)));
    /* yaw wrap-around at +-180: 179 and -179 are 2 degrees apart, both ways */
    h = spot(0, 179, 0, 5, 1);
    assert_true(psc_hotspot_contains(&h, (psc_bam_t)DEG(-179), 0));
    assert_true(psc_hotspot_contains(&h, (psc_bam_t)DEG(-176.1), 0));
    assert_false(psc_hotspot_contains(&h, (psc_bam_t)DEG(-175.9), 0));
    assert_false(psc_hotspot_contains(&h, 0, 0));
    h = spot(0, -178, 0, 5, 1);
    assert_true(psc_hotspot_contains(&h, (psc_bam_t)DEG(178), 0));
    assert_true(psc_hotspot_contains(&h, (psc_bam_t)DEG(182), 0));   /* 182 == -178 */
    /* near a pole yaw matters little: 180 degrees of yaw at pitch 89 are 2 degrees */
    h = spot(0, 0, 89, 3, 1);
    assert_true(psc_hotspot_contains(&h, (psc_bam_t)DEG(180), (int32_t)DEG(89)));
    assert_false(psc_hotspot_contains(&h, (psc_bam_t)DEG(180), (int32_t)DEG(87)));
    /* the cosine is the great-circle distance's, against doubles */
    for (int i = 0; i < 50; i++) {
        double y1 = -180 + i * 7.3, p1 = -85 + i * 3.4, y2 = 170 - i * 5.1, p2 = 60 - i * 2.9;
        h = spot(0, y1, p1, 10, 0);
        double want = cos(tsup_angle_between(y1 * TSUP_DEG, p1 * TSUP_DEG, y2 * TSUP_DEG, p2 * TSUP_DEG));
        double got = psc_hotspot_cos_distance(&h, (psc_bam_t)DEG(y2), (int32_t)DEG(p2)) / 1073741824.0;
        assert_true(fabs(got - want) < 1e-7);
    }

    /* pick: the nearest of those containing the centre; other scenes ignored; none -> -1 */
    psc_hotspot_t list[4] = { spot(0, 10, 0, 20, 1), spot(0, 4, 0, 5, 2), spot(1, 0, 0, 30, 3),
                              spot(0, -170, 0, 20, 3) };
    assert_int_equal(psc_hotspot_pick(list, 4, 0, 0, 0), 1);
    assert_int_equal(psc_hotspot_pick(list, 4, 0, (psc_bam_t)DEG(12), 0), 0);
    assert_int_equal(psc_hotspot_pick(list, 4, 0, (psc_bam_t)DEG(180), 0), 3);   /* across the seam */
    assert_int_equal(psc_hotspot_pick(list, 4, 0, (psc_bam_t)DEG(90), 0), -1);
    assert_int_equal(psc_hotspot_pick(list, 4, 1, 0, 0), 2);
    assert_int_equal(psc_hotspot_pick(list, 4, 2, 0, 0), -1);
    assert_int_equal(psc_hotspot_pick(NULL, 0, 0, 0, 0), -1);
}

/* Markers land on the pixel whose ray points at the hotspot (the viewer's projection). */
static void test_hotspot_projection(void **state)
{
    (void)state;
    const unsigned w = 160, h = 120;
    int32_t x, y;
    psc_view_t v = { .yaw = (psc_bam_t)DEG(100), .pitch = 0, .hfov = (psc_bam_t)DEG(60) };

    assert_true(psc_hotspot_project(&v, w, h, v.yaw, 0, &x, &y));
    assert_int_equal(x, w / 2);
    assert_int_equal(y, h / 2);
    /* behind the camera and 90 degrees aside: nothing to draw */
    assert_false(psc_hotspot_project(&v, w, h, v.yaw + PSC_BAM_180, 0, &x, &y));
    assert_false(psc_hotspot_project(&v, w, h, v.yaw + PSC_BAM_90, 0, &x, &y));
    assert_false(psc_hotspot_project(&v, w, h, v.yaw, (int32_t)DEG(90), &x, &y));
    /* right of the centre is right on screen, above is up */
    assert_true(psc_hotspot_project(&v, w, h, v.yaw + (psc_bam_t)DEG(10), (int32_t)DEG(5), &x, &y));
    assert_true(x > (int32_t)w / 2 && y < (int32_t)h / 2);

    /* against the exact ray of the pixel, over views and spots (pitched views, wrap) */
    double worst = 0;
    unsigned checked = 0;
    for (int i = 0; i < 400; i++) {
        psc_view_t view = { .yaw = (psc_bam_t)DEG(-180 + i * 17.7), .pitch = (int32_t)DEG(-70 + (i * 13) % 140),
                            .hfov = (psc_bam_t)DEG(30 + (i * 7) % 100) };
        double hy = BAM_TO_DEG(view.yaw) + ((i * 37) % 80 - 40) * BAM_TO_DEG(view.hfov) / 100.0;
        double hp = BAM_TO_DEG((psc_bam_t)view.pitch) + ((i * 53) % 60 - 30) * BAM_TO_DEG(view.hfov) / 100.0;
        if (hp > 89 || hp < -89)
            continue;
        if (!psc_hotspot_project(&view, w, h, (psc_bam_t)DEG(hy), (int32_t)DEG(hp), &x, &y) || x < 0 || y < 0 ||
            x >= (int32_t)w || y >= (int32_t)h)
            continue;
        double lon, lat;
        tsup_view_ray(&view, w, h, x + 0.5, y + 0.5, &lon, &lat);
        double err = tsup_angle_between(lon, lat, hy * TSUP_DEG, hp * TSUP_DEG) / TSUP_DEG;
        double pixel = BAM_TO_DEG(view.hfov) / w;   /* about one pixel's angle at the centre */
        /* no neighbouring pixel looks at the hotspot closer than the marker's (within
         * a fifth of a pixel: the pixel containing the point is not always the one
         * with the angularly nearest centre, and the integer trigonometry rounds) */
        for (int dy = -2; dy <= 2; dy++)
            for (int dx = -2; dx <= 2; dx++) {
                double lo, la;
                tsup_view_ray(&view, w, h, x + dx + 0.5, y + dy + 0.5, &lo, &la);
                if (tsup_angle_between(lo, la, hy * TSUP_DEG, hp * TSUP_DEG) < (err - 0.2 * pixel) * TSUP_DEG)
                    fail_msg("view %d: pixel %d,%d is nearer the hotspot than the marker's %d,%d", i, x + dx,
                             y + dy, x, y);
            }
        checked++;
        if (err / pixel > worst)
            worst = err / pixel;
    }
    printf("  marker placement: %u views, worst %.2f pixels from the hotspot's direction\n", checked, worst);
    assert_true(checked > 200);
    assert_true(worst < 1.0);
}

/* ---- markers --------------------------------------------------------------------- */

static uint32_t px32(const psc_surface_t *s, int32_t x, int32_t y)
{
    return ((const uint32_t *)s->pixels)[(size_t)y * (s->stride / 4) + (size_t)x];
}

static void test_hotspot_markers(void **state)
{
    (void)state;
    enum { W = 96, H = 64, GREY = 0xFF808080u };
    static uint32_t pix[W * H];
    psc_surface_t s = { .width = W, .height = H, .stride = W * 4, .format = PSC_PIX_XRGB8888, .pixels = pix };
    psc_view_t v = { .yaw = 0, .pitch = 0, .hfov = (psc_bam_t)DEG(90) };
    psc_hotspot_t list[3] = { spot(0, 0, 0, 10, 1), spot(0, 30, 0, 10, 1), spot(1, 0, 0, 10, 0) };
    const int32_t r = PSC_HOTSPOT_MARKER_RADIUS, cx = W / 2, cy = H / 2;

    for (unsigned i = 0; i < W * H; i++)
        pix[i] = GREY;
    assert_int_equal(psc_hotspots_draw(list, 3, 0, &v, &s), 2);
    /* the selectable one (view centre inside its radius) in green: dot, ring, dark edges */
    assert_int_equal(px32(&s, cx, cy), 0xFF000000u | PSC_HOTSPOT_ACTIVE_RGB);
    assert_int_equal(px32(&s, cx + r, cy), 0xFF000000u | PSC_HOTSPOT_ACTIVE_RGB);
    assert_int_equal(px32(&s, cx, cy - r + 1), 0xFF000000u | PSC_HOTSPOT_ACTIVE_RGB);
    assert_int_equal(px32(&s, cx + r + 1, cy), 0xFF000000u | PSC_HOTSPOT_OUTLINE_RGB);
    assert_int_equal(px32(&s, cx + 3, cy), 0xFF000000u | PSC_HOTSPOT_OUTLINE_RGB);
    assert_int_equal(px32(&s, cx + r + 2, cy), GREY);
    assert_int_equal(px32(&s, cx + r, cy + r), GREY);   /* a ring, not a square */
    /* the other, 30 degrees right: white, at the projected pixel */
    int32_t x, y;
    assert_true(psc_hotspot_project(&v, W, H, list[1].yaw, 0, &x, &y));
    assert_true(x > cx + 2 * r && x < W);
    assert_int_equal(px32(&s, x, y), 0xFF000000u | PSC_HOTSPOT_RGB);
    /* nothing but the two markers changed */
    unsigned changed = 0;
    for (unsigned i = 0; i < W * H; i++)
        changed += pix[i] != GREY;
    assert_true(changed > 2u * 2u * 12u && changed <= 2u * 15u * 15u);

    /* turned away: nothing drawn, the frame stays bit-exact */
    for (unsigned i = 0; i < W * H; i++)
        pix[i] = GREY;
    v.yaw = (psc_bam_t)DEG(180);
    assert_int_equal(psc_hotspots_draw(list, 3, 0, &v, &s), 0);
    for (unsigned i = 0; i < W * H; i++)
        assert_int_equal(pix[i], GREY);
    /* half off the left edge: clipped, no write outside the surface */
    v.yaw = (psc_bam_t)DEG(44.5);
    assert_int_equal(psc_hotspots_draw(list, 1, 0, &v, &s), 1);
    /* RGB565, twice the size at 480 lines */
    static uint16_t p16[640 * 480];
    psc_surface_t s16 = { .width = 640, .height = 480, .stride = 1280, .format = PSC_PIX_RGB565, .pixels = p16 };
    v.yaw = 0;
    assert_int_equal(psc_hotspots_draw(list, 3, 0, &v, &s16), 2);
    assert_int_equal(p16[240 * 640 + 320 + 2 * r], psc_xrgb_to_rgb565(PSC_HOTSPOT_ACTIVE_RGB));
    assert_int_equal(p16[240 * 640 + 320 + 2 * r + 2], psc_xrgb_to_rgb565(PSC_HOTSPOT_OUTLINE_RGB));
    assert_int_equal(p16[240 * 640 + 320 + 2 * r + 3], 0);
}

/* ---- the sim board: select follows a hotspot, attract starts ---------------------- */

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static uint8_t *read_all(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    uint8_t *buf = malloc(1 << 20);
    assert_non_null(f);
    assert_non_null(buf);
    *len = fread(buf, 1, 1 << 20, f);
    fclose(f);
    return buf;
}

static void test_sim_board_follows_hotspot(void **state)
{
    (void)state;
    const char *tmp = getenv("PSC_TEST_TMPDIR");
    char root[256], dir[300], path[400], pack[400], tourf[400], dump_a[400], dump_b[400], err[512];
    snprintf(root, sizeof root, "%s/test_kiosk_%ld", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    mkdir(root, 0755);
    snprintf(dir, sizeof dir, "%s/tour", root);
    mkdir(dir, 0755);

    /* a small pack of the synthetic scene */
    snprintf(pack, sizeof pack, "%s/tiny.pano", root);
    if (tsup_write_synth_pack(pack, 256, 128, 96, 64, 32, 24, err, sizeof err) != 0)
        fail_msg("pack: %s", err);

    /* scene 0's home view (yaw 0) is inside hotspot 1 only; select follows it to
     * scene 1 at yaw -120, pitch 20, hfov 70; 1 s after that nobody touches anything */
    snprintf(tourf, sizeof tourf, "%s/tour.txt", root);
    write_text(tourf, "wait 0.2s\nselect\nwait 2.5s\nend\n");
    snprintf(path, sizeof path, "%s/board.conf", dir);
    snprintf(dump_a, sizeof dump_a, "%s/a.raw", root);
    snprintf(dump_b, sizeof dump_b, "%s/b.raw", root);
    char conf[2048];
    snprintf(conf, sizeof conf,
             "display = sim\ndisplay_size = 96x64\ndisplay_format = xrgb8888\nframe_rate = 30\n"
             "input = sim\nclock = sim\nscene = %s\nscene = %s\nquality = fixed\n"
             "attract_idle_s = 1\nattract_rate = 20\n"
             "hotspot = 0 60 0 20 -> 0 0 0 90\n"
             "hotspot = 0 -3 2 10 -> 1 -120 20 70\n",
             pack, pack);
    write_text(path, conf);

    psc_cli_options_t opt;
    memset(&opt, 0, sizeof opt);
    opt.board = "tour";
    opt.boards_dir = root;
    opt.tour = tourf;
    opt.frames_every = 0;
    opt.quiet = true;
    opt.dumps[0] = (psc_cli_dump_t){ 12, dump_a };
    opt.dumps[1] = (psc_cli_dump_t){ 70, dump_b };
    opt.dump_count = 2;
    psc_app_t *app = NULL;
    if (psc_app_open(&opt, &app, err, sizeof err) != 0)
        fail_msg("psc_app_open: %s", err);
    psc_app_stats_t st;
    memset(&st, 0, sizeof st);
    if (psc_app_run(app, &st, err, sizeof err) != 0)
        fail_msg("psc_app_run: %s", err);
    psc_app_close(app);
    printf("  sim board: %u frames, %u hotspot followed, %u scene switch, %u attract start\n", st.frames,
           st.hotspot_follows, st.scene_switches, st.attract_starts);
    assert_int_equal(st.hotspot_follows, 1);
    assert_int_equal(st.scene_switches, 1);
    assert_int_equal(st.attract_starts, 1);

    /* frame 12 is scene 1 at the hotspot's target view, bit for bit what the
     * viewer renders there (scene 1 has no hotspots, so no marker) */
    psc_io_pack_t pf;
    if (psc_io_pack_load(pack, &pf, err, sizeof err) != 0)
        fail_msg("%s", err);
    size_t ws_size = psc_viewer_workspace_size(96, 64, &pf.pack.map);
    void *ws = aligned_alloc(64, (ws_size + 63) & ~(size_t)63);
    psc_viewer_t viewer;
    assert_int_equal(psc_viewer_init(&viewer, &pf.pack.map, pf.pack.luts, pf.pack.lut_count, 96, 64, ws, ws_size),
                     PSC_OK);
    assert_int_equal(psc_viewer_set_levels(&viewer, pf.pack.levels, pf.pack.level_count), PSC_OK);
    static uint32_t want[96 * 64];
    psc_surface_t s = { .width = 96, .height = 64, .stride = 96 * 4, .format = PSC_PIX_XRGB8888, .pixels = want };
    psc_view_t v = { .yaw = (psc_bam_t)DEG(-120), .pitch = (int32_t)DEG(20), .hfov = (psc_bam_t)DEG(70),
                     .filter = PSC_FILTER_MIP, .span_log2 = PSC_SPAN_LOG2_DEFAULT };
    psc_viewer_clamp(&viewer, &v, pf.pack.hfov_min);
    assert_int_equal(v.hfov, (psc_bam_t)DEG(70));
    assert_int_equal(psc_viewer_render(&viewer, &v, &s), PSC_OK);
    size_t got_len;
    uint8_t *got = read_all(dump_a, &got_len);
    assert_int_equal(got_len, sizeof want);
    assert_memory_equal(got, want, sizeof want);
    free(got);
    /* frame 70: attract turned it (started 1 s after the select's release) */
    got = read_all(dump_b, &got_len);
    assert_int_equal(got_len, sizeof want);
    assert_true(memcmp(got, want, sizeof want) != 0);
    free(got);
    free(ws);
    psc_io_pack_free(&pf);

    /* --scene replaces the list: hotspots are dropped, select does nothing */
    opt.scene = pack;
    opt.dump_count = 0;
    if (psc_app_open(&opt, &app, err, sizeof err) != 0)
        fail_msg("psc_app_open: %s", err);
    assert_int_equal(psc_app_run(app, &st, err, sizeof err), 0);
    psc_app_close(app);
    assert_int_equal(st.hotspot_follows, 0);
    assert_int_equal(st.scene_switches, 0);

    unlink(dump_a);
    unlink(dump_b);
    unlink(path);
    unlink(pack);
    unlink(tourf);
    rmdir(dir);
    rmdir(root);
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_attract_timing_and_rate),
        cmocka_unit_test(test_attract_hands_back_without_jump),
        cmocka_unit_test(test_hotspot_lines),
        cmocka_unit_test(test_hotspot_selection_geometry),
        cmocka_unit_test(test_hotspot_projection),
        cmocka_unit_test(test_hotspot_markers),
        cmocka_unit_test(test_sim_board_follows_hotspot),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
