/* SPDX-License-Identifier: MIT */
/*
 * fuzz_proxy.c - proxy packs (.ppx, core/proxy/psc_proxy.h: parts, joints,
 * view textures, billboard) as the proxy scene loads them: the input,
 * 64-byte aligned and with its container CRC made right, through
 * psc_proxy_parse; a refusal must give a message that io's loader formats
 * naming the file. A pack that parses must keep its counts within the
 * documented limits and be drawn by the device's proxy scene
 * (psc_scene_proxy_draw: psc_proxy_init, the level of detail, the pose at a
 * time chosen from the input, the frame) on a small output, at two views.
 */
#include <stdlib.h>

#include "fuzz_support.h"
#include "psc_io_load.h"
#include "scene/scene_object.h"
#include "scene/scene_proxy.h"

#define NAME "fuzz.ppx"
enum { OUT_W = 32, OUT_H = 24 };

static void check_parsed(const psc_proxy_model_t *m)
{
    FUZZ_REQUIRE(m->joint_count <= PSC_PROXY_MAX_JOINTS && m->part_count <= PSC_PROXY_MAX_PARTS);
    FUZZ_REQUIRE(m->vertex_count <= PSC_PROXY_MAX_VERTICES && m->triangle_count <= PSC_PROXY_MAX_TRIANGLES);
    FUZZ_REQUIRE(m->proxy_vertex_count <= PSC_PROXY_MAX_PROXY_VERTICES);
    FUZZ_REQUIRE(m->proxy_triangle_count <= PSC_PROXY_MAX_PROXY_TRIANGLES);
    for (uint32_t j = 0; m->node && j < m->joint_count; j++)
        FUZZ_REQUIRE(m->node[j] >= -1 && m->node[j] <= PSC_PROXY_MAX_NODE);
    FUZZ_REQUIRE(m->frame_count <= PSC_PROXY_MAX_FRAMES);
}

static void draw_parsed(const psc_proxy_model_t *m, uint32_t pick)
{
    static uint32_t out[OUT_W * OUT_H];
    psc_scene3d_look_t look = psc_scene3d_look(NULL);
    look.tile = (pick & 1u) ? 16 : 0;
    size_t ws_size = psc_scene_proxy_workspace_size(m, OUT_W, OUT_H, &look);
    if (ws_size == 0)
        return; /* the scene refuses it at start-up */
    void *ws = NULL;
    FUZZ_REQUIRE(posix_memalign(&ws, 64, ws_size) == 0);
    psc_surface_t o = {OUT_W, OUT_H, OUT_W * 4, PSC_PIX_XRGB8888, out};
    psc_view_t view = {
        .yaw = pick * 2654435761u,
        .pitch = (int32_t)((pick >> 4) % (2u * (uint32_t)PSC_OBJECT_PITCH_LIMIT + 1u)) - PSC_OBJECT_PITCH_LIMIT,
        .hfov = PSC_OBJECT_HFOV_MIN + (pick >> 8) % (PSC_OBJECT_HFOV_MAX - PSC_OBJECT_HFOV_MIN + 1u),
    };
    /* near (the full mesh or the proxies), then zoomed far out (proxies or the billboard) */
    if (psc_scene_proxy_draw(m, (pick >> 12) * 997u, &view, true, ws, ws_size, &o, NULL, &look) == PSC_OK) {
        view.hfov = PSC_OBJECT_HFOV_MAX;
        (void)psc_scene_proxy_draw(m, (pick >> 12) * 1999u, &view, false, ws, ws_size, &o, NULL, &look);
    }
    free(ws);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *buf = fuzz_aligned_copy(data, size);
    psc_proxy_model_t model;
    psc_container_error_t e = {NULL, 0};

    fuzz_fix_container_crc(buf, size);
    psc_status_t s = psc_proxy_parse(buf, size, &model, &e);
    if (s == PSC_OK) {
        check_parsed(&model);
        draw_parsed(&model, fuzz_hash(data, size));
    } else {
        char err[512];
        FUZZ_REQUIRE(s > PSC_OK && s <= PSC_ERR_UNSUPPORTED && e.what != NULL);
        FUZZ_REQUIRE(psc_io_container_errorf(err, sizeof err, NAME, "not a usable proxy pack: ", s, &e) == -1);
        fuzz_require_message_names(err, NAME);
    }
    free(buf);
    return 0;
}
