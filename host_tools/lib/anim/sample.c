/* SPDX-License-Identifier: MIT */
/* sample.c - sampled bone poses baked into a character's channels (sample.h). */
#include "anim/sample.h"
#include "util/note_text.h"
#include "psc_io_error.h"
#include "util/quat.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void psc_anim_rest_relative(const psc_patch_src_t *s, size_t b, double rel[4], double off[3])
{
    const psc_patch_bone_src_t *bone = &s->bone[b];
    double rb[4];
    memcpy(rb, bone->rot, sizeof rb);
    psc_quat_normalize(rb);
    if (bone->parent < 0) {
        memcpy(rel, rb, sizeof rb);
        memcpy(off, bone->head, 3 * sizeof *off);
        return;
    }
    const psc_patch_bone_src_t *p = &s->bone[bone->parent];
    double rp[4], pc[4], d[3];
    memcpy(rp, p->rot, sizeof rp);
    psc_quat_normalize(rp);
    psc_quat_conj(rp, pc);
    psc_quat_mul(pc, rb, rel);
    for (unsigned k = 0; k < 3; k++)
        d[k] = bone->head[k] - p->head[k];
    psc_quat_rotate(pc, d, off);
}

/* The local (q, t) of bone b in a posed skeleton g: G_b = G_p rel q, H_b = H_p + G_p (off + rel t). */
static void local_values(const psc_patch_src_t *s, size_t b, const psc_bone_pose_t *g, double q[4], double t[3])
{
    int p = s->bone[b].parent;
    double pr[4] = {0, 0, 0, 1}, ph[3] = {0, 0, 0}, rel[4], off[3], relc[4], pc[4], x[4], d[3];

    psc_anim_rest_relative(s, b, rel, off);
    if (p >= 0) {
        memcpy(pr, g[p].rot, sizeof pr);
        memcpy(ph, g[p].head, sizeof ph);
    }
    psc_quat_conj(rel, relc);
    psc_quat_conj(pr, pc);
    psc_quat_mul(relc, pc, x);
    psc_quat_mul(x, g[b].rot, q);
    psc_quat_normalize(q);
    for (unsigned k = 0; k < 3; k++)
        d[k] = g[b].head[k] - ph[k];
    psc_quat_rotate(pc, d, d);
    for (unsigned k = 0; k < 3; k++)
        d[k] -= off[k];
    psc_quat_rotate(relc, d, t);
}

int psc_anim_sample(psc_patch_src_t *s, const char *name, double duration, size_t frames, const psc_bone_pose_t *pose,
                   char *note, size_t notelen, char *err, size_t errlen)
{
    size_t nb = s->bone_count, moving = 0;
    int rc = -1;

    if (nb == 0)
        return psc_io_errorf(err, errlen, name, "the model has no bones for the motion to move");
    if (frames < 2 || !(duration > 0.0))
        return psc_io_errorf(err, errlen, name, "no motion to bake (%zu samples over %g s)", frames, duration);
    if (s->action_count >= PSC_PATCH_MAX_ACTIONS)
        return psc_io_errorf(err, errlen, name, "more than %u actions", PSC_PATCH_MAX_ACTIONS);
    double (*lq)[4] = malloc(nb * frames * sizeof *lq), (*lt)[3] = malloc(nb * frames * sizeof *lt);
    bool *rot_moves = calloc(nb, sizeof *rot_moves), *trans_moves = calloc(nb, sizeof *trans_moves);
    void *grown = realloc(s->action, (s->action_count + 1) * sizeof *s->action);
    if (grown)
        s->action = grown;
    if (!lq || !lt || !rot_moves || !trans_moves || !grown) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    for (size_t f = 0; f < frames; f++)
        for (size_t b = 0; b < nb; b++) {
            double *q = lq[f * nb + b], *t = lt[f * nb + b];
            local_values(s, b, pose + f * nb, q, t);
            if (fabs(q[3]) < 1.0 - 1e-9)
                rot_moves[b] = true;
            double scale = s->bone[b].length > 0 ? s->bone[b].length : 1.0;
            if (sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]) > 1e-6 * scale)
                trans_moves[b] = true;
        }
    psc_patch_action_src_t *a = &s->action[s->action_count];
    memset(a, 0, sizeof *a);
    snprintf(a->name, sizeof a->name, "%.27s", name);
    a->duration = duration;
    for (size_t b = 0; b < nb; b++)
        a->chan_count += (size_t)rot_moves[b] + (size_t)trans_moves[b];
    a->chan = calloc(a->chan_count ? a->chan_count : 1, sizeof *a->chan);
    if (a->chan == NULL) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    s->action_count++;   /* from here psc_patch_src_free owns it */
    size_t ci = 0;
    for (size_t b = 0; b < nb; b++)
        for (unsigned kind = 0; kind < 2; kind++) {
            if (!(kind == 0 ? rot_moves[b] : trans_moves[b]))
                continue;
            psc_patch_chan_src_t *c = &a->chan[ci++];
            c->target = (uint16_t)b;
            c->kind = kind == 0 ? PSC_PATCH_CHAN_ROTATE : PSC_PATCH_CHAN_TRANSLATE;
            c->time = malloc(frames * sizeof *c->time);
            c->value = calloc(frames, sizeof *c->value);
            if (!c->time || !c->value) {
                psc_io_errorf(err, errlen, name, "out of memory");
                goto done;
            }
            c->count = frames;
            for (size_t f = 0; f < frames; f++) {
                c->time[f] = duration * (double)f / (double)(frames - 1u);
                memcpy(c->value[f], kind == 0 ? lq[f * nb + b] : lt[f * nb + b], (kind == 0 ? 4 : 3) * sizeof(double));
            }
            moving++;
        }
    psc_note_add(note, notelen, "baked %zu samples of %zu channels", frames, moving);
    rc = 0;
done:
    free(lq);
    free(lt);
    free(rot_moves);
    free(trans_moves);
    return rc;
}
