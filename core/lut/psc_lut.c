/* SPDX-License-Identifier: MIT */
/* psc_lut.c - checks on look-up table descriptions. */
#include "lut/psc_lut.h"
#include "base/psc_fixed.h"

/* u_max above tan(85 deg) (Q8.24) would make the table too coarse to be useful. */
#define LUT_U_MAX_LIMIT_Q24 191764456u

psc_status_t psc_lut_check(const psc_lut_t *lut)
{
    if (!lut || !lut->entries)
        return PSC_ERR_ARG;
    if (lut->rows < 2 || lut->cols < 2)
        return PSC_ERR_CORRUPT;
    if (lut->rows > PSC_MAX_LUT_DIM || lut->cols > PSC_MAX_LUT_DIM)
        return PSC_ERR_TOO_LARGE;
    if (lut->u_max_q24 == 0 || lut->u_max_q24 > LUT_U_MAX_LIMIT_Q24)
        return PSC_ERR_CORRUPT;
    if (lut->hfov_max < PSC_BAM_FROM_MDEG(1000) || lut->hfov_max >= PSC_BAM_180)
        return PSC_ERR_CORRUPT;
    /* The table must reach exactly as far as it claims: u_max = tan(hfov_max / 2)
     * within 1/4096 (else views near hfov_max would read past its last column). */
    int32_t s, c;
    psc_sincos(lut->hfov_max / 2u, &s, &c);
    int64_t want = psc_div_round64((int64_t)s * (1 << 24), c);
    int64_t diff = want - (int64_t)lut->u_max_q24;
    if (diff < 0)
        diff = -diff;
    if (diff > want / 4096) /* diff * 4096 > want, without the product: want reaches 2^54 near 180 degrees */
        return PSC_ERR_CORRUPT;
    return PSC_OK;
}
