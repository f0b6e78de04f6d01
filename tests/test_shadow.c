/* SPDX-License-Identifier: MIT */
/*
 * test_shadow.c - self-shadowing from sphere-occluder tables (core/shadow/,
 * host_tools/lib/bake/shadow.c):
 *  - the accessibility map against its closed form (a sphere wholly above
 *    the horizon occludes cos(omega) sin^2(alpha) of the cosine-weighted
 *    hemisphere), monotone in both coordinates; the composite arc map:
 *    coincident caps are one, caps apart add, symmetric;
 *  - the run time: two coincident spheres occlude exactly as one, two far
 *    apart add; the bent normal against a ray-cast mean open direction;
 *  - against ray-cast ambient occlusion (256 cosine-weighted rays a vertex on
 *    the posed tessellation): per-vertex correlation and mean absolute
 *    error of what the frame shows on Thom in three poses (goal 0.85) and
 *    the teapot; the tree against one level; each vertex composing its own;
 *    no seams between patches;
 *  - animation: Thom's armpits darken as his arms come down;
 *  - fuzzed and truncated shadow packs are refused with a message.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "psc_testsupport.h"
#include "tsup_files.h"
#include "tsup_patch.h"
#include "measure/raycast.h"
#include "tsup_teapot.h"

#include "import/bpt.h"
#include "import/gltf_model.h"
#include "import/patch_source.h"
#include "bake/patch_any.h"
#include "measure/patch.h"
#include "bake/shadow.h"
#include "bake/shadow_grid.h"
#include "shadow/psc_shadow_frame.h"
#include "psc_io_container_write.h"
#include "base/psc_crc32.h"
#include "3d/psc_3d_orbit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define THOM TSUP_THOM_DIR "Thom.mdl"

/* ---- the maps --------------------------------------------------------------------------------------------- */

static void test_access_closed_form(void **state)
{
    (void)state;
    double worst = 0;
    unsigned checked = 0;
    for (unsigned i = 0; i <= 20; i++)
        for (unsigned j = 1; j <= 20; j++) {
            double omega = M_PI / 2 * i / 20, theta = 2 * M_PI * j / 20, alpha = acos(1 - theta / (2 * M_PI));
            double area, angle;
            psc_bake_shadow_access_cell(omega, theta, 64, &area, &angle);
            if (omega + alpha <= M_PI / 2) {   /* wholly above the horizon */
                double want = cos(omega) * sin(alpha) * sin(alpha);
                worst = fmax(worst, fabs(area - want));
                checked++;
                assert_true(fabs(area - want) <= 1e-14);
            }
            assert_true(area >= 0 && area <= 1.0 + 1e-9);
        }
    print_message("  %u cells above the horizon within %.2e of cos(omega) sin^2(alpha)\n", checked, worst);
    /* monotone: more sphere, more occlusion; further from the normal, less */
    for (unsigned i = 0; i <= 12; i++) {
        double prev = -1;
        for (unsigned j = 0; j <= 12; j++) {
            double area, angle;
            psc_bake_shadow_access_cell(M_PI * i / 12, 2 * M_PI * j / 12, 32, &area, &angle);
            assert_true(area >= prev - 1e-3);
            prev = area;
        }
    }
    for (unsigned j = 1; j <= 12; j++) {
        double prev = 2;
        for (unsigned i = 0; i <= 12; i++) {
            double area, angle;
            psc_bake_shadow_access_cell(M_PI * i / 12, 2 * M_PI * j / 12, 32, &area, &angle);
            assert_true(area <= prev + 1e-3);
            prev = area;
        }
    }
}

static void test_composite_map(void **state)
{
    (void)state;
    for (unsigned a = 1; a <= 8; a++) {
        double t = 2 * M_PI * a / 16, t3, phi;
        /* coincident caps are one cap */
        psc_bake_shadow_composite_cell(t, t, 0.0, 48, &t3, &phi);
        assert_true(fabs(t3 - t) <= 0.01 * t + 1e-9);
        assert_true(fabs(phi) <= 1e-6);
        /* caps that do not meet add */
        double alpha = acos(1 - t / (2 * M_PI));
        if (2 * alpha < M_PI * 0.9) {
            psc_bake_shadow_composite_cell(t, t, 2 * alpha + 0.05, 48, &t3, &phi);
            assert_true(fabs(t3 - fmin(2 * t, 2 * M_PI)) <= 1e-6);
            /* two equal caps: the union's centre halfway */
            assert_true(fabs(phi - (alpha + 0.025)) <= 0.02);
        }
        /* symmetric in its two caps' areas */
        for (unsigned b = 1; b <= 8; b++) {
            double u = 2 * M_PI * b / 16, x, y, p1, p2;
            psc_bake_shadow_composite_cell(t, u, 0.4, 48, &x, &p1);
            psc_bake_shadow_composite_cell(u, t, 0.4, 48, &y, &p2);
            assert_true(fabs(x - y) <= 0.02 * fmax(x, y) + 1e-9);
        }
    }
}

/* ---- the run time on hand-made spheres -------------------------------------------------------------------- */

typedef struct {
    uint8_t *buf;
    psc_shadow_model_t m;
    psc_shadow_t s;
    void *ws;
} shadow_fixture_t;

static psc_patch_model_t no_bones;

static void fixture(shadow_fixture_t *f, const psc_shadow_sphere_t *sph, size_t n)
{
    uint16_t level_first[PSC_SHADOW_MAX_LEVELS] = {0};
    size_t len;
    char err[256];
    if (psc_bake_shadow_write(sph, n, 1, level_first, 0, 32, "fixture", &f->buf, &len, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_container_error_t e = {0};
    assert_int_equal(psc_shadow_parse(f->buf, len, &f->m, &e), PSC_OK);
    f->ws = malloc(psc_shadow_workspace_size(&f->m, &no_bones) + 8);
    assert_int_equal(psc_shadow_init(&f->s, &f->m, &no_bones, f->ws, psc_shadow_workspace_size(&f->m, &no_bones)), PSC_OK);
}

static void fixture_free(shadow_fixture_t *f)
{
    free(f->buf);
    free(f->ws);
}

static psc_shadow_sphere_t ball(double x, double y, double z, double r)
{
    psc_shadow_sphere_t s = {{(int32_t)lround(x * 65536), (int32_t)lround(y * 65536), (int32_t)lround(z * 65536)},
                             (int32_t)lround(r * 65536), PSC_SHADOW_NO_CHILD, 0, 0, PSC_SHADOW_NO_BONE,
                             PSC_SHADOW_NO_BONE, 0, 0};
    return s;
}

static void test_overlap(void **state)
{
    (void)state;
    const int32_t origin[3] = {0, 0, 0}, up[3] = {0, 65536, 0};
    shadow_fixture_t one, two, apart, single_b;
    psc_shadow_sphere_t a = ball(0.3, 1.0, 0.0, 0.4), b = ball(-0.6, 0.8, 0.3, 0.3);
    psc_shadow_sphere_t same[2] = {a, a}, far[2] = {a, b};
    fixture(&one, &a, 1);
    fixture(&two, same, 2);
    fixture(&apart, far, 2);
    fixture(&single_b, &b, 1);
    uint32_t o1 = psc_shadow_occlusion(&one.s, origin, up), o2 = psc_shadow_occlusion(&two.s, origin, up);
    uint32_t ob = psc_shadow_occlusion(&single_b.s, origin, up), oab = psc_shadow_occlusion(&apart.s, origin, up);
    print_message("  one sphere %.4f, the same twice %.4f; apart: %.4f + %.4f -> %.4f\n", o1 / 65536.0, o2 / 65536.0,
                  o1 / 65536.0, ob / 65536.0, oab / 65536.0);
    assert_true(o1 > 1000);
    assert_true(abs((int)o2 - (int)o1) <= 2);   /* coincident spheres occlude exactly as one */
    assert_true(abs((int)oab - (int)(o1 + ob)) <= 2);   /* far-apart spheres add */
    /* the bent normal leans away from the sphere, as the mean open direction of a ray-cast hemisphere does */
    int32_t bent[3];
    psc_shadow_occlusion_bent(&one.s, origin, up, bent);
    double ref[3] = {0, 0, 0}, c[3] = {0.3, 1.0, 0.0};
    for (unsigned i = 0; i < 256; i++)
        for (unsigned j = 0; j < 256; j++) {   /* cosine-weighted directions about y */
            double u = (i + 0.5) / 256, ph = 2 * M_PI * (j + 0.5) / 256, r = sqrt(u);
            double dir[3] = {r * cos(ph), sqrt(1 - u), r * sin(ph)};
            double along = dir[0] * c[0] + dir[1] * c[1] + dir[2] * c[2], cc = c[0] * c[0] + c[1] * c[1];
            if (along > 0 && along * along - (cc - 0.4 * 0.4) >= 0)
                continue;   /* blocked */
            for (unsigned k = 0; k < 3; k++)
                ref[k] += dir[k];
        }
    double rl = sqrt(ref[0] * ref[0] + ref[1] * ref[1] + ref[2] * ref[2]), dotb = 0;
    for (unsigned k = 0; k < 3; k++)
        dotb += ref[k] / rl * bent[k] / 65536.0;
    double err_deg = acos(fmin(1.0, dotb)) * 180 / M_PI, lean_deg = acos(ref[1] / rl) * 180 / M_PI;
    print_message("  bent normal (%.3f, %.3f, %.3f): %.2f degrees from the ray-cast mean open direction, which leans "
                  "%.2f degrees\n", bent[0] / 65536.0, bent[1] / 65536.0, bent[2] / 65536.0, err_deg, lean_deg);
    assert_true(bent[0] < 0 && abs(bent[2]) < 64);
    assert_true(err_deg < 0.25 * lean_deg);
    int32_t open_bent[3];
    psc_shadow_occlusion_bent(&one.s, origin, (const int32_t[3]){0, -65536, 0}, open_bent);
    assert_true(open_bent[1] == -65536 && open_bent[0] == 0 && open_bent[2] == 0);   /* nothing over it: n itself */
    /* against the closed form for the lone sphere: above the horizon, cos(omega) sin^2(alpha) */
    double d = sqrt(0.3 * 0.3 + 1.0), want = (1.0 / d) * (0.4 / d) * (0.4 / d);
    assert_true(fabs(o1 / 65536.0 - want) <= 0.01);
    fixture_free(&one);
    fixture_free(&two);
    fixture_free(&apart);
    fixture_free(&single_b);
}

/* ---- against ray-cast AO ---------------------------------------------------------------------------------- */

/* The reference (docs/characters.md, "What occlusion means": unbounded, both sides of the triangles blocking,
 * about the smooth normal) on 20 x 20 rays: not the bake's 16 x 16 grid, so its rest correction is measured
 * against rays it never cast. */
static double reference(const psc_measure_bvh_t *bvh, const double p[3], const double n[3])
{
    return psc_measure_ao(bvh, p, n, 20, 1e-4, INFINITY);
}

/* The frame's triangles as one mesh in double (all faces: culling off). */
static void frame_mesh(const psc_patch_t *p, double (**pos)[3], size_t *nv, uint32_t (**tri)[3], size_t *nt)
{
    size_t v = 0, t = 0;
    for (unsigned b = 0; b < p->batch_count; b++) {
        v += p->batch[b].vertex_count;
        t += p->batch[b].triangle_count;
    }
    *pos = malloc(v * sizeof **pos);
    *tri = malloc(t * sizeof **tri);
    size_t vb = 0, tb = 0;
    for (unsigned b = 0; b < p->batch_count; b++) {
        const psc_mesh_t *m = &p->batch[b];
        for (uint32_t i = 0; i < m->vertex_count; i++)
            for (unsigned k = 0; k < 3; k++)
                (*pos)[vb + i][k] = m->position_q16[3 * i + k] / 65536.0;
        for (uint32_t i = 0; i < m->triangle_count; i++)
            for (unsigned k = 0; k < 3; k++)
                (*tri)[tb + i][k] = (uint32_t)(vb + m->index[3 * i + k]);
        vb += m->vertex_count;
        tb += m->triangle_count;
    }
    *nv = v;
    *nt = t;
}

typedef struct {
    double corr, mae;          /* buried vertices left out */
    double corr_all, mae_all;  /* every vertex compared */
    double mean, ref_mean;           /* the product's and the reference's mean occlusion, buried left out */
    double mean_all, ref_mean_all;   /* the same, every vertex compared */
    unsigned compared, buried; /* vertices compared, and of them buried */
    unsigned unnormed;         /* vertices without a normal, left out before comparing */
} accuracy_t;

/* Correlation and mean absolute error over pairs (x: the product, y: the ray-cast reference). */
typedef struct {
    double sx, sy, sxx, syy, sxy, sad;
    unsigned n;
} pairs_t;

static void pairs_add(pairs_t *s, double x, double y)
{
    s->sx += x, s->sy += y, s->sxx += x * x, s->syy += y * y, s->sxy += x * y, s->sad += fabs(x - y);
    s->n++;
}

static void pairs_result(const pairs_t *s, double *corr, double *mae)
{
    double n = s->n, cov = s->sxy / n - s->sx / n * s->sy / n;
    double vx = s->sxx / n - s->sx / n * s->sx / n, vy = s->syy / n - s->sy / n * s->sy / n;
    *corr = cov / sqrt(vx * vy);
    *mae = s->sad / n;
}

/* Both figures from the pairs, without and with the buried vertices. */
static accuracy_t accuracy_of(const pairs_t *open, const pairs_t *all)
{
    accuracy_t a = {0};
    pairs_result(open, &a.corr, &a.mae);
    pairs_result(all, &a.corr_all, &a.mae_all);
    a.mean = open->sx / open->n;
    a.ref_mean = open->sy / open->n;
    a.mean_all = all->sx / all->n;
    a.ref_mean_all = all->sy / all->n;
    a.compared = all->n;
    a.buried = all->n - open->n;
    return a;
}

/* The frame's occlusion (occ, per vertex) against ray-cast AO over every 7th vertex of p's frame; vertices every
 * ray of which is blocked are buried inside another part of the body (Thom's arm passes through his shirt as he
 * walks: the model's own), nobody sees them, and the first figures leave them out; the second include them. */
static accuracy_t compare(const psc_patch_t *p, const uint32_t *occ, const psc_measure_bvh_t *bvh)
{
    pairs_t open = {0}, all = {0};
    unsigned unnormed = 0;
    for (uint32_t i = 0; i < p->vtx_total; i += 7) {
        int32_t nq[3] = {p->out_nrm[3 * i] * 4, p->out_nrm[3 * i + 1] * 4, p->out_nrm[3 * i + 2] * 4};
        double x = occ[i] / 65536.0;
        double pp[3], nn[3];
        for (unsigned k = 0; k < 3; k++) {
            pp[k] = p->out_pos[3 * i + k] / 65536.0;
            nn[k] = nq[k] / 65536.0;
        }
        double l = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
        if (l < 0.5) {
            unnormed++;   /* no normal to cast rays about (a degenerate spot): left out, counted */
            continue;
        }
        for (unsigned k = 0; k < 3; k++)
            nn[k] /= l;
        double y = reference(bvh, pp, nn);
        pairs_add(&all, x, y);
        if (y < 1.0)
            pairs_add(&open, x, y);
    }
    accuracy_t a = accuracy_of(&open, &all);
    a.unnormed = unnormed;
    return a;
}

/* The figures the asserts read: over every vertex compared when a rest correction covers the model (it makes a
 * vertex buried in every pose dark: the product is asked for the inside too), else over the open ones (the
 * spheres alone know no inside); and how many vertices that leaves out (those without a normal, and the buried). */
typedef struct {
    double corr, mae, mean, ref_mean;
    unsigned left_out, sampled;
} figures_t;

static figures_t figures_of(const accuracy_t *a, bool with_buried)
{
    figures_t f = {with_buried ? a->corr_all : a->corr, with_buried ? a->mae_all : a->mae,
                   with_buried ? a->mean_all : a->mean, with_buried ? a->ref_mean_all : a->ref_mean,
                   a->unnormed + (with_buried ? 0u : a->buried), a->compared + a->unnormed};
    return f;
}

/* The figures' left-out vertices: say how many, and at most max_share of those sampled. */
static void print_left_out(const char *label, const accuracy_t *a, const figures_t *f, double max_share)
{
    print_message("  %-20s %u of %u vertices left out (%.2f %%; %u buried, %s; %u without a normal); buried left out: "
                  "correlation %.3f, mean abs error %.3f; every vertex: %.3f, %.3f\n", label, f->left_out, f->sampled,
                  100.0 * f->left_out / f->sampled, a->buried, f->left_out > a->unnormed ? "left out" : "compared",
                  a->unnormed, a->corr, a->mae, a->corr_all, a->mae_all);
    assert_true(f->left_out <= max_share * f->sampled);
}

static int cmp_vertex(const void *a, const void *b)
{
    const int32_t *x = a, *y = b;
    for (unsigned k = 0; k < 3; k++)
        if (x[k] != y[k])
            return x[k] < y[k] ? -1 : 1;
    return 0;
}

/* Vertices at the same place (on an edge two patches share): how many, how many of them disagree on the occlusion
 * by more than 1/100, and the largest difference. */
typedef struct {
    uint32_t shared, disagree;
    double worst;
} seams_t;

static seams_t seams(const psc_patch_t *p, const uint32_t *occ)
{
    int32_t (*v)[4] = malloc(p->vtx_total * sizeof *v);
    assert_non_null(v);
    for (uint32_t i = 0; i < p->vtx_total; i++) {
        for (unsigned k = 0; k < 3; k++)
            v[i][k] = p->out_pos[3 * i + k];
        v[i][3] = (int32_t)occ[i];
    }
    qsort(v, p->vtx_total, sizeof *v, cmp_vertex);
    seams_t r = {0, 0, 0.0};
    for (uint32_t i = 1; i < p->vtx_total; i++)
        if (cmp_vertex(v[i - 1], v[i]) == 0) {
            uint32_t d = (uint32_t)abs(v[i][3] - v[i - 1][3]);
            r.worst = d / 65536.0 > r.worst ? d / 65536.0 : r.worst;
            r.shared++;
            r.disagree += d > 655;
        }
    free(v);
    return r;
}

/* Thom's and the teapot's packs: the product's (the tree of spheres and its rest correction), the tree alone and one
 * level alone (the seed's). */
typedef struct {
    psc_shadow_model_t product, tree, single;
    uint8_t *buf[3];
} packs_t;

static void shade_and_compare(const char *label, const psc_patch_model_t *m, const packs_t *pk, int action,
                              uint32_t ms, double min_corr, double max_mae, double max_left_out)
{
    tsup_tess_t t;
    assert_int_equal(tsup_tess_new(&t, m), 0);
    assert_int_equal(tsup_tess_fine(&t, action, ms), 0);
    double (*pos)[3];
    uint32_t (*tri)[3];
    size_t nv, nt;
    frame_mesh(&t.p, &pos, &nv, &tri, &nt);
    psc_measure_bvh_t *bvh = psc_measure_bvh_new((const double(*)[3])pos, nv, (const uint32_t(*)[3])tri, nt);
    assert_non_null(bvh);
    const psc_shadow_model_t *sm = &pk->product, *tree = &pk->tree, *single = &pk->single;
    psc_shadow_t s, st, s1;
    void *ws = malloc(psc_shadow_workspace_size(sm, m) + 8), *wst = malloc(psc_shadow_workspace_size(tree, m) + 8);
    void *ws1 = malloc(psc_shadow_workspace_size(single, m) + 8);
    assert_int_equal(psc_shadow_init(&s, sm, m, ws, psc_shadow_workspace_size(sm, m)), PSC_OK);
    assert_int_equal(psc_shadow_init(&st, tree, m, wst, psc_shadow_workspace_size(tree, m)), PSC_OK);
    assert_int_equal(psc_shadow_init(&s1, single, m, ws1, psc_shadow_workspace_size(single, m)), PSC_OK);
    /* the product without its correction through each action: the rest correction alone, as a frame posed by hand */
    psc_shadow_model_t avg_model = *sm;
    avg_model.phase_q15 = NULL;
    avg_model.phase_actions = avg_model.phase_samples = 0;
    psc_shadow_t sa;
    void *wsa = malloc(psc_shadow_workspace_size(&avg_model, m) + 8);
    assert_int_equal(psc_shadow_init(&sa, &avg_model, m, wsa, psc_shadow_workspace_size(&avg_model, m)), PSC_OK);
    psc_shadow_update(&s, &t.p);
    psc_shadow_update(&st, &t.p);
    psc_shadow_update(&s1, &t.p);
    psc_shadow_update(&sa, &t.p);
    /* what the frame shows (spheres chosen and composed once a patch): the product, the tree alone, one level; and
     * each vertex choosing and composing its own spheres (psc_shadow_occlusion, the seed's way) */
    uint32_t *frame = malloc(t.p.vtx_total * sizeof *frame), *frame1 = malloc(t.p.vtx_total * sizeof *frame1);
    uint32_t *own = malloc(t.p.vtx_total * sizeof *own), *frame_t = malloc(t.p.vtx_total * sizeof *frame_t);
    uint32_t *frame_a = malloc(t.p.vtx_total * sizeof *frame_a);
    assert_true(frame && frame1 && own && frame_t && frame_a);
    for (uint32_t i = 0; i < t.p.vtx_total; i++) {
        int32_t nq[3] = {t.p.out_nrm[3 * i] * 4, t.p.out_nrm[3 * i + 1] * 4, t.p.out_nrm[3 * i + 2] * 4};
        own[i] = psc_shadow_occlusion(&s, &t.p.out_pos[3 * i], nq);
    }
    /* (each shades the frame and bends its normals: the second and the comparisons start from the normals as
     * tessellated) */
    size_t nbytes = 3u * t.p.vtx_total * sizeof *t.p.out_nrm;
    int16_t *normals = malloc(nbytes);
    assert_non_null(normals);
    memcpy(normals, t.p.out_nrm, nbytes);
    psc_shadow_apply(&s1, &t.p, PSC_SHADOW_STRENGTH_Q16, frame1);
    memcpy(t.p.out_nrm, normals, nbytes);
    psc_shadow_apply(&st, &t.p, PSC_SHADOW_STRENGTH_Q16, frame_t);
    memcpy(t.p.out_nrm, normals, nbytes);
    psc_shadow_apply(&sa, &t.p, PSC_SHADOW_STRENGTH_Q16, frame_a);
    memcpy(t.p.out_nrm, normals, nbytes);
    psc_shadow_apply(&s, &t.p, PSC_SHADOW_STRENGTH_Q16, frame);
    memcpy(t.p.out_nrm, normals, nbytes);
    free(normals);
    accuracy_t a = compare(&t.p, frame, bvh), at = compare(&t.p, frame_t, bvh), b = compare(&t.p, frame1, bvh);
    accuracy_t c = compare(&t.p, own, bvh), av = compare(&t.p, frame_a, bvh);
    seams_t sd = seams(&t.p, frame);
    bool grid = sm->grid_quads != 0 && !s.at_corners, corrected = (sm->rest_count != 0 && s.at_corners) || grid;
    /* posed by one of its actions, the product knows where a part runs through another (its correction through
     * the action), and so does the patch grid correction of a character at rest (the teapot's spout inside its
     * body): every vertex compared. Else (the rest pose, a pack without them) a character's figures leave its
     * buried vertices out, the model's own, and say how many; the correction's own are held over every vertex too */
    bool phased = s.phase_a != NULL, every = phased || grid;
    figures_t f = figures_of(&a, every), ft = figures_of(&at, every), fb = figures_of(&b, every);
    figures_t fc = figures_of(&c, every), fall = figures_of(&a, true), ftall = figures_of(&at, true);
    figures_t favg = figures_of(&av, true);
    print_left_out(label, &a, &f, max_left_out);
    print_message("  %-20s the frame: correlation %.3f, mean abs error %.3f, mean %.3f against %.3f (%s)\n"
                  "  %-20s the spheres alone: %.3f, %.3f, mean %.3f; one level: %.3f, %.3f; each vertex its own "
                  "spheres: %.3f, %.3f\n  %-20s patches' mean edge %.3f R (%s); of %u vertices two patches share, "
                  "%u disagree by more than 0.01 (worst %.3f)\n", label, f.corr, f.mae, f.mean, f.ref_mean,
                  grid ? "with the patch grid correction" : corrected ? "with the rest correction" : "no correction", "", ft.corr, ft.mae, ft.mean, fb.corr,
                  fb.mae, fc.corr, fc.mae, "", s.mean_edge_q16 / 65536.0,
                  s.at_corners ? "composed at the corners" : "at every vertex", (unsigned)sd.shared,
                  (unsigned)sd.disagree, sd.worst);
    if (phased)
        print_message("  %-20s through its action (phases %u to %u, %.2f of the way): every vertex %.3f, %.3f, mean %.3f "
                      "against %.3f; the rest correction alone %.3f, %.3f, mean %.3f\n", "",
                      (unsigned)((s.phase_a - sm->phase_q15) / sm->rest_count % sm->phase_samples),
                      (unsigned)((s.phase_b - sm->phase_q15) / sm->rest_count % sm->phase_samples),
                      s.phase_f_q16 / 65536.0, fall.corr, fall.mae, fall.mean, fall.ref_mean, favg.corr, favg.mae,
                      favg.mean);
    /* a vertex two patches share gets one occlusion from both: no seams (but where a patch runs along one spline
     * segment twice, as one of Thom's six-sided patches does, or a strongly bent edge strays from its arch) */
    assert_true(sd.disagree * 200u <= sd.shared);
    assert_true(f.corr >= min_corr);
    assert_true(f.mae <= max_mae);
    if (corrected)   /* (the spheres alone run light: the teapot's mean 0.104 against 0.171) */
        assert_true(fabs(f.mean - f.ref_mean) <= 0.05);
    assert_true(at.corr > b.corr && at.mae < b.mae);   /* the tree beats one level (the spheres alone, open vertices) */
    /* the correction beats the spheres alone; over every vertex it holds 0.05 under the goal (with the buried,
     * walking: 0.879 against the spheres' 0.887) and the same error */
    if (corrected) {
        assert_true(f.corr > ft.corr && f.mae < ft.mae && fall.mae < ftall.mae);
        assert_true(fall.corr >= min_corr - 0.05 && fall.mae <= max_mae);
    }
    if (phased)   /* the correction through the action beats its average over poses, every vertex compared */
        assert_true(fall.corr > favg.corr && fall.mae < favg.mae);
    assert_true(c.corr >= min_corr - 0.1);
    assert_int_equal(s.shaded, t.p.vtx_total);
    free(frame);
    free(frame1);
    free(frame_t);
    free(frame_a);
    free(wsa);
    free(own);
    psc_measure_bvh_free(bvh);
    free(pos);
    free(tri);
    free(ws);
    free(wst);
    free(ws1);
    tsup_tess_free(&t);
}

static void build_pack(const psc_patch_model_t *m, unsigned levels, unsigned spheres, bool rest, uint8_t **buf,
                       psc_shadow_model_t *out)
{
    psc_bake_shadow_opts_t o = {.levels = levels, .spheres = spheres, .table = 32, .no_rest = !rest};
    size_t len;
    char err[512], note[256] = "";
    if (psc_bake_shadow(m, &o, "test", buf, &len, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_container_error_t e = {0};
    assert_int_equal(psc_shadow_parse(*buf, len, out, &e), PSC_OK);
}

static void build_packs(const psc_patch_model_t *m, packs_t *pk)
{
    build_pack(m, PSC_BAKE_SHADOW_LEVELS, PSC_BAKE_SHADOW_SPHERES, true, &pk->buf[0], &pk->product);
    build_pack(m, PSC_BAKE_SHADOW_LEVELS, PSC_BAKE_SHADOW_SPHERES, false, &pk->buf[1], &pk->tree);
    build_pack(m, 1, PSC_BAKE_SHADOW_SPHERES, false, &pk->buf[2], &pk->single);
}

static void packs_free(packs_t *pk)
{
    for (unsigned i = 0; i < 3; i++)
        free(pk->buf[i]);
}

static void test_against_raycast(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    char err[768];
    psc_bake_patch_opts_t o = {.actions = {"assets/thom/ResoluteWalk.act", "assets/thom/Wave.act"}, .action_count = 2,
                               .skin_from = "assets/thom/Thom2.mdl", .quiet = true};
    if (psc_bake_patch_any(THOM, &o, &pf, err, sizeof err) != 0)
        fail_msg("%s", err);
    packs_t pk;
    build_packs(&pf.model, &pk);
    /* the goal: 0.85, every vertex compared in motion (his arm passes through his shirt as it comes down, the
     * model's own: 2.3 % of the vertices walking, 2.8 % waving, which the correction through each action makes
     * dark); at rest nothing is buried */
    shade_and_compare("Thom at rest", &pf.model, &pk, -1, 0, 0.85, 0.06, 0.02);
    shade_and_compare("Thom walking, 0.5 s", &pf.model, &pk, 0, 500, 0.85, 0.06, 0.02);
    shade_and_compare("Thom waving, 1.1 s", &pf.model, &pk, 1, 1100, 0.85, 0.06, 0.02);
    /* and at times between the phases the correction was sampled at (walk 1033 ms long, wave 2233 ms; phases every
     * eighth): the goal's bounds, 0.85 and 0.10 */
    shade_and_compare("Thom walking, 0.17 s", &pf.model, &pk, 0, 170, 0.85, 0.10, 0.02);
    shade_and_compare("Thom walking, 0.73 s", &pf.model, &pk, 0, 730, 0.85, 0.10, 0.02);
    shade_and_compare("Thom waving, 0.64 s", &pf.model, &pk, 1, 640, 0.85, 0.10, 0.02);
    shade_and_compare("Thom waving, 1.73 s", &pf.model, &pk, 1, 1730, 0.85, 0.10, 0.02);
    packs_free(&pk);
    psc_io_patch_free(&pf);

    /* the second model: the teapot (no bones), its handle and spout over the body */
    size_t len, plen;
    char *text = tsup_teapot_bpt(&len);
    psc_patch_src_t src;
    if (psc_bpt_parse("teapot.bpt", text, len, &src, err, sizeof err) != 0)
        fail_msg("%s", err);
    uint8_t *pack;
    if (psc_bake_patch_pack(&src, "teapot.bpt", &pack, &plen, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_patch_model_t tm;
    psc_container_error_t e = {0};
    assert_int_equal(psc_patch_parse(pack, plen, &tm, &e), PSC_OK);
    build_packs(&tm, &pk);
    /* its patches are large (0.3 R): composed at every vertex, with the correction over each patch's (u, v); the
     * spout's and the handle's ends run inside the body (23 % of the vertices, the Utah teapot's own), which it
     * makes dark: every vertex compared */
    assert_int_equal(pk.product.grid_quads, psc_bake_shadow_grid_quads(&tm));
    assert_int_equal(pk.product.rest_count, 0);
    shade_and_compare("the teapot", &tm, &pk, -1, 0, 0.85, 0.10, 0.02);
    packs_free(&pk);
    /* held out: A:M's own torus and bent tube (CC0), large patches too (the hole's inside, the bend's) */
    static const char *const am[] = {TSUP_DATA_AM "Torus.mdl", TSUP_DATA_AM "Cylindrical_Elbow.mdl"};
    for (unsigned k = 0; k < 2; k++) {
        psc_bake_patch_opts_t ao = {.quiet = true};
        psc_io_patch_t af;
        if (psc_bake_patch_any(am[k], &ao, &af, err, sizeof err) != 0)
            fail_msg("%s", err);
        build_packs(&af.model, &pk);
        shade_and_compare(k ? "A:M's bent tube" : "A:M's torus", &af.model, &pk, -1, 0, 0.85, 0.10, 0.02);
        packs_free(&pk);
        psc_io_patch_free(&af);
    }
    free(pack);
    free(text);
    psc_patch_src_free(&src);
}

/* ---- glTF models --------------------------------------------------------------------------------------------- */

#define GLTF_DIR TSUP_DATA_GLTF

/* A glTF model posed at t (< 0: rest) in units of R, shaded by the run time at every vertex, against ray-cast AO
 * on the same posed triangles; mean[0], mean[1]: the two mean occlusions; mean[2]: how far the finest spheres'
 * posed centres lie from the posed surface (the mean distance to the nearest vertex, units of R). */
static accuracy_t gltf_accuracy(const psc_gltf_t *g, const psc_shadow_model_t *sm, double t, int bend,
                                uint32_t *occ_out, double *mean)
{
    uint32_t nv = g->mesh.vertex_count, nj = g->joint_count;
    double c[3], r, (*skin)[12] = malloc(nj * sizeof *skin), *pos = malloc(nv * 3 * sizeof *pos);
    double *nrm = malloc(nv * 3 * sizeof *nrm);
    psc_gltf_trs_t *local = malloc(nj * sizeof *local);
    psc_mat4_q16_t *skin_q16 = calloc(nj, sizeof *skin_q16);
    int32_t *pq = malloc(nv * 3 * sizeof *pq);
    int16_t *nq = malloc(nv * 3 * sizeof *nq);
    uint32_t *col = calloc(nv, sizeof *col), *occ = occ_out ? occ_out : malloc(nv * sizeof *occ);
    double (*dpos)[3] = malloc(nv * sizeof *dpos);
    uint32_t (*tri)[3] = malloc(g->mesh.triangle_count * sizeof *tri);
    assert_true(skin && pos && nrm && local && skin_q16 && pq && nq && col && occ && dpos && tri);
    psc_gltf_frame(g, c, &r);
    psc_gltf_pose(g, t, local);
    psc_gltf_adjust_t *adjust = NULL;
    if (bend) {   /* every third joint turned by bend degrees about z, past anything the animation does */
        double cb = cos(bend * M_PI / 180), sn = sin(bend * M_PI / 180);
        const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, rz[12] = {cb, -sn, 0, 0, sn, cb, 0, 0, 0, 0, 1, 0};
        adjust = malloc(nj * sizeof *adjust);
        assert_non_null(adjust);
        for (uint32_t j = 0; j < nj; j++) {
            memcpy(adjust[j].pre, id, sizeof id);
            memcpy(adjust[j].post, j > 2 && j % 3 == 0 ? rz : id, sizeof id);
        }
    }
    psc_gltf_skin(g, local, adjust, skin);
    free(adjust);
    psc_gltf_deform(g, (const double(*)[12])skin, pos, nrm);
    for (uint32_t i = 0; i < nv; i++)
        for (unsigned a = 0; a < 3; a++) {
            dpos[i][a] = (pos[3 * i + a] - c[a]) / r;
            pq[3 * i + a] = (int32_t)lround(dpos[i][a] * 65536.0);
            nq[3 * i + a] = (int16_t)lround(nrm[3 * i + a] * 16383.0);
        }
    for (uint32_t j = 0; j < nj; j++) {
        for (unsigned row = 0; row < 3; row++) {
            for (unsigned k = 0; k < 3; k++)
                skin_q16[j].m[row][k] = (int32_t)lround(skin[j][4 * row + k] * 65536.0);
            double tr = skin[j][4 * row] * c[0] + skin[j][4 * row + 1] * c[1] + skin[j][4 * row + 2] * c[2] +
                        skin[j][4 * row + 3] - c[row];
            skin_q16[j].m[row][3] = (int32_t)lround(tr / r * 65536.0);
        }
        skin_q16[j].m[3][3] = 65536;
    }
    memcpy(tri, g->mesh.index, g->mesh.triangle_count * sizeof *tri);
    double (*smooth)[3] = malloc(nv * sizeof *smooth);
    assert_non_null(smooth);
    assert_int_equal(psc_measure_smooth_normals((const double(*)[3])dpos, nv, g->mesh.index, g->mesh.triangle_count,
                                                smooth), 0);
    psc_measure_bvh_t *bvh = psc_measure_bvh_new((const double(*)[3])dpos, nv, (const uint32_t(*)[3])tri, g->mesh.triangle_count);
    assert_non_null(bvh);
    psc_shadow_t s;
    void *ws = malloc(psc_shadow_workspace_size(sm, NULL) + 8);
    assert_int_equal(psc_shadow_init_mesh(&s, sm, nj, ws, psc_shadow_workspace_size(sm, NULL)), PSC_OK);
    psc_shadow_update_bones(&s, skin_q16, nj);
    double track = 0;
    unsigned tracked = 0;
    uint32_t fine = sm->level_first[sm->level_count - 1u];
    for (uint32_t i = fine; i < sm->sphere_count; i++) {
        if (sm->spheres[i].radius_q16 < 66)
            continue;   /* an empty cluster's placeholder */
        double best = INFINITY;
        for (uint32_t v = 0; v < nv; v++) {
            double d2 = 0;
            for (unsigned a = 0; a < 3; a++)
                d2 += (s.center[i][a] / 65536.0 - dpos[v][a]) * (s.center[i][a] / 65536.0 - dpos[v][a]);
            best = fmin(best, d2);
        }
        track += sqrt(best);
        tracked++;
    }
    mean[2] = tracked ? track / tracked : 0.0;
    psc_shadow_apply_mesh(&s, pq, nq, col, nv, PSC_SHADOW_STRENGTH_Q16, occ);
    assert_int_equal(s.shaded, nv);
    pairs_t open = {0}, all = {0};
    for (uint32_t i = 0; i < nv; i += 3) {
        if (smooth[i][0] == 0.0 && smooth[i][1] == 0.0 && smooth[i][2] == 0.0)
            continue;   /* no triangle with area round it */
        double y = reference(bvh, dpos[i], smooth[i]), x = occ[i] / 65536.0;
        pairs_add(&all, x, y);
        if (y < 1.0)
            pairs_add(&open, x, y);   /* not buried */
    }
    mean[0] = open.sx / open.n;
    mean[1] = open.sy / open.n;
    psc_measure_bvh_free(bvh);
    free(ws);
    free(skin), free(pos), free(nrm), free(local), free(skin_q16), free(pq), free(nq), free(col), free(dpos), free(tri);
    free(smooth);
    if (!occ_out)
        free(occ);
    return accuracy_of(&open, &all);
}

typedef struct {
    double t;                  /* seconds; < 0: rest */
    int bend;                  /* degrees at every third joint, 0: none */
    double min_corr;           /* correlation at least */
    double max_mae, max_left_out;
} gltf_pose_t;

typedef struct {
    bool beats_one_level;      /* the tree of spheres beats one level (the spheres alone, open vertices) */
    bool correction_beats;     /* the rest correction beats the spheres alone */
} gltf_expect_t;

/* A model (glTF, OBJ or what libassimp reads) in poses: the product's pack (the tree and its rest correction)
 * against ray-cast AO, the tree alone and one level alongside; the mean occlusion within 0.05 of the reference's. */
static void gltf_case(const char *path, const gltf_pose_t *poses, unsigned npose, gltf_expect_t expect)
{
    psc_gltf_t g;
    char err[512], note[256] = "";
    const char *file = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    if (psc_gltf_load(path, &g, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    uint8_t *b[3] = {NULL, NULL, NULL};
    size_t len[3] = {0, 0, 0};
    const psc_bake_shadow_opts_t o[3] = {{0}, {.no_rest = true}, {.levels = 1, .spheres = 8, .no_rest = true}};
    psc_shadow_model_t sm[3];
    psc_container_error_t e = {0};
    for (unsigned i = 0; i < 3; i++) {
        if (psc_bake_shadow_gltf(&g, &o[i], file, &b[i], &len[i], note, sizeof note, err, sizeof err) != 0)
            fail_msg("%s", err);
        assert_int_equal(psc_shadow_parse(b[i], len[i], &sm[i], &e), PSC_OK);
    }
    assert_int_equal(sm[0].rest_count, g.mesh.vertex_count);
    double rest_track = 0;
    for (unsigned k = 0; k < npose; k++) {
        const gltf_pose_t *ps = &poses[k];
        double mean[3], mean_t[3], mean1[3];
        accuracy_t a = gltf_accuracy(&g, &sm[0], ps->t, ps->bend, NULL, mean);
        accuracy_t at = gltf_accuracy(&g, &sm[1], ps->t, ps->bend, NULL, mean_t);
        accuracy_t a1 = gltf_accuracy(&g, &sm[2], ps->t, ps->bend, NULL, mean1);
        figures_t f = figures_of(&a, true), ft = figures_of(&at, true);
        char label[96];
        int n = snprintf(label, sizeof label, ps->t < 0 ? "%s at rest" : "%s at %.2f s", file, ps->t);
        if (ps->bend)
            snprintf(label + n, sizeof label - (size_t)n, ", bent %d", ps->bend);
        print_message("  %-40s correlation %.3f, mean abs error %.3f, mean %.3f against %.3f (with the rest "
                      "correction, gain %.3f);\n  %-40s the spheres alone: %.3f, %.3f, mean %.3f; one level (buried "
                      "left out): %.3f, %.3f against the tree's %.3f, %.3f;\n  %-40s the finest spheres' centres %.4f "
                      "R from the surface\n", label, f.corr, f.mae, f.mean, f.ref_mean, sm[0].rest_gain_q16 / 65536.0,
                      "", ft.corr, ft.mae, ft.mean, a1.corr, a1.mae, at.corr, at.mae, "", mean[2]);
        print_left_out(label, &a, &f, ps->max_left_out);
        assert_true(f.corr >= ps->min_corr);
        assert_true(f.mae <= ps->max_mae);
        assert_true(fabs(f.mean - f.ref_mean) <= 0.05);
        if (expect.beats_one_level)
            assert_true(at.corr > a1.corr);
        if (expect.correction_beats)
            assert_true(f.corr > ft.corr && f.mae < ft.mae);
        if (k == 0)
            rest_track = mean[2];
        assert_true(mean[2] <= 1.5 * rest_track);   /* the spheres follow the joints: as near the skin as at rest */
    }
    for (unsigned i = 0; i < 3; i++)
        free(b[i]);
    psc_gltf_free(&g);
}

/* The glTF models: a skinned bar bent by a bone chain and a rigid truck (a hollow shell with an inside: spheres fit
 * it worse than a body). In its own animation the bar hardly occludes itself (ray-cast mean 0.000 to 0.005), so
 * its correlation is weak (the spheres alone: 0.22 to 0.57) and what counts most is no false shadow (mean abs
 * error) and spheres that follow the bones. */
static void test_gltf_against_raycast(void **state)
{
    (void)state;
    const gltf_pose_t bar[] = {{-1.0, 0, 0.5, 0.04, 0.0}, {0.2, 0, 0.2, 0.04, 0.0}, {0.4, 0, 0.35, 0.04, 0.0}};
    const gltf_pose_t truck[] = {{-1.0, 0, 0.85, 0.10, 0.0}};   /* its cab's inside is closed: 9.4 % buried */
    gltf_case(GLTF_DIR "animation_with_skeleton.gltf", bar, 3, (gltf_expect_t){false, false});
    gltf_case(GLTF_DIR "CesiumMilkTruck.gltf", truck, 1, (gltf_expect_t){true, true});
}

/* Models nobody tuned the tables for (tests/data/assimp/SOURCES.md), at the goals of docs/characters.md: a static
 * spider (thin legs over a body) and a skinned human in his own animation at times between the poses the bake
 * averages over. */
static void test_heldout_against_raycast(void **state)
{
    (void)state;
    const gltf_pose_t spider[] = {{-1.0, 0, 0.85, 0.10, 0.02}};
    /* its animation is 3.3 s long: the bake averages 0.41, 1.24, 2.06 and 2.89 s; these lie between */
    const gltf_pose_t human[] = {{0.2, 0, 0.85, 0.10, 0.02}, {0.8, 0, 0.85, 0.10, 0.02},
                                 {1.6, 0, 0.85, 0.10, 0.02}, {2.5, 0, 0.85, 0.10, 0.02}};
    gltf_case(TSUP_DATA_ASSIMP "spider.obj", spider, 1, (gltf_expect_t){false, true});
    gltf_case(TSUP_DATA_ASSIMP "BCN_Epileptic.X", human, 4, (gltf_expect_t){true, true});
}

/* Mutated and truncated glTF files: the importer refuses them with a message naming the file, or reads a model
 * the posing handles. */
static void test_gltf_fuzz(void **state)
{
    (void)state;
    FILE *f = fopen(GLTF_DIR "animation_with_skeleton.gltf", "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *orig = malloc((size_t)n), *buf = malloc((size_t)n);
    assert_true(orig && buf && fread(orig, 1, (size_t)n, f) == (size_t)n);
    fclose(f);
    char path[] = "/tmp/periscope-gltf-fuzz-XXXXXX.gltf";
    int fd = mkstemps(path, 5);
    assert_true(fd >= 0);
    close(fd);
    uint32_t seed = 0x5eed1234u;
    unsigned refused = 0, read = 0;
    for (unsigned round = 0; round < 60; round++) {
        memcpy(buf, orig, (size_t)n);
        long len = n;
        if (round % 3 == 0) {
            seed = seed * 1664525u + 1013904223u;
            len = (long)(seed % (uint32_t)n);   /* truncated */
        } else {
            for (unsigned k = 0; k < 1u + round % 7u; k++) {   /* bytes changed, in the JSON or the data */
                seed = seed * 1664525u + 1013904223u;
                buf[seed % (uint32_t)n] = (char)(seed >> 24);
            }
        }
        f = fopen(path, "wb");
        assert_non_null(f);
        assert_true(fwrite(buf, 1, (size_t)len, f) == (size_t)len);
        fclose(f);
        psc_gltf_t g;
        char err[512], note[256] = "";
        if (psc_gltf_load(path, &g, note, sizeof note, err, sizeof err) != 0) {
            assert_non_null(strstr(err, path));
            refused++;
            continue;
        }
        read++;
        psc_gltf_trs_t *local = malloc(g.joint_count * sizeof *local);
        double (*skin)[12] = malloc(g.joint_count * sizeof *skin);
        double *pos = malloc(g.mesh.vertex_count * 3 * sizeof *pos), *nrm = malloc(g.mesh.vertex_count * 3 * sizeof *nrm);
        assert_true(local && skin && pos && nrm);
        psc_gltf_pose(&g, g.duration / 2, local);
        psc_gltf_skin(&g, local, NULL, skin);
        psc_gltf_deform(&g, (const double(*)[12])skin, pos, nrm);
        for (uint32_t t = 0; t < 3u * g.mesh.triangle_count; t++)
            assert_true(g.mesh.index[t] < g.mesh.vertex_count);
        free(local), free(skin), free(pos), free(nrm);
        psc_gltf_free(&g);
    }
    print_message("  60 mutated or truncated glTF files: %u refused with a message, %u read and posed\n", refused, read);
    assert_true(refused > 0);
    remove(path);
    free(orig);
    free(buf);
}

/* ---- the rest correction (SREF) ------------------------------------------------------------------------------ */

/* A copy of pack (len bytes) with the rest correction's head at head set to count and gain, checksummed again,
 * parsed: the status, and the message in e. */
static psc_status_t parse_edited(const uint8_t *pack, size_t len, size_t head, uint32_t count, uint32_t gain,
                                 psc_container_error_t *e)
{
    uint8_t *b;
    assert_int_equal(posix_memalign((void **)&b, 64, len), 0);
    memcpy(b, pack, len);
    tsup_wr32(b + head, count);
    tsup_wr32(b + head + 4, gain);
    tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, 0);
    tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, b, len));
    psc_shadow_model_t m;
    psc_status_t st = psc_shadow_parse(b, len, &m, e);
    free(b);
    return st;
}

/* The pack's rest correction: each vertex's occlusion is the spheres' times the gain plus its correction, to the
 * bit (clamped to 0..1); a gain or count outside the format's limits, or a size that does not match the count, is
 * refused with a message; a character whose point count differs is refused, a mesh whose vertex count differs
 * gets the spheres alone. */
static void test_rest_section(void **state)
{
    (void)state;
    psc_gltf_t g;
    char err[512], note[256] = "";
    if (psc_gltf_load(GLTF_DIR "animation_with_skeleton.gltf", &g, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_bake_shadow_opts_t o = {.levels = 2, .spheres = 16, .table = 8};
    uint8_t *pack = NULL;
    size_t len = 0;
    if (psc_bake_shadow_gltf(&g, &o, "bar", &pack, &len, note, sizeof note, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_shadow_model_t m;
    psc_container_error_t e = {0};
    assert_int_equal(psc_shadow_parse(pack, len, &m, &e), PSC_OK);
    uint32_t nv = g.mesh.vertex_count;
    assert_int_equal(m.rest_count, nv);
    assert_true(m.rest_gain_q16 >= PSC_SHADOW_REST_GAIN_MIN_Q16 && m.rest_gain_q16 <= PSC_SHADOW_REST_GAIN_MAX_Q16);

    /* the formula, to the bit, on the rest pose as the device has it */
    double c[3], r, (*skin)[12] = malloc(g.joint_count * sizeof *skin), *pos = malloc(nv * 3 * sizeof *pos);
    double *nrm = malloc(nv * 3 * sizeof *nrm);
    psc_gltf_trs_t *local = malloc(g.joint_count * sizeof *local);
    int32_t *pq = malloc(nv * 3 * sizeof *pq);
    int16_t *nq = malloc(nv * 3 * sizeof *nq), *nq0 = malloc(nv * 3 * sizeof *nq0);
    psc_mat4_q16_t *skq = calloc(g.joint_count, sizeof *skq);
    uint32_t *col = calloc(nv, sizeof *col), *occ = malloc(nv * sizeof *occ), *occ1 = malloc(nv * sizeof *occ1);
    void *ws = malloc(psc_shadow_workspace_size(&m, NULL) + 8);
    assert_true(skin && pos && nrm && local && pq && nq && nq0 && skq && col && occ && occ1 && ws);
    psc_gltf_frame(&g, c, &r);
    psc_gltf_pose(&g, -1.0, local);
    psc_gltf_skin(&g, local, NULL, skin);
    psc_gltf_deform(&g, (const double(*)[12])skin, pos, nrm);
    psc_gltf_quantize(&g, c, r, pos, nrm, (const double(*)[12])skin, pq, nq, skq);
    memcpy(nq0, nq, nv * 3 * sizeof *nq);
    psc_shadow_t s;
    assert_int_equal(psc_shadow_init_mesh(&s, &m, g.joint_count, ws, psc_shadow_workspace_size(&m, NULL)), PSC_OK);
    psc_shadow_update_bones(&s, skq, g.joint_count);
    psc_shadow_apply_mesh(&s, pq, nq, col, nv, PSC_SHADOW_STRENGTH_Q16, occ);
    unsigned clamped = 0;
    for (uint32_t i = 0; i < nv; i++) {
        int32_t n[3] = {nq0[3 * i] * 4, nq0[3 * i + 1] * 4, nq0[3 * i + 2] * 4};
        int64_t sph = psc_shadow_occlusion(&s, &pq[3 * i], n);
        int64_t want = ((sph * m.rest_gain_q16 + 32768) >> 16) + 2 * m.rest_q15[i];
        clamped += want < 0 || want > 65536;
        want = want < 0 ? 0 : want > 65536 ? 65536 : want;
        assert_int_equal(occ[i], (uint32_t)want);
    }
    /* one vertex fewer: not this pack's mesh, the spheres alone */
    memcpy(nq, nq0, nv * 3 * sizeof *nq);
    psc_shadow_apply_mesh(&s, pq, nq, col, nv - 1u, PSC_SHADOW_STRENGTH_Q16, occ1);
    for (uint32_t i = 0; i + 1u < nv; i++) {
        int32_t n[3] = {nq0[3 * i] * 4, nq0[3 * i + 1] * 4, nq0[3 * i + 2] * 4};
        assert_int_equal(occ1[i], psc_shadow_occlusion(&s, &pq[3 * i], n));
    }
    print_message("  %u vertices: the spheres' occlusion x %.3f + the correction, to the bit (%u clamped)\n", nv,
                  m.rest_gain_q16 / 65536.0, clamped);

    /* a character of another point count is refused; of the pack's own, taken */
    psc_patch_model_t pm = {0};
    pm.bone_count = m.bone_count;
    pm.point_count = nv + 1u;
    void *pws = malloc(psc_shadow_workspace_size(&m, &pm) + 8);
    assert_non_null(pws);
    assert_int_equal(psc_shadow_init(&s, &m, &pm, pws, psc_shadow_workspace_size(&m, &pm)), PSC_ERR_ARG);
    pm.point_count = nv;
    assert_int_equal(psc_shadow_init(&s, &m, &pm, pws, psc_shadow_workspace_size(&m, &pm)), PSC_OK);

    /* the section's limits */
    size_t head = (size_t)((const uint8_t *)m.rest_q15 - pack) - sizeof(psc_shadow_rest_raw_t);
    const struct {
        uint32_t count, gain;
        const char *what;
    } bad[] = {
        {nv, 0, "gain"},
        {nv, PSC_SHADOW_REST_GAIN_MIN_Q16 - 1u, "gain"},
        {nv, PSC_SHADOW_REST_GAIN_MAX_Q16 + 1u, "gain"},
        {nv + 1u, 65536, "size"},
        {nv - 1u, 65536, "size"},
        {0, 65536, "count"},
        {PSC_SHADOW_MAX_REST + 1u, 65536, "count"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        psc_container_error_t be = {0};
        assert_int_not_equal(parse_edited(pack, len, head, bad[k].count, bad[k].gain, &be), PSC_OK);
        assert_non_null(be.what);
        assert_non_null(strstr(be.what, bad[k].what));
    }
    psc_container_error_t ge = {0};
    assert_int_equal(parse_edited(pack, len, head, nv, PSC_SHADOW_REST_GAIN_MAX_Q16, &ge), PSC_OK);
    free(pws);
    free(skin), free(pos), free(nrm), free(local), free(pq), free(nq), free(nq0), free(skq), free(col), free(occ);
    free(occ1), free(ws), free(pack);
    psc_gltf_free(&g);
}

/* The pack's correction through each action (SRPH): a frame posed by action a at time t takes phases k and k + 1
 * (looping) round t / duration x samples, and each corner point's occlusion is the spheres' times the gain plus the
 * two phases' blend, to the bit (clamped); the rest pose, and a character of another action count, take the rest
 * correction; the section's limits are refused with a message, and so is SRPH without SREF. */
static void test_phase_section(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    char err[768];
    psc_bake_patch_opts_t po = {.actions = {"assets/thom/ResoluteWalk.act", "assets/thom/Wave.act"},
                                .action_count = 2, .skin_from = "assets/thom/Thom2.mdl", .quiet = true};
    if (psc_bake_patch_any(THOM, &po, &pf, err, sizeof err) != 0)
        fail_msg("%s", err);
    const psc_patch_model_t *pm = &pf.model;
    uint8_t *pack;
    psc_shadow_model_t m;
    build_pack(pm, 2, 32, true, &pack, &m);   /* a small tree: the section is what is tested */
    assert_int_equal(m.phase_actions, 2);
    assert_int_equal(m.phase_samples, 8);
    assert_int_equal(m.rest_count, pm->point_count);
    size_t len = tsup_rd32(pack + PSC_CONTAINER_FILE_SIZE_OFFSET);

    tsup_tess_t t;
    assert_int_equal(tsup_tess_new(&t, pm), 0);
    size_t ws_size = psc_shadow_workspace_size(&m, pm);
    void *ws = malloc(ws_size + 8);
    psc_shadow_t s;
    assert_int_equal(psc_shadow_init(&s, &m, pm, ws, ws_size), PSC_OK);
    static const struct {
        int action;
        uint32_t ms;
    } poses[] = {{-1, 0}, {0, 0}, {0, 640}, {0, 1032}, {1, 1100}, {1, 2232}, {1, 3000}};
    unsigned checked = 0;
    for (size_t k = 0; k < sizeof poses / sizeof poses[0]; k++) {
        assert_int_equal(tsup_tess_fine(&t, poses[k].action, poses[k].ms), 0);
        psc_shadow_update(&s, &t.p);
        if (poses[k].action < 0) {
            assert_null(s.phase_a);
        } else {
            uint32_t d = pm->actions[poses[k].action].duration_ms, tm = poses[k].ms % d;
            uint64_t at = ((uint64_t)tm * 8u << 16) / d;
            uint32_t ph = (uint32_t)(at >> 16), a = (uint32_t)poses[k].action;
            assert_ptr_equal(s.phase_a, m.phase_q15 + ((size_t)a * 8u + ph) * m.rest_count);
            assert_ptr_equal(s.phase_b, m.phase_q15 + ((size_t)a * 8u + (ph + 1u) % 8u) * m.rest_count);
            assert_int_equal(s.phase_f_q16, (uint32_t)(at & 0xFFFFu));
        }
        psc_shadow_apply(&s, &t.p, PSC_SHADOW_STRENGTH_Q16, NULL);
        for (uint32_t i = 0; i < pm->point_count; i++) {
            if (s.point[i].occ == UINT32_MAX)
                continue;   /* not a corner of a face drawn */
            int32_t bent[3];
            int64_t sph = psc_shadow_occlusion_bent(&s, t.p.pos[i], t.p.nrm[i], bent);
            int64_t off = 2 * (int64_t)m.rest_q15[i];
            if (s.phase_a) {
                int64_t x = s.phase_a[i], y = s.phase_b[i], prod = (y - x) * s.phase_f_q16;
                off = 2 * x + ((prod + 16384) >> 15);   /* (psc_shr_round64's rounding: half up) */
            }
            int64_t want = ((sph * m.rest_gain_q16 + 32768) >> 16) + off;
            want = want < 0 ? 0 : want > 65536 ? 65536 : want;
            assert_int_equal(s.point[i].occ, (uint32_t)want);
            checked++;
        }
    }
    print_message("  %u corner occlusions over 7 poses: the spheres' x %.3f + the two phases' blend (the rest "
                  "correction at rest), to the bit\n", checked, m.rest_gain_q16 / 65536.0);
    assert_true(checked > 1000);
    /* a character of another action count: the rest correction */
    psc_patch_model_t one = *pm;
    one.action_count = 1;
    psc_shadow_t s1;
    assert_int_equal(psc_shadow_init(&s1, &m, &one, ws, ws_size), PSC_OK);
    psc_patch_t p1 = t.p;
    p1.m = &one;
    p1.pose_action = 0;
    psc_shadow_update(&s1, &p1);
    assert_null(s1.phase_a);

    /* the section's limits: actions, samples, count, size; SRPH without SREF */
    size_t head = (size_t)((const uint8_t *)m.phase_q15 - pack) - sizeof(psc_shadow_phase_raw_t);
    const struct {
        uint16_t actions, samples;
        uint32_t count;
        const char *what;
    } bad[] = {
        {0, 8, m.rest_count, "actions or phases"},
        {2, 0, m.rest_count, "actions or phases"},
        {PSC_SHADOW_MAX_PHASE_ACTIONS + 1u, 8, m.rest_count, "actions or phases"},
        {2, PSC_SHADOW_MAX_PHASES + 1u, m.rest_count, "actions or phases"},
        {2, 8, m.rest_count + 1u, "SREF's"},
        {1, 8, m.rest_count, "size"},
        {2, 7, m.rest_count, "size"},
    };
    uint8_t *b;
    assert_int_equal(posix_memalign((void **)&b, 64, len), 0);
    for (size_t k = 0; k <= sizeof bad / sizeof bad[0]; k++) {
        memcpy(b, pack, len);
        if (k < sizeof bad / sizeof bad[0]) {
            psc_shadow_phase_raw_t h = {bad[k].actions, bad[k].samples, bad[k].count};
            memcpy(b + head, &h, sizeof h);
        } else {   /* SREF's entry in the section table renamed: SRPH alone */
            const uint8_t *rest_at = (const uint8_t *)m.rest_q15 - sizeof(psc_shadow_rest_raw_t);
            uint32_t off = (uint32_t)(rest_at - pack);
            for (size_t e = PSC_CONTAINER_HEADER_SIZE; e + 16 <= len; e += 4)
                if (tsup_rd32(b + e) == PSC_SECTION_SHADOW_REST && tsup_rd32(b + e + 4) == off) {
                    tsup_wr32(b + e, PSC_FOURCC('X', 'R', 'E', 'F'));
                    break;
                }
        }
        tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, 0);
        tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, b, len));
        psc_shadow_model_t bm;
        psc_container_error_t be = {0};
        assert_int_not_equal(psc_shadow_parse(b, len, &bm, &be), PSC_OK);
        assert_non_null(be.what);
        print_message("  refused: %s\n", be.what);
        assert_non_null(strstr(be.what, k < sizeof bad / sizeof bad[0] ? bad[k].what : "SRPH without SREF"));
    }
    free(b);
    free(ws);
    free(pack);
    tsup_tess_free(&t);
    psc_io_patch_free(&pf);
}

/* The teapot's patch pack (its caller frees *pack and *text, and src). */
static void teapot_pack(psc_patch_src_t *src, char **text, uint8_t **pack, psc_patch_model_t *tm)
{
    size_t len, plen;
    char err[512];
    *text = tsup_teapot_bpt(&len);
    if (psc_bpt_parse("teapot.bpt", *text, len, src, err, sizeof err) != 0)
        fail_msg("%s", err);
    if (psc_bake_patch_pack(src, "teapot.bpt", pack, &plen, err, sizeof err) != 0)
        fail_msg("%s", err);
    psc_container_error_t e = {0};
    assert_int_equal(psc_patch_parse(*pack, plen, tm, &e), PSC_OK);
}

/* The patch grid correction (SGRD) at a vertex of place uv in the patch whose first quad is q, as the test reads
 * psc_shadow.h: its quad's grid, bilinear in (u, v) x (side - 1), Q1.15, rounded half up. */
static int64_t grid_want(const psc_shadow_model_t *m, uint32_t q, uint32_t uv)
{
    int64_t n = m->grid_side - 1, gu = (int64_t)PSC_PATCH_UV_U(uv) * n, gv = (int64_t)PSC_PATCH_UV_V(uv) * n;
    int64_t i = gu >> 13, j = gv >> 13, fu = gu & 8191, fv = gv & 8191;
    if (i >= n)
        i = n - 1, fu = 8192;
    if (j >= n)
        j = n - 1, fv = 8192;
    const int16_t *g = m->grid_q15 + ((q + PSC_PATCH_UV_QUAD(uv)) * m->grid_side + (uint32_t)j) * m->grid_side + i;
    int64_t top = g[0] * (8192 - fu) + g[1] * fu, bottom = g[m->grid_side] * (8192 - fu) + g[m->grid_side + 1] * fu;
    return (top * (8192 - fv) + bottom * fv + ((int64_t)1 << 25)) >> 26;
}

/* The patch grid correction (SGRD) of a character whose patches are large (the teapot): made by the bake, with no
 * rest correction beside it; each vertex's occlusion is the spheres' plus its quad's grid at its (u, v), to the bit
 * (a node's own value where the vertex falls on one; within half a unit of the blend in double), at two tolerances;
 * a pack for other patches, or for a mesh, refused at start; the section's limits refused with a message, and so is
 * SGRD beside SREF. */
static void test_grid_section(void **state)
{
    (void)state;
    psc_patch_src_t src;
    char *text;
    uint8_t *ppk, *pack;
    psc_patch_model_t tm;
    teapot_pack(&src, &text, &ppk, &tm);
    psc_shadow_model_t m;
    build_pack(&tm, 2, 32, true, &pack, &m);
    assert_int_equal(m.rest_count, 0);
    assert_int_equal(m.grid_quads, psc_bake_shadow_grid_quads(&tm));
    assert_int_equal(m.grid_side, PSC_BAKE_SHADOW_GRID_SIDE);
    size_t len = tsup_rd32(pack + PSC_CONTAINER_FILE_SIZE_OFFSET);
    tsup_tess_t t;
    assert_int_equal(tsup_tess_new(&t, &tm), 0);
    size_t ws_size = psc_shadow_workspace_size(&m, &tm);
    void *ws = malloc(ws_size + 8);
    psc_shadow_t s;
    assert_int_equal(psc_shadow_init(&s, &m, &tm, ws, ws_size), PSC_OK);
    assert_false(s.at_corners);
    unsigned checked = 0, on_nodes = 0;
    for (unsigned pass = 0; pass < 2; pass++) {
        psc_patch_camera_t cam = {0};
        psc_mat4_identity(&cam.camera_from_object);
        cam.camera_from_object.m[2][3] = 100 * 65536;
        cam.focal_px_q16 = 65536;
        cam.tol_units_q16 = pass ? 65536 / 500 : 65536 / 25;   /* 0.002 R (between the nodes), and 0.04 R */
        cam.near_q16 = 65536;
        psc_patch_pose(&t.p, -1, 0);
        psc_patch_tangents(&t.p);
        assert_int_equal(psc_patch_tessellate(&t.p, &cam, NULL), PSC_OK);
        psc_shadow_update(&s, &t.p);
        size_t nbytes = 3u * t.p.vtx_total * sizeof *t.p.out_nrm;
        int16_t *normals = malloc(nbytes);
        uint32_t *occ = malloc(t.p.vtx_total * sizeof *occ);
        assert_true(normals && occ);
        memcpy(normals, t.p.out_nrm, nbytes);
        psc_shadow_apply(&s, &t.p, PSC_SHADOW_STRENGTH_Q16, occ);
        uint32_t v = 0, q = 0;
        for (uint32_t f = 0; f < tm.face_count; f++) {
            uint32_t first = q;
            q += psc_patch_face_quads(&tm.faces[f]);
            if (t.p.face_cache[f] == PSC_PATCH_NO_CACHE)
                continue;
            for (uint32_t c = 0; c < t.p.face_cache_count[f]; c++, v++) {
                int32_t nq[3] = {normals[3 * v] * 4, normals[3 * v + 1] * 4, normals[3 * v + 2] * 4}, bent[3];
                int64_t sph = psc_shadow_occlusion_bent(&s, &t.p.out_pos[3 * v], nq, bent);
                uint32_t uv = t.p.out_uv[v];
                int64_t corr = grid_want(&m, first, uv), want = sph + 2 * corr;
                {   /* and within half a unit of the bilinear blend in double */
                    double gu = PSC_PATCH_UV_U(uv) / 8192.0 * (m.grid_side - 1), gv = PSC_PATCH_UV_V(uv) / 8192.0 *
                                                                                      (m.grid_side - 1);
                    unsigned i = gu >= m.grid_side - 1 ? m.grid_side - 2 : (unsigned)gu;
                    unsigned j = gv >= m.grid_side - 1 ? m.grid_side - 2 : (unsigned)gv;
                    const int16_t *g = m.grid_q15 + ((first + PSC_PATCH_UV_QUAD(uv)) * m.grid_side + j) * m.grid_side + i;
                    double fu = gu - i, fv = gv - j;
                    double d = (g[0] * (1 - fu) + g[1] * fu) * (1 - fv) +
                               (g[m.grid_side] * (1 - fu) + g[m.grid_side + 1] * fu) * fv;
                    assert_true(fabs((double)corr - d) <= 0.5 + 1e-9);
                }
                want = want < 0 ? 0 : want > 65536 ? 65536 : want;
                assert_int_equal(occ[v], (uint32_t)want);
                uint32_t step = PSC_PATCH_UV_ONE / (m.grid_side - 1u);
                if (PSC_PATCH_UV_U(uv) % step == 0 && PSC_PATCH_UV_V(uv) % step == 0) {
                    uint32_t i = PSC_PATCH_UV_U(uv) / step, j = PSC_PATCH_UV_V(uv) / step;
                    assert_int_equal(corr, m.grid_q15[((first + PSC_PATCH_UV_QUAD(uv)) * m.grid_side + j) *
                                                          m.grid_side + i]);
                    on_nodes++;
                }
                checked++;
            }
        }
        assert_int_equal(v, t.p.vtx_total);
        memcpy(t.p.out_nrm, normals, nbytes);
        free(normals);
        free(occ);
    }
    print_message("  %u vertex occlusions at two tolerances: the spheres' plus the grid at (u, v), to the bit (%u on "
                  "a node: its value)\n", checked, on_nodes);
    assert_true(checked > 3000 && on_nodes > 500);
    /* a pack for other patches (one patch fewer), or for a mesh: refused at start */
    psc_patch_model_t fewer = tm;
    fewer.face_count--;
    psc_shadow_t s2;
    assert_int_equal(psc_shadow_init(&s2, &m, &fewer, ws, ws_size), PSC_ERR_ARG);
    assert_int_equal(psc_shadow_init_mesh(&s2, &m, m.bone_count, ws, ws_size), PSC_ERR_ARG);

    /* the section's limits: quads, side, size; SGRD beside SREF */
    size_t head = (size_t)((const uint8_t *)m.grid_q15 - pack) - sizeof(psc_shadow_grid_raw_t);
    const struct {
        uint32_t quads;
        uint16_t side;
        const char *what;
    } bad[] = {
        {0, 17, "quads or side"},
        {PSC_SHADOW_MAX_GRID_QUADS + 1u, 17, "quads or side"},
        {m.grid_quads, 1, "quads or side"},
        {m.grid_quads, PSC_SHADOW_MAX_GRID_SIDE + 1u, "quads or side"},
        {m.grid_quads + 1u, 17, "size"},
        {m.grid_quads, 16, "size"},
    };
    uint8_t *b;
    assert_int_equal(posix_memalign((void **)&b, 64, len), 0);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        memcpy(b, pack, len);
        psc_shadow_grid_raw_t h = {bad[k].quads, bad[k].side, 0};
        memcpy(b + head, &h, sizeof h);
        tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, 0);
        tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, b, len));
        psc_shadow_model_t bm;
        psc_container_error_t be = {0};
        assert_int_not_equal(psc_shadow_parse(b, len, &bm, &be), PSC_OK);
        print_message("  refused: %s\n", be.what);
        assert_non_null(strstr(be.what, bad[k].what));
    }
    free(b);
    /* the same pack written again with a rest correction beside its grid */
    psc_shadow_info_raw_t si = {0};   /* (SINF rebuilt from the parsed counts) */
    si.sphere_count = m.sphere_count;
    si.level_count = (uint8_t)m.level_count;
    si.access_omega = (uint16_t)m.access_omega;
    si.access_theta = (uint16_t)m.access_theta;
    si.comp_theta = (uint16_t)m.comp_theta;
    si.comp_delta = (uint16_t)m.comp_delta;
    for (uint32_t l = 0; l < m.level_count; l++)
        si.level_first[l] = (uint16_t)m.level_first[l];
    si.bone_count = m.bone_count;
    uint8_t sref[sizeof(psc_shadow_rest_raw_t) + 2u * 37u] = {0};
    psc_shadow_rest_raw_t rh = {37u, 65536u};
    memcpy(sref, &rh, sizeof rh);
    size_t grid_bytes = sizeof(psc_shadow_grid_raw_t) + (size_t)m.grid_quads * m.grid_side * m.grid_side * 2u;
    psc_container_part_t parts[] = {
        {PSC_SECTION_SHADOW_INFO, &si, sizeof si},
        {PSC_SECTION_SHADOW_SPHERES, m.spheres, m.sphere_count * sizeof *m.spheres},
        {PSC_SECTION_SHADOW_ACCESS, m.access, (size_t)m.access_omega * m.access_theta * 4u},
        {PSC_SECTION_SHADOW_COMPOSITE, m.comp, (size_t)m.comp_theta * m.comp_theta * m.comp_delta * sizeof *m.comp},
        {PSC_SECTION_SHADOW_ACOS, m.acos_table, PSC_SHADOW_ACOS_SIZE * 2u},
        {PSC_SECTION_SHADOW_REST, sref, sizeof sref},
        {PSC_SECTION_SHADOW_GRID, pack + head, grid_bytes},
    };
    uint8_t *both;
    size_t both_len;
    char err[256];
    assert_int_equal(psc_io_container_write(&psc_shadow_format, parts, 7, &both, &both_len, "both", err, sizeof err),
                     0);
    psc_shadow_model_t bm;
    psc_container_error_t be = {0};
    assert_int_equal(psc_shadow_parse(both, both_len, &bm, &be), PSC_ERR_CORRUPT);
    print_message("  refused: %s\n", be.what);
    assert_non_null(strstr(be.what, "SGRD beside SREF"));
    parts[5] = parts[6];   /* and without it, the same bytes parse */
    free(both);
    assert_int_equal(psc_io_container_write(&psc_shadow_format, parts, 6, &both, &both_len, "grid", err, sizeof err),
                     0);
    assert_int_equal(psc_shadow_parse(both, both_len, &bm, &be), PSC_OK);
    assert_int_equal(bm.grid_quads, m.grid_quads);
    free(both);
    free(ws);
    free(pack);
    tsup_tess_free(&t);
    free(ppk);
    free(text);
    psc_patch_src_free(&src);
}

/* ---- animation -------------------------------------------------------------------------------------------- */

/* Thom's torso (green shirt) darkens as his arms come down from the T-pose (Wave.act starts arms down). */
static void test_armpits_darken(void **state)
{
    (void)state;
    psc_io_patch_t pf;
    char err[768];
    psc_bake_patch_opts_t o = {.actions = {"assets/thom/Wave.act"}, .action_count = 1,
                               .skin_from = "assets/thom/Thom2.mdl", .quiet = true};
    if (psc_bake_patch_any(THOM, &o, &pf, err, sizeof err) != 0)
        fail_msg("%s", err);
    uint8_t *buf;
    psc_shadow_model_t sm;
    build_pack(&pf.model, PSC_BAKE_SHADOW_LEVELS, PSC_BAKE_SHADOW_SPHERES, false, &buf, &sm);
    double mean[2];
    for (unsigned pose = 0; pose < 2; pose++) {
        tsup_tess_t t;
        assert_int_equal(tsup_tess_new(&t, &pf.model), 0);
        assert_int_equal(tsup_tess_fine(&t, pose ? 0 : -1, 0), 0);
        psc_shadow_t s;
        void *ws = malloc(psc_shadow_workspace_size(&sm, &pf.model) + 8);
        assert_int_equal(psc_shadow_init(&s, &sm, &pf.model, ws, psc_shadow_workspace_size(&sm, &pf.model)), PSC_OK);
        psc_shadow_update(&s, &t.p);
        double sum = 0;
        unsigned n = 0;
        for (uint32_t i = 0; i < t.p.vtx_total; i++) {
            uint32_t c = t.p.out_color[i];
            if (!(((c >> 8) & 255) > 100 && ((c >> 16) & 255) < 60 && (c & 255) < 60))
                continue;   /* the shirt's green only */
            int32_t nq[3] = {t.p.out_nrm[3 * i] * 4, t.p.out_nrm[3 * i + 1] * 4, t.p.out_nrm[3 * i + 2] * 4};
            sum += psc_shadow_occlusion(&s, &t.p.out_pos[3 * i], nq) / 65536.0;
            n++;
        }
        mean[pose] = sum / n;
        free(ws);
        tsup_tess_free(&t);
    }
    print_message("  the shirt's mean occlusion: arms out %.4f, arms down %.4f\n", mean[0], mean[1]);
    assert_true(mean[1] > mean[0] * 1.2);
    free(buf);
    psc_io_patch_free(&pf);
}

/* ---- fuzzing ---------------------------------------------------------------------------------------------- */

static void test_pack_fuzz(void **state)
{
    (void)state;
    psc_shadow_sphere_t sph[3] = {ball(0, 0, 0, 0.5), ball(1, 0, 0, 0.4), ball(0, 1, 0, 0.3)};
    uint16_t level_first[PSC_SHADOW_MAX_LEVELS] = {0};
    uint8_t *buf;
    size_t len;
    char err[256];
    assert_int_equal(psc_bake_shadow_write(sph, 3, 1, level_first, 0, 8, "fuzz.pao", &buf, &len, err, sizeof err), 0);
    tsup_rng_t r;
    tsup_rng_seed(&r, 71);
    unsigned parsed = 0, refused = 0;
    for (unsigned k = 0; k < 4000; k++) {
        size_t n = len;
        uint8_t *b;
        assert_int_equal(posix_memalign((void **)&b, 64, n), 0);
        memcpy(b, buf, n);
        unsigned muts = 1 + tsup_rng_below(&r, 4);
        for (unsigned j = 0; j < muts; j++) {
            size_t at = tsup_rng_below(&r, (uint32_t)n);
            switch (tsup_rng_below(&r, 4)) {
            case 0: b[at] ^= (uint8_t)(1u << tsup_rng_below(&r, 8)); break;
            case 1: b[at] = (uint8_t)tsup_rng_u32(&r); break;
            case 2: b[tsup_rng_below(&r, 32 + 16 * 5 + 96)] = (uint8_t)tsup_rng_u32(&r); break;
            default: n = tsup_rng_below(&r, (uint32_t)n) + 1; break;
            }
        }
        if (tsup_rng_below(&r, 8) != 0 && n >= 24) {
            tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, 0);
            tsup_wr32(b + PSC_CONTAINER_CRC_OFFSET, psc_crc32(0, b, n));
        }
        psc_shadow_model_t m;
        psc_container_error_t e = {NULL, 0};
        if (psc_shadow_parse(b, n, &m, &e) == PSC_OK) {
            parsed++;
            psc_shadow_t s;
            psc_patch_model_t pm = {0};
            pm.bone_count = m.bone_count;
            void *ws = malloc(psc_shadow_workspace_size(&m, &pm) + 8);
            if (m.bone_count == 0 && psc_shadow_init(&s, &m, &pm, ws, psc_shadow_workspace_size(&m, &pm)) == PSC_OK) {
                const int32_t o[3] = {0, 0, 0}, up[3] = {0, 65536, 0};
                assert_true(psc_shadow_occlusion(&s, o, up) <= 65536);
            }
            free(ws);
        } else {
            assert_non_null(e.what);
            refused++;
        }
        free(b);
    }
    print_message("  4000 mutated shadow packs: %u parsed, %u refused with a message\n", parsed, refused);
    assert_true(refused > 0);
    free(buf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_access_closed_form),
        cmocka_unit_test(test_composite_map),
        cmocka_unit_test(test_overlap),
        cmocka_unit_test(test_against_raycast),
        cmocka_unit_test(test_gltf_against_raycast),
        cmocka_unit_test(test_heldout_against_raycast),
        cmocka_unit_test(test_rest_section),
        cmocka_unit_test(test_phase_section),
        cmocka_unit_test(test_grid_section),
        cmocka_unit_test(test_gltf_fuzz),
        cmocka_unit_test(test_armpits_darken),
        cmocka_unit_test(test_pack_fuzz),
    };
    if (getenv("PSC_SHADOW_ONLY"))   /* one test while working on it, e.g. test_against_raycast */
        cmocka_set_test_filter(getenv("PSC_SHADOW_ONLY"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
