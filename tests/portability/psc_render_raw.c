/* SPDX-License-Identifier: MIT */
/*
 * psc-render-raw - the bit-exact portability probe: renders views of a scene
 * pack through core alone (psc_pack_parse, psc_viewer_*) and writes the raw
 * surface bytes, so that it links with nothing but libc and builds for every
 * architecture, even one without multiarch image libraries (riscv64 on
 * Debian 12). tests/portability/run.sh runs it natively and under qemu-user
 * and compares the bytes.
 *
 *   psc-render-raw PACK OUT.raw VIEW...
 *   VIEW = FORMAT,FILTER,SPAN_LOG2,YAW,PITCH,HFOV
 *     FORMAT rgb565 | xrgb8888, FILTER nearest | bilinear | mip,
 *     YAW and HFOV binary angles (2^32 per turn, unsigned decimal),
 *     PITCH a signed binary angle (2^30 = 90 degrees, decimal).
 * Angles are integers so that no floating-point conversion sits between the
 * command line and core. Every view is brought inside the pack's limits
 * (psc_viewer_clamp) and rendered at the pack's display size; OUT.raw holds
 * the frames one after another, rows packed (stride = width x bytes per pixel).
 * A tiled pack's tiles are all made resident from the file itself (raw tiles:
 * its tile store, read whole), so its frames go through the tiled spans and
 * kernels.
 * A patch pack (core/patch/psc_patch.h) instead (PACK.ppk, or
 * PACK.ppk,SHADOW.pao for its self-shadowing too): a character posed, its
 * patches tessellated and drawn by the 3D pipeline at 160x120,
 *   VIEW = FORMAT,ACTION,TIME_MS,YAW,PITCH,TOL_PX_Q16[,LOOK]
 *     ACTION an index into the pack's actions or -1 (the rest pose), the
 *     orbit camera at 2.5 R with hfov 50 degrees; LOOK phong, aa (the
 *     A-buffer, 32-pixel tiles with 16 KB each) or phong+aa.
 * A proxy pack (core/proxy/psc_proxy.h, PACK.ppx): the model posed at its
 * animation's time and drawn at 160x120 as its proxies, full mesh or billboard,
 *   VIEW = FORMAT,LOD,TIME_US,YAW,PITCH,DIST_Q16[,relit]
 *     LOD 0 proxies, 1 full, 2 billboard; TIME_US -1 for the rest pose;
 *     relit: lit from the side (psc_proxy_set_light), else as baked.
 * Exit status: 0 done, 1 the work failed, 2 bad arguments.
 */
#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_render.h"
#include "morph/psc_morph.h"
#include "pack/psc_pack.h"
#include "patch/psc_patch_frame.h"
#include "proxy/psc_proxy.h"
#include "shadow/psc_shadow_frame.h"
#include "viewer/psc_viewer.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PROG "psc-render-raw"

static int fail(const char *what, const char *detail)
{
    fprintf(stderr, PROG ": %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    return 1;
}

/* The whole file in 64-byte aligned memory (the pack parser wants aligned tables). */
static void *read_file(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    void *buf = NULL;
    long n;

    if (!f)
        return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) > 0 && fseek(f, 0, SEEK_SET) == 0 &&
        posix_memalign(&buf, 64, (size_t)n) == 0) {
        if (fread(buf, 1, (size_t)n, f) == (size_t)n) {
            *len = (size_t)n;
        } else {
            free(buf);
            buf = NULL;
        }
    }
    fclose(f);
    return buf;
}

static int parse_u32(const char *s, uint32_t *out)
{
    char *end;
    unsigned long long v;

    errno = 0;
    v = strtoull(s, &end, 10);
    if (errno != 0 || end == s || *end != '\0' || s[0] == '-' || v > 0xffffffffull)
        return -1;
    *out = (uint32_t)v;
    return 0;
}

static int parse_i32(const char *s, int32_t *out)
{
    char *end;
    long long v;

    errno = 0;
    v = strtoll(s, &end, 10);
    if (errno != 0 || end == s || *end != '\0' || v < INT32_MIN || v > INT32_MAX)
        return -1;
    *out = (int32_t)v;
    return 0;
}

/* "FORMAT,FILTER,SPAN_LOG2,YAW,PITCH,HFOV" -> view and format; -1 if malformed. */
static int parse_view(char *spec, psc_view_t *view, psc_pixfmt_t *format)
{
    char *field[6];
    uint32_t span;
    unsigned n = 0;

    for (char *tok = strtok(spec, ","); tok && n < 6; tok = strtok(NULL, ","))
        field[n++] = tok;
    if (n != 6 || strtok(NULL, ",") != NULL)
        return -1;
    if (strcmp(field[0], "rgb565") == 0)
        *format = PSC_PIX_RGB565;
    else if (strcmp(field[0], "xrgb8888") == 0)
        *format = PSC_PIX_XRGB8888;
    else
        return -1;
    if (strcmp(field[1], "nearest") == 0)
        view->filter = PSC_FILTER_NEAREST;
    else if (strcmp(field[1], "bilinear") == 0)
        view->filter = PSC_FILTER_BILINEAR;
    else if (strcmp(field[1], "mip") == 0)
        view->filter = PSC_FILTER_MIP;
    else
        return -1;
    if (parse_u32(field[2], &span) != 0 || span > 4 || parse_u32(field[3], &view->yaw) != 0 ||
        parse_i32(field[4], &view->pitch) != 0 || parse_u32(field[5], &view->hfov) != 0)
        return -1;
    view->span_log2 = (uint8_t)span;
    return 0;
}

/* A tiled pack's viewer, every tile resident in the file's own bytes (buf, len: the whole file). */
static psc_status_t init_tiled(psc_viewer_t *viewer, const psc_pack_t *pack, const uint8_t *buf, size_t len,
                               psc_tiles_t *tiles, const void ***resident, void *ws, size_t ws_size)
{
    if (pack->tile_codec != PSC_TILE_CODEC_RAW || pack->store_offset > len || len - pack->store_offset < pack->store_size)
        return PSC_ERR_CORRUPT;   /* (psc_pack_parse checked every tile lies inside the store) */
    *tiles = pack->tiles;
    *resident = calloc(tiles->tile_count, sizeof **resident);
    if (!*resident)
        return PSC_ERR_NOMEM;
    for (uint32_t i = 0; i < tiles->tile_count; i++)
        (*resident)[i] = buf + pack->store_offset + pack->tile_index[i].offset;
    tiles->resident = *resident;
    return psc_viewer_init_tiled(viewer, &pack->map, tiles, pack->luts, pack->lut_count, pack->display_width,
                                 pack->display_height, ws, ws_size);
}

static int render_views(const psc_pack_t *pack, const uint8_t *buf, size_t len, FILE *out, char **specs, int count)
{
    uint16_t w = pack->display_width, h = pack->display_height;
    size_t ws_size = pack->tiled ? psc_viewer_workspace_size_tiled(w, h, &pack->map)
                                 : psc_viewer_workspace_size(w, h, &pack->map);
    size_t frame_max = (size_t)w * h * 4;
    void *ws = NULL, *pixels = NULL;
    const void **resident = NULL;
    psc_tiles_t tiles;
    psc_viewer_t viewer;
    psc_status_t s;
    int rc = 1;

    if (posix_memalign(&ws, 64, ws_size) != 0 || posix_memalign(&pixels, 64, frame_max) != 0) {
        rc = fail("out of memory", NULL);
    } else if (pack->tiled ? (s = init_tiled(&viewer, pack, buf, len, &tiles, &resident, ws, ws_size)) != PSC_OK
                           : (s = psc_viewer_init(&viewer, &pack->map, pack->luts, pack->lut_count, w, h, ws,
                                                  ws_size)) != PSC_OK ||
                                 (s = psc_viewer_set_levels(&viewer, pack->levels, pack->level_count)) != PSC_OK) {
        rc = fail("cannot set up the viewer", psc_status_str(s));
    } else {
        rc = 0;
        for (int i = 0; i < count && rc == 0; i++) {
            psc_view_t view = {0};
            psc_pixfmt_t format;
            if (parse_view(specs[i], &view, &format) != 0) {
                fprintf(stderr, PROG ": bad view '%s' (FORMAT,FILTER,SPAN_LOG2,YAW,PITCH,HFOV)\n", specs[i]);
                rc = 2;
                break;
            }
            uint32_t bpp = psc_pixfmt_bytes(format);
            psc_surface_t surf = {.width = w, .height = h, .stride = (uint32_t)w * bpp, .format = format,
                                  .pixels = pixels};
            memset(pixels, 0, frame_max);
            psc_viewer_clamp(&viewer, &view, pack->hfov_min);
            if ((s = psc_viewer_render(&viewer, &view, &surf)) != PSC_OK)
                rc = fail("rendering failed", psc_status_str(s));
            else if (fwrite(pixels, 1, (size_t)surf.stride * h, out) != (size_t)surf.stride * h)
                rc = fail("cannot write the output", strerror(errno));
        }
    }
    free(resident);
    free(pixels);
    free(ws);
    return rc;
}

/* ---- patch packs ---------------------------------------------------------------------------------------- */

#define PATCH_W 160u
#define PATCH_H 120u

#define PATCH_ABUF_BYTES (16u << 10)

static int render_patch_view(const psc_patch_model_t *m, psc_patch_t *p, psc_shadow_t *sh, void *ws3d,
                             size_t ws3d_size, void *abuf, char *spec, void *pixels, FILE *out)
{
    char *field[7];
    unsigned n = 0;
    int32_t action, pitch, tol;
    uint32_t time_ms, yaw;
    psc_pixfmt_t format;

    for (char *tok = strtok(spec, ","); tok && n < 7; tok = strtok(NULL, ","))
        field[n++] = tok;
    bool phong = n == 7 && strstr(field[6], "phong") != NULL, aa = n == 7 && strstr(field[6], "aa") != NULL;
    bool area = n == 7 && strstr(field[6], "area") != NULL;
    if ((n != 6 && n != 7) || (strcmp(field[0], "rgb565") != 0 && strcmp(field[0], "xrgb8888") != 0) ||
        parse_i32(field[1], &action) != 0 || parse_u32(field[2], &time_ms) != 0 || parse_u32(field[3], &yaw) != 0 ||
        parse_i32(field[4], &pitch) != 0 || parse_i32(field[5], &tol) != 0 || tol <= 0) {
        fprintf(stderr, PROG ": bad view (FORMAT,ACTION,TIME_MS,YAW,PITCH,TOL_PX_Q16)\n");
        return 2;
    }
    format = strcmp(field[0], "rgb565") == 0 ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888;
    psc_bam_t hfov = 0x238E38E4u;   /* 50 degrees */
    psc_3d_config_t cfg = {PATCH_W, PATCH_H, aa || area ? 32 : 0, aa || area ? 32 : 0, 32, hfov, 0, 0,
                           PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES,
                           area ? PSC_3D_HSR_AREA : PSC_3D_HSR_ZBUFFER};
    psc_vec3_q16_t lo = {m->lo_q16[0], m->lo_q16[1], m->lo_q16[2]}, hi = {m->hi_q16[0], m->hi_q16[1], m->hi_q16[2]};
    psc_patch_camera_t cam = {0};
    psc_status_t s = psc_3d_orbit(lo, hi, yaw, pitch, 5 * PSC_Q16_ONE / 2, &cam.camera_from_object, &cfg.near_q16,
                                  &cfg.far_q16);
    int32_t s30, c30;
    psc_sincos(hfov / 2u, &s30, &c30);
    cam.focal_px_q16 = (int32_t)psc_div_round64((int64_t)PATCH_W * 32768 * c30, s30);
    cam.tol_px_q16 = tol;
    cam.near_q16 = cfg.near_q16;
    cam.cull = true;
    psc_3d_t r;
    if (s == PSC_OK) {
        psc_patch_pose(p, action, time_ms);
        psc_patch_tangents(p);
        s = psc_patch_tessellate(p, &cam, NULL);
    }
    if (s == PSC_OK && sh) {
        psc_shadow_update(sh, p);
        psc_shadow_apply(sh, p, PSC_SHADOW_STRENGTH_Q16, NULL);
    }
    if (s == PSC_OK)
        s = psc_3d_init(&r, &cfg, ws3d, ws3d_size);
    if (s == PSC_OK && aa)
        s = psc_3d_set_abuffer(&r, abuf, PATCH_ABUF_BYTES);
    psc_surface_t surf = {PATCH_W, PATCH_H, PATCH_W * psc_pixfmt_bytes(format), format, pixels};
    if (s == PSC_OK) {
        psc_3d_draw_t d[PSC_PATCH_MAX_BATCHES];
        unsigned draws = psc_patch_draws(p, &cam, d);
        for (unsigned i = 0; i < draws && phong; i++) {
            d[i].shade = PSC_SHADE_PHONG;
            d[i].specular_q8 = 90;
            d[i].shininess = 24;
        }
        uint32_t bg = 0x30343Cu;
        s = psc_3d_render(&r, d, draws, &bg, &surf, NULL);
    }
    if (s != PSC_OK)
        return fail("patch frame failed", psc_status_str(s));
    size_t bytes = (size_t)surf.stride * PATCH_H;
    return fwrite(pixels, 1, bytes, out) == bytes ? 0 : fail("cannot write the output", strerror(errno));
}

static int render_patch(const void *buf, size_t len, const void *sbuf, size_t slen, FILE *out, char **specs,
                        int count)
{
    psc_shadow_model_t sm;
    psc_shadow_t sh;
    void *sh_ws = NULL;
    psc_patch_model_t m;
    psc_container_error_t e;
    psc_patch_limits_t lim = {PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES, 1u << 20, PSC_PATCH_MAX_DEPTH};
    /* sized for tiles and area subdivision too (the aa and area views use them) */
    psc_3d_config_t cfg = {PATCH_W, PATCH_H, 32, 32, 32, 0x238E38E4u, PSC_Q16_ONE, 4 * PSC_Q16_ONE,
                           PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES, PSC_3D_HSR_AREA};
    psc_patch_t p;
    void *ws = NULL, *ws3d = NULL, *pixels = NULL, *abuf = NULL;
    int rc = 1;

    if (psc_patch_parse(buf, len, &m, &e) != PSC_OK)
        return fail("not a valid patch pack", e.what);
    size_t ws_size = psc_patch_workspace_size(&m, &lim), ws3d_size = psc_3d_workspace_size(&cfg);
    if (posix_memalign(&ws, 64, ws_size) != 0 || posix_memalign(&ws3d, 64, ws3d_size) != 0 ||
        posix_memalign(&pixels, 64, PATCH_W * PATCH_H * 4) != 0 || posix_memalign(&abuf, 64, PATCH_ABUF_BYTES) != 0) {
        rc = fail("out of memory", NULL);
    } else if (psc_patch_init(&p, &m, &lim, ws, ws_size) != PSC_OK) {
        rc = fail("cannot set up the tessellator", NULL);
    } else if (sbuf && (psc_shadow_parse(sbuf, slen, &sm, &e) != PSC_OK ||
                        posix_memalign(&sh_ws, 64, psc_shadow_workspace_size(&sm, &m)) != 0 ||
                        psc_shadow_init(&sh, &sm, &m, sh_ws, psc_shadow_workspace_size(&sm, &m)) != PSC_OK)) {
        rc = fail("not a usable shadow pack for this character", NULL);
    } else {
        rc = 0;
        for (int i = 0; i < count && rc == 0; i++)
            rc = render_patch_view(&m, &p, sbuf ? &sh : NULL, ws3d, ws3d_size, abuf, specs[i], pixels, out);
    }
    free(sh_ws);
    free(pixels);
    free(ws3d);
    free(abuf);
    free(ws);
    return rc;
}

/* Proxy frames at 160 x 120 (the patch frames' size). */
static int render_proxy(const void *buf, size_t len, FILE *out, char **specs, int count)
{
    psc_proxy_model_t m;
    psc_container_error_t e;
    if (psc_proxy_parse(buf, len, &m, &e) != PSC_OK)
        return fail("not a valid proxy pack", e.what);
    size_t np = psc_proxy_workspace_size(&m);
    psc_3d_config_t cfg = {PATCH_W, PATCH_H, 0, 0, 32, 0x238E38E4u, PSC_Q16_ONE, 4 * PSC_Q16_ONE,
                           psc_proxy_max_vertices(&m), PSC_3D_HSR_ZBUFFER};
    size_t n3 = psc_3d_workspace_size(&cfg);
    void *ws = NULL, *ws3d = NULL, *pixels = NULL;
    psc_mat4_q16_t *skin = malloc(m.joint_count * sizeof *skin);
    psc_proxy_t p;
    int rc = 1;
    if (!skin || posix_memalign(&ws, 64, np) != 0 || posix_memalign(&ws3d, 64, n3) != 0 ||
        posix_memalign(&pixels, 64, PATCH_W * PATCH_H * 4) != 0 || psc_proxy_init(&p, &m, ws, np) != PSC_OK) {
        rc = fail("out of memory", NULL);
        goto done;
    }
    psc_vec3_q16_t lo, hi;
    psc_proxy_rest_bounds(&m, &lo, &hi);
    psc_proxy_set_focal(&p, psc_proxy_focal_px_q16(PATCH_W, cfg.hfov));   /* the mip levels too */
    rc = 0;
    for (int i = 0; i < count && rc == 0; i++) {
        char fmt[16];
        int lod;
        long long t_us, pitch;
        unsigned long long yaw;
        long dist;
        char look[16] = "";
        int fields = sscanf(specs[i], "%15[^,],%d,%lld,%llu,%lld,%ld,%15s", fmt, &lod, &t_us, &yaw, &pitch, &dist, look);
        if (fields < 6 || (fields == 7 && strcmp(look, "relit") != 0) || lod < 0 || lod > 2 ||
            (strcmp(fmt, "rgb565") != 0 && strcmp(fmt, "xrgb8888") != 0)) {
            rc = fail("bad proxy view", specs[i]);
            break;
        }
        psc_pixfmt_t format = strcmp(fmt, "rgb565") == 0 ? PSC_PIX_RGB565 : PSC_PIX_XRGB8888;
        psc_mat4_q16_t cam;
        psc_3d_t r;
        const psc_3d_draw_t *d;
        unsigned nd;
        psc_surface_t surf = {PATCH_W, PATCH_H, PATCH_W * psc_pixfmt_bytes(format), format, pixels};
        uint32_t bg = 0x30343Cu;
        psc_proxy_pose_at(&m, t_us, skin);
        static const int32_t side[3] = {-64000, 11380, 9000};
        psc_status_t s = psc_proxy_set_light(&p, fields == 7 ? side : NULL, 5000);
        if (s == PSC_OK)
            s = psc_3d_orbit(lo, hi, (psc_bam_t)yaw, (int32_t)pitch, (int32_t)dist, &cam, &cfg.near_q16,
                             &cfg.far_q16);
        if (s == PSC_OK)
            s = psc_3d_init(&r, &cfg, ws3d, n3);
        if (s == PSC_OK)
            s = psc_proxy_frame(&p, skin, &cam, (psc_proxy_lod_t)lod, false, &d, &nd);
        if (s == PSC_OK)
            s = psc_3d_render(&r, d, nd, &bg, &surf, NULL);
        if (s != PSC_OK) {
            rc = fail("proxy frame failed", psc_status_str(s));
            break;
        }
        size_t bytes = (size_t)surf.stride * PATCH_H;
        if (fwrite(pixels, 1, bytes, out) != bytes)
            rc = fail("cannot write the output", strerror(errno));
    }
done:
    free(skin), free(ws), free(ws3d), free(pixels);
    return rc;
}

/* ---- the 3D pipeline's newer parts: blend shapes, translucency, area subdivision, rows by several workers ---- */

#define FEAT_W 96
#define FEAT_H 72
#define FEAT_SHEETS 6
#define FEAT_NV 200
#define FEAT_NT 5

static uint32_t lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

/* Blend shapes on pseudo-random sparse targets and weights: the positions and normals, raw. */
static int feature_morph(FILE *out)
{
    static int32_t base[3 * FEAT_NV], dpos[FEAT_NT][3 * FEAT_NV], dn[FEAT_NT][3 * FEAT_NV], pos[3 * FEAT_NV],
        sum[3 * FEAT_NV];
    static int16_t nb[3 * FEAT_NV], nrm[3 * FEAT_NV];
    static uint32_t vert[FEAT_NT][FEAT_NV];
    psc_morph_target_t t[FEAT_NT];
    int32_t w[FEAT_NT];
    uint32_t seed = 7;
    for (unsigned i = 0; i < 3 * FEAT_NV; i++) {
        base[i] = (int32_t)(lcg(&seed) % 524288u) - 262144;
        nb[i] = (int16_t)((int32_t)(lcg(&seed) % 16384u) - 8192);
    }
    for (unsigned k = 0; k < FEAT_NT; k++) {
        uint32_t c = 0;
        for (uint32_t v = 0; v < FEAT_NV; v++)
            if (lcg(&seed) % 3u == 0) {
                vert[k][c] = v;
                for (unsigned a = 0; a < 3; a++) {
                    dpos[k][3 * c + a] = (int32_t)(lcg(&seed) % 131072u) - 65536;
                    dn[k][3 * c + a] = (int32_t)(lcg(&seed) % 16384u) - 8192;
                }
                c++;
            }
        t[k] = (psc_morph_target_t){c, vert[k], dpos[k], dn[k]};
        w[k] = (int32_t)(lcg(&seed) % 196608u) - 98304;
    }
    psc_morph_t m = {FEAT_NV, base, nb, FEAT_NT, t};
    if (psc_morph_check(&m) != PSC_OK || psc_morph_apply(&m, w, pos, nrm, sum) != PSC_OK)
        return fail("--features", "the morph failed");
    fwrite(pos, sizeof pos, 1, out);
    fwrite(nrm, sizeof nrm, 1, out);
    return 0;
}

/* Sheets at random depths, some translucent, in a frame: hsr, tiles, A-buffer, and the rows split between two
 * workers (core's frame steps, as the threads call them) when split. */
static int feature_frame(FILE *out, uint8_t hsr, uint16_t tile, bool aa, bool split, uint32_t *pixels)
{
    static int32_t pos[FEAT_SHEETS][4][3];
    static uint32_t col[FEAT_SHEETS][4];
    static uint16_t idx[FEAT_SHEETS][6];
    static psc_mesh_t mesh[FEAT_SHEETS];
    psc_3d_draw_t d[FEAT_SHEETS];
    uint32_t seed = 99;
    for (unsigned k = 0; k < FEAT_SHEETS; k++) {
        int32_t z = (int32_t)(65536 + lcg(&seed) % 262144u), x0 = (int32_t)(lcg(&seed) % 65536u) - 49152,
                y0 = (int32_t)(lcg(&seed) % 65536u) - 49152, wd = (int32_t)(20000 + lcg(&seed) % 60000u);
        int32_t xs[4] = {x0, x0 + wd, x0 + wd, x0}, ys[4] = {y0, y0, y0 + wd, y0 + wd};
        for (unsigned v = 0; v < 4; v++) {
            pos[k][v][0] = (int32_t)((int64_t)xs[v] * z >> 16);
            pos[k][v][1] = (int32_t)((int64_t)ys[v] * z >> 16);
            pos[k][v][2] = z + (int32_t)(v * 3000u);
            col[k][v] = lcg(&seed) & 0xFFFFFFu;
        }
        static const uint16_t q[6] = {0, 1, 2, 0, 2, 3};
        memcpy(idx[k], q, sizeof q);
        mesh[k] = (psc_mesh_t){.vertex_count = 4, .triangle_count = 2, .position_q16 = &pos[k][0][0],
                               .color = col[k], .index = idx[k]};
        psc_3d_draw_defaults(&d[k], &mesh[k]);
        d[k].cull_back = false;
        if (k % 2u == 1u) {
            d[k].blend = PSC_BLEND_ALPHA;
            d[k].opacity_q8 = (uint16_t)(40u + lcg(&seed) % 200u);
        }
    }
    psc_3d_config_t cfg = {FEAT_W, FEAT_H, tile, tile, 16, 0x238E38E4u, PSC_Q16_ONE / 8, 16 * PSC_Q16_ONE,
                           4 * FEAT_SHEETS, hsr};
    size_t n = psc_3d_workspace_size(&cfg), wn = psc_3d_worker_bytes(&cfg), ab = psc_3d_abuffer_bytes(&cfg, 4000);
    void *ws = NULL, *wws = NULL, *abuf = NULL, *abuf2 = NULL;
    psc_3d_t r;
    psc_3d_worker_t w2;
    psc_surface_t sf = {FEAT_W, FEAT_H, FEAT_W * 4, PSC_PIX_XRGB8888, pixels};
    uint32_t bg = 0x203040;
    psc_3d_stats_t st = {0}, st2 = {0};
    int rc = 0;
    if (posix_memalign(&ws, 64, n) != 0 || posix_memalign(&wws, 64, wn) != 0 || posix_memalign(&abuf, 64, ab) != 0 ||
        posix_memalign(&abuf2, 64, ab) != 0 || psc_3d_init(&r, &cfg, ws, n) != PSC_OK ||
        psc_3d_worker_init(&w2, &cfg, wws, wn) != PSC_OK ||
        (aa && (psc_3d_set_abuffer(&r, abuf, ab) != PSC_OK || psc_3d_worker_set_abuffer(&w2, &cfg, abuf2, ab) != PSC_OK))) {
        rc = fail("--features", "cannot set up the renderer");
    } else if (!split) {
        if (psc_3d_render(&r, d, FEAT_SHEETS, &bg, &sf, &st) != PSC_OK)
            rc = fail("--features", "rendering failed");
    } else if (psc_3d_frame_begin(&r, d, FEAT_SHEETS, &bg, &sf, &st) != PSC_OK) {
        rc = fail("--features", "rendering failed");
    } else {
        psc_3d_frame_vertices(&r, 1, 2); /* the parts in another order than one thread's */
        psc_3d_frame_vertices(&r, 0, 2);
        psc_3d_frame_ready(&r, 2);
        psc_3d_frame_triangles(&r, 1, &st2);
        psc_3d_frame_triangles(&r, 0, &st);
        for (uint32_t row = psc_3d_frame_rows(&r); row-- > 0;)
            psc_3d_frame_row(&r, row % 2u ? &w2 : &r.own, row, row % 2u ? &st2 : &st);
    }
    if (rc == 0)
        fwrite(pixels, (size_t)FEAT_W * FEAT_H * 4u, 1, out);
    free(ws), free(wws), free(abuf), free(abuf2);
    return rc;
}

/* --features OUT.raw: the morph, then frames: z-buffer, area, tiles + A-buffer, the same split between two
 * workers, area + A-buffer in tiles split (each pair of frames must match: checked here, and across machines by
 * the caller's comparison of the whole file). */
static int render_features(const char *path)
{
    FILE *out = fopen(path, "wb");
    if (!out)
        return fail(path, strerror(errno));
    static uint32_t a[FEAT_W * FEAT_H], b[FEAT_W * FEAT_H];
    int rc = feature_morph(out);
    if (rc == 0)
        rc = feature_frame(out, PSC_3D_HSR_ZBUFFER, 0, false, false, a);
    if (rc == 0)
        rc = feature_frame(out, PSC_3D_HSR_AREA, 0, false, false, b);
    if (rc == 0 && memcmp(a, b, sizeof a) != 0)
        rc = fail("--features", "area subdivision differs from the z-buffer");
    if (rc == 0)
        rc = feature_frame(out, PSC_3D_HSR_ZBUFFER, 16, true, false, a);
    if (rc == 0)
        rc = feature_frame(out, PSC_3D_HSR_ZBUFFER, 16, true, true, b);
    if (rc == 0 && memcmp(a, b, sizeof a) != 0)
        rc = fail("--features", "rows split between two workers differ");
    if (rc == 0)
        rc = feature_frame(out, PSC_3D_HSR_AREA, 24, false, true, b);
    if (fclose(out) != 0 && rc == 0)
        rc = fail(path, strerror(errno));
    return rc;
}

int main(int argc, char **argv)
{
    psc_container_error_t perr;
    psc_pack_t pack;
    size_t len = 0;
    void *buf;
    FILE *out;
    int rc;

    if (argc == 3 && strcmp(argv[1], "--features") == 0)
        return render_features(argv[2]);
    if (argc < 4) {
        fprintf(stderr, "usage: " PROG " PACK OUT.raw FORMAT,FILTER,SPAN_LOG2,YAW,PITCH,HFOV...\n");
        return 2;
    }
    char *comma = strchr(argv[1], ',');
    void *sbuf = NULL;
    size_t slen = 0;
    if (comma) {   /* PACK.ppk,SHADOW.pao */
        *comma = '\0';
        if (!(sbuf = read_file(comma + 1, &slen)))
            return fail(comma + 1, "cannot read");
    }
    buf = read_file(argv[1], &len);
    if (!buf) {
        free(sbuf);
        return fail(argv[1], "cannot read");
    }
    if (len >= PSC_CONTAINER_MAGIC_SIZE && memcmp(buf, PSC_PROXY_MAGIC, PSC_CONTAINER_MAGIC_SIZE) == 0) {
        free(sbuf);
        out = fopen(argv[2], "wb");
        if (!out) {
            free(buf);
            return fail(argv[2], strerror(errno));
        }
        rc = render_proxy(buf, len, out, argv + 3, argc - 3);
        if (fclose(out) != 0 && rc == 0)
            rc = fail(argv[2], strerror(errno));
        free(buf);
        return rc;
    }
    if (len >= PSC_CONTAINER_MAGIC_SIZE && memcmp(buf, PSC_PATCH_MAGIC, PSC_CONTAINER_MAGIC_SIZE) == 0) {
        out = fopen(argv[2], "wb");
        if (!out) {
            free(buf);
            return fail(argv[2], strerror(errno));
        }
        rc = render_patch(buf, len, sbuf, slen, out, argv + 3, argc - 3);
        if (fclose(out) != 0 && rc == 0)
            rc = fail(argv[2], strerror(errno));
        free(buf);
        free(sbuf);
        return rc;
    }
    free(sbuf);
    /* a tiled pack's container comes first (its header says how long), its tile store after it */
    size_t clen = len >= 32u ? psc_rd32((const uint8_t *)buf + 16) : len;
    if (psc_pack_parse(buf, clen < len ? clen : len, &pack, &perr) != PSC_OK) {
        free(buf);
        return fail(argv[1], "not a valid scene pack");
    }
    out = fopen(argv[2], "wb");
    if (!out) {
        free(buf);
        return fail(argv[2], strerror(errno));
    }
    rc = render_views(&pack, buf, len, out, argv + 3, argc - 3);
    if (fclose(out) != 0 && rc == 0)
        rc = fail(argv[2], strerror(errno));
    free(buf);
    return rc;
}
