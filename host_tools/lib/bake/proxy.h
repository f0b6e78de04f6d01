/* SPDX-License-Identifier: MIT */
/*
 * proxy.h - the proxy animator's preprocessing (core/proxy/psc_proxy.h):
 * an articulated or skinned model (gltf_model.h) divided into parts and
 * joints, a proxy surface formed for each, view textures rendered for each
 * by the device's own rasterizer, and the whole written as a proxy pack.
 *
 *  - Parts: the triangles whose three vertices follow the same joint most
 *    (rigid when every vertex follows it alone); joints: the triangles
 *    between parts, grouped by the two parts they join.
 *  - A part's proxy (proxy_envelope.c): a discrete oriented polytope - the
 *    part's support planes along the 49 directions of the view grid and the
 *    box axes, pushed out by 1 % of its size - which contains it by
 *    construction and is as tight as a convex shape can be (a box-like part
 *    gets its six faces). A part whose polytope stands off it by more than
 *    10 % of its radius (area-weighted, from each face's centre to the part)
 *    is halved along its longest axis, up to three times: a wheel pair
 *    becomes two wheels, a ring four arcs. Chosen over the seed's voxel
 *    isosurface (shrunk, then pruned) for its few, exact faces and over a
 *    simplified mesh because it never cuts into the part; the price is the
 *    halving of concave parts (more textures).
 *    A joint's proxy: its own triangles pushed out along the vertex normals
 *    by 0.05 % of R, skinned as they are (they stretch): it lies on the
 *    surface, so its views need no parallax.
 *  - View textures (proxy_views.c): for each proxy and each direction of the
 *    octahedral grid, the proxy's own geometry, orthographic, lit at rest,
 *    fitted to the proxy's bounding sphere; the proxy's vertices projected
 *    the same way give the direction's texture coordinates. Where another
 *    part lies in front at rest the texels stay empty: a proxy stands off its
 *    part, so depth between proxies is only roughly right, and this keeps a
 *    wheel in its wheel well visible through the body's proxy.
 */
#ifndef PSC_BAKE_PROXY_H
#define PSC_BAKE_PROXY_H

#include <stddef.h>
#include <stdint.h>

#include "import/gltf_model.h"

#define PSC_BAKE_PROXY_VIEWS 49u     /* a 7 x 7 grid */
#define PSC_BAKE_PROXY_TEX 64u
#define PSC_BAKE_PROXY_FPS 30.0
#define PSC_BAKE_PROXY_BB_SIDE 5u    /* the billboard: 5 x 5 views ... */
#define PSC_BAKE_PROXY_BB_TEX 32u    /* ... of 32 x 32 texels (50 KB) */

typedef struct {
    unsigned views;                  /* at least this many: the grid side is the smallest odd one that gives them */
    unsigned tex;                    /* texels per side of a view texture, a power of two */
} psc_bake_proxy_opts_t;

/* The default lighting of proxy and full renders alike: base x (0.45 + 0.55 max(0, n.L)), L = normalize(0.4, 0.8,
 * 0.45), model space, n the rest-pose normal. */
uint32_t psc_bake_proxy_light(uint32_t base, const double n[3]);

/**
 * Bake model g (name for messages) into a proxy pack in *out (malloc'd,
 * *len bytes). note receives a one-line summary. 0, or -1 with err naming
 * the file and the problem.
 */
int psc_bake_proxy(const psc_gltf_t *g, const psc_bake_proxy_opts_t *o, const char *name, uint8_t **out, size_t *len,
                   char *note, size_t notelen, char *err, size_t errlen);

/* ---- the pieces, shared by proxy_bake.c, proxy_envelope.c and proxy_views.c ---- */

/** One proxy's geometry while baking: what it is drawn from and the proxy itself, in units of R. */
typedef struct {
    double (*src_pos)[3];            /* the part's own triangles: vertices ... */
    uint32_t *src_color;             /* ... lit at rest ... */
    uint32_t *src_index;             /* ... and triangles (3 each) */
    uint32_t src_vertices, src_triangles;
    double (*prx_pos)[3];            /* the proxy */
    uint32_t *prx_index;
    uint32_t prx_vertices, prx_triangles;
    double centre[3], radius;        /* the proxy's bounding sphere */
} psc_proxy_shape_t;

/** The envelope of a part (its src_*): prx_* filled (malloc'd). 0, or -1 out of memory. */
int psc_bake_proxy_envelope(psc_proxy_shape_t *s);

/** Render shape s's view textures (view_count x tex^2 RGB565) and its proxy's coordinates (view_count x prx_vertices
 *  x 2) for a grid of side x side views; where another of the model's shapes (others[0..n_others), s among them)
 *  lies in front at rest, the texels stay empty. 0, or -1 out of memory. */
int psc_bake_proxy_views(const psc_proxy_shape_t *s, const psc_proxy_shape_t *others, unsigned n_others,
                           unsigned side, unsigned tex, uint16_t *texels, uint16_t *uv);

/** The billboard (the far level of detail): every shape drawn, at rest, into side x side views of tex^2 fitted to
 *  the sphere (centre, radius); axes_q16 receives each view's right and up (Q16.16). 0, or -1 out of memory. */
int psc_bake_proxy_billboard(const psc_proxy_shape_t *shapes, unsigned n, const double centre[3], double radius,
                               unsigned side, unsigned tex, uint16_t *texels, int32_t *axes_q16);

#endif
