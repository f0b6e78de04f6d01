/* SPDX-License-Identifier: MIT */
/*
 * psc_proxy.h - image-based rendering with proxy surface animation (the seed,
 * US 6,924,805): an articulated or skinned model drawn as a few proxy
 * surfaces carrying pre-rendered view textures, its parts still animated;
 * and the proxy pack (.ppx) that holds it, read in place.
 *
 * Preprocessing (host, periscope-proxy bake; the seed's preprocessor 710):
 *  - parts: pieces that move without changing shape (the triangles whose
 *    vertices all follow one joint most); joints: the triangles between
 *    parts, whose skin weights are split - they stretch;
 *  - the proxies: the model simplified as a whole (a quarter of its
 *    triangles at most), cut along the parts' and joints' borders, so a
 *    part's proxy and a joint's strip share their border vertices; each
 *    proxy vertex a model vertex with its skin weights (a part may have
 *    none: simplifying gave its surface to its neighbours');
 *  - view textures per proxy: its piece of the model and its neighbours'
 *    rendered at the rest pose from each direction of the octahedral grid
 *    (psc_proxy_view.h), orthographically, lighting baked in, kept where the
 *    surface lies on the proxy, with a texture-coordinate set per
 *    direction: each proxy vertex projected into that view;
 *  - the skeleton, its animation sampled at a fixed rate as skin matrices,
 *    and the full mesh with rest-pose lighting (the near level of detail and
 *    the comparison).
 * Rendering (core, every frame, psc_proxy_draw.c; the seed's animator 720):
 *  - M2, a part's transform, is its joint's skin matrix; the direction it is
 *    drawn from is Dr = Ds M1^-1 M2^-1 (psc_proxy_view_for_part); its three
 *    nearest views are blended with barycentric weights, the silhouette the
 *    blend's (PSC_SHADE_VIEWS, psc_raster.h);
 *  - each joint strip is skinned and drawn as one surface with its own M3,
 *    the rotation of its bones' skin matrices weighted as its vertices weigh
 *    on them, hence its own direction and views: joints stretch with the
 *    parts (the seed gives each joint triangle its own M3; a strip of the
 *    simplified mesh is a ring of a few triangles, and one draw a strip, not
 *    one a triangle, is what makes a skinned character cheaper as proxies);
 *  - everything goes through the 3D pipeline: one z-buffer, tiles, culling,
 *    RGB565 or XRGB8888.
 *
 * Units: positions Q16.16 in units of R (half the rest pose's bounding-box
 * diagonal) from the rest box centre; skin matrices Q16.16 in the same
 * units; skin weights Q0.15 (summing to 32768); view coordinates Q0.16 of
 * the view texture (u right, v down); texels RGB565, PSC_VIEW_TEXEL_EMPTY
 * where the proxy's geometry is not.
 *
 * Pack: the container of base/psc_container.h, magic "PSCPRXY\x1a". Sections
 * (counts from "XINF"; part p's texture for view k is p x view_count + k):
 *   "XINF"  psc_proxy_info_raw_t
 *   "XJNT"  joint_count psc_proxy_joint_raw_t (parents before children)
 *   "XANM"  frame_count x joint_count x 12 int32: skin matrices, row-major
 *           3x4 (optional: frame_count 0 has none)
 *   "XPRT"  part_count psc_proxy_part_raw_t (parts, then joints)
 *   "XVPS"  vertex_count x 3 int32 positions (rest)
 *   "XVCL"  vertex_count uint32 colours (XRGB, lit at rest)
 *   "XVSK"  vertex_count psc_proxy_skin_raw_t
 *   "XIDX"  triangle_count x 3 uint16, relative to the piece's first vertex
 *   "XPPS"  proxy_vertex_count x 3 int32 positions (rest)
 *   "XPSK"  proxy_vertex_count psc_proxy_skin_raw_t
 *   "XPIX"  proxy_triangle_count x 3 uint16, relative to the part's first
 *           proxy vertex
 *   "XPUV"  per part, per view, its proxy vertices' (u, v) uint16 pairs
 *   "XTEX"  the view textures, RGB565, one run of texels per part in part
 *           order (the atlas: every proxy's texels in one section, none
 *           shared): per view, its mip chain, level l of side tex >> l.
 *           A pack with PSC_PROXY_ATLAS (1.2) gives each part its own side
 *           and level count (in proportion to its size: one texel density
 *           for the whole model; none for a part without a proxy); an older
 *           one, tex_size^2 texels a view, one level, for every part
 *   "XNOD"  optional (1.1): joint_count int32, each joint's index in the
 *           glTF file's "nodes" array (-1: none), what a pose file's
 *           numbers mean
 *   "XBBB"  optional, the billboard (the far level of detail: the whole
 *           model at rest in a few small views): per view its image axes,
 *           right and up (3 int32 each, Q16.16 unit vectors)
 *   "XBBT"  with XBBB: bb_side^2 textures of bb_tex^2 RGB565 texels
 *   With PSC_PROXY_NORMALS (1.3, relightable; needs PSC_PROXY_ATLAS), the
 *   surface's rest-pose normal as psc_oct16 codes (base/psc_oct.h), model
 *   space:
 *   "XVNM"  vertex_count uint16: the full mesh's vertices'
 *   "XTNM"  per part, per view, side^2: its view textures' normals at
 *           their level 0's side (1.5, PSC_PROXY_NORMALS_FULL: a crease, a
 *           door's seam, a pillar a texel or two wide relights as itself),
 *           (side / 2)^2 in a 1.3-1.4 pack; one texture for every mip level
 *   "XBBN"  with the billboard: per view, (bb_tex / 2)^2
 *   The colours stay lit by the bake's light (PSC_PROXY_BAKE_LIGHT_*), so a
 *   frame lit by it needs no normals; another light relights them by the
 *   ratio of the two lights' Lambert terms (psc_raster.h).
 *   With PSC_PROXY_DEPTH (1.4; needs PSC_PROXY_ATLAS):
 *   "XTDP"  per part, per view, (side / 2)^2 int8: how far the surface a
 *           texel shows lies behind its proxy's front along the view, in
 *           1/256 R (clamped to +-127), at half the level 0's side (depth
 *           varies slowly): each pixel of a proxy takes its depth from the surface,
 *           so proxies that cross composite as their surfaces do.
 */
#ifndef PSC_PROXY_H
#define PSC_PROXY_H

#include "3d/psc_3d_render.h"
#include "base/psc_container.h"
#include "base/psc_types.h"

#define PSC_PROXY_MAGIC "PSCPRXY\x1a"
#define PSC_PROXY_VERSION_MAJOR 1u
#define PSC_PROXY_VERSION_MINOR 5u   /* 1: the optional XNOD; 2: per-part texture sizes and mips (PSC_PROXY_ATLAS);
                                      * 3: normals (PSC_PROXY_NORMALS); 4: depth offsets (PSC_PROXY_DEPTH);
                                      * 5: normals at the texels' side (PSC_PROXY_NORMALS_FULL) */
#define PSC_PROXY_MAX_SECTIONS 24u
#define PSC_PROXY_MAX_JOINTS 1024u
#define PSC_PROXY_MAX_PARTS 4096u
#define PSC_PROXY_MAX_VERTICES (1u << 21)
#define PSC_PROXY_MAX_TRIANGLES (1u << 21)
#define PSC_PROXY_MAX_PROXY_VERTICES (1u << 20)
#define PSC_PROXY_MAX_PROXY_TRIANGLES (1u << 20)
#define PSC_PROXY_MAX_FRAMES 65536u
#define PSC_PROXY_PIECE_MAX_VERTICES 65535u   /* a part's full mesh and its proxy: uint16 indices */
#define PSC_PROXY_TEX_MIN 8u
#define PSC_PROXY_TEX_LEVEL_MIN 4u            /* a mip chain ends at 4 x 4 texels or before */
#define PSC_PROXY_ATLAS 1u                    /* XINF flags: per-part texture sizes and mip levels (1.2) */
#define PSC_PROXY_NORMALS 2u                  /* XINF flags: XVNM, XTNM (and XBBN): relightable (1.3) */
#define PSC_PROXY_DEPTH 4u                    /* XINF flags: XTDP, each texel's depth from its proxy (1.4) */
#define PSC_PROXY_NORMALS_FULL 8u             /* XINF flags: XTNM at its textures' level 0 side (1.5; else half) */
#define PSC_PROXY_DEPTH_STEPS_PER_R 256       /* XTDP's unit: 1/256 R */
/* The side of a view texture's depth offsets, of the billboard's normals and of a 1.3-1.4 pack's normals: half its
 * level 0's (psc_proxy_normal_side gives a pack's normals') */
#define PSC_PROXY_HALF_SIDE(side) ((side) >> 1)
/* The light the pack's colours were baked with, model space: base x (0.45 + 0.55 max(0, n.L)), L toward the light,
 * (0.4, 0.8, 0.45) normalised (azimuth 41.6 degrees from +z toward +x, elevation 53.0 degrees); Q2.14. */
#define PSC_PROXY_BAKE_LIGHT_X_Q14 6545
#define PSC_PROXY_BAKE_LIGHT_Y_Q14 13091
#define PSC_PROXY_BAKE_LIGHT_Z_Q14 7364
#define PSC_PROXY_BAKE_AMBIENT_Q14 7373
#define PSC_PROXY_TEX_MAX 512u
#define PSC_PROXY_POS_MAX_Q16 (64 * 65536)    /* |position| <= 64 R */
#define PSC_PROXY_NO_JOINT 0xFFFFu

extern const psc_container_format_t psc_proxy_format;

#define PSC_SECTION_PROXY_INFO PSC_FOURCC('X', 'I', 'N', 'F')
#define PSC_SECTION_PROXY_JOINTS PSC_FOURCC('X', 'J', 'N', 'T')
#define PSC_SECTION_PROXY_ANIM PSC_FOURCC('X', 'A', 'N', 'M')
#define PSC_SECTION_PROXY_PARTS PSC_FOURCC('X', 'P', 'R', 'T')
#define PSC_SECTION_PROXY_VPOS PSC_FOURCC('X', 'V', 'P', 'S')
#define PSC_SECTION_PROXY_VCOLOR PSC_FOURCC('X', 'V', 'C', 'L')
#define PSC_SECTION_PROXY_VSKIN PSC_FOURCC('X', 'V', 'S', 'K')
#define PSC_SECTION_PROXY_INDEX PSC_FOURCC('X', 'I', 'D', 'X')
#define PSC_SECTION_PROXY_PPOS PSC_FOURCC('X', 'P', 'P', 'S')
#define PSC_SECTION_PROXY_PSKIN PSC_FOURCC('X', 'P', 'S', 'K')
#define PSC_SECTION_PROXY_PINDEX PSC_FOURCC('X', 'P', 'I', 'X')
#define PSC_SECTION_PROXY_PUV PSC_FOURCC('X', 'P', 'U', 'V')
#define PSC_SECTION_PROXY_TEXTURES PSC_FOURCC('X', 'T', 'E', 'X')
#define PSC_SECTION_PROXY_BB_BASES PSC_FOURCC('X', 'B', 'B', 'B')
#define PSC_SECTION_PROXY_BB_TEXTURES PSC_FOURCC('X', 'B', 'B', 'T')
#define PSC_SECTION_PROXY_NODES PSC_FOURCC('X', 'N', 'O', 'D')
#define PSC_SECTION_PROXY_VNORMALS PSC_FOURCC('X', 'V', 'N', 'M')
#define PSC_SECTION_PROXY_TEX_NORMALS PSC_FOURCC('X', 'T', 'N', 'M')
#define PSC_SECTION_PROXY_BB_NORMALS PSC_FOURCC('X', 'B', 'B', 'N')
#define PSC_SECTION_PROXY_TEX_DEPTH PSC_FOURCC('X', 'T', 'D', 'P')
#define PSC_PROXY_MAX_NODE (1 << 24)   /* a glTF file's node index, at most */

/** "XINF", 64 bytes. */
typedef struct {
    uint32_t joint_count, part_count;
    uint32_t vertex_count, triangle_count;             /* the full mesh */
    uint32_t proxy_vertex_count, proxy_triangle_count;
    uint32_t frame_count, frame_period_us;             /* the animation's samples and their spacing */
    uint16_t view_side, tex_size;                      /* view_side^2 views; the largest view texture's side */
    uint32_t model_r_um;                               /* R in the model's units x 10^6 (information) */
    uint16_t bb_side, bb_tex;                          /* the billboard's views: bb_side^2 of bb_tex^2 (0: none) */
    int32_t bb_centre_q16[3], bb_radius_q16;           /* the sphere its views are fitted to */
    uint8_t flags;                                     /* PSC_PROXY_ATLAS (1.2; 0 before), PSC_PROXY_NORMALS (1.3),
                                                        * PSC_PROXY_DEPTH (1.4) */
    uint8_t reserved[3];
} psc_proxy_info_raw_t;

/** "XJNT" entry, 96 bytes: a node of the model's hierarchy. */
typedef struct {
    char name[44];                 /* NUL-terminated (cut to 43 bytes) */
    int32_t parent;                /* -1 for a root, else an earlier joint */
    int32_t rest_world_q16[12];    /* the joint's world transform at rest, units of R from the centre */
} psc_proxy_joint_raw_t;

enum { PSC_PROXY_KIND_PART = 0, PSC_PROXY_KIND_JOINT = 1 };
enum { PSC_PROXY_RIGID = 1u };     /* part flag: every vertex follows `joint` alone */

/** "XPRT" entry, 56 bytes: a part or a joint, with its full-mesh piece and its proxy. */
typedef struct {
    uint16_t joint;                /* the joint a part follows (M2); a joint's first part's */
    uint8_t kind;                  /* PSC_PROXY_KIND_* */
    uint8_t flags;                 /* PSC_PROXY_RIGID */
    uint32_t first_vertex, vertex_count;           /* full-mesh piece */
    uint32_t first_triangle, triangle_count;
    uint32_t first_proxy_vertex, proxy_vertex_count;   /* both 0: no proxy (drawn by its neighbours') */
    uint32_t first_proxy_triangle, proxy_triangle_count;
    int32_t centre_q16[3];         /* of the proxy's bounding sphere, at rest (no proxy: its piece's) */
    int32_t radius_q16;
    uint16_t tex_size;             /* (PSC_PROXY_ATLAS) its view textures' side: 0 without a proxy, else a power of
                                    * two PSC_PROXY_TEX_LEVEL_MIN..PSC_PROXY_TEX_MAX */
    uint8_t tex_levels;            /* (PSC_PROXY_ATLAS) mip levels, 1.., the last at least 4 texels a side */
    uint8_t reserved;
} psc_proxy_part_raw_t;

/** "XVSK" / "XPSK" entry, 16 bytes: up to four joints and their weights (unused: weight 0). */
typedef struct {
    uint16_t joint[4];
    uint16_t weight_q15[4];
} psc_proxy_skin_raw_t;

_Static_assert(sizeof(psc_proxy_info_raw_t) == 64, "XINF is 64 bytes");
_Static_assert(sizeof(psc_proxy_joint_raw_t) == 96, "a joint is 96 bytes");
_Static_assert(sizeof(psc_proxy_part_raw_t) == 56, "a part is 56 bytes");
_Static_assert(sizeof(psc_proxy_skin_raw_t) == 16, "a skin entry is 16 bytes");

/** A parsed proxy pack (points into the caller's buffer). */
typedef struct {
    uint32_t joint_count, part_count, vertex_count, triangle_count;
    uint32_t proxy_vertex_count, proxy_triangle_count, frame_count, frame_period_us;
    uint32_t view_side, view_count, tex_size, model_r_um;
    const psc_proxy_joint_raw_t *joints;
    const int32_t *anim_q16;       /* frame_count x joint_count x 12, or NULL */
    const psc_proxy_part_raw_t *parts;
    const int32_t *position_q16;
    const uint32_t *color;
    const psc_proxy_skin_raw_t *skin;
    const uint16_t *index;
    const int32_t *proxy_position_q16;
    const psc_proxy_skin_raw_t *proxy_skin;
    const uint16_t *proxy_index;
    const uint16_t *proxy_uv;
    const uint16_t *texels;
    bool atlas;                                        /* per-part sizes and levels (1.2), else tex_size and 1 */
    uint32_t bb_side, bb_view_count, bb_tex;           /* 0: no billboard */
    int32_t bb_centre_q16[3], bb_radius_q16;
    const int32_t *bb_axes_q16;                        /* per view: right[3], up[3] */
    const uint16_t *bb_texels;
    const int32_t *node;                               /* joint_count: its glTF file's node index (-1 none), or NULL */
    const uint16_t *vertex_normals;                    /* PSC_PROXY_NORMALS: XVNM, XTNM, XBBN (NULL without) */
    uint8_t normal_shift;                              /* XTNM's side: level 0's >> this (0: PSC_PROXY_NORMALS_FULL) */
    const uint16_t *tex_normals;
    const uint16_t *bb_normals;
    const int8_t *tex_depth;                           /* PSC_PROXY_DEPTH: XTDP (NULL without) */
} psc_proxy_model_t;

/** The side of the normals of a view texture whose level 0 is side texels a side, in pack m. */
static inline uint32_t psc_proxy_normal_side(const psc_proxy_model_t *m, uint32_t side)
{
    return side >> m->normal_shift;
}

/**
 * Validate and parse a proxy pack in buf[0..len) (aligned to 8): the
 * container, every count against its limit and its section's size, every
 * part's ranges, index, joint, weight sum and position, the joints' parents.
 * On failure returns the status and fills *err (err may be NULL). Nothing is
 * read outside buf.
 */
psc_status_t psc_proxy_parse(const void *buf, size_t len, psc_proxy_model_t *out, psc_container_error_t *err);

/** Part i's view textures: their side (0: none), mip levels, and texels per view (the whole chain). */
typedef struct {
    uint32_t side, levels, chain;
} psc_proxy_tex_t;

psc_proxy_tex_t psc_proxy_part_tex(const psc_proxy_model_t *m, uint32_t i);

/** The box of the full mesh at rest (what the orbit camera is centred on, for every pose). */
void psc_proxy_rest_bounds(const psc_proxy_model_t *m, psc_vec3_q16_t *lo, psc_vec3_q16_t *hi);

/** The animation's length in microseconds (0 without one). */
uint64_t psc_proxy_duration_us(const psc_proxy_model_t *m);

/**
 * The skin matrices at t_us microseconds into the animation (looping),
 * linear between samples; the rest pose (identities) for t_us < 0 or a model
 * without animation. skin: joint_count matrices.
 */
void psc_proxy_pose_at(const psc_proxy_model_t *m, int64_t t_us, psc_mat4_q16_t *skin);

/* ---- drawing (psc_proxy_draw.c) ------------------------------------------------ */

typedef enum {
    PSC_PROXY_LOD_PROXIES = 0,     /* the proxies with their view textures (the middle distance) */
    PSC_PROXY_LOD_FULL = 1,        /* the full mesh (near, and the comparison) */
    PSC_PROXY_LOD_BILLBOARD = 2    /* a quad facing the camera with the billboard's nearest view (far; rest pose) */
} psc_proxy_lod_t;

/** A bone of a joint strip and its vertices' weights on it, summed (Q0.15 x vertices). */
typedef struct {
    uint32_t joint;
    uint32_t weight;
} psc_proxy_bone_t;

/** A model's drawing state; everything in the caller's workspace. */
typedef struct {
    const psc_proxy_model_t *m;
    int32_t *posed_q16;            /* skinned full-mesh positions (non-rigid pieces) */
    int32_t *proxy_posed_q16;      /* skinned proxy positions (non-rigid parts, joints) */
    psc_mesh_t *meshes;            /* per part (and joint strip) */
    psc_texture_t *textures;       /* 3 per draw */
    psc_3d_draw_t *draws;
    uint32_t max_draws;
    psc_tex_filter_t filter;       /* of the view textures: PSC_TEX_EDGES (psc_proxy_init's: nearest, bilinear at the
                                    * silhouette's texels: the held-out human's IoU 0.942 -> 0.958 at 6 R for 7 % more instructions) */
    int32_t bb_pos_q16[12];        /* the billboard's corners this frame */
    uint16_t bb_uv[3][8];          /* and their coordinates in its three views */
    psc_proxy_lod_t lod;           /* psc_proxy_lod_pick's last choice */
    int32_t focal_px_q16;          /* psc_proxy_lod_pick's focal length, for the mip levels (0: level 0 always) */
    int32_t full_px, billboard_px; /* its thresholds: the model's projected radius in pixels beyond which the full
                                    * mesh is drawn whatever it costs (init 0: never) and under which the billboard
                                    * (init 40) */
    uint32_t texels_per_r;         /* the views' texel density (texels per R, the parts weighing as their areas):
                                    * nearer than a radius of that many pixels, the views are magnified */
    uint32_t area_r2_q16;          /* the model's silhouette in R^2 (Q16): its billboard's covered share */
    uint32_t area_gain_q8;         /* pixels the full mesh writes per pixel of silhouette (Q8): psc_proxy_observe's */
    uint32_t proxy_gain_q8;        /* and the proxies (their own overlaps and alpha-tested edges); until a frame of
                                    * each has been seen, the other's */
    uint8_t gains_seen;            /* bit 0: the full mesh's gain observed, bit 1: the proxies' */
    uint32_t silhouette_px;        /* the last pick's silhouette on the screen, for psc_proxy_observe (0: none) */
    bool area_seen;                /* a frame has set a gain */
    psc_proxy_lod_t observed_lod;  /* the level psc_proxy_observe's next frame was drawn at (psc_proxy_lod_pick's) */
    uint32_t *view_area_r2_q16;    /* the silhouette's area in R^2 (Q16) from each billboard view */
    uint32_t screen_w, screen_h;   /* psc_proxy_set_screen's (0: the area is not clipped) */
    bool relit;                    /* psc_proxy_set_light given: lit by `light` (else as baked) */
    int32_t light_q16[3];          /* toward the light, model space, unit (Q16.16) */
    uint16_t ambient_q14;
    uint32_t *relit_color;         /* (packs with normals) the full mesh's vertex colours relit this frame */
    psc_texture_t *normal_tex;     /* (packs with normals) 3 per draw: the views' normals */
    int32_t *joint_light_q14;      /* (packs with normals) per joint, this frame: the light in its rest frame (Q2.14) */
    int16_t *strip_light_q14;      /* (packs with normals) per skinned proxy vertex: its joints' lights blended */
    uint32_t blended_vertices;     /* full-mesh vertices that follow more than one joint (they cost more) */
    uint32_t *strip_first;         /* part_count + 1: part i's bones are strip_bones[strip_first[i] .. [i + 1]) */
    psc_proxy_bone_t *strip_bones; /* a joint strip's bones, for its M3 */
} psc_proxy_t;

/* The level of detail's cost model, in instructions (callgrind, x86-64, gcc -O2): `build/bench/proxy --callgrind`
 * counts both levels over four models (a rigid assembly, the skinned bar, two held-out characters), two screens and
 * six distances and refits these by least squares of the relative error. A level costs its vertices (posing,
 * projection), its triangles (set-up), the rows its triangles span (about sqrt(area x triangles / 2): half face the
 * camera) and its pixels: a view-textured pixel samples three textures; a full-mesh pixel costs little beyond its
 * row's loop, and a full-mesh vertex that blends joints costs nearly twice one that follows one joint or none (a
 * held-out robot, whose 7 068 vertices mostly follow one joint each, showed a cost a vertex alone cannot fit). */
#define PSC_PROXY_COST_VERTEX 859u
#define PSC_PROXY_COST_TRIANGLE 194u
#define PSC_PROXY_COST_ROW 499u
#define PSC_PROXY_COST_PIXEL 655u   /* (with soft silhouettes, psc_3d_set_soft_silhouettes) */
#define PSC_PROXY_COST_FULL_VERTEX 390u
#define PSC_PROXY_COST_FULL_BLEND 334u   /* more for a vertex that blends joints */
#define PSC_PROXY_COST_FULL_TRIANGLE 175u
#define PSC_PROXY_COST_FULL_ROW 590u
#define PSC_PROXY_COST_SCREEN_PIXEL 1u   /* either level: the frame's clear, a pixel of the screen */
/* Relit (psc_proxy_set_light; the bench's "relit" lines): a proxy pixel reads a normal (four texels) and divides; a
 * full-mesh vertex is relit, one that blends joints renormalises its light as well. */
#define PSC_PROXY_COST_RELIT_PIXEL 630u
#define PSC_PROXY_COST_RELIT_VERTEX 254u
#define PSC_PROXY_COST_RELIT_BLEND 518u

/** A level's estimated cost for one frame (in instructions of the x86-64 build; what matters is their ratio), and
 *  what it was estimated from: the model's radius and the area it covers on the screen, in pixels. */
typedef struct {
    uint64_t proxies, full;
    int32_t radius_px;
    uint32_t area_px;         /* the pixels a frame writes at the level last picked: the silhouette's times the gain frames
                               * of that level have shown */
    uint32_t silhouette_px;   /* the silhouette's, from the billboard, clipped by the screen */
} psc_proxy_cost_t;

/** Workspace bytes for drawing model m (0 if it cannot be drawn). */
size_t psc_proxy_workspace_size(const psc_proxy_model_t *m);

/** The vertices one frame submits to the pipeline at most (for psc_3d_config_t.max_vertices). */
uint32_t psc_proxy_max_vertices(const psc_proxy_model_t *m);

/** Prepare to draw m. ws: psc_proxy_workspace_size(m) bytes aligned to 8. */
psc_status_t psc_proxy_init(psc_proxy_t *p, const psc_proxy_model_t *m, void *ws, size_t ws_size);

/**
 * The level of detail for the model seen through camera_from_object by a
 * camera of focal length focal_px_q16 (pixels, Q16.16): the billboard while
 * the model's projected radius is under billboard_px; else the cheaper of
 * the proxies and the full mesh by psc_proxy_cost (the other taken only
 * when its estimate is 5 % lower; before psc_proxy_observe has seen a frame,
 * the level whose cost against the other's is least at the worse of the
 * pixels written per pixel of silhouette 1.1 and 1.6, the range the bench's
 * models write); the full mesh while the radius exceeds
 * full_px when the caller sets it (e.g. twice texels_per_r: the views never
 * magnified more than twice). The billboard's threshold is crossed back
 * 10 % beyond it. Without a billboard the far level is the proxies. The
 * focal length is kept for psc_proxy_frame's choice of mip levels; draw the
 * level and give psc_proxy_observe what it wrote.
 */
psc_proxy_lod_t psc_proxy_lod_pick(psc_proxy_t *p, const psc_mat4_q16_t *camera_from_object, int32_t focal_px_q16);

/** Both levels' estimated costs for that camera: vertices, triangles, the rows and pixels the model's silhouette
 *  covers (the three nearest billboard views' covered shares of their squares, blended, clipped by the screen of
 *  psc_proxy_set_screen). */
psc_proxy_cost_t psc_proxy_cost(const psc_proxy_t *p, const psc_mat4_q16_t *camera_from_object, int32_t focal_px_q16);

/** What the frame drawn at psc_proxy_lod_pick's level wrote (psc_3d_render's stats): the pixels written per pixel
 *  of the estimated silhouette (overlaps, the pose) corrects the next estimates: the first frame's wholly, then a
 *  quarter of the way a frame. */
void psc_proxy_observe(psc_proxy_t *p, const psc_3d_stats_t *st);

/** The screen the model is drawn on, for psc_proxy_cost's area (0 x 0: not clipped). */
void psc_proxy_set_screen(psc_proxy_t *p, uint32_t width, uint32_t height);

/** (psc_proxy_init) The silhouette's area and the views' texel density, from the pack. */
void psc_proxy_lod_prepare(psc_proxy_t *p);

/** The focal length in pixels (Q16.16) of a camera `width` pixels wide with horizontal field of view hfov:
 *  (width / 2) / tan(hfov / 2); 0 for a field outside (0, 180) degrees. */
int32_t psc_proxy_focal_px_q16(uint32_t width, psc_bam_t hfov);

/**
 * Light the model from toward_q16 (model space, any length but not zero)
 * with ambient_q14 (0..16384; the bake's is PSC_PROXY_BAKE_AMBIENT_Q14)
 * instead of as baked: every level relit each frame, its normals turned
 * with the pose (proxies: the part's rotation; the full mesh: each vertex's
 * blended skin). NULL returns to the baked lighting (the fastest: no
 * normals read). PSC_ERR_UNSUPPORTED for a pack without normals (baked
 * before 1.3 or with --no-normals), PSC_ERR_ARG for a zero direction.
 */
psc_status_t psc_proxy_set_light(psc_proxy_t *p, const int32_t *toward_q16, uint16_t ambient_q14);

/** The camera's focal length for psc_proxy_frame's mip levels (psc_proxy_lod_pick sets it too; 0: level 0). */
void psc_proxy_set_focal(psc_proxy_t *p, int32_t focal_px_q16);

/**
 * This frame's draws for the model posed by skin (joint_count matrices)
 * and seen through camera_from_object (rigid). ids: every surface drawn flat
 * in colour part index + 1 (the mask of PSC_SHADE_VIEWS for proxies). *draws
 * and *n receive the list for psc_3d_render (valid until the next call).
 */
psc_status_t psc_proxy_frame(psc_proxy_t *p, const psc_mat4_q16_t *skin, const psc_mat4_q16_t *camera_from_object,
                             psc_proxy_lod_t lod, bool ids, const psc_3d_draw_t **draws, unsigned *n);

#endif
