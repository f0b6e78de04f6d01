/* SPDX-License-Identifier: MIT */
/*
 * shadow_rest.c - the shadow pack's rest correction (shadow.h,
 * core/shadow/psc_shadow.h "SREF"): for each point or vertex, the ray-traced
 * occlusion (measure/raycast.h: 256 stratified cosine-weighted rays,
 * unbounded, both sides of the triangles blocking, about the smooth normal)
 * less what the device's own spheres give there (core's integer code on the
 * device's inputs), averaged over the rest pose and REST_POSES_PER_ACTION
 * times through each action; the device adds it to the spheres' every frame,
 * after scaling theirs by one gain for the whole character: how much the
 * reference moves, from pose to pose, with what the spheres give (fitted by
 * least squares within each point; the spheres, which leave out what lies
 * between them, see only part of a change).
 * Why averaged: what the spheres miss in one pose only (a sphere that pokes
 * out of an elbow as it bends, a part that comes near) is not the
 * character's, and a correction that kept it would darken every other pose;
 * what they miss in all (a crease, a thin part, a rim) is. A pose in which a
 * point is buried (every ray blocked: the point runs inside another part
 * there, nobody sees it) says nothing of it and is left out, unless the
 * point is buried in every pose (a cab's inside): then its correction makes
 * it dark.
 * For a patch character, the correction through each action too (SRPH): at
 * REST_PHASES phases of every action, each point's reference less the gain
 * times the spheres in that pose, buried or not (a point inside another part
 * there is dark), which a frame of that action interpolates by its time.
 */
#include "bake/shadow.h"
#include "bake/shadow_grid.h"
#include "measure/raycast.h"
#include "psc_io_container_write.h"
#include "psc_io_error.h"
#include "patch/psc_patch_frame.h"
#include "shadow/psc_shadow_frame.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define REST_STRATA 16u            /* 16 x 16 = 256 rays a point */
#define REST_EPS 1e-4              /* the rays start this far along the normal (units of R) */
#define REST_POSES_PER_ACTION 4u   /* at (k + 1/2) / 4 of each action's length */
/* The correction through each action: at k / 8 of its length. Thom waving, every vertex compared: correlation
 * 0.818 with the average alone (docs/characters.md). */
#define REST_PHASES 8u
/* The rest pose weighs this many action poses: it is the pose an author sets the character in and the one a
 * visitor sees first. Thom's correlation at rest / waving: 0.955 / 0.80 with the rest pose alone, 0.896 / 0.851
 * with 4 (docs/characters.md). */
#define REST_WEIGHT 4.0
#define REST_GAIN_MIN 0.5   /* the fitted gain's range (the format allows 1/4..4) */
#define REST_GAIN_MAX 2.0

/* Each point's reference (y) and spheres' occlusion (x) over the poses it is open in: the weighted sums, the
 * rest pose weighing REST_WEIGHT action poses; and over those it is buried in. */
typedef struct {
    double (*m)[5];              /* [point]: sum w, w x, w y, w x x, w x y */
    double *buried_sum;          /* y - x over the poses it is buried in */
    uint32_t *buried_n;
    uint32_t n;
} rest_acc_t;

static int acc_new(rest_acc_t *a, uint32_t n)
{
    size_t k = n ? n : 1u;
    a->m = calloc(k, sizeof *a->m);
    a->buried_sum = calloc(k, sizeof *a->buried_sum);
    a->buried_n = calloc(k, sizeof *a->buried_n);
    a->n = n;
    return a->m && a->buried_sum && a->buried_n ? 0 : -1;
}

static void acc_free(rest_acc_t *a)
{
    free(a->m), free(a->buried_sum), free(a->buried_n);
}

/* Point i's reference ref (1: buried) against the spheres' occ_q16 in pose q (0: rest). */
static void acc_add(rest_acc_t *a, uint32_t i, unsigned q, double ref, uint32_t occ_q16)
{
    double x = occ_q16 / 65536.0, w = q == 0 ? REST_WEIGHT : 1.0;
    if (ref >= 1.0) {
        a->buried_sum[i] += ref - x;
        a->buried_n[i]++;
        return;
    }
    double *m = a->m[i];
    m[0] += w, m[1] += w * x, m[2] += w * ref, m[3] += w * x * x, m[4] += w * x * ref;
}

/* The gain: how the reference changes with the spheres' occlusion from pose to pose, within each point (least
 * squares over every point's poses about its own means), REST_GAIN_MIN..MAX; 1 when the poses do not move the spheres. */
static double acc_gain(const rest_acc_t *a)
{
    double sxy = 0, sxx = 0;
    for (uint32_t i = 0; i < a->n; i++) {
        const double *m = a->m[i];
        if (m[0] <= 0)
            continue;
        sxx += m[3] - m[1] * m[1] / m[0];
        sxy += m[4] - m[1] * m[2] / m[0];
    }
    if (sxx < 1e-6 * a->n)
        return 1.0;
    double g = sxy / sxx;
    return g < REST_GAIN_MIN ? REST_GAIN_MIN : g > REST_GAIN_MAX ? REST_GAIN_MAX : g;
}

/* Q1.15, saturated. */
static int16_t q15(double d)
{
    long v = lround(d * 32768.0);
    return (int16_t)(v > 32767 ? 32767 : v < -32767 ? -32767 : v);
}

/* The correction of each point, Q1.15 (saturated), for gain g: the weighted mean of y - g x over the poses it is
 * open in; one buried in all is a mesh's vertex inside (a cab's: dark, the mean of y - x), or a patch corner
 * inside (a teapot's spout's end: its correction would spread over the part outside, so none). */
static void acc_result(const rest_acc_t *a, double g, bool corners, int16_t *rest)
{
    for (uint32_t i = 0; i < a->n; i++) {
        const double *m = a->m[i];
        double d = m[0] > 0 ? (m[2] - g * m[1]) / m[0]
                   : a->buried_n[i] && !corners ? a->buried_sum[i] / a->buried_n[i] : 0.0;
        rest[i] = q15(d);
    }
}

/* The poses: 0 the rest pose, then REST_POSES_PER_ACTION through each of actions actions. */
static unsigned pose_count(unsigned actions)
{
    return 1u + actions * REST_POSES_PER_ACTION;
}

/* Pose q's action (-1: rest) and its fraction of the action's length. */
static int pose_action(unsigned q, double *fraction)
{
    if (q == 0) {
        *fraction = 0.0;
        return -1;
    }
    *fraction = ((q - 1u) % REST_POSES_PER_ACTION + 0.5) / REST_POSES_PER_ACTION;
    return (int)((q - 1u) / REST_POSES_PER_ACTION);
}

/* The correction through each action (SRPH): actions x REST_PHASES x n, Q1.15; NULL for none. */
typedef struct {
    const int16_t *q15;
    uint32_t actions;
} rest_phases_t;

/* The patch grid correction (SGRD): quads x PSC_BAKE_SHADOW_GRID_SIDE^2, Q1.15; NULL for none. */
typedef struct {
    const int16_t *q15;
    uint32_t quads;
} rest_grid_t;

/* The pack sm (parsed) written again with the rest correction rest[0..n) (and ph's, if any), or with grid's in
 * its place (rest NULL): *out replaced (freed). */
static int write_with_rest(const psc_shadow_model_t *sm, const int16_t *rest, uint32_t n, double gain,
                           const rest_phases_t *ph, const rest_grid_t *grid, const char *name, uint8_t **out,
                           size_t *out_len, char *err, size_t errlen)
{
    psc_shadow_info_raw_t info = {0};
    info.sphere_count = sm->sphere_count;
    info.level_count = (uint8_t)sm->level_count;
    info.access_omega = (uint16_t)sm->access_omega;
    info.access_theta = (uint16_t)sm->access_theta;
    info.comp_theta = (uint16_t)sm->comp_theta;
    info.comp_delta = (uint16_t)sm->comp_delta;
    for (uint32_t l = 0; l < sm->level_count; l++)
        info.level_first[l] = (uint16_t)sm->level_first[l];
    info.bone_count = sm->bone_count;
    const unsigned side = PSC_BAKE_SHADOW_GRID_SIDE;
    size_t rest_size = rest ? sizeof(psc_shadow_rest_raw_t) + (size_t)n * 2u : 0;
    size_t grid_size = grid ? sizeof(psc_shadow_grid_raw_t) + (size_t)grid->quads * side * side * 2u : 0;
    uint8_t *sref = malloc(rest ? rest_size : grid_size);
    if (sref == NULL)
        return psc_io_errorf(err, errlen, name, "out of memory");
    if (rest) {
        psc_shadow_rest_raw_t head = {n, (uint32_t)lround(gain * 65536.0)};
        memcpy(sref, &head, sizeof head);
        memcpy(sref + sizeof head, rest, (size_t)n * 2u);
    } else {
        psc_shadow_grid_raw_t head = {grid->quads, (uint16_t)side, 0};
        memcpy(sref, &head, sizeof head);
        memcpy(sref + sizeof head, grid->q15, grid_size - sizeof head);
    }
    size_t phase_size = ph && ph->q15 ? sizeof(psc_shadow_phase_raw_t) + (size_t)ph->actions * REST_PHASES * n * 2u : 0;
    uint8_t *srph = phase_size ? malloc(phase_size) : NULL;
    if (phase_size && srph == NULL) {
        free(sref);
        return psc_io_errorf(err, errlen, name, "out of memory");
    }
    if (srph) {
        psc_shadow_phase_raw_t phead = {(uint16_t)ph->actions, REST_PHASES, n};
        memcpy(srph, &phead, sizeof phead);
        memcpy(srph + sizeof phead, ph->q15, phase_size - sizeof phead);
    }
    psc_container_part_t parts[] = {
        {PSC_SECTION_SHADOW_INFO, &info, sizeof info},
        {PSC_SECTION_SHADOW_SPHERES, sm->spheres, sm->sphere_count * sizeof *sm->spheres},
        {PSC_SECTION_SHADOW_ACCESS, sm->access, (size_t)sm->access_omega * sm->access_theta * 4u},
        {PSC_SECTION_SHADOW_COMPOSITE, sm->comp,
         (size_t)sm->comp_theta * sm->comp_theta * sm->comp_delta * sizeof *sm->comp},
        {PSC_SECTION_SHADOW_ACOS, sm->acos_table, PSC_SHADOW_ACOS_SIZE * 2u},
        {rest ? PSC_SECTION_SHADOW_REST : PSC_SECTION_SHADOW_GRID, sref, rest ? rest_size : grid_size},
        {PSC_SECTION_SHADOW_PHASE, srph, phase_size},
    };
    uint8_t *bytes = NULL;
    size_t len = 0;
    int rc = psc_io_container_write(&psc_shadow_format, parts, srph ? 7 : 6, &bytes, &len, name, err, errlen);
    free(sref);
    free(srph);
    if (rc != 0)
        return -1;
    psc_shadow_model_t chk;
    psc_container_error_t e = {0};
    if (psc_shadow_parse(bytes, len, &chk, &e) != PSC_OK || chk.rest_count != (rest ? n : 0u) ||
        chk.grid_quads != (grid ? grid->quads : 0u) || chk.phase_actions != (srph ? ph->actions : 0u)) {
        free(bytes);
        return psc_io_errorf(err, errlen, name, "the shadow pack with its rest correction does not parse: %s",
                             e.what ? e.what : "?");
    }
    free(*out);
    *out = bytes;
    *out_len = len;
    return 0;
}

int psc_bake_shadow_rest_gltf(const psc_gltf_t *g, const char *name, uint8_t **pack, size_t *pack_len, char *err,
                              size_t errlen)
{
    psc_shadow_model_t sm;
    psc_container_error_t e = {0};
    if (psc_shadow_parse(*pack, *pack_len, &sm, &e) != PSC_OK)
        return psc_io_errorf(err, errlen, name, "the shadow pack does not parse: %s", e.what ? e.what : "?");
    uint32_t nv = g->mesh.vertex_count, nj = g->joint_count ? g->joint_count : 1u;
    double c[3], r;
    psc_gltf_frame(g, c, &r);
    psc_gltf_trs_t *local = malloc(nj * sizeof *local);
    double (*skin)[12] = malloc(nj * sizeof *skin), *pos = malloc((size_t)nv * 3u * sizeof *pos);
    double *nrm = malloc((size_t)nv * 3u * sizeof *nrm), (*dpos)[3] = malloc(nv * sizeof *dpos);
    double (*sn)[3] = malloc(nv * sizeof *sn);
    int32_t *pq = malloc((size_t)nv * 3u * sizeof *pq);
    int16_t *nq = malloc((size_t)nv * 3u * sizeof *nq), *rest = malloc(nv * sizeof *rest);
    psc_mat4_q16_t *skq = calloc(nj, sizeof *skq);
    uint32_t *col = calloc(nv, sizeof *col), *occ = malloc(nv * sizeof *occ);
    void *ws = malloc(psc_shadow_workspace_size(&sm, NULL) + 8u);
    rest_acc_t acc;
    int rc = -1;
    if (acc_new(&acc, nv) != 0 || !local || !skin || !pos || !nrm || !dpos || !sn || !pq || !nq || !rest || !skq ||
        !col || !occ || !ws) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    psc_shadow_t s;
    if (psc_shadow_init_mesh(&s, &sm, g->joint_count, ws, psc_shadow_workspace_size(&sm, NULL)) != PSC_OK) {
        psc_io_errorf(err, errlen, name, "the shadow pack does not fit the model");
        goto done;
    }
    unsigned poses = pose_count(g->duration > 0 ? 1u : 0u);
    for (unsigned q = 0; q < poses; q++) {
        /* the pose in the device's formats, shaded by the spheres alone (as a frame shades it) */
        double fraction;
        int action = pose_action(q, &fraction);
        psc_gltf_pose(g, action < 0 ? -1.0 : fraction * g->duration, local);
        psc_gltf_skin(g, local, NULL, skin);
        psc_gltf_deform(g, (const double(*)[12])skin, pos, nrm);
        psc_gltf_quantize(g, c, r, pos, nrm, (const double(*)[12])skin, pq, nq, skq);
        psc_shadow_update_bones(&s, skq, g->joint_count);
        psc_shadow_apply_mesh(&s, pq, nq, col, nv, PSC_SHADOW_STRENGTH_Q16, occ);
        /* the reference, in units of R */
        for (uint32_t i = 0; i < nv; i++)
            for (unsigned a = 0; a < 3; a++)
                dpos[i][a] = (pos[3 * i + a] - c[a]) / r;
        psc_measure_bvh_t *bvh = NULL;
        if (psc_measure_smooth_normals((const double(*)[3])dpos, nv, g->mesh.index, g->mesh.triangle_count, sn) != 0 ||
            (bvh = psc_measure_bvh_new((const double(*)[3])dpos, nv,
                                       (const uint32_t(*)[3])(const void *)g->mesh.index,
                                       g->mesh.triangle_count)) == NULL) {
            psc_io_errorf(err, errlen, name, "out of memory");
            goto done;
        }
        for (uint32_t i = 0; i < nv; i++)
            if (sn[i][0] != 0.0 || sn[i][1] != 0.0 || sn[i][2] != 0.0)   /* else no surface round it */
                acc_add(&acc, i, q, psc_measure_ao(bvh, dpos[i], sn[i], REST_STRATA, REST_EPS, INFINITY), occ[i]);
        psc_measure_bvh_free(bvh);
    }
    double gain = acc_gain(&acc);
    acc_result(&acc, gain, false, rest);
    rc = write_with_rest(&sm, rest, nv, gain, NULL, NULL, name, pack, pack_len, err, errlen);
done:
    acc_free(&acc);
    free(local), free(skin), free(pos), free(nrm), free(dpos), free(sn), free(pq), free(nq), free(rest), free(skq);
    free(col), free(occ), free(ws);
    return rc;
}

/* The frame's meshes of p as one in double (every batch's triangles index its own vertices); NULL out of memory. */
static psc_measure_bvh_t *frame_bvh(const psc_patch_t *p)
{
    double (*vpos)[3] = malloc((p->vtx_total ? p->vtx_total : 1u) * sizeof *vpos);
    uint32_t (*tri)[3] = malloc((p->tri_total ? p->tri_total : 1u) * sizeof *tri);
    psc_measure_bvh_t *bvh = NULL;
    if (vpos && tri) {
        for (uint32_t i = 0; i < p->vtx_total; i++)
            for (unsigned a = 0; a < 3; a++)
                vpos[i][a] = p->out_pos[3 * i + a] / 65536.0;
        for (uint32_t b = 0, t = 0; b <= p->batch_count; b++) {
            uint32_t t_end = b < p->batch_count ? p->batch_start_tri[b + 1u] : p->tri_total;
            for (; t < t_end; t++)
                for (unsigned k = 0; k < 3; k++)
                    tri[t][k] = p->batch_start_vertex[b] + p->out_index[3 * t + k];
        }
        bvh = psc_measure_bvh_new((const double(*)[3])vpos, p->vtx_total, (const uint32_t(*)[3])tri, p->tri_total);
    }
    free(vpos);
    free(tri);
    return bvh;
}

/* The character posed by action (-1: rest) at ms, finely tessellated: each point's reference y[i] (1: buried) and
 * the spheres' occlusion x[i], and has[i] 0 where the point has no normal (a degenerate spot). 0, or -1 with err. */
static int pose_figures(psc_patch_t *p, psc_shadow_t *s, const psc_patch_camera_t *cam, int action, uint32_t ms,
                        double *y, uint32_t *x, uint8_t *has, const char *name, char *err, size_t errlen)
{
    psc_patch_pose(p, action, ms);
    psc_patch_tangents(p);
    if (psc_patch_tessellate(p, cam, NULL) != PSC_OK)
        return psc_io_errorf(err, errlen, name, "cannot tessellate the pose (action %d at %u ms)", action, (unsigned)ms);
    psc_measure_bvh_t *bvh = frame_bvh(p);
    if (bvh == NULL)
        return psc_io_errorf(err, errlen, name, "out of memory");
    psc_shadow_update(s, p);
    for (uint32_t i = 0; i < p->m->point_count; i++) {
        int32_t bent[3];
        x[i] = psc_shadow_occlusion_bent(s, p->pos[i], p->nrm[i], bent);
        double at[3], n[3], l = 0;
        for (unsigned a = 0; a < 3; a++) {
            at[a] = p->pos[i][a] / 65536.0;
            n[a] = p->nrm[i][a] / 65536.0;
            l += n[a] * n[a];
        }
        l = sqrt(l);
        has[i] = l >= 0.5;
        if (!has[i])
            continue;   /* no normal: nothing to correct */
        for (unsigned a = 0; a < 3; a++)
            n[a] /= l;
        y[i] = psc_measure_ao(bvh, at, n, REST_STRATA, REST_EPS, INFINITY);
    }
    psc_measure_bvh_free(bvh);
    return 0;
}

/* The patch grid correction of p's character at rest, written into the pack (sm parsed from it): 2, or -1 with
 * err. */
static int grid_at_rest(psc_patch_t *p, psc_shadow_t *s, const psc_patch_camera_t *cam, const psc_shadow_model_t *sm,
                        const char *name, uint8_t **pack, size_t *pack_len, char *err, size_t errlen)
{
    psc_patch_pose(p, -1, 0);
    psc_patch_tangents(p);
    if (psc_patch_tessellate(p, cam, NULL) != PSC_OK)
        return psc_io_errorf(err, errlen, name, "cannot tessellate the rest pose");
    psc_shadow_update(s, p);
    uint32_t quads = psc_bake_shadow_grid_quads(p->m);
    if (quads > PSC_SHADOW_MAX_GRID_QUADS)   /* (before the rays, not after) */
        return psc_io_errorf(err, errlen, name, "%u quads: beyond the patch grid correction's %u", (unsigned)quads,
                             (unsigned)PSC_SHADOW_MAX_GRID_QUADS);
    const unsigned side = PSC_BAKE_SHADOW_GRID_SIDE;
    int16_t *q15 = malloc((size_t)quads * side * side * sizeof *q15);
    int rc = -1;
    if (q15 == NULL || psc_bake_shadow_grid(p, s, REST_STRATA, REST_EPS, q15) != 0)
        psc_io_errorf(err, errlen, name, "out of memory");
    else {
        rest_grid_t grid = {q15, quads};
        rc = write_with_rest(sm, NULL, 0, 1.0, NULL, &grid, name, pack, pack_len, err, errlen) == 0 ? 2 : -1;
    }
    free(q15);
    return rc;
}

int psc_bake_shadow_rest_patch(const psc_patch_model_t *m, const char *name, uint8_t **pack, size_t *pack_len,
                               char *err, size_t errlen)
{
    psc_shadow_model_t sm;
    psc_container_error_t e = {0};
    if (psc_shadow_parse(*pack, *pack_len, &sm, &e) != PSC_OK)
        return psc_io_errorf(err, errlen, name, "the shadow pack does not parse: %s", e.what ? e.what : "?");
    /* each pose finely tessellated (0.005 R): the reference's mesh, and the points as the device has them */
    psc_patch_limits_t lim = {PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES, 1u << 21, PSC_PATCH_MAX_DEPTH};
    size_t ws_size = psc_patch_workspace_size(m, &lim), sh_size = psc_shadow_workspace_size(&sm, m);
    uint32_t np = m->point_count ? m->point_count : 1u;
    uint32_t actions = m->action_count <= PSC_SHADOW_MAX_PHASE_ACTIONS ? m->action_count : 0u;
    void *ws = NULL, *sh_ws = malloc(sh_size + 8u);
    int16_t *rest = malloc(np * sizeof *rest);
    int16_t *phase = actions ? malloc((size_t)actions * REST_PHASES * np * sizeof *phase) : NULL;
    double *y = malloc(np * sizeof *y);
    uint32_t *x = malloc(np * sizeof *x);
    uint8_t *has = malloc(np);
    rest_acc_t acc;
    psc_patch_t p;
    psc_shadow_t s;
    int rc = -1;
    if (acc_new(&acc, m->point_count) != 0 || !sh_ws || !rest || (actions && !phase) || !y || !x || !has ||
        ws_size == 0 || posix_memalign(&ws, 64, ws_size) != 0 || psc_patch_init(&p, m, &lim, ws, ws_size) != PSC_OK) {
        psc_io_errorf(err, errlen, name, "out of memory");
        goto done;
    }
    if (psc_shadow_init(&s, &sm, m, sh_ws, sh_size) != PSC_OK) {
        psc_io_errorf(err, errlen, name, "the shadow pack does not fit the character");
        goto done;
    }
    psc_patch_camera_t cam = {0};
    psc_mat4_identity(&cam.camera_from_object);
    cam.camera_from_object.m[2][3] = 100 * 65536;
    cam.focal_px_q16 = 65536;
    cam.tol_units_q16 = 65536 / 200;
    cam.near_q16 = 65536;
    if (!s.at_corners) {   /* large patches: a correction at their corners would not hold across them; a grid over
                            * each one's (u, v) at rest */
        rc = grid_at_rest(&p, &s, &cam, &sm, name, pack, pack_len, err, errlen);
        goto done;
    }
    /* the average over poses, and the gain */
    unsigned poses = pose_count(m->action_count);
    for (unsigned q = 0; q < poses; q++) {
        double fraction;
        int action = pose_action(q, &fraction);
        uint32_t ms = action < 0 ? 0u : (uint32_t)(fraction * m->actions[action].duration_ms);
        if (pose_figures(&p, &s, &cam, action, ms, y, x, has, name, err, errlen) != 0)
            goto done;
        for (uint32_t i = 0; i < m->point_count; i++)
            if (has[i])
                acc_add(&acc, i, q, y[i], x[i]);
    }
    double gain = acc_gain(&acc);
    acc_result(&acc, gain, true, rest);
    /* through each action: y - gain x at each phase, buried or not; a point without a normal there keeps its
     * average */
    for (uint32_t a = 0; a < actions; a++)
        for (unsigned k = 0; k < REST_PHASES; k++) {
            uint32_t ms = (uint32_t)((uint64_t)m->actions[a].duration_ms * k / REST_PHASES);
            if (pose_figures(&p, &s, &cam, (int)a, ms, y, x, has, name, err, errlen) != 0)
                goto done;
            int16_t *out = phase + ((size_t)a * REST_PHASES + k) * m->point_count;
            for (uint32_t i = 0; i < m->point_count; i++)
                out[i] = has[i] ? q15(y[i] - gain * (x[i] / 65536.0)) : rest[i];
        }
    rest_phases_t ph = {phase, actions};
    rc = write_with_rest(&sm, rest, m->point_count, gain, &ph, NULL, name, pack, pack_len, err, errlen);
done:
    acc_free(&acc);
    free(ws);
    free(sh_ws);
    free(rest);
    free(phase);
    free(y);
    free(x);
    free(has);
    return rc;
}
