/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_option_bool.c - yes/no backend options (psc_hal_option_bool.h).
 */
#include <string.h>

#include "psc_hal_option_bool.h"

int psc_hal_options_get_bool(const psc_hal_options_t *opts, const char *key, const char *device, bool def, bool *out,
                             char *err, size_t errlen)
{
    static const char *const yes[] = { "yes", "true", "on", "1" };
    static const char *const no[] = { "no", "false", "off", "0" };
    const psc_hal_option_t *o = psc_hal_options_find(opts, key);
    const char *v;

    *out = def;
    if (o == NULL)
        return 0;
    v = o->value != NULL ? o->value : "";
    for (size_t i = 0; i < sizeof yes / sizeof yes[0]; i++) {
        if (strcmp(v, yes[i]) == 0) {
            *out = true;
            return 0;
        }
        if (strcmp(v, no[i]) == 0) {
            *out = false;
            return 0;
        }
    }
    psc_hal_error_set(err, errlen, "%s: %s option '%s' must be yes or no, got '%s'",
                      o->origin != NULL ? o->origin : "(built-in)", device, key, v);
    return -EINVAL;
}
