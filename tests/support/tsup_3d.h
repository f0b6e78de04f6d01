/* SPDX-License-Identifier: MIT */
/*
 * tsup_3d.h - test helpers for the 3D pipeline (host only: double, heap).
 *
 *  - Generated geometry comes from host_tools/lib/import/model.h (psc_model_t).
 *  - Conversion to a psc_mesh_t the tests own (Q16.16 or normalised Q1.15
 *    positions); the reference renderer reads back the quantised values, so
 *    a comparison measures the rasterizer, not the quantisation.
 *  - A double-precision reference renderer of psc_3d_render's conventions:
 *    the same camera matrices (their Q16.16 entries read exactly), near/far
 *    clipping, exact projection with f = (W/2)/tan(hfov/2), coverage of
 *    pixel centres by exact edge functions with the top-left rule, depth
 *    from 1/z, Gouraud colours linear on the screen, perspective-correct
 *    texture coordinates, nearest/bilinear texels at texel centres with
 *    repeat wrapping, Lambert lighting. No sub-pixel snapping, no fixed point.
 */
#ifndef TSUP_3D_H
#define TSUP_3D_H

#include <stddef.h>
#include <stdint.h>
#include "3d/psc_3d_render.h"
#include "import/model.h"

/** The generated shapes the 3D tests draw. */
typedef enum { TSUP_CUBE, TSUP_SPHERE, TSUP_TORUS, TSUP_TEAPOT } tsup_shape_t;

/** Shape s into g: a unit cube, a 40 x 21 sphere, a 48 x 20 torus, the teapot at 8 steps (free with psc_model_free). */
void tsup_shape_make(tsup_shape_t s, psc_model_t *g);

/** A mesh the tests own, built from a geometry. */
typedef struct {
    psc_mesh_t mesh;
    int16_t *pos_q15;
    int32_t *pos_q16;
    int16_t *normal_q14;
    int16_t *uv_q12;
    uint32_t *color;
    uint16_t *index;
} tsup_mesh_t;

/**
 * normalise != 0: centre on the bounding box and scale the longest half-axis
 * to 32767 (as the mesh pack does), positions Q1.15; otherwise positions are
 * Q16.16 copies of g's. Returns 0, or -1 (too many vertices, no memory).
 */
int tsup_mesh_from_geom(tsup_mesh_t *m, const psc_model_t *g, int normalise);
void tsup_mesh_free(tsup_mesh_t *m);

/** camera_from_object for an orbit camera as periscope-render's --orbit: at distance dist from the origin,
 * looking at it, view turned up by pitch_deg then right by yaw_deg. */
void tsup_orbit_matrix(psc_mat4_q16_t *m, double yaw_deg, double pitch_deg, double dist);

/** A texture the tests own: a w x h checkerboard with colour ramps, RGB565 or XRGB8888. */
typedef struct {
    psc_texture_t tex;
    void *pixels;
} tsup_texture_t;

int tsup_texture_make(tsup_texture_t *t, uint16_t w, uint16_t h, psc_pixfmt_t fmt);
void tsup_texture_free(tsup_texture_t *t);

/** Reference rendering: rgb[w*h*3] in 0..255 and, if cover != NULL, 1 where any triangle drew. */
void tsup_ref_render3d(const psc_3d_config_t *cfg, const psc_3d_draw_t *draws, unsigned n, uint32_t clear_xrgb,
                       double *rgb, uint8_t *cover);

/** The reference at ss x ss samples a pixel (pixel (x, y)'s sample (i, j) at ((i + 0.5)/ss, (j + 0.5)/ss)),
 * box-filtered; covered (may be NULL) receives each pixel's number of samples some triangle drew (ss <= 15). */
void tsup_ref_render3d_ss(const psc_3d_config_t *cfg, const psc_3d_draw_t *draws, unsigned n, uint32_t clear_xrgb,
                          unsigned ss, double *rgb, uint8_t *covered);

/** Fraction of pixels whose largest channel difference from the reference (quantised as the surface stores it) exceeds tol. */
double tsup_frac_differing(const psc_surface_t *s, const double *ref_rgb, double tol);

/** A surface with heap pixels. */
psc_surface_t tsup_surface_new(uint16_t w, uint16_t h, psc_pixfmt_t fmt);
void tsup_surface_free(psc_surface_t *s);

/** A renderer with a heap workspace (free with tsup_3d_free). */
typedef struct {
    psc_3d_t r;
    void *ws;
} tsup_3d_t;

psc_status_t tsup_3d_init(tsup_3d_t *t, const psc_3d_config_t *cfg);
void tsup_3d_free(tsup_3d_t *t);

/** Write a surface as PNG under $PSC_TEST_TMPDIR (for looking at failures); ignores errors. */
void tsup_save_png(const psc_surface_t *s, const char *name);

#endif
