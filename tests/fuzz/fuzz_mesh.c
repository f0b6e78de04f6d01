/* SPDX-License-Identifier: MIT */
/*
 * fuzz_mesh.c - mesh packs (.pmesh, core/mesh/psc_mesh.h) as the object
 * scene loads them: the input, 64-byte aligned and with its container CRC
 * made right, through io's psc_io_mesh_parse_named; a refusal must name the
 * file. A mesh that parses must keep its counts within the documented limits,
 * every index below the vertex count and its arrays inside the input, and be
 * drawn by the device's object scene (psc_scene_object_draw: orbit, tiles or
 * not, A-buffer or not, as chosen from the input) on a small output.
 */
#include <stdlib.h>

#include "fuzz_support.h"
#include "psc_io_load.h"
#include "scene/scene_object.h"

#define NAME "fuzz.pmesh"
enum { OUT_W = 32, OUT_H = 24 };

static void check_inside(const uint8_t *buf, size_t len, const void *p, size_t bytes)
{
    const uint8_t *b = p;
    FUZZ_REQUIRE(b >= buf && b <= buf + len && (size_t)(buf + len - b) >= bytes);
}

static void check_parsed(const uint8_t *buf, size_t len, const psc_mesh_t *m)
{
    FUZZ_REQUIRE(m->vertex_count >= 1 && m->vertex_count <= PSC_MESH_MAX_VERTICES);
    FUZZ_REQUIRE(m->triangle_count >= 1 && m->triangle_count <= PSC_MESH_MAX_TRIANGLES);
    FUZZ_REQUIRE(m->position_q15 != NULL && m->index != NULL);
    check_inside(buf, len, m->position_q15, (size_t)m->vertex_count * 6u);
    check_inside(buf, len, m->index, (size_t)m->triangle_count * 6u);
    for (size_t i = 0; i < (size_t)m->triangle_count * 3u; i++)
        FUZZ_REQUIRE(m->index[i] < m->vertex_count);
    if (m->normal_q14)
        check_inside(buf, len, m->normal_q14, (size_t)m->vertex_count * 6u);
    if (m->uv_q12)
        check_inside(buf, len, m->uv_q12, (size_t)m->vertex_count * 4u);
    if (m->color)
        check_inside(buf, len, m->color, (size_t)m->vertex_count * 4u);
    FUZZ_REQUIRE(m->opacity_groups <= PSC_MESH_MAX_OPACITY_GROUPS);
    for (uint32_t k = 0, first = 0; k < m->opacity_groups; first += m->opacity[k++].count) {
        FUZZ_REQUIRE(m->opacity[k].first == first && m->opacity[k].count >= 1);
        FUZZ_REQUIRE(m->opacity[k].opacity_q8 >= 1 && m->opacity[k].opacity_q8 <= 256);
        FUZZ_REQUIRE(k + 1u < m->opacity_groups || first + m->opacity[k].count == m->triangle_count);
    }
    if (m->has_texture) {
        FUZZ_REQUIRE(m->uv_q12 != NULL);
        check_inside(buf, len, m->texture.pixels, (size_t)m->texture.stride * m->texture.height);
    }
}

/* One frame of the object scene: whatever parses is safe to draw. */
static void draw_parsed(const psc_mesh_t *m, uint32_t pick)
{
    static uint32_t out[OUT_W * OUT_H];
    psc_scene3d_look_t look = psc_scene3d_look(NULL);
    look.tile = (pick & 1u) ? 16 : 0;
    look.abuffer_bytes = (pick & 2u) ? 16384 : 0;
    psc_view_t view = {
        .yaw = pick * 2654435761u,
        .pitch = (int32_t)((pick >> 4) % (2u * (uint32_t)PSC_OBJECT_PITCH_LIMIT + 1u)) - PSC_OBJECT_PITCH_LIMIT,
        .hfov = PSC_OBJECT_HFOV_MIN + (pick >> 8) % (PSC_OBJECT_HFOV_MAX - PSC_OBJECT_HFOV_MIN + 1u),
        .filter = (psc_filter_t)((pick >> 2) % 3u),
    };
    size_t ws_size = psc_scene_object_workspace_size(m, OUT_W, OUT_H, &look);
    void *ws = NULL;

    FUZZ_REQUIRE(ws_size > 0 && posix_memalign(&ws, 64, ws_size) == 0);
    psc_surface_t o = {OUT_W, OUT_H, OUT_W * 4, PSC_PIX_XRGB8888, out};
    (void)psc_scene_object_draw(m, &view, ws, ws_size, &o, &look);
    free(ws);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *buf = fuzz_aligned_copy(data, size);
    psc_mesh_t mesh;
    char err[512] = "";

    fuzz_fix_container_crc(buf, size);
    if (psc_io_mesh_parse_named(NAME, buf, size, &mesh, err, sizeof err) == 0) {
        check_parsed(buf, size, &mesh);
        draw_parsed(&mesh, fuzz_hash(data, size));
    } else {
        fuzz_require_message_names(err, NAME);
    }
    free(buf);
    return 0;
}
