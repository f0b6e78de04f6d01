/* SPDX-License-Identifier: MIT */
/* simplify_none.c - a build without libmeshoptimizer: meshes stay as they are (simplify.h). */
#include "bake/simplify.h"

#include <stdlib.h>
#include <string.h>

bool psc_bake_simplify_available(void)
{
    return false;
}

int psc_bake_simplify(const double (*pos)[3], uint32_t nv, const uint32_t *idx, uint32_t nt, const uint32_t *region,
                      uint32_t target, double max_error, uint32_t **out, uint32_t *out_nt, uint32_t **out_region,
                      double *error)
{
    (void)pos, (void)nv, (void)target, (void)max_error;
    *out = malloc((nt ? nt : 1u) * 3u * sizeof **out);
    *out_nt = 0;
    *error = 0;
    if (out_region)
        *out_region = region ? malloc((nt ? nt : 1u) * sizeof **out_region) : NULL;
    if (!*out || (out_region && region && !*out_region)) {
        free(*out);
        if (out_region)
            free(*out_region);
        return -1;
    }
    memcpy(*out, idx, 3u * (size_t)nt * sizeof *idx);
    if (out_region && region)
        memcpy(*out_region, region, (size_t)nt * sizeof *region);
    *out_nt = nt;
    return 0;
}

int psc_bake_simplify_loose(const double (*pos)[3], uint32_t nv, const uint32_t *idx, uint32_t nt, uint32_t target,
                            double max_error, uint32_t **out, uint32_t *out_nt)
{
    return psc_bake_simplify(pos, nv, idx, nt, NULL, target, max_error, out, out_nt, NULL, &(double){0});
}
