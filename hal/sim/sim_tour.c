/* SPDX-License-Identifier: MIT */
/*
 * sim_tour.c - the tour script parser.
 *
 * Tour script format (one command per line; '#' starts a comment anywhere;
 * blank lines are ignored; words are separated by spaces or tabs):
 *
 *   Time is a cursor that starts at 0. Every command acts at the cursor.
 *   TIME is "<n>" or "<n>ms" (milliseconds) or "<x>s" (seconds, decimals
 *   allowed: "1.5s"). ACTION is a logical button (pan_left pan_right look_up
 *   look_down zoom_in zoom_out home next_scene prev_scene select back).
 *   AXIS is yaw (+ turns right), pitch (+ looks up) or zoom (+ zooms in);
 *   VALUE is a decimal from -1.0 to 1.0 (full deflection).
 *
 *   at TIME [COMMAND]          move the cursor to TIME (never backwards), then
 *                              run COMMAND if one follows on the same line
 *   wait TIME                  move the cursor forward by TIME
 *   press ACTION               button down now, up 100 ms later
 *   down ACTION / up ACTION    button down / up now (a long press if held
 *                              for the long-press time or more)
 *   hold TIME ACTION           button down now, up after TIME; the cursor
 *                              moves to the release
 *   axis AXIS VALUE            the stick moves to VALUE and stays there
 *   hold TIME axis AXIS VALUE  the stick at VALUE for TIME, then back to 0;
 *                              the cursor moves to the release
 *   ACTION                     short for "press ACTION"
 *   AXIS VALUE                 short for "axis AXIS VALUE"
 *   device N                   the following button and axis commands come
 *                              from device slot N (0..7; 0, the board's own
 *                              keypad, is plugged in at time 0)
 *   plug N / unplug N          device N arrives / leaves (a gamepad
 *                              hot-plug); leaving releases what it held
 *   tap X Y                    a finger (or click) at display pixel X Y,
 *                              lifted 50 ms later
 *   drag TIME X0 Y0 X1 Y1      a finger down at X0 Y0 moved evenly to X1 Y1
 *                              over TIME (a move every 20 ms), lifted there:
 *                              a short TIME is a flick; the cursor moves
 *                              to the lift
 *   pinch TIME X Y D0 D1       two fingers about X Y, D0 pixels apart
 *                              across, moved to D1 apart over TIME (D1 > D0
 *                              zooms in), lifted; the cursor moves on
 *   wheel N                    the wheel turned N notches (> 0 zooms in)
 *   end                        the tour ends here; without it, it ends with
 *                              its last event
 *
 * Example: pan right at full rate for 4 s, press home, look up, zoom in:
 *   hold 4s axis yaw 1.0
 *   press home
 *   wait 1s
 *   hold 1.5s axis pitch 1.0
 *   hold 2s zoom_in
 *   end
 *
 * Mistakes are errors, not guesses: "<file>:<line>: <problem>" for an
 * unknown command or name, a value out of range, time going backwards, a
 * button released that is not held or pressed while held, a device used
 * while unplugged, anything after "end".
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "psc_hal_parse.h"
#include "psc_io_file.h"
#include "psc_sim_tour.h"

#define TOUR_MAX_WORDS 8u
#define TOUR_HELD_FOREVER UINT64_MAX   /* held by "down" until an "up" */
#define TOUR_NOT_HELD 0u

/* An event and its position in the script, so sorting by time is stable. */
typedef struct {
    psc_hal_input_event_t ev;
    size_t seq;
} tour_item_t;

typedef struct {
    const char *name;
    unsigned line;
    uint32_t long_press_ms;
    uint64_t cursor_ms;
    uint8_t device;
    bool plugged[PSC_HAL_INPUT_MAX_DEVICES];
    /* per device and action: time pressed + 1 (0 = not held), release time */
    uint64_t down_at[PSC_HAL_INPUT_MAX_DEVICES][PSC_HAL_ACTION_COUNT];
    uint64_t up_at[PSC_HAL_INPUT_MAX_DEVICES][PSC_HAL_ACTION_COUNT];
    bool ended;
    tour_item_t *items;
    size_t count, cap;
    uint64_t last_ms;
    char *err;
    size_t errlen;
} tour_parser_t;

static int tour_fail(tour_parser_t *p, const char *what, const char *arg)
{
    psc_hal_error_set(p->err, p->errlen, "%s:%u: %s%s%s%s", p->name, p->line, what,
                      arg ? " '" : "", arg ? arg : "", arg ? "'" : "");
    return -EINVAL;
}

static int tour_add(tour_parser_t *p, uint64_t t_ms, psc_hal_input_type_t type, uint8_t device,
                    uint16_t code, int32_t value)
{
    if (p->count == p->cap) {
        size_t cap = p->cap ? p->cap * 2u : 64u;
        tour_item_t *n;

        if (p->count >= PSC_SIM_TOUR_MAX_EVENTS)
            return tour_fail(p, "the tour has more events than the limit of 65536", NULL);
        n = realloc(p->items, cap * sizeof *n);
        if (n == NULL) {
            psc_hal_error_set(p->err, p->errlen, "%s: out of memory", p->name);
            return -ENOMEM;
        }
        p->items = n;
        p->cap = cap;
    }
    p->items[p->count].ev = (psc_hal_input_event_t){
        .type = type, .device = device, .code = code, .value = value, .time_us = t_ms * 1000u,
    };
    p->items[p->count].seq = p->count;
    p->count++;
    if (t_ms > p->last_ms)
        p->last_ms = t_ms;
    return 0;
}

/* TIME: "250", "250ms", "4s", "1.5s". */
static int tour_parse_time(tour_parser_t *p, const char *s, uint64_t *ms)
{
    char num[32];
    size_t n = strlen(s);
    unsigned digits = 0;
    int64_t v;

    if (n >= 2 && strcmp(s + n - 2, "ms") == 0)
        n -= 2;
    else if (n >= 1 && s[n - 1] == 's') {
        n -= 1;
        digits = 3;   /* seconds with up to millisecond precision */
    }
    if (n == 0 || n >= sizeof num)
        return tour_fail(p, "expected a time like 250, 250ms or 1.5s, got", s);
    memcpy(num, s, n);
    num[n] = '\0';
    if (digits == 0 && strchr(num, '.') != NULL)
        return tour_fail(p, "milliseconds must be whole; write seconds as '1.5s', got", s);
    if (psc_hal_parse_decimal(num, digits, &v) != 0 || v < 0)
        return tour_fail(p, "expected a time like 250, 250ms or 1.5s, got", s);
    if ((uint64_t)v > PSC_SIM_TOUR_MAX_MS)
        return tour_fail(p, "time is longer than a day:", s);
    *ms = (uint64_t)v;
    return 0;
}

/* VALUE in -1.0..1.0 to Q1.15, rounded; +1.0 saturates at 32767. */
static int tour_parse_axis_value(tour_parser_t *p, const char *s, int32_t *q15)
{
    int64_t micro;

    if (psc_hal_parse_decimal(s, 6, &micro) != 0)
        return tour_fail(p, "expected an axis value from -1.0 to 1.0, got", s);
    if (micro < -1000000 || micro > 1000000)
        return tour_fail(p, "axis value is outside -1.0..1.0:", s);
    int64_t q = (micro * 32768 + (micro >= 0 ? 500000 : -500000)) / 1000000;
    if (q > PSC_HAL_AXIS_MAX)
        q = PSC_HAL_AXIS_MAX;
    *q15 = (int32_t)q;
    return 0;
}

static int tour_parse_slot(tour_parser_t *p, const char *s, uint8_t *slot)
{
    int64_t v;

    if (psc_hal_parse_decimal(s, 0, &v) != 0 || v < 0 || v >= (int64_t)PSC_HAL_INPUT_MAX_DEVICES)
        return tour_fail(p, "expected a device slot from 0 to 7, got", s);
    *slot = (uint8_t)v;
    return 0;
}

static int tour_parse_action(tour_parser_t *p, const char *s, psc_hal_action_t *a)
{
    *a = psc_hal_action_parse(s);
    if (*a == PSC_HAL_ACTION_NONE)
        return tour_fail(p, "unknown action (pan_left pan_right look_up look_down zoom_in "
                            "zoom_out home next_scene prev_scene select back):", s);
    return 0;
}

static int tour_parse_axis(tour_parser_t *p, const char *s, psc_hal_axis_t *axis)
{
    int i = psc_hal_axis_parse(s);

    if (i < 0)
        return tour_fail(p, "unknown axis (yaw pitch zoom):", s);
    *axis = (psc_hal_axis_t)i;
    return 0;
}

static bool tour_is_held(const tour_parser_t *p, psc_hal_action_t a)
{
    return p->down_at[p->device][a] != TOUR_NOT_HELD && p->cursor_ms < p->up_at[p->device][a];
}

/* The cursor must be on a plugged device before buttons or axes move. */
static int tour_need_device(tour_parser_t *p)
{
    char slot[8];

    if (p->plugged[p->device])
        return 0;
    snprintf(slot, sizeof slot, "%u", (unsigned)p->device);
    return tour_fail(p, "device is not plugged in (use 'plug N' first):", slot);
}

/* Button down at the cursor, up at up_ms (TOUR_HELD_FOREVER: at a later "up"). */
static int tour_button_down(tour_parser_t *p, psc_hal_action_t a, uint64_t up_ms)
{
    int rc = tour_need_device(p);

    if (rc != 0)
        return rc;
    if (tour_is_held(p, a))
        return tour_fail(p, "button is already held:", psc_hal_action_name(a));
    rc = tour_add(p, p->cursor_ms, PSC_HAL_INPUT_BUTTON_DOWN, p->device, (uint16_t)a, 1);
    if (rc != 0)
        return rc;
    p->down_at[p->device][a] = p->cursor_ms + 1u;
    p->up_at[p->device][a] = up_ms;
    if (up_ms == TOUR_HELD_FOREVER)
        return 0;
    if (up_ms - p->cursor_ms >= p->long_press_ms) {
        rc = tour_add(p, p->cursor_ms + p->long_press_ms, PSC_HAL_INPUT_BUTTON_LONG, p->device, (uint16_t)a, 1);
        if (rc != 0)
            return rc;
    }
    return tour_add(p, up_ms, PSC_HAL_INPUT_BUTTON_UP, p->device, (uint16_t)a, 0);
}

/* The end of an open-ended hold (an "up", an unplug, the end of the tour):
 * a long-press event if it lasted long enough, and the UP if send_up. */
static int tour_button_release(tour_parser_t *p, uint8_t dev, psc_hal_action_t a, uint64_t at_ms, bool send_up)
{
    uint64_t down = p->down_at[dev][a] - 1u;
    int rc = 0;

    if (at_ms - down >= p->long_press_ms)
        rc = tour_add(p, down + p->long_press_ms, PSC_HAL_INPUT_BUTTON_LONG, dev, (uint16_t)a, 1);
    if (rc == 0 && send_up)
        rc = tour_add(p, at_ms, PSC_HAL_INPUT_BUTTON_UP, dev, (uint16_t)a, 0);
    p->down_at[dev][a] = TOUR_NOT_HELD;
    return rc;
}

/* Release what device dev still holds "forever" at at_ms (unplug, end). */
static int tour_release_all(tour_parser_t *p, uint8_t dev, uint64_t at_ms, bool send_up)
{
    for (unsigned a = 1; a < PSC_HAL_ACTION_COUNT; a++) {
        if (p->down_at[dev][a] == TOUR_NOT_HELD)
            continue;
        if (p->up_at[dev][a] != TOUR_HELD_FOREVER) {
            p->down_at[dev][a] = TOUR_NOT_HELD;   /* a timed hold already has its UP */
            continue;
        }
        int rc = tour_button_release(p, dev, (psc_hal_action_t)a, at_ms, send_up);
        if (rc != 0)
            return rc;
    }
    return 0;
}

static int tour_move_cursor(tour_parser_t *p, uint64_t ms)
{
    if (ms < p->cursor_ms) {
        psc_hal_error_set(p->err, p->errlen, "%s:%u: time goes backwards: asked for %llu ms but the "
                          "cursor is already at %llu ms", p->name, p->line,
                          (unsigned long long)ms, (unsigned long long)p->cursor_ms);
        return -EINVAL;
    }
    if (ms > PSC_SIM_TOUR_MAX_MS)
        return tour_fail(p, "the tour is longer than a day", NULL);
    p->cursor_ms = ms;
    return 0;
}

static int tour_command(tour_parser_t *p, char **w, unsigned n);

/* hold TIME ACTION | hold TIME axis AXIS VALUE */
static int tour_cmd_hold(tour_parser_t *p, char **w, unsigned n)
{
    uint64_t ms = 0, up;
    int rc;

    if (n < 3)
        return tour_fail(p, "expected 'hold TIME ACTION' or 'hold TIME axis AXIS VALUE'", NULL);
    rc = tour_parse_time(p, w[1], &ms);
    if (rc != 0)
        return rc;
    up = p->cursor_ms + ms;
    if (strcmp(w[2], "axis") == 0 || (n == 4 && psc_hal_axis_parse(w[2]) >= 0)) {
        unsigned k = strcmp(w[2], "axis") == 0 ? 3u : 2u;
        psc_hal_axis_t axis = PSC_HAL_AXIS_YAW;
        int32_t q = 0;

        if (n != k + 2u)
            return tour_fail(p, "expected 'hold TIME axis AXIS VALUE'", NULL);
        if ((rc = tour_need_device(p)) != 0 || (rc = tour_parse_axis(p, w[k], &axis)) != 0 ||
            (rc = tour_parse_axis_value(p, w[k + 1u], &q)) != 0)
            return rc;
        rc = tour_add(p, p->cursor_ms, PSC_HAL_INPUT_AXIS, p->device, (uint16_t)axis, q);
        if (rc == 0)
            rc = tour_add(p, up, PSC_HAL_INPUT_AXIS, p->device, (uint16_t)axis, 0);
    } else {
        psc_hal_action_t a = PSC_HAL_ACTION_NONE;

        if (n != 3)
            return tour_fail(p, "expected 'hold TIME ACTION'", NULL);
        if ((rc = tour_parse_action(p, w[2], &a)) != 0)
            return rc;
        if (ms == 0)
            return tour_fail(p, "a hold must last longer than 0 ms", NULL);
        rc = tour_button_down(p, a, up);
    }
    return rc != 0 ? rc : tour_move_cursor(p, up);
}

static int tour_cmd_button(tour_parser_t *p, const char *cmd, char **w, unsigned n)
{
    psc_hal_action_t a = PSC_HAL_ACTION_NONE;
    int rc;

    if (n != 2)
        return tour_fail(p, "expected one action after", cmd);
    if ((rc = tour_parse_action(p, w[1], &a)) != 0)
        return rc;
    if (strcmp(cmd, "press") == 0)
        return tour_button_down(p, a, p->cursor_ms + PSC_SIM_TOUR_PRESS_MS);
    if (strcmp(cmd, "down") == 0)
        return tour_button_down(p, a, TOUR_HELD_FOREVER);
    if ((rc = tour_need_device(p)) != 0)
        return rc;
    if (!tour_is_held(p, a) || p->up_at[p->device][a] != TOUR_HELD_FOREVER)
        return tour_fail(p, "'up' for a button that no 'down' holds:", w[1]);
    return tour_button_release(p, p->device, a, p->cursor_ms, true);
}

static int tour_cmd_axis(tour_parser_t *p, char **w, unsigned n)
{
    psc_hal_axis_t axis = PSC_HAL_AXIS_YAW;
    int32_t q = 0;
    int rc;

    if (n != 3)
        return tour_fail(p, "expected 'axis AXIS VALUE'", NULL);
    if ((rc = tour_need_device(p)) != 0 || (rc = tour_parse_axis(p, w[1], &axis)) != 0 ||
        (rc = tour_parse_axis_value(p, w[2], &q)) != 0)
        return rc;
    return tour_add(p, p->cursor_ms, PSC_HAL_INPUT_AXIS, p->device, (uint16_t)axis, q);
}

static int tour_cmd_plug(tour_parser_t *p, bool plug, char **w, unsigned n)
{
    uint8_t slot = 0;
    int rc;

    if (n != 2)
        return tour_fail(p, plug ? "expected 'plug N'" : "expected 'unplug N'", NULL);
    if ((rc = tour_parse_slot(p, w[1], &slot)) != 0)
        return rc;
    if (plug == p->plugged[slot])
        return tour_fail(p, plug ? "device is already plugged in:" : "device is not plugged in:", w[1]);
    if (!plug && (rc = tour_release_all(p, slot, p->cursor_ms, false)) != 0)
        return rc;
    p->plugged[slot] = plug;
    return tour_add(p, p->cursor_ms, plug ? PSC_HAL_INPUT_DEVICE_ARRIVE : PSC_HAL_INPUT_DEVICE_LEAVE, slot, 0, 0);
}

static int tour_add_pointer(tour_parser_t *p, uint64_t t_ms, psc_hal_input_type_t type, uint16_t contact, int32_t x,
                            int32_t y)
{
    int rc = tour_add(p, t_ms, type, p->device, contact, 0);

    if (rc == 0) {
        p->items[p->count - 1u].ev.x = (int16_t)x;
        p->items[p->count - 1u].ev.y = (int16_t)y;
    }
    return rc;
}

/* A pixel coordinate: a whole number, -32768..32767 (off the display is allowed). */
static int tour_parse_pixel(tour_parser_t *p, const char *s, int32_t *v)
{
    int64_t n;

    if (psc_hal_parse_decimal(s, 0, &n) != 0 || n < -32768 || n > 32767)
        return tour_fail(p, "expected a pixel coordinate, a whole number from -32768 to 32767, got", s);
    *v = (int32_t)n;
    return 0;
}

/* tap X Y | drag TIME X0 Y0 X1 Y1 | pinch TIME X Y D0 D1 | wheel N */
static int tour_cmd_pointer(tour_parser_t *p, char **w, unsigned n)
{
    int32_t v[5] = { 0, 0, 0, 0, 0 };
    uint64_t ms = 0, t0 = p->cursor_ms;
    bool tap = w[0][0] == 't', wheel = w[0][0] == 'w', pinch = w[0][0] == 'p';
    unsigned want = tap ? 3u : wheel ? 2u : 6u, first = tap || wheel ? 1u : 2u;
    int rc;

    if (n != want)
        return tour_fail(p, tap ? "expected 'tap X Y'" : wheel ? "expected 'wheel N'" :
                            pinch ? "expected 'pinch TIME X Y D0 D1'" : "expected 'drag TIME X0 Y0 X1 Y1'", NULL);
    if ((rc = tour_need_device(p)) != 0 || (!tap && !wheel && (rc = tour_parse_time(p, w[1], &ms)) != 0))
        return rc;
    for (unsigned i = first; i < n; i++)
        if ((rc = tour_parse_pixel(p, w[i], &v[i - first])) != 0)
            return rc;
    if (wheel)
        return tour_add(p, t0, PSC_HAL_INPUT_WHEEL, p->device, 0, v[0]);
    if (tap) {
        if ((rc = tour_add_pointer(p, t0, PSC_HAL_INPUT_POINTER_DOWN, 0, v[0], v[1])) != 0)
            return rc;
        return tour_add_pointer(p, t0 + 50u, PSC_HAL_INPUT_POINTER_UP, 0, v[0], v[1]);
    }
    if (ms == 0)
        return tour_fail(p, "a drag or pinch takes some time, got", w[1]);
    unsigned steps = (unsigned)((ms + 19u) / 20u);
    for (unsigned k = 0; k <= steps; k++) {
        uint64_t t = t0 + ms * k / steps;
        psc_hal_input_type_t type = k == 0 ? PSC_HAL_INPUT_POINTER_DOWN : PSC_HAL_INPUT_POINTER_MOVE;
        int64_t a = (int64_t)v[pinch ? 2 : 0], b = (int64_t)v[pinch ? 3 : 2];
        int32_t x = (int32_t)(a + (b - a) * (int64_t)k / (int64_t)steps);
        if (!pinch) {
            int32_t y = (int32_t)(v[1] + ((int64_t)v[3] - v[1]) * (int64_t)k / (int64_t)steps);
            rc = tour_add_pointer(p, t, type, 0, x, y);
        } else {
            /* x is the fingers' distance here: half of it each side of the centre */
            rc = tour_add_pointer(p, t, type, 0, v[0] - x / 2, v[1]);
            if (rc == 0)
                rc = tour_add_pointer(p, t, type, 1, v[0] + (x - x / 2), v[1]);
        }
        if (rc != 0)
            return rc;
    }
    /* lifted where the last step left them (copies: adding may move the items) */
    int32_t lx = p->items[p->count - 1u].ev.x, ly = p->items[p->count - 1u].ev.y;
    int32_t fx = pinch ? p->items[p->count - 2u].ev.x : lx;
    if ((rc = tour_add_pointer(p, t0 + ms, PSC_HAL_INPUT_POINTER_UP, 0, fx, ly)) != 0)
        return rc;
    if (pinch && (rc = tour_add_pointer(p, t0 + ms, PSC_HAL_INPUT_POINTER_UP, 1, lx, ly)) != 0)
        return rc;
    return tour_move_cursor(p, t0 + ms);
}

/* One command, its words already split; w[0] is the command. */
static int tour_command(tour_parser_t *p, char **w, unsigned n)
{
    const char *cmd = w[0];
    uint64_t ms = 0;
    int rc;

    if (p->ended)
        return tour_fail(p, "command after 'end':", cmd);
    if (strcmp(cmd, "at") == 0 || strcmp(cmd, "wait") == 0) {
        if (n < 2 || (cmd[0] == 'w' && n != 2))
            return tour_fail(p, cmd[0] == 'a' ? "expected 'at TIME [COMMAND]'" : "expected 'wait TIME'", NULL);
        if ((rc = tour_parse_time(p, w[1], &ms)) != 0)
            return rc;
        rc = tour_move_cursor(p, cmd[0] == 'a' ? ms : p->cursor_ms + ms);
        return (rc != 0 || n == 2) ? rc : tour_command(p, w + 2, n - 2u);
    }
    if (strcmp(cmd, "press") == 0 || strcmp(cmd, "down") == 0 || strcmp(cmd, "up") == 0)
        return tour_cmd_button(p, cmd, w, n);
    if (strcmp(cmd, "hold") == 0)
        return tour_cmd_hold(p, w, n);
    if (strcmp(cmd, "axis") == 0)
        return tour_cmd_axis(p, w, n);
    if (strcmp(cmd, "plug") == 0 || strcmp(cmd, "unplug") == 0)
        return tour_cmd_plug(p, cmd[0] == 'p', w, n);
    if (strcmp(cmd, "tap") == 0 || strcmp(cmd, "drag") == 0 || strcmp(cmd, "pinch") == 0 ||
        strcmp(cmd, "wheel") == 0)
        return tour_cmd_pointer(p, w, n);
    if (strcmp(cmd, "device") == 0) {
        if (n != 2)
            return tour_fail(p, "expected 'device N'", NULL);
        return tour_parse_slot(p, w[1], &p->device);
    }
    if (strcmp(cmd, "end") == 0) {
        if (n != 1)
            return tour_fail(p, "'end' takes nothing after it", NULL);
        p->ended = true;
        return 0;
    }
    /* the short forms: "home" = "press home", "yaw 0.5" = "axis yaw 0.5" */
    if (psc_hal_action_parse(cmd) != PSC_HAL_ACTION_NONE && n == 1) {
        char *pw[2] = { "press", w[0] };
        return tour_cmd_button(p, "press", pw, 2);
    }
    if (psc_hal_axis_parse(cmd) >= 0 && n == 2) {
        char *aw[3] = { "axis", w[0], w[1] };
        return tour_cmd_axis(p, aw, 3);
    }
    return tour_fail(p, "unknown command (at wait press down up hold axis tap drag pinch wheel device plug unplug "
                        "end, or an action or axis name):", cmd);
}

/* Split line (modified in place) into words, stopping at '#'. */
static unsigned tour_split(char *line, char **w)
{
    unsigned n = 0;
    char *s = line;

    for (;;) {
        while (*s == ' ' || *s == '\t' || *s == '\r')
            s++;
        if (*s == '\0' || *s == '#')
            break;
        if (n == TOUR_MAX_WORDS)
            return n + 1u;   /* too many: the caller reports it */
        w[n++] = s;
        while (*s && *s != ' ' && *s != '\t' && *s != '\r' && *s != '#')
            s++;
        if (*s == '#') {
            *s = '\0';
            break;
        }
        if (*s)
            *s++ = '\0';
    }
    return n;
}

static int tour_item_compare(const void *a, const void *b)
{
    const tour_item_t *x = a, *y = b;

    if (x->ev.time_us != y->ev.time_us)
        return x->ev.time_us < y->ev.time_us ? -1 : 1;
    return x->seq < y->seq ? -1 : x->seq > y->seq;
}

/* Sort the parsed items by time and keep just the events. */
static int tour_finish(tour_parser_t *p, psc_sim_tour_t *tour)
{
    uint64_t end_ms = p->ended ? p->cursor_ms : (p->cursor_ms > p->last_ms ? p->cursor_ms : p->last_ms);
    psc_hal_input_event_t *ev;
    int rc = 0;

    for (unsigned d = 0; d < PSC_HAL_INPUT_MAX_DEVICES && rc == 0; d++)
        rc = tour_release_all(p, (uint8_t)d, end_ms, false);
    if (rc != 0)
        return rc;
    qsort(p->items, p->count, sizeof *p->items, tour_item_compare);
    ev = malloc((p->count ? p->count : 1u) * sizeof *ev);
    if (ev == NULL) {
        psc_hal_error_set(p->err, p->errlen, "%s: out of memory", p->name);
        return -ENOMEM;
    }
    for (size_t i = 0; i < p->count; i++)
        ev[i] = p->items[i].ev;
    tour->events = ev;
    tour->count = p->count;
    tour->end_us = end_ms * 1000u;
    return 0;
}

int psc_sim_tour_parse(const char *text, size_t len, const char *name, uint32_t long_press_ms,
                       psc_sim_tour_t *tour, char *err, size_t errlen)
{
    tour_parser_t *p;
    size_t pos = 0;
    int rc = 0;

    memset(tour, 0, sizeof *tour);
    p = calloc(1, sizeof *p);
    if (p == NULL) {
        psc_hal_error_set(err, errlen, "%s: out of memory", name);
        return -ENOMEM;
    }
    p->name = name;
    p->long_press_ms = long_press_ms ? long_press_ms : PSC_SIM_TOUR_LONG_PRESS_MS;
    p->err = err;
    p->errlen = errlen;
    p->plugged[0] = true;
    rc = tour_add(p, 0, PSC_HAL_INPUT_DEVICE_ARRIVE, 0, 0, 0);

    while (rc == 0 && pos < len) {
        char line[PSC_SIM_TOUR_MAX_LINE + 1];
        char *w[TOUR_MAX_WORDS];
        size_t start = pos, n;
        unsigned words;

        while (pos < len && text[pos] != '\n')
            pos++;
        n = pos - start;
        pos++;   /* past the newline */
        p->line++;
        if (memchr(text + start, '\0', n) != NULL) {
            rc = tour_fail(p, "the line contains a NUL byte (is this a text file?)", NULL);
            break;
        }
        if (n > PSC_SIM_TOUR_MAX_LINE) {
            rc = tour_fail(p, "the line is longer than 511 characters", NULL);
            break;
        }
        memcpy(line, text + start, n);
        line[n] = '\0';
        words = tour_split(line, w);
        if (words == 0)
            continue;
        if (words > TOUR_MAX_WORDS) {
            rc = tour_fail(p, "too many words on the line", NULL);
            break;
        }
        rc = tour_command(p, w, words);
    }
    if (rc == 0)
        rc = tour_finish(p, tour);
    free(p->items);
    free(p);
    return rc;
}

int psc_sim_tour_load(const char *path, uint32_t long_press_ms, psc_sim_tour_t *tour,
                      char *err, size_t errlen)
{
    FILE *f;
    char *buf = NULL;
    size_t len = 0, cap = 0;
    int rc;

    memset(tour, 0, sizeof *tour);
    f = psc_io_fopen_regular(path, (uint64_t)16 << 20, err, errlen);
    if (f == NULL)
        return -EIO;
    for (;;) {
        if (len == cap) {
            char *n;
            if (cap >= (size_t)16 << 20) {
                fclose(f);
                free(buf);
                psc_hal_error_set(err, errlen, "tour script %s is larger than 16 MiB", path);
                return -EINVAL;
            }
            cap = cap ? cap * 2u : 4096u;
            n = realloc(buf, cap);
            if (n == NULL) {
                fclose(f);
                free(buf);
                psc_hal_error_set(err, errlen, "%s: out of memory", path);
                return -ENOMEM;
            }
            buf = n;
        }
        size_t got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0)
            break;
    }
    if (ferror(f)) {
        fclose(f);
        free(buf);
        psc_hal_error_set(err, errlen, "cannot read tour script %s: read error", path);
        return -EIO;
    }
    fclose(f);
    rc = psc_sim_tour_parse(buf, len, path, long_press_ms, tour, err, errlen);
    free(buf);
    return rc;
}

void psc_sim_tour_free(psc_sim_tour_t *tour)
{
    if (tour == NULL)
        return;
    free(tour->events);
    tour->events = NULL;
    tour->count = 0;
    tour->end_us = 0;
}
