/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_simd_avx2.c - the vector scanline kernel with AVX2: eight lanes,
 * gathers in one instruction. The build compiles this file with -mavx2 on
 * x86-64 only; the kernel is offered when the CPU has AVX2.
 */
#include "viewer/psc_viewer_simd.h"

#ifdef __AVX2__
#define KERNEL_LANES 8
#define KERNEL_AVX2
#define KERNEL_ROW row_avx2
#define KERNEL_SAMPLES samples_avx2
#define KERNEL_COMPOSITE composite_avx2
#define KERNEL_ROW_TILED row_tiled_avx2
#define KERNEL_MIP_TILED mip_tiled_avx2
#define KERNEL_MIP mip_avx2
#define KERNEL kernel_avx2
#include "viewer/psc_viewer_simd_kernel.h"

const psc_simd_kernel_t *psc_simd_kernel_avx2(void)
{
    return __builtin_cpu_supports("avx2") ? &kernel_avx2 : 0;
}
#else
const psc_simd_kernel_t *psc_simd_kernel_avx2(void)
{
    return 0;
}
#endif
