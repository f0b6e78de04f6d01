/* SPDX-License-Identifier: MIT */
/*
 * patch_pack.c - the patch pack written from a host character
 * (psc_bake_patch_pack, patch_source.h): positions in units of R centred on
 * the rest box, bones relative to their parents, quaternions Q2.30, key
 * times in milliseconds. Every conversion rounds to nearest.
 */
#include "import/patch_source.h"
#include "psc_io_container_write.h"
#include "psc_io_error.h"
#include "psc_io_load.h"
#include "util/quat.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void quat_to_q30(const double q[4], int32_t out[4])
{
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (unsigned k = 0; k < 4; k++)
        out[k] = n > 0.0 ? (int32_t)lround(q[k] / n * 1073741824.0 * (1.0 - 1e-9)) : (k == 3 ? 1 << 30 : 0);
}

static int32_t to_q16(double v)
{
    double s = v * 65536.0;
    return (int32_t)lround(s > 2147483647.0 ? 2147483647.0 : s < -2147483647.0 ? -2147483647.0 : s);
}

int psc_bake_patch_pack(const psc_patch_src_t *s, const char *name, uint8_t **out, size_t *out_len, char *err,
                         size_t errlen)
{
    double c[3], d2 = 0.0;
    int rc = -1;

    *out = NULL;
    *out_len = 0;
    for (unsigned a = 0; a < 3; a++) {
        c[a] = (s->lo[a] + s->hi[a]) / 2.0;
        d2 += (s->hi[a] - s->lo[a]) * (s->hi[a] - s->lo[a]);
    }
    double r = sqrt(d2) / 2.0;
    if (!(r > 0.0) || !isfinite(r))
        return psc_io_errorf(err, errlen, name, "the control points have no extent");
    double inv = 1.0 / r;

    size_t keys = 0, chans = 0;
    for (size_t a = 0; a < s->action_count; a++) {
        chans += s->action[a].chan_count;
        for (size_t k = 0; k < s->action[a].chan_count; k++)
            keys += s->action[a].chan[k].count;
    }
    int32_t *pts = malloc((s->point_count ? s->point_count : 1) * 3 * sizeof *pts);
    psc_patch_bone_t *bones = calloc(s->bone_count ? s->bone_count : 1, sizeof *bones);
    psc_patch_action_t *acts = calloc(s->action_count ? s->action_count : 1, sizeof *acts);
    psc_patch_channel_t *chn = calloc(chans ? chans : 1, sizeof *chn);
    psc_patch_key_t *key = calloc(keys ? keys : 1, sizeof *key);
    int32_t *hnd = s->handle ? calloc(s->cp_count * 6, sizeof *hnd) : NULL;
    if (!pts || !bones || !acts || !chn || !key || (s->handle && !hnd)) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    for (size_t i = 0; i < s->point_count; i++)
        for (unsigned a = 0; a < 3; a++)
            pts[3 * i + a] = to_q16((s->point[i][a] - c[a]) * inv);
    if (hnd)
        for (size_t i = 0; i < s->cp_count; i++)
            for (unsigned h = 0; h < 2; h++)
                for (unsigned a = 0; a < 3; a++)   /* handles are offsets: scaled, not moved */
                    hnd[6 * i + 3 * h + a] = to_q16(s->handle[i][h][a] * inv);
    for (size_t b = 0; b < s->bone_count; b++) {
        const psc_patch_bone_src_t *bs = &s->bone[b];
        double off[3], rel[4];
        if (bs->parent < 0) {
            for (unsigned a = 0; a < 3; a++)
                off[a] = (bs->head[a] - c[a]) * inv;
            memcpy(rel, bs->rot, sizeof rel);
        } else {
            const psc_patch_bone_src_t *ps = &s->bone[bs->parent];
            double dv[3], pc[4];
            for (unsigned a = 0; a < 3; a++)
                dv[a] = (bs->head[a] - ps->head[a]) * inv;
            psc_quat_conj(ps->rot, pc);
            psc_quat_rotate(pc, dv, off);
            psc_quat_mul(pc, bs->rot, rel);
        }
        bones[b].parent = bs->parent < 0 ? PSC_PATCH_NO_BONE : (uint16_t)bs->parent;
        for (unsigned a = 0; a < 3; a++)
            bones[b].offset_q16[a] = to_q16(off[a]);
        quat_to_q30(rel, bones[b].rot_q30);
    }
    size_t ci = 0, ki = 0;
    for (size_t a = 0; a < s->action_count; a++) {
        const psc_patch_action_src_t *as = &s->action[a];
        memcpy(acts[a].name, as->name, sizeof acts[a].name - 1u);
        long dur = lround(as->duration * 1000.0);
        acts[a].duration_ms = (uint32_t)(dur < 1 ? 1 : dur);
        acts[a].first_channel = (uint32_t)ci;
        acts[a].channel_count = (uint16_t)as->chan_count;
        for (size_t k = 0; k < as->chan_count; k++) {
            const psc_patch_chan_src_t *cs = &as->chan[k];
            psc_patch_channel_t *cd = &chn[ci++];
            cd->target = cs->target;
            cd->kind = cs->kind;
            cd->first_key = (uint32_t)ki;
            double prevq[4] = {0, 0, 0, 1};
            for (size_t j = 0; j < cs->count; j++) {
                long t = lround(cs->time[j] * 1000.0);
                psc_patch_key_t *kd = &key[ki];
                if (ki > cd->first_key && (long)key[ki - 1].time_ms >= t)
                    kd = &key[ki - 1];   /* two keys in one millisecond: the later one stands */
                else
                    ki++;
                kd->time_ms = (uint32_t)(t < 0 ? 0 : t);
                if (cs->kind == PSC_PATCH_CHAN_ROTATE) {
                    double q[4];
                    memcpy(q, cs->value[j], sizeof q);
                    /* the nearer of q and -q, so interpolation takes the short way */
                    if (q[0] * prevq[0] + q[1] * prevq[1] + q[2] * prevq[2] + q[3] * prevq[3] < 0.0)
                        for (unsigned e = 0; e < 4; e++)
                            q[e] = -q[e];
                    memcpy(prevq, q, sizeof q);
                    quat_to_q30(q, kd->v);
                } else {
                    for (unsigned e = 0; e < 3; e++)
                        kd->v[e] = to_q16(cs->value[j][e] * inv);
                    kd->v[3] = 0;
                }
            }
            cd->key_count = (uint32_t)(ki - cd->first_key);
        }
    }

    psc_patch_info_raw_t info = {
        .point_count = (uint32_t)s->point_count,
        .cp_count = (uint32_t)s->cp_count,
        .spline_count = (uint32_t)s->spline_count,
        .hook_count = (uint32_t)s->hook_count,
        .edge_count = (uint32_t)s->edge_count,
        .face_count = (uint32_t)s->face_count,
        .color_count = (uint32_t)s->color_count,
        .bone_count = (uint32_t)s->bone_count,
        .action_count = (uint32_t)s->action_count,
        .channel_count = (uint32_t)ci,
        .key_count = (uint32_t)ki,
        .scale_q16 = (uint32_t)to_q16(r),
    };
    for (unsigned a = 0; a < 3; a++)
        info.center_q16[a] = to_q16(c[a]);
    psc_container_part_t parts[16];
    unsigned n = 0;
    parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_INFO, &info, sizeof info};
    parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_POINTS, pts, s->point_count * 12};
    parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_CPS, s->cp, s->cp_count * sizeof *s->cp};
    parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_SPLINES, s->spline, s->spline_count * sizeof *s->spline};
    if (s->hook_count)
        parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_HOOKS, s->hook, s->hook_count * sizeof *s->hook};
    parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_EDGES, s->edge, s->edge_count * sizeof *s->edge};
    parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_FACES, s->face, s->face_count * sizeof *s->face};
    parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_COLORS, s->color, s->color_count * sizeof *s->color};
    if (hnd)
        parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_HANDLES, hnd, s->cp_count * 6 * sizeof *hnd};
    if (s->bone_count) {
        parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_BONES, bones, s->bone_count * sizeof *bones};
        parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_SKIN, s->skin, s->point_count * sizeof *s->skin};
    }
    if (s->action_count) {
        parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_ACTIONS, acts, s->action_count * sizeof *acts};
        parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_CHANNELS, chn, ci * sizeof *chn};
        parts[n++] = (psc_container_part_t){PSC_SECTION_PATCH_KEYS, key, ki * sizeof *key};
    }
    if (psc_io_container_write(&psc_patch_format, parts, n, out, out_len, name, err, errlen) != 0)
        goto done;
    /* what the device will read: checked by the device's own parser */
    psc_patch_model_t m;
    if (psc_io_patch_parse_named(name, *out, *out_len, &m, err, errlen) != 0) {
        free(*out);
        *out = NULL;
        *out_len = 0;
        goto done;
    }
    rc = 0;
done:
    free(pts);
    free(bones);
    free(acts);
    free(chn);
    free(key);
    free(hnd);
    return rc;
}
