/* SPDX-License-Identifier: MIT */
/*
 * psc_viewer_simd_avx2.c - the vector scanline kernel with AVX2: eight lanes,
 * gathers in one instruction. The build compiles this file with -mavx2 on
 * x86-64 only; the kernel is offered when the CPU has AVX2.
 */
#include "viewer/psc_viewer_simd.h"

#ifdef __AVX2__
#include <immintrin.h>
#define KERNEL_LANES 8
#define KERNEL_AVX2
#define KERNEL_ROW row_avx2
#include "viewer/psc_viewer_simd_kernel.h"

psc_simd_row_fn psc_simd_row_avx2(void)
{
    return __builtin_cpu_supports("avx2") ? row_avx2 : 0;
}
#else
psc_simd_row_fn psc_simd_row_avx2(void)
{
    return 0;
}
#endif
