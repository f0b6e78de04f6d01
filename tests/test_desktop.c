/* SPDX-License-Identifier: MIT */
/*
 * test_desktop.c - the desktop preview as a content author uses it: the real
 * device program in an SDL window on an X server (Xvfb, with openbox as the
 * window manager, as a desktop has one), driven by xdotool the way a person
 * drives it, its window read back with xwd:
 *  - a click on a hotspot's marker follows it; Backspace comes back;
 *  - grab-drag: dragged 100 pixels, the picture under the pointer moved 100
 *    pixels with it (measured by the best match of the two screenshots);
 *  - the wheel zooms in: the centre row is magnified;
 *  - F11 makes the window fill the screen and F11 again brings it back;
 *  - a resized window shows the whole frame scaled, black bars beside it;
 *  - q quits with status 0.
 * Needs Xvfb, openbox, xdotool and xwd (scripts/install-deps.sh installs
 * them); without them the test says so and is skipped.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define FW 320
#define FH 240

static char tmpdir[512], board_dir[600], log_path[700], shot_path[700];
static char display_name[32];
static pid_t xvfb_pid, wm_pid, fw_pid;
static char window_id[32];

static void sleep_ms(unsigned ms)
{
    struct timespec ts = { ms / 1000u, (long)(ms % 1000u) * 1000000L };
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR) {
    }
}

static bool have(const char *prog)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", prog);
    return system(cmd) == 0;
}

/* Run a shell command with DISPLAY set; its first output line into out (may be NULL). */
static int run(char *out, size_t outlen, const char *fmt, ...)
{
    char cmd[1024];
    va_list ap;
    FILE *p;
    int rc;

    /* every X client under a time limit: a stuck server fails the test instead of hanging it */
    strcpy(cmd, "timeout 20 ");
    va_start(ap, fmt);
    vsnprintf(cmd + strlen(cmd), sizeof cmd - strlen(cmd), fmt, ap);
    va_end(ap);
    p = popen(cmd, "r");
    if (p == NULL)
        return -1;
    if (out != NULL) {
        out[0] = '\0';
        if (fgets(out, (int)outlen, p) != NULL)
            out[strcspn(out, "\n")] = '\0';
    }
    while (fgetc(p) != EOF) {
    }
    rc = pclose(p);
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

static pid_t spawn(const char *const argv[], const char *log)
{
    pid_t pid = fork();

    if (pid == 0) {
        int fd = open(log, O_WRONLY | O_CREAT | O_APPEND, 0600);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
        }
        setpgid(0, 0);
        execvp(argv[0], (char *const *)argv);
        _exit(127);
    }
    return pid;
}

/* ---- screenshots: xwd of the window's inside, as 0xRRGGBB -------------------------- */

typedef struct {
    uint32_t w, h;
    uint32_t *px;
} shot_t;

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static shot_t shoot(void)
{
    shot_t s = { 0, 0, NULL };
    FILE *f;
    uint8_t hdr[100], *data;
    long size;

    /* a window the manager is still mapping or moving cannot be read for a moment */
    int rc = -1;
    for (int i = 0; i < 20 && (rc = run(NULL, 0, "xwd -silent -id %s -out %s 2>/dev/null", window_id, shot_path)) != 0; i++)
        sleep_ms(100);
    if (rc != 0)
        fail_msg("xwd of window %s failed", window_id);
    f = fopen(shot_path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    size = ftell(f);
    fseek(f, 0, SEEK_SET);
    data = malloc((size_t)size);
    assert_non_null(data);
    assert_int_equal(fread(data, 1, (size_t)size, f), (size_t)size);
    fclose(f);
    memcpy(hdr, data, sizeof hdr);
    uint32_t header_size = be32(hdr), w = be32(hdr + 16), h = be32(hdr + 20), byte_order = be32(hdr + 28);
    uint32_t bpp = be32(hdr + 44) / 8, bpl = be32(hdr + 48), ncolors = be32(hdr + 76);
    size_t off = header_size + (size_t)ncolors * 12u;
    /* Xvfb's depth 24: 3 or 4 bytes a pixel, least significant byte first */
    assert_true((bpp == 3 || bpp == 4) && byte_order == 0);
    assert_true(off + (size_t)bpl * h <= (size_t)size);
    s.w = w;
    s.h = h;
    s.px = malloc((size_t)w * h * 4u);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            const uint8_t *p = data + off + (size_t)y * bpl + (size_t)x * bpp;
            s.px[y * w + x] = (uint32_t)p[2] << 16 | (uint32_t)p[1] << 8 | p[0];
        }
    free(data);
    unlink(shot_path);
    return s;
}

static int pixel_diff(uint32_t a, uint32_t b)
{
    return abs((int)(a >> 16 & 255) - (int)(b >> 16 & 255)) + abs((int)(a >> 8 & 255) - (int)(b >> 8 & 255)) +
           abs((int)(a & 255) - (int)(b & 255));
}

/* The horizontal shift that best maps rows y0..y1, columns x0..x1 of a onto b. */
static int best_shift(const shot_t *a, const shot_t *b, int y0, int y1, int x0, int x1, int lo, int hi)
{
    long best = -1;
    int at = lo;

    for (int s = lo; s <= hi; s++) {
        long err = 0;
        for (int y = y0; y <= y1; y++)
            for (int x = x0; x <= x1; x++)
                err += pixel_diff(a->px[y * (int)a->w + x], b->px[y * (int)b->w + x + s]);
        if (best < 0 || err < best) {
            best = err;
            at = s;
        }
    }
    return at;
}

/* ---- the session ------------------------------------------------------------------- */

static bool log_has(const char *what, unsigned timeout_ms)
{
    for (unsigned t = 0; t <= timeout_ms; t += 100) {
        FILE *f = fopen(log_path, "r");
        char line[512];
        bool found = false;
        while (f != NULL && fgets(line, sizeof line, f) != NULL)
            found = found || strstr(line, what) != NULL;
        if (f != NULL)
            fclose(f);
        if (found)
            return true;
        sleep_ms(100);
    }
    return false;
}

static void window_size(unsigned *w, unsigned *h)
{
    char line[128];
    assert_int_equal(run(line, sizeof line, "xdotool getwindowgeometry --shell %s | grep -E '^(WIDTH|HEIGHT)=' | "
                                            "tr '\\n' ' '", window_id), 0);
    assert_int_equal(sscanf(line, "WIDTH=%u HEIGHT=%u", w, h), 2);
}

/* SIGTERM, then SIGKILL after 3 s: a test must end even if what it started hangs. */
static void stop(pid_t *pid)
{
    int status;

    if (*pid <= 0)
        return;
    kill(*pid, SIGTERM);
    for (int i = 0; i < 30; i++) {
        if (waitpid(*pid, &status, WNOHANG) == *pid) {
            *pid = 0;
            return;
        }
        sleep_ms(100);
    }
    kill(*pid, SIGKILL);
    waitpid(*pid, &status, 0);
    *pid = 0;
}

/* Start openbox and wait until it manages windows; its pid, or 0 if it ended (its log printed). */
static pid_t start_wm(const char *log, int attempt)
{
    const char *wm[] = { "openbox", "--sm-disable", NULL };
    pid_t pid = spawn(wm, log);
    int status = 0, up = 1;

    /* the window manager is up when it says so on the root window */
    for (int i = 0; i < 50 && (up = run(NULL, 0, "xprop -root _NET_SUPPORTING_WM_CHECK 2>/dev/null | "
                                             "grep -q window")) != 0; i++)
        sleep_ms(100);
    if (up != 0) {
        stop(&pid);
        fail_msg("the X server %s or openbox did not answer within 5 s", display_name);
    }
    /* openbox announces itself before it handles map requests: a window mapped in between is never
     * shown, and SDL waits for it forever */
    sleep_ms(1500);
    if (waitpid(pid, &status, WNOHANG) != pid)
        return pid;
    printf("  openbox ended at start-up (attempt %d, %s %d); its log:\n", attempt,
           WIFEXITED(status) ? "exit status" : "signal", WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
    char cmd[800];
    snprintf(cmd, sizeof cmd, "sed 's/^/    /' '%s' | tail -20", log);
    if (system(cmd) != 0)
        printf("    (unreadable)\n");
    /* its check window may still be named on the root window: the next attempt waits for its own */
    run(NULL, 0, "xprop -root -remove _NET_SUPPORTING_WM_CHECK 2>/dev/null");
    return 0;
}

static int setup(void **state)
{
    const char *dir = getenv("PSC_TEST_TMPDIR");
    const char *bin = getenv("PSC_BIN_DIR");
    char prog[600], cwd[400], conf[2048], num[32] = "";
    (void)state;

    if (!have("Xvfb") || !have("xdotool") || !have("xwd") || !have("openbox")) {
        printf("  skipped: needs Xvfb, openbox, xdotool and xwd (sh scripts/install-deps.sh installs them)\n");
        return 0;
    }
    snprintf(prog, sizeof prog, "%s/periscope", bin && *bin ? bin : "build/bin");
    if (access(prog, X_OK) != 0 || access("out/sample.pano", R_OK) != 0 || getcwd(cwd, sizeof cwd) == NULL) {
        printf("  skipped: needs %s and out/sample.pano (make all out/sample.pano)\n", prog);
        return 0;
    }
    snprintf(tmpdir, sizeof tmpdir, "%s/test_desktop_%ld", dir && *dir ? dir : "/tmp", (long)getpid());
    mkdir(tmpdir, 0755);
    snprintf(board_dir, sizeof board_dir, "%s/preview", tmpdir);
    mkdir(board_dir, 0755);
    snprintf(log_path, sizeof log_path, "%s/periscope.log", tmpdir);
    snprintf(shot_path, sizeof shot_path, "%s/shot.xwd", tmpdir);
    snprintf(conf, sizeof conf, "%s/board.conf", board_dir);
    FILE *f = fopen(conf, "w");
    assert_non_null(f);
    /* two scenes; the hotspot sits where the first one opens, labelled with the second's title */
    fprintf(f, "display = sdl\ndisplay_size = %ux%u\ndisplay_format = xrgb8888\ndisplay.vsync = no\n"
               "frame_rate = 30\ninput = sdl\nclock = linux\nquality = fixed\n"
               "scene.rocks = %s/out/sample.pano\nscene.rocks.view = 0 0 90\n"
               "scene.lake = %s/out/sample.pano\nscene.lake.title = The lake\n"
               "hotspot = rocks 0 0 4 -> lake 180 0 90\n",
            FW, FH, cwd, cwd);
    fclose(f);

    /* an X server on a display nobody uses (no lock file, no socket), answering within 5 s */
    char xlog[700];
    snprintf(xlog, sizeof xlog, "%s/xvfb.log", tmpdir);
    for (int n = 90 + (int)(getpid() % 50), tries = 0; tries < 20 && display_name[0] == '\0'; n++, tries++) {
        char lock[64], sock[64];
        snprintf(lock, sizeof lock, "/tmp/.X%d-lock", n);
        snprintf(sock, sizeof sock, "/tmp/.X11-unix/X%d", n);
        if (access(lock, F_OK) == 0 || access(sock, F_OK) == 0)
            continue;
        snprintf(num, sizeof num, ":%d", n);
        const char *xvfb[] = { "Xvfb", num, "-screen", "0", "800x600x24", "-nolisten", "tcp", NULL };
        xvfb_pid = spawn(xvfb, xlog);
        setenv("DISPLAY", num, 1);
        for (int i = 0; i < 50; i++) {
            if (run(NULL, 0, "xprop -root >/dev/null 2>&1") == 0) {
                snprintf(display_name, sizeof display_name, "%s", num);
                break;
            }
            if (waitpid(xvfb_pid, NULL, WNOHANG) == xvfb_pid) {
                xvfb_pid = 0;   /* it lost a race for that display: the next one */
                break;
            }
            sleep_ms(100);
        }
        if (display_name[0] == '\0')
            stop(&xvfb_pid);
    }
    if (display_name[0] == '\0')
        fail_msg("no X server would start (see %s)", xlog);
    setenv("SDL_VIDEODRIVER", "x11", 1);
    /* openbox, up to three times: on a loaded machine it has been seen to end at start-up (1 run in ~40);
     * what it said each time is printed */
    char wmlog[700];
    snprintf(wmlog, sizeof wmlog, "%s/openbox.log", tmpdir);
    for (int attempt = 1; attempt <= 3 && wm_pid == 0; attempt++)
        wm_pid = start_wm(wmlog, attempt);
    if (wm_pid == 0)
        fail_msg("openbox ended at start-up three times (its log: %s)", wmlog);
    const char *fw[] = { prog, "--boards-dir", tmpdir, "--board", "preview", NULL };
    fw_pid = spawn(fw, log_path);
    for (int i = 0; i < 100 && window_id[0] == '\0'; i++) {
        sleep_ms(100);
        run(window_id, sizeof window_id, "xdotool search --onlyvisible --name '^periscope$' 2>/dev/null | head -1");
    }
    if (window_id[0] == '\0')
        fail_msg("no periscope window appeared");
    sleep_ms(800);   /* the first frames */
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    stop(&fw_pid);
    stop(&wm_pid);
    stop(&xvfb_pid);
    if (tmpdir[0] != '\0' && getenv("PSC_KEEP_TMP") == NULL) {
        char cmd[700];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
        (void)system(cmd);
    }
    return 0;
}

#define NEED_SESSION() do { if (window_id[0] == '\0') skip(); } while (0)

static void test_click_hotspot_and_back(void **state)
{
    (void)state;
    NEED_SESSION();
    shot_t a = shoot();
    assert_int_equal(a.w, FW);
    /* the label beside the marker: white letters on a dark band right of the centre */
    unsigned white = 0;
    for (int y = FH / 2 - 8; y < FH / 2 + 8; y++)
        for (int x = FW / 2 + 8; x < FW / 2 + 80; x++)
            white += a.px[y * FW + x] == 0xFFFFFFu;
    assert_true(white > 40);
    assert_int_equal(run(NULL, 0, "xdotool mousemove --window %s %d %d click 1", window_id, FW / 2, FH / 2), 0);
    if (!log_has("tapped) -> scene 1", 3000))
        fail_msg("the click on the marker was not followed (see %s)", log_path);
    sleep_ms(600);   /* past the fade */
    shot_t b = shoot();
    assert_true(memcmp(a.px, b.px, (size_t)FW * FH * 4u) != 0);
    assert_int_equal(run(NULL, 0, "xdotool key BackSpace"), 0);
    if (!log_has("back -> scene 0", 3000))
        fail_msg("Backspace did not go back (see %s)", log_path);
    free(a.px);
    free(b.px);
}

static void test_grab_drag(void **state)
{
    (void)state;
    NEED_SESSION();
    sleep_ms(600);
    shot_t a = shoot();
    /* grab left of the centre (not on the marker), drag 100 pixels right in ten moves, hold */
    assert_int_equal(run(NULL, 0, "xdotool mousemove --window %s 80 150 mousedown 1", window_id), 0);
    for (int i = 1; i <= 10; i++) {
        run(NULL, 0, "xdotool mousemove --window %s %d 150", window_id, 80 + 10 * i);
        sleep_ms(30);
    }
    sleep_ms(400);
    shot_t b = shoot();
    run(NULL, 0, "xdotool mouseup 1");
    /* around the grabbed point the picture moved with the pointer */
    int s = best_shift(&a, &b, 145, 155, 40, 120, 80, 120);
    printf("  dragged 100 pixels: the picture under the pointer moved %d\n", s);
    assert_true(abs(s - 100) <= 2);
    free(a.px);
    free(b.px);
}

static void test_wheel_zooms_in(void **state)
{
    (void)state;
    NEED_SESSION();
    sleep_ms(500);
    shot_t a = shoot();
    run(NULL, 0, "xdotool mousemove --window %s %d %d click 4 click 4 click 4 click 4", window_id, FW / 2, FH / 2);
    sleep_ms(600);
    shot_t b = shoot();
    /* the centre row: b(cx + k dx) = a(cx + dx) for the magnification k */
    double best_k = 1;
    long best = -1;
    for (double k = 1.0; k <= 3.0; k += 0.02) {
        long err = 0;
        for (int dx = -40; dx <= 40; dx++) {
            int xb = FW / 2 + (int)lround(k * dx);
            for (int y = FH / 2 - 2; y <= FH / 2 + 2; y++)
                err += pixel_diff(a.px[y * FW + FW / 2 + dx], b.px[(FH / 2 + (int)lround(k * (y - FH / 2))) * FW + xb]);
        }
        if (best < 0 || err < best) {
            best = err;
            best_k = k;
        }
    }
    printf("  four wheel notches: magnified %.2f times\n", best_k);
    assert_true(best_k > 1.8);
    free(a.px);
    free(b.px);
}

static void test_fullscreen_and_resize(void **state)
{
    unsigned w, h;
    (void)state;
    NEED_SESSION();
    run(NULL, 0, "xdotool key F11");
    sleep_ms(800);
    window_size(&w, &h);
    printf("  F11: %ux%u\n", w, h);
    assert_true(w == 800 && h == 600);
    run(NULL, 0, "xdotool key F11");
    sleep_ms(800);
    window_size(&w, &h);
    assert_true(w == FW && h == FH);
    /* a wide window: the frame scaled to its height, centred, black beside it */
    run(NULL, 0, "xdotool windowsize %s %u %u", window_id, 2 * FW, FH);
    sleep_ms(800);
    shot_t s = shoot();
    assert_int_equal(s.w, 2 * FW);
    unsigned black_sides = 0, lit_middle = 0;
    for (uint32_t y = 0; y < s.h; y++) {
        black_sides += s.px[y * s.w + 5] == 0 && s.px[y * s.w + s.w - 5] == 0;
        lit_middle += s.px[y * s.w + s.w / 2] != 0;
    }
    assert_true(black_sides == s.h && lit_middle > s.h * 9 / 10);
    free(s.px);
}

static void test_q_quits(void **state)
{
    int status = 0;
    (void)state;
    NEED_SESSION();
    run(NULL, 0, "xdotool key q");
    for (int i = 0; i < 50; i++) {
        if (waitpid(fw_pid, &status, WNOHANG) == fw_pid) {
            fw_pid = 0;
            assert_true(WIFEXITED(status));
            assert_int_equal(WEXITSTATUS(status), 0);
            return;
        }
        sleep_ms(100);
    }
    fail_msg("q did not quit within 5 s");
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_click_hotspot_and_back),
        cmocka_unit_test(test_grab_drag),
        cmocka_unit_test(test_wheel_zooms_in),
        cmocka_unit_test(test_fullscreen_and_resize),
        cmocka_unit_test(test_q_quits),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
