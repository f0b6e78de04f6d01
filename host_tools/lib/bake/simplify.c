/* SPDX-License-Identifier: MIT */
/* simplify.c - a mesh made coarser by libmeshoptimizer (simplify.h). */
#include "bake/simplify.h"

#include <meshoptimizer.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(sizeof(unsigned) == sizeof(uint32_t), "meshoptimizer's indices are unsigned int");

bool psc_bake_simplify_available(void)
{
    return true;
}

static const uint64_t *corner_key;

static int by_key(const void *a, const void *b)
{
    uint64_t x = corner_key[*(const uint32_t *)a], y = corner_key[*(const uint32_t *)b];
    return x < y ? -1 : x > y;
}

int psc_bake_simplify(const double (*pos)[3], uint32_t nv, const uint32_t *idx, uint32_t nt, const uint32_t *region,
                      uint32_t target, double max_error, uint32_t **out, uint32_t *out_nt, uint32_t **out_region,
                      double *error)
{
    size_t ni = 3u * (size_t)nt;
    float *p = malloc((nv ? nv : 1u) * 3u * sizeof *p), *q = malloc((ni ? ni : 1u) * 3u * sizeof *q);
    unsigned *remap = malloc((nv ? nv : 1u) * sizeof *remap), *first = malloc((nv ? nv : 1u) * sizeof *first);
    unsigned *welded = malloc((ni ? ni : 1u) * sizeof *welded), *res = malloc((ni ? ni : 1u) * sizeof *res);
    uint64_t *key = malloc((ni ? ni : 1u) * sizeof *key);
    uint32_t *order = malloc((ni ? ni : 1u) * sizeof *order), *vfirst = malloc((ni ? ni : 1u) * sizeof *vfirst);
    uint32_t *vregion = malloc((ni ? ni : 1u) * sizeof *vregion), *reg = NULL;
    int rc = -1;
    *out = NULL;
    *out_nt = 0;
    if (out_region)
        *out_region = NULL;
    *error = 0;
    if (!p || !q || !remap || !first || !welded || !res || !key || !order || !vfirst || !vregion)
        goto done;
    for (uint32_t i = 0; i < nv; i++)
        for (unsigned a = 0; a < 3; a++)
            p[3u * i + a] = (float)pos[i][a];
    /* one vertex per position and region: seams of normals or texture coordinates are not borders to keep, and
     * meshoptimizer takes the two vertices where regions meet for a seam, collapsed only along itself */
    meshopt_generateVertexRemap(remap, idx, ni, p, nv, 3u * sizeof *p);
    for (uint32_t i = nv; i-- > 0;)   /* the first of the model's vertices at each position */
        if (remap[i] != ~0u)
            first[remap[i]] = i;
    for (size_t c = 0; c < ni; c++) {
        key[c] = (uint64_t)remap[idx[c]] << 32 | (region ? region[c / 3u] : 0u);
        order[c] = (uint32_t)c;
    }
    corner_key = key;
    qsort(order, ni, sizeof *order, by_key);
    size_t nu = 0;
    for (size_t k = 0; k < ni; k++) {
        uint32_t c = order[k];
        if (k == 0 || key[c] != key[order[k - 1]]) {
            vfirst[nu] = first[remap[idx[c]]];
            vregion[nu] = (uint32_t)key[c];
            for (unsigned a = 0; a < 3; a++)
                q[3u * nu + a] = p[3u * vfirst[nu] + a];
            nu++;
        }
        welded[c] = (unsigned)(nu - 1u);
    }
    /* meshoptimizer's errors are relative to the mesh's extent */
    float scale = meshopt_simplifyScale(q, nu, 3u * sizeof *q), reached = 0;
    float rel = scale > 0 ? (float)(max_error / scale) : 0;
    size_t n = meshopt_simplify(res, welded, ni, q, nu, 3u * sizeof *q, 3u * (size_t)target, rel, 0, &reached);
    if (out_region && region && !(reg = malloc((n / 3u + 1u) * sizeof *reg)))
        goto done;
    for (size_t t = 0; reg && t < n / 3u; t++)
        reg[t] = vregion[res[3u * t]];
    for (size_t i = 0; i < n; i++)
        res[i] = vfirst[res[i]];
    *out = (uint32_t *)res;
    res = NULL;
    *out_nt = (uint32_t)(n / 3u);
    if (out_region)
        *out_region = reg;
    *error = (double)reached * scale;
    rc = 0;
done:
    free(p), free(q), free(remap), free(first), free(welded), free(res), free(key), free(order), free(vfirst),
        free(vregion);
    return rc;
}

int psc_bake_simplify_loose(const double (*pos)[3], uint32_t nv, const uint32_t *idx, uint32_t nt, uint32_t target,
                            double max_error, uint32_t **out, uint32_t *out_nt)
{
    float *p = malloc((nv ? nv : 1u) * 3u * sizeof *p);
    unsigned *res = malloc((3u * (size_t)nt + 1u) * sizeof *res);
    *out = NULL;
    *out_nt = 0;
    if (!p || !res) {
        free(p), free(res);
        return -1;
    }
    for (uint32_t i = 0; i < nv; i++)
        for (unsigned a = 0; a < 3; a++)
            p[3u * i + a] = (float)pos[i][a];
    float scale = meshopt_simplifyScale(p, nv, 3u * sizeof *p), reached = 0;
    float rel = scale > 0 ? (float)(max_error / scale) : 0;
    size_t n = meshopt_simplifySloppy(res, idx, 3u * (size_t)nt, p, nv, 3u * sizeof *p, 3u * (size_t)target, rel,
                                      &reached);
    free(p);
    *out = (uint32_t *)res;
    *out_nt = (uint32_t)(n / 3u);
    return 0;
}
