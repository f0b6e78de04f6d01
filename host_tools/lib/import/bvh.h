/* SPDX-License-Identifier: MIT */
/*
 * bvh.h - motion capture in the BioVision Hierarchy format (.bvh), and
 * its retargeting onto a patch character's skeleton by bone name.
 *
 * The file: HIERARCHY with one ROOT and nested JOINTs ({ OFFSET x y z,
 * CHANNELS n names..., children, or End Site { OFFSET } }), then MOTION with
 * "Frames: N", "Frame Time: seconds" and N lines of the channels' values in
 * hierarchy order. Rotation channels are degrees, applied in the order they
 * are listed (Zrotation Xrotation Yrotation: R = Rz Rx Ry); the rest pose
 * is every rotation zero, the skeleton standing as its offsets draw it.
 *
 * Retargeting (psc_anim_retarget_bvh): a joint's turn from its rest, in model space,
 * turns the bone a name map pairs it with from the character's own rest
 * pose (both skeletons are taken to stand alike at rest, e.g. T-poses); the
 * root's travel moves the bone the root maps to, scaled by the two
 * skeletons' heights. Bones no joint maps to follow their parents. The map
 * is "bvh_joint = model bone" lines (# comments); without one, the common
 * mocap names (Hips, Spine, Chest, Neck, Head, LeftUpLeg/LeftUpperLeg,
 * LeftLeg, LeftFoot, LeftShoulder/LeftCollar, LeftArm/LeftUpArm,
 * LeftForeArm/LeftLowArm, LeftHand and the right ones) go to bones named
 * like Animation:Master's (Hips, Back, Back2, Neck, Head, Left Thigh, Left
 * Calf, Left Foot, Left Shoulder, Left Bicep, Left Forearm, Left Hand, ...).
 * Sampled at 30 per second. Errors name file:line.
 */
#ifndef PSC_IMPORT_BVH_H
#define PSC_IMPORT_BVH_H

#include <stddef.h>

#include "import/patch_source.h"

#define PSC_BVH_MAX_JOINTS 256u
#define PSC_BVH_MAX_FRAMES 200000u
#define PSC_BVH_NAME_MAX 64u

typedef struct {
    char name[PSC_BVH_NAME_MAX];
    int parent;                  /* -1 for the root */
    double offset[3];
    unsigned channel_first;      /* into a frame's values */
    unsigned channel_count;      /* 0, 3 or 6 */
    unsigned char channel[6];    /* 0..2 X/Y/Z position, 3..5 X/Y/Z rotation */
} psc_bvh_joint_t;

typedef struct {
    psc_bvh_joint_t *joint;
    size_t joint_count;
    unsigned channels;           /* values a frame */
    size_t frames;
    double frame_time;           /* seconds */
    double *value;               /* frames x channels */
} psc_bvh_t;

/** Parse .bvh text[0..len) named name. 0, or -1 with err "name: line N: problem". */
int psc_bvh_parse(const char *name, const char *text, size_t len, psc_bvh_t *out, char *err, size_t errlen);
int psc_bvh_load(const char *path, psc_bvh_t *out, char *err, size_t errlen);
void psc_bvh_free(psc_bvh_t *b);

/** Joints' model-space rotations (x y z w) and positions at frame f. */
void psc_bvh_pose(const psc_bvh_t *b, size_t f, double (*rot)[4], double (*pos)[3]);

/**
 * Retarget b onto the skeleton of s as a new action named name. map_text
 * (may be NULL: the built-in map) pairs joints with bones. 0, or -1 with err.
 */
int psc_anim_retarget_bvh(const psc_bvh_t *b, const char *map_text, const char *name, psc_patch_src_t *s, char *note,
                 size_t notelen, char *err, size_t errlen);

#endif
