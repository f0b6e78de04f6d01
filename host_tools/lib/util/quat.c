/* SPDX-License-Identifier: MIT */
/* quat.c - quaternions for the host (quat.h). */
#include "util/quat.h"

#include <math.h>
#include <string.h>

void psc_quat_mul(const double a[4], const double b[4], double out[4])
{
    double r[4] = {
        a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
        a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
        a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
        a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
    };
    memcpy(out, r, sizeof r);
}

void psc_quat_conj(const double q[4], double out[4])
{
    out[0] = -q[0];
    out[1] = -q[1];
    out[2] = -q[2];
    out[3] = q[3];
}

void psc_quat_normalize(double q[4])
{
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(n > 0.0)) {
        q[0] = q[1] = q[2] = 0.0;
        q[3] = 1.0;
        return;
    }
    for (unsigned k = 0; k < 4; k++)
        q[k] /= n;
}

void psc_quat_rotate(const double q[4], const double v[3], double out[3])
{
    double p[4] = {v[0], v[1], v[2], 0.0}, c[4], t[4];
    psc_quat_conj(q, c);
    psc_quat_mul(q, p, t);
    psc_quat_mul(t, c, t);
    memcpy(out, t, 3 * sizeof *out);
}

static double unit3(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0.0)
        for (unsigned k = 0; k < 3; k++)
            v[k] /= n;
    return n;
}

void psc_quat_swing(const double a_in[3], const double b_in[3], double q[4])
{
    double a[3] = {a_in[0], a_in[1], a_in[2]}, b[3] = {b_in[0], b_in[1], b_in[2]};
    if (unit3(a) == 0.0 || unit3(b) == 0.0) {
        q[0] = q[1] = q[2] = 0.0;
        q[3] = 1.0;
        return;
    }
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    if (d < -1.0 + 1e-12) {   /* opposite: half a turn about any perpendicular */
        double x[3] = {fabs(a[0]) > 0.9 ? 0.0 : 1.0, fabs(a[0]) > 0.9 ? 1.0 : 0.0, 0.0};
        double p[3] = {a[1] * x[2] - a[2] * x[1], a[2] * x[0] - a[0] * x[2], a[0] * x[1] - a[1] * x[0]};
        unit3(p);
        q[0] = p[0], q[1] = p[1], q[2] = p[2], q[3] = 0.0;
        return;
    }
    q[0] = c[0];
    q[1] = c[1];
    q[2] = c[2];
    q[3] = 1.0 + d;
    psc_quat_normalize(q);
}

void psc_quat_axis_angle(const double axis[3], double angle, double q[4])
{
    double s = sin(angle / 2.0);
    q[0] = axis[0] * s;
    q[1] = axis[1] * s;
    q[2] = axis[2] * s;
    q[3] = cos(angle / 2.0);
}
