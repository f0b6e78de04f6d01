/* SPDX-License-Identifier: MIT */
/*
 * proxy - how much the proxy animator saves: each model drawn as its proxies
 * with view textures and as its full mesh, by the same pipeline, side by side
 * in one run (800x480, RGB565, 16-bit depth, one core, best of PASSES passes
 * of FRAMES frames, the camera turning 3 degrees a frame), near (2.5 R: the
 * model fills the view) and at a middle distance (7 R: a third of it, where
 * the proxies are the level of detail drawn):
 *  - a rigid assembly of 12 rings of 9 216 triangles each (110 592 in all),
 *    every ring its own node, built here;
 *  - the bundled skinned bar (tests/data/gltf), its animation
 *    playing;
 *  - a held-out skinned human (tests/data/assimp/BCN_Epileptic.X, 5 126
 *    triangles), baked with 64 views (9 x 9), its animation playing.
 * Each at 800x480 near and at the middle distance, and at 320x240 at the
 * middle distance (the model a third of the view).
 * Each is baked here with periscope-proxy's defaults (7 x 7 views, 12 MB of
 * view textures with their mips, one texel density).
 *
 *   build/bench/proxy --out bench/results     the table (`make bench`)
 */
#include "common/bench_time.h"
#include "import/gltf_model.h"
#include "bake/proxy.h"
#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_render.h"
#include "base/psc_fixed.h"
#include "proxy/psc_proxy.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 800u
#define H 480u
#define FRAMES 60u
#define PASSES 3u
#define RINGS 12u


typedef struct {
    const char *name;
    double t_step;               /* animation seconds a frame (0: rest) */
    uint8_t *pack;
    size_t len;
    psc_proxy_model_t m;
    char note[512];
} model_t;

static int bake(model_t *mo, const psc_gltf_t *g, unsigned views)
{
    psc_bake_proxy_opts_t o = {views, PSC_BAKE_PROXY_TEX, 0 /* by the model */, PSC_BAKE_PROXY_TEX_MB,
                               PSC_BAKE_PROXY_PACK_MB};
    char err[512];
    uint8_t *bytes;
    if (psc_bake_proxy(g, &o, mo->name, &bytes, &mo->len, mo->note, sizeof mo->note, err, sizeof err) != 0) {
        fprintf(stderr, "proxy bench: %s\n", err);
        return -1;
    }
    if (posix_memalign((void **)&mo->pack, 64, mo->len) != 0)
        return -1;
    memcpy(mo->pack, bytes, mo->len);
    free(bytes);
    psc_container_error_t e = {0};
    return psc_proxy_parse(mo->pack, mo->len, &mo->m, &e) == PSC_OK ? 0 : -1;
}

/* Best time of PASSES passes of FRAMES frames (ms per frame) at w x h, proxies or full. */
static double run(model_t *mo, psc_proxy_lod_t lod, unsigned w, unsigned h, int32_t dist_q16, uint32_t *triangles)
{
    const psc_proxy_model_t *m = &mo->m;
    psc_vec3_q16_t lo, hi;
    psc_proxy_rest_bounds(m, &lo, &hi);
    psc_3d_config_t cfg = {(uint16_t)w, (uint16_t)h, 0, 0, 16, 0x238E38E4u, 0, 0, psc_proxy_max_vertices(m)};
    psc_mat4_q16_t cam;
    psc_3d_orbit(lo, hi, 0, (int32_t)0x0E38E38E, dist_q16, &cam, &cfg.near_q16, &cfg.far_q16);
    size_t n3 = psc_3d_workspace_size(&cfg), np = psc_proxy_workspace_size(m);
    void *ws3d = NULL, *wsp = NULL, *px = NULL;
    psc_mat4_q16_t *skin = malloc(m->joint_count * sizeof *skin);
    psc_3d_t r;
    psc_proxy_t p;
    double best = 1e30;
    if (!skin || posix_memalign(&ws3d, 64, n3) != 0 || posix_memalign(&wsp, 64, np ? np : 8) != 0 ||
        posix_memalign(&px, 64, (size_t)w * h * 2) != 0 || psc_3d_init(&r, &cfg, ws3d, n3) != PSC_OK ||
        psc_proxy_init(&p, m, wsp, np) != PSC_OK)
        goto done;
    psc_surface_t sf = {(uint16_t)w, (uint16_t)h, w * 2u, PSC_PIX_RGB565, px};
    psc_proxy_set_focal(&p, psc_proxy_focal_px_q16(w, cfg.hfov));
    for (unsigned pass = 0; pass < PASSES; pass++) {
        double t0 = bench_now_s();
        for (unsigned f = 0; f < FRAMES; f++) {
            psc_3d_orbit(lo, hi, (psc_bam_t)(f * 0x02222222u), (int32_t)0x0E38E38E, dist_q16, &cam, &cfg.near_q16,
                         &cfg.far_q16);
            psc_proxy_pose_at(m, mo->t_step > 0 ? (int64_t)(f * mo->t_step * 1e6) : -1, skin);
            const psc_3d_draw_t *d;
            unsigned nd;
            psc_3d_stats_t st;
            uint32_t bg = 0x30343Cu;
            if (psc_proxy_frame(&p, skin, &cam, lod, false, &d, &nd) != PSC_OK ||
                psc_3d_render(&r, d, nd, &bg, &sf, &st) != PSC_OK)
                goto done;
            *triangles = st.triangles;
        }
        double dt = (bench_now_s() - t0) / FRAMES * 1e3;
        best = dt < best ? dt : best;
    }
done:
    free(skin), free(ws3d), free(wsp), free(px);
    return best;
}

int main(int argc, char **argv)
{
    const char *out = "bench/results";
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) {
            out = argv[++i];
        } else if (strcmp(argv[i], "--callgrind") == 0) {
            printf("proxy: no callgrind mode (the table's ratio is measured in one run)\n");
            return 0;
        } else {
            fprintf(stderr, "usage: build/bench/proxy [--out DIR]\n");
            return 2;
        }
    }
    psc_gltf_t g[3];
    char note[256], err[512];
    model_t models[3] = {{.name = "assembly, 12 rigid rings"},
                         {.name = "bar, skinned, playing", .t_step = 1.0 / 60},
                         {.name = "human, skinned, playing", .t_step = 1.0 / 60}};
    static const char *const files[3] = {NULL, "tests/data/gltf/animation_with_skeleton.gltf",
                                         "tests/data/assimp/BCN_Epileptic.X"};
    for (unsigned k = 0; k < 3; k++) {
        int rc = k == 0 ? psc_gltf_machine(&g[0], RINGS, 0)
                        : psc_gltf_load(files[k], &g[k], note, sizeof note, err, sizeof err);
        if (rc != 0) {
            fprintf(stderr, "proxy bench: %s (run from the repository's root)\n", k ? err : "out of memory");
            return 1;
        }
        if (bake(&models[k], &g[k], k == 2 ? 64u : PSC_BAKE_PROXY_VIEWS) != 0)
            return 1;
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/proxy.txt", out);
    FILE *j = fopen(path, "w");
    printf("proxy animator against the full mesh, RGB565, one core, best of %u passes of %u frames\n", PASSES, FRAMES);
    printf("%-26s %9s %9s %7s %10s %8s %9s %10s %10s %7s\n", "model", "triangles", "drawn", "views", "textures", "size",
           "distance", "full ms", "proxy ms", "ratio");
    /* 800 x 480 near (the model fills the view: the full mesh's level) and at a middle distance (a third of it: the
     * proxies'), and 320 x 240 at the middle distance */
    static const struct {
        unsigned w, h;
        double dist;
    } shots[3] = {{W, H, 2.5}, {W, H, 7.0}, {320, 240, 7.0}};
    for (unsigned k = 0; k < 9; k++) {
        model_t *mo = &models[k / 3];
        uint32_t tf = 0, tp = 0;
        unsigned w = shots[k % 3].w, h = shots[k % 3].h;
        int32_t dq = (int32_t)lround(shots[k % 3].dist * 65536);
        double full = run(mo, PSC_PROXY_LOD_FULL, w, h, dq, &tf), prx = run(mo, PSC_PROXY_LOD_PROXIES, w, h, dq, &tp);
        double tex_mb = 0;
        for (uint32_t i = 0; i < mo->m.part_count; i++)
            tex_mb += (double)psc_proxy_part_tex(&mo->m, i).chain * mo->m.view_count * 2 / 1048576.0;
        char line[256], size[16];
        snprintf(size, sizeof size, "%ux%u", w, h);
        snprintf(line, sizeof line, "%-26s %9u %9u %7u %7.1f MB %8s %7.1f R %10.3f %10.3f %6.2fx\n", mo->name, tf, tp,
                 mo->m.view_count, tex_mb, size, shots[k % 3].dist, full, prx, full / prx);
        fputs(line, stdout);
        if (j)
            fputs(line, j);
    }
    if (j)
        fclose(j);
    for (unsigned k = 0; k < 3; k++) {
        free(models[k].pack);
        psc_gltf_free(&g[k]);
    }
    return 0;
}
