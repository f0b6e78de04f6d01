/* SPDX-License-Identifier: MIT */
/*
 * psc_patch_frame.h - one frame of a Hash patch character: pose the skeleton
 * from an action at a time (psc_patch_pose), solve the spline tangents
 * (psc_patch_tangents), and tessellate the patches for a camera into
 * triangle meshes for the 3D pipeline (psc_patch_tessellate). Every buffer
 * lives in one workspace sized at start-up (psc_patch_workspace_size);
 * nothing is allocated per frame.
 *
 * Tessellation (Hash's recursive halving, crack-free by construction):
 *  - each edge is halved (de Casteljau at 1/2) until every piece passes the
 *    flatness test against a tolerance taken from screen space for this
 *    frame: tol_px pixels at the edge's nearest depth (so near edges split
 *    more than far ones); an edge's depth depends on the edge alone, so the
 *    two patches that share it halve it alike and share its vertices;
 *  - a patch is halved across u as often as its deeper u edge needs and
 *    across v likewise, the direction with more halvings left first; each
 *    halving makes the middle curve from the two halved edges' midpoints
 *    with handles interpolated linearly from the other two edges' handles
 *    (the interior comes from the perimeter alone: no twist vectors); a
 *    boundary piece that has reached its edge's depth is MakeFlat'ed before
 *    any further halving;
 *  - the grid's inner rows are stitched to each edge's own vertices, so a
 *    patch halved more often than its neighbour adds no vertex on their
 *    shared edge: no cracks and no T-junctions;
 *  - patches of 3, 5 or 6 sides are n quads around a contrived centre point
 *    (their edges are halved at least once);
 *  - normals: corner normals from the boundary tangents, averaged at each
 *    point over its patches; along curves the seed's c and s rules;
 *  - a patch whose edges are all flat and whose corner normals all face
 *    away from the eye is dropped before it is split (culling);
 *  - lazy: a patch none of whose points moved, whose edges keep their
 *    depths, is emitted from last frame's vertices.
 */
#ifndef PSC_PATCH_FRAME_H
#define PSC_PATCH_FRAME_H

#include "3d/psc_3d_math.h"
#include "3d/psc_3d_render.h"
#include "mesh/psc_mesh.h"
#include "patch/psc_patch.h"
#include "patch/psc_patch_curve.h"

#define PSC_PATCH_MAX_DEPTH 6u        /* halvings of one edge or one patch direction at most */
#define PSC_PATCH_MAX_BATCHES 8u      /* output meshes of one frame (each below 65536 vertices) */
#define PSC_PATCH_BATCH_VERTICES 65535u

/** Output budget, fixed at start-up. */
typedef struct {
    uint32_t max_vertices;            /* all batches together */
    uint32_t max_triangles;
    uint8_t max_depth;                /* 3..PSC_PATCH_MAX_DEPTH (a quarter of a hooked segment on an n-sided patch needs 3) */
} psc_patch_limits_t;

/** What a tessellation did. */
typedef struct {
    uint32_t patches;                 /* drawn (n-sided ones count once) */
    uint32_t culled;                  /* dropped before splitting */
    uint32_t reused;                  /* emitted from last frame's vertices */
    uint32_t triangles, vertices;
    uint32_t depth_capped;            /* edges or patches held at max_depth */
    uint32_t budget_raised;           /* tolerance doublings to stay within the budget */
} psc_patch_stats_t;

/** One vertex of an edge's or a patch's grid. */
typedef struct {
    int32_t p[3];                     /* Q16.16 */
    int32_t n[3];                     /* unit, Q16.16 */
} psc_patch_vtx_t;

typedef struct {
    const psc_patch_model_t *m;
    psc_patch_limits_t lim;
    /* per point */
    int32_t (*pos)[3];                /* posed positions */
    int32_t (*prev_pos)[3];           /* last frame's */
    int32_t pose_action;              /* the action psc_patch_pose_begin posed (-1: the rest pose) */
    uint32_t pose_time_ms;            /* and its time within the action's duration */
    int32_t (*nrm)[3];                /* normals, unit Q16.16 */
    int32_t (*prev_nrm)[3];
    /* per CP: tangent handles as offsets from its point */
    int32_t (*h_in)[3], (*h_out)[3];
    /* per edge */
    uint16_t (*edge_pt)[2];           /* start and end points */
    uint8_t *edge_depth, *prev_edge_depth;
    uint8_t *edge_kind;               /* psc_curve_kind_t of the whole edge */
    uint8_t *edge_changed;            /* its curve or depth differs from last frame's */
    uint32_t *edge_parent;            /* a hook's part of a segment: the whole segment's edge (or itself) */
    uint8_t *edge_min;                /* least depth: its own, and what its parts need */
    uint32_t *edge_vtx;               /* first vertex in vtx_pool: 2^depth + 1 of them */
    psc_curve_t *edge_prev;           /* last frame's curve */
    psc_patch_vtx_t *vtx_pool;        /* this frame's edge vertices */
    uint32_t vtx_pool_size;
    /* per face: its last emission, kept for lazy re-evaluation */
    uint32_t *face_cache;             /* first vertex in last frame's cache, PSC_PATCH_NO_CACHE none */
    uint16_t *face_cache_count;
    uint32_t *face_cache_tri;
    uint16_t *face_cache_tris;
    psc_patch_vtx_t *cache_vtx[2];    /* by frame parity: last frame's and this frame's */
    uint32_t *cache_uv[2];            /* their places in their patches */
    uint16_t *cache_idx[2];
    uint32_t cache_used_vtx, cache_used_tri;
    /* bones */
    psc_mat4_q16_t *bone_world;       /* posed, model space */
    psc_mat4_q16_t *bone_skin;        /* posed * rest^-1 */
    psc_mat4_q16_t *bone_rest_inv;
    int32_t (*bone_rot_q30)[4];       /* this frame's local rotations */
    int32_t (*bone_trans_q16)[3];
    /* scratch for one patch */
    psc_patch_vtx_t *grid;            /* (2^max_depth + 1)^2 */
    uint16_t *grid_index;
    psc_patch_vtx_t *inner;           /* an n-sided patch's curves to its centre */
    /* output */
    int32_t *out_pos;                 /* 3 per vertex */
    int16_t *out_nrm;                 /* 3 per vertex, Q1.14 */
    uint32_t *out_uv;                 /* each vertex's place in its patch (PSC_PATCH_UV) */
    uint32_t *out_color;
    uint16_t *out_index;              /* 3 per triangle, relative to the batch's first vertex */
    uint32_t vtx_total, tri_total;
    uint32_t batch_first_vertex, batch_first_tri;
    uint32_t batch_start_vertex[PSC_PATCH_MAX_BATCHES], batch_start_tri[PSC_PATCH_MAX_BATCHES];
    psc_mesh_t batch[PSC_PATCH_MAX_BATCHES];
    unsigned batch_count;
    uint32_t frame;
} psc_patch_t;

#define PSC_PATCH_NO_CACHE 0xFFFFFFFFu

/*
 * A vertex's place in its patch (out_uv): u and v in Q0.13 (8192 = 1; a
 * vertex of a patch halved at most PSC_PATCH_MAX_DEPTH times lies on a
 * multiple of 1/64), u along the patch's first side (from its first corner
 * to its second), v along its last side run backwards (from the first corner
 * to the fourth); for an n-sided patch, in which of its n quads (each from
 * corner k: u toward side k's midpoint, v toward side k-1's).
 */
#define PSC_PATCH_UV_ONE 8192u
#define PSC_PATCH_UV(u_q13, v_q13, quad) ((uint32_t)(u_q13) | (uint32_t)(v_q13) << 14 | (uint32_t)(quad) << 28)
#define PSC_PATCH_UV_U(uv) ((uv) & 0x3FFFu)
#define PSC_PATCH_UV_V(uv) ((uv) >> 14 & 0x3FFFu)
#define PSC_PATCH_UV_QUAD(uv) ((uv) >> 28)

/** Workspace bytes for model m within lim (0 when lim is out of range). */
size_t psc_patch_workspace_size(const psc_patch_model_t *m, const psc_patch_limits_t *lim);

/** Start: ws (aligned to 8) of psc_patch_workspace_size bytes. The rest pose is posed. */
psc_status_t psc_patch_init(psc_patch_t *p, const psc_patch_model_t *m, const psc_patch_limits_t *lim, void *ws,
                            size_t ws_size);

/**
 * Pose the points: action (index into the model's actions, or -1 for the
 * rest pose) at time_ms (looping over the action's duration): bones from
 * their channels, points from their bones, then muscle offsets.
 */
void psc_patch_pose(psc_patch_t *p, int action, uint32_t time_ms);

/** psc_patch_pose in two steps, for a caller that adjusts the bones between: the action's channels into
 *  bone_rot_q30 and bone_trans_q16 (and the muscles into the points), then the bones and the points from them. */
void psc_patch_pose_begin(psc_patch_t *p, int action, uint32_t time_ms);
void psc_patch_pose_finish(psc_patch_t *p);

/** Solve every CP's tangent handles from the posed points (hooks placed on their segments first). */
void psc_patch_tangents(psc_patch_t *p);

/** A camera for the tessellation. */
typedef struct {
    psc_mat4_q16_t camera_from_object;   /* rigid */
    int32_t focal_px_q16;                /* pixels per unit of x/z at depth 1: (width / 2) / tan(hfov / 2) */
    int32_t tol_px_q16;                  /* allowed chord error in pixels */
    int32_t tol_units_q16;               /* > 0: allowed chord error in units of R everywhere, instead */
    int32_t near_q16;                    /* depths below it count as it */
    bool cull;                           /* drop patches that face away */
} psc_patch_camera_t;

/**
 * Tessellate the posed, tangent-solved patches for cam into p->batch[0 ..
 * p->batch_count): positions Q16.16, normals Q1.14, the patches' colours.
 * When the budget would overflow, the tolerance is doubled and the frame
 * tessellated again (counted in stats). stats may be NULL.
 */
psc_status_t psc_patch_tessellate(psc_patch_t *p, const psc_patch_camera_t *cam, psc_patch_stats_t *stats);

/* The light the character is drawn with: from the upper left, behind the eye (camera space, as the object
 * scene's), and the ambient share. */
#define PSC_PATCH_LIGHT_X (-26000)
#define PSC_PATCH_LIGHT_Y 39000
#define PSC_PATCH_LIGHT_Z (-45000)
#define PSC_PATCH_AMBIENT_Q8 72

/**
 * The 3D pipeline's draws for the frame just tessellated, seen through cam: Gouraud, lit, back faces culled
 * when cam->cull. d has room for PSC_PATCH_MAX_BATCHES; returns how many it filled.
 */
unsigned psc_patch_draws(const psc_patch_t *p, const psc_patch_camera_t *cam, psc_3d_draw_t *d);

/** The cubic of edge e this frame (its part of its spline segment; after psc_patch_tangents). */
void psc_patch_edge_curve(const psc_patch_t *p, uint32_t e, psc_curve_t *c);

/** Local rotation (Q2.30 quaternion) and translation of bone b this frame, as posed. */
void psc_patch_bone_pose(const psc_patch_t *p, unsigned b, int32_t rot_q30[4], int32_t trans_q16[3]);

/** Evaluate channel c at time_ms: v[0..4) (rotations normalised). Keys are a Catmull-Rom spline in time. */
void psc_patch_channel_eval(const psc_patch_model_t *m, const psc_patch_channel_t *c, uint32_t time_ms,
                            int32_t v[4]);

#endif
