/* SPDX-License-Identifier: MIT */
/*
 * scene.c - the benchmark scenes (a textured, lit Utah teapot of 10816
 * triangles; Thom's tessellated mesh, thom.c), as the device would load them
 * from a mesh pack, and the timed Periscope runs.
 */
#include "render3d.h"
#include "common/bench_time.h"
#include "bake/mesh_pack.h"
#include "import/model.h"
#include "3d/psc_3d_orbit.h"
#include "psc_io_load.h"
#include "psc_io_render3d.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* R3D_BLOCKS_COUNT boxes of many sizes in a loose stack (a fixed pseudo-random layout), each its own colour: large
 * faces that cover one another, few triangles. */
static void blocks_model(psc_model_t *out)
{
    psc_model_t box;
    psc_model_cube(&box, 1.0);
    uint32_t nv = box.vertex_count, nt = box.triangle_count, n = R3D_BLOCKS_COUNT;
    *out = (psc_model_t){malloc(sizeof(double) * 3 * nv * n), box.normal ? malloc(sizeof(double) * 3 * nv * n) : NULL,
                         NULL, malloc(sizeof(uint32_t) * nv * n), malloc(sizeof(uint32_t) * 3 * nt * n), nv * n, nt * n,
                         NULL, NULL};
    uint32_t seed = 12345u;
    for (uint32_t b = 0; b < n; b++) {
        double r[6];
        for (int k = 0; k < 6; k++) {
            seed = seed * 1664525u + 1013904223u;
            r[k] = (seed >> 8) / 16777216.0;
        }
        double size[3] = {0.15 + 0.5 * r[0], 0.15 + 0.5 * r[1], 0.15 + 0.5 * r[2]};
        double at[3] = {r[3] * 2 - 1, r[4] * 1.2 - 0.6, r[5] * 2 - 1};
        uint32_t color = 0x404040u + ((seed >> 4) & 0x9F9F9Fu);
        for (uint32_t v = 0; v < nv; v++) {
            for (int k = 0; k < 3; k++) {
                out->pos[3 * (b * nv + v) + k] = at[k] + box.pos[3 * v + k] * size[k];
                if (out->normal)
                    out->normal[3 * (b * nv + v) + k] = box.normal[3 * v + k];
            }
            out->color[b * nv + v] = color;
        }
        for (uint32_t t = 0; t < 3 * nt; t++)
            out->index[3 * nt * b + t] = box.index[t] + b * nv;
    }
    psc_model_free(&box);
}

int r3d_scene_make(r3d_scene_t *s, r3d_kind_t kind)
{
    memset(s, 0, sizeof *s);
    s->kind = kind;
    s->name = kind == R3D_THOM ? "thom" : kind == R3D_BLOCKS ? "blocks" : "teapot";
    s->textured = kind == R3D_TEAPOT;
    psc_model_t m;
    psc_image_t tex = {0, 0, NULL};
    if (kind == R3D_THOM) {
        if (r3d_thom_model(&m) != 0)
            return -1;
    } else if (kind == R3D_BLOCKS) {
        blocks_model(&m);
    } else {
        psc_model_teapot(&m, R3D_TEAPOT_STEPS);
        /* A checkerboard with colour ramps: every texel differs from its neighbours. */
        tex = (psc_image_t){R3D_TEXTURE_SIDE, R3D_TEXTURE_SIDE, malloc(R3D_TEXTURE_SIDE * R3D_TEXTURE_SIDE * 4)};
        for (uint32_t y = 0; y < R3D_TEXTURE_SIDE; y++)
            for (uint32_t x = 0; x < R3D_TEXTURE_SIDE; x++) {
                uint32_t check = ((x / 32) + (y / 32)) & 1u;
                tex.xrgb[y * R3D_TEXTURE_SIDE + x] = 0xFF000000u | (x << 16) | (y << 8) | (check ? 220u : 60u);
            }
    }
    uint8_t *bytes = NULL;
    size_t len = 0;
    char err[512];
    int rc = psc_bake_mesh_pack(&m, s->textured ? &tex : NULL, NULL, s->name, &bytes, &len, err, sizeof err);
    psc_io_image_free(&tex);
    psc_model_free(&m);
    if (rc != 0) {
        fprintf(stderr, "render3d bench: %s\n", err);
        return -1;
    }
    if (posix_memalign(&s->pack, 64, len) != 0) {
        free(bytes);
        return -1;
    }
    memcpy(s->pack, bytes, len);
    free(bytes);
    s->pack_len = len;
    if (psc_io_mesh_parse_named(s->name, s->pack, len, &s->mesh, err, sizeof err) != 0) {
        fprintf(stderr, "render3d bench: %s\n", err);
        return -1;
    }
    s->light_dir = psc_vec3_normalize((psc_vec3_q16_t){-26000, 39000, -45000});
    return 0;
}

void r3d_scene_free(r3d_scene_t *s)
{
    free(s->pack);
    memset(s, 0, sizeof *s);
}

void r3d_frame_view(const r3d_scene_t *s, unsigned k, unsigned frames, psc_3d_draw_t *d, int32_t *near_q16,
                    int32_t *far_q16)
{
    psc_3d_draw_defaults(d, &s->mesh);
    psc_vec3_q16_t lo, hi;
    psc_mesh_bounds_q16(&s->mesh, &lo, &hi);
    psc_bam_t yaw = (psc_bam_t)((uint64_t)k * 0x100000000ull / (frames ? frames : 1)) + PSC_BAM_FROM_MDEG(30000);
    (void)psc_3d_orbit(lo, hi, yaw, -(int32_t)PSC_BAM_FROM_MDEG(20000), (int32_t)(R3D_ORBIT_DIST * 65536),
                       &d->camera_from_object, near_q16, far_q16);
    d->shade = s->textured ? PSC_SHADE_TEXTURE : PSC_SHADE_GOURAUD;
    d->filter = PSC_TEX_BILINEAR;
    d->lit = true;
    d->cull_back = true;
    d->depth_test = true;
    d->light_dir = s->light_dir;
    d->ambient_q8 = R3D_AMBIENT_Q8;
}

r3d_result_t r3d_run_periscope(const r3d_scene_t *s, uint16_t w, uint16_t h, const r3d_options_t *o, unsigned frames,
                               unsigned passes, uint16_t *last)
{
    uint16_t tile = o->tile;
    r3d_result_t res = {0, 0, 0, false};
    psc_3d_draw_t d;
    int32_t near_q16, far_q16;
    r3d_frame_view(s, 0, frames, &d, &near_q16, &far_q16);
    psc_3d_config_t cfg = {w, h, tile, tile, 16, PSC_BAM_FROM_MDEG((int64_t)(R3D_HFOV_DEG * 1000)), near_q16,
                           far_q16, s->mesh.vertex_count, o->hsr};
    psc_io_render3d_config(&cfg, o->threads, o->abuffer_bytes != 0);
    size_t n = psc_3d_workspace_size(&cfg);
    void *ws = NULL;
    psc_surface_t out = {w, h, (uint32_t)w * 2, PSC_PIX_RGB565, last};
    psc_3d_t r;
    void *abuf = NULL;
    if (n == 0 || posix_memalign(&ws, 64, n) != 0 || psc_3d_init(&r, &cfg, ws, n) != PSC_OK ||
        (o->abuffer_bytes && (posix_memalign(&abuf, 64, o->abuffer_bytes) != 0 ||
                              psc_3d_set_abuffer(&r, abuf, o->abuffer_bytes) != PSC_OK))) {
        free(ws);
        free(abuf);
        return res;
    }
    char err[256];
    psc_io_bands_t *pool = o->threads > 1 ? psc_io_bands_start(o->threads, w, err, sizeof err) : NULL;
    psc_io_render3d_t *threads = pool ? psc_io_render3d_start(pool, &cfg, o->abuffer_bytes, err, sizeof err) : NULL;
    if (o->threads > 1 && !threads) {
        fprintf(stderr, "render3d bench: %s\n", err);
        psc_io_bands_stop(pool);
        free(ws);
        free(abuf);
        return res;
    }
    uint32_t bg = R3D_BACKGROUND;
    double best = 1e30, pixels = 0, tests = 0;
    for (unsigned p = 0; p < passes; p++) {
        double t0 = bench_now_ms();
        pixels = 0;
        tests = 0;
        for (unsigned k = 0; k < frames; k++) {
            psc_3d_stats_t st;
            r3d_frame_view(s, k, frames, &d, &near_q16, &far_q16);
            if (o->phong) {
                d.shade = PSC_SHADE_PHONG;
                d.specular_q8 = 90;
                d.shininess = 24;
            }
            if (psc_io_render3d_frame(threads, &r, &d, 1, &bg, &out, &st) != PSC_OK) {
                psc_io_render3d_stop(threads);
                psc_io_bands_stop(pool);
                free(ws);
                free(abuf);
                return res;
            }
            pixels += (double)st.pixels;
            tests += (double)st.depth_tests;
        }
        double ms = (bench_now_ms() - t0) / frames;
        best = ms < best ? ms : best;
    }
    psc_io_render3d_stop(threads);
    psc_io_bands_stop(pool);
    free(ws);
    free(abuf);
    res.ms_per_frame = best;
    res.pixels_written = pixels / frames;
    res.depth_tests = tests / frames;
    res.ok = true;
    return res;
}
