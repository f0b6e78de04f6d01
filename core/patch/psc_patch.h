/* SPDX-License-Identifier: MIT */
/*
 * psc_patch.h - a Hash spline-patch character in memory, and the patch pack
 * (.ppk) that holds one on the device, read in place like every Periscope
 * file (base/psc_container.h).
 *
 * The surface (Hash, "A complete algorithm for real-time spline-based
 * character animation"):
 *  - Points: positions that move (skinned by bones, moved by muscle
 *    channels). A hook's point is not stored: it is computed every frame
 *    on the spline segment it hooks onto.
 *  - Splines: sequences of control points (CPs), open or closed. A CP names
 *    its point (several CPs of crossing splines share one point: A:M's
 *    "stacked" CPs) and carries its bias: in/out alpha and gamma (degrees,
 *    as int16 binary angles, 65536 per turn) and magnitude (Q4.12, 4096 =
 *    the default). Tangents are solved from the points every frame
 *    (psc_patch_tangent.c); two consecutive CPs of a spline and their
 *    tangents make one cubic segment.
 *  - Edges: a spline segment, or a dyadic part of one (quarters: lo..hi of
 *    0..4) where a hook splits it; patches that share an edge share its
 *    subdivision and so its vertices.
 *  - Patches: 3 to 6 edges around the patch, each referenced with a
 *    direction; a colour.
 * The animation:
 *  - Bones: a hierarchy with a rest pose; each point follows one bone, or two
 *    with a weight.
 *  - Actions: channels of keys over time (ms): a bone's rotation (a
 *    quaternion relative to its rest, Q2.30) or translation (Q16.16, in its
 *    rest frame), or a point's muscle offset (Q16.16, before tangents).
 *
 * Units: positions are Q16.16 in units of R, half the diagonal of the rest
 * pose's control-point bounding box (so the rest pose lies within +-1.0 of
 * the box centre... and animation may take it further).
 *
 * Pack layout: the container of base/psc_container.h with magic
 * "PSCPTCH\x1a", version PSC_PATCH_VERSION_MAJOR.MINOR; sections (raw
 * structs below, little-endian, exactly their sizes times the counts of PINF):
 *   "PINF" psc_patch_info_raw_t                         required
 *   "PPNT" point_count x 3 int32 rest positions (Q16.16)  required
 *   "PCPT" cp_count x psc_patch_cp_t                      required
 *   "PSPL" spline_count x psc_patch_spline_t              required
 *   "PHOK" hook_count x psc_patch_hook_t                  when hooks
 *   "PEDG" edge_count x psc_patch_edge_t                  required
 *   "PPAT" patch_count x psc_patch_face_t                 required
 *   "PCOL" color_count x uint32 XRGB                      required
 *   "PHND" cp_count x 6 int32: in and out handles (Q16.16, at rest) of the
 *          CPs flagged FIXED (others ignored)             when fixed CPs
 *   "PBON" bone_count x psc_patch_bone_t                  when bones
 *   "PSKN" point_count x psc_patch_skin_t                 when bones
 *   "PACT" action_count x psc_patch_action_t              when actions
 *   "PCHN" channel_count x psc_patch_channel_t            when actions
 *   "PKEY" key_count x psc_patch_key_t                    when actions
 * Unknown sections are skipped.
 */
#ifndef PSC_PATCH_H
#define PSC_PATCH_H

#include "base/psc_container.h"
#include "base/psc_fixed.h"
#include "base/psc_types.h"

#define PSC_PATCH_MAGIC "PSCPTCH\x1a"
#define PSC_PATCH_VERSION_MAJOR 1u
#define PSC_PATCH_VERSION_MINOR 0u
#define PSC_PATCH_MAX_SECTIONS 24u

/* Limits: every per-frame buffer is sized from these and the counts. */
#define PSC_PATCH_MAX_POINTS 16384u
#define PSC_PATCH_MAX_CPS 32768u
#define PSC_PATCH_MAX_SPLINES 8192u
#define PSC_PATCH_MAX_EDGES 32768u
#define PSC_PATCH_MAX_FACES 16384u
#define PSC_PATCH_MAX_COLORS 256u
#define PSC_PATCH_MAX_BONES 256u
#define PSC_PATCH_MAX_ACTIONS 32u
#define PSC_PATCH_MAX_CHANNELS 4096u
#define PSC_PATCH_MAX_KEYS (1u << 20)
/* Rest positions lie within +-PSC_PATCH_MAX_COORD units (of R). */
#define PSC_PATCH_MAX_COORD_Q16 (64 * PSC_Q16_ONE)

/** The pack's container format (reader and writer). */
extern const psc_container_format_t psc_patch_format;

#define PSC_SECTION_PATCH_INFO PSC_FOURCC('P', 'I', 'N', 'F')
#define PSC_SECTION_PATCH_POINTS PSC_FOURCC('P', 'P', 'N', 'T')
#define PSC_SECTION_PATCH_CPS PSC_FOURCC('P', 'C', 'P', 'T')
#define PSC_SECTION_PATCH_SPLINES PSC_FOURCC('P', 'S', 'P', 'L')
#define PSC_SECTION_PATCH_HOOKS PSC_FOURCC('P', 'H', 'O', 'K')
#define PSC_SECTION_PATCH_EDGES PSC_FOURCC('P', 'E', 'D', 'G')
#define PSC_SECTION_PATCH_FACES PSC_FOURCC('P', 'P', 'A', 'T')
#define PSC_SECTION_PATCH_COLORS PSC_FOURCC('P', 'C', 'O', 'L')
#define PSC_SECTION_PATCH_HANDLES PSC_FOURCC('P', 'H', 'N', 'D')
#define PSC_SECTION_PATCH_BONES PSC_FOURCC('P', 'B', 'O', 'N')
#define PSC_SECTION_PATCH_SKIN PSC_FOURCC('P', 'S', 'K', 'N')
#define PSC_SECTION_PATCH_ACTIONS PSC_FOURCC('P', 'A', 'C', 'T')
#define PSC_SECTION_PATCH_CHANNELS PSC_FOURCC('P', 'C', 'H', 'N')
#define PSC_SECTION_PATCH_KEYS PSC_FOURCC('P', 'K', 'E', 'Y')

/** "PINF", 64 bytes. */
typedef struct {
    uint32_t point_count, cp_count, spline_count, hook_count;
    uint32_t edge_count, face_count, color_count, bone_count;
    uint32_t action_count, channel_count, key_count;
    uint32_t scale_q16;          /* R in the source file's units, Q16.16 (for reference) */
    int32_t center_q16[3];       /* the rest box centre in source units (for reference) */
    uint32_t reserved;
} psc_patch_info_raw_t;

#define PSC_PATCH_CP_HOOK 1u     /* the CP's point is a hook's */
#define PSC_PATCH_CP_FIXED 2u    /* its handles are given (PHND), not solved: Bezier patches (.bpt) */
#define PSC_PATCH_CP_PEAKED 4u   /* a corner: each handle points at its neighbour, a third of the way (before bias) */

/** A control point on a spline ("PCPT"), 16 bytes. */
typedef struct {
    uint16_t point;
    uint16_t flags;
    int16_t in_alpha, in_gamma;  /* bias angles: 65536 per turn */
    int16_t out_alpha, out_gamma;
    uint16_t in_mag_q12, out_mag_q12;   /* 4096 = the default magnitude */
} psc_patch_cp_t;

#define PSC_PATCH_SPLINE_CLOSED 1u

/** A spline ("PSPL"), 8 bytes: cps[first .. first + count). */
typedef struct {
    uint32_t first;
    uint16_t count;              /* 2 or more */
    uint16_t flags;
} psc_patch_spline_t;

/** A hook ("PHOK"), 8 bytes: point lies at frac_q2 quarters along segment seg of spline. */
typedef struct {
    uint16_t point;
    uint16_t spline;
    uint16_t seg;                /* the segment from cps[first + seg] to the next CP */
    uint8_t frac_q2;             /* 1, 2 or 3 quarters */
    uint8_t reserved;
} psc_patch_hook_t;

/** An edge ("PEDG"), 8 bytes: quarters lo..hi of a spline segment. */
typedef struct {
    uint16_t spline;
    uint16_t seg;
    uint8_t lo_q2, hi_q2;        /* 0 <= lo < hi <= 4, hi - lo a power of two, lo a multiple of it */
    uint8_t min_depth;           /* halvings this edge must have at least (patches of 3, 5 or 6 sides: 1) */
    uint8_t reserved;
} psc_patch_edge_t;

#define PSC_PATCH_EDGE_REVERSED 0x80000000u

/* Sides a patch may have: A:M's 3-, 4- and 5-point patches, and a patch whose side runs through a point it does
 * not list as a corner (around hooks) gains one. */
#define PSC_PATCH_MAX_SIDES 6u

/** A patch ("PPAT"), 28 bytes: its edges in order around it. */
typedef struct {
    uint8_t sides;               /* 3 .. PSC_PATCH_MAX_SIDES */
    uint8_t color;               /* index into the colours */
    uint16_t flags;
    uint32_t edge[PSC_PATCH_MAX_SIDES];   /* edge index | PSC_PATCH_EDGE_REVERSED (run from its end to its start) */
} psc_patch_face_t;

/** The quads a face is tessellated as: one for a four-sided patch, n around the centre of an n-sided one. */
static inline uint32_t psc_patch_face_quads(const psc_patch_face_t *f)
{
    return f->sides == 4 ? 1u : f->sides;
}

#define PSC_PATCH_NO_BONE 0xFFFFu

/** A bone ("PBON"), 48 bytes. */
typedef struct {
    uint16_t parent;             /* PSC_PATCH_NO_BONE for a top bone; parents come before children */
    uint16_t flags;
    int32_t offset_q16[3];       /* rest head in the parent's rest frame (top bones: model space) */
    int32_t rot_q30[4];          /* rest rotation relative to the parent's: x y z w, unit */
    int32_t reserved[4];
} psc_patch_bone_t;

/** A point's bones ("PSKN"), 8 bytes: bone0 with weight 1 - w1, bone1 with w1. */
typedef struct {
    uint16_t bone0, bone1;       /* bone1 PSC_PATCH_NO_BONE: bone0 alone */
    uint16_t w1_q15;             /* 0..32768 */
    uint16_t reserved;
} psc_patch_skin_t;

/** An action ("PACT"), 40 bytes. */
typedef struct {
    char name[28];               /* NUL-padded */
    uint32_t duration_ms;        /* it loops over [0, duration) */
    uint32_t first_channel;
    uint16_t channel_count;
    uint16_t flags;
} psc_patch_action_t;

typedef enum {
    PSC_PATCH_CHAN_ROTATE = 1,   /* bone target; keys: quaternion x y z w, Q2.30 */
    PSC_PATCH_CHAN_TRANSLATE = 2,/* bone target; keys: x y z, Q16.16, in its rest frame */
    PSC_PATCH_CHAN_MUSCLE = 3,   /* point target; keys: offset x y z, Q16.16, model space at rest */
} psc_patch_chan_kind_t;

/** A channel ("PCHN"), 12 bytes: keys[first_key .. first_key + key_count), times increasing. */
typedef struct {
    uint16_t target;             /* bone or point */
    uint8_t kind;                /* psc_patch_chan_kind_t */
    uint8_t reserved;
    uint32_t first_key;
    uint32_t key_count;          /* 1 or more */
} psc_patch_channel_t;

/** A key ("PKEY"), 20 bytes. */
typedef struct {
    uint32_t time_ms;
    int32_t v[4];
} psc_patch_key_t;

/* the raw structs are read in place: their sizes are the format's */
_Static_assert(sizeof(psc_patch_info_raw_t) == 64, "PINF is 64 bytes");
_Static_assert(sizeof(psc_patch_cp_t) == 16, "a CP is 16 bytes");
_Static_assert(sizeof(psc_patch_spline_t) == 8, "a spline is 8 bytes");
_Static_assert(sizeof(psc_patch_hook_t) == 8, "a hook is 8 bytes");
_Static_assert(sizeof(psc_patch_edge_t) == 8, "an edge is 8 bytes");
_Static_assert(sizeof(psc_patch_face_t) == 28, "a patch is 28 bytes");
_Static_assert(sizeof(psc_patch_bone_t) == 48, "a bone is 48 bytes");
_Static_assert(sizeof(psc_patch_skin_t) == 8, "a skin entry is 8 bytes");
_Static_assert(sizeof(psc_patch_action_t) == 40, "an action is 40 bytes");
_Static_assert(sizeof(psc_patch_channel_t) == 12, "a channel is 12 bytes");
_Static_assert(sizeof(psc_patch_key_t) == 20, "a key is 20 bytes");

/** A parsed pack: counts and pointers into the caller's buffer. */
typedef struct {
    uint32_t point_count, cp_count, spline_count, hook_count, edge_count, face_count, color_count;
    uint32_t bone_count, action_count, channel_count, key_count;
    const int32_t *rest_q16;             /* 3 per point */
    const psc_patch_cp_t *cps;
    const psc_patch_spline_t *splines;
    const psc_patch_hook_t *hooks;
    const psc_patch_edge_t *edges;
    const psc_patch_face_t *faces;
    const uint32_t *colors;
    const int32_t *handles_q16;          /* 6 per CP when any CP is FIXED, else NULL */
    const psc_patch_bone_t *bones;
    const psc_patch_skin_t *skin;
    const psc_patch_action_t *actions;
    const psc_patch_channel_t *channels;
    const psc_patch_key_t *keys;
    int32_t lo_q16[3], hi_q16[3];        /* the rest points' bounding box */
    uint32_t scale_q16;                  /* R in the source's units, and the rest box centre there (for reference) */
    int32_t center_q16[3];
    uint16_t version_minor;
} psc_patch_model_t;

/**
 * Validate and parse a patch pack held in buf[0..len) (aligned to 8): the
 * container, every count against its limit and its section's size, every
 * index (points, CPs, splines, segments, edges, colours, bones, channels,
 * keys) against what it indexes, edges and hooks on real segments with valid
 * quarters, patches closing (each edge starting where the previous one
 * ends), bones before their children, unit quaternions, increasing key
 * times, rest positions within PSC_PATCH_MAX_COORD_Q16. On failure returns
 * the status and fills *err (may be NULL); nothing is read outside buf; the
 * model points into buf.
 */
psc_status_t psc_patch_parse(const void *buf, size_t len, psc_patch_model_t *out, psc_container_error_t *err);

/** The point edge e starts (end 0) or ends (end 1) at: its CP's, or the hook's at that quarter (-1: no hook there;
 *  never for a parsed pack). */
int32_t psc_patch_edge_point(const psc_patch_model_t *m, const psc_patch_edge_t *e, unsigned end);

/** The CP index that starts segment seg of spline s, and the one that ends it (closed splines wrap). */
static inline uint32_t psc_patch_seg_cp(const psc_patch_model_t *m, uint32_t s, uint32_t seg, unsigned end)
{
    const psc_patch_spline_t *sp = &m->splines[s];
    uint32_t k = seg + end;
    return sp->first + (k >= sp->count ? k - sp->count : k);
}

/** Segments of spline s: count - 1, or count when it is closed. */
static inline uint32_t psc_patch_seg_count(const psc_patch_model_t *m, uint32_t s)
{
    const psc_patch_spline_t *sp = &m->splines[s];
    return (sp->flags & PSC_PATCH_SPLINE_CLOSED) ? sp->count : sp->count - 1u;
}

#endif
