/* SPDX-License-Identifier: MIT */
/*
 * test_soak.c - the device program for a long time on the simulated board
 * (issue 16): a generated tour that keeps a visitor busy and then leaves -
 * the stick turning and zooming, a hotspot followed, scenes switched both
 * ways, home, long idle spells in which attract mode turns the view, and the
 * gamepad unplugged and plugged again - over two panoramas and a patch
 * character when the sample one is built. Asserts: every frame is drawn,
 * and not one allocation (malloc, calloc, realloc, aligned) is made after
 * start-up (tests/faults/tsup_faults.h counts them), and none is freed.
 *
 * PSC_SOAK_FRAMES sets the length (default 3000: about 100 s of board time,
 * what `make test` runs); `make soak` runs 100000 frames and prints the
 * frame-time distribution (median, p99, max: wall clock, this machine, not
 * asserted - no timing in tests).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "app.h"
#include "cli.h"
#include "psc_testsupport.h"
#include "tsup_faults.h"
#include "tsup_files.h"
#include "tsup_pack.h"
#include "psc_io_image.h"

#include <png.h>

#define SOAK_W 320
#define SOAK_H 240

static char root[400];

static void write_text(const char *path, const char *text)
{
    assert_int_equal(tsup_write_bytes(path, text, strlen(text)), 0);
}

/* One 35-second visit, repeated: a visitor, then nobody (attract), then a gamepad coming and going. */
static const char soak_visit[] =
    "hold 3s axis yaw 0.8\n"
    "hold 1s axis pitch 0.5\n"
    "hold 1.5s zoom_in\n"
    "press home\n"
    "wait 1s\n"
    "press select\n"          /* the hotspot the home view looks at: to scene 1 */
    "wait 1s\n"
    "press next_scene\n"
    "wait 0.5s\n"
    "press prev_scene\n"
    "wait 0.5s\n"
    "press prev_scene\n"
    "wait 8s\n"               /* nobody: attract mode (after 5 s) turns the view */
    "press home\n"
    "plug 1\n"
    "device 1\n"
    "hold 2s axis yaw -1.0\n"
    "hold 1s axis zoom -0.7\n"
    "unplug 1\n"              /* the gamepad pulled out mid-visit */
    "device 0\n"
    "wait 1s\n"
    "plug 1\n"
    "device 1\n"
    "press next_scene\n"
    "wait 0.5s\n"
    "unplug 1\n"
    "device 0\n"
    "drag 300ms 60 60 200 80\n"  /* a flick: the view coasts */
    "wait 1s\n"
    "pinch 300ms 160 120 40 100\n"
    "wheel -2\n"
    "wait 1s\n"
    "press back\n"           /* back through the scenes left, each a cross-fade */
    "wait 1s\n"
    "press back\n"
    "wait 10.4s\n";

/* The soak's board: two panoramas with hotspots between them (and Thom when out/thom.ppk is built). */
static void soak_board(uint32_t frames)
{
    char path[600], pack0[500], pack1[500], tour[500], conf[4096], err[300];
    const char *tmp = getenv("PSC_TEST_TMPDIR");

    snprintf(root, sizeof root, "%s/test_soak_%ld", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    mkdir(root, 0755);
    snprintf(path, sizeof path, "%s/soak", root);
    mkdir(path, 0755);
    snprintf(pack0, sizeof pack0, "%s/a.pano", root);
    snprintf(pack1, sizeof pack1, "%s/b.pano", root);
    if (tsup_write_synth_pack(pack0, 512, 256, SOAK_W, SOAK_H, 32, 128, err, sizeof err) != 0 ||
        tsup_write_synth_pack(pack1, 1024, 512, SOAK_W, SOAK_H, 32, 128, err, sizeof err) != 0)
        fail_msg("pack: %s", err);
    /* enough visits for the frames asked (30 frames/s, 35 s a visit: 30 counted, to spare), within the
     * tour's event limit */
    unsigned visits = frames / (30u * 30u) + 2u;
    size_t len = visits * sizeof soak_visit + 16;
    char *text = malloc(len), *p = text;
    assert_non_null(text);
    for (unsigned i = 0; i < visits; i++)
        p += sprintf(p, "%s", soak_visit);
    sprintf(p, "end\n");
    snprintf(tour, sizeof tour, "%s/tour.txt", root);
    write_text(tour, text);
    free(text);
    bool thom = tsup_thom_scene_line()[0] != '\0';
    snprintf(conf, sizeof conf,
             "display = sim\ndisplay_size = %ux%u\ndisplay_format = rgb565\nframe_rate = 30\n"
             "input = sim\ntour = %s\nclock = sim\nwatchdog = sim\nwatchdog_timeout_ms = 2000\n"
             "frames_every = 0\nscene = %s\nscene = %s\n%s"
             "attract_idle_s = 5\nattract_rate = 10\n"
             "hotspot = 0 0 0 15 -> 1 180 0 90\nhotspot = 1 0 -5 20 -> 0 90 0 75\nscene_fade_ms = 300\n"
             "quality = adaptive\nquality_fast_speed = 0.6\n",
             SOAK_W, SOAK_H, tour, pack0, pack1, tsup_thom_scene_line());
    snprintf(path, sizeof path, "%s/soak/board.conf", root);
    write_text(path, conf);
    printf("  soak board: two panoramas%s, %u visits of 35 s\n", thom ? " and Thom" : " (out/thom.ppk not built)",
           visits);
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

static void test_soak(void **state)
{
    (void)state;
    const char *env = getenv("PSC_SOAK_FRAMES");
    uint32_t frames = env && *env ? (uint32_t)strtoul(env, NULL, 10) : 3000u;
    psc_cli_options_t opt = {.board = "soak", .frames_every = 0, .quiet = true, .max_frames = frames};
    psc_app_stats_t st;
    psc_app_t *app = NULL;
    char err[600];

    assert_true(frames > 0);
    /* the count is real: an allocation in the window is seen (volatile: not optimised away) */
    tsup_faults_start(0, 0);
    void *volatile probe = malloc(24);
    free(probe);
    tsup_faults_stats_t probe_count = tsup_faults_stop();
    assert_int_equal(probe_count.allocations, 1);
    assert_int_equal(probe_count.frees, 1);
    soak_board(frames);
    opt.boards_dir = root;
    uint32_t *times = calloc(frames, sizeof *times);
    assert_non_null(times);
    if (psc_app_open(&opt, &app, err, sizeof err) != 0)
        fail_msg("psc_app_open: %s", err);
    psc_app_record_frame_times(app, times, frames);

    tsup_faults_start(0, 0);   /* count from the first frame on */
    int rc = psc_app_run(app, &st, err, sizeof err);
    tsup_faults_stats_t c = tsup_faults_stop();
    psc_app_close(app);
    if (rc != 0)
        fail_msg("psc_app_run: %s", err);

    printf("  %u frames (%llu.%03llu s of board time): %u scene switches, %u hotspots followed, %u attract starts, "
           "%u fast frames\n", (unsigned)st.frames, (unsigned long long)(st.sim_time_us / 1000000u),
           (unsigned long long)(st.sim_time_us / 1000u % 1000u), (unsigned)st.scene_switches,
           (unsigned)st.hotspot_follows, (unsigned)st.attract_starts, (unsigned)st.fast_frames);
    printf("  after start-up: %llu allocations, %llu frees\n", (unsigned long long)c.allocations,
           (unsigned long long)c.frees);
    qsort(times, frames, sizeof *times, cmp_u32);
    printf("  frame time (wall clock, this machine): median %u us, p99 %u us, max %u us\n",
           (unsigned)times[frames / 2], (unsigned)times[(uint64_t)frames * 99u / 100u], (unsigned)times[frames - 1]);
    free(times);

    assert_int_equal(st.frames, frames);
    /* the tour did what a soak is for (each visit has a hotspot, scene switches, an attract spell) */
    assert_true(st.hotspot_follows >= frames / 1050u);
    assert_true(st.scene_switches >= 3u * (frames / 1050u));
    assert_true(st.attract_starts >= frames / 1050u);
    assert_int_equal(c.allocations, 0);
    assert_int_equal(c.frees, 0);
}

/* The window the soak counts in sees what is allocated out of sight too: inside the C library (strdup, fopen's
 * FILE) and inside a shared library (libpng's read structures, a whole PNG decoded through io), each counted and
 * each freed. */
static void test_window_sees_library_allocations(void **state)
{
    (void)state;
    char path[512], err[300];
    tsup_tmp_path(path, sizeof path, "test_soak", "probe.png");
    psc_image_t img = {.width = 8, .height = 4};
    img.xrgb = calloc(8 * 4, sizeof *img.xrgb);
    assert_non_null(img.xrgb);
    if (psc_io_image_write_png(path, &img, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_io_image_free(&img);

    tsup_faults_start(0, 0);
    char *volatile copy = strdup("probe");
    tsup_faults_stats_t after_strdup = tsup_faults_now();
    free(copy);
    FILE *f = fopen(path, "rb");
    tsup_faults_stats_t after_fopen = tsup_faults_now();
    assert_non_null(f);
    fclose(f);
    tsup_faults_stats_t before_png = tsup_faults_now();
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    tsup_faults_stats_t after_png = tsup_faults_now();
    png_destroy_read_struct(&png, &info, NULL);
    tsup_faults_stats_t before_decode = tsup_faults_now();
    psc_image_t back;
    int rc = psc_io_image_load(path, &back, err, sizeof err);
    tsup_faults_stats_t after_decode = tsup_faults_now();
    if (rc == 0)
        psc_io_image_free(&back);
    tsup_faults_stats_t end = tsup_faults_stop();
    remove(path);
    printf("  counted: strdup %llu, fopen %llu, libpng's read structures %llu, a PNG decoded %llu allocations; "
           "%llu allocated and %llu freed in all\n", (unsigned long long)after_strdup.allocations,
           (unsigned long long)(after_fopen.allocations - after_strdup.allocations),
           (unsigned long long)(after_png.allocations - before_png.allocations),
           (unsigned long long)(after_decode.allocations - before_decode.allocations),
           (unsigned long long)end.allocations, (unsigned long long)end.frees);
    assert_int_equal(rc, 0);
    assert_int_equal(after_strdup.allocations, 1);
    assert_true(after_fopen.allocations > after_strdup.allocations);
    assert_true(after_png.allocations >= before_png.allocations + 2);   /* png_struct and png_info, in libpng */
    assert_true(after_decode.allocations > before_decode.allocations + 1);   /* libpng's, beside io's pixels */
    assert_int_equal(end.frees, end.allocations);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_window_sees_library_allocations),
        cmocka_unit_test(test_soak),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
