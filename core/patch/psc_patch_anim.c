/* SPDX-License-Identifier: MIT */
/*
 * psc_patch_anim.c - channels, the skeleton and the points it moves
 * (psc_patch_pose, psc_patch_channel_eval; psc_patch_frame.h).
 *
 * A bone's transform in model space is its parent's times its local one,
 * local = translate(offset) * rotate(rest) * translate(t) * rotate(q), with
 * (q, t) its channels' rotation and translation at the time (identity and
 * zero when the action has none: the bone keeps its rest pose). A point
 * follows skin = posed * rest^-1 of its bone, or the weighted sum of two.
 * Formats: quaternions Q2.30 (x y z w), matrices and positions Q16.16.
 */
#include "patch/psc_patch_frame.h"
#include "base/psc_fixed.h"

/* ---- channels --------------------------------------------------------------------------------------------- */

/* Catmull-Rom through v1..v2 at s (Q16.16 in [0, 1)), v0 and v3 the neighbours. */
static int32_t catmull_rom(int32_t v0, int32_t v1, int32_t v2, int32_t v3, int32_t s_q16)
{
    int64_t c0 = 2 * (int64_t)v1, c1 = (int64_t)v2 - v0, c2 = 2 * (int64_t)v0 - 5 * (int64_t)v1 + 4 * (int64_t)v2 - v3;
    int64_t c3 = -(int64_t)v0 + 3 * (int64_t)v1 - 3 * (int64_t)v2 + v3;
    int64_t r = psc_shr_round64(c3 * s_q16, 16) + c2;
    r = psc_shr_round64(r * s_q16, 16) + c1;
    r = psc_shr_round64(r * s_q16, 16) + c0;
    return (int32_t)psc_shr_round64(r, 1);
}

/* q scaled to unit length (Q2.30); a zero quaternion becomes the identity. */
static void quat_normalize(int32_t q[4])
{
    uint64_t n = 0;
    for (unsigned k = 0; k < 4; k++)
        n += (uint64_t)((int64_t)q[k] * q[k]);
    uint32_t len = psc_isqrt64(n);
    if (len == 0) {
        q[0] = q[1] = q[2] = 0;
        q[3] = PSC_Q30_ONE;
        return;
    }
    for (unsigned k = 0; k < 4; k++)
        q[k] = (int32_t)psc_div_round64((int64_t)q[k] * ((int64_t)1 << 30), len);
}

void psc_patch_channel_eval(const psc_patch_model_t *m, const psc_patch_channel_t *c, uint32_t time_ms, int32_t v[4])
{
    const psc_patch_key_t *k = m->keys + c->first_key;
    uint32_t n = c->key_count, lo = 0, hi = n - 1u;

    if (n == 1 || time_ms <= k[0].time_ms || time_ms >= k[n - 1u].time_ms) {
        const psc_patch_key_t *e = (n == 1 || time_ms <= k[0].time_ms) ? &k[0] : &k[n - 1u];
        for (unsigned j = 0; j < 4; j++)
            v[j] = e->v[j];
        return;
    }
    while (hi - lo > 1u) {   /* the key interval holding time_ms */
        uint32_t mid = lo + (hi - lo) / 2u;
        if (k[mid].time_ms <= time_ms)
            lo = mid;
        else
            hi = mid;
    }
    uint32_t i0 = lo ? lo - 1u : lo, i3 = hi + 1u < n ? hi + 1u : hi;
    /* the fraction of the interval, Q16.16 rounded to nearest (below 1: time_ms < k[hi].time_ms) */
    uint64_t span = k[hi].time_ms - k[lo].time_ms;
    int32_t s = (int32_t)((((uint64_t)(time_ms - k[lo].time_ms) << 16) + span / 2u) / span);
    for (unsigned j = 0; j < 4; j++)
        v[j] = catmull_rom(k[i0].v[j], k[lo].v[j], k[hi].v[j], k[i3].v[j], s);
    if (c->kind == PSC_PATCH_CHAN_ROTATE)
        quat_normalize(v);
}

/* ---- bones ------------------------------------------------------------------------------------------------ */

/* The rotation matrix (Q16.16) of a unit quaternion (Q2.30). */
static void quat_matrix(const int32_t q[4], psc_mat4_q16_t *r)
{
    int64_t x = q[0], y = q[1], z = q[2], w = q[3];
    /* entries 1 - 2(y^2 + z^2) etc.: products are Q4.60, scaled to Q16.16 */
#define Q(e) ((int32_t)psc_shr_round64((e), 44))
    int64_t one = (int64_t)1 << 60;
    psc_mat4_identity(r);
    r->m[0][0] = Q(one - 2 * (y * y + z * z));
    r->m[0][1] = Q(2 * (x * y - z * w));
    r->m[0][2] = Q(2 * (x * z + y * w));
    r->m[1][0] = Q(2 * (x * y + z * w));
    r->m[1][1] = Q(one - 2 * (x * x + z * z));
    r->m[1][2] = Q(2 * (y * z - x * w));
    r->m[2][0] = Q(2 * (x * z - y * w));
    r->m[2][1] = Q(2 * (y * z + x * w));
    r->m[2][2] = Q(one - 2 * (x * x + y * y));
#undef Q
}

/* local = translate(offset) rotate(rest) translate(t) rotate(q) */
static void bone_local(const psc_patch_bone_t *b, const int32_t q[4], const int32_t t[3], psc_mat4_q16_t *out)
{
    psc_mat4_q16_t rest, anim;

    quat_matrix(b->rot_q30, &rest);
    quat_matrix(q, &anim);
    anim.m[0][3] = t[0];
    anim.m[1][3] = t[1];
    anim.m[2][3] = t[2];
    rest.m[0][3] = b->offset_q16[0];
    rest.m[1][3] = b->offset_q16[1];
    rest.m[2][3] = b->offset_q16[2];
    psc_mat4_mul(out, &rest, &anim);
}

/* The inverse of a rigid transform: R^T and -R^T t. */
static void rigid_inverse(const psc_mat4_q16_t *a, psc_mat4_q16_t *out)
{
    psc_mat4_identity(out);
    for (unsigned i = 0; i < 3; i++)
        for (unsigned j = 0; j < 3; j++)
            out->m[i][j] = a->m[j][i];
    for (unsigned i = 0; i < 3; i++) {
        int64_t s = 0;
        for (unsigned j = 0; j < 3; j++)
            s += (int64_t)a->m[j][i] * a->m[j][3];
        out->m[i][3] = (int32_t)-psc_shr_round64(s, 16);
    }
}

/* Bones' model-space transforms from their local rotations and translations this frame. */
static void pose_bones(psc_patch_t *p, bool rest)
{
    const psc_patch_model_t *m = p->m;
    static const int32_t identity[4] = {0, 0, 0, PSC_Q30_ONE}, zero[3] = {0, 0, 0};

    for (uint32_t b = 0; b < m->bone_count; b++) {
        const psc_patch_bone_t *bone = &m->bones[b];
        psc_mat4_q16_t local;
        bone_local(bone, rest ? identity : p->bone_rot_q30[b], rest ? zero : p->bone_trans_q16[b], &local);
        if (bone->parent == PSC_PATCH_NO_BONE)
            p->bone_world[b] = local;
        else
            psc_mat4_mul(&p->bone_world[b], &p->bone_world[bone->parent], &local);
    }
}

void psc_patch_bone_pose(const psc_patch_t *p, unsigned b, int32_t rot_q30[4], int32_t trans_q16[3])
{
    for (unsigned k = 0; k < 4; k++)
        rot_q30[k] = p->bone_rot_q30[b][k];
    for (unsigned k = 0; k < 3; k++)
        trans_q16[k] = p->bone_trans_q16[b][k];
}

/* Called once at start-up: the rest transforms and their inverses. */
void psc_patch_anim_init(psc_patch_t *p);

void psc_patch_anim_init(psc_patch_t *p)
{
    const psc_patch_model_t *m = p->m;

    for (uint32_t b = 0; b < m->bone_count; b++) {
        for (unsigned k = 0; k < 4; k++)
            p->bone_rot_q30[b][k] = k == 3 ? PSC_Q30_ONE : 0;
        p->bone_trans_q16[b][0] = p->bone_trans_q16[b][1] = p->bone_trans_q16[b][2] = 0;
    }
    pose_bones(p, true);
    for (uint32_t b = 0; b < m->bone_count; b++)
        rigid_inverse(&p->bone_world[b], &p->bone_rest_inv[b]);
}

/* p_out = M p (Q16.16), exact to the rounding of one product sum */
static void apply(const psc_mat4_q16_t *mx, const int32_t pin[3], int64_t out[3])
{
    for (unsigned i = 0; i < 3; i++)
        out[i] = (int64_t)mx->m[i][0] * pin[0] + (int64_t)mx->m[i][1] * pin[1] + (int64_t)mx->m[i][2] * pin[2] +
                 (int64_t)mx->m[i][3] * 65536;
}

void psc_patch_pose(psc_patch_t *p, int action, uint32_t time_ms)
{
    psc_patch_pose_begin(p, action, time_ms);
    psc_patch_pose_finish(p);
}

void psc_patch_pose_begin(psc_patch_t *p, int action, uint32_t time_ms)
{
    const psc_patch_model_t *m = p->m;
    const psc_patch_action_t *a = (action >= 0 && (uint32_t)action < m->action_count) ? &m->actions[action] : NULL;
    uint32_t t = a ? time_ms % a->duration_ms : 0;
    p->pose_action = a ? action : -1;   /* (what the self-shadowing's correction through each action reads) */
    p->pose_time_ms = t;

    for (uint32_t i = 0; i < m->point_count; i++)
        for (unsigned k = 0; k < 3; k++)
            p->prev_pos[i][k] = p->pos[i][k];
    for (uint32_t b = 0; b < m->bone_count; b++) {
        for (unsigned k = 0; k < 4; k++)
            p->bone_rot_q30[b][k] = k == 3 ? PSC_Q30_ONE : 0;
        p->bone_trans_q16[b][0] = p->bone_trans_q16[b][1] = p->bone_trans_q16[b][2] = 0;
    }
    /* the rest positions, moved by muscle channels, are what the bones carry */
    for (uint32_t i = 0; i < m->point_count; i++)
        for (unsigned k = 0; k < 3; k++)
            p->pos[i][k] = m->rest_q16[3 * i + k];
    if (a != NULL) {
        for (uint32_t c = 0; c < a->channel_count; c++) {
            const psc_patch_channel_t *ch = &m->channels[a->first_channel + c];
            int32_t v[4];
            psc_patch_channel_eval(m, ch, t, v);
            if (ch->kind == PSC_PATCH_CHAN_ROTATE)
                for (unsigned k = 0; k < 4; k++)
                    p->bone_rot_q30[ch->target][k] = v[k];
            else if (ch->kind == PSC_PATCH_CHAN_TRANSLATE)
                for (unsigned k = 0; k < 3; k++)
                    p->bone_trans_q16[ch->target][k] = v[k];
            else
                for (unsigned k = 0; k < 3; k++)
                    p->pos[ch->target][k] += v[k];
        }
    }
}

void psc_patch_pose_finish(psc_patch_t *p)
{
    const psc_patch_model_t *m = p->m;

    if (m->bone_count == 0)
        return;
    pose_bones(p, false);
    for (uint32_t b = 0; b < m->bone_count; b++)
        psc_mat4_mul(&p->bone_skin[b], &p->bone_world[b], &p->bone_rest_inv[b]);
    for (uint32_t i = 0; i < m->point_count; i++) {
        const psc_patch_skin_t *s = &m->skin[i];
        int64_t a0[3], a1[3];
        int32_t rest[3] = {p->pos[i][0], p->pos[i][1], p->pos[i][2]};
        apply(&p->bone_skin[s->bone0], rest, a0);
        if (s->bone1 != PSC_PATCH_NO_BONE && s->w1_q15 != 0) {
            apply(&p->bone_skin[s->bone1], rest, a1);
            for (unsigned k = 0; k < 3; k++)
                a0[k] += psc_shr_round64((a1[k] - a0[k]) * s->w1_q15, 15);
        }
        for (unsigned k = 0; k < 3; k++)
            p->pos[i][k] = (int32_t)psc_shr_round64(a0[k], 16);
    }
}
