/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_parse.c - decimal text to scaled integers, without strtod: the
 * firmware and HAL keep floating point out of the device program entirely,
 * and strtod would also accept forms ("1e3", "inf", hex) a board file should
 * not contain.
 */
#include <errno.h>
#include <stdbool.h>
#include <stddef.h>

#include "psc_hal_parse.h"

int psc_hal_parse_decimal(const char *s, unsigned frac_digits, int64_t *out)
{
    bool neg = false, any = false, round_up = false;
    int64_t v = 0;
    unsigned frac = 0;

    if (s == NULL || frac_digits > 9)
        return -EINVAL;
    if (*s == '+' || *s == '-')
        neg = (*s++ == '-');
    for (; *s >= '0' && *s <= '9'; s++) {
        v = v * 10 + (*s - '0');
        any = true;
        if (v > PSC_HAL_PARSE_LIMIT)
            return -ERANGE;
    }
    if (*s == '.') {
        s++;
        for (; *s >= '0' && *s <= '9'; s++) {
            any = true;
            if (frac < frac_digits) {
                if (v > PSC_HAL_PARSE_LIMIT / 10) /* checked before it could overflow */
                    return -ERANGE;
                v = v * 10 + (*s - '0');
                frac++;
            } else if (frac == frac_digits) {
                /* the first dropped digit decides the rounding */
                round_up = *s >= '5';
                frac++;
            }
        }
    }
    if (!any || *s != '\0')
        return -EINVAL;
    for (; frac < frac_digits; frac++) {
        if (v > PSC_HAL_PARSE_LIMIT / 10)
            return -ERANGE;
        v *= 10;
    }
    if (round_up)
        v++;
    if (v > PSC_HAL_PARSE_LIMIT)
        return -ERANGE;
    *out = neg ? -v : v;
    return 0;
}
