/* SPDX-License-Identifier: MIT */
/*
 * pano.h - periscope-render's panorama mode: a perspective view of a scene
 * pack (.pano), or of an equirectangular JPEG or PNG packed for the output as
 * the device packs one, drawn by the device's own viewer.
 */
#ifndef PSC_RENDER_PANO_H
#define PSC_RENDER_PANO_H

#include <stdbool.h>

/** Always: the mode of whatever file the other modes do not take (render/modes.h keeps it last). */
bool psc_render_pano_wanted(int argc, char **argv);

/** periscope-render in this mode, as prog: 0 done, 1 the work failed, 2 bad arguments. */
int psc_render_pano_main(const char *prog, int argc, char **argv);

#endif
