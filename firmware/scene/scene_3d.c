/* SPDX-License-Identifier: MIT */
/* scene_3d.c - tiles and the A-buffer of the 3D scenes (scene_3d.h). */
#include "scene/scene_3d.h"

static size_t align8(size_t v)
{
    return (v + 7u) & ~(size_t)7u;
}

psc_scene3d_look_t psc_scene3d_look(const psc_board_config_t *b)
{
    psc_scene3d_look_t l = {0, 0};
    if (b) {
        l.tile = (uint16_t)b->render3d_tile;
        l.abuffer_bytes = (size_t)b->render3d_abuffer_kb * 1024u;
    }
    return l;
}

void psc_scene3d_tiles(psc_3d_config_t *c, const psc_scene3d_look_t *look)
{
    uint16_t t = look ? look->tile : 0;
    c->tile_width = c->tile_height = t;
}

size_t psc_scene3d_workspace_size(const psc_3d_config_t *c, const psc_scene3d_look_t *look)
{
    size_t a = psc_3d_workspace_size(c);
    return a ? align8(a) + (look ? align8(look->abuffer_bytes) : 0) : 0;
}

psc_status_t psc_scene3d_init(psc_3d_t *r, const psc_3d_config_t *c, const psc_scene3d_look_t *look, void *ws,
                              size_t ws_size)
{
    size_t a = align8(psc_3d_workspace_size(c)), need = psc_scene3d_workspace_size(c, look);
    psc_status_t s;
    if (need == 0 || ws_size < need)
        return PSC_ERR_NOMEM;
    if ((s = psc_3d_init(r, c, ws, a)) != PSC_OK)
        return s;
    if (look && look->abuffer_bytes)
        return psc_3d_set_abuffer(r, (uint8_t *)ws + a, look->abuffer_bytes);
    return PSC_OK;
}
