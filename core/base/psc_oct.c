/* SPDX-License-Identifier: MIT */
/* psc_oct.c - the octahedral map's encoder (psc_oct.h). */
#include "base/psc_oct.h"

/* a / l in Q2.14 rounded to nearest (|a| <= l, l > 0) */
static int32_t ratio_q14(int64_t a, int64_t l)
{
    int64_t q = (((a < 0 ? -a : a) << 15) / l + 1) >> 1;
    return (int32_t)(a < 0 ? -q : q);
}

/* x in [-16384, 16384] to 0..255: round((x + 16384) 255 / 32768) */
static uint32_t byte_of(int32_t x)
{
    return (uint32_t)(((int64_t)x + 16384) * 255 + 16384) >> 15;
}

uint16_t psc_oct16_encode(const int32_t n[3])
{
    int64_t ax = n[0] < 0 ? -(int64_t)n[0] : n[0], ay = n[1] < 0 ? -(int64_t)n[1] : n[1];
    int64_t az = n[2] < 0 ? -(int64_t)n[2] : n[2];
    int64_t l = ax + ay + az;
    if (l == 0)
        return (uint16_t)(byte_of(0) | byte_of(0) << 8);
    int32_t x = ratio_q14(n[0], l), y = ratio_q14(n[1], l);
    if (n[2] < 0) {   /* the lower half, folded over the diagonals */
        int32_t fx = 16384 - (y < 0 ? -y : y), fy = 16384 - (x < 0 ? -x : x);
        x = n[0] < 0 ? -fx : fx;
        y = n[1] < 0 ? -fy : fy;
    }
    return (uint16_t)(byte_of(x) | byte_of(y) << 8);
}
