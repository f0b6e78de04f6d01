/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_options.c - error text and backend-specific board options.
 *
 * Options arrive as strings with their origin so that every backend reports
 * a bad value the same way: "<file>:<line>: <device> option '<key>' ...".
 */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "psc_hal.h"

void psc_hal_error_set(char *err, size_t errlen, const char *fmt, ...)
{
    va_list ap;

    if (err == NULL || errlen == 0)
        return;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

const psc_hal_option_t *psc_hal_options_find(const psc_hal_options_t *opts, const char *key)
{
    const psc_hal_option_t *found = NULL;

    if (opts == NULL || opts->items == NULL)
        return NULL;
    for (size_t i = 0; i < opts->count; i++)
        if (opts->items[i].key != NULL && strcmp(opts->items[i].key, key) == 0)
            found = &opts->items[i];
    return found;
}

/* Options made up by code may have no origin; never print "(null)". */
static const char *option_origin(const psc_hal_option_t *o)
{
    return o->origin != NULL ? o->origin : "(built-in)";
}

int psc_hal_options_check(const psc_hal_options_t *opts, const char *const *known,
                          const char *device, const char *backend, char *err, size_t errlen)
{
    if (opts == NULL || opts->items == NULL)
        return 0;
    for (size_t i = 0; i < opts->count; i++) {
        const psc_hal_option_t *o = &opts->items[i];
        bool ok = false;
        char list[160] = "";
        size_t used = 0;

        for (size_t k = 0; known != NULL && known[k] != NULL; k++) {
            if (o->key != NULL && strcmp(o->key, known[k]) == 0)
                ok = true;
            if (used < sizeof list) {
                int n = snprintf(list + used, sizeof list - used, "%s%s", k ? ", " : "", known[k]);
                if (n > 0)
                    used += (size_t)n;
            }
        }
        if (!ok) {
            psc_hal_error_set(err, errlen, "%s: %s option '%s' is not known to the %s backend (it knows: %s)",
                              option_origin(o), device, o->key ? o->key : "", backend,
                              list[0] ? list : "no options");
            return -EINVAL;
        }
    }
    return 0;
}

int psc_hal_options_get_u32(const psc_hal_options_t *opts, const char *key, uint32_t min,
                            uint32_t max, uint32_t def, uint32_t *out, char *err, size_t errlen)
{
    const psc_hal_option_t *o = psc_hal_options_find(opts, key);
    uint64_t v = 0;
    const char *p;

    if (o == NULL) {
        *out = def;
        return 0;
    }
    p = o->value != NULL ? o->value : "";
    if (*p == '\0')
        goto bad;
    for (; *p; p++) {
        if (*p < '0' || *p > '9')
            goto bad;
        v = v * 10u + (uint64_t)(*p - '0');
        if (v > max)
            goto bad;
    }
    if (v < min)
        goto bad;
    *out = (uint32_t)v;
    return 0;
bad:
    psc_hal_error_set(err, errlen, "%s: option '%s' must be a whole number from %u to %u, got '%s'",
                      option_origin(o), key, (unsigned)min, (unsigned)max, o->value ? o->value : "");
    return -EINVAL;
}
