/* SPDX-License-Identifier: MIT */
/*
 * am_rig.h - an Animation:Master model's rig played by an action, on the host
 * in double precision, and the action baked into a patch character's
 * channels (psc_anim_sample_am_action).
 *
 * The rig (read as A:M documents its bones and constraints):
 *  - forward kinematics: a bone's model-space rotation is its parent's times
 *    its rest rotation relative to the parent times the action's rotation;
 *    the action's translation moves the bone in its own rest frame, scaled by
 *    the model's ScaleBoneName length over the action's ScaleStandard;
 *  - the constraints the model's switches turn on (the action's <CONSTDRIVER>s
 *    override them): "aim at" turns a bone the least way to point at its
 *    target; "orient like" gives a bone its target's rotation (keeping their
 *    rest offset); "kinematic" on a bone bends it and its parent to reach the
 *    target with its tip: two-bone analytic IK in the plane the chain already
 *    bends in (so the knee or elbow goes where the rig's hinge sets it).
 *    Roll-like and translate-to are not played (a note says so).
 *    Constraints are applied in bone order, three sweeps, so a target later in
 *    the order is up to date.
 */
#ifndef PSC_ANIM_AM_RIG_H
#define PSC_ANIM_AM_RIG_H

#include <stddef.h>

#include "import/am_action.h"
#include "import/am_model.h"
#include "anim/sample.h"
#include "import/patch_source.h"

/** A bone posed (patch_bake.h). */
typedef psc_bone_pose_t psc_am_pose_t;

typedef struct psc_am_rig psc_am_rig_t;

/** A rig for model am playing act (NULL: the rest pose). note receives remarks. NULL out of memory. */
psc_am_rig_t *psc_am_rig_new(const psc_am_model_t *am, const psc_am_action_t *act, char *note, size_t notelen);

/** Every bone of the model at time t (seconds) into pose[bone_count]. */
void psc_am_rig_eval(psc_am_rig_t *rig, double t, psc_am_pose_t *pose);

void psc_am_rig_free(psc_am_rig_t *rig);

/**
 * Bake action act played on model am into a new action of s (built from am
 * by psc_patch_from_am): the rig sampled every frame (30 per second), each
 * bone that moves as rotation and translation channels relative to its rest.
 * 0, or -1 with err.
 */
int psc_anim_sample_am_action(const psc_am_action_t *act, const psc_am_model_t *am, psc_patch_src_t *s, char *note,
                       size_t notelen, char *err, size_t errlen);

#endif
