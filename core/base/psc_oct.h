/* SPDX-License-Identifier: MIT */
/*
 * psc_oct.h - a direction in 16 bits: the octahedral map. A vector n is
 * scaled to |x| + |y| + |z| = 1 (onto the octahedron); the upper half
 * (z >= 0) keeps (x, y), the lower half is folded over the diagonals
 * ((1 - |y|) sign x, (1 - |x|) sign y), so the whole sphere fills the
 * square [-1, 1]^2 with no gap and no overlap. Each coordinate is stored in
 * 8 bits, u = round((x + 1) 255 / 2): the code is u | v << 8. Its error is
 * under 1 degree everywhere (tests/test_fixed.c), and the square's linear
 * layout makes the decode a few integer steps, what a view-textured pixel
 * can afford.
 *
 * The decode gives the point on the octahedron in Q2.14 (|x| + |y| + |z| =
 * 16384): the direction, not unit length; a weighted sum of such points
 * renormalised once is the blend of nearby normals.
 */
#ifndef PSC_OCT_H
#define PSC_OCT_H

#include "base/psc_types.h"

/** The 16-bit code of direction n (any length; the zero vector encodes as +z). */
uint16_t psc_oct16_encode(const int32_t n[3]);

/** Code c's point on the octahedron, Q2.14: |x| + |y| + |z| = 16384 (to rounding). */
static inline void psc_oct16_decode(uint16_t c, int32_t n_q14[3])
{
    /* (2u - 255) / 255 in Q2.14: times 16384 / 255 = 131586 / 2^11, rounded (ties up) */
    int32_t x = (((int32_t)(c & 255u) * 2 - 255) * 131586 + 1024) >> 11;
    int32_t y = (((int32_t)(c >> 8) * 2 - 255) * 131586 + 1024) >> 11;
    int32_t ax = x < 0 ? -x : x, ay = y < 0 ? -y : y;
    int32_t z = 16384 - ax - ay;
    if (z < 0) {   /* the lower half, unfolded */
        int32_t fx = 16384 - ay, fy = 16384 - ax;
        x = x < 0 ? -fx : fx;
        y = y < 0 ? -fy : fy;
    }
    n_q14[0] = x;
    n_q14[1] = y;
    n_q14[2] = z;
}

#endif
