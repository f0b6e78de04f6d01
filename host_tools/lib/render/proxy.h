/* SPDX-License-Identifier: MIT */
/*
 * proxy.h - periscope-render's proxy-pack mode: a model baked by
 * periscope-proxy, posed, and drawn by the device's own run time
 * (core/proxy) as proxies with view textures, or as its full mesh.
 *
 *   periscope-render M.ppx --orbit Y,P,D --hfov F --size WxH [--pose rest|t=SECONDS|POSE.json] [--full]
 *                    [--depth d.pgm] [--ids ids.pgm] [--repeat K] [--tiles N] [--format rgb565|xrgb8888] -o out.png
 *
 * The orbit camera is centred on the rest pose's bounding box for every pose.
 * --ids writes a 16-bit PGM: part index + 1 of the front-most surface, 0 for
 * the background.
 */
#ifndef PSC_RENDER_PROXY_H
#define PSC_RENDER_PROXY_H

#include <stdbool.h>

#include "3d/psc_3d_math.h"
#include "proxy/psc_proxy.h"

/** Whether the command line names a proxy pack. */
bool psc_render_proxy_wanted(int argc, char **argv);

/** Run the mode; the process exit status (2 for bad arguments). */
int psc_render_proxy_main(const char *prog, int argc, char **argv);

/**
 * The skin matrices of POSE.json's adjustments (pre, post per joint, model units, NULL: none) on top of the
 * animation at time t (seconds, < 0 rest): local' = pre x local x post through the pack's skeleton. skin:
 * joint_count matrices. 0, or -1 out of memory.
 */
int psc_render_proxy_pose(const psc_proxy_model_t *m, double t, const double (*pre)[12], const double (*post)[12],
                            psc_mat4_q16_t *skin);

#endif
