/* SPDX-License-Identifier: MIT */
/*
 * am_action.h - read an Animation:Master action (.act): the channels it keys,
 * by bone name, so it plays on any model with bones of those names.
 *
 * Read from the files (they are text):
 *  - <ACTION>: Frames=S:F (the length), ScaleStandard= and <ScaleMethod>
 *    ScaleBoneName=..|Bone (translations were made for a model whose bone of
 *    that name is ScaleStandard long: they scale by the model's length over it);
 *  - <OBJECTSHORTCUT> MatchName=BONE (nested under MatchName=Bones), holding
 *    <QUATERNIONROTATEDRIVER> (a rotation: channels X Y Z W, the quaternion
 *    times 100) and <TRANSLATECHANNELDRIVER>s X Y Z (a translation in the
 *    bone's own rest frame);
 *  - <SPLINE> rows "FLAGS TIME VALUE [inAngle inMag outAngle outMag]", TIME
 *    as A:M writes it ("F", "S:F") at 30 frames per second;
 *  - <CONSTDRIVER> <BOOL> NAME Value=TRUE|FALSE: the model's switches the
 *    action turns on or off (e.g. "Ik Arms Setup").
 * Other drivers (constraints on bones the action adds, Euler limits) are read
 * past. Errors name the file and line.
 */
#ifndef PSC_IMPORT_AM_ACTION_H
#define PSC_IMPORT_AM_ACTION_H

#include <stdbool.h>
#include <stddef.h>

#include "import/am_model.h"

#define PSC_AM_FPS 30.0

typedef enum {
    PSC_AM_CURVE_ROTATE = 0,     /* axis 0..3 = x y z w, values x100 */
    PSC_AM_CURVE_TRANSLATE = 1,  /* axis 0..2 */
} psc_am_curve_kind_t;

typedef struct {
    double time;                 /* seconds */
    double value;
} psc_am_key_t;

typedef struct {
    char bone[PSC_AM_NAME_MAX];
    psc_am_curve_kind_t kind;
    unsigned axis;
    psc_am_key_t *keys;          /* times increasing */
    size_t count;
    unsigned line;
} psc_am_curve_t;

typedef struct {
    char name[PSC_AM_NAME_MAX];  /* the file's base name without .act */
    double duration;             /* seconds */
    double scale_standard;       /* 0 when the action gives none */
    char scale_bone[PSC_AM_NAME_MAX];
    psc_am_curve_t *curves;
    size_t curve_count;
    psc_am_switch_t switches[PSC_AM_SWITCH_MAX];
    size_t switch_count;
} psc_am_action_t;

/** Parse .act text[0..len) named name. 0, or -1 with err "name:line: problem". */
int psc_am_action_parse(const char *name, const char *text, size_t len, psc_am_action_t *a, char *err,
                        size_t errlen);

/** Read and parse a .act file. */
int psc_am_action_load(const char *path, psc_am_action_t *a, char *err, size_t errlen);

void psc_am_action_free(psc_am_action_t *a);

/** The value of curve c at time t (seconds): Catmull-Rom through its keys, held past the ends. */
double psc_am_curve_eval(const psc_am_curve_t *c, double t);

#endif
