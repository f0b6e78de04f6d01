/* SPDX-License-Identifier: MIT */
/*
 * patch.h - periscope-render's patch mode: one view of a Hash patch
 * character (an A:M model, a Newell .bpt file or a patch pack) posed by an
 * action at a time, tessellated by core's psc_patch_tessellate and drawn by
 * the device's 3D pipeline.
 *
 *   periscope-render MODEL.{mdl,bpt,ppk} --orbit Y,P,D --hfov F --size WxH
 *       [--flatness TOL | --tol-px P] [--action A.act ...] [--play NAME] [--time T]
 *       [--skin-from D.mdl] [--deform B1,B2..] [--cull back|none] [--tiles N]
 *       [--depth d.pgm] [--stats] [--dump-obj tess.obj] [--write-pack P.ppk] -o out.png
 *
 * The orbit camera is centred on the rest pose's box (R = half its diagonal)
 * at every time, so frames of an action do not jump.
 */
#ifndef PSC_RENDER_PATCH_H
#define PSC_RENDER_PATCH_H

#include <stdbool.h>

/** true when the command line names a patch character (.mdl, .bpt, or a patch pack). */
bool psc_render_patch_wanted(int argc, char **argv);

/** Run the patch mode; returns the exit status (0 done, 1 failed, 2 bad arguments). */
int psc_render_patch_main(const char *prog, int argc, char **argv);

#endif
