/* SPDX-License-Identifier: MIT */
/*
 * psc_fixed.h - fixed-point arithmetic: rounding shifts, square roots and
 * CORDIC trigonometry on binary angles.
 *
 * Formats used here:
 *  - Q2.30 (int32_t, "_q30"): sines and cosines, 1.0 = 2^30.
 *  - Q16.16 (int32_t, "_q16").
 *  - psc_bam_t angles (2^32 per turn, see psc_types.h).
 * All functions are exact-integer and give identical results on every target.
 */
#ifndef PSC_FIXED_H
#define PSC_FIXED_H

#include "base/psc_types.h"

#define PSC_Q30_ONE ((int32_t)0x40000000)
#define PSC_Q16_ONE ((int32_t)0x10000)

/** Arithmetic shift right by s (1..62) rounding to nearest, ties toward +inf. */
static inline int64_t psc_shr_round64(int64_t v, unsigned s)
{
    return (v + ((int64_t)1 << (s - 1))) >> s;
}

/** 32-bit variant of psc_shr_round64 (s 1..30); v + 2^(s-1) must not overflow. */
static inline int32_t psc_shr_round32(int32_t v, unsigned s)
{
    return (int32_t)(((int64_t)v + ((int64_t)1 << (s - 1))) >> s);
}

/** Q16.16 product, rounded to nearest. Overflow-free for |a*b| < 2^47. */
static inline int32_t psc_mul_q16(int32_t a, int32_t b)
{
    return (int32_t)psc_shr_round64((int64_t)a * b, 16);
}

/**
 * n r / 2^62 rounded to nearest (ties away from zero), for |n| < 2^63 and the
 * quotient within int64: the magnitudes' product through 128 bits, the same
 * on every target (a division by d as a product by r = 2^62 / d). Where the
 * compiler has 128-bit integers (64-bit targets) one multiply; elsewhere four
 * 32 x 32-bit products: the same exact product, the same bits.
 */
static inline int64_t psc_mul_rcp62(int64_t n, uint64_t r)
{
    uint64_t a = n < 0 ? 0u - (uint64_t)n : (uint64_t)n;
#ifdef __SIZEOF_INT128__
    unsigned __int128 p = (unsigned __int128)a * r + ((unsigned __int128)1 << 61);
    uint64_t q = (uint64_t)(p >> 62);
#else
    uint64_t al = a & 0xFFFFFFFFu, ah = a >> 32, bl = r & 0xFFFFFFFFu, bh = r >> 32;
    uint64_t ll = al * bl, lh = al * bh, hl = ah * bl, hh = ah * bh;
    uint64_t mid = (ll >> 32) + (lh & 0xFFFFFFFFu) + (hl & 0xFFFFFFFFu);
    uint64_t lo = (mid << 32) | (ll & 0xFFFFFFFFu), hi = hh + (lh >> 32) + (hl >> 32) + (mid >> 32);
    uint64_t lo_r = lo + ((uint64_t)1 << 61);
    hi += lo_r < lo;
    uint64_t q = (hi << 2) | (lo_r >> 62);
#endif
    return n < 0 ? -(int64_t)q : (int64_t)q;
}

/** Floor of the square root of a 64-bit value (exact for every input). */
uint32_t psc_isqrt64(uint64_t v);

/**
 * 2^46 / sqrt(v) (relative error below 2^-16; UINT64_MAX for 0): a table of
 * 384 mantissas and one Newton step, multiplications only. For normalising
 * vectors: v a squared length in Q32 gives 2^30 / the length in Q16.
 */
uint64_t psc_rsqrt46(uint64_t v);

/** 2^30 / sqrt(x), rounded (relative error below 2^-16; UINT32_MAX for 0): renormalising a normal a pixel. */
uint32_t psc_rsqrt_q30(uint32_t x);

/**
 * v / |v| in Q16.16 for any 64-bit components (zero stays zero), within 2^-16 of it: v scaled below 2^30, then
 * times psc_rsqrt46 of its squared length (no division; a direction found every frame).
 */
void psc_unit3_q16(const int64_t v[3], int32_t out[3]);

/** Signed division of 64-bit values rounded to nearest (ties away from zero); d != 0
 * and the quotient must fit (not INT64_MIN / -1). */
int64_t psc_div_round64(int64_t n, int64_t d);

/**
 * sin and cos of a binary angle in Q2.30, |error| <= 1 unit (2^-30).
 * Either output pointer may be NULL.
 */
void psc_sincos(psc_bam_t a, int32_t *sin_q30, int32_t *cos_q30);

/**
 * Angle of the vector (x, y) measured from +x toward +y, as a binary angle;
 * atan2 semantics (the full circle). (0,0) gives 0. Inputs may use the
 * whole int32 range. |error| <= 1 binary-angle unit
 * when max(|x|,|y|) >= 2^16; smaller vectors lose accuracy with their precision.
 * If mag is not NULL it receives sqrt(x^2 + y^2), rounded, saturated to UINT32_MAX.
 */
psc_bam_t psc_atan2(int32_t y, int32_t x, uint32_t *mag);

/**
 * Base-2 logarithm in Q24.8 (the mantissa's top 8 bits through a table;
 * |error| < 0.01), INT32_MIN for 0. Used for the map level of detail.
 */
int32_t psc_log2_q8(uint64_t v);

#endif
