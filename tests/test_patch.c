/* SPDX-License-Identifier: MIT */
/*
 * test_patch.c - Hash spline patches and skeletal animation (core/patch/,
 * host_tools/lib/{am_*,patch_*,bpt_load}.c).
 *
 *  - the curve: halving exact and symmetric; the s/c flatness tests keep a
 *    curve within E = T/4 of its chord (20 000 random cubics); MakeFlat;
 *  - crack-freeness as a property: random patch meshes (open and closed,
 *    biased), random tolerances and views; Thom (hooks, 3-, 5- and 6-sided
 *    patches) in several poses; closed models leave no background pixel
 *    inside their silhouettes;
 *  - the measured chord error stays within the tolerance, and the triangle
 *    count falls as the tolerance rises;
 *  - against the double-precision reference tessellation (tsup_patch.h):
 *    silhouette IoU and depth on the sample models at several views and
 *    tolerances;
 *  - animation: a bone moves exactly its points (weighted ones by weight);
 *    an action naming bones a model lacks still plays the rest; channels
 *    match a double Catmull-Rom; lazy re-evaluation gives the same frame;
 *    motion capture (.bvh) retargeted by bone name moves the bones it names;
 *  - the A:M and .bpt importers and the pack: fuzzed and truncated input
 *    gives a message naming the file (and line), never a crash.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "psc_testsupport.h"
#include "tsup_files.h"
#include "tsup_3d.h"
#include "tsup_patch.h"
#include "tsup_teapot.h"

#include "import/am_action.h"
#include "psc_io_angle.h"
#include "import/am_model.h"
#include "anim/am_rig.h"
#include "import/bpt.h"
#include "import/bvh.h"
#include "import/patch_source.h"
#include "bake/patch_any.h"
#include "measure/patch.h"
#include "measure/surface.h"
#include "psc_io_file.h"
#include "base/psc_crc32.h"
#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_render.h"
#include "scene/scene_character.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define AM_DIR TSUP_DATA_AM
#define THOM "assets/thom/Thom.mdl"
#define THOM2 "assets/thom/Thom2.mdl"
#define WAVE "assets/thom/Wave.act"
#define WALK "assets/thom/ResoluteWalk.act"

/* ---- helpers ---------------------------------------------------------------------------------------------- */

typedef tsup_tess_t tess_t;

static void tess_new(tess_t *t, const psc_patch_model_t *m)
{
    assert_int_equal(tsup_tess_new(t, m), 0);
}

static void tess_free(tess_t *t)
{
    tsup_tess_free(t);
}

/* An orbit camera on the rest box, as periscope-render's. */
static void camera(const psc_patch_model_t *m, double yaw, double pitch, double dist, double hfov, unsigned w,
                   double tol_px, double tol_units, bool cull, psc_patch_camera_t *cam, int32_t *near_q16,
                   int32_t *far_q16)
{
    psc_vec3_q16_t lo = {m->lo_q16[0], m->lo_q16[1], m->lo_q16[2]}, hi = {m->hi_q16[0], m->hi_q16[1], m->hi_q16[2]};
    *cam = (psc_patch_camera_t){0};
    assert_int_equal(psc_3d_orbit(lo, hi, tsup_bam_from_deg(yaw), psc_io_sbam_from_deg(pitch),
                                  (int32_t)lround(dist * 65536.0), &cam->camera_from_object, near_q16, far_q16),
                     PSC_OK);
    cam->focal_px_q16 = (int32_t)lround(w / 2.0 / tan(hfov * M_PI / 360.0) * 65536.0);
    cam->tol_px_q16 = (int32_t)lround(tol_px * 65536.0);
    cam->tol_units_q16 = (int32_t)lround(tol_units * 65536.0);
    cam->near_q16 = *near_q16;
    cam->cull = cull;
}

static void frame(psc_patch_t *p, int action, uint32_t ms, const psc_patch_camera_t *cam, psc_patch_stats_t *st)
{
    psc_patch_pose(p, action, ms);
    psc_patch_tangents(p);
    assert_int_equal(psc_patch_tessellate(p, cam, st), PSC_OK);
}

static void load(const char *path, const psc_bake_patch_opts_t *o, psc_io_patch_t *pf)
{
    char err[768];
    if (psc_bake_patch_any(path, o, pf, err, sizeof err) != 0)
        fail_msg("%s", err);
}

/* Thom with his skin from Thom2 and both actions (0: ResoluteWalk, 1: Wave). */
static void load_thom(psc_io_patch_t *pf)
{
    psc_bake_patch_opts_t o = {.actions = {WALK, WAVE}, .action_count = 2, .skin_from = THOM2, .quiet = true};
    load(THOM, &o, pf);
}

/* The Utah teapot (tests/support/tsup_teapot.h) as a patch pack in *buf, parsed into m. */
static void load_teapot(uint8_t **buf, psc_patch_model_t *m)
{
    size_t n = 0, len = 0;
    char err[512];
    char *text = tsup_teapot_bpt(&n);
    psc_patch_src_t src;
    if (psc_bpt_parse("teapot.bpt", text, n, &src, err, sizeof err) != 0 ||
        psc_bake_patch_pack(&src, "teapot.bpt", buf, &len, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_container_error_t e = {0};
    assert_int_equal(psc_patch_parse(*buf, len, m, &e), PSC_OK);
    psc_patch_src_free(&src);
    free(text);
}

static void load_plain(const char *path, psc_io_patch_t *pf)
{
    psc_bake_patch_opts_t o = {.quiet = true};
    load(path, &o, pf);
}

/* ---- the curve -------------------------------------------------------------------------------------------- */

static void random_curve(tsup_rng_t *r, psc_curve_t *c, double scale)
{
    for (unsigned i = 0; i < 4; i++)
        for (unsigned k = 0; k < 3; k++)
            c->p[i][k] = (int32_t)lround(tsup_rng_range(r, -scale, scale) * 65536.0);
}

static void curve_at(const psc_curve_t *c, double t, double out[3])
{
    double s = 1 - t;
    for (unsigned k = 0; k < 3; k++)
        out[k] = (s * s * s * c->p[0][k] + 3 * s * s * t * c->p[1][k] + 3 * s * t * t * c->p[2][k] +
                  t * t * t * c->p[3][k]) / 65536.0;
}

/* The largest distance from the curve to its chord, sampled densely. */
static double chord_distance(const psc_curve_t *c)
{
    double a[3], b[3], worst = 0;
    curve_at(c, 0, a);
    curve_at(c, 1, b);
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    for (unsigned i = 0; i <= 256; i++) {
        double x[3], ax[3];
        curve_at(c, i / 256.0, x);
        for (unsigned k = 0; k < 3; k++)
            ax[k] = x[k] - a[k];
        double t = l2 > 0 ? (ax[0] * ab[0] + ax[1] * ab[1] + ax[2] * ab[2]) / l2 : 0;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        double d2 = 0;
        for (unsigned k = 0; k < 3; k++)
            d2 += (ax[k] - t * ab[k]) * (ax[k] - t * ab[k]);
        worst = fmax(worst, sqrt(d2));
    }
    return worst;
}

static void test_curve_split(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 11);
    for (unsigned n = 0; n < 20000; n++) {
        psc_curve_t c, rc, l, rr, rl, rrr;
        random_curve(&r, &c, 60.0);
        psc_curve_split(&c, &l, &rr);
        /* the halves meet on the curve at 1/2 and keep the ends */
        double mid[3];
        curve_at(&c, 0.5, mid);
        for (unsigned k = 0; k < 3; k++) {
            assert_int_equal(l.p[3][k], rr.p[0][k]);
            assert_true(fabs(l.p[3][k] / 65536.0 - mid[k]) <= 2.0 / 65536.0);
            assert_int_equal(l.p[0][k], c.p[0][k]);
            assert_int_equal(rr.p[3][k], c.p[3][k]);
        }
        /* a reversed curve halves into the reversed halves, bit for bit (shared edges agree either way) */
        psc_curve_reverse(&c, &rc);
        psc_curve_split(&rc, &rl, &rrr);
        psc_curve_t back;
        psc_curve_reverse(&rrr, &back);
        assert_memory_equal(&back, &l, sizeof l);
        psc_curve_reverse(&rl, &back);
        assert_memory_equal(&back, &rr, sizeof rr);
    }
}

/* Property: when the tests pass a curve as flat at T, it lies within T/4 of its chord (s test always; c test on
 * the halves it allows). */
static void check_flat_bound(const psc_curve_t *c, psc_curve_kind_t kind, int32_t t, unsigned depth,
                             unsigned *checked)
{
    bool cl, cr;
    if (!psc_curve_needs_split(c, kind, t, &cl, &cr)) {
        double d = chord_distance(c), e = t / 65536.0 / 4.0;
        if (d > e + 4.0 / 65536.0)
            fail_msg("a %s curve passed as flat at E = %.6f strays %.6f from its chord", kind ? "c" : "s", e, d);
        (*checked)++;
        return;
    }
    if (depth == 0)
        return;
    psc_curve_t l, r;
    psc_curve_split(c, &l, &r);
    check_flat_bound(&l, kind == PSC_CURVE_C || cl ? PSC_CURVE_C : PSC_CURVE_S, t, depth - 1, checked);
    check_flat_bound(&r, kind == PSC_CURVE_C || cr ? PSC_CURVE_C : PSC_CURVE_S, t, depth - 1, checked);
}

static void test_flatness_bound(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 12);
    unsigned checked = 0;
    for (unsigned n = 0; n < 20000; n++) {
        psc_curve_t c;
        random_curve(&r, &c, tsup_rng_range(&r, 0.01, 40.0));
        int32_t t = (int32_t)lround(tsup_rng_range(&r, 0.0005, 2.0) * 65536.0);
        check_flat_bound(&c, PSC_CURVE_S, t, 8, &checked);
    }
    print_message("  %u flat pieces of 20000 random cubics within T/4 of their chords\n", checked);
    assert_true(checked > 20000);
}

/*
 * The split test at the range's limits (a posed pack may put points anywhere in Q16.16: found by
 * fuzzing, the products overflowed int64): 100 000 random cubics with control points up to ±(2^31 - 1)
 * (UBSan watches the arithmetic in the sanitizer builds); the convexity flags agree with the signs of
 * the dot products in double wherever the angle is not within 10^-6 of a right angle, and a curve whose
 * second differences pass T is always split.
 */
static void test_split_test_at_range_limits(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 1601);
    unsigned compared = 0;
    for (unsigned n = 0; n < 100000; n++) {
        psc_curve_t c;
        double scale = n % 4 == 0 ? 2147483647.0 : tsup_rng_range(&r, 1.0, 2147483647.0);
        for (unsigned i = 0; i < 4; i++)
            for (unsigned k = 0; k < 3; k++)
                c.p[i][k] = (int32_t)lround(tsup_rng_range(&r, -1.0, 1.0) * scale);
        int32_t t = (int32_t)lround(tsup_rng_range(&r, 0.0005, 2.0) * 65536.0);
        bool cl, cr, split = psc_curve_needs_split(&c, PSC_CURVE_S, t, &cl, &cr);
        double d1[3], d2[3], e0[3], em[3], e1[3], dl = 0, dr = 0, nl0 = 0, nlm = 0, nl1 = 0, len1 = 0;
        for (unsigned k = 0; k < 3; k++) {
            d1[k] = 4.0 * c.p[0][k] - 6.0 * c.p[1][k] + 2.0 * c.p[3][k];
            d2[k] = 2.0 * c.p[0][k] - 6.0 * c.p[2][k] + 4.0 * c.p[3][k];
            e0[k] = 2 * d1[k] - d2[k];
            em[k] = d1[k] + d2[k];
            e1[k] = 2 * d2[k] - d1[k];
            dl += e0[k] * em[k];
            dr += em[k] * e1[k];
            nl0 += e0[k] * e0[k];
            nlm += em[k] * em[k];
            nl1 += e1[k] * e1[k];
            len1 += d1[k] * d1[k];
        }
        if (sqrt(len1) > t + 2.0)
            assert_true(split);
        if (fabs(dl) > 1e-6 * sqrt(nl0 * nlm)) {
            assert_int_equal(cl, dl >= 0);
            compared++;
        }
        if (fabs(dr) > 1e-6 * sqrt(nlm * nl1)) {
            assert_int_equal(cr, dr >= 0);
            compared++;
        }
    }
    print_message("  %u convexity flags of curves out to 2^31 agree with double\n", compared);
    assert_true(compared > 190000);
}

static void test_make_flat(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 13);
    for (unsigned n = 0; n < 5000; n++) {
        psc_curve_t c, f;
        random_curve(&r, &c, 10.0);
        f = c;
        psc_curve_make_flat(&f);
        assert_memory_equal(f.p[0], c.p[0], sizeof f.p[0]);
        assert_memory_equal(f.p[3], c.p[3], sizeof f.p[3]);
        /* the inner points lie on the chord's line (to rounding) and keep their distances from the ends */
        double a[3], b[3], ab[3], l = 0;
        for (unsigned k = 0; k < 3; k++) {
            a[k] = f.p[0][k] / 65536.0;
            b[k] = f.p[3][k] / 65536.0;
            ab[k] = b[k] - a[k];
            l += ab[k] * ab[k];
        }
        if (l < 1e-6)
            continue;
        for (unsigned i = 1; i < 3; i++) {
            double ax[3], t = 0, d2 = 0, keep0 = 0, keep1 = 0;
            unsigned e = i == 1 ? 0 : 3;   /* p1 keeps its distance from p0, p2 from p3 */
            for (unsigned k = 0; k < 3; k++) {
                ax[k] = f.p[i][k] / 65536.0 - a[k];
                t += ax[k] * ab[k] / l;
                double o = (c.p[i][k] - c.p[e][k]) / 65536.0, q = (f.p[i][k] - f.p[e][k]) / 65536.0;
                keep0 += o * o;
                keep1 += q * q;
            }
            for (unsigned k = 0; k < 3; k++)
                d2 += (ax[k] - t * ab[k]) * (ax[k] - t * ab[k]);
            /* the direction is a unit vector in Q16.16: a relative error of about 2^-16 */
            double slack = (3.0 + 2.0 * sqrt(keep0)) / 65536.0;
            assert_true(sqrt(d2) <= slack);
            assert_true(fabs(sqrt(keep0) - sqrt(keep1)) <= slack);
        }
    }
}

/* ---- random patch meshes ----------------------------------------------------------------------------------- */

/* A grid of nu x nv patches on a bumpy sheet (or a tube when closed), splines along both ways, random biases,
 * a hook at the middle of some segments of the last row, and the top corners collapsed into three-sided
 * patches when fan is set. */
static void random_mesh(tsup_rng_t *r, psc_patch_src_t *s, bool closed)
{
    unsigned nu = (closed ? 3 : 2) + tsup_rng_below(r, 4), nv = 2 + tsup_rng_below(r, 4);
    unsigned pu = closed ? nu : nu + 1u, pv = nv + 1u;
    memset(s, 0, sizeof *s);
    s->point_count = (size_t)pu * pv;
    s->point = calloc(s->point_count, sizeof *s->point);
    double amp = tsup_rng_range(r, 0.0, 0.6), fx = tsup_rng_range(r, 0.5, 3.0), fy = tsup_rng_range(r, 0.5, 3.0);
    for (unsigned j = 0; j < pv; j++)
        for (unsigned i = 0; i < pu; i++) {
            double *p = s->point[j * pu + i];
            if (closed) {
                double a = 2 * M_PI * i / pu, rad = 1.0 + amp * 0.5 * sin(fy * j);
                p[0] = rad * cos(a);
                p[1] = j * 0.7;
                p[2] = rad * sin(a);
            } else {
                p[0] = i + tsup_rng_range(r, -0.2, 0.2);
                p[1] = j + tsup_rng_range(r, -0.2, 0.2);
                p[2] = amp * sin(fx * i) * cos(fy * j);
            }
        }
    /* splines: rows (u) then columns (v) */
    s->spline_count = pv + pu;
    s->cp_count = (size_t)pv * pu + (size_t)pu * pv;
    s->spline = calloc(s->spline_count, sizeof *s->spline);
    s->cp = calloc(s->cp_count, sizeof *s->cp);
    size_t cp = 0;
    for (unsigned j = 0; j < pv; j++) {
        s->spline[j] = (psc_patch_spline_t){(uint32_t)cp, (uint16_t)pu, closed ? PSC_PATCH_SPLINE_CLOSED : 0};
        for (unsigned i = 0; i < pu; i++)
            s->cp[cp++].point = (uint16_t)(j * pu + i);
    }
    for (unsigned i = 0; i < pu; i++) {
        s->spline[pv + i] = (psc_patch_spline_t){(uint32_t)cp, (uint16_t)pv, 0};
        for (unsigned j = 0; j < pv; j++)
            s->cp[cp++].point = (uint16_t)(j * pu + i);
    }
    for (size_t k = 0; k < s->cp_count; k++) {
        psc_patch_cp_t *c = &s->cp[k];
        c->in_mag_q12 = c->out_mag_q12 = 4096;
        if (tsup_rng_below(r, 3) == 0) {
            c->in_alpha = (int16_t)tsup_rng_range(r, -3000, 3000);
            c->out_alpha = (int16_t)tsup_rng_range(r, -3000, 3000);
            c->in_gamma = (int16_t)tsup_rng_range(r, -3000, 3000);
            c->out_gamma = (int16_t)tsup_rng_range(r, -3000, 3000);
            c->in_mag_q12 = (uint16_t)tsup_rng_range(r, 2048, 9000);
            c->out_mag_q12 = (uint16_t)tsup_rng_range(r, 2048, 9000);
        }
        if (tsup_rng_below(r, 10) == 0)
            c->flags |= PSC_PATCH_CP_PEAKED;
    }
    /* edges: row segments, column segments */
    s->edge = calloc((size_t)pv * nu + (size_t)pu * nv, sizeof *s->edge);
    for (unsigned j = 0; j < pv; j++)
        for (unsigned i = 0; i < nu; i++)
            s->edge[s->edge_count++] = (psc_patch_edge_t){(uint16_t)j, (uint16_t)i, 0, 4, 0, 0};
    for (unsigned i = 0; i < pu; i++)
        for (unsigned j = 0; j < nv; j++)
            s->edge[s->edge_count++] = (psc_patch_edge_t){(uint16_t)(pv + i), (uint16_t)j, 0, 4, 0, 0};
    s->face = calloc((size_t)nu * nv, sizeof *s->face);
    for (unsigned j = 0; j < nv; j++)
        for (unsigned i = 0; i < nu; i++) {
            uint32_t bottom = j * nu + i, top = (j + 1) * nu + i;
            uint32_t left = pv * nu + i * nv + j, right = pv * nu + ((i + 1) % pu) * nv + j;
            psc_patch_face_t *f = &s->face[s->face_count++];
            f->sides = 4;
            f->edge[0] = bottom;
            f->edge[1] = right;
            f->edge[2] = top | PSC_PATCH_EDGE_REVERSED;
            f->edge[3] = left | PSC_PATCH_EDGE_REVERSED;
        }
    s->color = malloc(sizeof *s->color);
    s->color[0] = 0xC0C0C0;
    s->color_count = 1;
    psc_patch_src_bounds(s);
}

/* Pack a host character and parse it in place. */
static void pack_src(const psc_patch_src_t *s, uint8_t **buf, psc_patch_model_t *m)
{
    size_t len;
    char err[512];
    if (psc_bake_patch_pack(s, "random", buf, &len, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_container_error_t e = {0};
    assert_int_equal(psc_patch_parse(*buf, len, m, &e), PSC_OK);
}

static void test_cracks_random(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 21);
    unsigned cases = 0, triangles = 0;
    for (unsigned n = 0; n < 60; n++) {
        psc_patch_src_t s;
        random_mesh(&r, &s, n % 3 == 2);
        uint8_t *buf;
        psc_patch_model_t m;
        pack_src(&s, &buf, &m);
        tess_t t;
        tess_new(&t, &m);
        for (unsigned v = 0; v < 4; v++) {
            psc_patch_camera_t cam;
            int32_t nr, fr;
            double tol = tsup_rng_range(&r, 0.05, 4.0);
            camera(&m, tsup_rng_range(&r, -180, 180), tsup_rng_range(&r, -60, 60), tsup_rng_range(&r, 1.2, 6.0),
                   tsup_rng_range(&r, 30, 90), 640, tol, 0, false, &cam, &nr, &fr);
            psc_patch_stats_t st;
            frame(&t.p, -1, 0, &cam, &st);
            long cracks = psc_measure_cracks(&t.p);
            if (cracks != 0)
                fail_msg("random mesh %u view %u (tolerance %.3f px): %ld crack edges", n, v, tol, cracks);
            cases++;
            triangles += st.triangles;
        }
        tess_free(&t);
        free(buf);
        psc_patch_src_free(&s);
    }
    print_message("  %u random meshes and views (%u triangles): no crack edge\n", cases, triangles);
}

/* The crack counter can fail: on a closed model (every edge shared by two patches) tessellated without a crack,
 * one unit (2^-16 R) added to one copy of a shared vertex - a corner, then a vertex inside an edge - makes crack
 * edges, and putting it back leaves none. */
static void test_crack_counter_fires(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    load_plain(AM_DIR "8Patch_Sphere.mdl", &pf);
    tess_t t;
    tess_new(&t, &pf.model);
    psc_patch_camera_t cam;
    int32_t nr, fr;
    camera(&pf.model, 30, 10, 2.5, 50, 800, 0.5, 0, false, &cam, &nr, &fr);
    psc_patch_stats_t st;
    frame(&t.p, -1, 0, &cam, &st);
    assert_int_equal(psc_measure_cracks(&t.p), 0);
    /* a patch's first corner, then the middle vertex of a chain of its (an edge vertex another patch has a copy
     * of, not one of the patch's inner vertices) */
    uint32_t fi = 0, e = 0;
    bool found = false;
    for (uint32_t f = 0; f < pf.model.face_count && !found; f++)
        for (unsigned i = 0; i < pf.model.faces[f].sides && !found; i++) {
            uint32_t ei = pf.model.faces[f].edge[i] & ~PSC_PATCH_EDGE_REVERSED;
            if (t.p.edge_depth[ei] >= 1)
                fi = f, e = ei, found = true;
        }
    assert_true(found);
    const psc_patch_vtx_t *vt;
    const uint16_t *ix;
    uint32_t vn, tn;
    psc_measure_face_output(&t.p, fi, &vt, &vn, &ix, &tn);
    assert_true(vn > 4 && tn > 0);
    const psc_patch_vtx_t *chain = t.p.vtx_pool + t.p.edge_vtx[e];
    const int32_t *targets[2] = {chain[0].p, chain[1u << (t.p.edge_depth[e] - 1u)].p};
    for (unsigned k = 0; k < 2; k++) {
        psc_patch_vtx_t *v = NULL;
        for (uint32_t i = 0; i < vn; i++)
            if (memcmp(vt[i].p, targets[k], sizeof vt[i].p) == 0)
                v = (psc_patch_vtx_t *)&vt[i];
        assert_non_null(v);
        v->p[1] += 1;
        long cracks = psc_measure_cracks(&t.p);
        print_message("  the sphere's patch %u: %s moved by one unit: %ld crack edges\n", (unsigned)fi,
                      k ? "the middle vertex of an edge" : "a corner", cracks);
        assert_true(cracks >= 2);   /* both pieces of the patch that meet there, at least */
        v->p[1] -= 1;
        assert_int_equal(psc_measure_cracks(&t.p), 0);
    }
    tess_free(&t);
    psc_io_patch_free(&pf);
}

/* ---- the sample models ------------------------------------------------------------------------------------ */

static void test_cracks_thom(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    load_thom(&pf);
    const psc_patch_model_t *m = &pf.model;
    unsigned sides[PSC_PATCH_MAX_SIDES + 1] = {0};
    for (uint32_t f = 0; f < m->face_count; f++)
        sides[m->faces[f].sides]++;
    print_message("  Thom: %u patches (%u three-, %u four-, %u five-, %u six-sided), %u hooks\n",
                  (unsigned)m->face_count, sides[3], sides[4], sides[5], sides[6], (unsigned)m->hook_count);
    assert_int_equal(m->face_count, 392);
    assert_int_equal(m->hook_count, 12);
    assert_true(sides[3] > 0 && sides[5] > 0);
    tess_t t;
    tess_new(&t, m);
    static const struct {
        int action;
        uint32_t ms;
        double tol, yaw;
    } poses[] = {{-1, 0, 0.5, 30}, {0, 300, 0.25, 200}, {0, 700, 1.0, 90}, {1, 400, 0.5, 160},
                 {1, 1300, 2.0, 250}, {1, 1900, 0.5, 330}};
    for (unsigned k = 0; k < sizeof poses / sizeof poses[0]; k++) {
        psc_patch_camera_t cam;
        int32_t nr, fr;
        camera(m, poses[k].yaw, 10, 2.5, 50, 800, poses[k].tol, 0, false, &cam, &nr, &fr);
        psc_patch_stats_t st;
        frame(&t.p, poses[k].action, poses[k].ms, &cam, &st);
        long cracks = psc_measure_cracks(&t.p);
        print_message("  action %d at %u ms, %.2f px: %u triangles, %ld crack edges\n", poses[k].action,
                      (unsigned)poses[k].ms, poses[k].tol, (unsigned)st.triangles, cracks);
        assert_int_equal(cracks, 0);
        assert_int_equal(st.patches, 392);
    }
    tess_free(&t);
    psc_io_patch_free(&pf);
}

/* Draw p's batches with the device pipeline; z receives camera depths (INFINITY where nothing drew). */
static void draw(const psc_patch_t *p, const psc_patch_camera_t *cam, int32_t near_q16, int32_t far_q16,
                 double hfov, psc_surface_t *out, double *z, bool cull)
{
    psc_3d_config_t cfg = {out->width, out->height, 0, 0, 32, tsup_bam_from_deg(hfov), near_q16, far_q16,
                           PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES, PSC_3D_HSR_ZBUFFER};
    tsup_3d_t r;
    assert_int_equal(tsup_3d_init(&r, &cfg), PSC_OK);
    uint16_t *zout = calloc((size_t)out->width * out->height, 2);
    r.r.depth_out = zout;
    psc_3d_draw_t d[PSC_PATCH_MAX_BATCHES];
    psc_patch_camera_t c = *cam;
    c.cull = cull;
    unsigned n = psc_patch_draws(p, &c, d);
    uint32_t bg = 0x30343C;
    assert_int_equal(psc_3d_render(&r.r, d, n, &bg, out, NULL), PSC_OK);
    /* depth: affine in 1/z, 0 at near .. 1 at far (top 16 bits) */
    double nq = near_q16 / 65536.0, fq = far_q16 / 65536.0;
    for (size_t i = 0; i < (size_t)out->width * out->height; i++) {
        double dn = zout[i] / 65536.0;
        z[i] = zout[i] == 0xFFFF ? INFINITY : nq / (1.0 - dn * (fq - nq) / fq);
    }
    free(zout);
    tsup_3d_free(&r);
}

/* Background pixels no path of background pixels joins to the border: holes in the silhouette. */
static unsigned enclosed_background(const double *z, unsigned w, unsigned h)
{
    uint8_t *seen = calloc((size_t)w * h, 1);
    uint32_t *stack = malloc((size_t)w * h * sizeof *stack);
    size_t top = 0;
    for (unsigned y = 0; y < h; y++)
        for (unsigned x = 0; x < w; x++)
            if ((x == 0 || y == 0 || x == w - 1 || y == h - 1) && isinf(z[y * w + x])) {
                seen[y * w + x] = 1;
                stack[top++] = y * w + x;
            }
    while (top) {
        uint32_t at = stack[--top], x = at % w, y = at / w;
        const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
        for (unsigned k = 0; k < 4; k++) {
            int nx = (int)x + dx[k], ny = (int)y + dy[k];
            if (nx < 0 || ny < 0 || nx >= (int)w || ny >= (int)h)
                continue;
            uint32_t n = (uint32_t)ny * w + (uint32_t)nx;
            if (!seen[n] && isinf(z[n])) {
                seen[n] = 1;
                stack[top++] = n;
            }
        }
    }
    unsigned holes = 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        holes += isinf(z[i]) && !seen[i];
    free(seen);
    free(stack);
    return holes;
}

static void test_closed_no_holes(void **state)
{
    (void)state;
    static const char *const models[] = {AM_DIR "8Patch_Sphere.mdl", AM_DIR "Cylinder.mdl"};
    for (unsigned k = 0; k < 2; k++) {
        psc_io_patch_t pf;
        load_plain(models[k], &pf);
        tess_t t;
        tess_new(&t, &pf.model);
        psc_surface_t s = tsup_surface_new(320, 240, PSC_PIX_RGB565);
        double *z = malloc(320 * 240 * sizeof *z);
        for (unsigned v = 0; v < 6; v++) {
            psc_patch_camera_t cam;
            int32_t nr, fr;
            double tol = v < 3 ? 0.5 : 3.0;
            camera(&pf.model, v * 61.0, -50 + v * 20.0, 2.2, 60, 320, tol, 0, true, &cam, &nr, &fr);
            psc_patch_stats_t st;
            frame(&t.p, -1, 0, &cam, &st);
            draw(&t.p, &cam, nr, fr, 60, &s, z, true);
            unsigned holes = enclosed_background(z, 320, 240);
            if (holes)
                tsup_save_png(&s, "patch-hole.png");
            if (holes)
                fail_msg("%s view %u: %u background pixels inside the silhouette", models[k], v, holes);
        }
        free(z);
        tsup_surface_free(&s);
        tess_free(&t);
        psc_io_patch_free(&pf);
    }
}

/*
 * --flatness TOL is met for every TOL from 0.004 down to 0.0005 R: the chord
 * error, measured against the double-precision reference surface of the same
 * pose (measure/surface.h: every patch halved uniformly in double, u and v in
 * turn, 65 x 65 points a quad), is within the tolerance asked for; fewer
 * triangles as it rises. On the A:M primitives (a torus, whose patches bulge
 * more inside than along their edges; a cone; a bent tube, which needs the
 * deepest halving; a sphere; a cylinder), the Utah teapot and Thom in two
 * actions.
 */
static void test_chord_error(void **state)
{
    (void)state;
    static const struct {
        const char *path;
        int action;          /* -1 rest, else Thom's action at 1 s */
    } cases[] = {{AM_DIR "Torus.mdl", -1},     {AM_DIR "Cone.mdl", -1},     {AM_DIR "Cylindrical_Elbow.mdl", -1},
                 {AM_DIR "8Patch_Sphere.mdl", -1}, {AM_DIR "Cylinder.mdl", -1}, {"teapot.bpt", -1},
                 {THOM, 0},                      {THOM, 1}};
    static const double tols[] = {0.004, 0.002, 0.001, 0.0005};
    for (unsigned k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        psc_io_patch_t pf;
        uint8_t *teapot = NULL;
        psc_patch_model_t tm;
        const psc_patch_model_t *m;
        if (strcmp(cases[k].path, THOM) == 0) {
            load_thom(&pf);
            m = &pf.model;
        } else if (strcmp(cases[k].path, "teapot.bpt") == 0) {
            load_teapot(&teapot, &tm);
            m = &tm;
        } else {
            load_plain(cases[k].path, &pf);
            m = &pf.model;
        }
        tess_t t;
        tess_new(&t, m);
        psc_patch_camera_t cam;
        int32_t nr, fr;
        uint32_t prev = UINT32_MAX;
        double worst_ratio = 0;
        for (unsigned i = 0; i < sizeof tols / sizeof tols[0]; i++) {
            camera(m, 30, 10, 2.5, 50, 800, 0, tols[sizeof tols / sizeof tols[0] - 1 - i], false, &cam, &nr, &fr);
            psc_patch_stats_t st;
            frame(&t.p, cases[k].action, 1000, &cam, &st);
            psc_measure_surface_t ref;
            assert_int_equal(psc_measure_surface_build(&t.p, 6, &ref), 0);
            double e = psc_measure_surface_chord(&t.p, &ref, NULL), tol = cam.tol_units_q16 / 65536.0;
            psc_measure_surface_free(&ref);
            worst_ratio = fmax(worst_ratio, e / tol);
            if (e > tol)
                fail_msg("%s (action %d) at %.4f R: chord error %.6f R against the reference, over the tolerance "
                         "(%u triangles, %u held at the depth cap)", cases[k].path, cases[k].action, tol, e,
                         (unsigned)st.triangles, (unsigned)st.depth_capped);
            assert_true(st.triangles <= prev);
            prev = st.triangles;
            if (i + 1 == sizeof tols / sizeof tols[0])
                print_message("  %-26s action %2d: at %.4f R %6u triangles, %.6f R; at most %.2f of the tolerance\n",
                              strrchr(cases[k].path, '/') ? strrchr(cases[k].path, '/') + 1 : cases[k].path,
                              cases[k].action, tol, (unsigned)st.triangles, e, worst_ratio);
        }
        tess_free(&t);
        if (teapot)
            free(teapot);
        else
            psc_io_patch_free(&pf);
    }
}

/* Thom (with his actions) and the teapot: the two characters the (u, v) and fold tests take. */
static void load_thom_and_teapot(psc_io_patch_t *pf, uint8_t **teapot, psc_patch_model_t *tm)
{
    load_thom(pf);
    load_teapot(teapot, tm);
}

/* Each vertex's place in its patch (out_uv): within the patch (an n-sided one's quad among its n), and where it falls
 * on the reference surface's grid, that surface's point there to the tolerance (the device's vertices lie on it but
 * where a boundary piece was made flat), for coarse and fine tolerances, Thom walking (his n-sided patches) and the
 * teapot (collapsed sides: three-sided patches). */
static void test_vertex_uv(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    uint8_t *teapot = NULL;
    psc_patch_model_t tm;
    load_thom_and_teapot(&pf, &teapot, &tm);
    const psc_patch_model_t *models[2] = {&pf.model, &tm};
    static const double tols[] = {0.01, 0.002, 0.0005};
    for (unsigned k = 0; k < 2; k++) {
        const psc_patch_model_t *m = models[k];
        tess_t t;
        tess_new(&t, m);
        for (unsigned i = 0; i < sizeof tols / sizeof tols[0]; i++) {
            psc_patch_camera_t cam;
            int32_t nr, fr;
            camera(m, 30, 10, 2.5, 50, 800, 0, tols[i], false, &cam, &nr, &fr);
            psc_patch_stats_t st;
            frame(&t.p, k == 0 ? 0 : -1, 400, &cam, &st);
            psc_measure_surface_t ref;   /* 64 x 64 cells a four-sided patch, 32 x 32 each quad of another */
            assert_int_equal(psc_measure_surface_build(&t.p, 6, &ref), 0);
            uint32_t v = 0, on_grid = 0;
            double worst = 0;
            for (uint32_t f = 0; f < m->face_count; f++) {
                if (t.p.face_cache[f] == PSC_PATCH_NO_CACHE)
                    continue;
                unsigned sides = m->faces[f].sides, n = sides == 4 ? 65u : 33u, step = PSC_PATCH_UV_ONE / (n - 1u);
                for (uint32_t c = 0; c < t.p.face_cache_count[f]; c++, v++) {
                    uint32_t uv = t.p.out_uv[v], u = PSC_PATCH_UV_U(uv), w = PSC_PATCH_UV_V(uv), q = PSC_PATCH_UV_QUAD(uv);
                    assert_true(u <= PSC_PATCH_UV_ONE && w <= PSC_PATCH_UV_ONE);
                    assert_true(sides == 4 ? q == 0 : q < sides);
                    if (u % step || w % step)
                        continue;
                    const double *r = ref.pos[ref.face_first[f] + (size_t)q * n * n + (w / step) * n + u / step];
                    double d = 0;
                    for (unsigned a = 0; a < 3; a++)
                        d += pow(t.p.out_pos[3 * v + a] / 65536.0 - r[a], 2);
                    worst = fmax(worst, sqrt(d));
                    on_grid++;
                }
            }
            assert_int_equal(v, t.p.vtx_total);
            print_message("  %s at %.4f R: %u of %u vertices on the reference's grid, at most %.2e R from its point "
                          "there\n", k ? "the teapot" : "Thom walking", tols[i], (unsigned)on_grid,
                          (unsigned)t.p.vtx_total, worst);
            assert_true(on_grid * 2u > t.p.vtx_total);
            assert_true(worst <= tols[i]);   /* (pieces made flat where they reached their depth move it) */
            psc_measure_surface_free(&ref);
        }
        tess_free(&t);
    }
    free(teapot);
    psc_io_patch_free(&pf);
}

/* Against the double reference: silhouette IoU and depth. */
static void test_reference(void **state)
{
    (void)state;
    static const char *const models[] = {AM_DIR "8Patch_Sphere.mdl", AM_DIR "Cylinder.mdl", THOM, THOM};
    const unsigned w = 320, h = 240;
    double worst_iou = 1, worst_depth = 1;
    for (unsigned k = 0; k < 4; k++) {
        psc_io_patch_t pf;
        if (k >= 2)
            load_thom(&pf);
        else
            load_plain(models[k], &pf);
        tess_t t;
        tess_new(&t, &pf.model);
        psc_surface_t s = tsup_surface_new(w, h, PSC_PIX_RGB565);
        double *z = malloc(w * h * sizeof *z), *zr = malloc(w * h * sizeof *zr);
        for (unsigned v = 0; v < 3; v++)
            for (unsigned ti = 0; ti < 2; ti++) {
                psc_patch_camera_t cam;
                int32_t nr, fr;
                double tol = ti ? 2.0 : 0.5, yaw = 40.0 + 110.0 * v, hfov = 50;
                /* both sides drawn: the reference has no culling (Thom's shirt is open below) */
                camera(&pf.model, yaw, 15 - 12.0 * v, k >= 2 ? 2.2 : 2.5, hfov, w, tol, 0, false, &cam, &nr, &fr);
                psc_patch_stats_t st;
                int action = k == 3 ? 1 : -1;
                frame(&t.p, action, 1100, &cam, &st);
                draw(&t.p, &cam, nr, fr, hfov, &s, z, false);
                psc_measure_surface_t ref;
                assert_int_equal(psc_measure_surface_build(&t.p, 5, &ref), 0);
                tsup_patch_raster((const double(*)[3])ref.pos, (const uint32_t(*)[3])ref.tri, ref.triangle_count,
                                  &cam.camera_from_object, hfov * M_PI / 180, w, h, zr);
                /* depth agrees within 0.01 R plus three times the chord error the tolerance allows there */
                unsigned both = 0, either = 0, near_depth = 0;
                double f = w / 2.0 / tan(hfov * M_PI / 360.0);
                for (size_t i = 0; i < (size_t)w * h; i++) {
                    bool a = !isinf(z[i]), b = !isinf(zr[i]);
                    both += a && b;
                    either += a || b;
                    near_depth += a && b && fabs(z[i] - zr[i]) <= 0.01 + 3.0 * tol * zr[i] / f;
                }
                double iou = (double)both / either, depth = (double)near_depth / both;
                worst_iou = fmin(worst_iou, iou);
                worst_depth = fmin(worst_depth, depth);
                if (iou < 0.98 || depth < 0.99) {
                    tsup_save_png(&s, "patch-reference.png");
                    fail_msg("%s (action %d) view %u at %.1f px: IoU %.4f, depth agrees at %.4f of pixels",
                             models[k], action, v, tol, iou, depth);
                }
                psc_measure_surface_free(&ref);
            }
        free(z);
        free(zr);
        tsup_surface_free(&s);
        tess_free(&t);
        psc_io_patch_free(&pf);
    }
    print_message("  24 views of 4 models: silhouette IoU >= %.4f, depth within 0.01 R + 3 chord errors at >= %.4f "
                  "of pixels\n",
                  worst_iou, worst_depth);
}

/* ---- animation -------------------------------------------------------------------------------------------- */

/* Two bones: a root and a child turning about its head; points owned by each and one weighted half-way. */
static void test_bone_moves_its_points(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 31);
    psc_patch_src_t s;
    random_mesh(&r, &s, false);
    s.bone_count = 2;
    s.bone = calloc(2, sizeof *s.bone);
    s.bone[0] = (psc_patch_bone_src_t){"root", -1, {0, 0, 0}, {0, 0, 0, 1}, 1.0};
    s.bone[1] = (psc_patch_bone_src_t){"arm", 0, {1.5, 1.0, 0}, {0, 0, 0, 1}, 1.0};
    s.skin = calloc(s.point_count, sizeof *s.skin);
    for (size_t i = 0; i < s.point_count; i++) {
        bool right = s.point[i][0] > 1.5;
        s.skin[i] = (psc_patch_skin_t){(uint16_t)(right ? 1 : 0), PSC_PATCH_NO_BONE, 0, 0};
        if (i == 1) /* one point weighted 25% to the arm */
            s.skin[i] = (psc_patch_skin_t){0, 1, 8192, 0};
    }
    /* an action turning the arm 90 degrees about z over one second */
    double angle = M_PI / 2;
    s.action_count = 1;
    s.action = calloc(1, sizeof *s.action);
    snprintf(s.action[0].name, sizeof s.action[0].name, "turn");
    s.action[0].duration = 2.0;
    s.action[0].chan_count = 1;
    s.action[0].chan = calloc(1, sizeof *s.action[0].chan);
    psc_patch_chan_src_t *c = &s.action[0].chan[0];
    c->target = 1;
    c->kind = PSC_PATCH_CHAN_ROTATE;
    c->count = 2;
    c->time = malloc(2 * sizeof *c->time);
    c->value = calloc(2, sizeof *c->value);
    c->time[0] = 0;
    c->time[1] = 1;
    c->value[0][3] = 1;
    c->value[1][2] = sin(angle / 2);
    c->value[1][3] = cos(angle / 2);
    uint8_t *buf;
    psc_patch_model_t m;
    pack_src(&s, &buf, &m);
    tess_t t;
    tess_new(&t, &m);
    psc_patch_pose(&t.p, 0, 1000);
    double cx = (s.lo[0] + s.hi[0]) / 2, cy = (s.lo[1] + s.hi[1]) / 2, cz = (s.lo[2] + s.hi[2]) / 2;
    double d2 = 0;
    for (unsigned a = 0; a < 3; a++)
        d2 += (s.hi[a] - s.lo[a]) * (s.hi[a] - s.lo[a]);
    double R = sqrt(d2) / 2;
    unsigned still = 0, turned = 0;
    for (uint32_t i = 0; i < m.point_count; i++) {
        const int32_t *rest = &m.rest_q16[3 * i];
        const int32_t *pos = t.p.pos[i];
        if (m.skin[i].bone0 == 0 && m.skin[i].bone1 == PSC_PATCH_NO_BONE) {
            /* the root does not move: bit for bit */
            assert_memory_equal(pos, rest, 12);
            still++;
            continue;
        }
        /* the arm turns about its head (1.5, 1.0, 0) in source units */
        double p[3] = {rest[0] / 65536.0 * R + cx, rest[1] / 65536.0 * R + cy, rest[2] / 65536.0 * R + cz};
        double dx = p[0] - 1.5, dy = p[1] - 1.0;
        double q[3] = {1.5 + dx * cos(angle) - dy * sin(angle), 1.0 + dx * sin(angle) + dy * cos(angle), p[2]};
        double w = m.skin[i].bone1 == 1 ? m.skin[i].w1_q15 / 32768.0 : 1.0;
        for (unsigned a = 0; a < 3; a++) {
            double want = (1 - w) * p[a] + w * q[a];
            double got = pos[a] / 65536.0 * R + (a == 0 ? cx : a == 1 ? cy : cz);
            if (fabs(got - want) > 4e-4 * R)
                fail_msg("point %u axis %u: %.6f, expected %.6f (weight %.3f)", (unsigned)i, a, got, want, w);
        }
        turned++;
    }
    print_message("  %u points kept bit for bit, %u turned (one weighted 25%%) within 4e-4 R\n", still, turned);
    assert_true(still > 0 && turned > 0);
    /* half-way: the channel interpolates */
    psc_patch_pose(&t.p, 0, 500);
    int32_t rot[4], tr[3];
    psc_patch_bone_pose(&t.p, 1, rot, tr);
    assert_true(rot[2] > 0 && rot[2] < (int32_t)lround(sin(angle / 2) * 1073741824.0));
    tess_free(&t);
    free(buf);
    psc_patch_src_free(&s);
}

/* Channel evaluation against a double Catmull-Rom through the same keys, at the fraction of the key interval
 * rounded to Q16.16 as the format documents (psc_am_curve_eval is the host's: the same spline, any time). */
static double ref_channel(const psc_patch_key_t *k, unsigned n, uint32_t t)
{
    if (t <= k[0].time_ms)
        return k[0].v[0] / 65536.0;
    if (t >= k[n - 1].time_ms)
        return k[n - 1].v[0] / 65536.0;
    unsigned i = 0;
    while (k[i + 1].time_ms <= t)
        i++;
    double span = k[i + 1].time_ms - k[i].time_ms, s = floor((t - k[i].time_ms) * 65536.0 / span + 0.5) / 65536.0;
    double v0 = k[i ? i - 1 : 0].v[0] / 65536.0, v1 = k[i].v[0] / 65536.0, v2 = k[i + 1].v[0] / 65536.0;
    double v3 = k[i + 2 < n ? i + 2 : i + 1].v[0] / 65536.0;
    return 0.5 * (2 * v1 + (v2 - v0) * s + (2 * v0 - 5 * v1 + 4 * v2 - v3) * s * s + (-v0 + 3 * v1 - 3 * v2 + v3) * s * s * s);
}

static void test_channel_eval(void **state)
{
    (void)state;
    tsup_rng_t r;
    tsup_rng_seed(&r, 41);
    psc_patch_key_t keys[12];
    psc_patch_channel_t ch = {0, PSC_PATCH_CHAN_TRANSLATE, 0, 0, 12};
    psc_patch_model_t m = {0};
    m.keys = keys;
    double worst = 0, worst_host = 0;
    for (unsigned n = 0; n < 2000; n++) {
        uint32_t t = 0;
        for (unsigned k = 0; k < 12; k++) {
            t += 1 + tsup_rng_below(&r, 400);
            keys[k].time_ms = t;
            keys[k].v[0] = (int32_t)lround(tsup_rng_range(&r, -50, 50) * 65536.0);
            keys[k].v[1] = keys[k].v[2] = keys[k].v[3] = 0;
        }
        psc_am_key_t ak[12];
        for (unsigned k = 0; k < 12; k++)
            ak[k] = (psc_am_key_t){keys[k].time_ms, keys[k].v[0] / 65536.0};
        psc_am_curve_t c = {"x", PSC_AM_CURVE_TRANSLATE, 0, ak, 12, 0};
        for (unsigned q = 0; q < 50; q++) {
            uint32_t at = tsup_rng_below(&r, t + 100);
            int32_t v[4];
            psc_patch_channel_eval(&m, &ch, at, v);
            worst = fmax(worst, fabs(v[0] / 65536.0 - ref_channel(keys, 12, at)));
            /* the host's evaluation (what actions are baked with) is the same spline */
            double s_err = 0.5 / 65536.0 * 4 * 100;   /* half a step of the fraction times |dv/ds| <= 4 x 100 */
            worst_host = fmax(worst_host, fabs(v[0] / 65536.0 - psc_am_curve_eval(&c, at)) - s_err);
        }
    }
    print_message("  100000 evaluations: within %.2e of the double Catmull-Rom\n", worst);
    assert_true(worst <= 3.0 / 65536.0);
    assert_true(worst_host <= 3.0 / 65536.0);
}

/* An action for bones a model lacks: the rest still plays, with a note; Wave on Thom moves the waving hand. */
static void test_action_by_bone_name(void **state)
{
    (void)state;
    char err[512], note[1024] = "";
    psc_am_model_t am;
    if (psc_am_model_load(THOM, &am, err, sizeof err) != 0)
        fail_msg("%s", err);
    static const char act_text[] =
        "<ACTIONFILE>\n<ACTIONS>\n<ACTION>\nFrames=1:0\n<OBJECTSHORTCUT>\nMatchName=Bones\n"
        "<OBJECTSHORTCUT>\nMatchName=Tail\n<EMPTYDRIVER>\nMatchName=Transform\n<QUATERNIONROTATEDRIVER>\n"
        "MatchName=Rotate\n<CHANNELDRIVER>\nMatchName=X\n<SPLINE>\n1 0 0\n1 15 50\n</SPLINE>\n</CHANNELDRIVER>\n"
        "</QUATERNIONROTATEDRIVER>\n</EMPTYDRIVER>\n</OBJECTSHORTCUT>\n"
        "<OBJECTSHORTCUT>\nMatchName=Head\n<EMPTYDRIVER>\nMatchName=Transform\n<QUATERNIONROTATEDRIVER>\n"
        "MatchName=Rotate\n<CHANNELDRIVER>\nMatchName=Y\n<SPLINE>\n1 0 0\n1 15 30\n1 1:0 0\n</SPLINE>\n"
        "</CHANNELDRIVER>\n</QUATERNIONROTATEDRIVER>\n</EMPTYDRIVER>\n</OBJECTSHORTCUT>\n"
        "</OBJECTSHORTCUT>\n</ACTION>\n</ACTIONS>\n</ACTIONFILE>\n";
    psc_am_action_t act;
    if (psc_am_action_parse("shake.act", act_text, sizeof act_text - 1, &act, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(act.curve_count, 2);
    psc_patch_src_t s;
    psc_patch_skin_opts_t skin = {0};
    assert_int_equal(psc_patch_from_am(&am, &skin, THOM, &s, NULL, 0, err, sizeof err), 0);
    assert_int_equal(psc_anim_sample_am_action(&act, &am, &s, note, sizeof note, err, sizeof err), 0);
    print_message("  note: %s\n", note);
    assert_non_null(strstr(note, "'Tail'"));
    assert_int_equal(s.action_count, 1);
    /* the head turns: a rotation channel for it, and the head's bone moves nothing else */
    int head = psc_patch_src_bone(&s, "Head");
    assert_true(head >= 0);
    bool head_turns = false;
    for (size_t c = 0; c < s.action[0].chan_count; c++)
        head_turns = head_turns || (s.action[0].chan[c].target == head && s.action[0].chan[c].kind == PSC_PATCH_CHAN_ROTATE);
    assert_true(head_turns);
    psc_am_action_free(&act);
    psc_patch_src_free(&s);
    psc_am_model_free(&am);

    /* Wave: Thom's left hand rises above his shoulders at 1.1 s, and the feet stay on the ground */
    psc_io_patch_t pf;
    load_thom(&pf);
    tess_t t;
    tess_new(&t, &pf.model);
    psc_patch_pose(&t.p, 1, 1100);
    int32_t top = INT32_MIN, low_rest = INT32_MAX, low_pose = INT32_MAX;
    for (uint32_t i = 0; i < pf.model.point_count; i++) {
        top = t.p.pos[i][1] > top ? t.p.pos[i][1] : top;
        low_pose = t.p.pos[i][1] < low_pose ? t.p.pos[i][1] : low_pose;
        low_rest = pf.model.rest_q16[3 * i + 1] < low_rest ? pf.model.rest_q16[3 * i + 1] : low_rest;
    }
    print_message("  Wave at 1.1 s: lowest point %.3f R (rest %.3f R)\n", low_pose / 65536.0, low_rest / 65536.0);
    assert_true(abs(low_pose - low_rest) < 65536 / 20);
    tess_free(&t);
    psc_io_patch_free(&pf);
}

/* Lazy re-evaluation: a moved point re-makes only the patches it touches, and the frame from cached patches is
 * the frame made afresh, bit for bit. */
static void moved_frame(psc_patch_t *p, const psc_patch_camera_t *cam, psc_patch_stats_t *st)
{
    psc_patch_pose(p, -1, 0);
    p->pos[100][0] += 2000;   /* as a muscle channel would */
    psc_patch_tangents(p);
    assert_int_equal(psc_patch_tessellate(p, cam, st), PSC_OK);
}

static void test_lazy(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    load_thom(&pf);
    tess_t a, b;
    tess_new(&a, &pf.model);
    psc_patch_camera_t cam;
    int32_t nr, fr;
    camera(&pf.model, 200, 10, 2.5, 50, 800, 0.5, 0, true, &cam, &nr, &fr);
    psc_patch_stats_t st;
    frame(&a.p, 1, 1000, &cam, &st);
    frame(&a.p, 1, 1000, &cam, &st);
    assert_int_equal(st.reused, st.patches);
    frame(&a.p, -1, 0, &cam, &st);
    moved_frame(&a.p, &cam, &st);
    print_message("  one point moved: %u of %u patches reused\n", (unsigned)st.reused, (unsigned)st.patches);
    assert_true(st.reused > 0 && st.reused + 24 >= st.patches && st.reused < st.patches);
    tess_new(&b, &pf.model);
    psc_patch_stats_t sb;
    moved_frame(&b.p, &cam, &sb);
    assert_int_equal(sb.reused, 0);
    assert_int_equal(sb.triangles, st.triangles);
    assert_int_equal(a.p.batch_count, b.p.batch_count);
    for (unsigned k = 0; k < a.p.batch_count; k++) {
        assert_int_equal(a.p.batch[k].vertex_count, b.p.batch[k].vertex_count);
        assert_memory_equal(a.p.batch[k].position_q16, b.p.batch[k].position_q16, 12u * a.p.batch[k].vertex_count);
        assert_memory_equal(a.p.batch[k].normal_q14, b.p.batch[k].normal_q14, 6u * a.p.batch[k].vertex_count);
        assert_memory_equal(a.p.batch[k].index, b.p.batch[k].index, 6u * a.p.batch[k].triangle_count);
    }
    assert_memory_equal(a.p.out_uv, b.p.out_uv, 4u * a.p.vtx_total);   /* the reused patches keep their places */
    tess_free(&a);
    tess_free(&b);
    psc_io_patch_free(&pf);
}

/* ---- importers and the pack ------------------------------------------------------------------------------- */


static void test_bpt_teapot(void **state)
{
    (void)state;
    size_t n;
    char *text = tsup_teapot_bpt(&n);
    assert_non_null(text);
    psc_patch_src_t s;
    char err[512];
    if (psc_bpt_parse("teapot.bpt", text, n, &s, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(s.face_count, 32);
    unsigned tri = 0;
    for (size_t f = 0; f < s.face_count; f++)
        tri += s.face[f].sides == 3;
    print_message("  teapot.bpt: 32 patches (%u three-sided: collapsed sides), %zu points, %zu edges\n", tri,
                  s.point_count, s.edge_count);
    uint8_t *buf;
    psc_patch_model_t m;
    pack_src(&s, &buf, &m);
    tess_t t;
    tess_new(&t, &m);
    for (unsigned v = 0; v < 4; v++) {
        psc_patch_camera_t cam;
        int32_t nr, fr;
        camera(&m, v * 90.0 + 20, 30 - 20.0 * v, 2.5, 50, 640, 0.5, 0, false, &cam, &nr, &fr);
        frame(&t.p, -1, 0, &cam, NULL);
        assert_int_equal(psc_measure_cracks(&t.p), 0);
    }
    /* truncated: a message with the line */
    for (size_t cut = 1; cut < n; cut += n / 37) {
        psc_patch_src_t bad;
        if (psc_bpt_parse("teapot.bpt", text, cut, &bad, err, sizeof err) == 0) {
            psc_patch_src_free(&bad);
            continue;
        }
        assert_true(strncmp(err, "teapot.bpt: line ", 17) == 0);
    }
    tess_free(&t);
    free(buf);
    psc_patch_src_free(&s);
    free(text);
}

/* The teapot's text with the patches that want (k) turned round: each one's 4 x 4 control points transposed, which
 * swaps u and v, so that it runs the other way. */
static char *teapot_turned(const char *text, size_t n, bool (*want)(unsigned k), size_t *out_len)
{
    char *end;
    const char *at = text;
    size_t len = 0;
    long count = strtol(at, &end, 10);
    assert_true(count > 0 && n > 0);
    char *out = malloc((size_t)count * (16u * 3u * 26u + 16u) + 32u);   /* 16 points of three %.17g a patch */
    assert_non_null(out);
    at = end;
    len += (size_t)sprintf(out + len, "%ld\n", count);
    for (long k = 0; k < count; k++) {
        double deg[2], cp[16][3];
        for (unsigned i = 0; i < 2; i++, at = end)
            deg[i] = strtod(at, &end);
        for (unsigned i = 0; i < 16; i++)
            for (unsigned a = 0; a < 3; a++, at = end)
                cp[i][a] = strtod(at, &end);
        len += (size_t)sprintf(out + len, "%g %g\n", deg[0], deg[1]);
        for (unsigned i = 0; i < 16; i++) {
            unsigned src = want((unsigned)k) ? (i % 4) * 4 + i / 4 : i;
            len += (size_t)sprintf(out + len, "%.17g %.17g %.17g\n", cp[src][0], cp[src][1], cp[src][2]);
        }
    }
    *out_len = len;
    return out;
}

static bool turn_none(unsigned k) { (void)k; return false; }
static bool turn_one(unsigned k) { return k == 5; }
static bool turn_three(unsigned k) { return k % 11 == 3; }
static bool turn_all(unsigned k) { (void)k; return true; }

/* Face f's normal by Newell's rule over its corners (the way it runs). */
static void face_newell(const psc_patch_src_t *s, size_t f, double n[3])
{
    const psc_patch_face_t *pf = &s->face[f];
    n[0] = n[1] = n[2] = 0;
    for (unsigned k = 0; k < pf->sides; k++) {
        const double *c[2];
        for (unsigned j = 0; j < 2; j++) {
            uint32_t e = pf->edge[(k + j) % pf->sides];
            const psc_patch_spline_t *sp = &s->spline[s->edge[e & ~PSC_PATCH_EDGE_REVERSED].spline];
            c[j] = s->point[s->cp[sp->first + ((e & PSC_PATCH_EDGE_REVERSED) ? 1u : 0u)].point];
        }
        n[0] += (c[0][1] - c[1][1]) * (c[0][2] + c[1][2]);
        n[1] += (c[0][2] - c[1][2]) * (c[0][0] + c[1][0]);
        n[2] += (c[0][0] - c[1][0]) * (c[0][1] + c[1][1]);
    }
}

/* A patch file whose patches run either way: each piece of the surface made to run one way, the way most of it runs
 * in the file. The teapot as it is (its pieces run one way already: nothing turned), with one patch turned round and
 * with three (each turned back), and with all of them (all kept so: which side is out is the file's). */
static void test_bpt_orientation(void **state)
{
    (void)state;
    size_t n;
    char *text = tsup_teapot_bpt(&n), err[512];
    psc_patch_src_t ref;
    if (psc_bpt_parse("teapot.bpt", text, n, &ref, err, sizeof err) != 0)
        fail_msg("%s", err);
    {   /* the file's own teapot runs as written: each patch's corners (control points 0, 3, 15, 12) go round the way
         * its face does */
        char *end;
        const char *at = text;
        long count = strtol(at, &end, 10);
        at = end;
        assert_int_equal(count, (long)ref.face_count);
        for (long k = 0; k < count; k++) {
            double cp[16][3], raw[3] = {0, 0, 0}, got[3];
            for (unsigned i = 0; i < 2; i++, at = end)
                (void)strtod(at, &end);
            for (unsigned i = 0; i < 16; i++)
                for (unsigned a = 0; a < 3; a++, at = end)
                    cp[i][a] = strtod(at, &end);
            static const unsigned corner[4] = {0, 3, 15, 12};
            for (unsigned q = 0; q < 4; q++) {
                const double *p = cp[corner[q]], *r = cp[corner[(q + 1) % 4]];
                raw[0] += (p[1] - r[1]) * (p[2] + r[2]);
                raw[1] += (p[2] - r[2]) * (p[0] + r[0]);
                raw[2] += (p[0] - r[0]) * (p[1] + r[1]);
            }
            face_newell(&ref, (size_t)k, got);
            assert_true(raw[0] * got[0] + raw[1] * got[1] + raw[2] * got[2] >= 0);
        }
    }
    bool (*const turns[])(unsigned) = {turn_none, turn_one, turn_three, turn_all};
    static const char *const names[] = {"no patch", "one patch", "three patches", "every patch"};
    for (unsigned c = 0; c < 4; c++) {
        size_t len;
        char *turned = teapot_turned(text, n, turns[c], &len);
        psc_patch_src_t s;
        if (psc_bpt_parse("turned.bpt", turned, len, &s, err, sizeof err) != 0)
            fail_msg("%s", err);
        assert_int_equal(s.face_count, ref.face_count);
        unsigned agree = 0, flat = 0;
        for (size_t f = 0; f < s.face_count; f++) {
            double a[3], b[3];
            face_newell(&ref, f, a);   /* (the file's own teapot, each patch as written: checked below) */
            face_newell(&s, f, b);
            double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            if (la < 1e-9) {   /* corners in a line (two of the spout's patches): no way round to compare */
                flat++;
                continue;
            }
            agree += a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0;
        }
        print_message("  %s turned round: %u of %zu patches run as the teapot's own (%u with their corners in a "
                      "line)\n", names[c], agree, s.face_count, flat);
        assert_int_equal(c == 3 ? agree : agree + flat, c == 3 ? 0 : s.face_count);
        assert_true(flat <= 2);
        psc_patch_src_free(&s);
        free(turned);
    }
    psc_patch_src_free(&ref);
    free(text);
}

/* Normals that face the way the surface does: a curve that turns more than a right angle (the teapot's knob in
 * profile, its handle and spout) keeps each vertex's normal on the side its triangles face. Every triangle of the
 * teapot and of Thom walking, finely tessellated, of area above 1e-7 R^2, whose corners' normals summed point
 * against its own normal: 133 of 5248 on the teapot, nearly all on the two patches at the spout's tip whose corners
 * lie in a line (1202 before: 193 of 234 on each of the knob's patches, 30-50 % on the handle's and the spout's);
 * 33 of 4489 on Thom. */
static void test_fold_normals(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    uint8_t *teapot = NULL;
    psc_patch_model_t tm;
    load_thom_and_teapot(&pf, &teapot, &tm);
    const psc_patch_model_t *models[2] = {&tm, &pf.model};
    for (unsigned k = 0; k < 2; k++) {
        tess_t t;
        tess_new(&t, models[k]);
        assert_int_equal(tsup_tess_fine(&t, k ? 0 : -1, 400), 0);
        const psc_patch_t *p = &t.p;
        unsigned against = 0, counted = 0;
        for (unsigned b = 0; b <= p->batch_count && b < PSC_PATCH_MAX_BATCHES; b++) {
            const psc_mesh_t *m = &p->batch[b];
            for (uint32_t i = 0; i < (b < p->batch_count ? m->triangle_count : 0u); i++) {
                double q[3][3], nsum[3] = {0, 0, 0}, u[3], w[3], g[3];
                for (unsigned c = 0; c < 3; c++)
                    for (unsigned a = 0; a < 3; a++) {
                        q[c][a] = m->position_q16[3 * m->index[3 * i + c] + a] / 65536.0;
                        nsum[a] += m->normal_q14[3 * m->index[3 * i + c] + a];
                    }
                for (unsigned a = 0; a < 3; a++)
                    u[a] = q[1][a] - q[0][a], w[a] = q[2][a] - q[0][a];
                g[0] = u[1] * w[2] - u[2] * w[1], g[1] = u[2] * w[0] - u[0] * w[2], g[2] = u[0] * w[1] - u[1] * w[0];
                if (sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) / 2 < 1e-7)
                    continue;
                counted++;
                against += g[0] * nsum[0] + g[1] * nsum[1] + g[2] * nsum[2] < 0;
            }
        }
        print_message("  %s: %u of %u triangles' normals point against them\n", k ? "Thom walking" : "the teapot",
                      against, counted);
        assert_true(counted > 1000);
        assert_true(k ? against * 100u <= counted : against * 100u <= 3u * counted);
        tess_free(&t);
    }
    free(teapot);
    psc_io_patch_free(&pf);
}

static char *read_text(const char *path, size_t *len)
{
    uint8_t *b = tsup_read_bytes(path, len);
    if (!b)
        fail_msg("cannot read %s", path);
    return (char *)b;
}

/* Up to six mutations of text[0..n): a byte replaced from junk, or the text cut short. The new length. */
static size_t mutate_text(tsup_rng_t *r, char *text, size_t n, const char *junk)
{
    unsigned muts = 1 + tsup_rng_below(r, 6);
    for (unsigned j = 0; j < muts; j++) {
        size_t at = tsup_rng_below(r, (uint32_t)n);
        if (tsup_rng_below(r, 5) == 0)
            n = at + 1;
        else
            text[at] = junk[tsup_rng_below(r, (uint32_t)strlen(junk))];
    }
    return n;
}

/* Mutated A:M models: parsed and built, or refused with "name:line: ..." or "name: ...". */
static void test_mdl_fuzz(void **state)
{
    (void)state;
    size_t len;
    char *orig = read_text(AM_DIR "8Patch_Sphere.mdl", &len);
    char *text = malloc(len + 64);
    tsup_rng_t r;
    tsup_rng_seed(&r, 51);
    unsigned built = 0, refused = 0;
    static const char junk[] = "<>=.|-0123456789eE \n\t:/x";
    for (unsigned k = 0; k < 600; k++) {
        memcpy(text, orig, len);
        size_t n = len;
        n = mutate_text(&r, text, n, junk);
        psc_am_model_t am;
        char err[512];
        if (psc_am_model_parse("fuzz.mdl", text, n, &am, err, sizeof err) != 0) {
            assert_true(strncmp(err, "fuzz.mdl", 8) == 0);
            refused++;
            continue;
        }
        psc_patch_src_t s;
        if (psc_patch_from_am(&am, NULL, "fuzz.mdl", &s, NULL, 0, err, sizeof err) == 0) {
            uint8_t *out;
            size_t olen;
            if (psc_bake_patch_pack(&s, "fuzz.mdl", &out, &olen, err, sizeof err) == 0) {
                free(out);
                built++;
            } else {
                assert_true(strncmp(err, "fuzz.mdl", 8) == 0);
                refused++;
            }
            psc_patch_src_free(&s);
        } else {
            assert_true(strncmp(err, "fuzz.mdl", 8) == 0);
            refused++;
        }
        psc_am_model_free(&am);
    }
    print_message("  600 mutated models: %u built, %u refused with a message\n", built, refused);
    assert_true(built > 0 && refused > 0);
    free(text);
    free(orig);
}

static void test_act_fuzz(void **state)
{
    (void)state;
    size_t len;
    char *orig = read_text(WAVE, &len);
    char *text = malloc(len + 64);
    char err[512];
    psc_am_model_t am;
    if (psc_am_model_load(THOM, &am, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_patch_src_t s;
    assert_int_equal(psc_patch_from_am(&am, NULL, THOM, &s, NULL, 0, err, sizeof err), 0);
    tsup_rng_t r;
    tsup_rng_seed(&r, 52);
    unsigned baked = 0, refused = 0;
    static const char junk[] = "<>=.|-0123456789eE \n\t:/x";
    for (unsigned k = 0; k < 300; k++) {
        memcpy(text, orig, len);
        size_t n = len;
        n = mutate_text(&r, text, n, junk);
        psc_am_action_t act;
        if (psc_am_action_parse("fuzz.act", text, n, &act, err, sizeof err) != 0) {
            assert_true(strncmp(err, "fuzz.act", 8) == 0);
            refused++;
            continue;
        }
        if (s.action_count < 4) {   /* bake a few: each adds an action */
            assert_int_equal(psc_anim_sample_am_action(&act, &am, &s, NULL, 0, err, sizeof err), 0);
            baked++;
        }
        psc_am_action_free(&act);
    }
    print_message("  300 mutated actions: %u refused with a message, %u baked\n", refused, baked);
    assert_true(refused > 0 && baked > 0);
    psc_patch_src_free(&s);
    psc_am_model_free(&am);
    free(text);
    free(orig);
}

static void fix_crc(uint8_t *b, size_t n)
{
    if (n < 24)
        return;
    tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, 0);
    tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, b, n));
}

/* Mutated patch packs: refused with a message naming the place, or parsed and drawn without harm. */
static void test_pack_fuzz(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    psc_bake_patch_opts_t o = {.actions = {WAVE}, .action_count = 1, .skin_from = THOM2, .quiet = true};
    load(THOM, &o, &pf);
    tsup_rng_t r;
    tsup_rng_seed(&r, 53);
    unsigned parsed = 0, refused = 0;
    for (unsigned k = 0; k < 3000; k++) {
        size_t n = pf.len;
        uint8_t *b;
        assert_int_equal(posix_memalign((void **)&b, 64, n), 0);
        memcpy(b, pf.buf, n);
        unsigned muts = 1 + tsup_rng_below(&r, 4);
        for (unsigned j = 0; j < muts; j++) {
            size_t at = tsup_rng_below(&r, (uint32_t)n);
            switch (tsup_rng_below(&r, 4)) {
            case 0: b[at] ^= (uint8_t)(1u << tsup_rng_below(&r, 8)); break;
            case 1: b[at] = (uint8_t)tsup_rng_u32(&r); break;
            case 2: b[tsup_rng_below(&r, 32 + 16 * 14)] = (uint8_t)tsup_rng_u32(&r); break;
            default: n = tsup_rng_below(&r, (uint32_t)n) + 1; break;
            }
        }
        if (tsup_rng_below(&r, 8) != 0)
            fix_crc(b, n);
        psc_patch_model_t m;
        psc_container_error_t e = {NULL, 0};
        if (psc_patch_parse(b, n, &m, &e) == PSC_OK) {
            parsed++;
            if (k % 10 == 0) {   /* draw some: posing and tessellating a parsed pack is safe */
                tess_t t;
                tess_new(&t, &m);
                psc_patch_camera_t cam;
                int32_t nr, fr;
                camera(&m, k * 7.0, 10, 2.5, 50, 320, 1.0, 0, true, &cam, &nr, &fr);
                psc_patch_pose(&t.p, m.action_count ? 0 : -1, k * 13u);
                psc_patch_tangents(&t.p);
                (void)psc_patch_tessellate(&t.p, &cam, NULL);
                tess_free(&t);
            }
        } else {
            assert_non_null(e.what);
            refused++;
        }
        free(b);
    }
    print_message("  3000 mutated packs: %u parsed, %u refused with a message\n", parsed, refused);
    assert_true(refused > 0);
    psc_io_patch_free(&pf);
}

/* ---- motion capture --------------------------------------------------------------------------------------- */

/* A small capture: hips travelling forward, the left thigh lifting 40 degrees about x over a second. */
static size_t make_bvh(char *text, size_t cap)
{
    size_t n = (size_t)snprintf(text, cap,
        "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation "
        "Yrotation\n  JOINT Spine\n  {\n    OFFSET 0 10 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n"
        "    End Site\n    {\n      OFFSET 0 10 0\n    }\n  }\n  JOINT LeftUpLeg\n  {\n    OFFSET 5 0 0\n"
        "    CHANNELS 3 Zrotation Xrotation Yrotation\n    JOINT LeftLeg\n    {\n      OFFSET 0 -20 0\n"
        "      CHANNELS 3 Zrotation Xrotation Yrotation\n      End Site\n      {\n        OFFSET 0 -20 0\n"
        "      }\n    }\n  }\n}\nMOTION\nFrames: 31\nFrame Time: 0.0333333333\n");
    for (unsigned f = 0; f <= 30; f++)
        n += (size_t)snprintf(text + n, cap - n, "0 40 %.3f 0 0 0 0 0 0 0 %.4f 0 0 0 0\n", f * 0.5, -40.0 * f / 30);
    return n;
}

static void test_bvh(void **state)
{
    (void)state;
    char text[8192], err[512], note[512] = "";
    size_t n = make_bvh(text, sizeof text);
    psc_bvh_t b;
    if (psc_bvh_parse("walk.bvh", text, n, &b, err, sizeof err) != 0)
        fail_msg("%s", err);
    assert_int_equal(b.joint_count, 4);
    assert_int_equal(b.channels, 15);
    assert_int_equal(b.frames, 31);
    psc_am_model_t am, donor;
    if (psc_am_model_load(THOM, &am, err, sizeof err) != 0 || psc_am_model_load(THOM2, &donor, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_patch_src_t s;
    psc_patch_skin_opts_t skin = {NULL, &donor};
    assert_int_equal(psc_patch_from_am(&am, &skin, THOM, &s, NULL, 0, err, sizeof err), 0);
    if (psc_anim_retarget_bvh(&b, NULL, "walk", &s, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    print_message("  note: %s\n", note);
    assert_non_null(strstr(note, "4 of the model's 52 bones"));
    int right_calf = psc_patch_src_bone(&s, "Right Calf"), left_calf = psc_patch_src_bone(&s, "Left Calf");
    uint8_t *buf;
    psc_patch_model_t m;
    pack_src(&s, &buf, &m);
    tess_t t;
    tess_new(&t, &m);
    psc_patch_pose(&t.p, 0, 990);
    /* the right leg only travels with the hips: one displacement for all its points; the left calf turns */
    int32_t d0[3] = {0, 0, 0};
    bool first = true;
    unsigned right = 0, left_turned = 0;
    for (uint32_t i = 0; i < m.point_count; i++) {
        int32_t d[3];
        for (unsigned k = 0; k < 3; k++)
            d[k] = t.p.pos[i][k] - m.rest_q16[3 * i + k];
        if (m.skin[i].bone0 == right_calf && m.skin[i].bone1 == PSC_PATCH_NO_BONE) {
            if (first)
                memcpy(d0, d, sizeof d0);
            first = false;
            for (unsigned k = 0; k < 3; k++)
                assert_true(abs(d[k] - d0[k]) <= 4);
            right++;
        } else if (m.skin[i].bone0 == left_calf) {
            double dd = 0;
            for (unsigned k = 0; k < 3; k++)
                dd += ((double)d[k] - d0[k]) * ((double)d[k] - d0[k]);
            left_turned += sqrt(dd) > 0.05 * 65536;
        }
    }
    print_message("  at 0.99 s: %u right-calf points travelled alike (%.3f R forward), %u left-calf points turned\n",
                  right, d0[2] / 65536.0, left_turned);
    assert_true(right > 0 && left_turned > 0);
    assert_true(d0[2] > 65536 / 20 && abs(d0[0]) < 100 && abs(d0[1]) < 100);
    /* a map that names nothing the model has is refused */
    assert_int_equal(psc_anim_retarget_bvh(&b, "Hips = Tail\n", "walk", &s, NULL, 0, err, sizeof err), -1);
    assert_non_null(strstr(err, "no joint maps"));
    assert_int_equal(psc_anim_retarget_bvh(&b, "Hips Tail\n", "walk", &s, NULL, 0, err, sizeof err), -1);
    assert_non_null(strstr(err, "map line 1"));
    /* mutated and truncated captures: a message with the line, or a capture */
    tsup_rng_t r;
    tsup_rng_seed(&r, 61);
    unsigned ok = 0;
    static const char junk[] = "{}-.0123456789 \nXYZ:";
    for (unsigned k = 0; k < 3000; k++) {
        char mut[8192];
        memcpy(mut, text, n);
        size_t len = n;
        unsigned muts = 1 + tsup_rng_below(&r, 4);
        for (unsigned j = 0; j < muts; j++) {
            size_t at = tsup_rng_below(&r, (uint32_t)len);
            if (tsup_rng_below(&r, 4) == 0)
                len = at + 1;
            else
                mut[at] = junk[tsup_rng_below(&r, sizeof junk - 1)];
        }
        psc_bvh_t fb;
        if (psc_bvh_parse("fuzz.bvh", mut, len, &fb, err, sizeof err) == 0) {
            ok++;
            psc_bvh_free(&fb);
        } else {
            assert_true(strncmp(err, "fuzz.bvh: line ", 15) == 0);
        }
    }
    print_message("  3000 mutated captures: %u parsed, the rest refused with file and line\n", ok);
    tess_free(&t);
    free(buf);
    psc_patch_src_free(&s);
    psc_am_model_free(&am);
    psc_am_model_free(&donor);
    psc_bvh_free(&b);
}

/* ---- the firmware's character scene ----------------------------------------------------------------------- */

static void test_character_scene(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    load_thom(&pf);
    psc_surface_t s = tsup_surface_new(320, 240, PSC_PIX_RGB565);
    size_t ws_size = psc_scene_character_workspace_size(&pf.model, NULL, 320, 240, NULL);
    void *ws;
    assert_true(ws_size > 0);
    assert_int_equal(posix_memalign(&ws, 64, ws_size), 0);
    psc_view_t view = {.yaw = PSC_CHARACTER_HOME_YAW, .pitch = PSC_CHARACTER_HOME_PITCH,
                       .hfov = tsup_bam_from_deg(50)};
    uint32_t sum[3] = {0, 0, 0};
    for (unsigned k = 0; k < 3; k++) {
        psc_patch_stats_t st;
        assert_int_equal(psc_scene_character_draw(&pf.model, NULL, 0, k * 300u, &view, k == 0, ws, ws_size, &s, &st, NULL),
                         PSC_OK);
        assert_int_equal(st.patches + st.culled, 392);
        const uint16_t *px = s.pixels;
        for (size_t i = 0; i < 320u * 240u; i++)
            sum[k] += px[i] != px[0];
    }
    /* something is drawn, and it moves */
    assert_true(sum[0] > 2000 && sum[0] != sum[1] && sum[1] != sum[2]);
    assert_int_equal(psc_scene_character_draw(&pf.model, NULL, 0, 0, &view, true, ws, ws_size - 1, &s, NULL, NULL),
                     PSC_ERR_NOMEM);
    /* The board's look (scene_3d.h): the A-buffer's budget in the workspace; 40-pixel tiles with 64 KB a tile give
     * the full screen's anti-aliased frame byte for byte, which differs from the plain one along edges (the
     * quality is test_3d_abuffer's). */
    psc_surface_t plain = tsup_surface_new(320, 240, PSC_PIX_RGB565), aa = tsup_surface_new(320, 240, PSC_PIX_RGB565);
    assert_int_equal(psc_scene_character_draw(&pf.model, NULL, 0, 600, &view, true, ws, ws_size, &plain, NULL, NULL),
                     PSC_OK);
    free(ws);
    char err[256];
    psc_io_bands_t *pool = psc_io_bands_start(3, 320, err, sizeof err);
    assert_non_null(pool);
    /* on the device's threads (render_threads): the same bytes, full screen in bands and anti-aliased in tiles */
    psc_scene3d_look_t threaded = {.pool = pool};
    size_t tn = psc_scene_character_workspace_size(&pf.model, NULL, 320, 240, &threaded);
    assert_true(tn > ws_size);
    assert_int_equal(posix_memalign(&ws, 64, tn), 0);
    assert_int_equal(psc_scene_character_draw(&pf.model, NULL, 0, 600, &view, true, ws, tn, &s, NULL, &threaded),
                     PSC_OK);
    assert_memory_equal(plain.pixels, s.pixels, (size_t)s.stride * s.height);
    free(ws);
    const psc_scene3d_look_t looks[3] = {{.tile = 0, .abuffer_bytes = 2u << 20},
                                         {.tile = 40, .abuffer_bytes = 64u << 10},
                                         {.tile = 40, .abuffer_bytes = 64u << 10, .pool = pool}};
    for (unsigned l = 0; l < 3; l++) {
        size_t n = psc_scene_character_workspace_size(&pf.model, NULL, 320, 240, &looks[l]);
        assert_true(n >= (l == 0 ? ws_size : 0) + looks[l].abuffer_bytes);
        assert_int_equal(posix_memalign(&ws, 64, n), 0);
        assert_int_equal(psc_scene_character_draw(&pf.model, NULL, 0, 600, &view, true, ws, n - 1, &s, NULL, &looks[l]),
                         PSC_ERR_NOMEM);
        assert_int_equal(psc_scene_character_draw(&pf.model, NULL, 0, 600, &view, true, ws, n, &s, NULL, &looks[l]),
                         PSC_OK);
        if (l == 0)
            memcpy(aa.pixels, s.pixels, (size_t)s.stride * s.height);
        else
            assert_memory_equal(aa.pixels, s.pixels, (size_t)s.stride * s.height);
        free(ws);
    }
    const uint16_t *p0 = plain.pixels, *p1 = aa.pixels;
    size_t changed = 0, drawn = 0;
    for (size_t i = 0; i < 320u * 240u; i++) {
        changed += p0[i] != p1[i];
        drawn += p0[i] != p0[0];
    }
    print_message("  the A-buffer changed %zu of the %zu pixels drawn (edges and creases); on 3 threads the same "
                  "bytes\n", changed, drawn);
    assert_true(changed > 200 && changed < drawn / 4);
    psc_io_bands_stop(pool);

    tsup_surface_free(&plain);
    tsup_surface_free(&aa);
    tsup_surface_free(&s);
    psc_io_patch_free(&pf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_curve_split),
        cmocka_unit_test(test_flatness_bound),
        cmocka_unit_test(test_split_test_at_range_limits),
        cmocka_unit_test(test_make_flat),
        cmocka_unit_test(test_cracks_random),
        cmocka_unit_test(test_crack_counter_fires),
        cmocka_unit_test(test_cracks_thom),
        cmocka_unit_test(test_closed_no_holes),
        cmocka_unit_test(test_chord_error),
        cmocka_unit_test(test_reference),
        cmocka_unit_test(test_vertex_uv),
        cmocka_unit_test(test_bone_moves_its_points),
        cmocka_unit_test(test_channel_eval),
        cmocka_unit_test(test_action_by_bone_name),
        cmocka_unit_test(test_lazy),
        cmocka_unit_test(test_bvh),
        cmocka_unit_test(test_bpt_teapot),
        cmocka_unit_test(test_bpt_orientation),
        cmocka_unit_test(test_fold_normals),
        cmocka_unit_test(test_mdl_fuzz),
        cmocka_unit_test(test_act_fuzz),
        cmocka_unit_test(test_pack_fuzz),
        cmocka_unit_test(test_character_scene),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
