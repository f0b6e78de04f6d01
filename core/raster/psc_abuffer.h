/* SPDX-License-Identifier: MIT */
/*
 * psc_abuffer.h - the A-buffer (seed 004, after Carpenter's REYES A-buffer):
 * anti-aliased edges from per-pixel coverage masks, resolved at the end of
 * the frame (or tile).
 *
 * The surface and the depth buffer keep their meaning: the colour and depth
 * of the nearest surface that covers the whole pixel (the seed's "positive
 * depth field": a single surface). A pixel that a triangle covers only in
 * part gets a fragment instead (the seed's "negative depth field": a list of
 * surfaces), holding
 *   - the coverage: a 4 x 4 grid of samples at (2i + 1)/8 of the pixel, one
 *     bit each (bit 4 j + i: column i, row j), decided by the rasterizer's
 *     edge functions with the same top-left rule as pixel centres, so two
 *     triangles sharing an edge cover complementary samples;
 *   - the colour at the centroid of the covered samples (inside the
 *     triangle, where a linear attribute takes its mean over them; the
 *     centre may lie far outside a sliver, where the planes extrapolate to
 *     nonsense), and the depth there too, or at the pixel centre when the
 *     triangle covers that (by the rasterizer's rule for pixels: exactly one
 *     triangle of a closed mesh does);
 *   - the surface (the draw it came from) and the link to the pixel's next
 *     fragment.
 * Fragments of one surface that meet in a pixel with disjoint coverage and
 * depths within the triangles' depth change across a pixel are merged:
 * their colours weighted by coverage, the depth of the one covering the
 * centre. So the edges inside a mesh cost no memory, and a merged fragment
 * covering the whole pixel becomes the pixel's colour and depth: the depth
 * it has without the A-buffer, the colour averaged over the triangles
 * (anti-aliasing the creases of a mesh: a cube's faces, texture seams). Fragments behind the stored depth are dropped on arrival and on
 * every visit. The resolve sorts a pixel's visible fragments front to back
 * (at most PSC_ABUF_RESOLVE_MAX, the nearest) and gives each the samples no
 * nearer fragment took; the samples left show the stored colour behind
 * them:  colour = (sum of fragment colour x its samples + stored x rest) / 16.
 *
 * Memory: one 32-bit head per pixel of the target rectangle and a pool of
 * PSC_ABUF_FRAGMENT_BYTES per fragment, both given by the caller (the 3D
 * pipeline takes them from a budget the board states). When the pool is
 * full, a partial fragment covering at least half the samples is drawn as
 * without the A-buffer and a smaller one is dropped (counted in overflow):
 * the frame degrades to aliased edges, it never fails.
 *
 * Translucent surfaces (psc_abuffer_add_translucent) leave the stored
 * colour and depth alone and give every pixel they reach a fragment with
 * their opacity; a pixel with one is resolved sample by sample, front to
 * back: each sample takes each fragment covering it by what light is left
 * (its transmittance), then the stored colour by what remains -- sorted
 * alpha compositing with the coverage, in any drawing order.
 *
 * Intersecting surfaces are not anti-aliased (one depth per fragment), nor
 * are added (PSC_BLEND_ADD) draws or draws without the depth test.
 */
#ifndef PSC_ABUFFER_H
#define PSC_ABUFFER_H

#include "base/psc_types.h"

#define PSC_ABUF_SAMPLES 16u
#define PSC_ABUF_FULL 0xFFFFu
/* Fragments a pixel's resolve sorts (the nearest of its list). */
#define PSC_ABUF_RESOLVE_MAX 8u

typedef struct {
    uint32_t next;        /* index + 1 of the pixel's next fragment; 0 ends the list */
    uint32_t depth_q32;   /* at the pixel centre (psc_raster.h's normalised depth) */
    uint16_t mask;        /* covered samples */
    uint16_t surface;     /* the draw it came from */
    uint32_t color;       /* RGB: its pieces' colours weighted by their coverage; PSC_ABUF_CENTRE when one of
                           * them covers the pixel centre (the depth is then the centre's) */
} psc_abuf_fragment_t;

#define PSC_ABUF_CENTRE 0x01000000u
/* A translucent fragment's transparency, bits 25..31 of its colour word: t in 0..127 (0 for an opaque one),
 * its opacity (128 - t) / 128. */
#define PSC_ABUF_CLEAR_SHIFT 25u

#define PSC_ABUF_FRAGMENT_BYTES 16u
#define PSC_ABUF_HEAD_BYTES 4u

typedef struct {
    uint32_t *head;               /* one per pixel of the rectangle, row by row */
    psc_abuf_fragment_t *pool;
    uint32_t pixels, capacity;    /* heads; fragments the pool holds */
    uint32_t used;                /* fragments handed out since the clear (the high-water mark) */
    uint32_t free_list;           /* index + 1 of a fragment given back, linked through next */
    uint32_t live, peak;          /* fragments in lists now; most at once since the clear */
    uint32_t overflow;            /* partial fragments that found no room since the clear */
    uint16_t surface;             /* the surface the next fragments belong to */
} psc_abuffer_t;

/** Bytes for heads of `pixels` pixels and a pool of `fragments` (0 when that overflows size_t). */
size_t psc_abuffer_bytes(uint32_t pixels, uint32_t fragments);

/** Fragments a budget of `bytes` holds beside the heads of `pixels` pixels (0 when none fit). */
uint32_t psc_abuffer_fragments_for(uint32_t pixels, size_t bytes);

/** Lay the A-buffer out in mem (aligned to 4, psc_abuffer_bytes(pixels, fragments) long) and clear it. */
void psc_abuffer_init(psc_abuffer_t *a, void *mem, uint32_t pixels, uint32_t fragments);

/** Empty every list (heads of the first `pixels` pixels) and the pool. */
void psc_abuffer_clear(psc_abuffer_t *a, uint32_t pixels);

/**
 * A partial fragment for head `pixel` (mask neither empty nor full): merged
 * into a fragment of the same surface, kept, or dropped as hidden. limit is
 * the stored depth in 32-bit terms (a fragment is visible when depth < limit),
 * zslack the depth change across one pixel of its triangle, centre whether
 * its triangle covers the pixel centre. Returns true when
 * the caller is to draw *color at *depth as a covered pixel instead: a merge
 * completed the coverage, or the pool is full and mask covers at least half.
 */
bool psc_abuffer_add(psc_abuffer_t *a, uint32_t pixel, uint16_t mask, bool centre, uint32_t limit, uint32_t zslack,
                     uint32_t *depth, uint32_t *color);

/**
 * A translucent surface's fragment for head `pixel` (any non-empty mask,
 * whole pixels too: what is behind shows through), of opacity
 * opacity_q7 / 128 (1..128), merged with its own surface's as
 * psc_abuffer_add does but never becoming the stored colour, or dropped
 * when the stored surface hides it. Returns true when the pool is full and
 * the mask covers at least half the samples: the caller is to blend
 * *color over the pixel instead (the frame degrades, counted in overflow).
 */
bool psc_abuffer_add_translucent(psc_abuffer_t *a, uint32_t pixel, uint16_t mask, bool centre, uint32_t limit,
                                 uint32_t zslack, uint32_t depth, uint32_t color, uint32_t opacity_q7);

/**
 * Blend every pixel that has fragments into the surface rectangle
 * [x0, x1) x [y0, y1) whose heads and depth (depth_bits 16 or 32, row stride
 * depth_stride bytes) the A-buffer and depth cover.
 */
void psc_abuffer_resolve(psc_abuffer_t *a, const psc_surface_t *s, uint16_t x0, uint16_t y0, uint16_t x1,
                         uint16_t y1, const void *depth, uint32_t depth_stride, uint8_t depth_bits);

#endif
