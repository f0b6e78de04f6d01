/* SPDX-License-Identifier: MIT */
/*
 * proxy.h - the proxy animator's preprocessing (core/proxy/psc_proxy.h):
 * an articulated or skinned model (gltf_model.h) divided into parts and
 * joints, a proxy surface formed for each, view textures rendered for each
 * by the device's own rasterizer, and the whole written as a proxy pack.
 *
 *  - Parts: the triangles whose three vertices follow the same joint most
 *    (rigid when every vertex follows it alone); joints: the triangles
 *    between parts, grouped by the two parts they join (the blend zone).
 *  - Proxies (simplify.h): the model simplified as a whole by edge
 *    collapses, no collapse crossing from one part or joint into another, as
 *    far as an error of 1 % of R allows and further (up to 4 %) to at most a
 *    quarter of its triangles (a model of rigid parts alone: 8 %, or 2 000
 *    triangles if more; parts that touch no other then made coarser whatever
 *    their topology, so a machine's bolts stop costing); each part's and
 *    joint's proxy is its piece of the result. The pieces share their border vertices, so they meet
 *    without cracks however the pose bends them, and a joint's proxy is a
 *    simplified strip. Each proxy vertex is the model's own vertex (its skin
 *    weights), pushed out along its normal by 0.05 % of R and by as much as
 *    its piece's surface bulges outside the simplified one (bulges()), so
 *    the proxy holds the silhouette. Chosen over the seed's shrunk voxel
 *    isosurface and over convex envelopes: a simplified surface has fewer
 *    triangles for the same closeness, never stands off concave parts, and
 *    needs no parallax where it lies on the surface.
 *  - View textures (proxy_views.c): for each proxy and each direction of the
 *    octahedral grid, the proxy's piece and its neighbours' (the pieces it
 *    touches) drawn orthographically, lit at rest, fitted to the proxy's
 *    bounding sphere, kept where their surface lies within reach of the
 *    proxy's front (4 times the simplification's error in front of it, 4
 *    times that behind it, in a hollow the proxy spans): the surface under
 *    the proxy wherever it spans, nothing of another part in front of it,
 *    and the rest of the model not drawn at all (at rest an arm hides the
 *    side of the chest that a raised arm shows). The proxy's vertices
 *    projected the same way give the direction's texture coordinates.
 */
#ifndef PSC_BAKE_PROXY_H
#define PSC_BAKE_PROXY_H

#include <stddef.h>
#include <stdint.h>

#include "import/gltf_model.h"

#define PSC_BAKE_PROXY_VIEWS 64u     /* at least 64: a 9 x 9 grid, or 11 x 11 where the texel density holds */
#define PSC_BAKE_PROXY_TEX 256u     /* the largest view texture's side */
#define PSC_BAKE_PROXY_TEX_MB 14.5  /* the view textures' budget, mips included ... */
#define PSC_BAKE_PROXY_PACK_MB 15.0 /* ... and less if the pack would be larger (15 MiB: under 16 MB either way) */
#define PSC_BAKE_PROXY_DENSITY 256.0 /* texels per R at most: proxies are drawn while R is under 200 pixels */
#define PSC_BAKE_PROXY_DENSITY_ENOUGH 200.0 /* a texel a pixel there: more views are worth the density above it */
#define PSC_BAKE_PROXY_FPS 30.0
#define PSC_BAKE_PROXY_BB_SIDE 5u    /* the billboard: 5 x 5 views ... */
#define PSC_BAKE_PROXY_BB_TEX 32u    /* ... of 32 x 32 texels (50 KB) */

#define PSC_BAKE_PROXY_MAX_ERROR 0.01 /* proxies: the model simplified as far as this error allows (units of R) ... */
#define PSC_BAKE_PROXY_SIMPLIFY 0.25  /* ... and further, up to 4 times the error, to at most this share of it */
#define PSC_BAKE_PROXY_SIMPLIFY_RIGID 0.08  /* ... (rigid parts alone, no joint strips to keep whole: this share, */
#define PSC_BAKE_PROXY_RIGID_FLOOR 2000.0   /*      or this many triangles if more: a light model loses nothing) */

typedef struct {
    unsigned views;                  /* at least this many: the smallest odd grid side that gives them, or the next
                                      * ones while the texel density holds and the views stay within twice this */
    unsigned tex;                    /* the largest view texture's side, a power of two */
    double simplify;                 /* the largest share of the model's triangles the proxies keep (0: the default) */
    double tex_mb;                   /* the view textures' budget in MB (0: the default) */
    double pack_mb;                  /* the pack's, the textures cut to fit it (0: the default) */
    bool no_normals;                 /* leave the normals out (1.2's pack: not relightable, its texels denser) */
} psc_bake_proxy_opts_t;

/* The default lighting of proxy and full renders alike: base x (0.45 + 0.55 max(0, n.L)), L = normalize(0.4, 0.8,
 * 0.45), model space, n the rest-pose normal. */
uint32_t psc_bake_proxy_light(uint32_t base, const double n[3]);

/** Unit normal n as a psc_oct16 code (base/psc_oct.h). */
uint16_t psc_bake_proxy_oct16(const double n[3]);

/** Unit normal n as a colour the rasterizer interpolates: each component (n + 1) / 2 in 8 bits, XRGB. */
uint32_t psc_bake_proxy_normal_rgb(const double n[3]);

/**
 * Bake model g (name for messages) into a proxy pack in *out (malloc'd,
 * *len bytes). note receives a one-line summary. 0, or -1 with err naming
 * the file and the problem.
 */
int psc_bake_proxy(const psc_gltf_t *g, const psc_bake_proxy_opts_t *o, const char *name, uint8_t **out, size_t *len,
                   char *note, size_t notelen, char *err, size_t errlen);

/* ---- the pieces, shared by proxy.c and proxy_views.c ---------------------------- */

/** One proxy's geometry while baking: what it is drawn from and the proxy itself, in units of R. */
typedef struct {
    double (*src_pos)[3];            /* the part's piece of the model: vertices ... */
    uint32_t *src_color;             /* ... lit at rest, their normals (psc_bake_proxy_normal_rgb) ... */
    uint32_t *src_normal;
    uint32_t *src_index;             /* ... and triangles (3 each) */
    uint32_t src_vertices, src_triangles;
    double (*prx_pos)[3];            /* the proxy (its piece of the simplified model) */
    uint32_t *prx_index;
    uint32_t prx_vertices, prx_triangles;
    double centre[3], radius;        /* the proxy's bounding sphere */
    double src_centre[3], src_radius;  /* the sphere of its own triangles */
    double reach;                    /* the model's surface within this of the proxy is the proxy's (units of R) */
} psc_proxy_shape_t;

/** A view texel's samples (of 16): those that show the model, and those of them kept on the proxy (its reach). */
typedef struct {
    uint8_t model, kept;
} psc_bake_cover_t;

/** Render shape s's view textures (view_count x tex^2 RGB565: each texel its kept samples' mean, empty with none;
 *  psc_bake_proxy_mips decides which are drawn) and their samples' counts (cov, as many), their depth offsets unless
 *  NULL (view_count x (tex / 2)^2, XTDP's: psc_proxy.h), their normals unless NULL (view_count x (tex / 2)^2
 *  psc_oct16 codes) and its proxy's coordinates (view_count x prx_vertices x 2) for a grid of side x side views:
 *  the shapes near[0..n_near) (s and its neighbours) at rest, where their surface lies within s->reach of s's proxy;
 *  elsewhere the texels stay empty. 0, or -1 out of memory. */
int psc_bake_proxy_views(const psc_proxy_shape_t *s, const psc_proxy_shape_t *const *near, unsigned n_near,
                         unsigned side, unsigned tex, uint16_t *texels, psc_bake_cover_t *cov, uint16_t *normals,
                         int8_t *offsets, uint16_t *uv);

/** A view texture's mip chain, `levels` in all, into chain: level l the (2^l)^2 texels of level 0 (side^2, with
 *  their counts cov0) as one, the mean of their kept samples, covered where a quarter of its samples are kept and
 *  half show the model (a quarter for a feature thinner than a texel). 0, or -1 out of memory. */
int psc_bake_proxy_mips(const uint16_t *level0, const psc_bake_cover_t *cov0, unsigned side, unsigned levels,
                        uint16_t *chain);

/** The billboard (the far level of detail): every shape drawn, at rest, into side x side views of tex^2 fitted to
 *  the sphere (centre, radius); axes_q16 receives each view's right and up (Q16.16). 0, or -1 out of memory. */
int psc_bake_proxy_billboard(const psc_proxy_shape_t *shapes, unsigned n, const double centre[3], double radius,
                             unsigned side, unsigned tex, uint16_t *texels, uint16_t *normals, int32_t *axes_q16);

#endif
