/* SPDX-License-Identifier: MIT */
/* proxy.c - periscope-render's proxy-pack mode (proxy.h). */
#include "render/proxy.h"
#include "util/path.h"
#include "psc_io_angle.h"
#include "util/cli_values.h"
#include "render/depth_pgm.h"
#include "import/gltf_model.h"
#include "import/pose_file.h"
#include "psc_io_cli.h"
#include "psc_io_error.h"
#include "psc_io_load.h"
#include "render/target.h"
#include "render/cli.h"
#include "render/view.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BACKGROUND 0x30343Cu   /* (48, 52, 60) */

typedef struct {
    const char *pack, *out, *depth, *ids, *pose_file;
    psc_render_view_t view;
    double time;
    int lod;                     /* psc_proxy_lod_t, or -1: chosen by the model's size on the screen */
    unsigned long tile;
    bool light;                  /* --light given: relit */
    double light_az, light_el, ambient;
} proxy_args_t;

static bool is_proxy_pack(const char *path)
{
    return psc_path_has_suffix(path, ".ppx");
}

bool psc_render_proxy_wanted(int argc, char **argv)
{
    return psc_render_cli_has_file(argc, argv, is_proxy_pack);
}

static void usage(const char *prog, FILE *f)
{
    fprintf(f,
            "usage: %s M.ppx -o view.png [options]\n"
            "\n"
            "Draw a proxy pack (periscope-proxy bake) posed, with the device's proxy animator: each part's\n"
            "proxy with the three view textures its direction picks, each joint triangle with its own.\n"
            "\n"
            "  --orbit Y,P,D       camera at D x R from the rest pose's box centre (R: half its diagonal),\n"
            "                      turned up by P then right by Y degrees (default 30,20,2.5)\n"
            "  --hfov F            horizontal field of view in degrees (default 50)\n"
            "  --size WxH          output size (default 640x480)\n"
            "  --pose P            rest (default), t=T (T seconds into the animation) or POSE.json\n"
            "  --full              the full mesh kept in the pack, same pose and shading (the near level of detail)\n"
            "  --lod L             proxies (default), full, billboard (the far level: the rest pose in a few\n"
            "                      small views on a quad facing the camera) or auto (the billboard below a\n"
            "                      projected radius of 40 pixels, else the cheaper of proxies and full mesh by\n"
            "                      estimated cost: vertices, triangles and the area covered)\n"
            "  --light AZ,EL       relight every level by a light toward azimuth AZ (degrees from +z toward +x,\n"
            "                      about the model's up axis) and elevation EL (degrees above the horizon),\n"
            "                      fixed in the model's space, the normals turning with the pose (default:\n"
            "                      as baked, a light at 41.6,53.0 fixed to the surface; needs a pack with\n"
            "                      normals, periscope-proxy's default)\n"
            "  --ambient A         with --light: the ambient share 0..1 (default 0.45, the bake's)\n"
            "  --depth d.pgm       the depth buffer as a 16-bit PGM\n"
            "  --ids ids.pgm       16-bit PGM: part index + 1 of the front-most surface, 0 for the background\n"
            "  --tiles N           render in N x N pixel tiles (0: full screen)\n"
            "  --cull back|none    back-face culling (default back)\n"
            "  --format F          output surface: rgb565 (default) or xrgb8888\n"
            PSC_RENDER_VIEW_LOOK_HELP
            "                      (--shade with --lod full only: proxies draw their views)\n"
            "  --repeat K          pose and draw K times, and report the time per frame\n"
            "  -o view.png         output PNG\n"
            "  --version, --help\n",
            prog);
}

static const struct option proxy_options[] = {
    {"pose", required_argument, NULL, 1}, {"full", no_argument, NULL, 1},
    {"depth", required_argument, NULL, 1}, {"lod", required_argument, NULL, 1},
    {"ids", required_argument, NULL, 1}, {"tiles", required_argument, NULL, 1},
    {"light", required_argument, NULL, 1}, {"ambient", required_argument, NULL, 1},
    {NULL, 0, NULL, 0},
};

static int proxy_option(const char *prog, const char *name, const char *v, void *args)
{
    proxy_args_t *a = args;
    if (strcmp(name, "--full") == 0) {
        a->lod = PSC_PROXY_LOD_FULL;
    } else if (strcmp(name, "--lod") == 0) {
        a->lod = strcmp(v, "proxies") == 0     ? PSC_PROXY_LOD_PROXIES
                 : strcmp(v, "full") == 0      ? PSC_PROXY_LOD_FULL
                 : strcmp(v, "billboard") == 0 ? PSC_PROXY_LOD_BILLBOARD
                 : strcmp(v, "auto") == 0      ? -1
                                               : -2;
        if (a->lod == -2)
            return psc_io_cli_usage_error(prog, "--lod '%s': expected proxies, full, billboard or auto", v);
    } else if (strcmp(name, "--light") == 0) {
        char az[64] = "";
        const char *comma = strchr(v, ',');
        size_t n = comma ? (size_t)(comma - v) : 0;
        if (n > 0 && n < sizeof az)
            memcpy(az, v, n);
        if (!comma || n == 0 || n >= sizeof az || psc_cli_parse_double(az, &a->light_az) != 0 ||
            psc_cli_parse_double(comma + 1, &a->light_el) != 0 || !(fabs(a->light_az) <= 360.0) ||
            !(fabs(a->light_el) <= 90.0))
            return psc_io_cli_usage_error(prog, "--light '%s': expected AZ,EL in degrees (-360..360, -90..90)", v);
        a->light = true;
    } else if (strcmp(name, "--ambient") == 0) {
        if (psc_cli_parse_double(v, &a->ambient) != 0 || !(a->ambient >= 0.0 && a->ambient <= 1.0))
            return psc_io_cli_usage_error(prog, "--ambient '%s': expected a share 0..1", v);
    } else if (strcmp(name, "--depth") == 0) {
        a->depth = v;
    } else if (strcmp(name, "--ids") == 0) {
        a->ids = v;
    } else if (strcmp(name, "--tiles") == 0) {
        if (psc_cli_parse_uint(v, 0, PSC_MAX_OUT_DIM, &a->tile) != 0)
            return psc_io_cli_usage_error(prog, "--tiles '%s': expected a tile side of 0..%u pixels", v,
                                          (unsigned)PSC_MAX_OUT_DIM);
    } else if (strcmp(name, "--pose") == 0) {
        int rc = psc_pose_option(prog, v, &a->pose_file, &a->time);
        if (rc != 0)
            return rc;
    }
    return 0;
}

static int parse_args(const char *prog, int argc, char **argv, proxy_args_t *a)
{
    static const psc_render_cli_t cli = {" (proxy mode)", "proxy pack", usage, proxy_options, proxy_option};
    return psc_render_cli_parse(&cli, prog, argc, argv, &a->view, &a->pack, &a->out, a);
}

/* ---- poses ------------------------------------------------------------------------ */

static void to_double(const int32_t *q, double m[12])
{
    for (unsigned k = 0; k < 12; k++)
        m[k] = q[k] / 65536.0;
}

int psc_render_proxy_pose(const psc_proxy_model_t *m, double t, const double (*pre)[12], const double (*post)[12],
                            psc_mat4_q16_t *skin)
{
    uint32_t nj = m->joint_count;
    psc_proxy_pose_at(m, t < 0 ? -1 : (int64_t)llround(t * 1e6), skin);
    if (!pre && !post)
        return 0;
    double(*w)[12] = malloc(nj * sizeof *w), (*wn)[12] = malloc(nj * sizeof *wn);
    if (!w || !wn) {
        free(w), free(wn);
        return -1;
    }
    double r = m->model_r_um > 0 ? m->model_r_um * 1e-6 : 1.0;
    /* posed worlds in R space: W = S Rest; locals; adjusted; recomposed; S' = W' Rest^-1 */
    for (uint32_t j = 0; j < nj; j++) {
        double s[12], rest[12];
        for (unsigned rr = 0; rr < 3; rr++)
            for (unsigned k = 0; k < 4; k++)
                s[4 * rr + k] = skin[j].m[rr][k] / 65536.0;
        to_double(m->joints[j].rest_world_q16, rest);
        psc_gltf_mat_mul(s, rest, w[j]);
    }
    for (uint32_t j = 0; j < nj; j++) {
        int32_t p = m->joints[j].parent;
        double local[12], inv[12], tmp[12], pr[12];
        if (p >= 0) {
            psc_gltf_mat_inverse(w[p], inv);
            psc_gltf_mat_mul(inv, w[j], local);
        } else {
            memcpy(local, w[j], sizeof local);
        }
        memcpy(pr, pre ? pre[j] : (const double[12]){1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, sizeof pr);
        if (p < 0)   /* a root's local is in R space: its translation in units of R */
            for (unsigned rr = 0; rr < 3; rr++)
                pr[4 * rr + 3] /= r;
        psc_gltf_mat_mul(pr, local, tmp);
        if (post)
            psc_gltf_mat_mul(tmp, post[j], local);
        else
            memcpy(local, tmp, sizeof local);
        if (p >= 0)
            psc_gltf_mat_mul(wn[p], local, wn[j]);
        else
            memcpy(wn[j], local, sizeof local);
    }
    for (uint32_t j = 0; j < nj; j++) {
        double rest[12], inv[12], s[12];
        to_double(m->joints[j].rest_world_q16, rest);
        psc_gltf_mat_inverse(rest, inv);
        psc_gltf_mat_mul(wn[j], inv, s);
        psc_mat4_identity(&skin[j]);
        for (unsigned rr = 0; rr < 3; rr++)
            for (unsigned k = 0; k < 4; k++)   /* within 64 (linear) and 64 R (translation), as the pack's */
                skin[j].m[rr][k] = (int32_t)lround(fmax(-64.0, fmin(64.0, s[4 * rr + k])) * 65536.0);
    }
    free(w), free(wn);
    return 0;
}

/* --pose POSE.json: its adjustments per joint (by name or number) and its time. */
static int pose_from_file(proxy_args_t *a, const psc_proxy_model_t *m, double (**pre)[12], double (**post)[12],
                          char *err, size_t errlen)
{
    psc_pose_file_t pf;
    if (psc_pose_file_load(a->pose_file, &pf, err, errlen) != 0)
        return -1;
    if (pf.has_weights) {
        psc_pose_file_free(&pf);
        return psc_io_errorf(err, errlen, a->pose_file, "weights: a proxy pack holds no blend shapes (morph targets)");
    }
    *pre = malloc(m->joint_count * sizeof **pre);
    *post = malloc(m->joint_count * sizeof **post);
    if (!*pre || !*post) {
        psc_pose_file_free(&pf);
        return psc_io_errorf(err, errlen, a->pose_file, "out of memory");
    }
    static const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    for (uint32_t j = 0; j < m->joint_count; j++) {
        memcpy((*pre)[j], id, sizeof id);
        memcpy((*post)[j], id, sizeof id);
    }
    int rc = 0;
    for (unsigned k = 0; k < pf.count && rc == 0; k++) {
        const psc_pose_node_t *n = &pf.nodes[k];
        int32_t j = -1;
        for (uint32_t q = 0; q < m->joint_count && j < 0; q++)
            if (strcmp(m->joints[q].name, n->name) == 0)
                j = (int32_t)q;
        /* a number: the glTF file's node of that index when the pack knows its joints' (XNOD), else the joint's */
        for (uint32_t q = 0; q < m->joint_count && j < 0 && n->index >= 0 && m->node; q++)
            if (m->node[q] == n->index)
                j = (int32_t)q;
        if (j < 0 && !m->node && n->index >= 0 && n->index < (long)m->joint_count)
            j = (int32_t)n->index;
        if (j < 0)
            rc = psc_io_errorf(err, errlen, a->pose_file, "node '%s' is neither a node's name nor its number in %s",
                               n->name, a->pack);
        else
            psc_pose_node_matrices(n, (*pre)[j], (*post)[j]);
    }
    a->time = pf.time;
    psc_pose_file_free(&pf);
    return rc;
}

/* One frame: the pack's draws for this pose into target rt. */
static psc_status_t draw(psc_proxy_t *px, psc_render_target_t *rt, const psc_mat4_q16_t *skin,
                         const psc_mat4_q16_t *cam, psc_proxy_lod_t lod, bool ids, const psc_render_view_t *vw,
                         psc_3d_stats_t *st)
{
    bool cull = vw->cull;
    const psc_3d_draw_t *cd;
    unsigned n;
    psc_status_t s = psc_proxy_frame(px, skin, cam, lod, ids, &cd, &n);
    if (s != PSC_OK)
        return s;
    for (unsigned i = 0; i < n && lod != PSC_PROXY_LOD_BILLBOARD; i++)
        px->draws[i].cull_back = cull;
    char why[160];
    if (lod == PSC_PROXY_LOD_FULL && !ids && psc_render_view_shade(vw, px->draws, n, "", why, sizeof why) != 0)
        return PSC_ERR_ARG;
    uint32_t bg = ids ? 0u : BACKGROUND;
    return psc_render_target_frame(rt, cd, n, bg, st);
}

int psc_render_proxy_main(const char *prog, int argc, char **argv)
{
    proxy_args_t a = {.view = psc_render_view_defaults(30, 20, 2.5, 50), .time = -1.0, .lod = PSC_PROXY_LOD_PROXIES,
                      .ambient = -1.0};
    int rc = parse_args(prog, argc, argv, &a);
    if (rc != 0)
        return rc;
    const psc_render_view_t *vw = &a.view;
    char err[768];
    psc_io_proxy_t pf;
    if (psc_io_proxy_load(a.pack, &pf, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        return 1;
    }
    rc = 1;
    const psc_proxy_model_t *m = &pf.model;
    psc_render_target_t rt = {0}, rid = {0};
    double(*pre)[12] = NULL, (*post)[12] = NULL;
    size_t wsn = psc_proxy_workspace_size(m);
    void *ws = NULL;
    psc_mat4_q16_t *skin = malloc(m->joint_count * sizeof *skin);
    psc_proxy_t px;
    if (!skin || posix_memalign(&ws, 64, wsn ? wsn : 8) != 0 || psc_proxy_init(&px, m, ws, wsn) != PSC_OK) {
        fprintf(stderr, "%s: %s: out of memory\n", prog, a.pack);
        goto done;
    }
    if (a.ambient >= 0 && !a.light) {
        fprintf(stderr, "%s: --ambient needs --light (the baked lighting has its own)\n", prog);
        rc = 2;
        goto done;
    }
    if (a.light) {   /* toward the light, model space: y up, azimuth from +z toward +x */
        double az = a.light_az * 3.14159265358979 / 180.0, el = a.light_el * 3.14159265358979 / 180.0;
        int32_t l[3] = {(int32_t)lround(cos(el) * sin(az) * 65536.0), (int32_t)lround(sin(el) * 65536.0),
                        (int32_t)lround(cos(el) * cos(az) * 65536.0)};
        double amb = a.ambient >= 0 ? a.ambient : PSC_PROXY_BAKE_AMBIENT_Q14 / 16384.0;
        psc_status_t s = psc_proxy_set_light(&px, l, (uint16_t)lround(amb * 16384.0));
        if (s != PSC_OK) {
            fprintf(stderr, "%s: %s: %s\n", prog, a.pack,
                    s == PSC_ERR_UNSUPPORTED ? "--light: the pack has no normals (baked before pack 1.3 or with "
                                               "--no-normals): bake it again to relight it"
                                             : "--light: the direction is not usable");
            goto done;
        }
    }
    if (a.pose_file && pose_from_file(&a, m, &pre, &post, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    /* the camera: on the rest pose's box */
    psc_vec3_q16_t lo, hi;
    psc_proxy_rest_bounds(m, &lo, &hi);
    psc_mat4_q16_t cam;
    psc_3d_config_t cfg = {vw->width, vw->height, (uint16_t)a.tile, (uint16_t)a.tile, 32, psc_io_bam_from_deg(vw->hfov),
                           0, 0, psc_proxy_max_vertices(m), vw->hsr};
    if (psc_render_view_orbit(vw, lo, hi, &cam, &cfg.near_q16, &cfg.far_q16) != PSC_OK) {
        fprintf(stderr, "%s: %s: the orbit view does not fit the fixed-point range\n", prog, a.pack);
        goto done;
    }
    if (vw->shade >= 0 && a.lod != PSC_PROXY_LOD_FULL) {
        fprintf(stderr, "%s: %s: --shade needs --lod full (proxies draw their view textures)\n", prog, a.pack);
        goto done;
    }
    if (psc_render_target_open_view(&rt, &cfg, vw, a.depth != NULL, a.pack, err, sizeof err) != 0 ||
        (a.ids && psc_render_target_open(&rid, &cfg, PSC_PIX_XRGB8888, false, a.pack, err, sizeof err) != 0)) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    psc_proxy_lod_t lod = (psc_proxy_lod_t)a.lod;
    /* the focal length in pixels, (W / 2) / tan(hfov / 2): the mip levels, and the level of detail for auto */
    int32_t focal = (int32_t)lround(vw->width / 2.0 / tan(vw->hfov * 3.14159265358979 / 360.0) * 65536.0);
    psc_proxy_set_focal(&px, focal);
    psc_proxy_set_screen(&px, vw->width, vw->height);
    if (a.lod < 0) {
        /* a frame at the first estimate's level tells how much the model covers; the level is picked again
         * from that, as the device's scene settles on it after its first frame */
        lod = psc_proxy_lod_pick(&px, &cam, focal);
        psc_3d_stats_t st0 = {0};
        if (lod != PSC_PROXY_LOD_BILLBOARD &&
            psc_render_proxy_pose(m, a.time, (const double(*)[12])pre, (const double(*)[12])post, skin) == 0 &&
            draw(&px, &rt, skin, &cam, lod, false, vw, &st0) == PSC_OK) {
            psc_proxy_observe(&px, &st0);
            lod = psc_proxy_lod_pick(&px, &cam, focal);
        }
    }
    double total = 0, best = 1e30;
    psc_3d_stats_t st = {0};
    for (unsigned long k = 0; k < vw->repeat; k++) {
        double t0 = psc_render_seconds();
        if (psc_render_proxy_pose(m, a.time, (const double(*)[12])pre, (const double(*)[12])post, skin) != 0) {
            fprintf(stderr, "%s: %s: out of memory\n", prog, a.pack);
            goto done;
        }
        psc_status_t s = draw(&px, &rt, skin, &cam, lod, false, vw, &st);
        double dt = psc_render_seconds() - t0;
        total += dt;
        best = dt < best ? dt : best;
        if (s != PSC_OK) {
            fprintf(stderr, "%s: %s: drawing failed: %s\n", prog, a.pack, psc_status_str(s));
            goto done;
        }
    }
    if (vw->repeat > 1)
        fprintf(stderr, "%s: %lu frames of %ux%u, %s, %u triangles (%u culled): %.3f ms per frame (best %.3f)\n", prog,
                vw->repeat, (unsigned)vw->width, (unsigned)vw->height,
                lod == PSC_PROXY_LOD_FULL ? "full mesh" : lod == PSC_PROXY_LOD_BILLBOARD ? "billboard" : "proxies",
                (unsigned)st.triangles, (unsigned)st.culled, total / vw->repeat * 1e3, best * 1e3);
    if (a.lod < 0) {
        psc_proxy_cost_t c = psc_proxy_cost(&px, &cam, focal);
        fprintf(stderr, "%s: --lod auto: %s (radius %d px, about %u px covered; estimated cost proxies %.2f M, full mesh "
                "%.2f M instructions; billboard below %d px; views magnified beyond %u px)\n", prog,
                lod == PSC_PROXY_LOD_FULL ? "full mesh" : lod == PSC_PROXY_LOD_BILLBOARD ? "billboard" : "proxies",
                (int)c.radius_px, (unsigned)c.area_px, c.proxies / 1e6, c.full / 1e6, (int)px.billboard_px,
                (unsigned)px.texels_per_r);
    }
    psc_render_target_note(&rt, &st, prog, a.pack);
    if (psc_render_target_write(&rt, a.out, a.depth, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    if (a.ids) {
        psc_status_t s = draw(&px, &rid, skin, &cam, lod, true, vw, NULL);
        uint16_t *id = malloc((size_t)vw->width * vw->height * sizeof *id);
        if (s != PSC_OK || !id) {
            free(id);
            fprintf(stderr, "%s: %s: drawing the ids failed\n", prog, a.pack);
            goto done;
        }
        for (uint32_t y = 0; y < vw->height; y++)
            for (uint32_t x = 0; x < vw->width; x++)
                id[(size_t)y * vw->width + x] =
                    (uint16_t)(((const uint32_t *)rid.out.pixels)[(size_t)y * (rid.out.stride / 4u) + x] & 0xFFFFu);
        int w = psc_render_depth_pgm_write(a.ids, id, vw->width, vw->height, err, sizeof err);
        free(id);
        if (w != 0) {
            fprintf(stderr, "%s: %s\n", prog, err);
            goto done;
        }
    }
    rc = 0;
done:
    free(pre), free(post), free(skin), free(ws);
    psc_render_target_close(&rt);
    psc_render_target_close(&rid);
    psc_io_proxy_free(&pf);
    return rc;
}
