/* SPDX-License-Identifier: MIT */
/*
 * test_morph.c - blend shapes in fixed point (core/morph/psc_morph.h) against glTF's definition in double.
 *
 *  - 300 random meshes of sparse targets, random signed weights within the
 *    limit: every position within half a unit (Q16.16) a target that moves
 *    it of base + sum w delta computed in double; every moved normal within
 *    1.5 units (Q2.14) of the normalised double sum, plus the sum's rounding
 *    (half a unit a term) over its length; unit length within 2 units;
 *    vertices no target moves keep their base bytes.
 *  - The range limits: weights of +-16.0 on deltas near +-2^31 saturate,
 *    never wrap; a normal sum cancelling to zero keeps the base normal;
 *    weights beyond the limit and malformed targets are refused.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "morph/psc_morph.h"
#include "psc_testsupport.h"

#define MAX_V 300
#define MAX_T 12

typedef struct {
    int32_t base[3 * MAX_V];
    int16_t nbase[3 * MAX_V];
    uint32_t vert[MAX_T][MAX_V];
    int32_t dpos[MAX_T][3 * MAX_V], dnrm[MAX_T][3 * MAX_V];
    psc_morph_target_t t[MAX_T];
    psc_morph_t m;
    int32_t w[MAX_T];
} fixture_t;

static void random_unit(tsup_rng_t *rng, double n[3])
{
    double l;
    do {
        for (int a = 0; a < 3; a++)
            n[a] = tsup_rng_range(rng, -1, 1);
        l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    } while (l < 0.1 || l > 1);
    for (int a = 0; a < 3; a++)
        n[a] /= l;
}

static void fixture_random(fixture_t *f, tsup_rng_t *rng)
{
    memset(f, 0, sizeof *f);
    uint32_t nv = 1 + tsup_rng_below(rng, MAX_V), nt = tsup_rng_below(rng, MAX_T + 1);
    for (uint32_t v = 0; v < nv; v++) {
        double n[3];
        random_unit(rng, n);
        for (int a = 0; a < 3; a++) {
            f->base[3 * v + a] = (int32_t)tsup_rng_range(rng, -4 * 65536, 4 * 65536);
            f->nbase[3 * v + a] = (int16_t)lround(n[a] * 16384);
        }
    }
    for (uint32_t k = 0; k < nt; k++) {
        uint32_t c = 0;
        double share = tsup_rng_unit(rng);
        for (uint32_t v = 0; v < nv; v++)
            if (tsup_rng_unit(rng) < share) {
                f->vert[k][c] = v;
                double n[3];
                random_unit(rng, n);
                for (int a = 0; a < 3; a++) {
                    f->dpos[k][3 * c + a] = (int32_t)tsup_rng_range(rng, -65536, 65536);
                    f->dnrm[k][3 * c + a] = (int32_t)lround(n[a] * 16384) - f->nbase[3 * v + a]; /* toward n */
                }
                c++;
            }
        f->t[k] = (psc_morph_target_t){c, f->vert[k], f->dpos[k], tsup_rng_below(rng, 4) ? f->dnrm[k] : NULL};
        f->w[k] = (int32_t)tsup_rng_range(rng, -1.5 * 65536, 1.5 * 65536);
        if (tsup_rng_below(rng, 6) == 0)
            f->w[k] = 0;
    }
    f->m = (psc_morph_t){nv, f->base, f->nbase, nt, f->t};
}

static void test_against_double(void **state)
{
    (void)state;
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 505);
    static fixture_t f;
    static int32_t pos[3 * MAX_V], sum[3 * MAX_V];
    static int16_t nrm[3 * MAX_V];
    double worst_pos = 0, worst_nrm = 0, worst_len = 0;
    unsigned moved = 0;
    for (unsigned c = 0; c < 300; c++) {
        fixture_random(&f, &rng);
        assert_int_equal(psc_morph_check(&f.m), PSC_OK);
        assert_int_equal(psc_morph_apply(&f.m, f.w, pos, nrm, sum), PSC_OK);
        for (uint32_t v = 0; v < f.m.vertex_count; v++) {
            double p[3], n[3];
            unsigned terms = 0;
            bool nmoved = false;
            for (int a = 0; a < 3; a++) {
                p[a] = f.base[3 * v + a];
                n[a] = f.nbase[3 * v + a];
            }
            for (uint32_t k = 0; k < f.m.target_count; k++)
                for (uint32_t j = 0; j < f.t[k].count; j++)
                    if (f.t[k].vertex[j] == v && f.w[k] != 0) {
                        terms++;
                        for (int a = 0; a < 3; a++) {
                            p[a] += f.w[k] / 65536.0 * f.dpos[k][3 * j + a];
                            if (f.t[k].dnormal_q14) {
                                n[a] += f.w[k] / 65536.0 * f.dnrm[k][3 * j + a];
                                nmoved = true;
                            }
                        }
                    }
            for (int a = 0; a < 3; a++) {
                double e = fabs(pos[3 * v + a] - p[a]);
                worst_pos = e > worst_pos ? e : worst_pos;
                if (e > 0.5 * terms + 1e-9)
                    fail_msg("case %u vertex %u: position %d against %.3f (%u terms)", c, v, pos[3 * v + a], p[a],
                             terms);
            }
            if (!nmoved) {
                assert_memory_equal(&nrm[3 * v], &f.nbase[3 * v], 6);
                continue;
            }
            double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (l < 1e-3 * 16384) /* nearly cancelled: direction ill-defined */
                continue;
            moved++;
            double got = 0;
            /* the sum is off by half a unit a term a component; over its length that turns the direction */
            double bound = 1.5 + 16384.0 * 0.5 * terms * sqrt(3.0) / l;
            for (int a = 0; a < 3; a++) {
                double e = fabs(nrm[3 * v + a] - n[a] / l * 16384);
                worst_nrm = e / bound > worst_nrm ? e / bound : worst_nrm;
                got += (double)nrm[3 * v + a] * nrm[3 * v + a];
            }
            double le = fabs(sqrt(got) - 16384);
            worst_len = le > worst_len ? le : worst_len;
        }
    }
    print_message("  300 random meshes: position error at most %.3f units (Q16.16, bound half a unit a term), moved "
                  "normals (%u) at most %.2f of their bound (1.5 units of Q2.14 and the sum's rounding over its "
                  "length), lengths within %.2f\n", worst_pos, moved, worst_nrm, worst_len);
    assert_true(worst_nrm <= 1.0);
    assert_true(worst_len <= 2.0);
    assert_true(moved > 1000);
}

static void test_range_limits(void **state)
{
    (void)state;
    int32_t base[6] = {INT32_MAX - 5, INT32_MIN + 5, 0, 100, -100, 7};
    int16_t nb[6] = {16384, 0, 0, 0, 16384, 0};
    uint32_t vert[2] = {0, 1};
    int32_t dpos[6] = {INT32_MAX, INT32_MIN, INT32_MAX, INT32_MAX, INT32_MIN, 1};
    int32_t dn[6] = {-16384, 0, 0, 0, -16384, 0}; /* cancels each normal at weight 1 */
    psc_morph_target_t t = {2, vert, dpos, dn};
    psc_morph_t m = {2, base, nb, 1, &t};
    int32_t pos[6], sum[6];
    int16_t nrm[6];
    int32_t w = PSC_MORPH_WEIGHT_MAX;
    assert_int_equal(psc_morph_check(&m), PSC_OK);
    assert_int_equal(psc_morph_apply(&m, &w, pos, nrm, sum), PSC_OK);
    assert_int_equal(pos[0], INT32_MAX);   /* saturated, not wrapped */
    assert_int_equal(pos[1], INT32_MIN);
    assert_int_equal(pos[2], INT32_MAX);
    assert_int_equal(pos[3], INT32_MAX);
    assert_int_equal(pos[4], INT32_MIN);
    w = -PSC_MORPH_WEIGHT_MAX;
    assert_int_equal(psc_morph_apply(&m, &w, pos, nrm, sum), PSC_OK);
    assert_int_equal(pos[0], INT32_MIN);
    assert_int_equal(pos[1], INT32_MAX);
    w = 65536; /* the normals' sums cancel: the base normals stay */
    assert_int_equal(psc_morph_apply(&m, &w, pos, nrm, sum), PSC_OK);
    assert_memory_equal(nrm, nb, sizeof nb);
    w = PSC_MORPH_WEIGHT_MAX + 1;
    assert_int_equal(psc_morph_apply(&m, &w, pos, nrm, sum), PSC_ERR_ARG);
    w = 65536;
    assert_int_equal(psc_morph_apply(&m, &w, pos, nrm, NULL), PSC_ERR_ARG);   /* normals need the scratch */
    assert_int_equal(psc_morph_apply(&m, &w, pos, NULL, NULL), PSC_OK);       /* not asked for: none */
    vert[1] = 0;                                                              /* not ascending */
    assert_int_equal(psc_morph_check(&m), PSC_ERR_ARG);
    vert[0] = 0, vert[1] = 2;                                                 /* out of range */
    assert_int_equal(psc_morph_check(&m), PSC_ERR_ARG);
    m.target_count = PSC_MORPH_MAX_TARGETS + 1;
    assert_int_equal(psc_morph_check(&m), PSC_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_against_double),
        cmocka_unit_test(test_range_limits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
