/* SPDX-License-Identifier: MIT */
/*
 * test_proxy.c - the proxy animator's view directions (core/proxy/psc_proxy_view.h):
 *  - the octahedral fold against a double-precision reference over 100 000
 *    random directions, and view k's direction picking view k alone;
 *  - the views and weights of random directions against the same choice in
 *    double: the same three views (but at cell edges, where two choices are
 *    equal), weights within 2/65536, non-negative, summing to exactly 1, and
 *    reproducing the direction's place on the grid;
 *  - the seed's Dr = Ds M1^-1 M2^-1: a part turned by M2 and the object
 *    turned by M1 pick exactly the views the camera turned by the inverse
 *    does (quarter turns, exact in fixed point; random rigid turns within a
 *    unit of rounding).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "proxy/psc_proxy_view.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint32_t rng = 12345u;

static double frand(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (rng >> 8) / 16777216.0;
}

static void random_dir(double d[3])
{
    double l;
    do {
        for (unsigned k = 0; k < 3; k++)
            d[k] = frand() * 2 - 1;
        l = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    } while (l > 1 || l < 1e-4);
    for (unsigned k = 0; k < 3; k++)
        d[k] /= sqrt(l);
}

static void ref_fold(const double d[3], double uv[2])
{
    double l1 = fabs(d[0]) + fabs(d[1]) + fabs(d[2]), u = d[0] / l1, v = d[2] / l1;
    if (d[1] < 0) {
        double fu = 1 - fabs(v), fv = 1 - fabs(u);
        u = d[0] < 0 ? -fu : fu;
        v = d[2] < 0 ? -fv : fv;
    }
    uv[0] = u;
    uv[1] = v;
}

static void test_fold(void **state)
{
    (void)state;
    double worst = 0;
    for (unsigned n = 0; n < 100000; n++) {
        double d[3], uv[2];
        random_dir(d);
        ref_fold(d, uv);
        int32_t q[3] = {(int32_t)lround(d[0] * 65536), (int32_t)lround(d[1] * 65536), (int32_t)lround(d[2] * 65536)};
        int32_t got[2];
        psc_proxy_octa_fold(q, got);
        double dq[3] = {q[0] / 65536.0, q[1] / 65536.0, q[2] / 65536.0}, uq[2];
        ref_fold(dq, uq);   /* the reference of the rounded input: the fold itself rounds once */
        for (unsigned k = 0; k < 2; k++)
            worst = fmax(worst, fabs(got[k] / 65536.0 - uq[k]) * 65536.0);
        if (d[1] >= 0)
            assert_true(labs((long)got[0]) + labs((long)got[1]) <= 65536 + 1);   /* the upper half: the diamond */
    }
    print_message("  100000 directions folded within %.2f units of 2^-16 of the double fold\n", worst);
    assert_true(worst <= 1.0);
    for (unsigned side = 3; side <= 17; side += 2)
        for (unsigned k = 0; k < side * side; k++) {
            int32_t d[3];
            psc_proxy_pick_t p;
            psc_proxy_view_dir(side, k, d);
            assert_int_equal(psc_proxy_view_pick(side, d, &p), PSC_OK);
            /* a border view has twins (the square's edges fold onto each other): one of them, wholly */
            int32_t back[3];
            psc_proxy_view_dir(side, p.view[0], back);
            assert_true(p.w_q16[0] >= 65536 - 8);
            for (unsigned a = 0; a < 3; a++)
                assert_true(labs((long)back[a] - d[a]) <= 8);
        }
}

/* The same choice in double: the views and their weights. */
static void ref_pick(unsigned side, const double d[3], unsigned view[3], double w[3])
{
    double uv[2];
    ref_fold(d, uv);
    double gx = (uv[0] + 1) * (side - 1) / 2, gy = (uv[1] + 1) * (side - 1) / 2;
    unsigned ix = (unsigned)floor(gx), iy = (unsigned)floor(gy);
    if (ix >= side - 1)
        ix = side - 2;
    if (iy >= side - 1)
        iy = side - 2;
    double fx = gx - ix, fy = gy - iy;
    unsigned v00 = iy * side + ix, v10 = v00 + 1, v01 = v00 + side, v11 = v01 + 1;
    double cu = 2.0 * ix + 1 - (side - 1), cv = 2.0 * iy + 1 - (side - 1);
    if ((cu > 0) == (cv > 0)) {
        if (fx + fy <= 1) {
            view[0] = v00, w[0] = 1 - fx - fy, view[1] = v10, w[1] = fx, view[2] = v01, w[2] = fy;
        } else {
            view[0] = v11, w[0] = fx + fy - 1, view[1] = v10, w[1] = 1 - fy, view[2] = v01, w[2] = 1 - fx;
        }
    } else if (fx >= fy) {
        view[0] = v00, w[0] = 1 - fx, view[1] = v10, w[1] = fx - fy, view[2] = v11, w[2] = fy;
    } else {
        view[0] = v00, w[0] = 1 - fy, view[1] = v01, w[1] = fy - fx, view[2] = v11, w[2] = fx;
    }
}

static void test_pick(void **state)
{
    (void)state;
    unsigned compared = 0, at_edges = 0;
    double worst = 0;
    for (unsigned n = 0; n < 100000; n++) {
        unsigned side = 3 + 2 * (n % 8);
        double d[3];
        random_dir(d);
        int32_t q[3] = {(int32_t)lround(d[0] * 65536), (int32_t)lround(d[1] * 65536), (int32_t)lround(d[2] * 65536)};
        psc_proxy_pick_t p;
        assert_int_equal(psc_proxy_view_pick(side, q, &p), PSC_OK);
        assert_int_equal(p.w_q16[0] + p.w_q16[1] + p.w_q16[2], 65536);
        assert_true(p.w_q16[0] >= p.w_q16[1] && p.w_q16[1] >= p.w_q16[2] && p.w_q16[2] >= 0);
        /* the weights put the direction back where it falls on the grid */
        int32_t uv[2];
        psc_proxy_octa_fold(q, uv);
        double gx = 0, gy = 0;
        for (unsigned a = 0; a < 3; a++) {
            gx += p.w_q16[a] / 65536.0 * (p.view[a] % side);
            gy += p.w_q16[a] / 65536.0 * (p.view[a] / side);
        }
        assert_true(fabs(gx - (uv[0] / 65536.0 + 1) * (side - 1) / 2) < 1e-3);
        assert_true(fabs(gy - (uv[1] / 65536.0 + 1) * (side - 1) / 2) < 1e-3);
        /* the double choice of the rounded input: the same views and weights, but on a cell's edge */
        double dq[3] = {q[0] / 65536.0, q[1] / 65536.0, q[2] / 65536.0}, w[3];
        unsigned view[3];
        ref_pick(side, dq, view, w);
        double wv[3] = {0, 0, 0};
        bool same = true;
        for (unsigned a = 0; a < 3; a++) {
            bool found = false;
            for (unsigned b = 0; b < 3; b++)
                if (view[b] == p.view[a]) {
                    wv[a] = w[b];
                    found = true;
                }
            same &= found || p.w_q16[a] <= 2;
        }
        if (!same) {
            at_edges++;
            continue;
        }
        for (unsigned a = 0; a < 3; a++)
            worst = fmax(worst, fabs(p.w_q16[a] / 65536.0 - wv[a]) * 65536.0);
        compared++;
    }
    print_message("  100000 directions: %u the same three views as the double choice (weights within %.2f units of "
                  "2^-16), %u on a cell's edge\n", compared, worst, at_edges);
    assert_true(worst <= 2.0);
    assert_true(at_edges * 1000u <= compared);
    psc_proxy_pick_t p;
    const int32_t zero[3] = {0, 0, 0}, up[3] = {0, 65536, 0};
    assert_int_equal(psc_proxy_view_pick(9, zero, &p), PSC_ERR_ARG);
    assert_int_equal(psc_proxy_view_pick(1, up, &p), PSC_ERR_ARG);
    assert_int_equal(psc_proxy_view_pick(PSC_PROXY_VIEW_SIDE_MAX + 1u, up, &p), PSC_ERR_ARG);
    /* straight up is the middle view of an odd grid */
    assert_int_equal(psc_proxy_view_pick(9, up, &p), PSC_OK);
    assert_int_equal(p.view[0], 4 * 9 + 4);
    assert_int_equal(p.w_q16[0], 65536);
}

/* Rotation about an axis by a quarter turns (exact) or by any angle, as a rigid transform. */
static psc_mat4_q16_t rotation(unsigned axis, double angle)
{
    double c = cos(angle), s = sin(angle);
    double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    unsigned a = (axis + 1) % 3, b = (axis + 2) % 3;
    r[a][a] = c, r[a][b] = -s, r[b][a] = s, r[b][b] = c;
    psc_mat4_q16_t m;
    memset(&m, 0, sizeof m);
    for (unsigned i = 0; i < 3; i++)
        for (unsigned j = 0; j < 3; j++)
            m.m[i][j] = (int32_t)lround(r[i][j] * 65536);
    m.m[3][3] = 65536;
    return m;
}

static psc_mat4_q16_t mul(const psc_mat4_q16_t *a, const psc_mat4_q16_t *b)
{
    psc_mat4_q16_t m;
    memset(&m, 0, sizeof m);
    for (unsigned i = 0; i < 3; i++)
        for (unsigned j = 0; j < 3; j++) {
            int64_t s = 0;
            for (unsigned k = 0; k < 3; k++)
                s += (int64_t)a->m[i][k] * b->m[k][j];
            m.m[i][j] = (int32_t)((s + 32768) >> 16);
        }
    m.m[3][3] = 65536;
    return m;
}

static void test_part_direction(void **state)
{
    (void)state;
    psc_mat4_q16_t id = rotation(0, 0);
    unsigned exact = 0, near = 0, other = 0;
    for (unsigned n = 0; n < 20000; n++) {
        double d[3];
        random_dir(d);
        int32_t ds[3] = {(int32_t)lround(d[0] * 65536), (int32_t)lround(d[1] * 65536), (int32_t)lround(d[2] * 65536)};
        bool quarter = n % 2 == 0;
        double a1 = quarter ? M_PI / 2 * (1 + n % 3) : frand() * 2 * M_PI, a2 = quarter ? M_PI / 2 * (n % 4) : frand() * 2 * M_PI;
        psc_mat4_q16_t m1 = rotation(n % 3, a1), m2 = rotation((n / 3) % 3, a2), both = mul(&m1, &m2);
        int32_t dr[3], dc[3];
        psc_proxy_view_for_part(ds, &m1, &m2, dr);          /* the object and the part turned */
        psc_proxy_view_for_part(ds, &both, &id, dc);        /* the camera turned by the inverse instead */
        psc_proxy_pick_t pr, pc;
        assert_int_equal(psc_proxy_view_pick(9, dr, &pr), PSC_OK);
        assert_int_equal(psc_proxy_view_pick(9, dc, &pc), PSC_OK);
        /* against double: the direction in the part's frame */
        double r1[3][3], r2[3][3], t[3], want[3];
        for (unsigned i = 0; i < 3; i++)
            for (unsigned j = 0; j < 3; j++) {
                r1[i][j] = m1.m[i][j] / 65536.0;
                r2[i][j] = m2.m[i][j] / 65536.0;
            }
        for (unsigned r = 0; r < 3; r++)
            t[r] = r1[0][r] * d[0] + r1[1][r] * d[1] + r1[2][r] * d[2];
        for (unsigned r = 0; r < 3; r++)
            want[r] = r2[0][r] * t[0] + r2[1][r] * t[1] + r2[2][r] * t[2];
        for (unsigned r = 0; r < 3; r++)
            assert_true(fabs(dr[r] / 65536.0 - want[r]) < 3e-4);
        bool same = memcmp(&pr, &pc, sizeof pr) == 0;
        if (quarter) {
            assert_true(same);   /* quarter turns are exact: exactly the same views and weights */
            exact++;
        } else if (same) {
            exact++;
        } else {
            bool views = memcmp(pr.view, pc.view, sizeof pr.view) == 0;
            for (unsigned a = 0; a < 3 && views; a++)
                assert_true(labs((long)pr.w_q16[a] - pc.w_q16[a]) <= 64);
            views ? near++ : other++;
        }
    }
    print_message("  20000 turned parts: %u pick exactly what the turned camera picks, %u the same views with weights "
                  "within 64/65536, %u on a cell's edge\n", exact, near, other);
    assert_true(other * 100u <= exact + near);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fold),
        cmocka_unit_test(test_pick),
        cmocka_unit_test(test_part_direction),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
