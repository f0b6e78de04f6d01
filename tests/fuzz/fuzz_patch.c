/* SPDX-License-Identifier: MIT */
/*
 * fuzz_patch.c - patch packs (.ppk, core/patch/psc_patch.h: Hash patches,
 * bones, actions) as the character scene loads them: the input, 64-byte
 * aligned and with its container CRC made right, through io's
 * psc_io_patch_parse_named; a refusal must name the file. A pack that parses
 * must keep every count within its documented limit, and be drawn by the
 * device's character scene (psc_scene_character_draw: workspace, init, pose
 * at an action and time chosen from the input, tangents, tessellation,
 * draws) on a small output, twice: the first frame and a later one.
 */
#include <stdlib.h>

#include "fuzz_support.h"
#include "psc_io_load.h"
#include "scene/scene_character.h"
#include "scene/scene_object.h"

#define NAME "fuzz.ppk"
enum { OUT_W = 32, OUT_H = 24 };

static void check_parsed(const psc_patch_model_t *m)
{
    FUZZ_REQUIRE(m->point_count <= PSC_PATCH_MAX_POINTS && m->cp_count <= PSC_PATCH_MAX_CPS);
    FUZZ_REQUIRE(m->spline_count <= PSC_PATCH_MAX_SPLINES && m->edge_count <= PSC_PATCH_MAX_EDGES);
    FUZZ_REQUIRE(m->face_count <= PSC_PATCH_MAX_FACES && m->color_count <= PSC_PATCH_MAX_COLORS);
    FUZZ_REQUIRE(m->bone_count <= PSC_PATCH_MAX_BONES && m->action_count <= PSC_PATCH_MAX_ACTIONS);
    FUZZ_REQUIRE(m->channel_count <= PSC_PATCH_MAX_CHANNELS && m->key_count <= PSC_PATCH_MAX_KEYS);
    for (uint32_t i = 0; i < m->face_count; i++)
        FUZZ_REQUIRE(m->faces[i].sides >= 3 && m->faces[i].sides <= PSC_PATCH_MAX_SIDES);
}

static void draw_parsed(const psc_patch_model_t *m, uint32_t pick)
{
    static uint32_t out[OUT_W * OUT_H];
    psc_scene3d_look_t look = psc_scene3d_look(NULL);
    look.tile = (pick & 1u) ? 16 : 0;
    size_t ws_size = psc_scene_character_workspace_size(m, NULL, OUT_W, OUT_H, &look);
    if (ws_size == 0)
        return; /* the scene refuses it at start-up */
    void *ws = NULL;
    FUZZ_REQUIRE(posix_memalign(&ws, 64, ws_size) == 0);
    psc_surface_t o = {OUT_W, OUT_H, OUT_W * 4, PSC_PIX_XRGB8888, out};
    int action = m->action_count ? (int)((pick >> 1) % (m->action_count + 1u)) - 1 : -1;
    psc_view_t view = {
        .yaw = pick * 2654435761u,
        .pitch = (int32_t)((pick >> 4) % (2u * (uint32_t)PSC_OBJECT_PITCH_LIMIT + 1u)) - PSC_OBJECT_PITCH_LIMIT,
        .hfov = PSC_OBJECT_HFOV_MIN + (pick >> 8) % (PSC_OBJECT_HFOV_MAX - PSC_OBJECT_HFOV_MIN + 1u),
    };
    if (psc_scene_character_draw(m, NULL, action, 0, &view, true, ws, ws_size, &o, NULL, &look) == PSC_OK)
        (void)psc_scene_character_draw(m, NULL, action, (pick >> 12) % 10000u, &view, false, ws, ws_size, &o, NULL,
                                       &look);
    free(ws);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *buf = fuzz_aligned_copy(data, size);
    psc_patch_model_t model;
    char err[512] = "";

    fuzz_fix_container_crc(buf, size);
    if (psc_io_patch_parse_named(NAME, buf, size, &model, err, sizeof err) == 0) {
        check_parsed(&model);
        draw_parsed(&model, fuzz_hash(data, size));
    } else {
        fuzz_require_message_names(err, NAME);
    }
    free(buf);
    return 0;
}
