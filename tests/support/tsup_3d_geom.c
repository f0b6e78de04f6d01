/* SPDX-License-Identifier: MIT */
/* tsup_3d_geom.c - generated meshes, test meshes, textures and cameras (tsup_3d.h). */
#include "tsup_3d.h"
#include "psc_testsupport.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void *xcalloc(size_t n, size_t size)
{
    void *p = calloc(n ? n : 1, size);
    if (!p)
        abort();
    return p;
}

/* ---- meshes ------------------------------------------------------------------- */

void tsup_shape_make(tsup_shape_t s, psc_model_t *g)
{
    switch (s) {
    case TSUP_CUBE: psc_model_cube(g, 1.0); break;
    case TSUP_SPHERE: psc_model_sphere(g, 1.0, 40, 21); break;
    case TSUP_TORUS: psc_model_torus(g, 1.0, 0.4, 48, 20); break;
    case TSUP_TEAPOT: psc_model_teapot(g, 8); break;
    }
}

static int16_t round16(double v)
{
    double r = floor(v + 0.5);
    return (int16_t)(r > 32767 ? 32767 : r < -32768 ? -32768 : r);
}

int tsup_mesh_from_geom(tsup_mesh_t *m, const psc_model_t *g, int normalise)
{
    memset(m, 0, sizeof *m);
    if (g->vertex_count == 0 || g->vertex_count > PSC_MESH_MAX_VERTICES)
        return -1;
    uint32_t nv = g->vertex_count, nt = g->triangle_count;
    psc_mesh_t *o = &m->mesh;
    o->vertex_count = nv;
    o->triangle_count = nt;
    o->base_color = 0xC0C0C0;
    if (normalise) {
        double lo[3], hi[3];
        for (int a = 0; a < 3; a++)
            lo[a] = hi[a] = g->pos[a];
        for (uint32_t v = 0; v < nv; v++)
            for (int a = 0; a < 3; a++) {
                lo[a] = fmin(lo[a], g->pos[3 * v + a]);
                hi[a] = fmax(hi[a], g->pos[3 * v + a]);
            }
        double half = 0;
        for (int a = 0; a < 3; a++)
            half = fmax(half, (hi[a] - lo[a]) / 2);
        double s = half > 0 ? 32767.0 / half : 1.0;
        m->pos_q15 = xcalloc((size_t)nv * 3, sizeof(int16_t));
        for (int a = 0; a < 3; a++) {
            o->bbox_min_q15[a] = 32767;
            o->bbox_max_q15[a] = -32768;
        }
        for (uint32_t v = 0; v < nv; v++)
            for (int a = 0; a < 3; a++) {
                int16_t q = round16((g->pos[3 * v + a] - (lo[a] + hi[a]) / 2) * s);
                m->pos_q15[3 * v + a] = q;
                if (q < o->bbox_min_q15[a])
                    o->bbox_min_q15[a] = q;
                if (q > o->bbox_max_q15[a])
                    o->bbox_max_q15[a] = q;
            }
        o->position_q15 = m->pos_q15;
    } else {
        m->pos_q16 = xcalloc((size_t)nv * 3, sizeof(int32_t));
        for (size_t i = 0; i < (size_t)nv * 3; i++)
            m->pos_q16[i] = (int32_t)llround(g->pos[i] * 65536.0);
        o->position_q16 = m->pos_q16;
    }
    if (g->normal) {
        m->normal_q14 = xcalloc((size_t)nv * 3, sizeof(int16_t));
        for (size_t i = 0; i < (size_t)nv * 3; i++)
            m->normal_q14[i] = round16(g->normal[i] * 16384.0);
        o->normal_q14 = m->normal_q14;
    }
    if (g->uv) {
        m->uv_q12 = xcalloc((size_t)nv * 2, sizeof(int16_t));
        for (size_t i = 0; i < (size_t)nv * 2; i++)
            m->uv_q12[i] = round16(g->uv[i] * 4096.0);
        o->uv_q12 = m->uv_q12;
    }
    if (g->color) {
        m->color = xcalloc(nv, sizeof(uint32_t));
        memcpy(m->color, g->color, (size_t)nv * 4);
        o->color = m->color;
    }
    m->index = xcalloc((size_t)nt * 3, sizeof(uint16_t));
    for (size_t i = 0; i < (size_t)nt * 3; i++)
        m->index[i] = (uint16_t)g->index[i];
    o->index = m->index;
    return 0;
}

void tsup_mesh_free(tsup_mesh_t *m)
{
    free(m->pos_q15);
    free(m->pos_q16);
    free(m->normal_q14);
    free(m->uv_q12);
    free(m->color);
    free(m->index);
    memset(m, 0, sizeof *m);
}

void tsup_orbit_matrix(psc_mat4_q16_t *m, double yaw_deg, double pitch_deg, double dist)
{
    double y = yaw_deg * TSUP_DEG, p = pitch_deg * TSUP_DEG;
    double dir[3] = {sin(y) * cos(p), sin(p), cos(y) * cos(p)};
    psc_vec3_q16_t eye = {(int32_t)llround(-dist * dir[0] * 65536.0), (int32_t)llround(-dist * dir[1] * 65536.0),
                          (int32_t)llround(-dist * dir[2] * 65536.0)};
    psc_mat4_camera(m, eye, tsup_bam_from_deg(yaw_deg), (int32_t)tsup_bam_from_deg(pitch_deg));
}

/* ---- textures and surfaces ------------------------------------------------------- */

int tsup_texture_make(tsup_texture_t *t, uint16_t w, uint16_t h, psc_pixfmt_t fmt)
{
    uint32_t bpp = psc_pixfmt_bytes(fmt);
    t->pixels = xcalloc((size_t)w * h, bpp);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            uint32_t check = ((x * 8 / w) + (y * 8 / h)) & 1u;
            uint32_t r = (x * 255u) / (w > 1 ? w - 1u : 1u), g = (y * 255u) / (h > 1 ? h - 1u : 1u);
            uint32_t b = check ? 230u : 40u;
            uint32_t c = (r << 16) | (g << 8) | b;
            if (fmt == PSC_PIX_RGB565)
                ((uint16_t *)t->pixels)[(size_t)y * w + x] = tsup_rgb888_to_rgb565(r, g, b);
            else
                ((uint32_t *)t->pixels)[(size_t)y * w + x] = 0xFF000000u | c;
        }
    return psc_texture_init(&t->tex, w, h, fmt, (uint32_t)w * bpp, t->pixels) == PSC_OK ? 0 : -1;
}

void tsup_texture_free(tsup_texture_t *t)
{
    free(t->pixels);
    memset(t, 0, sizeof *t);
}

psc_surface_t tsup_surface_new(uint16_t w, uint16_t h, psc_pixfmt_t fmt)
{
    psc_surface_t s = {w, h, (uint32_t)w * psc_pixfmt_bytes(fmt), fmt, NULL};
    s.pixels = xcalloc((size_t)s.stride * h, 1);
    return s;
}

void tsup_surface_free(psc_surface_t *s)
{
    free(s->pixels);
    s->pixels = NULL;
}

psc_status_t tsup_3d_init(tsup_3d_t *t, const psc_3d_config_t *cfg)
{
    size_t n = psc_3d_workspace_size(cfg);
    t->ws = NULL;
    if (n == 0)
        return PSC_ERR_ARG;
    if (posix_memalign(&t->ws, 64, n) != 0)
        return PSC_ERR_NOMEM;
    memset(t->ws, 0x5A, n); /* garbage: init and render must not rely on zeroes */
    psc_status_t s = psc_3d_init(&t->r, cfg, t->ws, n);
    if (s != PSC_OK) {
        free(t->ws);
        t->ws = NULL;
    }
    return s;
}

void tsup_3d_free(tsup_3d_t *t)
{
    free(t->ws);
    t->ws = NULL;
}
