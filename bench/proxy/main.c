/* SPDX-License-Identifier: MIT */
/*
 * proxy - how much the proxy animator saves: each model drawn as its proxies
 * with view textures and as its full mesh, by the same pipeline, side by side
 * in one run (800x480, RGB565, 16-bit depth, one core, best of PASSES passes
 * of FRAMES frames, the camera turning 3 degrees a frame, the two levels'
 * passes alternating), near (2.5 R: the
 * model fills the view) and at a middle distance (7 R: a third of it, where
 * the proxies are the level of detail drawn):
 *  - a rigid assembly of 12 rings of 9 216 triangles each (110 592 in all),
 *    every ring its own node, built here;
 *  - the bundled skinned bar (tests/data/gltf), its animation
 *    playing;
 *  - a held-out skinned human (tests/data/assimp/BCN_Epileptic.X, 5 126
 *    triangles), baked with 64 views (9 x 9), its animation playing;
 *  - a held-out skinned robot (tests/data/gltf/RobotExpressive.glb, 3 237
 *    triangles on 4 skins, three materials), the same, its first animation.
 * Each at 800x480 near and at the middle distance, and at 320x240 at the
 * middle distance (the model a third of the view).
 * Each is baked here with periscope-proxy's defaults (at least 64 views, 12 MB of
 * view textures with their mips, one texel density).
 *
 *   build/bench/proxy --out bench/results     the table (`make bench`)
 *   build/bench/proxy --callgrind --out DIR    the level of detail's choice (`make bench-callgrind`): each
 *                                              model at two screens and six distances, both levels' instructions
 *                                              a frame counted under callgrind beside psc_proxy_cost's estimates,
 *                                              the level --lod auto picks, how much slower it is than the cheaper
 *                                              (at most 10 % is the goal), and the cost model refitted from the
 *                                              counts beside the constants core uses
 */
#include "common/bench_callgrind.h"
#include "common/bench_cli.h"
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
#include <unistd.h>

/* Relit frames' light: from the side (azimuth -90, elevation 10 degrees), toward it in Q16.16 */
static const int32_t side_light[3] = {-64000, 11380, 0};

#define W 800u
#define H 480u
#define FRAMES 60u
#define PASSES 7u
#define RINGS 12u
#define MODELS 4u   /* the assembly, the bar and two held-out characters */


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
                               PSC_BAKE_PROXY_PACK_MB, false};
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

/* One level of detail drawn on its own renderer: the model at w x h and distance dist_q16, proxies or full, as
 * baked or relit by a light from the side (psc_proxy_set_light). */
typedef struct {
    model_t *mo;
    psc_proxy_lod_t lod;
    int32_t dist_q16;
    psc_vec3_q16_t lo, hi;
    psc_3d_config_t cfg;
    void *ws3d, *wsp, *px;
    psc_mat4_q16_t *skin;
    psc_3d_t r;
    psc_proxy_t p;
    psc_surface_t sf;
    uint32_t triangles;   /* drawn in the last frame */
    double best;          /* ms a frame, the best pass */
} runner_t;

static void runner_free(runner_t *u)
{
    free(u->skin), free(u->ws3d), free(u->wsp), free(u->px);
}

static int runner_init(runner_t *u, model_t *mo, psc_proxy_lod_t lod, unsigned w, unsigned h, int32_t dist_q16,
                       bool relit)
{
    const psc_proxy_model_t *m = &mo->m;
    *u = (runner_t){.mo = mo, .lod = lod, .dist_q16 = dist_q16, .best = 1e30};
    psc_proxy_rest_bounds(m, &u->lo, &u->hi);
    u->cfg = (psc_3d_config_t){(uint16_t)w, (uint16_t)h, 0, 0, 16, 0x238E38E4u, 0, 0, psc_proxy_max_vertices(m),
                               PSC_3D_HSR_ZBUFFER};
    psc_mat4_q16_t cam;
    psc_3d_orbit(u->lo, u->hi, 0, (int32_t)0x0E38E38E, dist_q16, &cam, &u->cfg.near_q16, &u->cfg.far_q16);
    size_t n3 = psc_3d_workspace_size(&u->cfg), np = psc_proxy_workspace_size(m);
    u->skin = malloc(m->joint_count * sizeof *u->skin);
    if (!u->skin || posix_memalign(&u->ws3d, 64, n3) != 0 || posix_memalign(&u->wsp, 64, np ? np : 8) != 0 ||
        posix_memalign(&u->px, 64, (size_t)w * h * 2) != 0 || psc_3d_init(&u->r, &u->cfg, u->ws3d, n3) != PSC_OK ||
        psc_proxy_init(&u->p, m, u->wsp, np) != PSC_OK)
        return -1;
    u->sf = (psc_surface_t){(uint16_t)w, (uint16_t)h, w * 2u, PSC_PIX_RGB565, u->px};
    psc_proxy_set_focal(&u->p, psc_proxy_focal_px_q16(w, u->cfg.hfov));
    return relit && psc_proxy_set_light(&u->p, side_light, 7373) != PSC_OK ? -1 : 0;
}

/* One pass of FRAMES frames, the camera turning; the best pass kept. */
static int runner_pass(runner_t *u)
{
    const psc_proxy_model_t *m = &u->mo->m;
    double t0 = bench_now_s();
    for (unsigned f = 0; f < FRAMES; f++) {
        psc_mat4_q16_t cam;
        psc_3d_orbit(u->lo, u->hi, (psc_bam_t)(f * 0x02222222u), (int32_t)0x0E38E38E, u->dist_q16, &cam,
                     &u->cfg.near_q16, &u->cfg.far_q16);
        psc_proxy_pose_at(m, u->mo->t_step > 0 ? (int64_t)(f * u->mo->t_step * 1e6) : -1, u->skin);
        const psc_3d_draw_t *d;
        unsigned nd;
        psc_3d_stats_t st;
        uint32_t bg = 0x30343Cu;
        if (psc_proxy_frame(&u->p, u->skin, &cam, u->lod, false, &d, &nd) != PSC_OK ||
            psc_3d_render(&u->r, d, nd, &bg, &u->sf, &st) != PSC_OK)
            return -1;
        u->triangles = st.triangles;
    }
    double dt = (bench_now_s() - t0) / FRAMES * 1e3;
    u->best = dt < u->best ? dt : u->best;
    return 0;
}

/* The full mesh's and the proxies' best times (ms a frame) at w x h, as baked or relit: their passes alternate, so
 * that a slower spell of this shared machine falls on both and their ratio holds. */
static int run_pair(model_t *mo, unsigned w, unsigned h, int32_t dist_q16, bool relit, double *full, double *prx,
                    uint32_t *tf, uint32_t *tp)
{
    runner_t u[2];
    int rc = runner_init(&u[0], mo, PSC_PROXY_LOD_FULL, w, h, dist_q16, relit) |
             runner_init(&u[1], mo, PSC_PROXY_LOD_PROXIES, w, h, dist_q16, relit);
    for (unsigned pass = 0; rc == 0 && pass < PASSES; pass++)
        rc = runner_pass(&u[pass & 1u]) | runner_pass(&u[!(pass & 1u)]);   /* each first in turn */
    *full = u[0].best, *prx = u[1].best, *tf = u[0].triangles, *tp = u[1].triangles;
    runner_free(&u[0]), runner_free(&u[1]);
    return rc;
}

/* The models baked (g: their imports, freed by the caller); the held-out characters with 64 views, as the issue
 * measured them. */
static int bake_all(psc_gltf_t g[MODELS], model_t models[MODELS])
{
    char note[256], err[512];
    static const char *const names[MODELS] = {"assembly, 12 rigid rings", "bar, skinned, playing",
                                              "human, skinned, playing", "robot, skinned, playing"};
    static const char *const files[MODELS] = {NULL, "tests/data/gltf/animation_with_skeleton.gltf",
                                              "tests/data/assimp/BCN_Epileptic.X", "tests/data/gltf/RobotExpressive.glb"};
    for (unsigned k = 0; k < MODELS; k++) {
        models[k] = (model_t){.name = names[k], .t_step = k ? 1.0 / 60 : 0};
        int rc = k == 0 ? psc_gltf_machine(&g[0], RINGS, 0)
                        : psc_gltf_load(files[k], &g[k], note, sizeof note, err, sizeof err);
        if (rc != 0) {
            fprintf(stderr, "proxy bench: %s (run from the repository's root)\n", k ? err : "out of memory");
            return -1;
        }
        if (bake(&models[k], &g[k], k >= 2 ? 64u : PSC_BAKE_PROXY_VIEWS) != 0)
            return -1;
    }
    return 0;
}

/* A line of the table, on the terminal and in the results file (j may be NULL). */
static void emit(FILE *j, const char *line)
{
    fputs(line, stdout);
    if (j)
        fputs(line, j);
}

/* What bake_all made, freed. */
static void free_all(psc_gltf_t g[MODELS], model_t models[MODELS])
{
    for (unsigned k = 0; k < MODELS; k++) {
        free(models[k].pack);
        psc_gltf_free(&g[k]);
    }
}

static int run_table(const char *out)
{
    psc_gltf_t g[MODELS] = {0};
    model_t models[MODELS];
    if (bake_all(g, models) != 0)
        return 1;
    char path[4096];
    snprintf(path, sizeof path, "%s/proxy.txt", out);
    FILE *j = fopen(path, "w");
    printf("proxy animator against the full mesh, RGB565, one core, best of %u passes of %u frames (the two levels' passes alternating)\n", PASSES, FRAMES);
    printf("%-26s %9s %9s %7s %10s %8s %9s %10s %10s %7s %17s %7s\n", "model", "triangles", "drawn", "views", "textures",
           "size", "distance", "full ms", "proxy ms", "ratio", "relit: full/proxy", "ratio");
    /* 800 x 480 near (the model fills the view: the full mesh's level) and at a middle distance (a third of it: the
     * proxies'), and 320 x 240 at the middle distance */
    static const struct {
        unsigned w, h;
        double dist;
    } shots[3] = {{W, H, 2.5}, {W, H, 7.0}, {320, 240, 7.0}};
    for (unsigned k = 0; k < 3 * MODELS; k++) {
        model_t *mo = &models[k / 3];
        uint32_t tf = 0, tp = 0;
        unsigned w = shots[k % 3].w, h = shots[k % 3].h;
        int32_t dq = (int32_t)lround(shots[k % 3].dist * 65536);
        double full, prx, rfull, rprx;
        if (run_pair(mo, w, h, dq, false, &full, &prx, &tf, &tp) != 0 ||
            run_pair(mo, w, h, dq, true, &rfull, &rprx, &tf, &tp) != 0) {
            fprintf(stderr, "proxy bench: %s could not be drawn at %ux%u\n", mo->name, w, h);
            free_all(g, models);
            return 1;
        }
        double tex_mb = 0;
        for (uint32_t i = 0; i < mo->m.part_count; i++)
            tex_mb += (double)psc_proxy_part_tex(&mo->m, i).chain * mo->m.view_count * 2 / 1048576.0;
        char line[320], size[16];
        snprintf(size, sizeof size, "%ux%u", w, h);
        snprintf(line, sizeof line, "%-26s %9u %9u %7u %7.1f MB %8s %7.1f R %10.3f %10.3f %6.2fx %8.3f/%8.3f %6.2fx\n",
                 mo->name, tf, tp, mo->m.view_count, tex_mb, size, shots[k % 3].dist, full, prx, full / prx, rfull, rprx,
                 rfull / rprx);
        emit(j, line);
    }
    if (j)
        fclose(j);
    free_all(g, models);
    return 0;
}

/* ---- callgrind: the level of detail's choice --------------------------------------------------------------- */

#define CG_FRAMES 3u
#define CG_CASE_ENV "PSC_BENCH_PROXY_CASE"   /* the child's case: "PACK W H DIST LEVEL TSTEP" */
#define CG_DISTS 6u

static const double cg_dists[CG_DISTS] = {1.8, 2.7, 4.0, 6.5, 11.0, 20.0};
static const unsigned cg_w[2] = {320, 800}, cg_h[2] = {240, 480};
static psc_3d_stats_t cg_stats;

/* A case's camera (yaw 0, pitch 20, dist R from the rest box's centre, 50 degrees) and pipeline. */
static int cg_camera(const psc_proxy_model_t *m, unsigned w, unsigned h, double dist, psc_mat4_q16_t *cam,
                     psc_3d_config_t *cfg)
{
    psc_vec3_q16_t lo, hi;
    psc_proxy_rest_bounds(m, &lo, &hi);
    *cfg = (psc_3d_config_t){(uint16_t)w, (uint16_t)h, 0, 0, 16, 0x238E38E4u, 0, 0,
                             psc_proxy_max_vertices(m), PSC_3D_HSR_ZBUFFER};
    return psc_3d_orbit(lo, hi, 0, (int32_t)0x0E38E38E, (int32_t)lround(dist * 65536), cam, &cfg->near_q16,
                        &cfg->far_q16) == PSC_OK ? 0 : -1;
}

/* What callgrind counts: CG_FRAMES frames posed, built and drawn at one level (the animation playing). */
__attribute__((noinline)) static int cg_frames(psc_proxy_t *p, psc_3d_t *r, psc_mat4_q16_t *skin,
                                               const psc_mat4_q16_t *cam, psc_proxy_lod_t lod, double t_step,
                                               const psc_surface_t *sf)
{
    for (unsigned f = 0; f < CG_FRAMES; f++) {
        const psc_3d_draw_t *d;
        unsigned nd;
        uint32_t bg = 0x30343Cu;
        psc_proxy_pose_at(p->m, t_step > 0 ? (int64_t)(f * t_step * 1e6) : -1, skin);
        if (psc_proxy_frame(p, skin, cam, lod, false, &d, &nd) != PSC_OK ||
            psc_3d_render(r, d, nd, &bg, sf, &cg_stats) != PSC_OK)
            return -1;
    }
    return 0;
}

static int cg_child(void)
{
    const char *c = getenv(CG_CASE_ENV);
    char path[4096];
    unsigned w, h, level;
    double dist, t_step;
    if (!c || sscanf(c, "%4095s %u %u %lf %u %lf", path, &w, &h, &dist, &level, &t_step) != 6)
        return 1;
    FILE *f = fopen(path, "rb");
    model_t mo = {.name = path, .t_step = t_step};
    long n = f && fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    if (n <= 0 || fseek(f, 0, SEEK_SET) != 0 || posix_memalign((void **)&mo.pack, 64, (size_t)n) != 0 ||
        fread(mo.pack, 1, (size_t)n, f) != (size_t)n) {
        if (f)
            fclose(f);
        return 1;
    }
    fclose(f);
    psc_container_error_t e = {0};
    psc_3d_config_t cfg;
    psc_mat4_q16_t cam;
    if (psc_proxy_parse(mo.pack, (size_t)n, &mo.m, &e) != PSC_OK || cg_camera(&mo.m, w, h, dist, &cam, &cfg) != 0)
        return 1;
    size_t n3 = psc_3d_workspace_size(&cfg), np = psc_proxy_workspace_size(&mo.m);
    void *ws3d = NULL, *wsp = NULL, *px = NULL;
    psc_mat4_q16_t *skin = malloc(mo.m.joint_count * sizeof *skin);
    psc_3d_t r;
    psc_proxy_t p;
    int rc = 1;
    if (skin && posix_memalign(&ws3d, 64, n3) == 0 && posix_memalign(&wsp, 64, np ? np : 8) == 0 &&
        posix_memalign(&px, 64, (size_t)w * h * 2) == 0 && psc_3d_init(&r, &cfg, ws3d, n3) == PSC_OK &&
        psc_proxy_init(&p, &mo.m, wsp, np) == PSC_OK) {
        psc_surface_t sf = {(uint16_t)w, (uint16_t)h, w * 2u, PSC_PIX_RGB565, px};
        psc_proxy_set_focal(&p, psc_proxy_focal_px_q16(w, cfg.hfov));
        if ((level < 2 || psc_proxy_set_light(&p, side_light, 7373) == PSC_OK) &&
            cg_frames(&p, &r, skin, &cam, level & 1u ? PSC_PROXY_LOD_FULL : PSC_PROXY_LOD_PROXIES, t_step, &sf) == 0) {
            printf("%u %u %u %llu\n", (unsigned)cg_stats.triangles, (unsigned)cg_stats.culled,
                   (unsigned)cg_stats.outside, (unsigned long long)cg_stats.pixels);
            rc = 0;
        }
    }
    free(skin), free(ws3d), free(wsp), free(px), free(mo.pack);
    return rc;
}

/* One case counted: instructions a frame, and the last frame's pixels. */
static int cg_count(const char *self, const char *pack, unsigned w, unsigned h, double dist, unsigned level,
                    double t_step, double *ir, double *pixels)
{
    char c[4200];
    snprintf(c, sizeof c, "%s %u %u %.3f %u %.6f", pack, w, h, dist, level, t_step);
    FILE *out = tmpfile();
    long long n = -1;
    char *const argv[] = {(char *)self, "--callgrind-child", NULL};
    unsigned tri, culled, outside;
    unsigned long long px;
    if (!out || setenv(CG_CASE_ENV, c, 1) != 0 || bench_callgrind_count("cg_frames", argv, out, &n) != 0 || n < 0 ||
        fseek(out, 0, SEEK_SET) != 0 || fscanf(out, "%u %u %u %llu", &tri, &culled, &outside, &px) != 4) {
        fprintf(stderr, "proxy bench: the callgrind run of %s failed\n", c);
        if (out)
            fclose(out);
        return -1;
    }
    fclose(out);
    *ir = (double)n / CG_FRAMES;
    *pixels = (double)px;
    return 0;
}

/* Whether the proxies' views are magnified there (the model's radius beyond their texels per R). */
static bool magnified_at(const psc_proxy_t *p, const psc_proxy_cost_t *c)
{
    return c->radius_px > (int32_t)p->texels_per_r;
}

/* What --lod auto does from a fresh state, as the first frame of a scene: its first pick, then (what a frame at that
 * level wrote, px[0] the proxies' pixels and px[1] the full mesh's, correcting the estimate as the device's scene does
 * every frame) the estimate and the pick after it; relit by `light` unless NULL. 0, or -1 out of memory. */
typedef struct {
    psc_proxy_lod_t first, pick;
    psc_proxy_cost_t cost;
    bool magnified;   /* the views magnified at that radius */
    double blended;   /* the full mesh's vertices that blend joints */
} cg_auto_t;

static int cg_auto(const psc_proxy_model_t *m, unsigned w, unsigned h, double dist, const int32_t *light,
                   const double px[2], cg_auto_t *out)
{
    psc_3d_config_t cfg;
    psc_mat4_q16_t cam;
    size_t np = psc_proxy_workspace_size(m);
    void *wsp = NULL;
    psc_proxy_t p;
    if (cg_camera(m, w, h, dist, &cam, &cfg) != 0 || posix_memalign(&wsp, 64, np ? np : 8) != 0 ||
        psc_proxy_init(&p, m, wsp, np) != PSC_OK || (light && psc_proxy_set_light(&p, light, 7373) != PSC_OK)) {
        free(wsp);
        return -1;
    }
    int32_t focal = psc_proxy_focal_px_q16(w, cfg.hfov);
    psc_proxy_set_screen(&p, w, h);
    out->first = psc_proxy_lod_pick(&p, &cam, focal);
    psc_3d_stats_t seen = {0};
    seen.pixels = out->first == PSC_PROXY_LOD_BILLBOARD ? 0 : (uint64_t)px[out->first == PSC_PROXY_LOD_FULL];
    psc_proxy_observe(&p, &seen);
    out->cost = psc_proxy_cost(&p, &cam, focal);
    out->pick = psc_proxy_lod_pick(&p, &cam, focal);
    out->magnified = magnified_at(&p, &out->cost);
    out->blended = p.blended_vertices;
    free(wsp);
    return 0;
}

/* Least squares of relative error: the k coefficients c minimising sum ((x_i . c - y_i) / y_i)^2 (k <= 5). */
static void fit(const double (*x)[5], const double *y, unsigned n, unsigned k, double *c)
{
    double a[5][6] = {{0}};
    for (unsigned i = 0; i < n; i++)
        for (unsigned r = 0; r < k; r++) {
            for (unsigned s = 0; s < k; s++)
                a[r][s] += x[i][r] * x[i][s] / (y[i] * y[i]);
            a[r][k] += x[i][r] / y[i];
        }
    for (unsigned r = 0; r < k; r++) {   /* Gauss-Jordan; the normal matrix is positive definite */
        for (unsigned s = 0; s < k; s++)
            if (s != r && a[r][r] != 0) {
                double f = a[s][r] / a[r][r];
                for (unsigned t = 0; t <= k; t++)
                    a[s][t] -= f * a[r][t];
            }
    }
    for (unsigned r = 0; r < k; r++)
        c[r] = a[r][r] != 0 ? a[r][k] / a[r][r] : 0;
}

static int run_callgrind(const char *self, const char *out_dir)
{
    if (bench_callgrind_require("proxy") != 0)
        return 1;
    psc_gltf_t g[MODELS] = {0};
    model_t models[MODELS];
    char packs[MODELS][64];
    if (bake_all(g, models) != 0)
        return 1;
    int rc = 0;
    for (unsigned k = 0; k < MODELS; k++) {   /* the children read the packs baked here */
        snprintf(packs[k], sizeof packs[k], "/tmp/periscope-proxy-bench-XXXXXX");
        int fd = mkstemp(packs[k]);
        FILE *f = fd >= 0 ? fdopen(fd, "wb") : NULL;
        if (!f || fwrite(models[k].pack, 1, models[k].len, f) != models[k].len || fclose(f) != 0) {
            fprintf(stderr, "proxy bench: cannot write %s\n", packs[k]);
            return 1;
        }
    }
    enum { CASES = MODELS * 2 * CG_DISTS };
    static double xp[CASES][5], yp[CASES], xf[CASES][5], yf[CASES];
    double worst = 1.0, worst_first = 1.0, worst_relit = 1.0;
    unsigned ncase = 0, billboard = 0, magnified_picks = 0;
    char path[4096];
    snprintf(path, sizeof path, "%s/proxy-lod-callgrind.txt", out_dir);
    FILE *j = fopen(path, "w");
    printf("proxy levels of detail under callgrind: instructions a frame (pose, build, draw; %u frames, RGB565), "
           "psc_proxy_cost's estimate beside each once a frame has corrected its area, and --lod auto's choice\n",
           CG_FRAMES);
    char head[256];
    snprintf(head, sizeof head, "%-26s %8s %6s %6s %15s %17s %17s %10s %7s\n", "model", "size", "dist", "r px",
             "pixels est/drawn", "proxies est/count", "full est/count", "auto", "slower");
    emit(j, head);
    for (unsigned k = 0; k < MODELS && rc == 0; k++)
        for (unsigned s = 0; s < 2 && rc == 0; s++)
            for (unsigned d = 0; d < CG_DISTS && rc == 0; d++) {
                const psc_proxy_model_t *m = &models[k].m;
                double ir[2], px[2];
                for (unsigned lv = 0; lv < 2 && rc == 0; lv++)
                    rc = cg_count(self, packs[k], cg_w[s], cg_h[s], cg_dists[d], lv, models[k].t_step, &ir[lv],
                                  &px[lv]);
                if (rc != 0)
                    break;
                /* the estimate and the choice from a fresh state, as the first frame of a scene makes them */
                cg_auto_t au;
                if ((rc = cg_auto(m, cg_w[s], cg_h[s], cg_dists[d], NULL, px, &au)) != 0)
                    break;
                psc_proxy_lod_t first = au.first, pick = au.pick;
                psc_proxy_cost_t c = au.cost;
                double first_slower = first == PSC_PROXY_LOD_BILLBOARD
                                          ? 1.0
                                          : ir[first == PSC_PROXY_LOD_FULL] / fmin(ir[0], ir[1]);
                worst_first = fmax(worst_first, first_slower);
                bool magnified = au.magnified;
                double slower = pick == PSC_PROXY_LOD_BILLBOARD ? 0 : ir[pick == PSC_PROXY_LOD_FULL] / fmin(ir[0], ir[1]);
                if (pick == PSC_PROXY_LOD_BILLBOARD)
                    billboard++;
                else
                    worst = fmax(worst, slower);
                if (pick == PSC_PROXY_LOD_PROXIES && magnified)
                    magnified_picks++;
                /* the cost model's features, for the refit (the pixels drawn, not estimated) */
                double t = m->proxy_triangle_count, tf = m->triangle_count;
                xp[ncase][0] = m->proxy_vertex_count, xp[ncase][1] = t, xp[ncase][2] = sqrt(px[0] * t / 2);
                xp[ncase][3] = px[0], xp[ncase][4] = (double)cg_w[s] * cg_h[s], yp[ncase] = ir[0];
                xf[ncase][0] = m->vertex_count, xf[ncase][1] = au.blended, xf[ncase][2] = tf;
                xf[ncase][3] = sqrt(px[1] * tf / 2), xf[ncase][4] = xp[ncase][4];
                yf[ncase] = ir[1];
                ncase++;
                char size[16], line[320], est[3][40], sl[16];
                snprintf(size, sizeof size, "%ux%u", cg_w[s], cg_h[s]);
                snprintf(est[0], sizeof est[0], "%u/%.0f", (unsigned)c.area_px, px[0]);
                snprintf(est[1], sizeof est[1], "%.2f/%.2f M", c.proxies / 1e6, ir[0] / 1e6);
                snprintf(est[2], sizeof est[2], "%.2f/%.2f M", c.full / 1e6, ir[1] / 1e6);
                snprintf(sl, sizeof sl, pick == PSC_PROXY_LOD_BILLBOARD ? "-" : "%.2fx%s", slower,
                         magnified && pick == PSC_PROXY_LOD_PROXIES ? "*" : "");
                char firstly[40] = "";   /* the first frame's pick, where the corrected estimate picks otherwise */
                if (first != pick)
                    snprintf(firstly, sizeof firstly, "  (first frame: %s, %.2fx)",
                             first == PSC_PROXY_LOD_FULL ? "full" : first == PSC_PROXY_LOD_BILLBOARD ? "billboard" : "proxies",
                             first_slower);
                snprintf(line, sizeof line, "%-26s %8s %4.1f R %6d %15s %17s %17s %10s %7s%s\n", models[k].name, size,
                         cg_dists[d], (int)c.radius_px, est[0], est[1], est[2],
                         pick == PSC_PROXY_LOD_FULL ? "full" : pick == PSC_PROXY_LOD_BILLBOARD ? "billboard" : "proxies",
                         sl, firstly);
                emit(j, line);
            }
    /* relit from the side against as baked: both levels, 320 x 240 and 800 x 480 at the middle distance */
    for (unsigned k = 0; k < MODELS && rc == 0; k++)
        for (unsigned s = 0; s < 2 && rc == 0; s++) {
            double ir[4], px[4];
            for (unsigned level = 0; level < 4 && rc == 0; level++)
                rc = cg_count(self, packs[k], cg_w[s], cg_h[s], 6.5, level, models[k].t_step, &ir[level], &px[level]);
            if (rc != 0)
                break;
            /* --lod auto relit: the estimate with the relit terms, corrected by a frame as above */
            cg_auto_t au;
            if ((rc = cg_auto(&models[k].m, cg_w[s], cg_h[s], 6.5, side_light, &px[2], &au)) != 0)
                break;
            psc_proxy_lod_t pick = au.pick;
            double slower = pick == PSC_PROXY_LOD_BILLBOARD ? 1.0 : ir[pick == PSC_PROXY_LOD_FULL ? 3 : 2] / fmin(ir[2], ir[3]);
            worst_relit = fmax(worst_relit, slower);
            char line[400];
            snprintf(line, sizeof line, "%-26s %4ux%-4u 6.5 R relit: proxies %.2f M (%.2fx as baked), full mesh %.2f M "
                     "(%.2fx); proxies %.2fx the full mesh's instructions relit, %.2fx as baked; auto: %s, %.2fx\n",
                     models[k].name, cg_w[s], cg_h[s], ir[2] / 1e6, ir[2] / ir[0], ir[3] / 1e6, ir[3] / ir[1],
                     ir[2] / ir[3], ir[0] / ir[1],
                     pick == PSC_PROXY_LOD_FULL ? "full" : pick == PSC_PROXY_LOD_BILLBOARD ? "billboard" : "proxies",
                     slower);
            emit(j, line);
        }
    for (unsigned k = 0; k < MODELS; k++)
        unlink(packs[k]);
    if (rc == 0) {
        double cp[5], cf[5];
        fit((const double(*)[5])xp, yp, ncase, 5, cp);
        fit((const double(*)[5])xf, yf, ncase, 5, cf);
        char line[640];
        snprintf(line, sizeof line,
                 "auto against the cheaper level: at most %.3fx slower (goal 1.10x) once a frame has corrected the "
                 "estimate of the area, %.3fx on the first frame; %u cases the billboard's; %u proxies with their "
                 "views magnified (*); relit, at most %.3fx\n"
                 "the cost model refitted from these counts (instructions): proxies %.0f a vertex, %.0f a triangle, "
                 "%.0f a row, %.0f a pixel, %.1f a screen pixel; full mesh %.0f a vertex, %.0f more one "
                 "that blends joints, %.0f a triangle, %.0f a row, %.1f a screen pixel\n"
                 "core's constants (psc_proxy.h):                           proxies %u, %u, %u, %u, %u; full mesh "
                 "%u, %u, %u, %u, %u\n",
                 worst, worst_first, billboard, magnified_picks, worst_relit, cp[0], cp[1], cp[2], cp[3], cp[4], cf[0],
                 cf[1], cf[2], cf[3], cf[4],
                 PSC_PROXY_COST_VERTEX, PSC_PROXY_COST_TRIANGLE, PSC_PROXY_COST_ROW, PSC_PROXY_COST_PIXEL,
                 PSC_PROXY_COST_SCREEN_PIXEL, PSC_PROXY_COST_FULL_VERTEX, PSC_PROXY_COST_FULL_BLEND,
                 PSC_PROXY_COST_FULL_TRIANGLE, PSC_PROXY_COST_FULL_ROW, PSC_PROXY_COST_SCREEN_PIXEL);
        emit(j, line);
    }
    if (j)
        fclose(j);
    free_all(g, models);
    return rc == 0 ? 0 : 1;
}

int main(int argc, char **argv)
{
    static const bench_cli_t cli = {"proxy", run_table, run_callgrind, cg_child};
    return bench_cli_main(&cli, argc, argv);
}
