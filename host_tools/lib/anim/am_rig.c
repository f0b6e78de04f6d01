/* SPDX-License-Identifier: MIT */
/* am_rig.c - an A:M rig played by an action, and the action baked into channels (am_rig.h). */
#include "anim/am_rig.h"
#include "util/hmath.h"
#include "util/note_text.h"
#include "anim/sample.h"
#include "psc_io_error.h"
#include "util/quat.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define RIG_SWEEPS 3
#define BAKE_FPS 30.0

/* ---- vectors ---------------------------------------------------------------------------------------------- */

static double norm3(double v[3])
{
    double n = sqrt(psc_hmath_dot3(v, v));
    if (n > 0.0)
        for (unsigned k = 0; k < 3; k++)
            v[k] /= n;
    return n;
}

/* ---- the rig ---------------------------------------------------------------------------------------------- */

typedef struct {
    psc_am_cons_kind_t kind;
    int bone, target;
} cons_t;

struct psc_am_rig {
    const psc_am_model_t *am;
    size_t n;
    double (*rel_rot)[4], (*rel_off)[3];
    const psc_am_curve_t *(*rot_curve)[4], *(*trans_curve)[3];
    double trans_scale;
    cons_t *cons;
    size_t cons_count;
    double (*loc_rot)[4], (*loc_trans)[3];
};

/* Is the switch named name on, with the action's override? (no name: always on) */
static bool switch_on(const psc_am_model_t *am, const psc_am_action_t *act, const char *name)
{
    if (name[0] == '\0')
        return true;
    if (act)
        for (size_t i = 0; i < act->switch_count; i++)
            if (strcasecmp(act->switches[i].name, name) == 0)
                return act->switches[i].value >= 0.5;
    for (size_t i = 0; i < am->switch_count; i++)
        if (strcasecmp(am->switches[i].name, name) == 0)
            return am->switches[i].value >= 0.5;
    return false;
}

psc_am_rig_t *psc_am_rig_new(const psc_am_model_t *am, const psc_am_action_t *act, char *note, size_t notelen)
{
    psc_am_rig_t *r = calloc(1, sizeof *r);
    size_t n = am->bone_count ? am->bone_count : 1;

    if (r == NULL)
        return NULL;
    r->am = am;
    r->n = am->bone_count;
    r->rel_rot = calloc(n, sizeof *r->rel_rot);
    r->rel_off = calloc(n, sizeof *r->rel_off);
    r->rot_curve = calloc(n, sizeof *r->rot_curve);
    r->trans_curve = calloc(n, sizeof *r->trans_curve);
    r->loc_rot = calloc(n, sizeof *r->loc_rot);
    r->loc_trans = calloc(n, sizeof *r->loc_trans);
    r->cons = calloc(am->constraint_count ? am->constraint_count : 1, sizeof *r->cons);
    if (!r->rel_rot || !r->rel_off || !r->rot_curve || !r->trans_curve || !r->loc_rot || !r->loc_trans || !r->cons) {
        psc_am_rig_free(r);
        return NULL;
    }
    for (size_t b = 0; b < r->n; b++) {
        const psc_am_bone_t *bone = &am->bones[b];
        double rot[4];
        memcpy(rot, bone->rot, sizeof rot);
        psc_quat_normalize(rot);
        if (bone->parent < 0) {
            memcpy(r->rel_rot[b], rot, sizeof rot);
            memcpy(r->rel_off[b], bone->start, sizeof r->rel_off[b]);
        } else {
            const psc_am_bone_t *p = &am->bones[bone->parent];
            double pc[4], pr[4], d[3];
            memcpy(pr, p->rot, sizeof pr);
            psc_quat_normalize(pr);
            psc_quat_conj(pr, pc);
            psc_quat_mul(pc, rot, r->rel_rot[b]);
            for (unsigned k = 0; k < 3; k++)
                d[k] = bone->start[k] - p->start[k];
            psc_quat_rotate(pc, d, r->rel_off[b]);
        }
    }
    r->trans_scale = 1.0;
    if (act != NULL) {
        int sb = act->scale_bone[0] ? psc_am_bone_find(am, act->scale_bone) : -1;
        if (sb >= 0 && act->scale_standard > 0.0 && am->bones[sb].length > 0.0)
            r->trans_scale = am->bones[sb].length / act->scale_standard;
        else if (act->scale_bone[0])
            psc_note_add(note, notelen, "the model has no bone '%s' to scale the action's moves by: unscaled",
                     act->scale_bone);
        size_t missing = 0;
        char first_missing[PSC_AM_NAME_MAX] = "";
        for (size_t c = 0; c < act->curve_count; c++) {
            const psc_am_curve_t *cv = &act->curves[c];
            int b = psc_am_bone_find(am, cv->bone);
            if (b < 0) {
                bool seen = false;
                for (size_t k = 0; k < c && !seen; k++)
                    seen = strcmp(act->curves[k].bone, cv->bone) == 0;
                if (!seen && missing++ == 0)
                    snprintf(first_missing, sizeof first_missing, "%s", cv->bone);
                continue;
            }
            if (cv->kind == PSC_AM_CURVE_ROTATE)
                r->rot_curve[b][cv->axis] = cv;
            else
                r->trans_curve[b][cv->axis] = cv;
        }
        if (missing)
            psc_note_add(note, notelen, "%zu bone%s the action keys the model lacks (e.g. '%s'): ignored", missing,
                     missing == 1 ? "" : "s", first_missing);
    }
    size_t skipped = 0;
    for (size_t c = 0; c < am->constraint_count; c++) {
        const psc_am_constraint_t *k = &am->constraints[c];
        int b = psc_am_bone_find(am, k->bone), t = psc_am_bone_find(am, k->target);
        if (b < 0 || t < 0 || !switch_on(am, act, k->owner_switch))
            continue;
        if (k->kind == PSC_AM_ROLL || k->kind == PSC_AM_TRANSLATE ||
            (k->kind == PSC_AM_KINEMATIC && am->bones[b].parent < 0)) {
            skipped++;
            continue;
        }
        r->cons[r->cons_count++] = (cons_t){k->kind, b, t};
    }
    if (skipped)
        psc_note_add(note, notelen, "%zu roll-like or translate-to constraints not played", skipped);
    return r;
}

void psc_am_rig_free(psc_am_rig_t *r)
{
    if (r == NULL)
        return;
    free(r->rel_rot);
    free(r->rel_off);
    free(r->rot_curve);
    free(r->trans_curve);
    free(r->loc_rot);
    free(r->loc_trans);
    free(r->cons);
    free(r);
}

/* Bone b from its parent and its local values (forward kinematics). */
static void forward(const psc_am_rig_t *r, size_t b, psc_am_pose_t *pose)
{
    int p = r->am->bones[b].parent;
    double q[4], off[3], moved[3];

    psc_quat_mul(r->rel_rot[b], r->loc_rot[b], q);
    psc_quat_rotate(r->rel_rot[b], r->loc_trans[b], moved);
    for (unsigned k = 0; k < 3; k++)
        off[k] = r->rel_off[b][k] + moved[k];
    if (p < 0) {
        memcpy(pose[b].rot, q, sizeof q);
        memcpy(pose[b].head, off, sizeof off);
        return;
    }
    psc_quat_mul(pose[p].rot, q, pose[b].rot);
    psc_quat_normalize(pose[b].rot);
    psc_quat_rotate(pose[p].rot, off, moved);
    for (unsigned k = 0; k < 3; k++)
        pose[b].head[k] = pose[p].head[k] + moved[k];
}

static void bone_tip(const psc_am_rig_t *r, size_t b, const psc_am_pose_t *pose, double tip[3])
{
    double z[3] = {0.0, 0.0, r->am->bones[b].length}, d[3];
    psc_quat_rotate(pose[b].rot, z, d);
    for (unsigned k = 0; k < 3; k++)
        tip[k] = pose[b].head[k] + d[k];
}

/* Rotate bone b's pose by q about its head. */
static void turn(psc_am_pose_t *pose, size_t b, const double q[4])
{
    psc_quat_mul(q, pose[b].rot, pose[b].rot);
    psc_quat_normalize(pose[b].rot);
}

/* Two-bone IK: parent p and bone b bend so b's tip reaches goal, in the plane they bend in now. */
static void reach(const psc_am_rig_t *r, size_t b, const double goal[3], psc_am_pose_t *pose)
{
    size_t p = (size_t)r->am->bones[b].parent;
    double hip[3], knee[3], tip[3], u[3], v[3], hk[3], q[4];

    memcpy(hip, pose[p].head, sizeof hip);
    memcpy(knee, pose[b].head, sizeof knee);
    bone_tip(r, b, pose, tip);
    for (unsigned k = 0; k < 3; k++) {
        hk[k] = knee[k] - hip[k];
        u[k] = goal[k] - hip[k];
    }
    double a = sqrt(psc_hmath_dot3(hk, hk)), c = r->am->bones[b].length, d = norm3(u);
    if (a <= 0.0 || c <= 0.0 || d <= 0.0)
        return;
    double lo = fabs(a - c) * 1.0001, hi = (a + c) * 0.9999;
    d = d < lo ? lo : d > hi ? hi : d;
    /* the bend side: the knee's offset from the hip-goal line (or the tip's, when straight) */
    double s = psc_hmath_dot3(hk, u);
    for (unsigned k = 0; k < 3; k++)
        v[k] = hk[k] - s * u[k];
    if (norm3(v) < 1e-9 * a) {
        double e[3];
        for (unsigned k = 0; k < 3; k++)
            e[k] = tip[k] - knee[k];
        s = psc_hmath_dot3(e, u);
        for (unsigned k = 0; k < 3; k++)
            v[k] = -(e[k] - s * u[k]);
        if (norm3(v) < 1e-12)
            return;
    }
    double ca = (a * a + d * d - c * c) / (2.0 * a * d);
    ca = ca > 1.0 ? 1.0 : ca < -1.0 ? -1.0 : ca;
    double sa = sqrt(1.0 - ca * ca), nk[3];
    for (unsigned k = 0; k < 3; k++)
        nk[k] = a * (ca * u[k] + sa * v[k]);
    psc_quat_swing(hk, nk, q);
    turn(pose, p, q);
    for (unsigned k = 0; k < 3; k++)
        pose[b].head[k] = hip[k] + nk[k];
    turn(pose, b, q);
    bone_tip(r, b, pose, tip);
    double from[3], to[3];
    for (unsigned k = 0; k < 3; k++) {
        from[k] = tip[k] - pose[b].head[k];
        to[k] = goal[k] - pose[b].head[k];
    }
    psc_quat_swing(from, to, q);
    turn(pose, b, q);
}

static void apply_constraint(const psc_am_rig_t *r, const cons_t *c, psc_am_pose_t *pose)
{
    const psc_am_bone_t *bb = &r->am->bones[c->bone], *tb = &r->am->bones[c->target];
    size_t b = (size_t)c->bone, t = (size_t)c->target;
    double q[4], a[3], d[3];

    switch (c->kind) {
    case PSC_AM_ORIENT: {   /* G_b = G_t * R_t_rest^-1 * R_b_rest */
        double tc[4], rb[4], rt[4];
        memcpy(rt, tb->rot, sizeof rt);
        memcpy(rb, bb->rot, sizeof rb);
        psc_quat_normalize(rt);
        psc_quat_normalize(rb);
        psc_quat_conj(rt, tc);
        psc_quat_mul(pose[t].rot, tc, q);
        psc_quat_mul(q, rb, pose[b].rot);
        psc_quat_normalize(pose[b].rot);
        break;
    }
    case PSC_AM_AIM: {
        double z[3] = {0.0, 0.0, 1.0};
        psc_quat_rotate(pose[b].rot, z, a);
        for (unsigned k = 0; k < 3; k++)
            d[k] = pose[t].head[k] - pose[b].head[k];
        psc_quat_swing(a, d, q);
        turn(pose, b, q);
        break;
    }
    case PSC_AM_KINEMATIC:
        reach(r, b, pose[t].head, pose);
        break;
    default:
        break;
    }
}

void psc_am_rig_eval(psc_am_rig_t *r, double t, psc_am_pose_t *pose)
{
    for (size_t b = 0; b < r->n; b++) {
        double q[4] = {0.0, 0.0, 0.0, 1.0};
        if (r->rot_curve[b][0] || r->rot_curve[b][1] || r->rot_curve[b][2] || r->rot_curve[b][3]) {
            for (unsigned k = 0; k < 4; k++)   /* an unkeyed component keeps the identity's value (x100) */
                q[k] = r->rot_curve[b][k] ? psc_am_curve_eval(r->rot_curve[b][k], t) : (k == 3 ? 100.0 : 0.0);
            psc_quat_normalize(q);
        }
        memcpy(r->loc_rot[b], q, sizeof q);
        for (unsigned k = 0; k < 3; k++)
            r->loc_trans[b][k] = r->trans_curve[b][k] ? psc_am_curve_eval(r->trans_curve[b][k], t) * r->trans_scale
                                                      : 0.0;
    }
    for (size_t b = 0; b < r->n; b++)
        forward(r, b, pose);
    for (unsigned sweep = 0; sweep < RIG_SWEEPS; sweep++)
        for (size_t b = 0; b < r->n; b++) {
            forward(r, b, pose);
            for (size_t c = 0; c < r->cons_count; c++)
                if ((size_t)r->cons[c].bone == b)
                    apply_constraint(r, &r->cons[c], pose);
        }
}

/* ---- baking ----------------------------------------------------------------------------------------------- */

int psc_anim_sample_am_action(const psc_am_action_t *act, const psc_am_model_t *am, psc_patch_src_t *s, char *note,
                       size_t notelen, char *err, size_t errlen)
{
    size_t frames = (size_t)lround(act->duration * BAKE_FPS) + 1u, nb = am->bone_count;

    if (nb == 0 || s->bone_count != nb)
        return psc_io_errorf(err, errlen, act->name, "the model has no bones for the action to move");
    if (frames < 2)
        frames = 2;
    psc_am_rig_t *rig = psc_am_rig_new(am, act, note, notelen);
    psc_bone_pose_t *pose = malloc(nb * frames * sizeof *pose);
    int rc = -1;
    if (!rig || !pose) {
        psc_io_errorf(err, errlen, act->name, "out of memory");
    } else {
        for (size_t f = 0; f < frames; f++)
            psc_am_rig_eval(rig, act->duration * (double)f / (double)(frames - 1u), pose + f * nb);
        rc = psc_anim_sample(s, act->name, act->duration, frames, pose, note, notelen, err, errlen);
    }
    psc_am_rig_free(rig);
    free(pose);
    return rc;
}
