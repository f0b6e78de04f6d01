/* SPDX-License-Identifier: MIT */
/*
 * periscope-patch - build the patch pack (core/patch/psc_patch.h) the device
 * plays a Hash patch character from: an Animation:Master model with its
 * actions (each baked from the model's rig), or a Newell .bpt patch file.
 *
 *   periscope-patch MODEL.{mdl,bpt} [--action A.act]... [--bvh M.bvh]... [--bvh-map MAP]
 *                   [--skin-from D.mdl] [--deform B1,B2,...] -o OUT.ppk
 *
 * Exit status: 0 done, 1 the work failed, 2 bad arguments.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake/patch_any.h"
#include "psc_io_cli.h"
#include "psc_io_file.h"

#define PROG "periscope-patch"

static void print_usage(const char *prog, FILE *f)
{
    (void)prog;   /* the same as PROG */
    fprintf(f,
            "usage: " PROG " MODEL.{mdl,bpt} [--action A.act]... [--skin-from D.mdl] [--deform B1,B2,..] -o OUT.ppk\n"
            "\n"
            "Build a patch pack for the device's character scene from an Animation:Master model\n"
            "(.mdl: splines, stacked CPs, hooks, patches, bias, bones and their CPs) with its\n"
            "actions (.act: baked from the model's rig, 30 samples a second, by bone name), or\n"
            "from a Newell Bezier patch file (.bpt).\n"
            "\n"
            "  --action A.act      an action to carry (repeat for more; the device plays them in turn)\n"
            "  --skin-from D.mdl   take the CP-to-bone assignments of another model of the same\n"
            "                      character (for a model that assigns none)\n"
            "  --deform B1,B2,..   else: the bones each point may follow (the nearest one)\n"
            "  --bvh M.bvh         a motion capture to carry as an action, retargeted by bone name\n"
            "                      (repeat for more; after the .act actions)\n"
            "  --bvh-map MAP       \"bvh_joint = model bone\" lines (default: the common mocap names\n"
            "                      to Animation:Master's)\n"
            "  -o OUT.ppk          the pack (written whole, or not at all)\n"
            "  --version           the program's version\n"
            "  --help              this text\n"
            "Options take their value as --opt VALUE or --opt=VALUE, before or after the model.\n");
}

#define usage_error(...) psc_io_cli_usage_error(PROG, __VA_ARGS__)

static const struct option patch_options[] = {
    {"action", required_argument, NULL, 1},
    {"skin-from", required_argument, NULL, 1},
    {"deform", required_argument, NULL, 1},
    {"bvh", required_argument, NULL, 1},
    {"bvh-map", required_argument, NULL, 1},
    PSC_IO_CLI_COMMON_OPTIONS,
};

int main(int argc, char **argv)
{
    psc_bake_patch_opts_t o = {0};
    const char *model = NULL;
    psc_io_cli_t c;
    char err[768];
    int opt;

    psc_io_cli_begin(&c, argc, argv, "ho:", patch_options);
    while ((opt = psc_io_cli_next_option(&c, PROG, "", print_usage)) > 0) {
        if (strcmp(c.name, "-o") == 0) {
            o.write_pack = c.arg;
        } else if (strcmp(c.name, "--action") == 0) {
            if (o.action_count >= PSC_BAKE_PATCH_MAX_ACTIONS)
                return usage_error("at most %u actions", PSC_BAKE_PATCH_MAX_ACTIONS);
            o.actions[o.action_count++] = c.arg;
        } else if (strcmp(c.name, "--skin-from") == 0) {
            o.skin_from = c.arg;
        } else if (strcmp(c.name, "--deform") == 0) {
            o.deform = c.arg;
        } else if (strcmp(c.name, "--bvh") == 0) {
            if (o.capture_count >= PSC_BAKE_PATCH_MAX_ACTIONS)
                return usage_error("at most %u captures", PSC_BAKE_PATCH_MAX_ACTIONS);
            o.captures[o.capture_count++] = c.arg;
        } else if (strcmp(c.name, "--bvh-map") == 0) {
            o.capture_map = c.arg;
        }
    }
    if (opt < 0)
        return -opt;   /* the mistake, said */
    int rc = psc_io_cli_one_file(&c, PROG, "model", &model);
    if (rc != 0)
        return rc;
    if (!o.write_pack)
        return usage_error("no output given (-o OUT.ppk)");
    if (psc_io_file_has_magic(model, PSC_PATCH_MAGIC, PSC_CONTAINER_MAGIC_SIZE))
        return usage_error("%s is a patch pack already", model);

    psc_io_patch_t pf;
    if (o.action_count + o.capture_count)
        fprintf(stderr, PROG ": baking %u action%s on %s\n", o.action_count + o.capture_count,
                o.action_count + o.capture_count == 1 ? "" : "s", model);
    if (psc_bake_patch_any(model, &o, &pf, err, sizeof err) != 0) {
        fprintf(stderr, PROG ": %s\n", err);
        return 1;
    }
    const psc_patch_model_t *m = &pf.model;
    printf("%s: %u points, %u CPs, %u splines, %u hooks, %u edges, %u patches, %u bones, %u actions "
           "(%u channels, %u keys), %zu bytes\n",
           o.write_pack, (unsigned)m->point_count, (unsigned)m->cp_count, (unsigned)m->spline_count,
           (unsigned)m->hook_count, (unsigned)m->edge_count, (unsigned)m->face_count, (unsigned)m->bone_count,
           (unsigned)m->action_count, (unsigned)m->channel_count, (unsigned)m->key_count, pf.len);
    psc_io_patch_free(&pf);
    return 0;
}
