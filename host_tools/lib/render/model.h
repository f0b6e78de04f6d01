/* SPDX-License-Identifier: MIT */
/*
 * model.h - periscope-render's model mode: one view of an OBJ file or
 * a mesh pack through the device's 3D pipeline (core/3d/psc_3d_render.h).
 *
 *   periscope-render MODEL.{obj,pmesh} --orbit YAW,PITCH,DIST --hfov F --size WxH
 *       [--texture T.png] [--cull back|none] [--tiles N] [--depth depth.pgm]
 *       [--format rgb565|xrgb8888] [--filter nearest|bilinear] [--shade flat|gouraud|texture]
 *       [--depth-bits 16|32] [--repeat K] [--write-pack OUT.pmesh] -o out.png
 *
 * An OBJ file is first turned into a mesh pack in memory (exactly what
 * --write-pack writes), so the view is what the device shows.
 */
#ifndef PSC_RENDER_MODEL_H
#define PSC_RENDER_MODEL_H

#include <stdbool.h>
#include <stddef.h>

#include "psc_io_load.h"

/** true when the command line names a model (a .obj file or a file with the mesh pack magic). */
bool psc_render_model_wanted(int argc, char **argv);

/** The model at path as a parsed mesh pack in an aligned buffer: a mesh pack read, an OBJ file built in memory
 *  (texture: another image for it, or NULL; write_pack: also write the pack there, or NULL). 0, or -1 with err. */
int psc_render_mesh_load(const char *path, const char *texture, const char *write_pack, psc_io_mesh_t *mf, char *err,
                         size_t errlen);

/** Run the model mode; returns the exit status (0 done, 1 failed, 2 bad arguments). */
int psc_render_model_main(const char *prog, int argc, char **argv);

#endif
