/* SPDX-License-Identifier: MIT */
/*
 * sim_input.c - the simulated board's input: a tour script (psc_sim_tour.h)
 * replayed against the clock the firmware polls with. The whole script is
 * parsed at open, so a mistake in it stops the program before the first
 * frame instead of halfway through a tour.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "psc_sim_tour.h"
#include "sim_internal.h"

typedef struct {
    psc_hal_input_t base;   /* first: the HAL hands this pointer back to us */
    psc_sim_tour_t tour;
    size_t next;            /* index of the next event to deliver */
    uint64_t start_us;      /* clock reading at open: the tour's time 0 */
    bool quit_sent;
} sim_input_t;

static const char *const sim_input_known_options[] = { "script", NULL };

static int sim_input_poll(psc_hal_input_t *in, uint64_t now_us, psc_hal_input_event_t *ev)
{
    sim_input_t *s = (sim_input_t *)in;
    uint64_t t = now_us >= s->start_us ? now_us - s->start_us : 0;

    if (s->quit_sent)
        return 0;
    /* The end wins over events scheduled after it (a press's release). */
    if (s->next < s->tour.count && s->tour.events[s->next].time_us <= t &&
        s->tour.events[s->next].time_us <= s->tour.end_us) {
        *ev = s->tour.events[s->next++];
        ev->time_us += s->start_us;
        return 1;
    }
    if (t >= s->tour.end_us) {
        *ev = (psc_hal_input_event_t){ .type = PSC_HAL_INPUT_QUIT, .time_us = s->start_us + s->tour.end_us };
        s->quit_sent = true;
        return 1;
    }
    return 0;
}

static int sim_input_get_device_name(psc_hal_input_t *in, uint8_t device, char *buf, size_t len)
{
    (void)in;
    if (device >= PSC_HAL_INPUT_MAX_DEVICES)
        return -ENODEV;
    snprintf(buf, len, device == 0 ? "sim keypad" : "sim gamepad %u", (unsigned)device);
    return 0;
}

static void sim_input_close(psc_hal_input_t *in)
{
    sim_input_t *s = (sim_input_t *)in;

    psc_sim_tour_free(&s->tour);
    free(s);
}

static const psc_hal_input_ops_t sim_input_ops = {
    .poll = sim_input_poll,
    .get_device_name = sim_input_get_device_name,
    .close = sim_input_close,
};

int psc_sim_input_open(const psc_hal_input_config_t *cfg, psc_hal_input_t **out, char *err, size_t errlen)
{
    const psc_hal_option_t *script;
    sim_input_t *s;
    int rc;

    *out = NULL;
    rc = psc_hal_options_check(&cfg->options, sim_input_known_options, "input", "sim", err, errlen);
    if (rc != 0)
        return rc;
    script = psc_hal_options_find(&cfg->options, "script");
    if (script == NULL || script->value == NULL || script->value[0] == '\0') {
        psc_hal_error_set(err, errlen, "sim input: no tour script to replay (board key 'tour' or --tour FILE)");
        return -EINVAL;
    }
    s = calloc(1, sizeof *s);
    if (s == NULL) {
        psc_hal_error_set(err, errlen, "sim input: out of memory");
        return -ENOMEM;
    }
    rc = psc_sim_tour_load(script->value, cfg->long_press_ms, &s->tour, err, errlen);
    if (rc != 0) {
        free(s);
        return rc;
    }
    s->base.ops = &sim_input_ops;
    s->base.backend = "sim";
    s->start_us = cfg->clock != NULL ? psc_hal_clock_now_us(cfg->clock) : 0;
    *out = &s->base;
    return 0;
}
