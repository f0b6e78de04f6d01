/* SPDX-License-Identifier: MIT */
/* gltf_morph.c - a glTF model's blend shapes through core (gltf_morph.h). */
#include "anim/gltf_morph.h"
#include "util/hmath.h"
#include "psc_io_error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int16_t q14(double v)
{
    long q = lround(v * 16384.0);
    return (int16_t)(q > 16384 ? 16384 : q < -16384 ? -16384 : q);
}

static int32_t q14_delta(double v)
{
    long q = lround(v * 16384.0);
    return (int32_t)(q > 65536 ? 65536 : q < -65536 ? -65536 : q);
}

int psc_gltf_morpher_new(psc_gltf_morpher_t *mm, const psc_gltf_t *g, const double c[3], double r, const char *name,
                         char *err, size_t errlen)
{
    memset(mm, 0, sizeof *mm);
    uint32_t nv = g->mesh.vertex_count, nt = g->target_count;
    size_t moved = 0;
    for (uint32_t k = 0; k < g->morph_count; k++)
        moved += (size_t)g->morphs[k].target_count * g->morphs[k].nv;
    mm->targets = calloc(nt ? nt : 1u, sizeof *mm->targets);
    mm->base_q16 = malloc(3u * nv * sizeof *mm->base_q16);
    mm->base_n14 = malloc(3u * nv * sizeof *mm->base_n14);
    mm->pos_q16 = malloc(3u * nv * sizeof *mm->pos_q16);
    mm->sum_q14 = malloc(3u * nv * sizeof *mm->sum_q14);
    mm->nrm_q14 = malloc(3u * nv * sizeof *mm->nrm_q14);
    mm->w_q16 = calloc(nt ? nt : 1u, sizeof *mm->w_q16);
    mm->vertex = malloc((moved ? moved : 1u) * sizeof *mm->vertex);
    mm->dpos_q16 = malloc((moved ? moved : 1u) * 3u * sizeof *mm->dpos_q16);
    mm->dnrm_q14 = malloc((moved ? moved : 1u) * 3u * sizeof *mm->dnrm_q14);
    if (!mm->targets || !mm->base_q16 || !mm->base_n14 || !mm->pos_q16 || !mm->sum_q14 || !mm->nrm_q14 ||
        !mm->w_q16 || !mm->vertex || !mm->dpos_q16 || !mm->dnrm_q14) {
        psc_gltf_morpher_free(mm);
        return psc_io_errorf(err, errlen, name, "out of memory");
    }
    memcpy(mm->c, c, sizeof mm->c);
    mm->r = r;
    for (uint32_t i = 0; i < nv; i++)
        for (unsigned a = 0; a < 3; a++) {
            mm->base_q16[3 * i + a] = psc_hmath_q16((g->mesh.pos[3 * i + a] - c[a]) / r);
            mm->base_n14[3 * i + a] = q14(g->mesh.normal[3 * i + a]);
        }
    /* each target: the vertices its quantised delta moves, ascending */
    size_t at = 0;
    uint32_t t = 0;
    for (uint32_t k = 0; k < g->morph_count; k++) {
        const psc_gltf_morph_t *mo = &g->morphs[k];
        for (uint32_t j = 0; j < mo->target_count; j++, t++) {
            psc_morph_target_t *tg = &mm->targets[t];
            tg->vertex = &mm->vertex[at];
            tg->dpos_q16 = &mm->dpos_q16[3u * at];
            tg->dnormal_q14 = mo->dnrm ? &mm->dnrm_q14[3u * at] : NULL;
            for (uint32_t i = 0; i < mo->nv; i++) {
                const double *d = &mo->dpos[((size_t)j * mo->nv + i) * 3u];
                const double *dn = mo->dnrm ? &mo->dnrm[((size_t)j * mo->nv + i) * 3u] : NULL;
                int32_t dq[3], nq[3] = {0, 0, 0};
                bool any = false;
                for (unsigned a = 0; a < 3; a++) {
                    dq[a] = psc_hmath_q16(d[a] / r);
                    if (dn)
                        nq[a] = q14_delta(dn[a]);
                    any = any || dq[a] != 0 || nq[a] != 0;
                }
                if (!any)
                    continue;
                mm->vertex[at] = mo->v0 + i;
                memcpy(&mm->dpos_q16[3u * at], dq, sizeof dq);
                memcpy(&mm->dnrm_q14[3u * at], nq, sizeof nq);
                at++;
                tg->count++;
            }
        }
    }
    mm->m = (psc_morph_t){nv, mm->base_q16, mm->base_n14, nt, mm->targets};
    if (psc_morph_check(&mm->m) != PSC_OK) {
        psc_gltf_morpher_free(mm);
        return psc_io_errorf(err, errlen, name, "its morph targets do not fit the device's limits");
    }
    return 0;
}

void psc_gltf_morph_rest(psc_gltf_morpher_t *mm, const psc_gltf_t *g, const double *w, double *pos, double *nrm)
{
    for (uint32_t k = 0; k < g->target_count; k++) {
        double x = w[k];
        if (x > 16.0 || x < -16.0) {
            x = x > 0 ? 16.0 : -16.0;
            mm->clamped++;
        }
        mm->w_q16[k] = (int32_t)lround(x * 65536.0);
    }
    (void)psc_morph_apply(&mm->m, mm->w_q16, mm->pos_q16, mm->nrm_q14, mm->sum_q14);
    for (uint32_t i = 0; i < g->mesh.vertex_count; i++) {
        double n[3], l = 0;
        for (unsigned a = 0; a < 3; a++) {
            pos[3 * i + a] = mm->c[a] + mm->pos_q16[3 * i + a] / 65536.0 * mm->r;
            n[a] = mm->nrm_q14[3 * i + a] / 16384.0;
            l += n[a] * n[a];
        }
        l = sqrt(l);
        for (unsigned a = 0; a < 3; a++)
            nrm[3 * i + a] = l > 0 ? n[a] / l : g->mesh.normal[3 * i + a];
    }
}

void psc_gltf_morpher_free(psc_gltf_morpher_t *mm)
{
    free(mm->targets);
    free(mm->base_q16);
    free(mm->base_n14);
    free(mm->pos_q16);
    free(mm->sum_q14);
    free(mm->nrm_q14);
    free(mm->w_q16);
    free(mm->vertex);
    free(mm->dpos_q16);
    free(mm->dnrm_q14);
    memset(mm, 0, sizeof *mm);
}
