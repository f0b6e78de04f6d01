/* SPDX-License-Identifier: MIT */
/*
 * periscope-shadow - build the self-shadowing tables of a character (stage
 * one of the sphere-occluder self-shadowing, host_tools/lib/bake/shadow.h):
 *
 *   periscope-shadow build MODEL.{mdl,bpt,ppk,gltf,glb,obj} -o M.pao [--levels L] [--spheres N] [--table-size N]
 *                    [--skin-from D.mdl] [--no-rest]
 *
 * A glTF model (through libassimp) gets tables for its joints, an OBJ file for its groups. The device's
 * character scene finds M.pao beside its .ppk (same name) and
 * shades the character with it. Exit status: 0 done, 1 the work failed, 2 bad
 * arguments.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "import/obj.h"
#include "util/cli_values.h"
#include "bake/patch_any.h"
#include "psc_io_cli.h"
#include "psc_io_file.h"
#include "bake/shadow.h"

#define PROG "periscope-shadow"

static void print_usage(const char *prog, FILE *f)
{
    (void)prog;   /* the same as PROG */
    fprintf(f,
            "usage: " PROG " build MODEL.{mdl,bpt,ppk,gltf,glb,obj} -o M.pao [--levels L] [--spheres N] [--table-size N]\n"
            "       [--skin-from D.mdl] [--no-rest]\n"
            "\n"
            "Precompute a character's or a glTF model's self-shadowing: the sphere tree fitted to its rest pose, the\n"
            "spheres' skin, the accessibility map and the composite arc map, and each vertex's rest correction (the\n"
            "ray-traced occlusion less the spheres', averaged over the rest pose and four times through each\n"
            "action, with one gain on the spheres fitted over the same poses) and, for a patch character with\n"
            "actions (a .ppk made with them), the same at eight phases of each action, which a\n"
            "frame of that action interpolates; for a character of large patches (composed at every vertex, as\n"
            "the teapot), the correction over each patch's (u, v) at rest instead; as a shadow pack. A model\n"
            "libassimp reads as .fbx, .dae, .x, .3ds or .blend is taken as a glTF model is.\n"
            "\n"
            "  --levels L          levels of the sphere tree, 1..4 (default 4: 8, 32, 128, 512 spheres)\n"
            "  --spheres N         spheres on the finest level (default 512)\n"
            "  --table-size N      the accessibility map's side (default 32; the composite map's is half)\n"
            "  --skin-from D.mdl   for an A:M model that assigns no CP to a bone (as periscope-patch)\n"
            "  --no-rest           no rest correction: the spheres alone (smaller pack, faster bake)\n"
            "  -o M.pao            the pack (written whole, or not at all)\n"
            "  --version, --help\n");
}

#define usage_error(...) psc_io_cli_usage_error(PROG, __VA_ARGS__)

static const struct option shadow_options[] = {
    {"levels", required_argument, NULL, 1},
    {"spheres", required_argument, NULL, 1},
    {"table-size", required_argument, NULL, 1},
    {"skin-from", required_argument, NULL, 1},
    {"no-rest", no_argument, NULL, 1},
    PSC_IO_CLI_COMMON_OPTIONS,
};

int main(int argc, char **argv)
{
    psc_bake_shadow_opts_t o = {.levels = PSC_BAKE_SHADOW_LEVELS, .spheres = PSC_BAKE_SHADOW_SPHERES, .table = 32};
    psc_bake_patch_opts_t lo = {.quiet = true};
    const char *model = NULL, *out = NULL;
    psc_io_cli_t c;
    char err[768], note[512] = "";
    int opt;

    psc_io_cli_begin(&c, argc, argv, "ho:", shadow_options);
    while ((opt = psc_io_cli_next_option(&c, PROG, "", print_usage)) > 0) {
        unsigned long v;
        if (strcmp(c.name, "-o") == 0) {
            out = c.arg;
        } else if (strcmp(c.name, "--levels") == 0) {
            if (psc_cli_parse_uint(c.arg, 1, 4, &v) != 0)
                return usage_error("--levels '%s': expected 1..4", c.arg);
            o.levels = (unsigned)v;
        } else if (strcmp(c.name, "--spheres") == 0) {
            if (psc_cli_parse_uint(c.arg, 8, 2048, &v) != 0)
                return usage_error("--spheres '%s': expected 8..2048", c.arg);
            o.spheres = (unsigned)v;
        } else if (strcmp(c.name, "--table-size") == 0) {
            if (psc_cli_parse_uint(c.arg, 4, 128, &v) != 0)
                return usage_error("--table-size '%s': expected 4..128", c.arg);
            o.table = (unsigned)v;
        } else if (strcmp(c.name, "--skin-from") == 0) {
            lo.skin_from = c.arg;
        } else if (strcmp(c.name, "--no-rest") == 0) {
            o.no_rest = true;
        }
    }
    if (opt < 0)
        return -opt;   /* the mistake, said */
    int rc = psc_io_cli_command_file(&c, PROG, "build", PROG " build MODEL -o M.pao", "model", &model);
    if (rc != 0)
        return rc;
    if (!out)
        return usage_error("no output given (-o M.pao)");
    psc_io_patch_t pf = {0};
    psc_gltf_t g = {0};
    bool gltf = psc_gltf_is_file(model) || psc_obj_is_file(model);
    char load_note[256] = "";
    if (gltf ? psc_gltf_load(model, &g, load_note, sizeof load_note, err, sizeof err) != 0
             : psc_bake_patch_any(model, &lo, &pf, err, sizeof err) != 0) {
        fprintf(stderr, PROG ": %s\n", err);
        return 1;
    }
    uint8_t *bytes = NULL;
    size_t len = 0;
    rc = 1;
    if ((gltf ? psc_bake_shadow_gltf(&g, &o, model, &bytes, &len, note, sizeof note, err, sizeof err)
              : psc_bake_shadow(&pf.model, &o, model, &bytes, &len, note, sizeof note, err, sizeof err)) != 0 ||
        psc_io_write_atomic(out, bytes, len, err, sizeof err) != 0)
        fprintf(stderr, PROG ": %s\n", err);
    else {
        printf("%s: %s, %zu bytes\n", out, note, len);
        rc = 0;
    }
    free(bytes);
    psc_io_patch_free(&pf);
    psc_gltf_free(&g);
    return rc;
}
