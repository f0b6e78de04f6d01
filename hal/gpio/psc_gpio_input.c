/* SPDX-License-Identifier: MIT */
/*
 * psc_gpio_input.c - the "gpio" input backend: push buttons on GPIO lines,
 * found by line name on any chip (psc_gpio_lines.h), debounced, with long
 * press (psc_hal_button.h).
 *
 * Board options ("input.KEY = VALUE"):
 *   line.ACTION = NAME    the button for ACTION (home, next_scene, pan_left,
 *                         ... see psc_hal_input.h) is GPIO line NAME, as
 *                         gpioinfo shows it (at least one, up to 16)
 *   active_low = yes|no   pressed pulls the line low (default yes: a button
 *                         to ground with a pull-up)
 *   bias = pull-up | pull-down | disabled | as-is   (default pull-up)
 *   debounce_ms = 0..1000 (default 10): by the kernel with libgpiod 2.x,
 *                         in software with 1.6 (or when the kernel refuses)
 *   rescan_ms = 50..60000 (default 1000): how often missing lines are
 *                         looked for again
 *   dev_dir = DIR         where the gpiochipN nodes are (default /dev)
 *
 * The buttons are one device, slot 0, "present" while every named line is
 * requested. Lines missing at start-up (a HAT not plugged, a gpio-sim chip
 * not yet made) are not an error: the reason is printed once and the lines
 * are looked for every rescan_ms; DEVICE_ARRIVE follows when all are there.
 * A chip that goes away mid-run (-ENODEV) gives DEVICE_LEAVE and the same
 * search. Finding and requesting lines allocates (libgpiod); the steady
 * state of reading edges does not.
 *
 * Times: kernel edge timestamps (CLOCK_MONOTONIC) are turned into the
 * input clock's time by their age at the poll that reads them, so the
 * debounce and long-press arithmetic runs in one time base whatever clock
 * the board uses.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "psc_gpio_lines.h"
#include "psc_hal_backends.h"
#include "psc_hal_button.h"
#include "psc_hal_clock.h"
#include "psc_hal_event_queue.h"
#include "psc_hal_input.h"
#include "psc_io_log.h"

#define GPIO_QUEUE_LEN 64u
#define GPIO_EDGES_PER_POLL 32u
#define GPIO_DEFAULT_DEBOUNCE_MS 10u
#define GPIO_DEFAULT_RESCAN_MS 1000u

typedef struct {
    psc_hal_input_t base;               /* first: the HAL hands this pointer back */
    psc_hal_clock_t *clock;
    size_t count;
    char names[PSC_GPIO_MAX_LINES][64];
    const char *name_ptrs[PSC_GPIO_MAX_LINES];
    psc_hal_action_t actions[PSC_GPIO_MAX_LINES];
    char dev_dir[128];
    psc_gpio_settings_t settings;
    uint32_t debounce_us;
    psc_hal_button_timing_t timing;     /* debounce 0 when the kernel does it */
    psc_gpio_lines_t *lines;            /* NULL while not every line is there */
    psc_hal_button_t buttons[PSC_GPIO_MAX_LINES];
    uint64_t rescan_us, next_try_us, last_t_us;
    char last_error[256];
    char device_name[160];
    psc_hal_input_event_t queue_store[GPIO_QUEUE_LEN];
    psc_hal_event_queue_t queue;
    psc_gpio_edge_t edges[GPIO_EDGES_PER_POLL];
} gpio_input_t;

static void gpio_queue(gpio_input_t *s, psc_hal_input_type_t type, uint16_t code, int32_t value, uint64_t t)
{
    psc_hal_input_event_t ev = { .type = type, .device = 0, .code = code, .value = value, .time_us = t };

    (void)psc_hal_event_queue_push(&s->queue, &ev);
}

static void gpio_advance(gpio_input_t *s, size_t i, uint64_t t)
{
    psc_hal_button_edge_t edges[2];
    unsigned n = psc_hal_button_advance(&s->buttons[i], &s->timing, t, edges);

    for (unsigned k = 0; k < n; k++)
        gpio_queue(s, edges[k].type, (uint16_t)s->actions[i], edges[k].type == PSC_HAL_INPUT_BUTTON_UP ? 0 : 1,
                   edges[k].time_us);
}

static uint64_t gpio_monotonic_ns(void)
{
    struct timespec ts;

    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

/* Look for the lines; on success the device arrives with its current levels. */
static void gpio_try_open(gpio_input_t *s, uint64_t now)
{
    char err[256];
    int rc = psc_gpio_lines_open(s->name_ptrs, s->count, &s->settings, &s->lines, err, sizeof err);

    if (rc != 0) {
        s->lines = NULL;
        if (strcmp(err, s->last_error) != 0) {   /* say it once, and again only if it changes */
            psc_io_log(PSC_LOG_WARNING, "periscope: gpio input: %s; looking again every %llu ms", err,
                    (unsigned long long)(s->rescan_us / 1000u));
            snprintf(s->last_error, sizeof s->last_error, "%s", err);
        }
        return;
    }
    s->last_error[0] = '\0';
    s->timing.debounce_us = psc_gpio_lines_kernel_debounce(s->lines) ? 0 : s->debounce_us;
    psc_gpio_lines_describe(s->lines, err, sizeof err);
    snprintf(s->device_name, sizeof s->device_name, "GPIO buttons on %.140s", err);
    gpio_queue(s, PSC_HAL_INPUT_DEVICE_ARRIVE, 0, 0, now);
    for (size_t i = 0; i < s->count; i++) {
        int v = psc_gpio_lines_get(s->lines, i);
        psc_hal_button_init(&s->buttons[i], now);
        /* a button already held counts as pressed once it has been for the debounce time */
        psc_hal_button_set(&s->buttons[i], v == 1, now);
    }
    s->last_t_us = now;
}

static void gpio_lost(gpio_input_t *s, uint64_t now)
{
    psc_io_log(PSC_LOG_WARNING, "periscope: gpio input: lost the lines (%s went away); looking for them every %llu ms",
            s->device_name, (unsigned long long)(s->rescan_us / 1000u));
    psc_gpio_lines_close(s->lines);
    s->lines = NULL;
    gpio_queue(s, PSC_HAL_INPUT_DEVICE_LEAVE, 0, 0, now);
    s->next_try_us = now + s->rescan_us;
}

static int gpio_poll(psc_hal_input_t *in, uint64_t now, psc_hal_input_event_t *ev)
{
    gpio_input_t *s = (gpio_input_t *)in;

    if (s->lines == NULL && now >= s->next_try_us) {
        gpio_try_open(s, now);
        s->next_try_us = now + s->rescan_us;
    }
    if (s->lines != NULL) {
        int n = psc_gpio_lines_read(s->lines, s->edges, GPIO_EDGES_PER_POLL);
        uint64_t mono = n > 0 ? gpio_monotonic_ns() : 0;

        if (n < 0) {
            gpio_lost(s, now);
        } else {
            for (int k = 0; k < n; k++) {
                const psc_gpio_edge_t *e = &s->edges[k];
                uint64_t age_us = mono > e->time_ns ? (mono - e->time_ns) / 1000u : 0;
                uint64_t t = age_us < now ? now - age_us : 0;

                if (t < s->last_t_us)
                    t = s->last_t_us;   /* never back in time, whatever the two clocks did */
                s->last_t_us = t;
                gpio_advance(s, e->line, t);
                psc_hal_button_set(&s->buttons[e->line], e->level, t);
            }
            for (size_t i = 0; i < s->count; i++)
                gpio_advance(s, i, now);
        }
    }
    return psc_hal_event_queue_pop(&s->queue, now, ev);
}

static int gpio_get_device_name(psc_hal_input_t *in, uint8_t device, char *buf, size_t len)
{
    gpio_input_t *s = (gpio_input_t *)in;

    if (device != 0)
        return -ENODEV;
    snprintf(buf, len, "%s", s->device_name[0] ? s->device_name : "GPIO buttons");
    return 0;
}

static void gpio_close(psc_hal_input_t *in)
{
    gpio_input_t *s = (gpio_input_t *)in;

    psc_gpio_lines_close(s->lines);
    free(s);
}

static const psc_hal_input_ops_t gpio_input_ops = {
    .poll = gpio_poll,
    .get_device_name = gpio_get_device_name,
    .close = gpio_close,
};

static const char *gpio_origin(const psc_hal_option_t *o)
{
    return o->origin != NULL ? o->origin : "(built-in)";
}

/* The options that are not line.ACTION: parse them into s. */
static int gpio_parse_setting(gpio_input_t *s, const psc_hal_option_t *o, char *err, size_t errlen)
{
    const char *v = o->value != NULL ? o->value : "";

    if (strcmp(o->key, "active_low") == 0) {
        if (strcmp(v, "yes") != 0 && strcmp(v, "no") != 0) {
            psc_hal_error_set(err, errlen, "%s: gpio input option 'active_low' must be yes or no, got '%s'",
                              gpio_origin(o), v);
            return -EINVAL;
        }
        s->settings.active_low = v[0] == 'y';
    } else if (strcmp(o->key, "bias") == 0) {
        static const char *const names[] = { "as-is", "disabled", "pull-up", "pull-down" };
        unsigned b = 0;
        while (b < 4 && strcmp(v, names[b]) != 0)
            b++;
        if (b == 4) {
            psc_hal_error_set(err, errlen, "%s: gpio input option 'bias' must be pull-up, pull-down, disabled or "
                              "as-is, got '%s'", gpio_origin(o), v);
            return -EINVAL;
        }
        s->settings.bias = (psc_gpio_bias_t)b;
    } else if (strcmp(o->key, "dev_dir") == 0) {
        snprintf(s->dev_dir, sizeof s->dev_dir, "%s", v);
    } else if (strcmp(o->key, "debounce_ms") != 0 && strcmp(o->key, "rescan_ms") != 0) {
        psc_hal_error_set(err, errlen, "%s: input option '%s' is not known to the gpio backend (it knows: "
                          "line.ACTION, active_low, bias, debounce_ms, rescan_ms, dev_dir)", gpio_origin(o), o->key);
        return -EINVAL;
    }
    return 0;
}

/* "line.home = BTN_HOME": one button. */
static int gpio_parse_line(gpio_input_t *s, const psc_hal_option_t *o, char *err, size_t errlen)
{
    psc_hal_action_t action = psc_hal_action_parse(o->key + 5);
    const char *v = o->value != NULL ? o->value : "";

    if (action == PSC_HAL_ACTION_NONE) {
        psc_hal_error_set(err, errlen, "%s: gpio input option '%s': '%s' is not an action (pan_left pan_right "
                          "look_up look_down zoom_in zoom_out home next_scene prev_scene select back)",
                          gpio_origin(o), o->key, o->key + 5);
        return -EINVAL;
    }
    if (v[0] == '\0' || strlen(v) >= sizeof s->names[0]) {
        psc_hal_error_set(err, errlen, "%s: gpio input option '%s': the line name must be 1 to %u characters",
                          gpio_origin(o), o->key, (unsigned)sizeof s->names[0] - 1u);
        return -EINVAL;
    }
    for (size_t i = 0; i < s->count; i++) {
        if (s->actions[i] == action || strcmp(s->names[i], v) == 0) {
            psc_hal_error_set(err, errlen, "%s: gpio input option '%s': %s", gpio_origin(o), o->key,
                              s->actions[i] == action ? "that action already has a line"
                                                      : "that line already serves another action");
            return -EINVAL;
        }
    }
    if (s->count == PSC_GPIO_MAX_LINES) {
        psc_hal_error_set(err, errlen, "%s: gpio input: more than %u lines", gpio_origin(o),
                          (unsigned)PSC_GPIO_MAX_LINES);
        return -EINVAL;
    }
    snprintf(s->names[s->count], sizeof s->names[0], "%s", v);
    s->name_ptrs[s->count] = s->names[s->count];
    s->actions[s->count++] = action;
    return 0;
}

static int gpio_input_open(const psc_hal_input_config_t *cfg, psc_hal_input_t **out, char *err, size_t errlen)
{
    const psc_hal_options_t *opts = &cfg->options;
    uint32_t debounce_ms = 0, rescan_ms = 0;
    gpio_input_t *s;
    int rc = 0;

    *out = NULL;
    s = calloc(1, sizeof *s);
    if (s == NULL) {
        psc_hal_error_set(err, errlen, "gpio input: out of memory");
        return -ENOMEM;
    }
    s->base.ops = &gpio_input_ops;
    s->base.backend = "gpio";
    s->clock = cfg->clock;
    s->settings = (psc_gpio_settings_t){ .active_low = true, .bias = PSC_GPIO_BIAS_PULL_UP,
                                         .consumer = "periscope", .dev_dir = NULL };
    psc_hal_event_queue_init(&s->queue, s->queue_store, GPIO_QUEUE_LEN);
    for (size_t i = 0; opts->items != NULL && i < opts->count && rc == 0; i++) {
        const psc_hal_option_t *o = &opts->items[i];
        if (o->key == NULL)
            continue;
        rc = strncmp(o->key, "line.", 5) == 0 ? gpio_parse_line(s, o, err, errlen)
                                              : gpio_parse_setting(s, o, err, errlen);
    }
    if (rc == 0)
        rc = psc_hal_options_get_u32(opts, "debounce_ms", 0, 1000, GPIO_DEFAULT_DEBOUNCE_MS, &debounce_ms, err,
                                     errlen);
    if (rc == 0)
        rc = psc_hal_options_get_u32(opts, "rescan_ms", 50, 60000, GPIO_DEFAULT_RESCAN_MS, &rescan_ms, err, errlen);
    if (rc == 0 && s->count == 0) {
        psc_hal_error_set(err, errlen, "gpio input: no buttons: add lines like 'input.line.home = BTN_HOME' "
                          "(action = GPIO line name) to the board file");
        rc = -EINVAL;
    }
    if (rc != 0) {
        free(s);
        return rc;
    }
    if (s->dev_dir[0] != '\0')
        s->settings.dev_dir = s->dev_dir;
    s->debounce_us = debounce_ms * 1000u;
    s->settings.debounce_us = s->debounce_us;
    s->timing = (psc_hal_button_timing_t){ s->debounce_us, (cfg->long_press_ms ? cfg->long_press_ms : 800u) * 1000u };
    s->rescan_us = (uint64_t)rescan_ms * 1000u;
    /* look for the lines now, so a board whose lines are there starts with them */
    gpio_try_open(s, cfg->clock != NULL ? psc_hal_clock_now_us(cfg->clock) : 0);
    s->next_try_us = (cfg->clock != NULL ? psc_hal_clock_now_us(cfg->clock) : 0) + s->rescan_us;
    *out = &s->base;
    return 0;
}

const psc_hal_backend_t psc_hal_gpio_backend = {
    .name = "gpio",
    .description = "push buttons on GPIO lines found by name (libgpiod 1.6 or 2.x), debounced, long press",
    .input_open = gpio_input_open,
};
