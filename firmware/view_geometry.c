/* SPDX-License-Identifier: MIT */
/*
 * view_geometry.c - pixel to direction and the grab solve (view_geometry.h).
 */
#include "view_geometry.h"
#include "base/psc_fixed.h"

/* A unit vector in Q2.30 from components of any size up to 2^62. */
static void geom_normalize(int64_t v[3])
{
    int64_t m = 0;
    unsigned shift = 0;

    for (int i = 0; i < 3; i++)
        m |= v[i] < 0 ? -v[i] : v[i];
    while ((m >> shift) >= ((int64_t)1 << 31))
        shift++;
    uint64_t sq = 0;
    int64_t s[3];
    for (int i = 0; i < 3; i++) {
        s[i] = v[i] >> shift;   /* the three lose the same low bits: the direction keeps 31 */
        sq += (uint64_t)(s[i] * s[i]);
    }
    uint32_t len = psc_isqrt64(sq);
    for (int i = 0; i < 3; i++)
        v[i] = len ? psc_div_round64(s[i] * PSC_Q30_ONE, len) : (i == 2 ? PSC_Q30_ONE : 0);
}

/* The camera-axis ray of pixel (x, y), unit, Q2.30: x right, y up, z ahead. */
static void geom_camera_ray(psc_bam_t hfov, uint16_t width, uint16_t height, int32_t x, int32_t y, int64_t c[3])
{
    int32_t shh, chh;

    psc_sincos(hfov / 2u, &shh, &chh);
    /* half-pixels times sin(hfov/2), and the plane's distance width / tan(hfov/2) times the same */
    c[0] = (2 * (int64_t)x + 1 - width) * shh;
    c[1] = ((int64_t)height - 1 - 2 * (int64_t)y) * shh;
    c[2] = (int64_t)width * chh;
    geom_normalize(c);
}

static int32_t geom_mul_q30(int64_t a, int64_t b)
{
    return (int32_t)psc_shr_round64(a * b, 30);
}

void psc_view_unproject(const psc_view_t *view, uint16_t width, uint16_t height, int32_t x, int32_t y,
                        psc_bam_t *yaw, int32_t *pitch)
{
    int64_t c[3];
    int32_t svp, cvp;
    uint32_t hor;

    geom_camera_ray(view->hfov, width, height, x, y, c);
    psc_sincos((psc_bam_t)view->pitch, &svp, &cvp);
    /* camera to world: turn up by the view's pitch (hotspots.c turns the other way) */
    int32_t wx = (int32_t)c[0];
    int32_t wy = geom_mul_q30(c[1], cvp) + geom_mul_q30(c[2], svp);
    int32_t wz = geom_mul_q30(c[2], cvp) - geom_mul_q30(c[1], svp);
    *yaw = view->yaw + psc_atan2(wx, wz, &hor);
    *pitch = (int32_t)psc_atan2(wy, (int32_t)(hor > INT32_MAX ? INT32_MAX : hor), NULL);
}

bool psc_view_grab(const psc_view_t *view, uint16_t width, uint16_t height, int32_t x, int32_t y, psc_bam_t yaw,
                   int32_t pitch, psc_view_t *out)
{
    int64_t c[3];
    int32_t sp, sv, cv;
    uint32_t r;
    bool exact = true;

    geom_camera_ray(view->hfov, width, height, x, y, c);
    psc_sincos((psc_bam_t)pitch, &sp, NULL);
    /* the world height of the ray after turning up by v is cy cos v + cz sin v = r sin(phi + v),
     * phi the ray's angle above the axis in the y-z plane: phi + v = asin(sin(pitch) / r) */
    psc_bam_t phi = psc_atan2((int32_t)c[1], (int32_t)c[2], &r);
    int64_t s = r ? psc_div_round64((int64_t)sp * PSC_Q30_ONE, r) : 0;
    if (s > PSC_Q30_ONE || s < -PSC_Q30_ONE) {
        s = s > 0 ? PSC_Q30_ONE : -PSC_Q30_ONE;
        exact = false;
    }
    int32_t cs = (int32_t)psc_isqrt64((uint64_t)((int64_t)PSC_Q30_ONE * PSC_Q30_ONE - s * s));
    int64_t v = (int64_t)(int32_t)psc_atan2((int32_t)s, cs, NULL) - (int64_t)(int32_t)phi;
    if (v > (int64_t)PSC_BAM_90 || v < -(int64_t)PSC_BAM_90) {
        v = v > 0 ? (int64_t)PSC_BAM_90 : -(int64_t)PSC_BAM_90;   /* the view would turn over the pole */
        exact = false;
    }
    psc_sincos((psc_bam_t)v, &sv, &cv);
    int32_t wz = geom_mul_q30(c[2], cv) - geom_mul_q30(c[1], sv);
    *out = *view;
    out->pitch = (int32_t)v;
    out->yaw = yaw - psc_atan2((int32_t)c[0], wz, NULL);
    return exact;
}
