/* SPDX-License-Identifier: MIT */
/*
 * patch_source.h - a Hash patch character on the host (floating point, the
 * source's units), made from an Animation:Master model or a Newell Bezier
 * patch file, and the patch pack (core/patch/psc_patch.h) written from it.
 * The device's own structs are used for the topology, so there is one
 * definition of the format.
 *
 * From an A:M model (psc_patch_from_am):
 *  - points: a CP with its own position is a point; a stacked CP is its
 *    stack's point; a hook is a point of its own (placed every frame);
 *  - splines and CPs in file order, bias converted (degrees -> 65536 per
 *    turn, magnitude -> Q4.12);
 *  - each patch's sides: the spline segment (or, where a hook splits one,
 *    the half) that joins two consecutive corners; shared sides become one
 *    edge; a patch whose corners run against A:M's normals is turned round;
 *  - bones with their rest pose; each point's bone from <NONSKINNEDCPS> /
 *    <WEIGHTEDCPS>, or - for a model that assigns none - the nearest bone
 *    (segment distance) among the deforming ones (PSC_PATCH_BUILD_DEFORM
 *    names them, or every bone that is not a null, a constraint's target or
 *    an aiming helper), or a donor model's assignment by nearest CP.
 */
#ifndef PSC_IMPORT_PATCH_SOURCE_H
#define PSC_IMPORT_PATCH_SOURCE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "import/am_model.h"
#include "patch/psc_patch.h"

typedef struct {
    char name[PSC_AM_NAME_MAX];
    int parent;
    double head[3];              /* rest, model space, source units */
    double rot[4];               /* rest rotation, model space, x y z w */
    double length;
} psc_patch_bone_src_t;

/** A channel on the host: keys at times (seconds) with up to 4 values (source units). */
typedef struct {
    uint16_t target;
    uint8_t kind;                /* psc_patch_chan_kind_t */
    double *time;
    double (*value)[4];
    size_t count;
} psc_patch_chan_src_t;

typedef struct {
    char name[28];
    double duration;             /* seconds */
    psc_patch_chan_src_t *chan;
    size_t chan_count;
} psc_patch_action_src_t;

typedef struct {
    double (*point)[3];          /* rest positions */
    size_t point_count;
    psc_patch_cp_t *cp;
    double (*handle)[2][3];      /* in, out handles of FIXED CPs (NULL when none) */
    size_t cp_count;
    psc_patch_spline_t *spline;
    size_t spline_count;
    psc_patch_hook_t *hook;
    size_t hook_count;
    psc_patch_edge_t *edge;
    size_t edge_count;
    psc_patch_face_t *face;
    size_t face_count;
    uint32_t *color;
    size_t color_count;
    psc_patch_bone_src_t *bone;
    size_t bone_count;
    psc_patch_skin_t *skin;      /* per point, when bones */
    psc_patch_action_src_t *action;
    size_t action_count;
    double lo[3], hi[3];         /* rest box of the points */
} psc_patch_src_t;

/** How a model without CP assignments is skinned. */
typedef struct {
    const char *deform;          /* comma-separated bone names to assign to (NULL: every deforming-looking bone) */
    const psc_am_model_t *donor; /* take assignments from this model of the same character, by nearest CP */
} psc_patch_skin_opts_t;

/**
 * Build the patch character of an A:M model. name names the model in
 * messages; note (may be NULL) receives remarks (e.g. how points were
 * skinned). 0, or -1 with err "name: problem".
 */
int psc_patch_from_am(const psc_am_model_t *am, const psc_patch_skin_opts_t *skin, const char *name,
                      psc_patch_src_t *out, char *note, size_t notelen, char *err, size_t errlen);

void psc_patch_src_free(psc_patch_src_t *s);

/**
 * Write the pack: positions normalised to R = half the rest box diagonal,
 * centred on the box; bones, channels likewise. The result is checked with
 * core's psc_patch_parse. *out (free()) of *out_len bytes; 0, or -1 with err.
 */
int psc_bake_patch_pack(const psc_patch_src_t *s, const char *name, uint8_t **out, size_t *out_len, char *err,
                         size_t errlen);

/** Set s->lo and s->hi: the box of the rest positions. */
void psc_patch_src_bounds(psc_patch_src_t *s);

/** The bone of model am named name, with its index, or -1. */
int psc_patch_src_bone(const psc_patch_src_t *s, const char *name);

#endif
