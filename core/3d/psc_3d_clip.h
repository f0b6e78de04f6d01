/* SPDX-License-Identifier: MIT */
/*
 * psc_3d_clip.h - clipping polygons in camera space against the view volume.
 *
 * Camera space (psc_3d_math.h): the camera at the origin looks along +Z.
 * The perspective projection of the pipeline maps a point (x, y, z) with
 * z > 0 to the raster position
 *     sx = W/2 + f x / z,   sy = H/2 - f y / z,   f = (W/2) / tan(hfov/2)
 * (the viewer's pixel-ray convention, pixel centres at half-integers), and
 * this is the homogeneous clip space (f x, f y, z) with w = z. The clipper
 * keeps the part of a polygon inside six planes, in this order:
 *   near  z >= near          nothing behind (or at) the camera is drawn
 *   far   z <= far
 *   left/right  |f x| <= gx z,   bottom/top  |f y| <= gy z
 * where gx = W/2 + PSC_3D_GUARD_PX and gy = H/2 + PSC_3D_GUARD_PX: a guard
 * band around the screen. Triangles crossing the screen edges inside the
 * band are not clipped (the rasterizer's bounding box does that exactly);
 * the band only keeps raster coordinates below PSC_RASTER_COORD_MAX_Q4.
 * Every plane distance is exact in int64 (|x|, |z| < 2^31, f and g in Q24.8
 * below 2^27). An edge crossing a plane is cut at t = d0 / (d0 - d1) in
 * Q2.30, its endpoints taken in a canonical order so that the two triangles
 * sharing an edge cut it at the same point (no cracks).
 */
#ifndef PSC_3D_CLIP_H
#define PSC_3D_CLIP_H

#include "base/psc_types.h"

#define PSC_3D_GUARD_PX 2048
/* A triangle clipped by six planes has at most 3 + 6 vertices. */
#define PSC_3D_CLIP_MAX_VERTICES 9u

enum {
    PSC_CLIP_NEAR = 1u << 0,
    PSC_CLIP_FAR = 1u << 1,
    PSC_CLIP_LEFT = 1u << 2,
    PSC_CLIP_RIGHT = 1u << 3,
    PSC_CLIP_BOTTOM = 1u << 4,
    PSC_CLIP_TOP = 1u << 5,
    PSC_CLIP_PLANES = 6
};

/** A polygon vertex: camera position and the attributes interpolated along with it. */
typedef struct {
    int32_t x, y, z;          /* camera space, Q16.16 units */
    int32_t u_q16, v_q16;     /* texture coordinates */
    int32_t r, g, b;          /* colour channels 0..255 */
    int32_t light_q8;         /* 0..256 */
    int32_t u1_q16, v1_q16, u2_q16, v2_q16;  /* the second and third view textures' (PSC_SHADE_VIEWS) */
    int32_t nx_q14, ny_q14, nz_q14;          /* the normal (PSC_SHADE_PHONG), camera space */
} psc_clip_vertex_t;

/** The view volume, in the units of psc_3d_clip.h's comment. */
typedef struct {
    int32_t near_q16, far_q16;
    int64_t f_q8;             /* focal length in pixels, Q24.8 */
    int64_t gx_q8, gy_q8;     /* guard-band half extents in pixels, Q24.8 */
} psc_clip_volume_t;

/** Bit set of the planes a camera-space point lies outside of. */
unsigned psc_clip_outcode(const psc_clip_volume_t *vol, int32_t x, int32_t y, int32_t z);

/**
 * Clip the convex polygon in[0..n) against every plane set in planes; out
 * receives at most PSC_3D_CLIP_MAX_VERTICES vertices (n <= 3 + the planes
 * already applied). Returns the vertex count, 0 when nothing is left.
 * Cut points on the near (far) plane get z = near (far) exactly.
 */
unsigned psc_clip_polygon(const psc_clip_volume_t *vol, unsigned planes, const psc_clip_vertex_t *in, unsigned n,
                          psc_clip_vertex_t *out);

#endif
