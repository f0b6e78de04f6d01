/* SPDX-License-Identifier: MIT */
/*
 * psc_shadow.h - self-shadowing of animated characters from precomputed
 * sphere-occluder tables (the seed: a device and method that precompute and
 * store what the self-occlusion shadows of animated 3D objects need), and
 * the shadow pack (.pao) that holds them, read in place.
 *
 * Stage one (host, periscope-shadow build; the seed's pre-processing module
 * 71) writes:
 *  - the sphere tree (球擬體階層, the sphere generator 701): levels of
 *    spheres, coarse to fine, each with its children on the next level;
 *  - each sphere centre's skin (the first computation module 705): two
 *    bones and a weight, the average of the points it encloses;
 *  - the accessibility map (存取值貼圖, modules 707-713): for a sphere seen
 *    from a vertex at angle omega from the normal (0..pi, rows) covering a
 *    solid angle theta of the directions (0..2 pi, columns: theta / 2 pi =
 *    1 - cos of the sphere's angular radius), the occluded area (the
 *    cosine-weighted fraction of the hemisphere it blocks, Q0.16) and the
 *    occlusion angle (between the mean blocked direction and the normal, as
 *    a fraction of pi, Q0.16);
 *  - the composite arc map (合成弧度貼圖, modules 715-719): for two spheres of
 *    solid angles theta1, theta2 whose centres are delta apart (0..pi) as
 *    seen from the vertex, the solid angle theta3 of the one sphere that
 *    stands for both (their union) and the angle Phi from the first sphere's
 *    direction to its centre, as cos and sin (Q1.14);
 *  - the arc-cosine table the run time indexes omega and delta with;
 *  - (an extension of the seed, version 1.1, optional) the rest correction:
 *    for each of the character's points (a patch character) or the mesh's
 *    vertices (a glTF or OBJ model), the ray-traced occlusion at rest less
 *    what the spheres give there, added to the spheres' every frame. The
 *    spheres stand for a body's surfaces, not for thin parts (legs, rims) nor
 *    for a part's inside (where another part runs into it, the reference's
 *    occlusion is 1): the correction carries what the rest pose knows, the
 *    spheres how the pose changes it;
 *  - (version 1.2, optional, with the rest correction) the correction
 *    through each action: for every action of the character, at phases
 *    k / samples of its length, each point's reference less the gain times
 *    the spheres in that pose (a point buried in it, where another part runs
 *    through, made dark). A frame posed by an action takes it, interpolated
 *    between the phases round its time, in place of the rest correction: the
 *    average over poses cannot know that an arm passes through the shirt at
 *    one moment of a wave and not at another;
 *  - (version 1.3, optional) the patch grid correction, for a character
 *    whose patches are large (composed at every vertex, not at their
 *    corners: the teapot): for every quad of every patch (one for a
 *    four-sided patch, n for an n-sided one, psc_patch_frame.h's
 *    PSC_PATCH_UV), a grid of side x side corrections over its (u, v), the
 *    reference less the spheres at those points of the surface at rest; a
 *    vertex takes its quad's grid interpolated at its (u, v). A point's
 *    correction would not hold across a patch a third of R wide, where a
 *    spout runs into a body half-way along it.
 * Stage two (core, every frame, psc_shadow_run.c; the real-time module 73):
 * update (721) moves the spheres with the skeleton; composition (725) finds
 * the nearest spheres per level for a point, looks the tables up, merges
 * overlapping spheres through the composite map and sums the rest; image
 * generation (727) darkens the vertex colours by the occlusion and bends
 * their normals (psc_shadow_frame.h).
 *
 * Units: positions and radii Q16.16 in units of the character's R (as its
 * patch pack). Pack: the container of base/psc_container.h, magic
 * "PSCSHAO\x1a"; sections "SINF" (psc_shadow_info_raw_t), "SSPH" (spheres),
 * "SACC" (omega x theta x 2 uint16), "SCMP" (theta1 x theta2 x delta x
 * {uint16 theta3, int16 cos, int16 sin, uint16 reserved}), "SACO" (acos
 * table: PSC_SHADOW_ACOS_SIZE uint16, omega / pi at cos = -1 .. 1), and the
 * optional "SREF" (psc_shadow_rest_raw_t, then count int16, Q1.15) and
 * "SRPH" (psc_shadow_phase_raw_t, then actions x samples x count int16,
 * Q1.15: action a's phase k at [(a x samples + k) x count]) and "SGRD"
 * (psc_shadow_grid_raw_t, then quads x side x side int16, Q1.15: quad q's
 * node (i, j) at [(q x side + j) x side + i], i along u).
 */
#ifndef PSC_SHADOW_H
#define PSC_SHADOW_H

#include "base/psc_container.h"
#include "base/psc_types.h"

#define PSC_SHADOW_MAGIC "PSCSHAO\x1a"
#define PSC_SHADOW_VERSION_MAJOR 1u
#define PSC_SHADOW_VERSION_MINOR 3u   /* 1: the rest correction, SREF; 2: through each action, SRPH; 3: SGRD */
#define PSC_SHADOW_MAX_SECTIONS 12u
#define PSC_SHADOW_MAX_LEVELS 4u
#define PSC_SHADOW_MAX_SPHERES 4096u
#define PSC_SHADOW_MAX_TABLE 128u
#define PSC_SHADOW_NEAREST 4u          /* spheres of the finest level for a point (the seed's four) */
#define PSC_SHADOW_NEAREST_COARSE 6u   /* of each level above: a sphere that stands for its children covers more */
#define PSC_SHADOW_ACOS_SIZE 1025u
#define PSC_SHADOW_MAX_REST (1u << 20)   /* points or vertices a rest correction covers */
#define PSC_SHADOW_MAX_PHASE_ACTIONS 64u    /* actions SRPH covers */
#define PSC_SHADOW_MAX_PHASES 64u           /* phases an action's correction is sampled at */
#define PSC_SHADOW_MAX_GRID_SIDE 33u      /* nodes a side of a quad's grid correction */
#define PSC_SHADOW_MAX_GRID_QUADS 65536u  /* quads SGRD covers */
#define PSC_SHADOW_REST_GAIN_MIN_Q16 (65536u / 4u)
#define PSC_SHADOW_REST_GAIN_MAX_Q16 (65536u * 4u)

extern const psc_container_format_t psc_shadow_format;

#define PSC_SECTION_SHADOW_INFO PSC_FOURCC('S', 'I', 'N', 'F')
#define PSC_SECTION_SHADOW_SPHERES PSC_FOURCC('S', 'S', 'P', 'H')
#define PSC_SECTION_SHADOW_ACCESS PSC_FOURCC('S', 'A', 'C', 'C')
#define PSC_SECTION_SHADOW_COMPOSITE PSC_FOURCC('S', 'C', 'M', 'P')
#define PSC_SECTION_SHADOW_ACOS PSC_FOURCC('S', 'A', 'C', 'O')
#define PSC_SECTION_SHADOW_REST PSC_FOURCC('S', 'R', 'E', 'F')
#define PSC_SECTION_SHADOW_PHASE PSC_FOURCC('S', 'R', 'P', 'H')
#define PSC_SECTION_SHADOW_GRID PSC_FOURCC('S', 'G', 'R', 'D')

/** "SINF", 32 bytes. */
typedef struct {
    uint32_t sphere_count;
    uint8_t level_count;
    uint8_t reserved0[3];
    uint16_t access_omega, access_theta;            /* accessibility map size */
    uint16_t comp_theta, comp_delta;                /* composite map: comp_theta^2 x comp_delta */
    uint16_t level_first[PSC_SHADOW_MAX_LEVELS];    /* first sphere of each level; levels are consecutive */
    uint32_t bone_count;                            /* of the character the spheres were made for */
    uint32_t reserved1;
} psc_shadow_info_raw_t;

#define PSC_SHADOW_NO_CHILD 0xFFFFu
#define PSC_SHADOW_NO_BONE 0xFFFFu

/** A sphere ("SSPH"), 28 bytes. */
typedef struct {
    int32_t center_q16[3];        /* at rest */
    int32_t radius_q16;
    uint16_t first_child;         /* on the next level, or PSC_SHADOW_NO_CHILD */
    uint8_t child_count;
    uint8_t level;
    uint16_t bone0, bone1;        /* the centre follows bone0 with weight 1 - w1 and bone1 with w1 */
    uint16_t w1_q15;              /* 0..32768; bone1 PSC_SHADOW_NO_BONE: bone0 alone */
    uint16_t reserved;
} psc_shadow_sphere_t;

/** A composite-map entry ("SCMP"), 8 bytes. */
typedef struct {
    uint16_t theta3;              /* the union's theta / 2 pi, Q0.16 */
    int16_t cos_q14, sin_q14;     /* Phi, from the first sphere's direction towards the second's */
    uint16_t reserved;
} psc_shadow_comp_t;

/** "SREF"'s head, 8 bytes, then count int16 (Q1.15, -1..1): the rest correction. */
typedef struct {
    uint32_t count;               /* the character's points, or the mesh's vertices */
    uint32_t gain_q16;            /* the spheres' occlusion times this, then the correction added; 1/4..4 */
} psc_shadow_rest_raw_t;

/** "SRPH"'s head, 8 bytes, then actions x samples x count int16 (Q1.15, -1..1; count: SREF's). */
typedef struct {
    uint16_t actions;             /* the character's actions, in its order (1..PSC_SHADOW_MAX_PHASE_ACTIONS) */
    uint16_t samples;             /* phases per action, k / samples of its length (1..PSC_SHADOW_MAX_PHASES) */
    uint32_t count;               /* SREF's count */
} psc_shadow_phase_raw_t;

/** "SGRD"'s head, 8 bytes, then quads x side x side int16 (Q1.15, -1..1). */
typedef struct {
    uint32_t quads;               /* the character's patches' quads, in face order (2..PSC_SHADOW_MAX_GRID_QUADS) */
    uint16_t side;                /* nodes a side (2..PSC_SHADOW_MAX_GRID_SIDE), at (i, j) / (side - 1) of (u, v) */
    uint16_t reserved;
} psc_shadow_grid_raw_t;

_Static_assert(sizeof(psc_shadow_info_raw_t) == 32, "SINF is 32 bytes");
_Static_assert(sizeof(psc_shadow_grid_raw_t) == 8, "SGRD's head is 8 bytes");
_Static_assert(sizeof(psc_shadow_phase_raw_t) == 8, "SRPH's head is 8 bytes");
_Static_assert(sizeof(psc_shadow_rest_raw_t) == 8, "SREF's head is 8 bytes");
_Static_assert(sizeof(psc_shadow_sphere_t) == 28, "a sphere is 28 bytes");
_Static_assert(sizeof(psc_shadow_comp_t) == 8, "a composite entry is 8 bytes");

/** A parsed shadow pack (points into the caller's buffer). */
typedef struct {
    uint32_t sphere_count, level_count, bone_count;
    uint32_t level_first[PSC_SHADOW_MAX_LEVELS + 1];   /* level_first[level_count] = sphere_count */
    const psc_shadow_sphere_t *spheres;
    uint32_t access_omega, access_theta, comp_theta, comp_delta;
    const uint16_t *access;          /* [omega][theta][2]: occluded area, occlusion angle */
    const psc_shadow_comp_t *comp;   /* [theta1][theta2][delta] */
    const uint16_t *acos_table;      /* PSC_SHADOW_ACOS_SIZE entries */
    uint32_t rest_count;             /* the rest correction's entries, 0: none */
    uint32_t rest_gain_q16;          /* its gain on the spheres' occlusion (Q16.16) */
    const int16_t *rest_q15;         /* rest_count, Q1.15 */
    uint32_t phase_actions, phase_samples;   /* the correction through each action (1.2), 0: none */
    const int16_t *phase_q15;        /* phase_actions x phase_samples x rest_count, Q1.15 */
    uint32_t grid_quads, grid_side;  /* the patch grid correction (1.3), 0: none */
    const int16_t *grid_q15;         /* grid_quads x grid_side x grid_side, Q1.15 */
} psc_shadow_model_t;

/**
 * Validate and parse a shadow pack in buf[0..len) (aligned to 8): the
 * container, the counts against their limits and the sections' sizes,
 * levels in order with their children on the next level, bones below
 * bone_count, positive radii. On failure fills *err (may be NULL).
 */
psc_status_t psc_shadow_parse(const void *buf, size_t len, psc_shadow_model_t *out, psc_container_error_t *err);

#endif
