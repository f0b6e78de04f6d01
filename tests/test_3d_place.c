/* SPDX-License-Identifier: MIT */
/*
 * test_3d_place.c - objects placed in a panorama (core/3d/psc_3d_place.h).
 *
 *  - Where: over 2000 random views (any yaw, across the +-180 degree seam,
 *    pitch up to the poles, hfov 20..120) an object is placed toward the
 *    direction the viewer shows at a random pixel (the exact ray of the
 *    viewer's pinhole, tsup_view_ray, which the viewer's own tests hold it
 *    to). A camera built here in double from the viewer's conventions puts
 *    its centre on that pixel exactly; the product's fixed-point camera puts
 *    every corner of its box within 1/20 pixel of where that one does (the
 *    pipeline's projection is the pinhole's: test_3d_golden), and the frame
 *    drawn covers the pixel. The box is 8..40 pixels wide, anywhere in its
 *    own units, of any R.
 *  - Which side: at turn 0 the visitor sees its +Z face (a glTF asset's
 *    front) from every direction; at turn 180 degrees its -Z face; at 90
 *    degrees its -X face.
 *  - Depth: of two objects in one direction, the nearer (by distance in R,
 *    whatever their scales) hides the other; the planes hold both.
 *  - Range limits: distances and scales beyond their ranges, an object too
 *    small for its scale or too far from its origin are refused; at the
 *    limits that are accepted, every corner of the box transforms in range.
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

#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_place.h"
#include "3d/psc_3d_render.h"
#include "psc_testsupport.h"
#include "tsup_3d.h"

#define W 320u
#define H 240u

/* Face colours: -X, +X, -Y, +Y, -Z, +Z. */
static const uint32_t face_color[6] = {0x100000u, 0x200000u, 0x300000u, 0x400000u, 0x500000u, 0x600000u};

typedef struct {
    int32_t pos[24 * 3];
    uint32_t color[24];
    uint16_t index[36];
    psc_mesh_t mesh;
    psc_vec3_q16_t lo, hi;
} cube_t;

/* A box of half-sides h (units) centred at c, each face its colour. */
static void cube_make(cube_t *k, const double c[3], const double h[3])
{
    unsigned v = 0, t = 0;
    for (unsigned axis = 0; axis < 3; axis++)
        for (int side = -1; side <= 1; side += 2) {
            unsigned u = (axis + 1) % 3, w = (axis + 2) % 3;
            static const int corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
            for (unsigned q = 0; q < 4; q++) {
                double p[3];
                p[axis] = side;
                p[u] = corner[q][0];
                p[w] = corner[q][1];
                for (unsigned a = 0; a < 3; a++)
                    k->pos[3 * (v + q) + a] = (int32_t)lround((c[a] + p[a] * h[a]) * 65536.0);
                k->color[v + q] = face_color[2 * axis + (side > 0)];
            }
            static const uint16_t tri[6] = {0, 1, 2, 0, 2, 3};
            for (unsigned i = 0; i < 6; i++)
                k->index[t++] = (uint16_t)(v + tri[i]);
            v += 4;
        }
    k->mesh = (psc_mesh_t){.vertex_count = 24, .triangle_count = 12, .position_q16 = k->pos, .color = k->color,
                           .index = k->index};
    psc_mesh_bounds_q16(&k->mesh, &k->lo, &k->hi);
}

static psc_3d_place_t place_deg(double yaw, double pitch, double dist, double scale, double turn)
{
    return (psc_3d_place_t){tsup_bam_from_deg(yaw), (int32_t)lround(pitch / 360.0 * 4294967296.0),
                            (int32_t)lround(dist * 65536), (int32_t)lround(scale * 65536), tsup_bam_from_deg(turn)};
}

/* Draw the objects (one cube each) with the view's camera into out (XRGB, cleared to 0). */
static void draw(const cube_t *const *k, const psc_3d_place_t *pl, unsigned n, const psc_view_t *view,
                 uint32_t *out)
{
    psc_3d_config_t cfg = {W, H, 0, 0, 32, view->hfov, 0, 0, 24 * n, PSC_3D_HSR_ZBUFFER};
    psc_3d_draw_t d[4];
    for (unsigned i = 0; i < n; i++) {
        psc_3d_draw_defaults(&d[i], &k[i]->mesh);
        d[i].cull_back = false;
        d[i].shade = PSC_SHADE_GOURAUD;   /* each face one colour */
        assert_int_equal(psc_3d_place(&pl[i], k[i]->lo, k[i]->hi, view->yaw, view->pitch, &d[i].camera_from_object),
                         PSC_OK);
        psc_3d_place_depth(&pl[i], &cfg.near_q16, &cfg.far_q16);
    }
    psc_3d_place_depth_finish(&cfg.near_q16, &cfg.far_q16);
    tsup_3d_t t;
    assert_int_equal(tsup_3d_init(&t, &cfg), PSC_OK);
    psc_surface_t s = {W, H, W * 4, PSC_PIX_XRGB8888, out};
    uint32_t bg = 0;
    assert_int_equal(psc_3d_render(&t.r, d, n, &bg, &s, NULL), PSC_OK);
    tsup_3d_free(&t);
}

/* The camera in double, from the viewer's conventions alone: Rx(-pitch) Ry(-yaw) of the view, the object's centre
 * dist x 64 along (lon, lat), turned by lon + 180 degrees + turn about +Y, scaled by 64 scale / R about its box's centre. */
static void reference_camera(const psc_view_t *view, double lon, double lat, double dist, double scale, double turn,
                             const cube_t *k, double out[3][4])
{
    double vy = tsup_bam_to_rad(view->yaw), vp = tsup_sbam_to_rad(view->pitch);
    if (view->pitch == (int32_t)PSC_BAM_90 || view->pitch == -(int32_t)PSC_BAM_90)
        vp = view->pitch > 0 ? M_PI / 2 : -M_PI / 2;
    double c[3], h[3];
    c[0] = (k->lo.x + (double)k->hi.x) / 2 / 65536, h[0] = (k->hi.x - (double)k->lo.x) / 2 / 65536;
    c[1] = (k->lo.y + (double)k->hi.y) / 2 / 65536, h[1] = (k->hi.y - (double)k->lo.y) / 2 / 65536;
    c[2] = (k->lo.z + (double)k->hi.z) / 2 / 65536, h[2] = (k->hi.z - (double)k->lo.z) / 2 / 65536;
    double s = 64 * scale / sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]), a = lon + M_PI + turn;
    double ry[3][3] = {{cos(a), 0, sin(a)}, {0, 1, 0}, {-sin(a), 0, cos(a)}};
    double p[3] = {64 * dist * cos(lat) * sin(lon), 64 * dist * sin(lat), 64 * dist * cos(lat) * cos(lon)};
    /* world = ry s (x - c) + p; camera = rx(-vp) ry(-vy) world */
    double cy = cos(-vy), sy = sin(-vy), cp = cos(-vp), sp = sin(-vp);
    double vyaw[3][3] = {{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}};
    double vpit[3][3] = {{1, 0, 0}, {0, cp, sp}, {0, -sp, cp}};
    double v[3][3], lin[3][3];
    for (unsigned i = 0; i < 3; i++)
        for (unsigned j = 0; j < 3; j++) {
            v[i][j] = 0;
            for (unsigned q = 0; q < 3; q++)
                v[i][j] += vpit[i][q] * vyaw[q][j];
        }
    for (unsigned i = 0; i < 3; i++)
        for (unsigned j = 0; j < 3; j++) {
            lin[i][j] = 0;
            for (unsigned q = 0; q < 3; q++)
                lin[i][j] += v[i][q] * ry[q][j] * s;
        }
    for (unsigned i = 0; i < 3; i++) {
        double t = 0;
        for (unsigned j = 0; j < 3; j++) {
            out[i][j] = lin[i][j];
            t += -lin[i][j] * c[j] + v[i][j] * p[j];
        }
        out[i][3] = t;
    }
}

static void test_where(void **state)
{
    (void)state;
    static uint32_t out[W * H];
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 32);
    double worst = 0;
    unsigned poles = 0, seam = 0;
    for (unsigned n = 0; n < 2000; n++) {
        double vy = tsup_rng_range(&rng, -180, 180), vp = tsup_rng_range(&rng, -89.9, 89.9);
        if (n % 10 == 0)
            vp = n % 20 ? 90 : -90;   /* straight up or down */
        if (n % 10 == 1)
            vy = n % 20 > 10 ? 179.99 : -179.99;
        psc_view_t view = tsup_view_deg(vy, vp, tsup_rng_range(&rng, 20, 120), PSC_FILTER_NEAREST, 2);
        double px = tsup_rng_range(&rng, 30, W - 30), py = tsup_rng_range(&rng, 30, H - 30), lon, lat;
        tsup_view_ray(&view, W, H, px, py, &lon, &lat);
        poles += fabs(lat) > 80 * M_PI / 180;
        seam += fabs(lon) > 170 * M_PI / 180;
        /* a cube of 8..40 pixels: its R subtends size / focal radians at dist */
        double focal = W / 2.0 / tan(tsup_bam_to_rad(view.hfov) / 2), size_px = tsup_rng_range(&rng, 8, 40);
        double dist = exp(tsup_rng_range(&rng, log(2), log(200)));
        double scale = dist * size_px / 2 / focal;
        if (scale > 16)
            dist *= 16 / scale, scale = 16;
        if (scale < 1.0 / 64)
            continue;
        double c[3] = {tsup_rng_range(&rng, -50, 50), tsup_rng_range(&rng, -50, 50), tsup_rng_range(&rng, -50, 50)};
        double rr = exp(tsup_rng_range(&rng, log(0.05), log(20))), h = rr / sqrt(3.0);
        if (64 * scale / rr >= 255)
            continue;   /* too small for its scale (test_range_limits) */
        cube_t k;
        cube_make(&k, c, (double[3]){h, h, h});
        psc_3d_place_t pl = place_deg(lon * 180 / M_PI, lat * 180 / M_PI, dist, scale, tsup_rng_range(&rng, 0, 360));
        /* the camera in double from the viewer's conventions puts the object's centre exactly on (px, py) */
        double cam[3][4];
        reference_camera(&view, lon, lat, dist, scale, tsup_bam_to_rad(pl.turn), &k, cam);
        double ctr[3] = {(k.lo.x + (double)k.hi.x) / 2 / 65536, (k.lo.y + (double)k.hi.y) / 2 / 65536,
                         (k.lo.z + (double)k.hi.z) / 2 / 65536}, q[3];
        for (unsigned r = 0; r < 3; r++)
            q[r] = cam[r][0] * ctr[0] + cam[r][1] * ctr[1] + cam[r][2] * ctr[2] + cam[r][3];
        assert_true(fabs(W / 2.0 + focal * q[0] / q[2] - px) < 1e-6 && fabs(H / 2.0 - focal * q[1] / q[2] - py) < 1e-6);
        /* and the product's camera puts every corner of its box where that one does, to 1/20 pixel */
        psc_mat4_q16_t m;
        assert_int_equal(psc_3d_place(&pl, k.lo, k.hi, view.yaw, view.pitch, &m), PSC_OK);
        for (unsigned corner = 0; corner < 8; corner++) {
            psc_vec3_q16_t v = {corner & 1 ? k.hi.x : k.lo.x, corner & 2 ? k.hi.y : k.lo.y,
                                corner & 4 ? k.hi.z : k.lo.z}, o;
            assert_true(psc_mat4_apply(&m, v, &o));
            double d[3] = {v.x / 65536.0, v.y / 65536.0, v.z / 65536.0}, e[3];
            for (unsigned r = 0; r < 3; r++)
                e[r] = cam[r][0] * d[0] + cam[r][1] * d[1] + cam[r][2] * d[2] + cam[r][3];
            double ex = focal * e[0] / e[2], ey = focal * e[1] / e[2];
            double gx = focal * o.x / (double)o.z, gy = focal * o.y / (double)o.z;
            double err = hypot(gx - ex, gy - ey);
            worst = err > worst ? err : worst;
            assert_true(err < 0.05);
        }
        /* drawn, it covers that pixel */
        const cube_t *kp = &k;
        draw(&kp, &pl, 1, &view, out);
        assert_true((out[(unsigned)py * W + (unsigned)px] & 0xFFFFFFu) != 0);
    }
    print_message("  2000 placements: the box's corners at most %.4f px from the double-precision camera's "
                  "(%u near the poles, %u across the seam)\n", worst, poles, seam);
    assert_true(poles > 20 && seam > 20);
}

/* The colour at the centre of the frame of a cube placed straight ahead of the view. */
static uint32_t centre_face(double view_yaw, double pitch, double turn)
{
    static uint32_t out[W * H];
    cube_t k;
    cube_make(&k, (double[3]){3, -2, 7}, (double[3]){0.5, 0.5, 0.5});
    psc_view_t view = tsup_view_deg(view_yaw, pitch, 60, PSC_FILTER_NEAREST, 2);
    psc_3d_place_t pl = place_deg(view_yaw, pitch, 4, 1, turn);
    const cube_t *kp = &k;
    draw(&kp, &pl, 1, &view, out);
    return out[(H / 2) * W + W / 2] & 0xFFFFFFu;
}

static void test_which_side(void **state)
{
    (void)state;
    for (int yaw = -180; yaw < 180; yaw += 15) {
        assert_int_equal(centre_face(yaw, 0, 0), face_color[5]);    /* +Z: its front */
        assert_int_equal(centre_face(yaw, 20, 180), face_color[4]); /* turned round: -Z */
        assert_int_equal(centre_face(yaw, -10, 90), face_color[0]); /* turned as yaw turns: -X faces the visitor */
    }
}

static void test_depth_order(void **state)
{
    (void)state;
    static uint32_t out[W * H];
    tsup_rng_t rng;
    tsup_rng_seed(&rng, 7);
    for (unsigned n = 0; n < 200; n++) {
        cube_t a, b;
        double ha = tsup_rng_range(&rng, 3, 10), hb = tsup_rng_range(&rng, 3, 10);
        cube_make(&a, (double[3]){0, 0, 0}, (double[3]){ha, ha, ha});
        cube_make(&b, (double[3]){5, 5, 5}, (double[3]){hb, hb, hb});
        double yaw = tsup_rng_range(&rng, -180, 180), pitch = tsup_rng_range(&rng, -60, 60);
        double near = tsup_rng_range(&rng, 2, 20), far = near * tsup_rng_range(&rng, 1.5, 4);
        /* the same apparent size: scale in proportion to distance */
        psc_3d_place_t pl[2] = {place_deg(yaw, pitch, far, far / 8, 0), place_deg(yaw, pitch, near, near / 8, 0)};
        const cube_t *k[2] = {&a, &b};
        psc_view_t view = tsup_view_deg(yaw, pitch, 60, PSC_FILTER_NEAREST, 2);
        for (unsigned i = 0; i < 24; i++)
            b.color[i] = 0x00FF00u;   /* the nearer one, green all over */
        unsigned first = n & 1u;   /* either order of submission */
        psc_3d_place_t order[2] = {pl[first], pl[1 - first]};
        const cube_t *ko[2] = {k[first], k[1 - first]};
        draw(ko, order, 2, &view, out);
        unsigned green = 0, other = 0;
        for (unsigned i = 0; i < W * H; i++)
            green += (out[i] & 0xFFFFFFu) == 0x00FF00u, other += (out[i] & 0xFFFFFFu) != 0 && (out[i] & 0xFFFFFFu) != 0x00FF00u;
        assert_int_equal(out[(H / 2) * W + W / 2] & 0xFFFFFFu, 0x00FF00u);
        assert_true(green > 100);
        assert_true(other * 20 < green);   /* the farther one shows at most along the nearer one's edges */
    }
}

static void test_range_limits(void **state)
{
    (void)state;
    cube_t k;
    cube_make(&k, (double[3]){0, 0, 0}, (double[3]){1, 1, 1});
    psc_mat4_q16_t m;
    psc_3d_place_t ok = place_deg(10, 5, 4, 1, 0), bad;
    assert_int_equal(psc_3d_place(&ok, k.lo, k.hi, 0, 0, &m), PSC_OK);
    bad = ok, bad.dist_q16 = PSC_3D_PLACE_DIST_MIN_Q16 - 1;
    assert_int_equal(psc_3d_place(&bad, k.lo, k.hi, 0, 0, &m), PSC_ERR_ARG);
    bad = ok, bad.dist_q16 = PSC_3D_PLACE_DIST_MAX_Q16 + 1;
    assert_int_equal(psc_3d_place(&bad, k.lo, k.hi, 0, 0, &m), PSC_ERR_ARG);
    bad = ok, bad.scale_q16 = PSC_3D_PLACE_SCALE_MIN_Q16 - 1;
    assert_int_equal(psc_3d_place(&bad, k.lo, k.hi, 0, 0, &m), PSC_ERR_ARG);
    bad = ok, bad.scale_q16 = PSC_3D_PLACE_SCALE_MAX_Q16 + 1;
    assert_int_equal(psc_3d_place(&bad, k.lo, k.hi, 0, 0, &m), PSC_ERR_ARG);
    bad = ok, bad.pitch = (int32_t)PSC_BAM_90 + 1;
    assert_int_equal(psc_3d_place(&bad, k.lo, k.hi, 0, 0, &m), PSC_ERR_ARG);
    assert_int_equal(psc_3d_place(&ok, k.lo, k.hi, 0, (int32_t)PSC_BAM_90 + 1, &m), PSC_ERR_ARG);
    /* too small for its scale: R of 2^-16 x sqrt(3) units at scale 16 needs k of 2^24 */
    cube_t tiny;
    cube_make(&tiny, (double[3]){0, 0, 0}, (double[3]){1.0 / 65536, 1.0 / 65536, 1.0 / 65536});
    bad = ok, bad.scale_q16 = PSC_3D_PLACE_SCALE_MAX_Q16;
    assert_int_equal(psc_3d_place(&bad, tiny.lo, tiny.hi, 0, 0, &m), PSC_ERR_ARG);
    /* far from its origin: a unit box 30 000 units out, scaled to 16 R */
    cube_t off;
    cube_make(&off, (double[3]){30000, 0, 0}, (double[3]){0.5, 0.5, 0.5});
    assert_int_equal(psc_3d_place(&bad, off.lo, off.hi, 0, 0, &m), PSC_ERR_ARG);
    /* the accepted extremes: every corner in range, the planes valid */
    static const double dists[2] = {1.0 / 16, 256}, scales[2] = {1.0 / 64, 16}, pitches[3] = {-90, 0, 90};
    cube_t big;
    cube_make(&big, (double[3]){-20000, 10000, 2000}, (double[3]){10000, 5000, 12000});
    const cube_t *boxes[2] = {&k, &big};
    for (unsigned b = 0; b < 2; b++)
        for (unsigned i = 0; i < 2; i++)
            for (unsigned j = 0; j < 2; j++)
                for (unsigned p = 0; p < 3; p++)
                    for (int yaw = -180; yaw < 180; yaw += 45) {
                        psc_3d_place_t pl = place_deg(yaw, pitches[p], dists[i], scales[j], yaw * 2);
                        int32_t near = 0, far = 0;
                        psc_3d_place_depth(&pl, &near, &far);
                        psc_3d_place_depth_finish(&near, &far);
                        assert_true(near >= 1 && far >= 2 * near && far / 4097 < near);
                        psc_status_t s = psc_3d_place(&pl, boxes[b]->lo, boxes[b]->hi, (psc_bam_t)yaw * 3u,
                                                      (int32_t)PSC_BAM_90 * (int32_t)(p - 1), &m);
                        double r = b ? sqrt(10000.0 * 10000 + 5000.0 * 5000 + 12000.0 * 12000) : sqrt(3.0);
                        if (64 * scales[j] / r >= 255.99) {   /* k at 256 or more: refused */
                            assert_int_equal(s, PSC_ERR_ARG);
                            continue;
                        }
                        assert_int_equal(s, PSC_OK);
                        /* k's rounding: half a step of its Q16.16 value, relative */
                        double tol = 0.5 / (64 * scales[j] / r * 65536) + 1e-4;
                        for (unsigned c = 0; c < 8; c++) {
                            psc_vec3_q16_t q = {c & 1 ? boxes[b]->hi.x : boxes[b]->lo.x,
                                                c & 2 ? boxes[b]->hi.y : boxes[b]->lo.y,
                                                c & 4 ? boxes[b]->hi.z : boxes[b]->lo.z}, o;
                            assert_true(psc_mat4_apply(&m, q, &o));
                            /* its distance from the eye within the sphere's: (dist +- scale) x PLACE_R, to k's rounding */
                            double d = sqrt((double)o.x * o.x + (double)o.y * o.y + (double)o.z * o.z) / 65536.0;
                            assert_true(d <= (dists[i] + scales[j] * (1 + tol)) * 64 + 0.01);
                            assert_true(d >= (dists[i] - scales[j] * (1 + tol)) * 64 - 0.01);
                        }
                    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_where),
        cmocka_unit_test(test_which_side),
        cmocka_unit_test(test_depth_order),
        cmocka_unit_test(test_range_limits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
