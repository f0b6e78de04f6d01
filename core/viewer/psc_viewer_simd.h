/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_simd.h - the viewer's vector scanlines (internal).
 *
 * A scanline whose spans are all N pixels long and none touches a polar cap
 * (the common case) can be drawn several pixels at a time: pixel x lies in
 * span k = x >> log2 N at i = x & (N - 1), at sample k plus step / 2 plus
 * i * step, exactly the positions the scalar spans reach by adding the step.
 * A kernel draws pixels [0, n) of the row for the combinations it serves and
 * returns n (a multiple of its lane count, 0 if it serves none); the scalar
 * spans draw the rest. Every kernel gives the scalar path's bytes
 * (tests/test_simd.c).
 *
 * The kernels are one source (psc_viewer_simd_kernel.h) built with GCC/clang
 * vector extensions: four lanes with the CPU's baseline vectors (SSE2 on
 * x86-64, NEON on arm64 and armhf), eight with AVX2 gathers where the CPU has
 * them (chosen at run time). Other targets (Cortex-M) have the scalar path only.
 */
#ifndef PSC_VIEWER_SIMD_H
#define PSC_VIEWER_SIMD_H

#include "base/psc_types.h"

typedef struct {
    const uint8_t *base;      /* map pixels */
    const uint32_t *rowoff;   /* byte offset of map row r at [r + 1], r = -1 .. H (edge rows repeated) */
    const uint32_t *pal;      /* PAL8 maps: the palette */
    const int32_t *row;       /* the scanline's boundary samples: map row, Q16.16 */
    const uint32_t *t;        /* and longitude from the map's left edge, binary angle */
    void *dst;                /* output row */
    uint32_t width;           /* output pixels, a multiple of the span */
    uint32_t span_log2;
    uint32_t col_shift;       /* 32 - log2(map width): power-of-two maps only */
    uint32_t half_col;        /* half a map column, binary angle */
    uint32_t map_height;      /* rows */
    uint32_t stride;          /* bytes from one map row to the next */
    uint8_t bilinear;         /* else nearest */
    uint8_t in;               /* psc_pixfmt_t of the map */
    uint8_t out_565;          /* RGB565 output, else XRGB8888 */
} psc_simd_row_t;

typedef unsigned (*psc_simd_row_fn)(const psc_simd_row_t *r);

/* The kernels this build has (NULL where the target has none). */
psc_simd_row_fn psc_simd_row_vector(void);
psc_simd_row_fn psc_simd_row_avx2(void); /* NULL also when the CPU lacks AVX2 */

#endif
