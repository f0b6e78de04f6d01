/* SPDX-License-Identifier: MIT */
/*
 * psc_raster.h - the triangle rasterizer: edge functions, top-left fill rule,
 * depth buffer, flat / Gouraud / perspective-correct texture shading.
 *
 * Conventions:
 *  - Raster coordinates: x right, y down, in 1/16 pixel (Q27.4, "_q4",
 *    PSC_RASTER_SUBPIXEL_BITS = 4). Pixel (i, j) covers [i, i+1) x [j, j+1)
 *    and is sampled at its centre (16i + 8, 16j + 8). Vertices must lie within
 *    +-PSC_RASTER_COORD_MAX_Q4; the pipeline's guard-band clipping keeps them
 *    there (triangles beyond are refused, never wrapped).
 *  - Edge function of edge a->b at p: E = (bx-ax)(py-ay) - (by-ay)(px-ax),
 *    exact in int64 (coordinates < 2^18, products < 2^38). A triangle is
 *    inside-positive when its doubled area E_01(v2) > 0; the rasterizer
 *    swaps two vertices of a negative one (culling is the pipeline's job) and
 *    skips a zero-area one.
 *  - Fill rule, top-left: a pixel centre exactly on an edge belongs to the
 *    triangle only if the edge is a left edge (by < ay: the interior lies to
 *    its right) or a top edge (horizontal, bx > ax: the interior lies below).
 *    Two triangles sharing an edge therefore never both draw, nor both miss,
 *    a pixel on it.
 *  - Attributes are planes over the raster: value(p) = v0 + a (px - x0) +
 *    b (py - y0), with the gradients a, b rounded once per triangle to F
 *    extra fraction bits and evaluated exactly (modulo 2^64, see the .c) at
 *    each pixel centre. A pixel's value depends only on the triangle and the
 *    pixel, never on where a span or tile started: tile mode is byte-identical.
 *  - Depth: normalised depth in Q0.32 (uint32: 0 at the near plane,
 *    0xFFFFFFFF at the far plane), affine in 1/z so linear on the screen.
 *    A 32-bit buffer stores it whole, a 16-bit buffer its top 16 bits. A pixel
 *    is written when its depth is strictly less than the stored one.
 *  - Colours: XRGB8888 (0xXXRRGGBB); RGB565 targets receive psc_xrgb_to_rgb565.
 *    Gouraud colours are linear on the screen (the classic Gouraud shading).
 *  - Textures: (u, v) in Q16.16 with (0, 0) the top-left corner of the image,
 *    (1, 1) the bottom-right; u right, v down; repeat wrapping; power-of-two
 *    sizes. Perspective-correct per pixel: u/w, v/w and 1/w are planes and
 *    each pixel divides once (q = near/z in Q4.28). Bilinear filtering samples
 *    at texel centres with 8-bit weights (psc_blend4_xrgb). Within one
 *    triangle, texture coordinates are shifted by a common whole number (free
 *    under repeat wrapping) and must then span less than 16.0; wider spans are
 *    clamped.
 *  - View textures (PSC_SHADE_VIEWS, the proxy animator's image-based
 *    surfaces): three RGB565 textures, each with its own perspective-correct
 *    coordinates (u, v), (u1, v1), (u2, v2) in [0, 1] (clamped, no wrapping),
 *    blended with constant weights view_w_q8 (summing to 256). Texel 0x0000
 *    is empty (PSC_VIEW_TEXEL_EMPTY): where the part is not. A pixel's
 *    coverage is the weighted share of non-empty texels (bilinear: each of
 *    the four weighted too); the pixel is drawn, and its depth written, only
 *    when the coverage reaches one half, with the colour the average of the
 *    non-empty texels under their weights (the alpha test of image-based
 *    rendering: the silhouette is the blend's, not the proxy's). With
 *    views_mask the pixel takes mask_color instead (part ids).
 *  - Anti-aliasing (target abuf set): a pixel is covered when all 16
 *    samples of its 4 x 4 grid are inside, and drawn as above; one partly
 *    covered gets a fragment with the coverage mask, the colour at the
 *    centroid of the covered samples and the depth there (at the centre when
 *    the triangle covers the centre), and the A-buffer blends it at the
 *    resolve. View textures turn their coverage
 *    into samples too (alpha to coverage: round(16 x coverage) samples of
 *    the geometric mask in a dispersed order, the coverage first ramped 16x
 *    steeper about the alpha test's one half: the views' coverage is blurred
 *    over a texel, which may span several pixels), so image-based
 *    silhouettes are smoothed as well. Which pixels are covered stays
 *    independent of where a tile starts.
 *  - Relit view textures (view_normals set): each view's texels carry the
 *    surface's normal (psc_oct.h) in a texture of its own; the heaviest
 *    view that covers the pixel gives it, sampled bilinearly at the same
 *    (u, v) (the views see one surface: their normals agree); N,
 *    renormalised (psc_rsqrt_q30), relights the blended colour by the ratio
 *    of the two lights' Lambert terms:
 *        colour x (a + (1 - a) max(0, N.L)) / (a0 + (1 - a0) max(0, N.L0))
 *    (Q2.14, the ratio in Q16.16, each channel rounded and saturated): the
 *    texels hold the colour lit by the bake's light L0, so the ratio is the
 *    albedo lit by L without storing the albedo.
 *  - View depth offsets (view_depth set, target depth_step non-zero): a
 *    pixel's depth is the proxy's plus its offset, the heaviest view's
 *    texel at its (u, v) (nearest), times the depth change of a step at the
 *    triangle's mean perspective weight q (depth_step q^2: the buffer's
 *    depth is (1 - near/z) far/(far - near), whose slope is q^2 / near),
 *    clamped to the buffer: tested and written as the surface's depth.
 *  - Phong shading (PSC_SHADE_PHONG): the vertex colours (unlit) and the
 *    vertex normals n_q14 are planes, linear on the screen like Gouraud's
 *    colours; each pixel renormalises its normal N (one 2^30/sqrt(|N|^2),
 *    psc_rsqrt_q30) and takes
 *        colour x (ambient + (1 - ambient) max(0, N.L)) + 255 specular max(0, N.H)^shininess
 *    per channel, saturated: Lambert's diffuse term and Blinn's highlight,
 *    with H the half vector between the light L and the viewer direction
 *    (0, 0, -1) (a viewer far away: H is constant over the frame). The power
 *    is taken by repeated squaring in Q16.16, rounded at each product.
 */
#ifndef PSC_RASTER_H
#define PSC_RASTER_H

#include "base/psc_types.h"
#include "raster/psc_abuffer.h"

#define PSC_RASTER_SUBPIXEL_BITS 4
#define PSC_RASTER_SUBPIXEL_ONE (1 << PSC_RASTER_SUBPIXEL_BITS)
/* Largest |raster coordinate| accepted: 2^18 sixteenths = 16384 pixels. */
#define PSC_RASTER_COORD_MAX_Q4 (INT32_C(1) << 18)
/* Perspective weight q = near/z, Q4.28: 1.0 at the near plane; the pipeline
 * keeps far/near <= 2^16, so q >= 2^12. */
#define PSC_RASTER_Q_ONE (INT32_C(1) << 28)
#define PSC_RASTER_Q_MIN (INT32_C(1) << 12)
/* Texture sizes: powers of two up to this. */
#define PSC_TEXTURE_MAX_DIM 4096u

/** One vertex as the rasterizer sees it (after projection). */
typedef struct {
    int32_t x_q4, y_q4;      /* raster position in 1/16 pixel */
    uint32_t depth_q32;      /* normalised depth: 0 near plane .. 0xFFFFFFFF far plane */
    int32_t q_q28;           /* near / z, Q4.28, in [PSC_RASTER_Q_MIN, PSC_RASTER_Q_ONE] */
    int32_t u_q16, v_q16;    /* texture coordinates */
    uint32_t color;          /* XRGB8888: flat (first vertex) and Gouraud colour */
    int32_t light_q8;        /* 0..256: texture modulation (1.0 = 256) */
    int32_t u1_q16, v1_q16, u2_q16, v2_q16;  /* VIEWS: the second and third views' coordinates */
    int16_t n_q14[3];        /* PHONG: the surface normal in camera space, unit length in Q2.14 */
} psc_raster_vertex_t;

typedef enum {
    PSC_SHADE_FLAT = 0,    /* every pixel takes the first vertex's colour (the provoking vertex) */
    PSC_SHADE_GOURAUD = 1, /* vertex colours, interpolated linearly on the screen */
    PSC_SHADE_TEXTURE = 2, /* perspective-correct texture, optionally times light_q8 */
    PSC_SHADE_VIEWS = 3,   /* three view textures blended and alpha-tested (below) */
    PSC_SHADE_PHONG = 4    /* vertex colours lit per pixel from interpolated normals (below) */
} psc_shade_t;

typedef enum {
    PSC_TEX_NEAREST = 0,
    PSC_TEX_BILINEAR = 1,
    PSC_TEX_EDGES = 2      /* (PSC_SHADE_VIEWS) nearest where every texel sampled is filled; where one is empty
                            * the coverage bilinear (the colour the nearest texels', or the bilinear ones' where no
                            * nearest texel is filled): an alpha-tested silhouette placed to a fraction of a texel
                            * for the price of nearest inside it; elsewhere nearest */
} psc_tex_filter_t;

typedef enum {
    PSC_BLEND_REPLACE = 0, /* the pixel becomes the colour */
    PSC_BLEND_ADD = 1,     /* per-channel saturating add (counts writes in tests) */
    PSC_BLEND_ALPHA = 2    /* translucent, opacity_q8: tested against the depth, never written to it; with the
                            * A-buffer a fragment composited in depth order at the resolve (psc_abuffer.h), without
                            * it blended over the pixel in drawing order (draw such surfaces last, far to near) */
} psc_blend_t;

/* The texel of a view texture where the surface is not (RGB565 black; content black is stored as 0x0020). */
#define PSC_VIEW_TEXEL_EMPTY 0x0000u

/** A texture the caller owns: power-of-two sides, RGB565 or XRGB8888 texels. */
typedef struct {
    uint16_t width, height;
    uint8_t width_log2, height_log2;
    psc_pixfmt_t format;
    uint32_t stride;          /* bytes per row */
    const void *pixels;
} psc_texture_t;

/** Describe pixels as a texture: PSC_ERR_ARG unless the sides are powers of two within limits. */
psc_status_t psc_texture_init(psc_texture_t *t, uint16_t width, uint16_t height, psc_pixfmt_t format,
                              uint32_t stride, const void *pixels);

/** A Lambert light: ambient + (1 - ambient) max(0, N.L). */
typedef struct {
    int16_t toward_q14[3];    /* toward the light, unit length, Q2.14 */
    uint16_t ambient_q14;     /* 0..16384 */
} psc_lambert_q14_t;

/**
 * Colour c (XRGB) lit by `now` instead of `bake`, for a surface of normal n
 * (any length within 2^14 a component; zero leaves c as it is): each channel
 * times lambert(now) / lambert(bake), rounded and saturated (psc_raster.h's
 * relit view textures; the proxy animator's full mesh, a vertex at a time).
 */
uint32_t psc_lambert_relight(const psc_lambert_q14_t *now, const psc_lambert_q14_t *bake, const int32_t n[3],
                             uint32_t c);

/** How to draw. */
typedef struct {
    psc_shade_t shade;
    psc_tex_filter_t filter;
    psc_blend_t blend;
    bool depth_test;          /* test against and write the depth buffer */
    uint16_t opacity_q8;      /* PSC_BLEND_ALPHA: 0..256 (256 opaque) */
    bool modulate;            /* TEXTURE: multiply texels by the interpolated light_q8 */
    const psc_texture_t *texture;  /* TEXTURE only */
    const psc_texture_t *view_tex[3];  /* VIEWS: RGB565, same size */
    uint16_t view_w_q8[3];    /* VIEWS: weights summing to 256, heaviest first (pixels end sooner) */
    bool views_mask;          /* VIEWS: write mask_color where covered */
    /* VIEWS relit (below): the views' normals, psc_oct16 codes, any power-of-two size (NULL: drawn as baked), and
     * the light they are lit by now and the one their texels were baked with, both in the normals' frame */
    const psc_texture_t *view_normals[3];
    psc_lambert_q14_t view_light, view_bake_light;
    /* VIEWS relit: the light differs from corner to corner (a skinned strip whose ends follow different bones): each
     * vertex's n_q14 holds it (toward the light in the normals' frame, unit Q2.14), a pixel takes their blend made
     * unit, with view_light's ambient */
    bool view_light_vertices;
    /* VIEWS with depth (below): the heaviest view's depth offsets, side^2 int8 row-major at its (u, v) (NULL: none) */
    const int8_t *view_depth;
    uint16_t view_depth_side;
    uint32_t mask_color;
    /* PHONG: one directional light and a viewer far along -z (camera space). */
    int16_t light_q14[3];     /* toward the light, unit length */
    int16_t half_q14[3];      /* Blinn's half vector: (light + (0, 0, -1)) normalised */
    uint16_t ambient_q8;      /* 0..256 */
    uint16_t specular_q8;     /* 0..256: the white highlight's strength */
    uint8_t shininess;        /* 1..255: the highlight's exponent */
} psc_raster_state_t;

/** Where to draw: a rectangle of a surface, with a depth buffer covering exactly that rectangle. */
typedef struct {
    const psc_surface_t *surface;  /* RGB565 or XRGB8888 */
    void *depth;                   /* depth of pixel (x0, y0) first; NULL when no test is made */
    uint32_t depth_stride;         /* bytes per depth row */
    uint8_t depth_bits;            /* 16 or 32 */
    uint16_t x0, y0, x1, y1;       /* pixels [x0, x1) x [y0, y1), inside the surface */
    psc_abuffer_t *abuf;           /* NULL, or the A-buffer over the rectangle (heads row by row, x1 - x0 a row):
                                    * depth-tested PSC_BLEND_REPLACE triangles then give partly covered pixels
                                    * fragments (psc_abuffer.h) */
    uint64_t *tested;              /* NULL, or counts the pixels depth-tested (what hidden-surface methods save) */
    uint64_t depth_step;           /* VIEWS with depth: the depth buffer's change (of 2^32) for a view depth step
                                    * (1/256 of a camera unit further) at the near plane, at most 2^35 (0: no
                                    * offsets) */
    /* Soft silhouettes (below): NULL, or a byte a pixel over the rectangle, pixel (x0, y0) first, zeros before the
     * first triangle; its bytes per row; the colour the rectangle was cleared to. */
    uint8_t *coverage;
    uint32_t coverage_stride;
    uint32_t background_xrgb;
} psc_raster_target_t;

/*
 * Soft silhouettes. With a coverage plane, depth-tested PSC_SHADE_VIEWS
 * triangles drawn with PSC_BLEND_REPLACE and without an A-buffer draw the
 * silhouettes their views give anti-aliased rather than alpha-tested: a
 * pixel's coverage (the views' bilinear one, steepened to change over one
 * pixel where a texel spans several) blends its colour over what the pixel
 * holds, and the plane keeps how much of the pixel is covered so far (255:
 * all). A fragment hidden by the depth test still fills the part of a pixel
 * left uncovered, in place of the background it replaces: a silhouette drawn
 * before what lies behind it, or the seam between two proxies each covering
 * part of a pixel, shows no background. Without the plane (or its
 * conditions), a pixel is drawn where half of it is covered.
 */

/**
 * Draw one triangle into the target's rectangle. Returns the number of
 * pixels written (after the depth test). Triangles with a vertex beyond
 * PSC_RASTER_COORD_MAX_Q4, zero area, or a texture state without a valid
 * texture draw nothing.
 */
uint32_t psc_raster_triangle(const psc_raster_target_t *t, const psc_raster_state_t *st,
                             const psc_raster_vertex_t *v0, const psc_raster_vertex_t *v1,
                             const psc_raster_vertex_t *v2);

/** An edge function: pixel centre (cx, cy) (raster units) lies on the triangle's side when a cx + b cy + c >= 0. */
typedef struct {
    int64_t a, b, c;
} psc_raster_edge_t;

/**
 * The three edge functions by which psc_raster_triangle decides which pixel
 * centres a triangle covers (the top-left rule folded into c): a centre is
 * drawn exactly when all three are >= 0. Being affine, over a rectangle of
 * centres each takes its extremes at corners, so whether a triangle covers
 * every centre of a rectangle, or none, is exact from four values an edge.
 * false for zero area or coordinates out of range (nothing is drawn).
 */
bool psc_raster_edges(const psc_raster_vertex_t *v0, const psc_raster_vertex_t *v1, const psc_raster_vertex_t *v2,
                      psc_raster_edge_t e[3]);

/** The depth plane of a triangle exactly as the loops evaluate it (psc_raster_depth_plane_range). */
typedef struct {
    int64_t a, b;       /* per raster unit, 2^-8 depth units */
    int64_t base;       /* the first vertex's depth, 2^-8 units */
    int32_t x0, y0;     /* the first vertex (raster units) */
} psc_raster_depth_plane_t;

/** A triangle's depth plane: false for zero area or coordinates out of range (nothing is drawn). */
bool psc_raster_depth_plane(const psc_raster_vertex_t *v0, const psc_raster_vertex_t *v1,
                            const psc_raster_vertex_t *v2, psc_raster_depth_plane_t *p);

/**
 * Bounds of the depth the rasterizer gives a triangle's pixels whose
 * centres lie in [x0_q4, x1_q4] x [y0_q4, y1_q4] (raster units): its depth
 * plane, exactly as the loops evaluate it, at the rectangle's corners (the
 * plane extended beyond the triangle; affine, so its extremes are there).
 * Every pixel of the rectangle the triangle draws gets a depth within
 * [*zmin, *zmax] (an anti-aliased fragment too, when the rectangle reaches
 * its samples); where the extended plane overflows, the bound widens to 0 or
 * 0xFFFFFFFF.
 */
void psc_raster_depth_plane_range(const psc_raster_depth_plane_t *p, int32_t x0_q4, int32_t y0_q4, int32_t x1_q4,
                                  int32_t y1_q4, uint32_t *zmin, uint32_t *zmax);

#endif
