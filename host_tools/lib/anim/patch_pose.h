/* SPDX-License-Identifier: MIT */
/*
 * patch_pose.h - a pose file (pose_file.h) on a patch character: its nodes
 * are the character's bones, by number (a patch pack keeps no bone names);
 * local' = T . local . R becomes the bone's animated rotation times R and its
 * animated translation plus T brought into the bone's rest frame.
 */
#ifndef PSC_ANIM_PATCH_POSE_H
#define PSC_ANIM_PATCH_POSE_H

#include <stddef.h>

#include "import/pose_file.h"
#include "patch/psc_patch_frame.h"

/** Whether pf's nodes all name bones of m (by number). 0, or -1 with err naming path and the node. */
int psc_anim_patch_pose_check(const psc_patch_model_t *m, const psc_pose_file_t *pf, const char *path, char *err,
                         size_t errlen);

/** Adjust p's bones by pf (checked), between psc_patch_pose_begin and psc_patch_pose_finish. Translations are in
 *  the model's own units (the pack's R converts them). */
void psc_anim_patch_pose(psc_patch_t *p, const psc_pose_file_t *pf);

#endif
