/* SPDX-License-Identifier: MIT */
/*
 * fuzz_shadow.c - shadow packs (.pao, core/shadow/psc_shadow.h: the sphere
 * tree and its occlusion tables) as the character scene loads them: the
 * input, 64-byte aligned and with its container CRC made right, through
 * psc_shadow_parse; a refusal must give a message that io's loader
 * formats naming the file. A pack that parses must keep its counts within
 * the documented limits, levels in increasing order ending at the sphere
 * count, and be used as the shading uses it (psc_shadow_init_mesh, as for a
 * mesh with the pack's own bone count; the character scene's psc_shadow_init
 * differs only in taking the bone count from the patch pack): the spheres
 * posed (identity skins), occlusions at a few points within 0..1 (Q16);
 * a rest correction (SREF) within its count and gain limits, and applied to
 * a mesh of as many vertices (when small) with every occlusion within 0..1;
 * a correction through each action (SRPH) only beside SREF, within its
 * limits and of SREF's count; a patch grid correction (SGRD) never beside
 * SREF, within its limits, and refused for a mesh.
 */
#include <stdlib.h>

#include "3d/psc_3d_math.h"
#include "fuzz_support.h"
#include "psc_io_load.h"
#include "shadow/psc_shadow_frame.h"

#define NAME "fuzz.pao"

static void check_parsed(const psc_shadow_model_t *m)
{
    FUZZ_REQUIRE(m->sphere_count >= 1 && m->sphere_count <= PSC_SHADOW_MAX_SPHERES);
    FUZZ_REQUIRE(m->level_count >= 1 && m->level_count <= PSC_SHADOW_MAX_LEVELS);
    FUZZ_REQUIRE(m->level_first[m->level_count] == m->sphere_count);
    for (uint32_t l = 0; l < m->level_count; l++)
        FUZZ_REQUIRE(m->level_first[l] < m->level_first[l + 1]);
    FUZZ_REQUIRE(m->access_omega <= PSC_SHADOW_MAX_TABLE && m->access_theta <= PSC_SHADOW_MAX_TABLE);
    FUZZ_REQUIRE(m->comp_theta <= PSC_SHADOW_MAX_TABLE && m->comp_delta <= PSC_SHADOW_MAX_TABLE);
    if (m->rest_count) {
        FUZZ_REQUIRE(m->rest_count <= PSC_SHADOW_MAX_REST && m->rest_q15 != NULL);
        FUZZ_REQUIRE(m->rest_gain_q16 >= PSC_SHADOW_REST_GAIN_MIN_Q16 &&
                     m->rest_gain_q16 <= PSC_SHADOW_REST_GAIN_MAX_Q16);
    }
    if (m->phase_q15) {
        FUZZ_REQUIRE(m->rest_count != 0);
        FUZZ_REQUIRE(m->phase_actions >= 1 && m->phase_actions <= PSC_SHADOW_MAX_PHASE_ACTIONS);
        FUZZ_REQUIRE(m->phase_samples >= 1 && m->phase_samples <= PSC_SHADOW_MAX_PHASES);
    } else {
        FUZZ_REQUIRE(m->phase_actions == 0);
    }
    if (m->grid_q15) {
        FUZZ_REQUIRE(m->rest_count == 0);
        FUZZ_REQUIRE(m->grid_quads >= 1 && m->grid_quads <= PSC_SHADOW_MAX_GRID_QUADS);
        FUZZ_REQUIRE(m->grid_side >= 2 && m->grid_side <= PSC_SHADOW_MAX_GRID_SIDE);
    } else {
        FUZZ_REQUIRE(m->grid_quads == 0);
    }
}

/* The rest correction at work: a mesh of the correction's vertex count (all on one spot with one normal), each
 * vertex's occlusion within 0..1 whatever the correction and the gain. */
static void use_rest(psc_shadow_t *s, uint32_t count, uint32_t pick)
{
    if (count == 0 || count > 4096u)
        return;
    int32_t *pos = calloc(3u * count, sizeof *pos);
    int16_t *nrm = calloc(3u * count, sizeof *nrm);
    uint32_t *col = calloc(count, sizeof *col), *occ = calloc(count, sizeof *occ);
    FUZZ_REQUIRE(pos && nrm && col && occ);
    for (uint32_t i = 0; i < count; i++) {
        pos[3 * i] = (int32_t)(pick & 0xFFFFu) - 0x8000;
        nrm[3 * i + 1] = 16384;
        col[i] = 0xFFFFFFu;
    }
    psc_shadow_apply_mesh(s, pos, nrm, col, count, PSC_SHADOW_STRENGTH_Q16, occ);
    for (uint32_t i = 0; i < count; i++)
        FUZZ_REQUIRE(occ[i] <= 65536u);
    free(pos), free(nrm), free(col), free(occ);
}

static void use_parsed(const psc_shadow_model_t *m, uint32_t pick)
{
    size_t ws_size = psc_shadow_workspace_size(m, NULL);
    void *ws = NULL;
    psc_mat4_q16_t *skin = calloc(m->bone_count ? m->bone_count : 1, sizeof *skin);
    psc_shadow_t s;

    FUZZ_REQUIRE(skin != NULL && posix_memalign(&ws, 64, ws_size ? ws_size : 8) == 0);
    psc_status_t st = psc_shadow_init_mesh(&s, m, m->bone_count, ws, ws_size);
    FUZZ_REQUIRE(m->grid_quads == 0 || st == PSC_ERR_ARG);   /* a patch grid is a patch character's */
    if (st == PSC_OK) {
        for (uint32_t b = 0; b < m->bone_count; b++)
            psc_mat4_identity(&skin[b]);
        psc_shadow_update_bones(&s, skin, m->bone_count);
        static const int32_t normals[3][3] = {{0, 65536, 0}, {65536, 0, 0}, {0, 0, -65536}};
        for (unsigned k = 0; k < 3; k++) {
            int32_t pos[3] = {(int32_t)(pick & 0x3FFFFu) - 0x20000, (int32_t)((pick >> 7) & 0x3FFFFu) - 0x20000,
                              (int32_t)((pick >> 14) & 0x3FFFFu) - 0x20000};
            int32_t bent[3];
            FUZZ_REQUIRE(psc_shadow_occlusion(&s, pos, normals[k]) <= 65536u);
            FUZZ_REQUIRE(psc_shadow_occlusion_bent(&s, pos, normals[k], bent) <= 65536u);
            pick = pick * 2654435761u + 1u;
        }
        use_rest(&s, m->rest_count, pick);
    }
    free(skin);
    free(ws);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *buf = fuzz_aligned_copy(data, size);
    psc_shadow_model_t model;
    psc_container_error_t e = {NULL, 0};

    fuzz_fix_container_crc(buf, size);
    psc_status_t s = psc_shadow_parse(buf, size, &model, &e);
    if (s == PSC_OK) {
        check_parsed(&model);
        use_parsed(&model, fuzz_hash(data, size));
    } else {
        char err[512];
        FUZZ_REQUIRE(s > PSC_OK && s <= PSC_ERR_UNSUPPORTED && e.what != NULL);
        FUZZ_REQUIRE(psc_io_container_errorf(err, sizeof err, NAME, "not a usable shadow pack: ", s, &e) == -1);
        fuzz_require_message_names(err, NAME);
    }
    free(buf);
    return 0;
}
