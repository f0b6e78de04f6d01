/* SPDX-License-Identifier: MIT */
/*
 * model.c - periscope-render's model mode (model.h).
 */
#include "render/model.h"
#include "psc_io_cli.h"
#include "psc_io_error.h"
#include "psc_io_file.h"
#include "psc_io_load.h"
#include "psc_io_angle.h"
#include "util/cli_values.h"
#include "render/target.h"
#include "render/cli.h"
#include "render/view.h"
#include "psc_io_image.h"
#include "bake/mesh_pack.h"
#include "import/obj.h"
#include "psc_io_pack_build.h"
#include "3d/psc_3d_orbit.h"
#include "3d/psc_3d_render.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>


typedef struct {
    const char *model, *out, *texture, *depth, *write_pack;
    psc_render_view_t view;
    unsigned long tile;
    psc_tex_filter_t filter;
    unsigned long depth_bits;
} model_args_t;


static bool is_mesh_file(const char *path)
{
    return psc_obj_is_file(path) || psc_io_file_has_magic(path, PSC_MESH_MAGIC, PSC_CONTAINER_MAGIC_SIZE);
}

bool psc_render_model_wanted(int argc, char **argv)
{
    return psc_render_cli_has_option(argc, argv, "--orbit") || psc_render_cli_has_file(argc, argv, is_mesh_file);
}

static void usage(const char *prog, FILE *f)
{
    fprintf(f,
            "usage: %s MODEL.{obj,pmesh} -o view.png [options]\n"
            "\n"
            "Render a model (OBJ file or mesh pack) with the device's 3D pipeline.\n"
            "\n"
            "  --orbit Y,P,D       camera at D x R from the bounding-box centre (R: half its\n"
            "                      diagonal) looking at it, turned up by P then right by Y degrees\n"
            "                      (default 30,20,2.5)\n"
            "  --hfov F            horizontal field of view in degrees (default 60)\n"
            "  --size WxH          output size (default 640x480)\n"
            "  --texture T.png     texture (replaces the material's or the pack's)\n"
            "  --cull back|none    back-face culling (default back)\n"
            "  --tiles N           render in N x N pixel tiles with a tile-sized depth buffer (0: full)\n"
            "  --depth D.pgm       also write the normalised depth as a 16-bit PGM (65535 = far)\n"
            "  --depth-bits B      16 or 32 (default 32)\n"
            PSC_RENDER_VIEW_LOOK_HELP
            "                      (--shade's default: texture when there is one, else gouraud)\n"
            "  --filter F          nearest or bilinear texture filter (default bilinear)\n"
            "  --format F          output surface: rgb565 (default) or xrgb8888\n"
            "  --repeat K          render K times and report the time per frame\n"
            "  --write-pack P      also write the mesh pack the view was drawn from\n"
            "  -o view.png         output PNG\n"
            "  --version           the program's version\n"
            "  --help              this text\n",
            prog);
}

static const struct option model_options[] = {
    {"texture", required_argument, NULL, 1}, {"tiles", required_argument, NULL, 1},
    {"depth", required_argument, NULL, 1}, {"depth-bits", required_argument, NULL, 1},
    {"filter", required_argument, NULL, 1}, {"write-pack", required_argument, NULL, 1},
    {NULL, 0, NULL, 0},
};

static int model_option(const char *prog, const char *name, const char *v, void *args)
{
    model_args_t *a = args;
    if (strcmp(name, "--texture") == 0) {
        a->texture = v;
    } else if (strcmp(name, "--tiles") == 0) {
        if (psc_cli_parse_uint(v, 0, PSC_MAX_OUT_DIM, &a->tile) != 0)
            return psc_io_cli_usage_error(prog, "--tiles '%s': expected a tile side of 0..%u pixels", v,
                                       (unsigned)PSC_MAX_OUT_DIM);
    } else if (strcmp(name, "--depth") == 0) {
        a->depth = v;
    } else if (strcmp(name, "--depth-bits") == 0) {
        if (psc_cli_parse_uint(v, 16, 32, &a->depth_bits) != 0 || (a->depth_bits != 16 && a->depth_bits != 32))
            return psc_io_cli_usage_error(prog, "--depth-bits '%s': expected 16 or 32", v);
    } else if (strcmp(name, "--filter") == 0) {
        if (strcmp(v, "nearest") != 0 && strcmp(v, "bilinear") != 0)
            return psc_io_cli_usage_error(prog, "--filter '%s': expected nearest or bilinear", v);
        a->filter = strcmp(v, "nearest") == 0 ? PSC_TEX_NEAREST : PSC_TEX_BILINEAR;
    } else if (strcmp(name, "--write-pack") == 0) {
        a->write_pack = v;
    }
    return 0;
}

static int parse_args(const char *prog, int argc, char **argv, model_args_t *a)
{
    static const psc_render_cli_t cli = {" (model mode)", "model", usage, model_options, model_option};
    return psc_render_cli_parse(&cli, prog, argc, argv, &a->view, &a->model, &a->out, a);
}

int psc_render_mesh_load(const char *path, const char *texture, const char *write_pack, psc_io_mesh_t *mf, char *err,
                         size_t errlen)
{
    struct {
        const char *model, *texture, *write_pack;
    } args = {path, texture, write_pack}, *a = &args;
    if (psc_io_file_has_magic(a->model, PSC_MESH_MAGIC, PSC_CONTAINER_MAGIC_SIZE))
        return psc_io_mesh_load(a->model, mf, err, errlen);
    psc_model_t m;
    char note[600];
    if (psc_obj_load(a->model, &m, note, sizeof note, err, errlen) != 0)
        return -1;
    if (note[0])
        fprintf(stderr, "note: %s\n", note);
    psc_image_t tex = {0, 0, NULL};
    const char *tex_path = a->texture ? a->texture : m.texture_path;
    int rc = -1;
    if (tex_path && m.uv && psc_io_image_load(tex_path, &tex, err, errlen) != 0)
        goto done;
    if (tex_path && !m.uv)
        fprintf(stderr, "note: %s has no texture coordinates: texture %s not used\n", a->model, tex_path);
    if (!tex.xrgb && m.uv) { /* coordinates without a texture to read (tiling ones, say): nothing to keep */
        free(m.uv);
        m.uv = NULL;
    }
    uint8_t *bytes = NULL;
    size_t len = 0;
    if (psc_bake_mesh_pack(&m, tex.xrgb ? &tex : NULL, NULL, a->model, &bytes, &len, err, errlen) != 0)
        goto done;
    if (a->write_pack && psc_io_write_atomic(a->write_pack, bytes, len, err, errlen) != 0) {
        free(bytes);
        goto done;
    }
    memset(mf, 0, sizeof *mf);
    if (posix_memalign(&mf->buf, 64, len) != 0) {
        free(bytes);
        psc_io_errorf(err, errlen, a->model, "out of memory");
        goto done;
    }
    memcpy(mf->buf, bytes, len);
    free(bytes);
    mf->len = len;
    if (psc_io_mesh_parse_named(a->model, mf->buf, len, &mf->mesh, err, errlen) != 0) {
        psc_io_mesh_free(mf);
        goto done;
    }
    rc = 0;
done:
    psc_io_image_free(&tex);
    psc_model_free(&m);
    return rc;
}

/* A --texture for a mesh pack: the image at power-of-two sides, RGB565, through the pack writer's rules. */
static int override_texture(const model_args_t *a, psc_io_mesh_t *mf, psc_io_mesh_t *texpack, char *err,
                            size_t errlen)
{
    /* A one-triangle pack carrying the texture: the same conversion as psc_bake_mesh_pack. */
    psc_image_t img;
    if (psc_io_image_load(a->texture, &img, err, errlen) != 0)
        return -1;
    double pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, uv[6] = {0, 0, 1, 0, 0, 1};
    uint32_t idx[3] = {0, 1, 2};
    psc_model_t tri = {pos, NULL, uv, NULL, idx, 3, 1, NULL, NULL};
    uint8_t *bytes;
    size_t len;
    int rc = psc_bake_mesh_pack(&tri, &img, NULL, a->texture, &bytes, &len, err, errlen);
    psc_io_image_free(&img);
    if (rc != 0)
        return -1;
    memset(texpack, 0, sizeof *texpack);
    if (posix_memalign(&texpack->buf, 64, len) != 0) {
        free(bytes);
        return psc_io_errorf(err, errlen, a->texture, "out of memory");
    }
    memcpy(texpack->buf, bytes, len);
    free(bytes);
    texpack->len = len;
    if (psc_io_mesh_parse_named(a->texture, texpack->buf, len, &texpack->mesh, err, errlen) != 0)
        return -1;
    mf->mesh.texture = texpack->mesh.texture;
    mf->mesh.has_texture = mf->mesh.uv_q12 != NULL;
    return 0;
}

int psc_render_model_main(const char *prog, int argc, char **argv)
{
    model_args_t a = {.view = psc_render_view_defaults(30, 20, 2.5, 60), .filter = PSC_TEX_BILINEAR,
                      .depth_bits = 32};
    int rc = parse_args(prog, argc, argv, &a);
    if (rc != 0)
        return rc;
    const psc_render_view_t *vw = &a.view;
    char err[768];
    psc_io_mesh_t mf, texpack = {0};
    if (psc_render_mesh_load(a.model, a.texture, a.write_pack, &mf, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        return 1;
    }
    rc = 1;
    psc_render_target_t rt = {0};
    if (a.texture && psc_io_file_has_magic(a.model, PSC_MESH_MAGIC, PSC_CONTAINER_MAGIC_SIZE) && override_texture(&a, &mf, &texpack, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    psc_3d_draw_t d;
    psc_3d_draw_defaults(&d, &mf.mesh);
    psc_vec3_q16_t lo, hi;
    psc_mesh_bounds_q16(&mf.mesh, &lo, &hi);
    psc_3d_config_t cfg = {vw->width, vw->height, (uint16_t)a.tile, (uint16_t)a.tile, (uint8_t)a.depth_bits,
                           psc_io_bam_from_deg(vw->hfov), 0, 0,
                           mf.mesh.vertex_count * (mf.mesh.opacity_groups ? mf.mesh.opacity_groups : 1u), vw->hsr};
    if (psc_render_view_orbit(vw, lo, hi, &d.camera_from_object, &cfg.near_q16, &cfg.far_q16) != PSC_OK) {
        fprintf(stderr, "%s: %s: the orbit view does not fit the fixed-point range\n", prog, a.model);
        goto done;
    }
    d.cull_back = vw->cull;
    d.filter = a.filter;
    d.lit = mf.mesh.normal_q14 != NULL;
    d.light_dir = psc_vec3_normalize((psc_vec3_q16_t){-26000, 39000, -45000}); /* from the upper left, behind */
    d.ambient_q8 = 72;
    d.shade = mf.mesh.has_texture ? PSC_SHADE_TEXTURE : PSC_SHADE_GOURAUD;
    if (psc_render_view_shade(vw, &d, 1, a.model, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    psc_status_t s;
    if (psc_render_target_open_view(&rt, &cfg, vw, a.depth != NULL, a.model, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    uint32_t bg = 0x30343C;
    psc_3d_stats_t st;
    double best = 1e30, total = 0;
    psc_mesh_t parts[PSC_MESH_MAX_OPACITY_GROUPS];
    psc_3d_draw_t draws[PSC_MESH_MAX_OPACITY_GROUPS];
    unsigned nd = psc_3d_draw_by_opacity(&d, parts, draws); /* OBJ d / Tr materials: translucent draws last */
    for (unsigned long k = 0; k < vw->repeat; k++) {
        double t0 = psc_render_seconds();
        s = psc_render_target_frame(&rt, draws, nd, bg, &st);
        double dt = psc_render_seconds() - t0;
        total += dt;
        best = dt < best ? dt : best;
        if (s != PSC_OK) {
            fprintf(stderr, "%s: %s: rendering failed: %s\n", prog, a.model, psc_status_str(s));
            goto done;
        }
    }
    if (vw->repeat > 1)
        fprintf(stderr, "%s: %lu frames of %ux%u, %u triangles (%u culled, %u outside): %.3f ms per frame "
                "(best %.3f)\n", prog, vw->repeat, (unsigned)vw->width, (unsigned)vw->height, (unsigned)st.triangles,
                (unsigned)st.culled, (unsigned)st.outside, total / vw->repeat * 1e3, best * 1e3);
    psc_render_target_note(&rt, &st, prog, a.model);
    if (psc_render_target_write(&rt, a.out, a.depth, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    rc = 0;
done:
    psc_render_target_close(&rt);
    psc_io_mesh_free(&mf);
    psc_io_mesh_free(&texpack);
    return rc;
}
