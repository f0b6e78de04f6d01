/* SPDX-License-Identifier: MIT */
/*
 * test_config_fuzz.c - the board file parser (firmware/board_config.h) and
 * the tour script parser (hal/sim/psc_sim_tour.h) on truncated and corrupt
 * input, starting from the repository's own boards/sim/board.conf and
 * boards/sim/tour.txt.
 *
 *  - every truncation, and a few thousand deterministic random mutations per
 *    file (bit flips, random bytes, inserted NULs, CRs and '#', duplicated,
 *    deleted and swapped lines, numbers replaced by huge ones, very long
 *    lines, repeated lines), either parse or fail with "FILE:LINE: problem"
 *    (LINE within the text) or "FILE: problem"; whatever parses obeys every
 *    documented range; a failed tour is left empty. Each parse reads a heap
 *    copy of exactly the text's length, so AddressSanitizer catches overreads;
 *  - prefixes that end at a line end behave as the files say: the board
 *    parses exactly once its four required keys are in, otherwise it names
 *    the missing key; every such tour prefix parses, never losing events;
 *  - specific corruptions name the right line (and the first line of a
 *    duplicate, both lines of a pitch_min/pitch_max conflict);
 *  - CRLF line ends give the same result as LF;
 *  - file-level errors (too large, a directory, missing) name the file.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "board_config.h"
#include "sim/psc_sim_tour.h"
#include "psc_testsupport.h"
#include "tsup_files.h"

#define BOARD_FILE "boards/sim/board.conf"
#define TOUR_FILE "boards/sim/tour.txt"
#define ERRLEN 1024
#define LONG_PRESS_MS 800u

/* ---- text buffers ------------------------------------------------------------------------- */

typedef struct {
    char *p;
    size_t len, cap;
} text_t;

static text_t text_from(const char *s, size_t n)
{
    text_t t = {malloc(n + 1), n, n + 1};
    assert_non_null(t.p);
    memcpy(t.p, s, n);
    return t;
}

static void text_reserve(text_t *t, size_t extra)
{
    if (t->len + extra <= t->cap)
        return;
    size_t cap = (t->len + extra) * 2;
    char *p = realloc(t->p, cap);
    assert_non_null(p);
    t->p = p;
    t->cap = cap;
}

static void text_insert(text_t *t, size_t at, const char *s, size_t n)
{
    text_reserve(t, n);
    memmove(t->p + at + n, t->p + at, t->len - at);
    memcpy(t->p + at, s, n);
    t->len += n;
}

static void text_delete(text_t *t, size_t at, size_t n)
{
    memmove(t->p + at, t->p + at + n, t->len - at - n);
    t->len -= n;
}

/* Lines as the parsers count them: one per '\n', plus an unterminated last one. */
static unsigned count_lines(const char *p, size_t len)
{
    unsigned n = 0;
    for (size_t i = 0; i < len; i++)
        n += p[i] == '\n';
    return n + (len > 0 && p[len - 1] != '\n');
}

/* Byte range of line k (0-based), without its '\n'. 0 if there is such a line. */
static int line_span(const text_t *t, unsigned k, size_t *start, size_t *end)
{
    size_t pos = 0;
    for (unsigned i = 0; i < k; i++) {
        const char *nl = memchr(t->p + pos, '\n', t->len - pos);
        if (!nl)
            return -1;
        pos = (size_t)(nl - t->p) + 1;
    }
    if (pos >= t->len && k > 0)
        return -1;
    const char *nl = memchr(t->p + pos, '\n', t->len - pos);
    *start = pos;
    *end = nl ? (size_t)(nl - t->p) : t->len;
    return 0;
}

/* The index of the first line that begins with prefix. */
static unsigned find_line(const text_t *t, const char *prefix)
{
    size_t s, e, n = strlen(prefix);
    for (unsigned k = 0; line_span(t, k, &s, &e) == 0; k++)
        if (e - s >= n && memcmp(t->p + s, prefix, n) == 0)
            return k;
    fail_msg("no line begins with \"%s\"", prefix);
    return 0;
}

static void replace_line(text_t *t, unsigned k, const char *with)
{
    size_t s, e;
    assert_int_equal(line_span(t, k, &s, &e), 0);
    text_delete(t, s, e - s);
    text_insert(t, s, with, strlen(with));
}

/* Insert a whole line (a '\n' is added) before line k; k may be one past the last line. */
static void insert_line(text_t *t, unsigned k, const char *line)
{
    size_t s = t->len, e;
    if (line_span(t, k, &s, &e) != 0)
        s = t->len;
    if (s == t->len && t->len > 0 && t->p[t->len - 1] != '\n') {
        text_insert(t, t->len, "\n", 1);
        s = t->len;
    }
    text_insert(t, s, "\n", 1);
    text_insert(t, s, line, strlen(line));
}

static void delete_line(text_t *t, unsigned k)
{
    size_t s, e;
    assert_int_equal(line_span(t, k, &s, &e), 0);
    text_delete(t, s, e - s + (e < t->len));
}

static text_t load_text(const char *path)
{
    size_t len;
    uint8_t *b = tsup_read_bytes(path, &len);
    if (!b)
        fail_msg("cannot read %s (the tests run from the repository root)", path);
    text_t t = text_from((const char *)b, len);
    free(b);
    return t;
}

/* ---- checking messages ------------------------------------------------------------------------ */

/*
 * err must be "<file>:<line>: <problem>" with 1 <= line <= nlines, or
 * "<file>: <problem>". Returns the line, or 0 for the second form.
 */
static unsigned check_message(const char *err, const char *file, unsigned nlines, const char *what)
{
    size_t n = strlen(file);
    if (strncmp(err, file, n) != 0 || err[n] != ':')
        fail_msg("%s: message does not begin with \"%s:\": \"%s\"", what, file, err);
    const char *p = err + n + 1;
    if (p[0] == ' ') {
        if (p[1] == '\0' || p[1] == ' ')
            fail_msg("%s: message without a problem: \"%s\"", what, err);
        return 0;
    }
    unsigned long line = 0;
    const char *d = p;
    while (*d >= '0' && *d <= '9' && d - p < 9)
        line = line * 10 + (unsigned long)(*d++ - '0');
    if (d == p || p[0] == '0' || d[0] != ':' || d[1] != ' ' || d[2] == '\0')
        fail_msg("%s: message is neither \"FILE:LINE: ...\" nor \"FILE: ...\": \"%s\"", what, err);
    if (line < 1 || line > nlines)
        fail_msg("%s: message names line %lu of a %u-line text: \"%s\"", what, line, nlines, err);
    return (unsigned)line;
}

/* ---- parsing from exact-size copies ------------------------------------------------------------- */

static int board_parse_exact(const char *text, size_t len, psc_board_config_t *cfg, char *err)
{
    char *b = malloc(len ? len : 1);
    assert_non_null(b);
    memcpy(b, text, len);
    psc_board_config_defaults(cfg);
    memset(err, '?', ERRLEN - 1);
    err[ERRLEN - 1] = '\0';
    int rc = psc_board_config_parse(b, len, BOARD_FILE, cfg, err, ERRLEN);
    free(b);
    return rc;
}

static void assert_terminated(const char *s, size_t cap, const char *what)
{
    if (!memchr(s, '\0', cap))
        fail_msg("parsed board: %s is not NUL-terminated", what);
}

/* Everything a parsed board promises (board_config.h, boards/README.md). */
static void check_board(const psc_board_config_t *c)
{
    assert_terminated(c->file, sizeof c->file, "file");
    assert_terminated(c->display_backend, sizeof c->display_backend, "display");
    assert_terminated(c->input_backend, sizeof c->input_backend, "input");
    assert_terminated(c->clock_backend, sizeof c->clock_backend, "clock");
    assert_terminated(c->camera_backend, sizeof c->camera_backend, "camera");
    assert_terminated(c->watchdog_backend, sizeof c->watchdog_backend, "watchdog");
    assert_terminated(c->tour, sizeof c->tour, "tour");
    assert_terminated(c->tour_origin, sizeof c->tour_origin, "tour origin");
    assert_true(c->display_backend[0] && c->input_backend[0] && c->clock_backend[0]);
    assert_true(c->display_width >= 16 && c->display_width <= PSC_MAX_OUT_DIM);
    assert_true(c->display_height >= 16 && c->display_height <= PSC_MAX_OUT_DIM);
    assert_true(c->display_format == PSC_PIX_RGB565 || c->display_format == PSC_PIX_XRGB8888);
    assert_true(c->display_buffers >= 1 && c->display_buffers <= 3);
    assert_true(c->frame_rate_mhz >= 1000 && c->frame_rate_mhz <= 240000);
    assert_true(c->long_press_ms >= 50 && c->long_press_ms <= 10000);
    assert_true(c->camera_width >= 2 && c->camera_width <= PSC_MAX_MAP_DIM);
    assert_true(c->camera_height >= 2 && c->camera_height <= PSC_MAX_MAP_DIM);
    assert_true(c->camera_rate_mhz >= 1000 && c->camera_rate_mhz <= 240000);
    assert_true(c->camera_buffers >= 2 && c->camera_buffers <= 8);
    assert_true(c->watchdog_timeout_ms >= 100 && c->watchdog_timeout_ms <= 600000);
    assert_true(c->frames_every <= 1000000);
    assert_true(c->scene_count <= PSC_BOARD_MAX_SCENES);
    for (unsigned i = 0; i < c->scene_count; i++) {
        assert_terminated(c->scenes[i], sizeof c->scenes[i], "scene");
        assert_true(c->scenes[i][0] != '\0');
    }
    assert_true(c->yaw_rate_max_mdeg >= 1000 && c->yaw_rate_max_mdeg <= 720000);
    assert_true(c->pitch_rate_max_mdeg >= 1000 && c->pitch_rate_max_mdeg <= 720000);
    assert_true(c->zoom_rate_max_mdeg >= 1000 && c->zoom_rate_max_mdeg <= 720000);
    assert_true(c->accel_mdeg >= 1000);
    assert_true(c->inertia_half_life_ms >= 1 && c->inertia_half_life_ms <= 10000);
    assert_true(c->home_half_life_ms >= 1 && c->home_half_life_ms <= 10000);
    assert_true(c->pitch_min_mdeg >= -90000 && c->pitch_max_mdeg <= 90000);
    assert_true(c->pitch_min_mdeg < c->pitch_max_mdeg);
    assert_true(c->hfov_min_mdeg >= 0 && c->hfov_min_mdeg <= 170000);
    assert_true(c->hfov_max_mdeg >= 0 && c->hfov_max_mdeg <= 170000);
    assert_true(c->hfov_min_mdeg == 0 || c->hfov_max_mdeg == 0 || c->hfov_min_mdeg < c->hfov_max_mdeg);
    assert_true(c->quality_fast_speed >= 1 && c->quality_fast_speed <= 100000);
    assert_true(c->quality_settle_frames >= 1 && c->quality_settle_frames <= 10000);
    assert_true(c->quality_fast_span_log2 <= PSC_SPAN_LOG2_MAX && c->quality_span_log2 <= PSC_SPAN_LOG2_MAX);
    assert_true(c->quality_fast_filter == PSC_FILTER_NEAREST || c->quality_fast_filter == PSC_FILTER_BILINEAR ||
                c->quality_fast_filter == PSC_FILTER_MIP);
    assert_true(c->quality_filter == PSC_FILTER_NEAREST || c->quality_filter == PSC_FILTER_BILINEAR ||
                c->quality_filter == PSC_FILTER_MIP);
    assert_true(c->option_count <= PSC_BOARD_MAX_OPTIONS);
    for (unsigned i = 0; i < c->option_count; i++) {
        const psc_board_option_t *o = &c->options[i];
        assert_true((unsigned)o->dev < PSC_BOARD_DEV_COUNT);
        assert_terminated(o->key, sizeof o->key, "option key");
        assert_terminated(o->value, sizeof o->value, "option value");
        assert_terminated(o->origin, sizeof o->origin, "option origin");
        assert_true(o->key[0] != '\0' && o->value[0] != '\0');
        assert_true(strncmp(o->origin, BOARD_FILE ":", strlen(BOARD_FILE) + 1) == 0);
    }
}

/* Parse a board text; on failure check the message form. Returns the line named (0: none), or -1 if parsed. */
static int board_try(const char *text, size_t len, psc_board_config_t *cfg, char *err, const char *what)
{
    int rc = board_parse_exact(text, len, cfg, err);
    if (rc == 0) {
        check_board(cfg);
        return -1;
    }
    assert_int_equal(rc, -1);
    return (int)check_message(err, BOARD_FILE, count_lines(text, len), what);
}

static int tour_parse_exact(const char *text, size_t len, psc_sim_tour_t *t, char *err)
{
    char *b = malloc(len ? len : 1);
    assert_non_null(b);
    memcpy(b, text, len);
    memset(t, 0x5A, sizeof *t);
    memset(err, '?', ERRLEN - 1);
    err[ERRLEN - 1] = '\0';
    int rc = psc_sim_tour_parse(b, len, TOUR_FILE, LONG_PRESS_MS, t, err, ERRLEN);
    free(b);
    return rc;
}

/* Everything a parsed tour promises (psc_sim_tour.h). */
static void check_tour(const psc_sim_tour_t *t)
{
    assert_true(t->count >= 1 && t->count <= PSC_SIM_TOUR_MAX_EVENTS);
    assert_non_null(t->events);
    assert_true(t->end_us <= (uint64_t)PSC_SIM_TOUR_MAX_MS * 1000u);
    /* The board's own keypad arrives first. */
    assert_int_equal(t->events[0].type, PSC_HAL_INPUT_DEVICE_ARRIVE);
    assert_int_equal(t->events[0].device, 0);
    assert_int_equal(t->events[0].time_us, 0);
    for (size_t i = 0; i < t->count; i++) {
        const psc_hal_input_event_t *e = &t->events[i];
        if (i > 0 && e->time_us < t->events[i - 1].time_us)
            fail_msg("tour event %zu at %llu us is before event %zu", i, (unsigned long long)e->time_us, i - 1);
        /* At most a press's release or a long press after the one-day limit. */
        assert_true(e->time_us <= ((uint64_t)PSC_SIM_TOUR_MAX_MS + LONG_PRESS_MS) * 1000u);
        assert_true(e->device < PSC_HAL_INPUT_MAX_DEVICES);
        switch (e->type) {
        case PSC_HAL_INPUT_BUTTON_DOWN:
        case PSC_HAL_INPUT_BUTTON_LONG:
        case PSC_HAL_INPUT_BUTTON_UP:
            assert_true(e->code > PSC_HAL_ACTION_NONE && e->code < PSC_HAL_ACTION_COUNT);
            assert_int_equal(e->value, e->type == PSC_HAL_INPUT_BUTTON_UP ? 0 : 1);
            break;
        case PSC_HAL_INPUT_AXIS:
            assert_true(e->code < PSC_HAL_AXIS_COUNT);
            assert_true(e->value >= PSC_HAL_AXIS_MIN && e->value <= PSC_HAL_AXIS_MAX);
            break;
        case PSC_HAL_INPUT_DEVICE_ARRIVE:
        case PSC_HAL_INPUT_DEVICE_LEAVE:
            break;
        case PSC_HAL_INPUT_POINTER_DOWN:   /* a tap (the demonstration tour taps Thom) */
        case PSC_HAL_INPUT_POINTER_MOVE:
        case PSC_HAL_INPUT_POINTER_UP:
            assert_true(e->code < PSC_HAL_POINTER_MAX);
            break;
        case PSC_HAL_INPUT_WHEEL:
            break;
        default:
            fail_msg("tour event %zu has type %d", i, (int)e->type);
        }
    }
}

/* Parse a tour text; as board_try. A parsed tour is freed here; a failed one must be empty. */
static int tour_try(const char *text, size_t len, size_t *count, char *err, const char *what)
{
    psc_sim_tour_t t;
    int rc = tour_parse_exact(text, len, &t, err);
    if (rc == 0) {
        check_tour(&t);
        if (count)
            *count = t.count;
        psc_sim_tour_free(&t);
        return -1;
    }
    if (rc != -EINVAL)
        fail_msg("%s: psc_sim_tour_parse returned %d (%s)", what, rc, err);
    assert_int_equal(t.count, 0);
    assert_null(t.events);
    return (int)check_message(err, TOUR_FILE, count_lines(text, len), what);
}

/* ---- the real files, truncated --------------------------------------------------------------------- */

static void test_board_truncated(void **state)
{
    (void)state;
    text_t t = load_text(BOARD_FILE);
    psc_board_config_t cfg;
    char err[ERRLEN], what[64];
    assert_int_equal(board_try(t.p, t.len, &cfg, err, "the whole file"), -1);
    assert_true(cfg.scene_count >= 1);

    /* A complete-line prefix parses exactly when it holds all four required keys. */
    static const char *const required[] = {"display =", "display_size =", "input =", "clock ="};
    size_t need = 0;
    for (unsigned i = 0; i < 4; i++) {
        size_t s, e;
        assert_int_equal(line_span(&t, find_line(&t, required[i]), &s, &e), 0);
        if (e + 1 > need)
            need = e + 1;
    }
    unsigned long parsed = 0, refused = 0;
    for (size_t n = 0; n < t.len; n++) {
        snprintf(what, sizeof what, "board cut to %zu bytes", n);
        int r = board_try(t.p, n, &cfg, err, what);
        parsed += r < 0;
        refused += r >= 0;
        if (n > 0 && t.p[n - 1] != '\n')
            continue;
        if (n >= need && r >= 0)
            fail_msg("%s (complete lines, every required key) refused: %s", what, err);
        if (n < need && (r != 0 || !strstr(err, "required key")))
            fail_msg("%s (complete lines, a required key missing) should name the missing key: %s%s", what,
                     r < 0 ? "parsed" : "", r < 0 ? "" : err);
    }
    printf("  %s cut at each of %zu lengths: %lu parsed, %lu refused with FILE[:LINE]: messages\n", BOARD_FILE,
           t.len, parsed, refused);
    assert_true(parsed > 0 && refused > 0);
    free(t.p);
}

static void test_tour_truncated(void **state)
{
    (void)state;
    text_t t = load_text(TOUR_FILE);
    char err[ERRLEN], what[64];
    size_t full = 0, prev = 0;
    assert_int_equal(tour_try(t.p, t.len, &full, err, "the whole tour"), -1);
    unsigned long parsed = 0, refused = 0;
    for (size_t n = 0; n < t.len; n++) {
        snprintf(what, sizeof what, "tour cut to %zu bytes", n);
        size_t count = 0;
        int r = tour_try(t.p, n, &count, err, what);
        parsed += r < 0;
        refused += r >= 0;
        if (n > 0 && t.p[n - 1] != '\n')
            continue;
        /* Every command of the tour is valid after the ones before it. */
        if (r >= 0)
            fail_msg("%s (complete lines) refused: %s", what, err);
        if (count < prev)
            fail_msg("%s has %zu events, the shorter prefix had %zu", what, count, prev);
        prev = count;
    }
    assert_true(prev <= full);
    printf("  %s cut at each of %zu lengths: %lu parsed, %lu refused with FILE:LINE: messages\n", TOUR_FILE, t.len,
           parsed, refused);
    assert_true(parsed > 0 && refused > 0);
    free(t.p);
}

/* ---- random mutations ------------------------------------------------------------------------------ */

static const char *const huge_numbers[] = {
    "99999999999999999999", "18446744073709551616", "4294967296", "-2147483649", "1000000000000000",
    "1000000000000001",     "0.00000000000000000001", "1e9", "-0", "+5", "0x10", ".", "-", "1..5", "99999999999999.9999",
};

static const char *const extra_lines[] = {
    "scene = more.pano", "display.capture_dir = x", "input.script = y", "pitch_min = 90", "hfov_min = 100",
    "hfov_max = 50",     "wait 1s", "press home", "down home", "up home", "plug 2", "unplug 0", "device 7",
    "end",               "at 0", "hold 10ms axis zoom -1", "yaw 1", "= 5", "#", "\t \r",
};

/* The next text of the mutation: one of about a dozen edits, 1-3 times. */
static void mutate_text(text_t *t, tsup_rng_t *rng)
{
    unsigned edits = 1 + tsup_rng_below(rng, 3);
    for (unsigned e = 0; e < edits; e++) {
        unsigned nlines = count_lines(t->p, t->len);
        size_t at = t->len ? tsup_rng_below(rng, (uint32_t)t->len) : 0;
        unsigned k = nlines ? tsup_rng_below(rng, nlines) : 0;
        size_t s, end;
        switch (tsup_rng_below(rng, 12)) {
        case 0: /* flip a bit */
            if (t->len)
                t->p[at] = (char)(t->p[at] ^ (1 << tsup_rng_below(rng, 8)));
            break;
        case 1: { /* a random byte, or a character that means something to the parsers */
            static const char special[] = "#=\r\t .x-+0s\n";
            if (t->len)
                t->p[at] = tsup_rng_below(rng, 2) ? (char)tsup_rng_u32(rng)
                                                  : special[tsup_rng_below(rng, sizeof special - 1)];
            break;
        }
        case 2: /* an inserted NUL */
            text_insert(t, at, "", 1);
            break;
        case 3: /* a duplicated line */
            if (nlines && line_span(t, k, &s, &end) == 0) {
                char *copy = malloc(end - s + 1);
                assert_non_null(copy);
                memcpy(copy, t->p + s, end - s);
                copy[end - s] = '\0';
                insert_line(t, tsup_rng_below(rng, nlines + 1), copy);
                free(copy);
            }
            break;
        case 4: /* a deleted line */
            if (nlines)
                delete_line(t, k);
            break;
        case 5: { /* two lines swapped: move line k before line j */
            if (nlines < 2 || line_span(t, k, &s, &end) != 0)
                break;
            char *copy = malloc(end - s + 1);
            assert_non_null(copy);
            memcpy(copy, t->p + s, end - s);
            copy[end - s] = '\0';
            delete_line(t, k);
            insert_line(t, tsup_rng_below(rng, nlines), copy);
            free(copy);
            break;
        }
        case 6: { /* a number replaced by a huge or malformed one */
            size_t i = at;
            while (i < t->len && !(t->p[i] >= '0' && t->p[i] <= '9'))
                i++;
            if (i == t->len)
                break;
            size_t j = i;
            while (j < t->len && ((t->p[j] >= '0' && t->p[j] <= '9') || t->p[j] == '.'))
                j++;
            const char *h = huge_numbers[tsup_rng_below(rng, sizeof huge_numbers / sizeof huge_numbers[0])];
            text_delete(t, i, j - i);
            text_insert(t, i, h, strlen(h));
            break;
        }
        case 7: { /* a very long line: a long value, comment or word, inserted or appended to a line */
            size_t n = 200 + tsup_rng_below(rng, 2800);
            char *longl = malloc(n + 16);
            assert_non_null(longl);
            const char *head = (const char *[]){"scene = ", "# ", "wait ", "display.x = ", ""}[tsup_rng_below(rng, 5)];
            size_t h = strlen(head);
            memcpy(longl, head, h);
            char fill = "a9#. "[tsup_rng_below(rng, 5)];
            memset(longl + h, fill, n);
            longl[h + n] = '\0';
            if (tsup_rng_below(rng, 2) && nlines && line_span(t, k, &s, &end) == 0)
                text_insert(t, end, longl + h, n);
            else
                insert_line(t, k, longl);
            free(longl);
            break;
        }
        case 8: { /* CRLF, a tab or a comment mark somewhere */
            const char *ins = (const char *[]){"\r", "\t", " #", "\r\n", "\n"}[tsup_rng_below(rng, 5)];
            text_insert(t, at, ins, strlen(ins));
            break;
        }
        case 9: { /* a line of either language, often repeated (too many scenes, options, events) */
            const char *l = extra_lines[tsup_rng_below(rng, sizeof extra_lines / sizeof extra_lines[0])];
            unsigned times = tsup_rng_below(rng, 4) == 0 ? 40 : 1;
            for (unsigned i = 0; i < times; i++)
                insert_line(t, k, l);
            break;
        }
        case 10: /* cut short */
            t->len = at;
            break;
        default: /* a word of one line pasted into another */
            if (nlines >= 2 && line_span(t, k, &s, &end) == 0 && end > s) {
                size_t from = s + tsup_rng_below(rng, (uint32_t)(end - s)), n = 1 + tsup_rng_below(rng, 12);
                if (from + n > end)
                    n = end - from;
                char word[16];
                memcpy(word, t->p + from, n);
                text_insert(t, at, word, n);
            }
            break;
        }
    }
}

typedef int (*try_fn)(const char *text, size_t len, char *err, const char *what);

static int board_try_any(const char *text, size_t len, char *err, const char *what)
{
    psc_board_config_t cfg;
    return board_try(text, len, &cfg, err, what);
}

static int tour_try_any(const char *text, size_t len, char *err, const char *what)
{
    return tour_try(text, len, NULL, err, what);
}

static void fuzz_file(const char *path, try_fn try_parse, unsigned iterations, uint64_t seed)
{
    text_t orig = load_text(path);
    tsup_rng_t rng;
    tsup_rng_seed(&rng, seed);
    unsigned long parsed = 0, with_line = 0, without_line = 0;
    char samples[4][ERRLEN] = {"", "", "", ""};
    for (unsigned it = 0; it < iterations; it++) {
        text_t t = text_from(orig.p, orig.len);
        mutate_text(&t, &rng);
        char err[ERRLEN], what[64];
        snprintf(what, sizeof what, "%s mutation %u", path, it);
        int r = try_parse(t.p, t.len, err, what);
        if (r < 0) {
            parsed++;
        } else {
            if (r > 0)
                with_line++;
            else
                without_line++;
            snprintf(samples[(with_line + without_line) % 4], ERRLEN, "%s", err);
        }
        free(t.p);
    }
    printf("  %s: %u mutations: %lu parsed, %lu refused naming a line, %lu naming only the file; e.g.\n", path,
           iterations, parsed, with_line, without_line);
    for (int i = 0; i < 4; i++)
        printf("    \"%.160s\"\n", samples[i]);
    /* Both outcomes must be common, or the mutations do not exercise the parser. */
    assert_true(parsed >= iterations / 20);
    assert_true(with_line >= iterations / 4);
    free(orig.p);
}

static void test_board_fuzz(void **state)
{
    (void)state;
    fuzz_file(BOARD_FILE, board_try_any, 4000, 0xB0A2D);
}

static void test_tour_fuzz(void **state)
{
    (void)state;
    fuzz_file(TOUR_FILE, tour_try_any, 4000, 0x70C2);
}

/* ---- specific corruptions name the right line ----------------------------------------------------------- */

/* The board with one edit must be refused naming line `line` (0: no line) and mentioning `mention`. */
static void expect_board_line(const text_t *t, int line, const char *mention, const char *what)
{
    psc_board_config_t cfg;
    char err[ERRLEN];
    int r = board_try(t->p, t->len, &cfg, err, what);
    if (r < 0)
        fail_msg("%s: the board was accepted", what);
    if (r != line || (mention && !strstr(err, mention)))
        fail_msg("%s: \"%s\" should name line %d and mention \"%s\"", what, err, line, mention ? mention : "");
    printf("  %s: \"%s\"\n", what, err);
}

static void test_board_specific(void **state)
{
    (void)state;
    text_t orig = load_text(BOARD_FILE);
    char buf[600];

    text_t t = text_from(orig.p, orig.len);
    unsigned k = find_line(&t, "frame_rate =");
    replace_line(&t, k, "frame_rate = fast");
    expect_board_line(&t, (int)k + 1, "frame_rate", "frame_rate = fast");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "display_size =");
    insert_line(&t, count_lines(t.p, t.len), "display_size = 320x240");
    snprintf(buf, sizeof buf, "line %u", k + 1);
    expect_board_line(&t, (int)count_lines(t.p, t.len), buf, "display_size again at the end");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "input =");
    size_t s, e;
    assert_int_equal(line_span(&t, k, &s, &e), 0);
    text_insert(&t, s + 3, "", 1);
    expect_board_line(&t, (int)k + 1, "NUL", "a NUL inside 'input = sim'");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "accel =");
    memset(buf, 'x', 500);
    buf[0] = '#';
    buf[500] = '\0';
    insert_line(&t, k, buf);
    expect_board_line(&t, (int)k + 1, "longer", "a 500-character comment line");
    free(t.p);

    t = text_from(orig.p, orig.len);
    delete_line(&t, find_line(&t, "clock ="));
    expect_board_line(&t, 0, "'clock'", "without its clock line");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "yaw_rate_max =");
    replace_line(&t, k, "yaw_rate_max = 99999999999999999999");
    expect_board_line(&t, (int)k + 1, "yaw_rate_max", "a huge yaw_rate_max");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "display_buffers =");
    replace_line(&t, k, "display_buffers = 258"); /* 2 modulo 256: must not wrap into range */
    expect_board_line(&t, (int)k + 1, "display_buffers", "display_buffers = 258");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "pitch_min =");
    unsigned kmax = find_line(&t, "pitch_max =");
    replace_line(&t, k, "pitch_min = 90");
    snprintf(buf, sizeof buf, "pitch_min = 90 (line %u) must be below pitch_max = 90 (line %u)", k + 1, kmax + 1);
    expect_board_line(&t, 0, buf, "pitch_min = pitch_max");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "scene.rocks =");
    for (unsigned i = 0; i < PSC_BOARD_MAX_SCENES; i++)
        insert_line(&t, k, "scene = extra.pano");
    expect_board_line(&t, (int)k + PSC_BOARD_MAX_SCENES + 1, "too many", "nine scene lines");
    free(t.p);

    /* objects standing in a panorama: each bad line refused naming its line, its file and the key */
    static const struct {
        const char *line, *says, *what;
    } objects[] = {
        {"scene.rocks.object = thom.ppk yaw=15 pitch=-12", "thom.ppk: the object needs dist=D", "an object without dist"},
        {"scene.rocks.object = thom.ppk yaw=15 pitch=-95 dist=3", "thom.ppk: pitch '-95'", "an object's pitch past -90"},
        {"scene.rocks.object = thom.ppk yaw=15 pitch=0 dist=3 colour=red", "unknown key 'colour'", "an unknown key"},
        {"scene.rocks.object = thom.ppk yaw=15 pitch=0 dist=3 scale=99", "scale '99'", "a scale past 16"},
        {"scene.rocks.object = yaw=15 pitch=0 dist=3", "needs its file first", "an object without its file"},
        {"scene.rocks.object = thom.ppk yaw=1 pitch=0 dist=3 hotspot=nowhere", "hotspot=nowhere names no scene",
         "a hotspot to no scene"},
        {"scene.nope.object = thom.ppk yaw=1 pitch=0 dist=3", "no scene 'nope' declared above", "an unknown scene"},
        {"scene.rocks.light = 30", "scene.rocks.light must be 'AZ EL [AMBIENT [RRGGBB]]'", "a light without elevation"},
        {"scene.rocks.light = 30 55 1.5", "scene.rocks.light must be", "an ambient past 1"},
        {"scene.rocks.light = 30 55 0.5 orange", "scene.rocks.light must be", "a light colour not in hex"},
        {"scene.rocks.light = 30 55 0.5 FFFFFF 1", "scene.rocks.light must be", "a light with a fifth field"},
    };
    for (unsigned i = 0; i < sizeof objects / sizeof objects[0]; i++) {
        t = text_from(orig.p, orig.len);
        k = find_line(&t, "scene.rocks.object =");
        replace_line(&t, k, objects[i].line);
        expect_board_line(&t, (int)k + 1, objects[i].says, objects[i].what);
        free(t.p);
    }
    t = text_from(orig.p, orig.len);
    k = find_line(&t, "scene.rocks.object =");
    for (unsigned i = 0; i < PSC_IO_OBJECTS_MAX; i++)
        insert_line(&t, k, "scene.rocks.object = a.ppk yaw=0 pitch=0 dist=3");
    expect_board_line(&t, (int)k + PSC_IO_OBJECTS_MAX + 1, "at most that many stand in one scene",
                      "nine objects in one scene");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "display =");
    replace_line(&t, k, "Display = sim");
    expect_board_line(&t, (int)k + 1, "Display", "an upper-case key");
    free(t.p);

    /* Values at the ends of each range are accepted and stored exactly; one step outside, refused. */
    static const struct {
        const char *key, *value;
        size_t offset, size;
        int64_t want; /* stored value, or INT64_MIN: refused */
    } edges[] = {
#define FIELD(f) offsetof(psc_board_config_t, f), sizeof(((psc_board_config_t *)0)->f)
        {"display_buffers", "1", FIELD(display_buffers), 1},
        {"display_buffers", "3", FIELD(display_buffers), 3},
        {"display_buffers", "0", FIELD(display_buffers), INT64_MIN},
        {"quality_span_log2", "0", FIELD(quality_span_log2), 0},
        {"quality_span_log2", "4", FIELD(quality_span_log2), 4},
        {"quality_fast_span_log2", "0", FIELD(quality_fast_span_log2), 0},
        {"quality_fast_span_log2", "5", FIELD(quality_fast_span_log2), INT64_MIN},
        {"long_press_ms", "50", FIELD(long_press_ms), 50},
        {"long_press_ms", "49", FIELD(long_press_ms), INT64_MIN},
        {"frame_rate", "29.97", FIELD(frame_rate_mhz), 29970},
        {"frame_rate", "240", FIELD(frame_rate_mhz), 240000},
        {"frame_rate", "240.0005", FIELD(frame_rate_mhz), INT64_MIN}, /* rounds to 240.001 */
        {"frame_rate", "0.9995", FIELD(frame_rate_mhz), 1000},       /* rounds to 1 */
        {"pitch_min", "-45.5", FIELD(pitch_min_mdeg), -45500},
        {"pitch_min", "-90.001", FIELD(pitch_min_mdeg), INT64_MIN},
        {"quality_fast_speed", "0.001", FIELD(quality_fast_speed), 1},
        {"quality_fast_speed", "0.0004", FIELD(quality_fast_speed), INT64_MIN},
        {"frames_every", "1000000", FIELD(frames_every), 1000000},
        {"frames_every", "1000001", FIELD(frames_every), INT64_MIN},
        {"hfov_max", "170", FIELD(hfov_max_mdeg), 170000},
        {"watchdog_timeout_ms", "600000", FIELD(watchdog_timeout_ms), 600000},
        {"display_size", "4096x16", FIELD(display_width), 4096},
        {"display_size", "4097x16", FIELD(display_width), INT64_MIN},
        {"display_size", "16x4096", FIELD(display_height), 4096},
#undef FIELD
    };
    for (size_t i = 0; i < sizeof edges / sizeof edges[0]; i++) {
        char line[128], what[160];
        snprintf(line, sizeof line, "%s = %s", edges[i].key, edges[i].value);
        snprintf(what, sizeof what, "'%s'", line);
        char prefix[64];
        snprintf(prefix, sizeof prefix, "%s =", edges[i].key);
        t = text_from(orig.p, orig.len);
        k = find_line(&t, prefix);
        replace_line(&t, k, line);
        if (edges[i].want == INT64_MIN) {
            expect_board_line(&t, (int)k + 1, edges[i].key, what);
        } else {
            psc_board_config_t c;
            char err[ERRLEN];
            if (board_try(t.p, t.len, &c, err, what) >= 0)
                fail_msg("%s refused: %s", what, err);
            int64_t got = 0;
            const char *f = (const char *)&c + edges[i].offset;
            if (edges[i].size == 1)
                got = *(const uint8_t *)f;
            else if (edges[i].size == 2)
                got = *(const uint16_t *)(const void *)f;
            else /* int32_t or uint32_t, every value here below 2^31 */
                got = *(const int32_t *)(const void *)f;
            if (got != edges[i].want)
                fail_msg("%s is stored as %lld, expected %lld", what, (long long)got, (long long)edges[i].want);
        }
        free(t.p);
    }

    /* The longest line is 383 characters (comment or not); 384 is refused, naming the line. */
    for (size_t n = 382; n <= 385; n++) {
        char line[400], what[64];
        memset(line, 'x', n);
        line[0] = '#';
        line[n] = '\0';
        snprintf(what, sizeof what, "a %zu-character comment line", n);
        t = text_from(orig.p, orig.len);
        k = find_line(&t, "accel =");
        insert_line(&t, k, line);
        if (n <= 383) {
            psc_board_config_t c;
            char err[ERRLEN];
            if (board_try(t.p, t.len, &c, err, what) >= 0)
                fail_msg("%s refused: %s", what, err);
        } else {
            expect_board_line(&t, (int)k + 1, "longer", what);
        }
        free(t.p);
    }

    /* CRLF line ends: the same board. */
    psc_board_config_t lf, crlf;
    char err[ERRLEN];
    assert_int_equal(board_parse_exact(orig.p, orig.len, &lf, err), 0);
    t = text_from(orig.p, orig.len);
    for (size_t i = 0; i < t.len; i++)
        if (t.p[i] == '\n')
            text_insert(&t, i++, "\r", 1);
    if (board_parse_exact(t.p, t.len, &crlf, err) != 0)
        fail_msg("CRLF board refused: %s", err);
    assert_memory_equal(&lf, &crlf, sizeof lf);
    free(t.p);
    free(orig.p);
}

static void expect_tour_line(const text_t *t, int line, const char *mention, const char *what)
{
    char err[ERRLEN];
    int r = tour_try(t->p, t->len, NULL, err, what);
    if (r < 0)
        fail_msg("%s: the tour was accepted", what);
    if (r != line || (mention && !strstr(err, mention)))
        fail_msg("%s: \"%s\" should name line %d and mention \"%s\"", what, err, line, mention ? mention : "");
    printf("  %s: \"%s\"\n", what, err);
}

/* The first line at or after k that holds a command (not blank, not a comment). */
static unsigned next_command(const text_t *t, unsigned k)
{
    size_t s, e;
    for (; line_span(t, k, &s, &e) == 0; k++) {
        while (s < e && (t->p[s] == ' ' || t->p[s] == '\t'))
            s++;
        if (s < e && t->p[s] != '#' && t->p[s] != '\r')
            return k;
    }
    fail_msg("no command at or after line %u", k + 1);
    return 0;
}

static void test_tour_specific(void **state)
{
    (void)state;
    text_t orig = load_text(TOUR_FILE);
    char buf[700];

    text_t t = text_from(orig.p, orig.len);
    unsigned k = find_line(&t, "wait 1s");
    replace_line(&t, k, "wait 1q");
    expect_tour_line(&t, (int)k + 1, "1q", "wait 1q");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "press home");
    insert_line(&t, k, "end");
    expect_tour_line(&t, (int)next_command(&t, k + 1) + 1, "after 'end'", "'end' in the middle");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "plug 1");
    insert_line(&t, k, "plug 1");
    expect_tour_line(&t, (int)k + 2, "already plugged", "plug 1 twice");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "plug 1");
    delete_line(&t, k);
    /* "device 1" only selects the slot; the next stick command on it fails. */
    unsigned dev = find_line(&t, "device 1");
    expect_tour_line(&t, (int)next_command(&t, dev + 1) + 1, "not plugged", "without plug 1");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "hold 4.05s");
    size_t s, e;
    assert_int_equal(line_span(&t, k, &s, &e), 0);
    text_insert(&t, s + 6, "", 1);
    expect_tour_line(&t, (int)k + 1, "NUL", "a NUL inside 'hold 4.05s ...'");
    free(t.p);

    /* an axis value whose fraction digits would overflow int64 (a bug this test found) */
    t = text_from(orig.p, orig.len);
    k = find_line(&t, "hold 4.05s axis yaw 1.0");
    replace_line(&t, k, "hold 4.05s axis yaw 18446744073710.051616");
    expect_tour_line(&t, (int)k + 1, "18446744073710.051616", "an axis value that wraps int64");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "hold 2s axis pitch");
    memset(buf, ' ', 600);
    memcpy(buf, "wait 1s", 7);
    buf[600] = '\0';
    replace_line(&t, k, buf);
    expect_tour_line(&t, (int)k + 1, "longer", "a 600-character line");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "wait 1.5s");
    replace_line(&t, k, "wait 99999999999999999999s");
    expect_tour_line(&t, (int)k + 1, "99999999999999999999s", "a huge wait");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "wait 1.5s");
    replace_line(&t, k, "wait 86400.001s");
    expect_tour_line(&t, (int)k + 1, "day", "a wait of a day and a millisecond");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "hold 4.05s axis yaw 1.0");
    replace_line(&t, k, "hold 4.05s axis yaw 1.5");
    expect_tour_line(&t, (int)k + 1, "1.5", "axis value 1.5");
    free(t.p);

    t = text_from(orig.p, orig.len);
    k = find_line(&t, "end");
    insert_line(&t, k, "at 2s");
    expect_tour_line(&t, (int)k + 1, "backwards", "'at 2s' at the end");
    free(t.p);

    /* The longest line is 511 characters; 512 is refused, naming the line. */
    for (size_t n = 510; n <= 513; n++) {
        char line[520], what[64];
        memset(line, ' ', n);
        memcpy(line, "wait 1s #", 9);
        line[n] = '\0';
        snprintf(what, sizeof what, "a %zu-character line", n);
        t = text_from(orig.p, orig.len);
        k = find_line(&t, "hold 2s axis pitch");
        insert_line(&t, k, line);
        if (n <= PSC_SIM_TOUR_MAX_LINE) {
            char err[ERRLEN];
            if (tour_try(t.p, t.len, NULL, err, what) >= 0)
                fail_msg("%s refused: %s", what, err);
        } else {
            expect_tour_line(&t, (int)k + 1, "longer", what);
        }
        free(t.p);
    }

    /* CRLF line ends: the same events and end. */
    psc_sim_tour_t lf, crlf;
    char err[ERRLEN];
    assert_int_equal(tour_parse_exact(orig.p, orig.len, &lf, err), 0);
    t = text_from(orig.p, orig.len);
    for (size_t i = 0; i < t.len; i++)
        if (t.p[i] == '\n')
            text_insert(&t, i++, "\r", 1);
    if (tour_parse_exact(t.p, t.len, &crlf, err) != 0)
        fail_msg("CRLF tour refused: %s", err);
    assert_int_equal(crlf.count, lf.count);
    assert_true(crlf.end_us == lf.end_us);
    for (size_t i = 0; i < lf.count; i++) {
        const psc_hal_input_event_t *a = &lf.events[i], *b = &crlf.events[i];
        assert_true(a->type == b->type && a->device == b->device && a->code == b->code && a->value == b->value &&
                    a->time_us == b->time_us);
    }
    psc_sim_tour_free(&lf);
    psc_sim_tour_free(&crlf);
    free(t.p);
    free(orig.p);
}

/* ---- files ------------------------------------------------------------------------------------------------- */

static void test_files(void **state)
{
    (void)state;
    char path[512], err[ERRLEN];
    psc_board_config_t cfg;
    psc_sim_tour_t tour;

    /* A board file over 64 KiB (the valid board, then comments). */
    text_t t = load_text(BOARD_FILE);
    while (t.len <= 64 * 1024)
        insert_line(&t, count_lines(t.p, t.len), "# padding padding padding padding padding padding padding");
    tsup_tmp_path(path, sizeof path, "test_config_fuzz", "big.conf");
    assert_int_equal(tsup_write_bytes(path, t.p, t.len), 0);
    assert_int_not_equal(psc_board_config_load(path, &cfg, err, sizeof err), 0);
    if (!strstr(err, path) || !strstr(err, "larger than the limit of 65536 bytes"))
        fail_msg("board file over 64 KiB: \"%s\"", err);
    printf("  \"%s\"\n", err);
    unlink(path);
    free(t.p);

    /* A corrupt board file on disk: the message names the path given and the line. */
    t = load_text(BOARD_FILE);
    unsigned k = find_line(&t, "frames_every =");
    replace_line(&t, k, "frames_every = often");
    tsup_tmp_path(path, sizeof path, "test_config_fuzz", "board.conf");
    assert_int_equal(tsup_write_bytes(path, t.p, t.len), 0);
    assert_int_not_equal(psc_board_config_load(path, &cfg, err, sizeof err), 0);
    char want[600];
    snprintf(want, sizeof want, "%s:%u: ", path, k + 1);
    if (strncmp(err, want, strlen(want)) != 0)
        fail_msg("corrupt board file: \"%s\" should begin with \"%s\"", err, want);
    unlink(path);
    free(t.p);

    /* The same for a tour file. */
    t = load_text(TOUR_FILE);
    k = find_line(&t, "unplug 1");
    replace_line(&t, k, "unplug 9");
    tsup_tmp_path(path, sizeof path, "test_config_fuzz", "tour.txt");
    assert_int_equal(tsup_write_bytes(path, t.p, t.len), 0);
    assert_int_not_equal(psc_sim_tour_load(path, LONG_PRESS_MS, &tour, err, sizeof err), 0);
    snprintf(want, sizeof want, "%s:%u: ", path, k + 1);
    if (strncmp(err, want, strlen(want)) != 0)
        fail_msg("corrupt tour file: \"%s\" should begin with \"%s\"", err, want);
    assert_int_equal(tour.count, 0);
    unlink(path);
    free(t.p);

    /* A directory where a file should be, and a missing file: named. */
    tsup_tmp_path(path, sizeof path, "test_config_fuzz", "a-directory");
    assert_int_equal(mkdir(path, 0755), 0);
    assert_int_not_equal(psc_board_config_load(path, &cfg, err, sizeof err), 0);
    assert_non_null(strstr(err, path));
    printf("  \"%s\"\n", err);
    assert_int_not_equal(psc_sim_tour_load(path, LONG_PRESS_MS, &tour, err, sizeof err), 0);
    assert_non_null(strstr(err, path));
    assert_int_equal(tour.count, 0);
    printf("  \"%s\"\n", err);
    rmdir(path);
    /* A FIFO (or a device) where a file should be: refused at once, not waited on for a writer. */
    tsup_tmp_path(path, sizeof path, "test_config_fuzz", "a-fifo");
    unlink(path);
    assert_int_equal(mkfifo(path, 0600), 0);
    alarm(20);
    assert_int_not_equal(psc_board_config_load(path, &cfg, err, sizeof err), 0);
    printf("  \"%s\"\n", err);
    assert_true(tsup_msg_starts_with_path(err, path) && strstr(err, "not a regular file (a FIFO)"));
    assert_int_not_equal(psc_sim_tour_load(path, LONG_PRESS_MS, &tour, err, sizeof err), 0);
    assert_true(tsup_msg_starts_with_path(err, path) && strstr(err, "not a regular file (a FIFO)"));
    alarm(0);
    unlink(path);
    tsup_tmp_path(path, sizeof path, "test_config_fuzz", "missing.txt");
    assert_int_not_equal(psc_sim_tour_load(path, LONG_PRESS_MS, &tour, err, sizeof err), 0);
    assert_non_null(strstr(err, path));
    assert_int_not_equal(psc_board_config_load(path, &cfg, err, sizeof err), 0);
    assert_non_null(strstr(err, path));

    /* A tiny error buffer is filled safely. */
    char tiny[8];
    memset(tiny, 'x', sizeof tiny);
    static const char bad[] = "display = sim\nframe_rate = x\n";
    psc_board_config_defaults(&cfg);
    assert_int_equal(psc_board_config_parse(bad, sizeof bad - 1, BOARD_FILE, &cfg, tiny, 6), -1);
    assert_true(strlen(tiny) <= 5);
    assert_int_equal(tiny[7], 'x');
    memset(tiny, 'x', sizeof tiny);
    assert_int_not_equal(psc_sim_tour_parse("jump\n", 5, TOUR_FILE, LONG_PRESS_MS, &tour, tiny, 6), 0);
    assert_true(strlen(tiny) <= 5);
    assert_int_equal(tiny[7], 'x');
}

int main(void)
{
    setvbuf(stdout, NULL, _IONBF, 0); /* keep output in order with cmocka's stderr */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_board_truncated), cmocka_unit_test(test_tour_truncated),
        cmocka_unit_test(test_board_fuzz),      cmocka_unit_test(test_tour_fuzz),
        cmocka_unit_test(test_board_specific),  cmocka_unit_test(test_tour_specific),
        cmocka_unit_test(test_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
