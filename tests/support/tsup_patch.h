/* SPDX-License-Identifier: MIT */
/*
 * tsup_patch.h - what the patch tests share (host only: double, heap):
 * tessellators with generous limits, and a double z-buffer rasterizer with
 * psc_3d_render's projection (f = (W/2) / tan(hfov/2), pixel centres, 1/z
 * depth), giving the silhouette and camera depth of every pixel of the
 * double-precision reference surface (measure/surface.h).
 */
#ifndef TSUP_PATCH_H
#define TSUP_PATCH_H

#include <stddef.h>
#include <stdint.h>

#include "patch/psc_patch_frame.h"


/** A tessellator with a heap workspace for the tests (generous limits). */
typedef struct {
    psc_patch_t p;
    void *ws;
} tsup_tess_t;

/** Set up t for model m; 0, or -1 (no memory, bad model). */
int tsup_tess_new(tsup_tess_t *t, const psc_patch_model_t *m);
void tsup_tess_free(tsup_tess_t *t);

/** Pose m as action (-1: rest) at ms and tessellate it finely everywhere (0.01 R, culling off). 0, or -1. */
int tsup_tess_fine(tsup_tess_t *t, int action, uint32_t ms);


/**
 * Rasterize triangles (object space) seen through cam (rigid, Q16.16) with
 * field of view hfov_rad onto w x h pixels: z[w*h] receives the camera depth
 * of the nearest surface at each pixel centre, or INFINITY.
 */
void tsup_patch_raster(const double (*pos)[3], const uint32_t (*tri)[3], size_t n, const psc_mat4_q16_t *cam,
                       double hfov_rad, unsigned w, unsigned h, double *z);

#endif
