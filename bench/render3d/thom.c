/* SPDX-License-Identifier: MIT */
/*
 * thom.c - the second benchmark scene: Thom (seed 002's character, assets/thom)
 * at 1.1 s of his Wave action, tessellated once by the patch splitter for an
 * 800-pixel-wide view (0.5 pixel chord tolerance, back faces kept so every
 * side is there as he turns), as one model with his colours and normals.
 */
#include "render3d.h"
#include "bake/patch_any.h"
#include "3d/psc_3d_orbit.h"
#include "patch/psc_patch_frame.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define THOM_DIR "assets/thom"
#define THOM_TIME_MS 1100u

static int thom_action(const psc_patch_model_t *m, const char *name)
{
    for (uint32_t i = 0; i < m->action_count; i++)
        if (strncmp(m->actions[i].name, name, sizeof m->actions[i].name) == 0)
            return (int)i;
    return -1;
}

/* The tessellated batches of p as one model, in the patch output's units (R). */
static int batches_to_model(const psc_patch_t *p, psc_model_t *out)
{
    memset(out, 0, sizeof *out);
    uint32_t nv = 0, nt = 0;
    for (unsigned b = 0; b < p->batch_count; b++) {
        nv += p->batch[b].vertex_count;
        nt += p->batch[b].triangle_count;
    }
    out->pos = malloc((size_t)nv * 3 * sizeof(double));
    out->normal = malloc((size_t)nv * 3 * sizeof(double));
    out->color = malloc((size_t)nv * sizeof(uint32_t));
    out->index = malloc((size_t)nt * 3 * sizeof(uint32_t));
    if (!out->pos || !out->normal || !out->color || !out->index)
        return -1;
    uint32_t v0 = 0, t = 0;
    for (unsigned b = 0; b < p->batch_count; b++) {
        const psc_mesh_t *m = &p->batch[b];
        for (uint32_t i = 0; i < m->vertex_count; i++) {
            for (unsigned k = 0; k < 3; k++) {
                out->pos[3 * (v0 + i) + k] = m->position_q16[3 * i + k] / 65536.0;
                out->normal[3 * (v0 + i) + k] = m->normal_q14[3 * i + k] / 16384.0;
            }
            out->color[v0 + i] = m->color ? m->color[i] : m->base_color;
        }
        for (uint32_t i = 0; i < m->triangle_count * 3; i++)
            out->index[3 * t + i] = v0 + m->index[i];
        v0 += m->vertex_count;
        t += m->triangle_count;
    }
    out->vertex_count = nv;
    out->triangle_count = nt;
    return 0;
}

int r3d_thom_model(psc_model_t *out)
{
    psc_bake_patch_opts_t o = {.actions = {THOM_DIR "/Wave.act"}, .action_count = 1,
                               .skin_from = THOM_DIR "/Thom2.mdl", .quiet = true};
    psc_io_patch_t pf;
    char err[512];
    if (psc_bake_patch_any(THOM_DIR "/Thom.mdl", &o, &pf, err, sizeof err) != 0) {
        fprintf(stderr, "render3d bench: %s\n", err);
        return -1;
    }
    const psc_patch_model_t *m = &pf.model;
    psc_patch_limits_t lim = {PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES, 1u << 21, PSC_PATCH_MAX_DEPTH};
    size_t size = psc_patch_workspace_size(m, &lim);
    void *ws = NULL;
    psc_patch_t p;
    int rc = -1;
    if (size == 0 || posix_memalign(&ws, 64, size) != 0 || psc_patch_init(&p, m, &lim, ws, size) != PSC_OK)
        goto done;
    psc_vec3_q16_t lo = {m->lo_q16[0], m->lo_q16[1], m->lo_q16[2]}, hi = {m->hi_q16[0], m->hi_q16[1], m->hi_q16[2]};
    psc_patch_camera_t cam = {0};
    int32_t near_q16, far_q16;
    if (psc_3d_orbit(lo, hi, PSC_BAM_FROM_MDEG(200000), PSC_BAM_FROM_MDEG(10000), 5 * PSC_Q16_ONE / 2,
                     &cam.camera_from_object, &near_q16, &far_q16) != PSC_OK)
        goto done;
    cam.focal_px_q16 = (int32_t)lround(400.0 / tan(R3D_HFOV_DEG * 3.14159265358979323846 / 360.0) * 65536.0);
    cam.tol_px_q16 = PSC_Q16_ONE / 2;
    cam.near_q16 = near_q16;
    cam.cull = false;
    psc_patch_pose_begin(&p, thom_action(m, "Wave"), THOM_TIME_MS);
    psc_patch_pose_finish(&p);
    psc_patch_tangents(&p);
    if (psc_patch_tessellate(&p, &cam, NULL) != PSC_OK || batches_to_model(&p, out) != 0)
        goto done;
    rc = 0;
done:
    if (rc != 0)
        fprintf(stderr, "render3d bench: %s could not be tessellated\n", THOM_DIR "/Thom.mdl");
    free(ws);
    psc_io_patch_free(&pf);
    return rc;
}
