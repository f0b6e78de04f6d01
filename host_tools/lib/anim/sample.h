/* SPDX-License-Identifier: MIT */
/*
 * sample.h - motion sampled on the host (a rig played by an action, or
 * motion capture retargeted) baked into a patch character's channels: for
 * every bone that moves, its rotation and translation relative to its rest
 * pose, one key per sample, in the device's bone convention
 * (core/patch/psc_patch_anim.c: parent x translate(offset) x rotate(rest) x
 * translate(t) x rotate(q)).
 */
#ifndef PSC_ANIM_SAMPLE_H
#define PSC_ANIM_SAMPLE_H

#include <stddef.h>

#include "import/patch_source.h"

/** A bone posed: model-space rotation (x y z w) and head position, source units. */
typedef struct {
    double rot[4];
    double head[3];
} psc_bone_pose_t;

/** Bone b's rest rotation relative to its parent's, and its rest head in the parent's rest frame (source units;
 *  a top bone: its model-space rotation and head). */
void psc_anim_rest_relative(const psc_patch_src_t *s, size_t b, double rel[4], double off[3]);

/**
 * Add an action named name of duration seconds to s from frames samples
 * (evenly spaced over [0, duration]) of every bone's pose: pose[f *
 * s->bone_count + b]. Bones that never leave their rest pose get no channel.
 * 0, or -1 with err.
 */
int psc_anim_sample(psc_patch_src_t *s, const char *name, double duration, size_t frames, const psc_bone_pose_t *pose,
                   char *note, size_t notelen, char *err, size_t errlen);

#endif
