/* SPDX-License-Identifier: MIT */
/*
 * gltf.h - periscope-render's glTF mode: an articulated or skinned
 * model (gltf_model.h) posed, optionally self-shadowed by the device's own
 * integer run time (core/shadow), and drawn by the device's 3D pipeline.
 *
 *   periscope-render MODEL.{gltf,glb} -o view.png [--orbit Y,P,D] [--hfov F] [--size WxH]
 *                    [--pose rest|t=SECONDS] [--shadow M.pao [--dump-ao AO.csv]] [--repeat K]
 *
 * The model is drawn in the frame of its rest pose (centre and R of its
 * bounding box) for every pose; lighting: vertex colour = base colour x
 * (0.45 + 0.55 max(0, n.L)), L = normalize(0.4, 0.8, 0.45) in model space, n
 * the posed normal (bent by the self-shadowing), Gouraud between vertices.
 */
#ifndef PSC_RENDER_GLTF_H
#define PSC_RENDER_GLTF_H

#include <stdbool.h>

/** Whether the command line names a glTF model. */
bool psc_render_gltf_wanted(int argc, char **argv);

/** Run the mode; the process exit status (2 for bad arguments). */
int psc_render_gltf_main(const char *prog, int argc, char **argv);

#endif
