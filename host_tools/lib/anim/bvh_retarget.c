/* SPDX-License-Identifier: MIT */
/* bvh_retarget.c - motion capture retargeted onto a character's skeleton by bone name (bvh.h). */
#include "import/bvh.h"
#include "util/note_text.h"
#include "anim/sample.h"
#include "psc_io_error.h"
#include "util/quat.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define BAKE_FPS 30.0

/* The built-in map: common mocap joint names to Animation:Master's bone names. */
static const char default_map[] =
    "Hips = Hips\nSpine = Back\nSpine1 = Back2\nChest = Back2\nNeck = Neck\nHead = Head\n"
    "LeftCollar = Left Shoulder\nLeftShoulder = Left Shoulder\nLeftUpArm = Left Bicep\nLeftArm = Left Bicep\n"
    "LeftLowArm = Left Forearm\nLeftForeArm = Left Forearm\nLeftHand = Left Hand\n"
    "LeftUpLeg = Left Thigh\nLeftUpperLeg = Left Thigh\nLeftHip = Left Thigh\nLeftLowLeg = Left Calf\n"
    "LeftLeg = Left Calf\nLeftKnee = Left Calf\nLeftFoot = Left Foot\nLeftAnkle = Left Foot\n"
    "LeftToeBase = Left Toes\nLeftToe = Left Toes\n"
    "RightCollar = Right Shoulder\nRightShoulder = Right Shoulder\nRightUpArm = Right Bicep\nRightArm = Right Bicep\n"
    "RightLowArm = Right Forearm\nRightForeArm = Right Forearm\nRightHand = Right Hand\n"
    "RightUpLeg = Right Thigh\nRightUpperLeg = Right Thigh\nRightHip = Right Thigh\nRightLowLeg = Right Calf\n"
    "RightLeg = Right Calf\nRightKnee = Right Calf\nRightFoot = Right Foot\nRightAnkle = Right Foot\n"
    "RightToeBase = Right Toes\nRightToe = Right Toes\n";

static void trim(char *s)
{
    size_t n = strlen(s), a = 0;
    while (a < n && (s[a] == ' ' || s[a] == '\t'))
        a++;
    while (n > a && strchr(" \t\r", s[n - 1]))
        n--;
    memmove(s, s + a, n - a);
    s[n - a] = '\0';
}

/* joint_of[bone] from "joint = bone" lines; returns how many bones got a joint, or -1 with err. */
static int read_map(const psc_bvh_t *b, const char *text, const psc_patch_src_t *s, int *joint_of, const char *name,
                    char *err, size_t errlen)
{
    unsigned line = 0;
    int mapped = 0;
    for (size_t i = 0; i < s->bone_count; i++)
        joint_of[i] = -1;
    for (const char *p = text; *p;) {
        const char *e = strchr(p, '\n');
        size_t n = e ? (size_t)(e - p) : strlen(p);
        char buf[256];
        line++;
        if (n >= sizeof buf)
            return psc_io_errorf(err, errlen, name, "map line %u is too long", line);
        memcpy(buf, p, n);
        buf[n] = '\0';
        p = e ? e + 1 : p + n;
        char *hash = strchr(buf, '#');
        if (hash)
            *hash = '\0';
        trim(buf);
        if (buf[0] == '\0')
            continue;
        char *eq = strchr(buf, '=');
        if (eq == NULL)
            return psc_io_errorf(err, errlen, name, "map line %u: expected \"bvh_joint = model bone\"", line);
        *eq = '\0';
        char *joint = buf, *bone = eq + 1;
        trim(joint);
        trim(bone);
        int bi = psc_patch_src_bone(s, bone), ji = -1;
        for (size_t j = 0; j < b->joint_count && ji < 0; j++)
            if (strcasecmp(b->joint[j].name, joint) == 0)
                ji = (int)j;
        if (bi >= 0 && ji >= 0 && joint_of[bi] < 0) {
            joint_of[bi] = ji;
            mapped++;
        }
    }
    return mapped;
}

/* The skeleton's height standing at rest (every channel zero), for scaling the root's travel. */
static double rest_height(const psc_bvh_t *b, double (*rot)[4], double (*pos)[3])
{
    psc_bvh_t rest = *b;
    double *zero = calloc(b->channels, sizeof *zero);
    if (zero == NULL)
        return 0;
    rest.value = zero;
    psc_bvh_pose(&rest, 0, rot, pos);
    free(zero);
    double lo = INFINITY, hi = -INFINITY;
    for (size_t j = 0; j < b->joint_count; j++) {
        lo = fmin(lo, pos[j][1]);
        hi = fmax(hi, pos[j][1]);
    }
    return hi - lo;
}

int psc_anim_retarget_bvh(const psc_bvh_t *b, const char *map_text, const char *name, psc_patch_src_t *s, char *note,
                 size_t notelen, char *err, size_t errlen)
{
    size_t nb = s->bone_count, nj = b->joint_count;
    int rc = -1;

    if (nb == 0)
        return psc_io_errorf(err, errlen, name, "the model has no bones for the motion to move");
    double duration = (double)(b->frames - 1u) * b->frame_time;
    size_t samples = (size_t)floor(duration * BAKE_FPS) + 1u;
    if (samples < 2)
        return psc_io_errorf(err, errlen, name, "%zu frames are no motion to play", b->frames);
    int *joint_of = malloc(nb * sizeof *joint_of);
    double (*jr)[4] = malloc(nj * sizeof *jr), (*jp)[3] = malloc(nj * sizeof *jp);
    double (*rest_r)[4] = malloc(nj * sizeof *rest_r), (*root0)[3] = malloc(nj * sizeof *root0);
    psc_bone_pose_t *pose = malloc(nb * samples * sizeof *pose);
    if (!joint_of || !jr || !jp || !rest_r || !root0 || !pose) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    int mapped = read_map(b, map_text ? map_text : default_map, s, joint_of, name, err, errlen);
    if (mapped < 0)
        goto done;
    if (mapped == 0) {
        psc_io_errorf(err, errlen, name, "no joint maps to a bone of the model (give a map: \"bvh_joint = bone\")");
        goto done;
    }
    double model_h = s->hi[1] - s->lo[1], bvh_h = rest_height(b, rest_r, jp);
    double scale = bvh_h > 0 ? model_h / bvh_h : 1.0;
    psc_bvh_pose(b, 0, jr, root0);   /* the root's place at the first frame: travel is measured from it */
    int root_bone = -1;
    for (size_t i = 0; i < nb; i++)
        if (joint_of[i] == 0)
            root_bone = (int)i;
    for (size_t f = 0; f < samples; f++) {
        size_t frame = (size_t)lround((double)f / BAKE_FPS / b->frame_time);
        psc_bvh_pose(b, frame < b->frames ? frame : b->frames - 1u, jr, jp);
        psc_bone_pose_t *g = pose + f * nb;
        for (size_t i = 0; i < nb; i++) {
            double rb[4], rel[4], off[3], d[3];
            memcpy(rb, s->bone[i].rot, sizeof rb);
            psc_quat_normalize(rb);
            psc_anim_rest_relative(s, i, rel, off);
            if (s->bone[i].parent < 0) {   /* a top bone stays where it stands */
                memcpy(g[i].head, off, sizeof g[i].head);
                memcpy(g[i].rot, rel, sizeof g[i].rot);
            } else {   /* forward kinematics from the parent as posed */
                const psc_bone_pose_t *gp = &g[s->bone[i].parent];
                psc_quat_mul(gp->rot, rel, g[i].rot);
                psc_quat_rotate(gp->rot, off, d);
                for (unsigned k = 0; k < 3; k++)
                    g[i].head[k] = gp->head[k] + d[k];
            }
            int j = joint_of[i];
            if (j >= 0) {   /* the joint's turn from its rest, in model space, from the bone's own rest */
                double rc4[4], turn[4];
                psc_quat_conj(rest_r[j], rc4);
                psc_quat_mul(jr[j], rc4, turn);
                psc_quat_mul(turn, rb, g[i].rot);
                psc_quat_normalize(g[i].rot);
            }
            if ((int)i == root_bone)
                for (unsigned k = 0; k < 3; k++)
                    g[i].head[k] += (jp[0][k] - root0[0][k]) * scale;
        }
    }
    psc_note_add(note, notelen, "%d of the model's %zu bones follow the capture's %zu joints (travel scaled %.3g)",
                 mapped, nb, nj, scale);
    rc = psc_anim_sample(s, name, duration, samples, pose, note, notelen, err, errlen);
done:
    free(joint_of);
    free(jr);
    free(jp);
    free(rest_r);
    free(root0);
    free(pose);
    return rc;
}
