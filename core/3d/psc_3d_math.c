/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_math.c - Q16.16 matrices and vectors (conventions: psc_3d_math.h).
 */
#include "3d/psc_3d_math.h"

static int32_t sat32(int64_t v)
{
    return v > INT32_MAX ? INT32_MAX : v < INT32_MIN ? INT32_MIN : (int32_t)v;
}

void psc_mat4_identity(psc_mat4_q16_t *m)
{
    for (unsigned r = 0; r < 4; r++)
        for (unsigned c = 0; c < 4; c++)
            m->m[r][c] = r == c ? PSC_Q16_ONE : 0;
}

void psc_mat4_mul(psc_mat4_q16_t *out, const psc_mat4_q16_t *a, const psc_mat4_q16_t *b)
{
    psc_mat4_q16_t t;
    for (unsigned r = 0; r < 4; r++)
        for (unsigned c = 0; c < 4; c++) {
            /* Four products of two int32 each below 2^62: the sum is kept
             * below 2^63 by halving before adding. */
            int64_t s = 0;
            for (unsigned k = 0; k < 4; k++)
                s += ((int64_t)a->m[r][k] * b->m[k][c]) >> 2;
            t.m[r][c] = sat32(psc_shr_round64(s, 14));
        }
    *out = t;
}

void psc_mat4_translate(psc_mat4_q16_t *m, psc_vec3_q16_t t)
{
    psc_mat4_identity(m);
    m->m[0][3] = t.x;
    m->m[1][3] = t.y;
    m->m[2][3] = t.z;
}

void psc_mat4_scale(psc_mat4_q16_t *m, int32_t s_q16)
{
    psc_mat4_identity(m);
    m->m[0][0] = m->m[1][1] = m->m[2][2] = s_q16;
}

/* sin and cos in Q16.16, rounded from CORDIC's Q2.30. */
static void sincos_q16(psc_bam_t a, int32_t *s, int32_t *c)
{
    int32_t s30, c30;
    psc_sincos(a, &s30, &c30);
    *s = (int32_t)psc_shr_round64(s30, 14);
    *c = (int32_t)psc_shr_round64(c30, 14);
}

void psc_mat4_rotate_y(psc_mat4_q16_t *m, psc_bam_t yaw)
{
    int32_t s, c;
    sincos_q16(yaw, &s, &c);
    psc_mat4_identity(m);
    m->m[0][0] = c;   /* x' = x cos + z sin */
    m->m[0][2] = s;
    m->m[2][0] = -s;  /* z' = -x sin + z cos */
    m->m[2][2] = c;
}

void psc_mat4_rotate_x(psc_mat4_q16_t *m, psc_bam_t pitch)
{
    int32_t s, c;
    sincos_q16(pitch, &s, &c);
    psc_mat4_identity(m);
    m->m[1][1] = c;   /* y' = y cos + z sin */
    m->m[1][2] = s;
    m->m[2][1] = -s;  /* z' = -y sin + z cos */
    m->m[2][2] = c;
}

void psc_mat4_rotate_z(psc_mat4_q16_t *m, psc_bam_t roll)
{
    int32_t s, c;
    sincos_q16(roll, &s, &c);
    psc_mat4_identity(m);
    m->m[0][0] = c;   /* x' = x cos - y sin */
    m->m[0][1] = -s;
    m->m[1][0] = s;   /* y' = x sin + y cos */
    m->m[1][1] = c;
}

void psc_mat4_camera(psc_mat4_q16_t *m, psc_vec3_q16_t eye, psc_bam_t yaw, int32_t pitch)
{
    psc_mat4_q16_t t, ry, rx;
    psc_mat4_translate(&t, (psc_vec3_q16_t){-eye.x, -eye.y, -eye.z});
    psc_mat4_rotate_y(&ry, 0u - yaw);
    psc_mat4_rotate_x(&rx, 0u - (psc_bam_t)pitch);
    psc_mat4_mul(m, &ry, &t);
    psc_mat4_mul(m, &rx, m);
}

bool psc_mat4_apply(const psc_mat4_q16_t *m, psc_vec3_q16_t p, psc_vec3_q16_t *out)
{
    int32_t r[3];
    for (unsigned i = 0; i < 3; i++) {
        /* |m| < 2^24 and |p| < 2^31: each product < 2^55, the sum < 2^57. */
        int64_t s = (int64_t)m->m[i][0] * p.x + (int64_t)m->m[i][1] * p.y + (int64_t)m->m[i][2] * p.z;
        s = psc_shr_round64(s, 16) + m->m[i][3];
        if (s > INT32_MAX || s < INT32_MIN)
            return false;
        r[i] = (int32_t)s;
    }
    out->x = r[0];
    out->y = r[1];
    out->z = r[2];
    return true;
}

psc_vec3_q16_t psc_mat4_apply_dir(const psc_mat4_q16_t *m, psc_vec3_q16_t d)
{
    int32_t r[3];
    for (unsigned i = 0; i < 3; i++) {
        int64_t s = (int64_t)m->m[i][0] * d.x + (int64_t)m->m[i][1] * d.y + (int64_t)m->m[i][2] * d.z;
        r[i] = sat32(psc_shr_round64(s, 16));
    }
    return (psc_vec3_q16_t){r[0], r[1], r[2]};
}

psc_vec3_q16_t psc_vec3_normalize(psc_vec3_q16_t d)
{
    int64_t x = d.x, y = d.y, z = d.z;
    /* Scale into [2^20, 2^30) first so the squared length fits and keeps precision. */
    uint64_t m = (uint64_t)(x < 0 ? -x : x) | (uint64_t)(y < 0 ? -y : y) | (uint64_t)(z < 0 ? -z : z);
    if (m == 0)
        return d;
    while (m >= ((uint64_t)1 << 30)) {
        x /= 2;
        y /= 2;
        z /= 2;
        m >>= 1;
    }
    while (m < ((uint64_t)1 << 20)) {
        x *= 2;
        y *= 2;
        z *= 2;
        m <<= 1;
    }
    uint64_t len = psc_isqrt64((uint64_t)(x * x + y * y + z * z)); /* < 2^31 */
    if (len == 0)
        return (psc_vec3_q16_t){0, 0, 0};
    return (psc_vec3_q16_t){(int32_t)psc_div_round64(x * 65536, (int64_t)len),
                            (int32_t)psc_div_round64(y * 65536, (int64_t)len),
                            (int32_t)psc_div_round64(z * 65536, (int64_t)len)};
}
