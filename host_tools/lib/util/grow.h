/* SPDX-License-Identifier: MIT */
/*
 * grow.h - room for one more element in a heap array the host readers fill
 * (doubling from 64), so a file of any size is read in one pass.
 */
#ifndef PSC_UTIL_GROW_H
#define PSC_UTIL_GROW_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

/** Make *v (n elements of elem bytes, *cap allocated) hold n + 1: 0, or -1 when out of memory (*v kept). */
static inline int psc_grow(void **v, size_t n, size_t *cap, size_t elem)
{
    if (n < *cap)
        return 0;
    size_t c = *cap ? *cap * 2u : 64u;
    if (c > SIZE_MAX / elem)
        return -1;
    void *p = realloc(*v, c * elem);
    if (p == NULL)
        return -1;
    *v = p;
    *cap = c;
    return 0;
}

#endif
