/* SPDX-License-Identifier: MIT */
/* tsup_teapot.c - the teapot as .bpt text (tsup_teapot.h). */
#include "tsup_teapot.h"
#include "import/teapot_patches.h"

#include <stdio.h>
#include <stdlib.h>

char *tsup_teapot_bpt(size_t *len)
{
    char *text = malloc(200000);
    if (text == NULL)
        return NULL;
    size_t n = (size_t)sprintf(text, "%d\n", PSC_TEAPOT_PATCHES);
    for (unsigned p = 0; p < PSC_TEAPOT_PATCHES; p++) {
        n += (size_t)sprintf(text + n, "3 3\n");
        for (unsigned i = 0; i < 16; i++) {
            const double *c = psc_teapot_points[psc_teapot_patches[p][i]];
            n += (size_t)sprintf(text + n, "%g %g %g\n", c[0], c[1], c[2]);
        }
    }
    *len = n;
    return text;
}
