/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_input_multi.c - merge several input backends into one
 * (psc_hal_input_multi.h). One look-ahead event per backend is enough to
 * hand events out in time order, because each backend already returns its
 * own oldest event first.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "psc_hal_input_multi.h"

#define MULTI_NAME_MAX 32u
#define MULTI_UNMAPPED 0xFFu

typedef struct {
    psc_hal_input_t base;                                   /* first: the HAL hands it back */
    size_t count;
    char names[PSC_HAL_INPUT_MULTI_MAX][MULTI_NAME_MAX];
    psc_hal_input_t *inputs[PSC_HAL_INPUT_MULTI_MAX];
    psc_hal_option_t *options[PSC_HAL_INPUT_MULTI_MAX];
    psc_hal_input_event_t ahead[PSC_HAL_INPUT_MULTI_MAX];   /* each backend's next due event */
    bool has_ahead[PSC_HAL_INPUT_MULTI_MAX];
    uint8_t slot_of[PSC_HAL_INPUT_MULTI_MAX][PSC_HAL_INPUT_MAX_DEVICES];   /* backend's slot -> ours */
    uint8_t owner[PSC_HAL_INPUT_MAX_DEVICES];               /* our slot -> backend index, or UNMAPPED */
    uint8_t owner_slot[PSC_HAL_INPUT_MAX_DEVICES];
    uint32_t dropped;
} multi_input_t;

/* Our slot for (backend i, its slot d), allocating one; MULTI_UNMAPPED when full. */
static uint8_t multi_slot(multi_input_t *m, size_t i, uint8_t d)
{
    if (d >= PSC_HAL_INPUT_MAX_DEVICES)
        return MULTI_UNMAPPED;
    if (m->slot_of[i][d] != MULTI_UNMAPPED)
        return m->slot_of[i][d];
    for (uint8_t g = 0; g < PSC_HAL_INPUT_MAX_DEVICES; g++) {
        if (m->owner[g] == MULTI_UNMAPPED) {
            m->owner[g] = (uint8_t)i;
            m->owner_slot[g] = d;
            m->slot_of[i][d] = g;
            return g;
        }
    }
    return MULTI_UNMAPPED;
}

static int multi_poll(psc_hal_input_t *in, uint64_t now_us, psc_hal_input_event_t *ev)
{
    multi_input_t *m = (multi_input_t *)in;

    for (;;) {
        size_t best = m->count;

        for (size_t i = 0; i < m->count; i++) {
            if (!m->has_ahead[i]) {
                int rc = psc_hal_input_poll(m->inputs[i], now_us, &m->ahead[i]);
                if (rc < 0)
                    return rc;
                m->has_ahead[i] = rc == 1;
            }
            if (m->has_ahead[i] && (best == m->count || m->ahead[i].time_us < m->ahead[best].time_us))
                best = i;
        }
        if (best == m->count)
            return 0;
        *ev = m->ahead[best];
        m->has_ahead[best] = false;
        if (ev->type == PSC_HAL_INPUT_QUIT)
            return 1;
        uint8_t local = ev->device, g = multi_slot(m, best, local);
        if (g == MULTI_UNMAPPED) {
            m->dropped++;   /* more devices than slots: this one is not heard */
            continue;
        }
        ev->device = g;
        if (ev->type == PSC_HAL_INPUT_DEVICE_LEAVE) {
            m->owner[g] = MULTI_UNMAPPED;
            m->slot_of[best][local] = MULTI_UNMAPPED;
        }
        return 1;
    }
}

static int multi_get_device_name(psc_hal_input_t *in, uint8_t device, char *buf, size_t len)
{
    multi_input_t *m = (multi_input_t *)in;

    if (device >= PSC_HAL_INPUT_MAX_DEVICES || m->owner[device] == MULTI_UNMAPPED)
        return -ENODEV;
    return psc_hal_input_get_device_name(m->inputs[m->owner[device]], m->owner_slot[device], buf, len);
}

static void multi_close(psc_hal_input_t *in)
{
    multi_input_t *m = (multi_input_t *)in;

    for (size_t i = m->count; i-- > 0;) {
        psc_hal_input_close(m->inputs[i]);
        free(m->options[i]);
    }
    free(m);
}

static const psc_hal_input_ops_t multi_ops = {
    .poll = multi_poll,
    .get_device_name = multi_get_device_name,
    .close = multi_close,
};

/* Split "gpio, usb" into m->names. */
static int multi_parse_list(multi_input_t *m, const char *list, char *err, size_t errlen)
{
    const char *p = list;

    for (;;) {
        const char *start, *end;
        size_t n;

        while (*p == ' ' || *p == '\t')
            p++;
        start = p;
        while (*p && *p != ',')
            p++;
        end = p;
        while (end > start && (end[-1] == ' ' || end[-1] == '\t'))
            end--;
        n = (size_t)(end - start);
        if (n == 0 || n >= MULTI_NAME_MAX || m->count == PSC_HAL_INPUT_MULTI_MAX) {
            psc_hal_error_set(err, errlen, "input '%s': %s", list,
                              n == 0 ? "an empty backend name in the list"
                              : n >= MULTI_NAME_MAX ? "a backend name is too long"
                                                    : "more than 4 backends in the list");
            return -EINVAL;
        }
        memcpy(m->names[m->count], start, n);
        m->names[m->count][n] = '\0';
        for (size_t k = 0; k < m->count; k++) {
            if (strcmp(m->names[k], m->names[m->count]) == 0) {
                psc_hal_error_set(err, errlen, "input '%s': backend '%s' is listed twice", list, m->names[k]);
                return -EINVAL;
            }
        }
        m->count++;
        if (*p == '\0')
            break;
        p++;
    }
    if (m->count < 2) {
        psc_hal_error_set(err, errlen, "input '%s': a list needs at least two backends", list);
        return -EINVAL;
    }
    return 0;
}

/* The backend an option belongs to, and its key as that backend reads it. */
static size_t multi_route(const multi_input_t *m, const char *key, const char **local_key)
{
    *local_key = key;
    for (size_t i = 0; key != NULL && i < m->count; i++) {
        size_t n = strlen(m->names[i]);
        if (strncmp(key, m->names[i], n) == 0 && key[n] == '.' && key[n + 1] != '\0') {
            *local_key = key + n + 1;
            return i;
        }
    }
    return 0;
}

int psc_hal_input_multi_open(const char *list, const psc_hal_input_config_t *cfg, psc_hal_input_t **out,
                             char *err, size_t errlen)
{
    multi_input_t *m;
    int rc;

    *out = NULL;
    m = calloc(1, sizeof *m);
    if (m == NULL) {
        psc_hal_error_set(err, errlen, "input: out of memory");
        return -ENOMEM;
    }
    m->base.ops = &multi_ops;
    m->base.backend = "multi";
    memset(m->slot_of, MULTI_UNMAPPED, sizeof m->slot_of);
    memset(m->owner, MULTI_UNMAPPED, sizeof m->owner);
    rc = multi_parse_list(m, list, err, errlen);
    for (size_t i = 0; rc == 0 && i < m->count; i++) {
        psc_hal_input_config_t sub = *cfg;
        size_t n = 0;

        m->options[i] = calloc(cfg->options.count ? cfg->options.count : 1, sizeof *m->options[i]);
        if (m->options[i] == NULL) {
            psc_hal_error_set(err, errlen, "input: out of memory");
            rc = -ENOMEM;
            break;
        }
        for (size_t k = 0; cfg->options.items != NULL && k < cfg->options.count; k++) {
            const psc_hal_option_t *o = &cfg->options.items[k];
            const char *key;
            if (multi_route(m, o->key, &key) == i)
                m->options[i][n++] = (psc_hal_option_t){ key, o->value, o->origin };
        }
        sub.options = (psc_hal_options_t){ m->options[i], n };
        rc = psc_hal_input_open(m->names[i], &sub, &m->inputs[i], err, errlen);
    }
    if (rc != 0) {
        multi_close(&m->base);
        return rc;
    }
    *out = &m->base;
    return 0;
}
