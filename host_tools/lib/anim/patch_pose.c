/* SPDX-License-Identifier: MIT */
/* patch_pose.c - pose files on patch characters (patch_pose.h). */
#include "anim/patch_pose.h"
#include "psc_io_error.h"

#include <math.h>

int psc_anim_patch_pose_check(const psc_patch_model_t *m, const psc_pose_file_t *pf, const char *path, char *err,
                         size_t errlen)
{
    if (pf->has_weights)
        return psc_io_errorf(err, errlen, path, "weights: a patch character has no blend shapes (morph targets)");
    for (unsigned k = 0; k < pf->count; k++)
        if (pf->nodes[k].index < 0 || pf->nodes[k].index >= (long)m->bone_count)
            return psc_io_errorf(err, errlen, path, "node '%s': a patch character's bones are given by number, "
                                 "0..%u", pf->nodes[k].name, m->bone_count ? (unsigned)m->bone_count - 1u : 0u);
    return 0;
}

/* a x b, quaternions (x, y, z, w) */
static void quat_mul(const double a[4], const double b[4], double out[4])
{
    double r[4] = {a[3] * b[0] + b[3] * a[0] + a[1] * b[2] - a[2] * b[1],
                   a[3] * b[1] + b[3] * a[1] + a[2] * b[0] - a[0] * b[2],
                   a[3] * b[2] + b[3] * a[2] + a[0] * b[1] - a[1] * b[0],
                   a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
    double l = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
    for (unsigned k = 0; k < 4; k++)
        out[k] = r[k] / l;
}

/* v rotated by the inverse of unit quaternion q (x, y, z, w): R(q)^T v */
static void rotate_back(const double q[4], const double v[3], double out[3])
{
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
                   2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                   2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
    for (unsigned i = 0; i < 3; i++)
        out[i] = r[i] * v[0] + r[3 + i] * v[1] + r[6 + i] * v[2];
}

void psc_anim_patch_pose(psc_patch_t *p, const psc_pose_file_t *pf)
{
    const psc_patch_model_t *m = p->m;
    double r_units = m->scale_q16 > 0 ? m->scale_q16 / 65536.0 : 1.0;
    for (unsigned k = 0; k < pf->count; k++) {
        const psc_pose_node_t *n = &pf->nodes[k];
        uint32_t b = (uint32_t)n->index;
        if (n->index < 0 || b >= m->bone_count)
            continue;
        if (n->rotate) {
            double h = n->degrees * M_PI / 360.0, q[4], r[4] = {n->axis[0] * sin(h), n->axis[1] * sin(h),
                                                                 n->axis[2] * sin(h), cos(h)};
            for (unsigned c = 0; c < 4; c++)
                q[c] = p->bone_rot_q30[b][c] / 1073741824.0;
            quat_mul(q, r, q);
            for (unsigned c = 0; c < 4; c++)
                p->bone_rot_q30[b][c] = (int32_t)lround(q[c] * 1073741823.0);
        }
        if (n->translate) {
            double rest[4], t[3];
            for (unsigned c = 0; c < 4; c++)
                rest[c] = m->bones[b].rot_q30[c] / 1073741824.0;
            rotate_back(rest, n->t, t);
            for (unsigned c = 0; c < 3; c++)
                p->bone_trans_q16[b][c] += (int32_t)lround(t[c] / r_units * 65536.0);
        }
    }
}
