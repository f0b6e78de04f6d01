/* SPDX-License-Identifier: MIT */
/* patch.c - periscope-render's patch mode (patch.h). */
#include "render/patch.h"
#include "util/cli_values.h"
#include "bake/patch_any.h"
#include "measure/patch.h"
#include "measure/surface.h"
#include "psc_io_cli.h"
#include "psc_io_error.h"
#include "psc_io_file.h"
#include "anim/patch_pose.h"
#include "render/target.h"
#include "render/cli.h"
#include "render/view.h"
#include "util/text_out.h"
#include "3d/psc_3d_render.h"
#include "shadow/psc_shadow_frame.h"
#include "psc_io_angle.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BACKGROUND 0x30343Cu

typedef struct {
    const char *model, *out, *depth, *dump_obj, *play, *shadow, *dump_ao, *pose_file;
    psc_bake_patch_opts_t load;
    psc_render_view_t view;
    double flatness, tol_px, time;
    bool stats, rest;
    unsigned long tile;
} patch_args_t;

bool psc_render_patch_wanted(int argc, char **argv)
{
    return psc_render_cli_has_file(argc, argv, psc_bake_patch_wanted);
}

static void usage(const char *prog, FILE *f)
{
    fprintf(f,
            "usage: %s MODEL.{mdl,bpt,ppk} -o view.png [options]\n"
            "\n"
            "Render a Hash patch character (Animation:Master model, Newell .bpt patches or a\n"
            "patch pack), posed by an action, with the device's tessellator and 3D pipeline.\n"
            "\n"
            "  --orbit Y,P,D       camera at D x R from the rest pose's box centre (R: half its\n"
            "                      diagonal), turned up by P then right by Y degrees (default 30,10,2.5)\n"
            "  --hfov F            horizontal field of view in degrees (default 50)\n"
            "  --size WxH          output size (default 640x480)\n"
            "  --flatness TOL      allowed chord error as a fraction of R, everywhere\n"
            "  --tol-px P          allowed chord error in pixels at each curve's depth (default 0.5)\n"
            "  --action A.act      an action for an A:M model (repeat for more; the first plays)\n"
            "  --play NAME         which of the character's actions plays (default: the first)\n"
            "  --time T            seconds into the action (default 0; it loops)\n"
            "  --pose P            rest, t=T (T seconds into the action, as --time) or POSE.json:\n"
            "                      {\"time\": T, \"nodes\": {\"BONE NUMBER\": {\"rotate\": [ax, ay, az, deg],\n"
            "                      \"translate\": [x, y, z]}}}, local' = T local R on top of the action\n"
            "  --skin-from D.mdl   take CP-to-bone assignments from another model of the character\n"
            "  --deform B1,B2,..   the bones that deform a model that assigns no CP to a bone\n"
            "  --bvh M.bvh         a motion capture, retargeted by bone name (after the actions)\n"
            "  --bvh-map MAP       \"bvh_joint = model bone\" lines (default: common mocap names)\n"
            "  --cull back|none    drop patches and triangles facing away (default back)\n"
            "  --tiles N           render in N x N pixel tiles (0: full screen)\n"
            "  --depth D.pgm       also write the normalised depth as a 16-bit PGM\n"
            "  --format F          output surface: rgb565 (default) or xrgb8888\n"
            PSC_RENDER_VIEW_LOOK_HELP
            "  --stats             print patches=N triangles=T max_chord_err=E crack_edges=C culled=K\n"
            "                      (E as a fraction of R, measured; C: shared edges whose sides differ)\n"
            "  --dump-obj T.obj    write the tessellation drawn as an OBJ file\n"
            "  --shadow M.pao      self-shadowing from the character's sphere-occluder tables\n"
            "                      (periscope-shadow build)\n"
            "  --dump-ao AO.csv    with --shadow: x,y,z,nx,ny,nz,occlusion of every shaded vertex\n"
            "                      (model coordinates; occlusion 0..1 of the cosine-weighted hemisphere)\n"
            "  --write-pack P.ppk  write the patch pack the view was drawn from\n"
            "  --repeat K          pose, tessellate and draw K times, and report the time per frame\n"
            "  -o view.png         output PNG\n"
            "  --version           the program's version\n"
            "  --help              this text\n",
            prog);
}

static const struct option patch_options[] = {
    {"flatness", required_argument, NULL, 1}, {"tol-px", required_argument, NULL, 1},
    {"action", required_argument, NULL, 1}, {"play", required_argument, NULL, 1},
    {"time", required_argument, NULL, 1}, {"pose", required_argument, NULL, 1},
    {"skin-from", required_argument, NULL, 1}, {"deform", required_argument, NULL, 1},
    {"bvh", required_argument, NULL, 1}, {"bvh-map", required_argument, NULL, 1},
    {"tiles", required_argument, NULL, 1}, {"depth", required_argument, NULL, 1},
    {"stats", no_argument, NULL, 1}, {"dump-obj", required_argument, NULL, 1},
    {"write-pack", required_argument, NULL, 1}, {"shadow", required_argument, NULL, 1},
    {"dump-ao", required_argument, NULL, 1},
    {NULL, 0, NULL, 0},
};

static int patch_option(const char *prog, const char *name, const char *v, void *args)
{
    patch_args_t *a = args;
    if (strcmp(name, "--flatness") == 0) {
        if (psc_cli_parse_double(v, &a->flatness) != 0 || !(a->flatness >= 1e-4 && a->flatness <= 1.0))
            return psc_io_cli_usage_error(prog, "--flatness '%s': expected a fraction of R in 0.0001..1", v);
    } else if (strcmp(name, "--tol-px") == 0) {
        if (psc_cli_parse_double(v, &a->tol_px) != 0 || !(a->tol_px >= 0.01 && a->tol_px <= 1000.0))
            return psc_io_cli_usage_error(prog, "--tol-px '%s': expected pixels in 0.01..1000", v);
    } else if (strcmp(name, "--action") == 0) {
        if (a->load.action_count >= PSC_BAKE_PATCH_MAX_ACTIONS)
            return psc_io_cli_usage_error(prog, "at most %u actions", PSC_BAKE_PATCH_MAX_ACTIONS);
        a->load.actions[a->load.action_count++] = v;
    } else if (strcmp(name, "--play") == 0) {
        a->play = v;
    } else if (strcmp(name, "--time") == 0) {
        if (psc_cli_parse_double(v, &a->time) != 0 || !(a->time >= 0.0 && a->time <= 3600.0))
            return psc_io_cli_usage_error(prog, "--time '%s': expected seconds in 0..3600", v);
    } else if (strcmp(name, "--pose") == 0) {
        const char *file;
        double t = a->time;
        int rc = psc_pose_option(prog, v, &file, &t);
        if (rc != 0)
            return rc;
        if (file) {
            a->pose_file = file;
        } else {
            a->rest = t < 0;
            a->time = a->rest ? a->time : t;
        }
    } else if (strcmp(name, "--skin-from") == 0) {
        a->load.skin_from = v;
    } else if (strcmp(name, "--deform") == 0) {
        a->load.deform = v;
    } else if (strcmp(name, "--bvh") == 0) {
        if (a->load.capture_count >= PSC_BAKE_PATCH_MAX_ACTIONS)
            return psc_io_cli_usage_error(prog, "at most %u captures", PSC_BAKE_PATCH_MAX_ACTIONS);
        a->load.captures[a->load.capture_count++] = v;
    } else if (strcmp(name, "--bvh-map") == 0) {
        a->load.capture_map = v;
    } else if (strcmp(name, "--tiles") == 0) {
        if (psc_cli_parse_uint(v, 0, PSC_MAX_OUT_DIM, &a->tile) != 0)
            return psc_io_cli_usage_error(prog, "--tiles '%s': expected a tile side of 0..%u pixels", v,
                                          (unsigned)PSC_MAX_OUT_DIM);
    } else if (strcmp(name, "--depth") == 0) {
        a->depth = v;
    } else if (strcmp(name, "--stats") == 0) {
        a->stats = true;
    } else if (strcmp(name, "--dump-obj") == 0) {
        a->dump_obj = v;
    } else if (strcmp(name, "--shadow") == 0) {
        a->shadow = v;
    } else if (strcmp(name, "--dump-ao") == 0) {
        a->dump_ao = v;
    } else if (strcmp(name, "--write-pack") == 0) {
        a->load.write_pack = v;
    }
    return 0;
}

static int parse_args(const char *prog, int argc, char **argv, patch_args_t *a)
{
    static const psc_render_cli_t cli = {" (patch mode)", "model", usage, patch_options, patch_option};
    int rc = psc_render_cli_parse(&cli, prog, argc, argv, &a->view, &a->model, &a->out, a);
    if (rc != 0)
        return rc;
    if (a->dump_ao && !a->shadow)
        return psc_io_cli_usage_error(prog, "--dump-ao needs --shadow M.pao");
    if (a->flatness > 0.0 && a->tol_px > 0.0)
        return psc_io_cli_usage_error(prog, "--flatness and --tol-px both given: choose one");
    return 0;
}

/* A tessellator over model m with its own workspace. */
typedef struct {
    psc_patch_t p;
    void *ws;
} tess_t;

static int tess_new(tess_t *t, const psc_patch_model_t *m, uint8_t max_depth)
{
    psc_patch_limits_t lim = {PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES, 1u << 21, max_depth};
    size_t size = psc_patch_workspace_size(m, &lim);
    t->ws = NULL;
    if (size == 0 || posix_memalign(&t->ws, 64, size) != 0)
        return -1;
    return psc_patch_init(&t->p, m, &lim, t->ws, size) == PSC_OK ? 0 : -1;
}

static int find_action(const psc_patch_model_t *m, const char *name)
{
    if (m->action_count == 0)
        return -1;
    if (name == NULL)
        return 0;
    for (uint32_t i = 0; i < m->action_count; i++)
        if (strncmp(m->actions[i].name, name, sizeof m->actions[i].name) == 0)
            return (int)i;
    return -2;
}

/* --dump-ao: every vertex of the frame with its occlusion, in the model's own units. */
static int write_ao(const psc_patch_t *p, const uint32_t *occlusion, const psc_patch_model_t *m, const char *path,
                    char *err, size_t errlen)
{
    psc_text_out_t out;
    if (psc_text_out_begin(&out, path, err, errlen) != 0)
        return -1;
    FILE *f = out.f;
    double r = m->scale_q16 / 65536.0;
    fprintf(f, "x,y,z,nx,ny,nz,occlusion\n");
    for (uint32_t i = 0; i < p->vtx_total; i++) {
        int32_t n[3] = {p->out_nrm[3 * i] * 4, p->out_nrm[3 * i + 1] * 4, p->out_nrm[3 * i + 2] * 4};
        uint32_t occ = occlusion[i];
        fprintf(f, "%.5f,%.5f,%.5f,%.4f,%.4f,%.4f,%.4f\n", p->out_pos[3 * i] / 65536.0 * r + m->center_q16[0] / 65536.0,
                p->out_pos[3 * i + 1] / 65536.0 * r + m->center_q16[1] / 65536.0,
                p->out_pos[3 * i + 2] / 65536.0 * r + m->center_q16[2] / 65536.0, n[0] / 65536.0, n[1] / 65536.0,
                n[2] / 65536.0, occ / 65536.0);
    }
    return psc_text_out_finish(&out, path, err, errlen);
}

/* Pose, solve and tessellate one tessellator. */
static psc_status_t frame(psc_patch_t *p, int action, uint32_t ms, const psc_pose_file_t *adjust,
                          const psc_patch_camera_t *cam, psc_patch_stats_t *st)
{
    psc_patch_pose_begin(p, action, ms);
    if (adjust)
        psc_anim_patch_pose(p, adjust);
    psc_patch_pose_finish(p);
    psc_patch_tangents(p);
    return psc_patch_tessellate(p, cam, st);
}

/* The depth the reference surface is halved to for --stats: 2^6 x 2^6 points a four-sided patch, as fine as the
 * device's deepest grid. */
#define STATS_SURFACE_DEPTH 6u

/*
 * The stats line: cracks, and the chord error against the double-precision
 * reference surface of the same pose (measure/surface.h), measured on a
 * culling-free tessellation of the same frame. With --flatness, a patch whose
 * error is over the tolerance (held at the depth cap) is named, with what it
 * reached: never a silent miss.
 */
static int print_stats(const char *prog, const psc_patch_model_t *m, int action, uint32_t ms,
                       const psc_pose_file_t *pose, const psc_patch_camera_t *cam, const psc_patch_stats_t *st)
{
    tess_t open = {0};
    psc_patch_camera_t c = *cam;
    psc_measure_surface_t surf = {0};
    double *face_err = malloc((m->face_count ? m->face_count : 1u) * sizeof *face_err);
    int result = -1;
    c.cull = false;
    if (!face_err || tess_new(&open, m, PSC_PATCH_MAX_DEPTH) != 0 || frame(&open.p, action, ms, pose, &c, NULL) != PSC_OK ||
        psc_measure_surface_build(&open.p, STATS_SURFACE_DEPTH, &surf) != 0)
        goto done;
    long cracks = psc_measure_cracks(&open.p);
    double chord = psc_measure_surface_chord(&open.p, &surf, face_err);
    if (cracks < 0 || chord < 0)
        goto done;
    printf("patches=%u triangles=%u max_chord_err=%.6f crack_edges=%ld culled=%u\n", (unsigned)st->patches,
           (unsigned)st->triangles, chord, cracks, (unsigned)st->culled);
    double tol = cam->tol_units_q16 / 65536.0;
    if (tol > 0 && chord > tol) {
        unsigned over = 0;
        for (uint32_t f = 0; f < m->face_count; f++)
            over += face_err[f] > tol;
        fprintf(stderr, "%s: note: %u patch%s did not reach --flatness %.6f (%u edges or patches held at the depth cap, "
                "%u halvings):", prog, over, over == 1 ? "" : "es", tol, (unsigned)st->depth_capped,
                (unsigned)PSC_PATCH_MAX_DEPTH);
        for (uint32_t f = 0, said = 0; f < m->face_count && said < 8u; f++)
            if (face_err[f] > tol) {
                fprintf(stderr, "%s patch %u %.6f", said ? "," : "", (unsigned)f, face_err[f]);
                said++;
            }
        fprintf(stderr, "%s\n", over > 8u ? ", ..." : "");
    }
    result = 0;
done:
    psc_measure_surface_free(&surf);
    free(face_err);
    free(open.ws);
    return result;
}

int psc_render_patch_main(const char *prog, int argc, char **argv)
{
    patch_args_t a = {.view = psc_render_view_defaults(30, 10, 2.5, 50)};
    int rc = parse_args(prog, argc, argv, &a);
    if (rc != 0)
        return rc;
    const psc_render_view_t *vw = &a.view;
    if (a.flatness == 0.0 && a.tol_px == 0.0)
        a.tol_px = 0.5;
    char err[768];
    psc_io_patch_t pf;
    if (psc_bake_patch_any(a.model, &a.load, &pf, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        return 1;
    }
    const psc_patch_model_t *m = &pf.model;
    rc = 1;
    tess_t t = {0};
    psc_render_target_t rt = {0};
    psc_io_shadow_t sf = {0};
    psc_shadow_t sh;
    void *sh_ws = NULL;
    uint32_t *ao = NULL;          /* --dump-ao: each vertex's occlusion as the frame shows it */
    psc_pose_file_t pose = {0};
    bool shaded = false;
    int action = find_action(m, a.play);
    if (action == -2) {
        fprintf(stderr, "%s: %s has no action named '%s'\n", prog, a.model, a.play);
        goto done;
    }
    if (a.pose_file) {   /* --pose POSE.json: its time, its bones */
        if (psc_pose_file_load(a.pose_file, &pose, err, sizeof err) != 0 ||
            psc_anim_patch_pose_check(m, &pose, a.pose_file, err, sizeof err) != 0) {
            fprintf(stderr, "%s: %s\n", prog, err);
            goto done;
        }
        a.rest = pose.time < 0;
        a.time = pose.time < 0 ? 0.0 : pose.time;
    }
    if (a.rest)
        action = -1;   /* --pose rest */
    if (tess_new(&t, m, PSC_PATCH_MAX_DEPTH) != 0) {
        fprintf(stderr, "%s: out of memory for the tessellation of %s\n", prog, a.model);
        goto done;
    }
    if (a.shadow) {
        psc_status_t ss;
        if (psc_io_shadow_load(a.shadow, &sf, err, sizeof err) != 0) {
            fprintf(stderr, "%s: %s\n", prog, err);
            goto done;
        }
        size_t n = psc_shadow_workspace_size(&sf.model, m);
        if (posix_memalign(&sh_ws, 64, n ? n : 8) != 0 ||
            (ss = psc_shadow_init(&sh, &sf.model, m, sh_ws, n)) != PSC_OK) {
            fprintf(stderr, "%s: %s: made for another character (%u bones, %s has %u)\n", prog, a.shadow,
                    (unsigned)sf.model.bone_count, a.model, (unsigned)m->bone_count);
            goto done;
        }
        shaded = true;
        if (a.dump_ao && (ao = malloc((size_t)PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES * sizeof *ao)) == NULL) {
            fprintf(stderr, "%s: out of memory\n", prog);
            goto done;
        }
    }
    psc_vec3_q16_t lo = {m->lo_q16[0], m->lo_q16[1], m->lo_q16[2]}, hi = {m->hi_q16[0], m->hi_q16[1], m->hi_q16[2]};
    psc_patch_camera_t cam = {0};
    int32_t near_q16, far_q16;
    if (psc_render_view_orbit(vw, lo, hi, &cam.camera_from_object, &near_q16, &far_q16) != PSC_OK) {
        fprintf(stderr, "%s: %s: the orbit view does not fit the fixed-point range\n", prog, a.model);
        goto done;
    }
    double focal = vw->width / 2.0 / tan(vw->hfov * M_PI / 360.0);
    cam.focal_px_q16 = (int32_t)lround(focal * 65536.0);
    cam.tol_px_q16 = a.tol_px > 0.0 ? (int32_t)lround(a.tol_px * 65536.0) : 0;
    cam.tol_units_q16 = a.flatness > 0.0 ? (int32_t)lround(a.flatness * 65536.0) : 0;
    cam.near_q16 = near_q16;
    cam.cull = vw->cull;
    uint32_t ms = (uint32_t)lround(a.time * 1000.0);
    psc_patch_stats_t st;
    psc_status_t s;
    double t_tess = 0.0, t_draw = 0.0;
    psc_3d_config_t cfg = {vw->width, vw->height, (uint16_t)a.tile, (uint16_t)a.tile, 32, psc_io_bam_from_deg(vw->hfov),
                           near_q16, far_q16, PSC_PATCH_MAX_BATCHES * PSC_PATCH_BATCH_VERTICES, vw->hsr};
    psc_3d_stats_t drawn = {0};
    if (psc_render_target_open_view(&rt, &cfg, vw, a.depth != NULL, a.model, err, sizeof err) != 0) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    for (unsigned long k = 0; k < vw->repeat; k++) {
        double t0 = psc_render_seconds();
        /* a repeated run plays the action from the given time on, a frame at 60 Hz */
        uint32_t at = ms + (uint32_t)(k * 1000ul / 60ul);
        if ((s = frame(&t.p, action, at, a.pose_file ? &pose : NULL, &cam, &st)) != PSC_OK) {
            fprintf(stderr, "%s: %s: tessellation failed: %s\n", prog, a.model, psc_status_str(s));
            goto done;
        }
        if (shaded) {
            psc_shadow_update(&sh, &t.p);
            psc_shadow_apply(&sh, &t.p, PSC_SHADOW_STRENGTH_Q16, ao);
        }
        double t1 = psc_render_seconds();
        psc_3d_draw_t d[PSC_PATCH_MAX_BATCHES];
        unsigned n = psc_patch_draws(&t.p, &cam, d);
        if (psc_render_view_shade(vw, d, n, a.model, err, sizeof err) != 0) {
            fprintf(stderr, "%s: %s\n", prog, err);
            goto done;
        }
        uint32_t bg = BACKGROUND;
        if ((s = psc_render_target_frame(&rt, d, n, bg, &drawn)) != PSC_OK) {
            fprintf(stderr, "%s: %s: drawing failed: %s\n", prog, a.model, psc_status_str(s));
            goto done;
        }
        t_tess += t1 - t0;
        t_draw += psc_render_seconds() - t1;
    }
    if (vw->repeat > 1)
        fprintf(stderr, "%s: %lu frames of %ux%u: pose+tessellate %.3f ms, draw %.3f ms per frame (%u patches, "
                "%u triangles, %u reused)\n", prog, vw->repeat, (unsigned)vw->width, (unsigned)vw->height,
                t_tess / vw->repeat * 1e3, t_draw / vw->repeat * 1e3, (unsigned)st.patches, (unsigned)st.triangles,
                (unsigned)st.reused);
    psc_render_target_note(&rt, &drawn, prog, a.model);
    if (psc_render_target_write(&rt, a.out, a.depth, err, sizeof err) != 0 ||
        (a.dump_obj && psc_measure_write_obj(&t.p, a.dump_obj, err, sizeof err) != 0) ||
        (a.dump_ao && write_ao(&t.p, ao, m, a.dump_ao, err, sizeof err) != 0)) {
        fprintf(stderr, "%s: %s\n", prog, err);
        goto done;
    }
    if (a.stats && print_stats(prog, m, action, ms, a.pose_file ? &pose : NULL, &cam, &st) != 0) {
        fprintf(stderr, "%s: %s: out of memory measuring the tessellation\n", prog, a.model);
        goto done;
    }
    rc = 0;
done:
    free(t.ws);
    free(sh_ws);
    free(ao);
    psc_io_shadow_free(&sf);
    psc_pose_file_free(&pose);
    psc_render_target_close(&rt);
    psc_io_patch_free(&pf);
    return rc;
}
