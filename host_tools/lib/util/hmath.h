/* SPDX-License-Identifier: MIT */
/*
 * hmath.h - the small double-precision helpers the host library's bakers,
 * rigs and measures share (host only: double).
 */
#ifndef PSC_UTIL_HMATH_H
#define PSC_UTIL_HMATH_H

#include <math.h>
#include <stdint.h>

/** v in Q16.16, rounded to nearest, saturated to the int32 range (an out-of-range value never wraps). */
static inline int32_t psc_hmath_q16(double v)
{
    double s = v * 65536.0;
    return s >= 2147483647.0 ? INT32_MAX : s <= -2147483648.0 ? INT32_MIN : (int32_t)lround(s);
}

static inline double psc_hmath_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

#endif
