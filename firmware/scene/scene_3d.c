/* SPDX-License-Identifier: MIT */
/* scene_3d.c - tiles, hidden surfaces and the A-buffer of the 3D scenes (scene_3d.h). */
#include "scene/scene_3d.h"
#include "base/psc_fixed.h"

static size_t align8(size_t v)
{
    return (v + 7u) & ~(size_t)7u;
}

psc_scene3d_look_t psc_scene3d_look(const psc_board_config_t *b)
{
    psc_scene3d_look_t l = {0};
    l.soft_edges = true;
    if (b) {
        l.tile = (uint16_t)b->render3d_tile;
        l.hsr = b->render3d_hsr;
        l.abuffer_bytes = (size_t)b->render3d_abuffer_kb * 1024u;
        l.soft_edges = b->render3d_soft_edges;
        l.relight = b->render3d_relight;
        l.light_azimuth_mdeg = b->render3d_light_azimuth_mdeg;
        l.light_elevation_mdeg = b->render3d_light_elevation_mdeg;
        l.light_turn_mdeg = b->render3d_light_turn_mdeg;
        l.light_ambient_q14 = (uint16_t)((b->render3d_light_ambient_milli * 16384u + 500u) / 1000u);
    }
    return l;
}

void psc_scene3d_light_at(const psc_scene3d_look_t *look, uint64_t t_us, int32_t toward_q16[3])
{
    /* the azimuth in millidegrees, turned and wrapped into one turn: time wraps every 360 000 s, after which a
     * whole number of millidegrees a second has turned a whole number of turns (no jump) */
    int64_t s = (int64_t)((t_us / 1000u) % 360000000u);   /* milliseconds */
    int64_t az = ((int64_t)look->light_azimuth_mdeg + look->light_turn_mdeg * s / 1000) % 360000;
    int32_t sa, ca, se, ce;
    psc_sincos(PSC_BAM_FROM_MDEG(az), &sa, &ca);
    psc_sincos(PSC_BAM_FROM_MDEG((int64_t)look->light_elevation_mdeg), &se, &ce);
    toward_q16[0] = (int32_t)psc_shr_round64((int64_t)ce * sa, 44);   /* Q30 x Q30 -> Q16 */
    toward_q16[1] = psc_shr_round32(se, 14);
    toward_q16[2] = (int32_t)psc_shr_round64((int64_t)ce * ca, 44);
}

void psc_scene3d_method(psc_3d_config_t *c, const psc_scene3d_look_t *look)
{
    uint16_t t = look ? look->tile : 0;
    c->tile_width = c->tile_height = t;
    c->hsr = look ? look->hsr : PSC_3D_HSR_ZBUFFER;
    if (look && look->pool)
        psc_io_render3d_config(c, psc_io_bands_threads(look->pool), look->abuffer_bytes != 0);
}

/* The other threads' workers (none without a pool). */
static size_t threads_bytes(const psc_3d_config_t *c, const psc_scene3d_look_t *look)
{
    return look && look->pool ? align8(psc_io_render3d_bytes(look->pool, c, look->abuffer_bytes)) : 0;
}

size_t psc_scene3d_workspace_size(const psc_3d_config_t *c, const psc_scene3d_look_t *look)
{
    size_t a = psc_3d_workspace_size(c);
    return a ? align8(a) + (look ? align8(look->abuffer_bytes) : 0) + threads_bytes(c, look) : 0;
}

psc_status_t psc_scene3d_init(psc_3d_t *r, const psc_3d_config_t *c, const psc_scene3d_look_t *look, void *ws,
                              size_t ws_size, psc_io_render3d_t **threads)
{
    size_t a = align8(psc_3d_workspace_size(c)), need = psc_scene3d_workspace_size(c, look);
    size_t ab = look ? align8(look->abuffer_bytes) : 0;
    psc_status_t s;
    *threads = NULL;
    if (need == 0 || ws_size < need)
        return PSC_ERR_NOMEM;
    if ((s = psc_3d_init(r, c, ws, a)) != PSC_OK)
        return s;
    psc_3d_set_soft_silhouettes(r, !look || look->soft_edges);
    if (look && look->abuffer_bytes && (s = psc_3d_set_abuffer(r, (uint8_t *)ws + a, look->abuffer_bytes)) != PSC_OK)
        return s;
    if (look && look->pool &&
        !(*threads = psc_io_render3d_init((uint8_t *)ws + a + ab, threads_bytes(c, look), look->pool, c,
                                          look->abuffer_bytes)))
        return PSC_ERR_NOMEM;
    return PSC_OK;
}
