/* object_scene.c - the "object" scene type (object_scene.h). */
#include "object_scene.h"
#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_render.h"

static psc_3d_config_t object_config(const psc_mesh_t *m, uint16_t width, uint16_t height, psc_bam_t hfov)
{
    /* near/far are set per view by the orbit; these placeholders only size the workspace. */
    psc_3d_config_t c = {width, height, 0, 0, 16, hfov, PSC_Q16_ONE, 4 * PSC_Q16_ONE, m->vertex_count};
    return c;
}

size_t psc_object_scene_workspace_size(const psc_mesh_t *m, uint16_t width, uint16_t height)
{
    psc_3d_config_t c = object_config(m, width, height, PSC_OBJECT_DEFAULT_HFOV);
    return psc_3d_workspace_size(&c);
}

psc_status_t psc_object_scene_render(const psc_mesh_t *m, const psc_view_t *view, void *ws, size_t ws_size,
                                     const psc_surface_t *out)
{
    psc_3d_config_t c = object_config(m, out->width, out->height, view->hfov);
    psc_3d_draw_t d;
    psc_vec3_q16_t lo, hi;
    psc_3d_t r;
    psc_status_t s;
    uint32_t bg = PSC_OBJECT_BACKGROUND;

    psc_3d_draw_defaults(&d, m);
    psc_mesh_bounds_q16(m, &lo, &hi);
    s = psc_3d_orbit(lo, hi, view->yaw, view->pitch, PSC_OBJECT_ORBIT_DIST_Q16, &d.camera_from_object, &c.near_q16,
                     &c.far_q16);
    if (s != PSC_OK)
        return s;
    if ((s = psc_3d_init(&r, &c, ws, ws_size)) != PSC_OK)
        return s;
    d.shade = m->has_texture ? PSC_SHADE_TEXTURE : PSC_SHADE_GOURAUD;
    d.filter = view->filter == PSC_FILTER_NEAREST ? PSC_TEX_NEAREST : PSC_TEX_BILINEAR;
    d.lit = m->normal_q14 != NULL;
    d.light_dir = psc_vec3_normalize((psc_vec3_q16_t){-26000, 39000, -45000});
    d.ambient_q8 = 72;
    return psc_3d_render(&r, &d, 1, &bg, out, NULL);
}
