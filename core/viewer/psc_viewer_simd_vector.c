/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_simd_vector.c - the vector scanline kernel with the CPU's
 * baseline vectors: SSE2 on x86-64, NEON on arm64 (and armhf built with
 * -mfpu=neon). Four lanes; gathers lane by lane. Not built elsewhere.
 */
#include "viewer/psc_viewer_simd.h"

#if defined(__SSE2__) || defined(__ARM_NEON)
#define KERNEL_LANES 4
#define KERNEL_ROW row_vector
#include "viewer/psc_viewer_simd_kernel.h"

psc_simd_row_fn psc_simd_row_vector(void)
{
    return row_vector;
}
#else
psc_simd_row_fn psc_simd_row_vector(void)
{
    return 0;
}
#endif
