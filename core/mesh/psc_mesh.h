/* SPDX-License-Identifier: MIT */
/*
 * psc_mesh.h - a triangle mesh in memory, and the mesh pack (.pmesh) that
 * holds one on the device, read in place like the scene pack (psc_pack.h).
 *
 * Mesh conventions (psc_3d_math.h for the axes):
 *  - Positions "_q15": int16 per axis, 1.0 unit = 32768. A mesh pack is
 *    normalised: centred on its bounding box, the longest half-axis scaled to
 *    32767, so it spans at most +-1.0 unit. (In-memory meshes may give
 *    Q16.16 positions instead, position_q16, e.g. for generated test scenes.)
 *  - Normals "_q14": int16 per axis, unit length = 16384 (renormalised after
 *    transformation, so small errors do not matter).
 *  - Texture coordinates "_q12": int16, 1.0 = 4096, range [-8, 8); (0, 0) is
 *    the top-left corner of the texture image, v grows downward (psc_raster.h).
 *  - Colours: XRGB8888 per vertex.
 *  - Triangles: three uint16 vertex indices; a triangle is front-facing when
 *    its vertices appear clockwise on the screen (raster y down), i.e.
 *    counter-clockwise seen from outside in OBJ's convention: the seed's
 *    V.N < 0 with N = (v1 - v0) x (v2 - v0) and V from the eye to the face.
 *
 * Mesh pack layout: the sectioned container of base/psc_container.h with
 * magic "PSCMESH\x1a", version PSC_MESH_VERSION_MAJOR.PSC_MESH_VERSION_MINOR
 * and at most PSC_MESH_MAX_SECTIONS sections. Types:
 *   "MINF"  32 bytes: u32 vertex_count (1..65535), u32 triangle_count
 *           (1..PSC_MESH_MAX_TRIANGLES), i16 bbox_min[3], i16 bbox_max[3]
 *           (Q1.15, min <= max), u32 base colour (XRGB), 8 bytes reserved
 *   "VPOS"  vertex_count * 3 int16 positions (Q1.15)          required
 *   "VNRM"  vertex_count * 3 int16 normals (Q1.14)            optional
 *   "VTEX"  vertex_count * 2 int16 texture coordinates (Q4.12) optional
 *   "VCOL"  vertex_count uint32 colours (XRGB8888)            optional
 *   "TIDX"  triangle_count * 3 uint16 indices, each < vertex_count  required
 *   "TEXR"  16-byte header {u16 width, u16 height, u8 format (psc_pixfmt_t:
 *           RGB565 or XRGB8888), 11 bytes reserved} then height rows of
 *           width texels, no padding; powers of two up to PSC_TEXTURE_MAX_DIM
 *           optional (needs VTEX)
 *   "TOPQ"  (1.1) the triangles' opacities: u32 group count n
 *           (1..PSC_MESH_MAX_OPACITY_GROUPS), then n groups of 8 bytes
 *           {u32 triangle count (>= 1), u16 opacity_q8 (1..256; 256 opaque),
 *           u16 reserved}: consecutive runs of TIDX from triangle 0, together
 *           all of them; the opaque first is the writer's order, so that
 *           translucent surfaces draw over what they show      optional
 * Unknown section types are skipped (a 1.0 reader draws a 1.1 pack opaque).
 */
#ifndef PSC_MESH_H
#define PSC_MESH_H

#include "base/psc_types.h"
#include "base/psc_container.h"
#include "raster/psc_raster.h"

#define PSC_MESH_MAGIC "PSCMESH\x1a"
#define PSC_MESH_VERSION_MAJOR 1u
#define PSC_MESH_VERSION_MINOR 1u
#define PSC_MESH_MAX_SECTIONS 16u
#define PSC_MESH_MAX_VERTICES 65535u
#define PSC_MESH_MAX_TRIANGLES (1u << 20)
#define PSC_MESH_INFO_SIZE 32u
#define PSC_MESH_TEXTURE_HEADER_SIZE 16u

/** The mesh pack's container format (reader and writer). */
extern const psc_container_format_t psc_mesh_format;

#define PSC_SECTION_MESH_INFO PSC_FOURCC('M', 'I', 'N', 'F')
#define PSC_SECTION_MESH_POS PSC_FOURCC('V', 'P', 'O', 'S')
#define PSC_SECTION_MESH_NORMAL PSC_FOURCC('V', 'N', 'R', 'M')
#define PSC_SECTION_MESH_UV PSC_FOURCC('V', 'T', 'E', 'X')
#define PSC_SECTION_MESH_COLOR PSC_FOURCC('V', 'C', 'O', 'L')
#define PSC_SECTION_MESH_INDEX PSC_FOURCC('T', 'I', 'D', 'X')
#define PSC_SECTION_MESH_TEXTURE PSC_FOURCC('T', 'E', 'X', 'R')
#define PSC_SECTION_MESH_OPACITY PSC_FOURCC('T', 'O', 'P', 'Q')
#define PSC_MESH_MAX_OPACITY_GROUPS 8u

/** A run of triangles drawn with one opacity (OBJ d / Tr, glTF BLEND materials). */
typedef struct {
    uint32_t first, count;         /* triangles [first, first + count) of the index list */
    uint16_t opacity_q8;           /* 1..256 (256 opaque) */
} psc_mesh_opacity_t;

/** A mesh: arrays the caller (or a parsed pack) owns. */
typedef struct {
    uint32_t vertex_count;
    uint32_t triangle_count;
    const int16_t *position_q15;   /* 3 per vertex; or NULL and position_q16 set */
    const int32_t *position_q16;   /* 3 per vertex, Q16.16 units (in-memory meshes) */
    const int16_t *normal_q14;     /* 3 per vertex, or NULL */
    const int16_t *uv_q12;         /* 2 per vertex, or NULL */
    const uint32_t *color;         /* 1 per vertex, or NULL */
    const uint16_t *index;         /* 3 per triangle, each < vertex_count */
    int16_t bbox_min_q15[3], bbox_max_q15[3];  /* packs: the bounding box of the positions */
    uint32_t base_color;           /* XRGB, used when color is NULL */
    bool has_texture;
    psc_texture_t texture;
    uint16_t version_minor;
    uint8_t opacity_groups;        /* 0: every triangle opaque; else the runs in opacity[] */
    psc_mesh_opacity_t opacity[PSC_MESH_MAX_OPACITY_GROUPS];
} psc_mesh_t;

/**
 * Validate and parse a mesh pack held in buf[0..len), aligned to 8 bytes.
 * Checks magic, version, sizes, CRC, section bounds and alignment, counts,
 * every index against the vertex count, the bounding box against the
 * positions, and the texture's size and format. On failure returns the status
 * and fills *err (what, byte offset; err may be NULL). Nothing is read
 * outside buf; the mesh points into buf.
 */
psc_status_t psc_mesh_parse(const void *buf, size_t len, psc_mesh_t *out, psc_container_error_t *err);

#endif
