/* SPDX-License-Identifier: MIT */
/*
 * patch - how fast the Hash patch character plays: Thom (assets/thom) waving
 * (Wave.act) at 800x480, side by side in one run with the same frames drawn
 * from a pre-tessellated static mesh by the same 3D pipeline (what a
 * renderer that cannot re-tessellate would draw).
 *
 *   build/bench/patch --out bench/results              the timed table (`make bench`)
 *   build/bench/patch --callgrind --out bench/results  instructions per frame under callgrind
 *                                                      (`make bench-callgrind`)
 *
 * Per frame: pose (channels, bones, skinning) + tangents, tessellation
 * (psc_patch_tessellate), drawing (psc_3d_render, 16-bit depth, Gouraud, lit,
 * RGB565). The frames step the action at 60 Hz, the camera turns 3 degrees
 * a frame, one core, best of PASSES passes.
 */
#include "common/bench_callgrind.h"
#include "common/bench_cli.h"
#include "common/bench_time.h"
#include "bake/patch_any.h"
#include "bake/shadow.h"
#include "shadow/psc_shadow_frame.h"
#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_render.h"
#include "base/psc_fixed.h"
#include "patch/psc_patch_frame.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define W 800u
#define H 480u
#define FRAMES 134u             /* Wave.act's 2.23 s at 60 Hz */
#define PASSES 3u
#define CG_FRAMES 8u
#define WAVE_ACTION 1

static const psc_patch_limits_t limits = {98304u, 131072u, 5u};   /* the character scene's (its max depth: 5) */

typedef struct {
    psc_io_patch_t pf;
    psc_patch_t p;
    void *ws, *ws3d, *pixels;
    size_t ws_size, ws3d_size;
    uint8_t *pao, *pao_plain;    /* the character's shadow pack, built here; and one without the rest correction */
    size_t pao_len;
    psc_shadow_model_t sm, sm_plain;
    psc_shadow_t sh, sh_plain;
    void *sh_ws, *sh_plain_ws;
} bench_t;

/* Shadow pack *pao for b's character (opts so) parsed into *sm, its run time *sh started in *ws. */
static int shadow_setup(bench_t *b, const psc_bake_shadow_opts_t *so, uint8_t **pao, size_t *len,
                        psc_shadow_model_t *sm, psc_shadow_t *sh, void **ws)
{
    char note[256] = "", err[768] = "";
    psc_container_error_t e = {0};
    if (psc_bake_shadow(&b->pf.model, so, "Thom.mdl", pao, len, note, sizeof note, err, sizeof err) != 0 ||
        psc_shadow_parse(*pao, *len, sm, &e) != PSC_OK ||
        posix_memalign(ws, 64, psc_shadow_workspace_size(sm, &b->pf.model)) != 0 ||
        psc_shadow_init(sh, sm, &b->pf.model, *ws, psc_shadow_workspace_size(sm, &b->pf.model)) != PSC_OK) {
        fprintf(stderr, "patch bench: the shadow pack: %s\n", err);
        return -1;
    }
    return 0;
}

/* The callgrind child takes the parent's shadow pack from this file (baking it again under valgrind, rays and
 * all, would take minutes a run). */
#define CG_PAO_ENV "PERISCOPE_BENCH_PAO"

/* b's character, frame buffers and shadow packs; plain: the pack without the rest correction too. */
static int setup(bench_t *b, bool plain)
{
    psc_bake_patch_opts_t o = {.actions = {"assets/thom/ResoluteWalk.act", "assets/thom/Wave.act"},
                               .action_count = 2, .skin_from = "assets/thom/Thom2.mdl", .quiet = true};
    char err[768];
    memset(b, 0, sizeof *b);
    if (psc_bake_patch_any("assets/thom/Thom.mdl", &o, &b->pf, err, sizeof err) != 0) {
        fprintf(stderr, "patch bench: %s (run from the repository)\n", err);
        return -1;
    }
    psc_3d_config_t cfg = {W, H, 0, 0, 16, 0x238E38E4u, PSC_Q16_ONE, 4 * PSC_Q16_ONE, limits.max_vertices, PSC_3D_HSR_ZBUFFER};
    b->ws_size = psc_patch_workspace_size(&b->pf.model, &limits);
    b->ws3d_size = psc_3d_workspace_size(&cfg);
    if (posix_memalign(&b->ws, 64, b->ws_size) != 0 || posix_memalign(&b->ws3d, 64, b->ws3d_size) != 0 ||
        posix_memalign(&b->pixels, 64, (size_t)W * H * 2) != 0 ||
        psc_patch_init(&b->p, &b->pf.model, &limits, b->ws, b->ws_size) != PSC_OK) {
        fprintf(stderr, "patch bench: out of memory\n");
        return -1;
    }
    psc_bake_shadow_opts_t so = {.levels = PSC_BAKE_SHADOW_LEVELS, .spheres = PSC_BAKE_SHADOW_SPHERES, .table = 32};
    psc_bake_shadow_opts_t po = so;
    po.no_rest = true;
    const char *given = getenv(CG_PAO_ENV);
    size_t plain_len;
    if (given != NULL) {
        psc_container_error_t e = {0};
        FILE *f = fopen(given, "rb");
        long n = f && fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
        int ok = n > 0 && fseek(f, 0, SEEK_SET) == 0 && posix_memalign((void **)&b->pao, 64, (size_t)n) == 0 &&
                 fread(b->pao, 1, (size_t)n, f) == (size_t)n;
        if (f)
            fclose(f);
        b->pao_len = ok ? (size_t)n : 0;
        if (!ok || psc_shadow_parse(b->pao, b->pao_len, &b->sm, &e) != PSC_OK ||
            posix_memalign(&b->sh_ws, 64, psc_shadow_workspace_size(&b->sm, &b->pf.model)) != 0 ||
            psc_shadow_init(&b->sh, &b->sm, &b->pf.model, b->sh_ws, psc_shadow_workspace_size(&b->sm, &b->pf.model)) !=
                PSC_OK) {
            fprintf(stderr, "patch bench: %s: not this character's shadow pack\n", given);
            return -1;
        }
    } else if (shadow_setup(b, &so, &b->pao, &b->pao_len, &b->sm, &b->sh, &b->sh_ws) != 0) {
        return -1;
    }
    return plain && shadow_setup(b, &po, &b->pao_plain, &plain_len, &b->sm_plain, &b->sh_plain, &b->sh_plain_ws) != 0
               ? -1
               : 0;
}

static void teardown(bench_t *b)
{
    free(b->ws);
    free(b->ws3d);
    free(b->pixels);
    free(b->pao);
    free(b->sh_ws);
    free(b->pao_plain);
    free(b->sh_plain_ws);
    psc_io_patch_free(&b->pf);
}

/* camera k of the run, and the 3D configuration that goes with it */
static void view(const bench_t *b, unsigned k, double tol_px, psc_patch_camera_t *cam, psc_3d_config_t *cfg)
{
    const psc_patch_model_t *m = &b->pf.model;
    psc_vec3_q16_t lo = {m->lo_q16[0], m->lo_q16[1], m->lo_q16[2]}, hi = {m->hi_q16[0], m->hi_q16[1], m->hi_q16[2]};
    *cfg = (psc_3d_config_t){W, H, 0, 0, 16, 0x238E38E4u, 0, 0, limits.max_vertices,
                             PSC_3D_HSR_ZBUFFER};
    *cam = (psc_patch_camera_t){0};
    psc_bam_t yaw = (psc_bam_t)(0x8E38E38Eu + k * 0x2222222u);   /* from 200 degrees, 3 degrees a frame */
    psc_3d_orbit(lo, hi, yaw, 0x071C71C7 / 16, 5 * PSC_Q16_ONE / 2, &cam->camera_from_object, &cfg->near_q16,
                 &cfg->far_q16);
    cam->focal_px_q16 = (int32_t)lround(W / 2.0 / tan(25.0 * M_PI / 180.0) * 65536.0);
    cam->tol_px_q16 = (int32_t)lround(tol_px * 65536.0);
    cam->near_q16 = cfg->near_q16;
    cam->cull = true;
}

static void draw(bench_t *b, const psc_mesh_t *meshes, unsigned n, const psc_patch_camera_t *cam,
                 const psc_3d_config_t *cfg)
{
    psc_3d_t r;
    psc_3d_draw_t d[PSC_PATCH_MAX_BATCHES];
    psc_surface_t out = {W, H, W * 2, PSC_PIX_RGB565, b->pixels};
    uint32_t bg = 0x30343Cu;
    psc_3d_init(&r, cfg, b->ws3d, b->ws3d_size);
    for (unsigned i = 0; i < n; i++) {
        psc_3d_draw_defaults(&d[i], &meshes[i]);
        d[i].camera_from_object = cam->camera_from_object;
        d[i].lit = true;
        d[i].light_dir = psc_vec3_normalize((psc_vec3_q16_t){PSC_PATCH_LIGHT_X, PSC_PATCH_LIGHT_Y, PSC_PATCH_LIGHT_Z});
        d[i].ambient_q8 = PSC_PATCH_AMBIENT_Q8;
    }
    psc_3d_render(&r, d, n, &bg, &out, NULL);
}

typedef struct {
    double pose, tess, draw;     /* ms per frame */
    double patches, triangles;   /* per frame */
    double shade, vertices;      /* self-shadowing ms per frame, vertices shaded */
} result_t;

static result_t run_animated(bench_t *b, double tol_px, psc_shadow_t *shadows)
{
    result_t best = {1e30, 1e30, 1e30, 0, 0, 0, 0};
    for (unsigned pass = 0; pass < PASSES; pass++) {
        double tp = 0, tt = 0, td = 0, ts = 0, patches = 0, tris = 0, verts = 0;
        for (unsigned k = 0; k < FRAMES; k++) {
            psc_patch_camera_t cam;
            psc_3d_config_t cfg;
            psc_patch_stats_t st;
            view(b, k, tol_px, &cam, &cfg);
            double t0 = bench_now_s();
            psc_patch_pose(&b->p, WAVE_ACTION, k * 1000u / 60u);
            psc_patch_tangents(&b->p);
            double t1 = bench_now_s();
            psc_patch_tessellate(&b->p, &cam, &st);
            double t2 = bench_now_s();
            if (shadows) {
                psc_shadow_update(shadows, &b->p);
                psc_shadow_apply(shadows, &b->p, PSC_SHADOW_STRENGTH_Q16, NULL);
                verts += shadows->shaded;
            }
            double t2s = bench_now_s();
            draw(b, b->p.batch, b->p.batch_count, &cam, &cfg);
            double t3 = bench_now_s();
            tp += t1 - t0;
            tt += t2 - t1;
            ts += t2s - t2;
            td += t3 - t2s;
            patches += st.patches;
            tris += st.triangles;
        }
        if (tp + tt + td + ts < best.pose + best.tess + best.draw + best.shade)
            best = (result_t){tp / FRAMES * 1e3, tt / FRAMES * 1e3, td / FRAMES * 1e3, patches / FRAMES,
                              tris / FRAMES, ts / FRAMES * 1e3, verts / FRAMES};
    }
    return best;
}

/* The reference: the rest pose tessellated once at 0.5 px, drawn as a static mesh every frame. */
static result_t run_static(bench_t *b)
{
    psc_patch_camera_t cam;
    psc_3d_config_t cfg;
    psc_patch_stats_t st;
    view(b, 0, 0.5, &cam, &cfg);
    cam.cull = false;   /* a static mesh must hold every side */
    psc_patch_pose(&b->p, -1, 0);
    psc_patch_tangents(&b->p);
    psc_patch_tessellate(&b->p, &cam, &st);
    psc_mesh_t meshes[PSC_PATCH_MAX_BATCHES];
    unsigned n = b->p.batch_count;
    int32_t *pos[PSC_PATCH_MAX_BATCHES];
    for (unsigned i = 0; i < n; i++) {   /* copies: the tessellator's output is reused below */
        meshes[i] = b->p.batch[i];
        pos[i] = malloc(12u * meshes[i].vertex_count);
        memcpy(pos[i], meshes[i].position_q16, 12u * meshes[i].vertex_count);
        meshes[i].position_q16 = pos[i];
    }
    result_t best = {0, 0, 1e30, 0, st.triangles, 0, 0};
    for (unsigned pass = 0; pass < PASSES; pass++) {
        double td = 0;
        for (unsigned k = 0; k < FRAMES; k++) {
            view(b, k, 0.5, &cam, &cfg);
            double t0 = bench_now_s();
            draw(b, meshes, n, &cam, &cfg);
            td += bench_now_s() - t0;
        }
        if (td / FRAMES * 1e3 < best.draw)
            best.draw = td / FRAMES * 1e3;
    }
    for (unsigned i = 0; i < n; i++)
        free(pos[i]);
    return best;
}

static int run_table(const char *out_dir)
{
    bench_t b;
    if (setup(&b, true) != 0)
        return 1;
    static const double tols[] = {0.25, 0.5, 1.0};
    result_t r[3], s, sh, shp;
    for (unsigned i = 0; i < 3; i++)
        r[i] = run_animated(&b, tols[i], NULL);
    sh = run_animated(&b, 0.5, &b.sh);
    shp = run_animated(&b, 0.5, &b.sh_plain);
    s = run_static(&b);
    printf("Hash patches: Thom (%u patches, %u CPs, %u bones) playing Wave.act at %ux%u, RGB565, one core,\n"
           "%u frames at 60 Hz, camera turning 3 degrees a frame, best of %u passes (ms per frame):\n\n",
           (unsigned)b.pf.model.face_count, (unsigned)b.pf.model.cp_count, (unsigned)b.pf.model.bone_count, W, H,
           FRAMES, PASSES);
    printf("| | pose+tangents | tessellate | draw | total | frames/s | patches/s | triangles/frame | triangles/s |\n"
           "|---|---|---|---|---|---|---|---|---|\n");
    for (unsigned i = 0; i < 3; i++) {
        double total = r[i].pose + r[i].tess + r[i].draw;
        printf("| patches, %.2f px | %.3f | %.3f | %.3f | %.3f | %.0f | %.0f | %.0f | %.2fM |\n", tols[i], r[i].pose,
               r[i].tess, r[i].draw, total, 1e3 / total, r[i].patches * 1e3 / total, r[i].triangles,
               r[i].triangles / total / 1e3);
    }
    printf("| static mesh (rest, 0.5 px) | - | - | %.3f | %.3f | %.0f | - | %.0f | %.2fM |\n\n", s.draw, s.draw,
           1e3 / s.draw, s.triangles, s.triangles / s.draw / 1e3);
    double plain = r[1].pose + r[1].tess + r[1].draw, shaded = sh.pose + sh.tess + sh.draw + sh.shade;
    printf("Self-shadowing (%u spheres on %u levels, maps %ux%u and %u^3; composed at the patches' corners: %s) at 0.5 px:\n"
           "%.3f ms per frame for %.0f vertices (%.0f ns a vertex); the frame %.3f ms with it, %.3f without: +%.0f %%\n"
           "(goal: at most +25 %%).\n"
           "The spheres alone (no rest correction): %.3f ms per frame; the correction (gain %.3f) costs %+.0f %% of "
           "the shading.\n\n",
           (unsigned)b.sm.sphere_count, (unsigned)b.sm.level_count, (unsigned)b.sm.access_omega,
           (unsigned)b.sm.access_theta, (unsigned)b.sm.comp_theta, b.sh.at_corners ? "yes" : "no", sh.shade, sh.vertices, sh.vertices > 0 ? sh.shade * 1e6 / sh.vertices : 0, shaded, plain,
           (shaded / plain - 1) * 100, shp.shade, b.sm.rest_gain_q16 / 65536.0,
           shp.shade > 0 ? (sh.shade / shp.shade - 1) * 100 : 0);
    double t05 = r[1].pose + r[1].tess + r[1].draw;
    psc_3d_config_t cfg = {W, H, 0, 0, 16, 0x238E38E4u, PSC_Q16_ONE, 4 * PSC_Q16_ONE, limits.max_vertices, PSC_3D_HSR_ZBUFFER};
    printf("At 0.5 px the animated character costs %.2fx the static mesh's frame; %.0f frames/s (goal: 60).\n"
           "Memory: patch workspace %zu bytes (limits %u vertices, %u triangles), 3D workspace at %ux%u %zu bytes,\n"
           "the pack %zu bytes.\n",
           t05 / s.draw, 1e3 / t05, b.ws_size, limits.max_vertices, limits.max_triangles, W, H,
           psc_3d_workspace_size(&cfg), b.pf.len);
    char path[512];
    snprintf(path, sizeof path, "%s/patch.json", out_dir);
    FILE *j = fopen(path, "w");
    if (j) {
        fprintf(j, "{\n  \"benchmark\": \"patch\",\n  \"size\": \"%ux%u\",\n  \"frames\": %u,\n  \"rows\": [\n", W, H,
                FRAMES);
        for (unsigned i = 0; i < 3; i++)
            fprintf(j, "    {\"tol_px\": %.2f, \"pose_ms\": %.4f, \"tessellate_ms\": %.4f, \"draw_ms\": %.4f, "
                       "\"triangles\": %.0f},\n", tols[i], r[i].pose, r[i].tess, r[i].draw, r[i].triangles);
        fprintf(j, "    {\"static_mesh\": true, \"draw_ms\": %.4f, \"triangles\": %.0f}\n  ],\n"
                   "  \"workspace_bytes\": %zu\n}\n", s.draw, s.triangles, b.ws_size);
        fclose(j);
    }
    teardown(&b);
    return 0;
}

/* ---- callgrind -------------------------------------------------------------------------------------------- */

static double cg_vertices;

__attribute__((noinline)) static void cg_frames(bench_t *b)
{
    for (unsigned k = 0; k < CG_FRAMES; k++) {
        psc_patch_camera_t cam;
        psc_3d_config_t cfg;
        view(b, k, 0.5, &cam, &cfg);
        psc_patch_pose(&b->p, WAVE_ACTION, 500u + k * 1000u / 60u);
        psc_patch_tangents(&b->p);
        psc_patch_tessellate(&b->p, &cam, NULL);
        psc_shadow_update(&b->sh, &b->p);
        psc_shadow_apply(&b->sh, &b->p, PSC_SHADOW_STRENGTH_Q16, NULL);
        cg_vertices += b->sh.shaded;
        draw(b, b->p.batch, b->p.batch_count, &cam, &cfg);
    }
}

static int cg_child(void)
{
    bench_t b;
    if (setup(&b, false) != 0)
        return 1;
    cg_frames(&b);
    printf("vertices %.0f\n", cg_vertices);
    teardown(&b);
    return 0;
}

static int run_callgrind(const char *self, const char *out_dir)
{
    if (bench_callgrind_require("patch") != 0)
        return 1;
    static const char *const fns[] = {"cg_frames", "psc_patch_pose", "psc_patch_tangents", "psc_patch_tessellate",
                                      "psc_3d_render", "psc_shadow_apply"};
    double ir[6];
    /* the shadow pack baked here, once, natively; the children read it */
    bench_t b;
    char pao_path[] = "/tmp/periscope-bench-XXXXXX";
    int fd = -1;
    if (setup(&b, false) != 0)
        return 1;
    FILE *f = (fd = mkstemp(pao_path)) >= 0 ? fdopen(fd, "wb") : NULL;
    int wrote = f && fwrite(b.pao, 1, b.pao_len, f) == b.pao_len;
    if (f ? fclose(f) != 0 : (fd >= 0 && close(fd) != 0))
        wrote = 0;
    teardown(&b);
    if (!wrote || setenv(CG_PAO_ENV, pao_path, 1) != 0) {
        fprintf(stderr, "patch bench: cannot write %s\n", pao_path);
        if (fd >= 0)
            unlink(pao_path);
        return 1;
    }
    int rc = bench_callgrind_counts("patch", self, fns, 6, ir);
    unlink(pao_path);
    unsetenv(CG_PAO_ENV);
    if (rc != 0)
        return 1;
    printf("Hash patches under callgrind: Thom waving at %ux%u, 0.5 px, %u frames: instructions per frame\n"
           "total %.0f = pose %.0f + tangents %.0f + tessellate %.0f + self-shadowing %.0f + draw %.0f\n",
           W, H, CG_FRAMES, ir[0] / CG_FRAMES, ir[1] / CG_FRAMES, ir[2] / CG_FRAMES, ir[3] / CG_FRAMES,
           ir[5] / CG_FRAMES, ir[4] / CG_FRAMES);
    char path[512];
    snprintf(path, sizeof path, "%s/patch-callgrind.json", out_dir);
    FILE *j = fopen(path, "w");
    if (j) {
        fprintf(j, "{\n  \"benchmark\": \"patch-callgrind\",\n  \"frames\": %u,\n  \"per_frame\": {\"total\": %.0f, "
                   "\"pose\": %.0f, \"tangents\": %.0f, \"tessellate\": %.0f, \"draw\": %.0f}\n}\n",
                CG_FRAMES, ir[0] / CG_FRAMES, ir[1] / CG_FRAMES, ir[2] / CG_FRAMES, ir[3] / CG_FRAMES,
                ir[4] / CG_FRAMES);
        fclose(j);
    }
    return 0;
}

int main(int argc, char **argv)
{
    static const bench_cli_t cli = {"patch", run_table, run_callgrind, cg_child};
    return bench_cli_main(&cli, argc, argv);
}
