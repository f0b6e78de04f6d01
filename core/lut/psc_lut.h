/* SPDX-License-Identifier: MIT */
/*
 * psc_lut.h - the scanline-coherent cylindrical look-up table (seed US 5,748,194).
 *
 * A cylinder of radius 1 has its axis along the view's X axis (parallel to the
 * viewing plane's scanlines). A point on it is (u, sin a, cos a): a is the
 * angle about the axis (the scanline's pitch), u the distance along the axis.
 * The direction through that point has
 *     lon = atan2(u, cos a)                      (the seed's phi)
 *     lat = atan2(sin a, sqrt(u^2 + cos^2 a))    (the seed's theta)
 * Only one octant is stored: a in [0, 90] degrees (rows), u in [0, u_max]
 * (columns). The seven others come from sign reflections:
 *     u < 0          -> lon = -lon
 *     a < 0          -> lat = -lat
 *     |a| > 90 deg   -> use 180 - |a|, lon = 180 - lon  (the view passed over a pole)
 * Row i is a = i * 90deg / (rows-1); column j is u = j * u_max / (cols-1).
 *
 * Entries store the angles themselves, not map indices, so one table serves
 * every projection, map size and map level: the map geometry turns angles
 * into (row, column) once per LUT sample (every N-th pixel).
 * Entry format (uint32_t): bits 0..15 lon, bits 16..31 lat, each an unsigned
 * Q0.16 fraction of 90 degrees, rounded to nearest and saturated at 0xFFFF
 * (so 90 degrees exactly reads 0xFFFF: 0.0014 degrees short; the viewer
 * computes the polar cap exactly and never relies on that entry there).
 */
#ifndef PSC_LUT_H
#define PSC_LUT_H

#include "base/psc_types.h"

typedef struct {
    uint16_t rows;            /* >= 2, rows over a in [0, 90] degrees */
    uint16_t cols;            /* >= 2, columns over u in [0, u_max] */
    uint32_t u_max_q24;       /* u_max = tan(hfov_max / 2), unsigned Q8.24 */
    psc_bam_t hfov_max;       /* widest horizontal field of view the table serves */
    const uint32_t *entries;  /* rows * cols entries, row-major */
} psc_lut_t;

#define PSC_LUT_LON(e) ((uint32_t)(e) & 0xFFFFu)
#define PSC_LUT_LAT(e) ((uint32_t)(e) >> 16)
#define PSC_LUT_ENTRY(lon16, lat16) (((uint32_t)(lat16) << 16) | ((uint32_t)(lon16) & 0xFFFFu))

/** Bytes needed for a table's entries. */
static inline size_t psc_lut_bytes(uint16_t rows, uint16_t cols)
{
    return (size_t)rows * cols * sizeof(uint32_t);
}

/** Check dimensions and u_max of a table (not its contents). */
psc_status_t psc_lut_check(const psc_lut_t *lut);

#endif
