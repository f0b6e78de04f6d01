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
#define KERNEL_SAMPLES samples_vector
#define KERNEL_COMPOSITE composite_vector
#define KERNEL_ROW_TILED row_tiled_vector
#define KERNEL_MIP_TILED mip_tiled_vector
#define KERNEL_MIP mip_vector
#define KERNEL kernel_vector
#include "viewer/psc_viewer_simd_kernel.h"

const psc_simd_kernel_t *psc_simd_kernel_vector(void)
{
    return &kernel_vector;
}
#else
const psc_simd_kernel_t *psc_simd_kernel_vector(void)
{
    return 0;
}
#endif
