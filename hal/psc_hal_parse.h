/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_parse.h - integer-only parsing of the decimal numbers people write
 * in board files and tour scripts ("0.5", "-90", "1.25s").
 *
 * Format: optional sign, digits, optional '.' and digits; nothing else, no
 * exponent, no spaces. The value is returned as an integer scaled by
 * 10^frac_digits ("-12.5" with 3 -> -12500). Digits past frac_digits are
 * rounded to nearest, ties away from zero, so "0.0005" with 3 gives 1.
 * |scaled value| is limited to 10^15, far beyond any setting, so callers can
 * multiply it by 10^3 without overflowing int64_t.
 */
#ifndef PSC_HAL_PARSE_H
#define PSC_HAL_PARSE_H

#include <stdint.h>

#define PSC_HAL_PARSE_LIMIT 1000000000000000LL

/**
 * Parse s as a decimal scaled by 10^frac_digits (0..9) into *out. Returns 0,
 * -EINVAL when s is not a decimal number of the format above (an empty
 * string, "1e3", "12abc", "." are not), or -ERANGE beyond PSC_HAL_PARSE_LIMIT.
 * *out is written only on success.
 */
int psc_hal_parse_decimal(const char *s, unsigned frac_digits, int64_t *out);

#endif
