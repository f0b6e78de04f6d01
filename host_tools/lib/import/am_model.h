/* SPDX-License-Identifier: MIT */
/*
 * am_model.h - read an Animation:Master model (.mdl): the spline mesh the
 * Hash patches are made of, the patches, their colours, the bones with their
 * control-point assignments, and the rig's constraints. Only what the patch
 * renderer and the rig need is kept; everything else in the file (images,
 * decals, groups, poses' channel data, previews) is read past.
 *
 * Read from the files (they are text):
 *  - <MESH><SPLINE>: one control point (CP) a row,
 *      FLAGS 0 ID x y z [BIAS]        a CP with its own position
 *      FLAGS 1 ID REF [BIAS]          a CP stacked on CP REF (same position)
 *      FLAGS 1 ID FRAC BASE [BIAS]    a hook (FLAGS & 16): the point FRAC along
 *                                     the spline segment that starts at CP BASE
 *    BIAS is ". ." (none) or "outAlpha outGamma outMagnitude inAlpha inGamma
 *    inMagnitude" (degrees, degrees, 1 = default). FLAGS & 4 on a spline's
 *    last CP closes the spline.
 *  - <PATCHES>: "FLAGS c1 c2 c3 c4 [c5] n1..n4 [n5] ATTR": the corner CPs
 *    (five when FLAGS & 1; a three-point patch repeats a corner), A:M's
 *    normal indices into <NORMALS> (which side is out), the colour ATTR.
 *  - <ATTRS><ATTRIBUTE> DiffuseColor=R G B: the patch colours.
 *  - <BONES>: nested <SEGMENT> (bone) and <NULLOBJECT> (null) blocks with
 *    Name, Start, End, Rotate (quaternion x y z w), Length, and the CPs a bone
 *    owns: <NONSKINNEDCPS> ids, <WEIGHTEDCPS> "id weight%".
 *  - <USERPROPERTY> <BOOL>/<PERCENT> switches with Value= (else DefaultValue=),
 *    and <RELATIONCONTAINER>: under each switch's relation, the constraints
 *    it turns on (KINEMATIC, AIMAT, ORIENTLIKE, ROLLLIKE, TRANSLATETO) of a
 *    bone (OBJECTSHORTCUT MatchName) towards BoneTarget=..|Name.
 * Errors name the file and line.
 */
#ifndef PSC_IMPORT_AM_MODEL_H
#define PSC_IMPORT_AM_MODEL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define PSC_AM_NAME_MAX 64u
#define PSC_AM_SWITCH_MAX 32u

#define PSC_AM_CP_CLOSED 4u      /* on a spline's last CP: the spline is a loop */
#define PSC_AM_CP_HOOK 16u       /* the CP is a hook */

typedef struct {
    int32_t id;
    uint32_t flags;
    bool stacked;                /* follows CP ref */
    bool hook;                   /* lies hook_frac along the segment starting at CP ref */
    int32_t ref;
    double hook_frac;
    double pos[3];               /* own position (neither stacked nor hook) */
    double bias_in[3], bias_out[3];   /* alpha (deg), gamma (deg), magnitude (1 = default) */
    unsigned line;
} psc_am_cp_t;

typedef struct {
    size_t first, count;         /* cps[first .. first + count) in spline order */
    bool closed;
    unsigned line;
} psc_am_spline_t;

typedef struct {
    uint32_t flags;
    unsigned corners;            /* 3, 4 or 5 (a repeated corner counted once) */
    int32_t corner[5];           /* CP ids, in order around the patch */
    int32_t normal[5];           /* A:M's normal at each corner: an index into the model's normals */
    unsigned attr;               /* colour index */
    unsigned line;
} psc_am_patch_t;

typedef enum {
    PSC_AM_KINEMATIC = 0,        /* reach the target with the bone's tip (IK) */
    PSC_AM_AIM,                  /* point the bone at the target */
    PSC_AM_ORIENT,               /* take the target's orientation */
    PSC_AM_ROLL,                 /* take the target's roll */
    PSC_AM_TRANSLATE,            /* move to the target */
} psc_am_cons_kind_t;

typedef struct {
    psc_am_cons_kind_t kind;
    char bone[PSC_AM_NAME_MAX];      /* the constrained bone */
    char target[PSC_AM_NAME_MAX];    /* the bone it follows */
    char owner_switch[PSC_AM_NAME_MAX];   /* the switch whose relation holds it ("" = always on) */
    unsigned line;
} psc_am_constraint_t;

typedef struct {
    char name[PSC_AM_NAME_MAX];
    int parent;                  /* index, -1 for a top bone */
    bool null_object;
    double start[3], end[3], rot[4];  /* rest pose, model space; rot = x y z w */
    double length;
    int32_t *cps;                /* NONSKINNEDCPS: fully owned */
    size_t cp_count;
    int32_t *wcps;               /* WEIGHTEDCPS: shared with the parent bone */
    double *weights;             /* 0..1 */
    size_t wcp_count;
    unsigned line;
} psc_am_bone_t;

typedef struct {
    char name[PSC_AM_NAME_MAX];
    double value;                /* BOOL: 0 or 1; PERCENT: 0..1 */
} psc_am_switch_t;

typedef struct {
    psc_am_cp_t *cps;
    size_t cp_count;
    psc_am_spline_t *splines;
    size_t spline_count;
    psc_am_patch_t *patches;
    size_t patch_count;
    double (*normals)[3];        /* <NORMALS>: A:M's patch corner normals (they tell which side is out) */
    size_t normal_count;
    uint32_t *colors;            /* 0xRRGGBB per ATTRIBUTE */
    size_t color_count;
    psc_am_bone_t *bones;
    size_t bone_count;
    psc_am_constraint_t *constraints;
    size_t constraint_count;
    psc_am_switch_t switches[PSC_AM_SWITCH_MAX];
    size_t switch_count;
} psc_am_model_t;

/** Parse .mdl text[0..len) named name. 0, or -1 with err "name:line: problem" (m is then empty). */
int psc_am_model_parse(const char *name, const char *text, size_t len, psc_am_model_t *m, char *err, size_t errlen);

/** Read and parse a .mdl file. */
int psc_am_model_load(const char *path, psc_am_model_t *m, char *err, size_t errlen);

void psc_am_model_free(psc_am_model_t *m);

/** The bone named name, or -1. */
int psc_am_bone_find(const psc_am_model_t *m, const char *name);

/** The switch named name (case-insensitive, as A:M matches them), or NULL. */
psc_am_switch_t *psc_am_switch_find(psc_am_model_t *m, const char *name);

#endif
