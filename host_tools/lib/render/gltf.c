/* SPDX-License-Identifier: MIT */
/* gltf.c - periscope-render's glTF mode (gltf.h). */
#include "render/gltf.h"
#include "util/hmath.h"
#include "import/gltf_model.h"
#include "import/obj.h"
#include "psc_io_cli.h"
#include "psc_io_error.h"
#include "psc_io_file.h"
#include "psc_io_load.h"
#include "psc_io_angle.h"
#include "util/cli_values.h"
#include "import/pose_file.h"
#include "anim/gltf_morph.h"
#include "render/target.h"
#include "render/cli.h"
#include "render/view.h"
#include "util/text_out.h"
#include "3d/psc_3d_render.h"
#include "shadow/psc_shadow_frame.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BACKGROUND 0x30343Cu   /* (48, 52, 60) */
/* The opaque triangles' draw and at most this many less one translucent opacities (more: the nearest kept). */
#define PSC_GLTF_DRAWS_MAX 16u

typedef struct {
    const char *model, *out, *shadow, *dump_ao, *pose_file;
    psc_render_view_t view;
    double time;
} gltf_args_t;

bool psc_render_gltf_wanted(int argc, char **argv)
{
    /* an OBJ self-shadowed: read as the articulated model, its groups the parts */
    return psc_render_cli_has_file(argc, argv, psc_gltf_is_file) ||
           (psc_render_cli_has_file(argc, argv, psc_obj_is_file) && psc_render_cli_has_option(argc, argv, "--shadow"));
}

static void usage(const char *prog, FILE *f)
{
    fprintf(f,
            "usage: %s MODEL.{gltf,glb,fbx,dae,x,3ds,blend} -o view.png [options]\n"
            "\n"
            "Pose an articulated or skinned model and draw it with the device's 3D pipeline.\n"
            "\n"
            "  --orbit Y,P,D       camera at D x R from the rest pose's box centre (R: half its\n"
            "                      diagonal), turned up by P then right by Y degrees (default 30,20,2.5)\n"
            "  --hfov F            horizontal field of view in degrees (default 50)\n"
            "  --size WxH          output size (default 640x480)\n"
            "  --pose P            rest (default), t=T (T seconds into the first animation) or POSE.json:\n"
            "                      {\"time\": T, \"nodes\": {\"NAME or INDEX\": {\"rotate\": [ax, ay, az, deg],\n"
            "                      \"translate\": [x, y, z]}}, \"weights\": [w, ...] or {\"NAME\": w}}, local' =\n"
            "                      T local R on top of the animation; weights: the blend shapes' (morph\n"
            "                      targets'), by hand, all in order or by their names\n"
            "  --shadow M.pao      self-shadowing from the model's sphere-occluder tables\n"
            "                      (periscope-shadow build MODEL)\n"
            "  --dump-ao AO.csv    with --shadow: x,y,z,nx,ny,nz,occlusion of every vertex\n"
            "                      (model coordinates; occlusion 0..1 of the cosine-weighted hemisphere)\n"
            "  --cull back|none    back-face culling (default back)\n"
            "  --format F          output surface: rgb565 (default) or xrgb8888\n"
            PSC_RENDER_VIEW_LOOK_HELP
            "  --repeat K          pose, shade and draw K times, and report the time per frame\n"
            "  -o view.png         output PNG\n"
            "  --version           the program's version\n"
            "  --help              this text\n",
            prog);
}

static const struct option gltf_options[] = {
    {"pose", required_argument, NULL, 1}, {"shadow", required_argument, NULL, 1},
    {"dump-ao", required_argument, NULL, 1},
    {NULL, 0, NULL, 0},
};

static int gltf_option(const char *prog, const char *name, const char *v, void *args)
{
    gltf_args_t *a = args;
    if (strcmp(name, "--pose") == 0) {
        int rc = psc_pose_option(prog, v, &a->pose_file, &a->time);
        if (rc != 0)
            return rc;
    } else if (strcmp(name, "--shadow") == 0) {
        a->shadow = v;
    } else if (strcmp(name, "--dump-ao") == 0) {
        a->dump_ao = v;
    }
    return 0;
}

static int parse_args(const char *prog, int argc, char **argv, gltf_args_t *a)
{
    static const psc_render_cli_t cli = {" (glTF mode)", "model", usage, gltf_options, gltf_option};
    int rc = psc_render_cli_parse(&cli, prog, argc, argv, &a->view, &a->model, &a->out, a);
    if (rc != 0)
        return rc;
    if (a->dump_ao && !a->shadow)
        return psc_io_cli_usage_error(prog, "--dump-ao needs --shadow M.pao");
    return 0;
}

/* The posed mesh the device draws: positions in units of R (Q16.16), normals Q1.14, colours. */
typedef struct {
    double c[3], r;              /* the rest frame */
    double *pos, *nrm;           /* posed, model space */
    double (*skin)[12];
    psc_gltf_trs_t *local;
    psc_mat4_q16_t *skin_q16;    /* in units of R, for the self-shadowing */
    int32_t *pos_q16;
    int16_t *nrm_q14;
    uint32_t *color;
    uint16_t *index;
    uint32_t *ao;
    psc_mesh_t mesh;
    /* the draws: the opaque triangles, then one a translucent opacity (their indices grouped in index) */
    psc_mesh_t part[PSC_GLTF_DRAWS_MAX];
    uint16_t part_opacity_q8[PSC_GLTF_DRAWS_MAX];
    unsigned parts;
    /* blend shapes (g->target_count > 0): the core morph, the morphed rest mesh, the weights (a pose file's when
     * it gives them) */
    psc_gltf_morpher_t morph;
    double *rest_pos, *rest_nrm, *weights, *anim_weights;
    bool weights_given;
    bool *weight_set;            /* weights_given by name: the targets named (the others the animation's) */
} posed_t;

static int posed_new(posed_t *p, const psc_gltf_t *g, const char *name, char *err, size_t errlen)
{
    uint32_t nv = g->mesh.vertex_count, nj = g->joint_count ? g->joint_count : 1u;
    memset(p, 0, sizeof *p);
    if (nv > 65535u)
        return psc_io_errorf(err, errlen, name, "%u vertices: the device's meshes hold at most 65 535", nv);
    p->pos = malloc(nv * 3u * sizeof *p->pos);
    p->nrm = malloc(nv * 3u * sizeof *p->nrm);
    p->skin = malloc(nj * sizeof *p->skin);
    p->local = malloc(nj * sizeof *p->local);
    p->skin_q16 = malloc(nj * sizeof *p->skin_q16);
    p->pos_q16 = malloc(nv * 3u * sizeof *p->pos_q16);
    p->nrm_q14 = malloc(nv * 3u * sizeof *p->nrm_q14);
    p->color = malloc(nv * sizeof *p->color);
    p->index = malloc(g->mesh.triangle_count * 3u * sizeof *p->index);
    p->ao = malloc(nv * sizeof *p->ao);
    if (!p->pos || !p->nrm || !p->skin || !p->local || !p->skin_q16 || !p->pos_q16 || !p->nrm_q14 || !p->color ||
        !p->index || !p->ao)
        return psc_io_errorf(err, errlen, name, "out of memory");
    psc_gltf_frame(g, p->c, &p->r);
    if (g->target_count) {
        p->rest_pos = malloc(nv * 3u * sizeof *p->rest_pos);
        p->rest_nrm = malloc(nv * 3u * sizeof *p->rest_nrm);
        p->weights = calloc(g->target_count, sizeof *p->weights);
        p->anim_weights = calloc(g->target_count, sizeof *p->anim_weights);
        p->weight_set = calloc(g->target_count, sizeof *p->weight_set);
        if (!p->rest_pos || !p->rest_nrm || !p->weights || !p->anim_weights || !p->weight_set)
            return psc_io_errorf(err, errlen, name, "out of memory");
        if (psc_gltf_morpher_new(&p->morph, g, p->c, p->r, name, err, errlen) != 0)
            return -1;
    }
    p->mesh = (psc_mesh_t){.vertex_count = nv, .triangle_count = g->mesh.triangle_count, .position_q16 = p->pos_q16,
                           .normal_q14 = p->nrm_q14, .color = p->color, .index = p->index};
    /* the opaque triangles first, then each translucent opacity's: a draw each, the translucent ones after */
    p->part_opacity_q8[p->parts++] = 256;
    for (uint32_t t = 0; g->tri_opacity_q8 && t < g->mesh.triangle_count; t++) {
        uint16_t o = g->tri_opacity_q8[t];
        unsigned k = 0;
        while (k < p->parts && p->part_opacity_q8[k] != o)
            k++;
        if (k == p->parts && p->parts < PSC_GLTF_DRAWS_MAX)
            p->part_opacity_q8[p->parts++] = o;
    }
    uint32_t at = 0;
    for (unsigned k = 0; k < p->parts; k++) {
        uint32_t first = at;
        for (uint32_t t = 0; t < g->mesh.triangle_count; t++) {
            uint16_t o = g->tri_opacity_q8 ? g->tri_opacity_q8[t] : 256;
            unsigned home = 0; /* an opacity beyond the draws' goes with the nearest one kept */
            for (unsigned q = 1; q < p->parts; q++)
                if (abs((int)p->part_opacity_q8[q] - (int)o) < abs((int)p->part_opacity_q8[home] - (int)o))
                    home = q;
            if (home != k)
                continue;
            for (unsigned c = 0; c < 3; c++)
                p->index[3u * at + c] = (uint16_t)g->mesh.index[3u * t + c];
            at++;
        }
        p->part[k] = p->mesh;
        p->part[k].index = &p->index[3u * first];
        p->part[k].triangle_count = at - first;
    }
    return 0;
}

static void posed_free(posed_t *p)
{
    free(p->pos);
    free(p->nrm);
    free(p->skin);
    free(p->local);
    free(p->skin_q16);
    free(p->pos_q16);
    free(p->nrm_q14);
    free(p->color);
    free(p->index);
    free(p->ao);
    free(p->rest_pos);
    free(p->rest_nrm);
    free(p->weights);
    free(p->anim_weights);
    free(p->weight_set);
    psc_gltf_morpher_free(&p->morph);
}

/* Pose at time t (< 0: rest), adjusted (NULL: not): the mesh in the device's formats, and the skin in units of R.
 * Blend shapes first (by core, glTF's order), then the skin. */
static void pose(posed_t *p, const psc_gltf_t *g, double t, const psc_gltf_adjust_t *adjust)
{
    psc_gltf_pose(g, t, p->local);
    psc_gltf_skin(g, p->local, adjust, p->skin);
    if (g->target_count) {
        psc_gltf_weights(g, t, p->anim_weights);
        for (uint32_t i = 0; p->weights_given && i < g->target_count; i++)
            if (p->weight_set[i])
                p->anim_weights[i] = p->weights[i];
        psc_gltf_morph_rest(&p->morph, g, p->anim_weights, p->rest_pos, p->rest_nrm);
        psc_gltf_t morphed = *g;
        morphed.mesh.pos = p->rest_pos;
        morphed.mesh.normal = p->rest_nrm;
        psc_gltf_deform(&morphed, (const double(*)[12])p->skin, p->pos, p->nrm);
    } else {
        psc_gltf_deform(g, (const double(*)[12])p->skin, p->pos, p->nrm);
    }
    psc_gltf_quantize(g, p->c, p->r, p->pos, p->nrm, (const double(*)[12])p->skin, p->pos_q16, p->nrm_q14, p->skin_q16);
    memcpy(p->color, g->mesh.color, g->mesh.vertex_count * sizeof *p->color);
}

/* The default lighting, after the self-shadowing has darkened the colours and bent the normals. */
static void light(posed_t *p)
{
    static const double l0[3] = {0.4, 0.8, 0.45};
    double ln = sqrt(l0[0] * l0[0] + l0[1] * l0[1] + l0[2] * l0[2]);
    for (uint32_t i = 0; i < p->mesh.vertex_count; i++) {
        double d = 0;
        for (unsigned a = 0; a < 3; a++)
            d += p->nrm_q14[3 * i + a] / 16384.0 * l0[a] / ln;
        double f = 0.45 + 0.55 * (d > 0 ? d : 0);
        uint32_t c = p->color[i], out = 0;
        for (unsigned sh = 0; sh < 24; sh += 8)
            out |= (uint32_t)lround(fmin(255.0, ((c >> sh) & 0xFFu) * f)) << sh;
        p->color[i] = out;
    }
}

static int write_ao(const posed_t *p, const char *path, char *err, size_t errlen)
{
    psc_text_out_t out;
    if (psc_text_out_begin(&out, path, err, errlen) != 0)
        return -1;
    FILE *f = out.f;
    fprintf(f, "x,y,z,nx,ny,nz,occlusion\n");
    for (uint32_t i = 0; i < p->mesh.vertex_count; i++)
        fprintf(f, "%.5f,%.5f,%.5f,%.4f,%.4f,%.4f,%.4f\n", p->pos[3 * i], p->pos[3 * i + 1], p->pos[3 * i + 2],
                p->nrm[3 * i], p->nrm[3 * i + 1], p->nrm[3 * i + 2], p->ao[i] / 65536.0);
    return psc_text_out_finish(&out, path, err, errlen);
}

/* --pose POSE.json: its time into a->time, its nodes as the joints' adjustments (*adjust, joint_count of them). */
static int pose_from_file(gltf_args_t *a, const psc_gltf_t *g, posed_t *p, psc_gltf_adjust_t **adjust, char *err,
                          size_t errlen)
{
    psc_pose_file_t pf;
    if (psc_pose_file_load(a->pose_file, &pf, err, errlen) != 0)
        return -1;
    if (pf.has_weights && !pf.weights_named && pf.weight_count != g->target_count) {
        unsigned given = pf.weight_count;
        psc_pose_file_free(&pf);
        return psc_io_errorf(err, errlen, a->pose_file, "weights: %u given, %s has %u morph targets", given,
                             a->model, (unsigned)g->target_count);
    }
    if (pf.has_weights && pf.weights_named) { /* by name: every target of that name, in every mesh */
        for (unsigned k = 0; k < pf.weight_count; k++) {
            unsigned found = 0;
            for (uint32_t i = 0; i < g->target_count; i++)
                if (g->target_name && strcmp(g->target_name[i], pf.weight_name[k]) == 0) {
                    p->weights[i] = pf.weights[k];
                    p->weight_set[i] = true;
                    found++;
                }
            if (!found) {
                char known[256] = "";
                size_t at = 0;
                for (uint32_t i = 0; i < g->target_count && g->target_name && at + 1 < sizeof known; i++) {
                    bool seen = false;
                    for (uint32_t j = 0; j < i; j++)
                        seen |= strcmp(g->target_name[j], g->target_name[i]) == 0;
                    if (!seen && g->target_name[i][0])
                        at += (size_t)snprintf(known + at, sizeof known - at, "%s\"%s\"", at ? ", " : "",
                                               g->target_name[i]);
                }
                psc_io_errorf(err, errlen, a->pose_file, "weights: no morph target of %s is named \"%s\" (%s%s)",
                              a->model, pf.weight_name[k], known[0] ? "its names: " : "its targets have no names",
                              known);
                psc_pose_file_free(&pf);
                return -1;
            }
        }
        p->weights_given = true;
    } else if (pf.has_weights && g->target_count) {
        memcpy(p->weights, pf.weights, g->target_count * sizeof *p->weights);
        for (uint32_t i = 0; i < g->target_count; i++)
            p->weight_set[i] = true;
        p->weights_given = true;
    }
    *adjust = malloc((g->joint_count ? g->joint_count : 1u) * sizeof **adjust);
    if (*adjust == NULL) {
        psc_pose_file_free(&pf);
        return psc_io_errorf(err, errlen, a->pose_file, "out of memory");
    }
    static const psc_gltf_adjust_t none = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}};
    for (uint32_t j = 0; j < g->joint_count; j++)
        (*adjust)[j] = none;
    int rc = 0;
    for (unsigned k = 0; k < pf.count && rc == 0; k++) {
        const psc_pose_node_t *n = &pf.nodes[k];
        int32_t j = psc_gltf_joint_for_key(g, n->name, n->index);
        if (j < 0)
            rc = psc_io_errorf(err, errlen, a->pose_file, "node '%s' is neither a node's name nor its number in %s",
                               n->name, a->model);
        else
            psc_pose_node_matrices(n, (*adjust)[j].pre, (*adjust)[j].post);
    }
    a->time = pf.time;
    psc_pose_file_free(&pf);
    return rc;
}

int psc_render_gltf_main(const char *prog, int argc, char **argv)
{
    gltf_args_t a = {.view = psc_render_view_defaults(30, 20, 2.5, 50), .time = -1.0};
    int rc = parse_args(prog, argc, argv, &a);
    if (rc != 0)
        return rc;
    const psc_render_view_t *vw = &a.view;
    char err[768], note[256] = "";
    psc_gltf_t g;
    if (psc_gltf_load(a.model, &g, note, sizeof note, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        return 1;
    }
    rc = 1;
    posed_t p;
    psc_io_shadow_t sf = {0};
    psc_shadow_t sh;
    void *sh_ws = NULL;
    psc_render_target_t rt = {0};
    psc_gltf_adjust_t *adjust = NULL;
    if (posed_new(&p, &g, a.model, err, sizeof err) != 0 ||
        (a.pose_file && pose_from_file(&a, &g, &p, &adjust, err, sizeof err) != 0)) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    if (a.shadow) {
        if (psc_io_shadow_load(a.shadow, &sf, err, sizeof err) != 0) {
            fprintf(stderr, "%s: %s\n", prog, err);
            goto done;
        }
        size_t n = psc_shadow_workspace_size(&sf.model, NULL);
        if (posix_memalign(&sh_ws, 64, n ? n : 8) != 0 ||
            psc_shadow_init_mesh(&sh, &sf.model, g.joint_count, sh_ws, n) != PSC_OK) {
            fprintf(stderr, "%s: %s: made for another model (%u joints, %s has %u)\n", prog, a.shadow,
                    (unsigned)sf.model.bone_count, a.model, (unsigned)g.joint_count);
            goto done;
        }
    }
    /* the camera: on the rest pose's box, in units of R (the meshes' own weights) */
    bool given = p.weights_given;
    p.weights_given = false;
    pose(&p, &g, -1.0, NULL);
    p.weights_given = given;
    psc_vec3_q16_t lo = {INT32_MAX, INT32_MAX, INT32_MAX}, hi = {INT32_MIN, INT32_MIN, INT32_MIN};
    for (uint32_t i = 0; i < p.mesh.vertex_count; i++) {
        const int32_t *v = &p.pos_q16[3 * i];
        lo = (psc_vec3_q16_t){v[0] < lo.x ? v[0] : lo.x, v[1] < lo.y ? v[1] : lo.y, v[2] < lo.z ? v[2] : lo.z};
        hi = (psc_vec3_q16_t){v[0] > hi.x ? v[0] : hi.x, v[1] > hi.y ? v[1] : hi.y, v[2] > hi.z ? v[2] : hi.z};
    }
    psc_3d_draw_t dd[PSC_GLTF_DRAWS_MAX], d;
    unsigned nd = 0;
    psc_3d_draw_defaults(&d, &p.mesh);
    d.cull_back = vw->cull;
    /* every draw names all the vertices: the frame transforms them once a draw */
    psc_3d_config_t cfg = {vw->width, vw->height, 0, 0, 32, psc_io_bam_from_deg(vw->hfov), 0, 0,
                           p.mesh.vertex_count * p.parts, vw->hsr};
    if (psc_render_view_orbit(vw, lo, hi, &d.camera_from_object, &cfg.near_q16, &cfg.far_q16) != PSC_OK) {
        fprintf(stderr, "%s: %s: the orbit view does not fit the fixed-point range\n", prog, a.model);
        goto done;
    }
    if (psc_render_view_shade(vw, &d, 1, a.model, err, sizeof err) != 0 ||
        psc_render_target_open_view(&rt, &cfg, vw, false, a.model, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    if (d.shade == PSC_SHADE_PHONG) { /* the light of light() below, per pixel instead of baked into the colours */
        d.light_dir = psc_vec3_normalize(psc_mat4_apply_dir(&d.camera_from_object, (psc_vec3_q16_t){26214, 52429, 29491}));
        d.ambient_q8 = 115;
    }
    for (unsigned k = 0; k < p.parts; k++) {
        if (p.part[k].triangle_count == 0)
            continue;
        dd[nd] = d;
        dd[nd].mesh = &p.part[k];
        if (p.part_opacity_q8[k] < 256) { /* translucent: composited by the A-buffer (--aa), else blended in order */
            dd[nd].blend = PSC_BLEND_ALPHA;
            dd[nd].opacity_q8 = p.part_opacity_q8[k];
        }
        nd++;
    }
    psc_3d_stats_t st = {0};
    double t_shade = 0;
    for (unsigned long k = 0; k < vw->repeat; k++) {
        pose(&p, &g, a.time, adjust);
        double t0 = psc_render_seconds();
        if (a.shadow) {
            psc_shadow_update_bones(&sh, p.skin_q16, g.joint_count);
            psc_shadow_apply_mesh(&sh, p.pos_q16, p.nrm_q14, p.color, p.mesh.vertex_count, PSC_SHADOW_STRENGTH_Q16,
                                  p.ao);
        }
        t_shade += psc_render_seconds() - t0;
        if (d.shade != PSC_SHADE_PHONG)
            light(&p);
        uint32_t bg = BACKGROUND;
        psc_status_t s = psc_render_target_frame(&rt, dd, nd, bg, &st);
        if (s != PSC_OK) {
            fprintf(stderr, "%s: %s: drawing failed: %s\n", prog, a.model, psc_status_str(s));
            goto done;
        }
    }
    if (vw->repeat > 1)
        fprintf(stderr, "%s: %lu frames of %ux%u: self-shadowing %.3f ms per frame (%u vertices)\n", prog, vw->repeat,
                (unsigned)vw->width, (unsigned)vw->height, t_shade / vw->repeat * 1e3, (unsigned)p.mesh.vertex_count);
    psc_render_target_note(&rt, &st, prog, a.model);
    if (psc_render_target_write(&rt, a.out, NULL, err, sizeof err) != 0 ||
        (a.dump_ao && write_ao(&p, a.dump_ao, err, sizeof err) != 0)) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    rc = 0;
done:
    free(adjust);
    psc_render_target_close(&rt);
    free(sh_ws);
    psc_io_shadow_free(&sf);
    posed_free(&p);
    psc_gltf_free(&g);
    return rc;
}
