/* SPDX-License-Identifier: MIT */
/* quat.h - unit quaternions (x y z w) in double precision for the host's rigs and writers. */
#ifndef PSC_UTIL_QUAT_H
#define PSC_UTIL_QUAT_H

/** out = a b (out may be a or b) */
void psc_quat_mul(const double a[4], const double b[4], double out[4]);
/** the inverse of a unit quaternion */
void psc_quat_conj(const double q[4], double out[4]);
/** scaled to unit length; a zero quaternion becomes the identity */
void psc_quat_normalize(double q[4]);
/** v turned by q (out may be v) */
void psc_quat_rotate(const double q[4], const double v[3], double out[3]);
/** the least rotation taking direction a to direction b (need not be unit) */
void psc_quat_swing(const double a[3], const double b[3], double q[4]);
/** the rotation by angle (radians) about the unit axis */
void psc_quat_axis_angle(const double axis[3], double angle, double q[4]);

#endif
