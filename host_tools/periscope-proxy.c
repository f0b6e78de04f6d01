/* SPDX-License-Identifier: MIT */
/*
 * periscope-proxy - bake an articulated or skinned model into a proxy pack
 * (image-based rendering with proxy surface animation, core/proxy/psc_proxy.h;
 * the preprocessing: host_tools/lib/bake/proxy.h):
 *
 *   periscope-proxy bake MODEL.{gltf,glb,obj} -o M.ppx [--views K] [--tex N]
 *
 * The device's object scene and periscope-render M.ppx draw the pack. Exit
 * status: 0 done, 1 the work failed, 2 bad arguments.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/cli_values.h"
#include "import/gltf_model.h"
#include "bake/proxy.h"
#include "psc_io_cli.h"
#include "psc_io_file.h"

#define PROG "periscope-proxy"

static void print_usage(const char *prog, FILE *f)
{
    (void)prog;   /* the same as PROG */
    fprintf(f,
            "usage: " PROG " bake MODEL -o M.ppx [--views K] [--tex-mb M] [--pack-mb M] [--tex N] [--simplify F]\n"
            "       [--no-normals]\n"
            "\n"
            "Divide a model into parts (pieces that move without changing shape) and joints (the triangles\n"
            "between them), form a proxy surface for each, render each proxy's view textures from a grid of\n"
            "directions with the rest-pose lighting, and write them with the skeleton, the first animation\n"
            "and the full mesh as a proxy pack. OBJ groups are rigid parts.\n"
            "\n"
            "  --views K           at least K view directions: the smallest odd grid side whose square reaches\n"
            "                      K (default 64: 9 x 9, octahedral), or a larger one while the texel\n"
            "                      density holds (or stays at 200 texels per R or more) and the views\n"
            "                      stay within 2 K\n"
            "  --tex-mb M          the view textures' budget, mip levels included (default 14.5): one texel\n"
            "                      density for every proxy, the highest that fits, at most 256 texels per R\n"
            "  --pack-mb M         the pack's size at most (default 15): the textures get what the full mesh,\n"
            "                      the proxies and their coordinates leave, down to 0.25 MB\n"
            "  --tex N             the largest view texture's side, a power of two 8..512 (default 256)\n"
            "  --simplify F        the proxies: the model simplified as far as an error of 1 %% of R allows, and\n"
            "                      further (up to 4 %%) to at most this share of its triangles (default 0.25; a\n"
            "                      model of rigid parts alone 0.08, or 2000 triangles if more)\n"
            "  --no-normals        leave out the normals that relight the pack under another light\n"
            "                      (periscope-render --light; about a sixth of the textures' budget goes\n"
            "                      to them): a denser, baked-light-only pack\n"
            "  -o M.ppx            the pack (written whole, or not at all)\n"
            "  --version, --help\n");
}

#define usage_error(...) psc_io_cli_usage_error(PROG, __VA_ARGS__)

static const struct option proxy_options[] = {
    {"views", required_argument, NULL, 1},
    {"tex", required_argument, NULL, 1},
    {"simplify", required_argument, NULL, 1},
    {"tex-mb", required_argument, NULL, 1},
    {"pack-mb", required_argument, NULL, 1},
    {"no-normals", no_argument, NULL, 1},
    PSC_IO_CLI_COMMON_OPTIONS,
};

int main(int argc, char **argv)
{
    psc_bake_proxy_opts_t o = {PSC_BAKE_PROXY_VIEWS, PSC_BAKE_PROXY_TEX, 0 /* by the model */, PSC_BAKE_PROXY_TEX_MB,
                               PSC_BAKE_PROXY_PACK_MB, false};
    const char *model = NULL, *out = NULL;
    psc_io_cli_t c;
    char err[768], note[512] = "", load_note[256] = "";
    int opt;

    psc_io_cli_begin(&c, argc, argv, "ho:", proxy_options);
    while ((opt = psc_io_cli_next_option(&c, PROG, "", print_usage)) > 0) {
        unsigned long v;
        if (strcmp(c.name, "-o") == 0) {
            out = c.arg;
        } else if (strcmp(c.name, "--views") == 0) {
            if (psc_cli_parse_uint(c.arg, 4, 3969, &v) != 0)
                return usage_error("--views '%s': expected 4..3969", c.arg);
            o.views = (unsigned)v;
        } else if (strcmp(c.name, "--tex") == 0) {
            if (psc_cli_parse_uint(c.arg, 8, 512, &v) != 0 || (v & (v - 1u)) != 0)
                return usage_error("--tex '%s': expected a power of two 8..512", c.arg);
            o.tex = (unsigned)v;
        } else if (strcmp(c.name, "--tex-mb") == 0) {
            if (psc_cli_parse_double(c.arg, &o.tex_mb) != 0 || !(o.tex_mb >= 0.01 && o.tex_mb <= 4096))
                return usage_error("--tex-mb '%s': expected a size in MB, 0.01..4096", c.arg);
        } else if (strcmp(c.name, "--pack-mb") == 0) {
            if (psc_cli_parse_double(c.arg, &o.pack_mb) != 0 || !(o.pack_mb >= 0.1 && o.pack_mb <= 65536))
                return usage_error("--pack-mb '%s': expected a size in MB, 0.1..65536", c.arg);
        } else if (strcmp(c.name, "--no-normals") == 0) {
            o.no_normals = true;
        } else if (strcmp(c.name, "--simplify") == 0) {
            if (psc_cli_parse_double(c.arg, &o.simplify) != 0 || !(o.simplify >= 0.001 && o.simplify <= 1.0))
                return usage_error("--simplify '%s': expected a share of the triangles, 0.001..1", c.arg);
        }
    }
    if (opt < 0)
        return -opt;   /* the mistake, said */
    int rc = psc_io_cli_command_file(&c, PROG, "bake", PROG " bake MODEL -o M.ppx", "model", &model);
    if (rc != 0)
        return rc;
    if (!out)
        return usage_error("no output given (-o M.ppx)");
    psc_gltf_t g = {0};
    if (psc_gltf_load(model, &g, load_note, sizeof load_note, err, sizeof err) != 0) {
        fprintf(stderr, PROG ": %s\n", err);
        return 1;
    }
    if (load_note[0])
        fprintf(stderr, PROG ": %s: %s\n", model, load_note);
    uint8_t *bytes = NULL;
    size_t len = 0;
    rc = 1;
    if (psc_bake_proxy(&g, &o, model, &bytes, &len, note, sizeof note, err, sizeof err) != 0 ||
        psc_io_write_atomic(out, bytes, len, err, sizeof err) != 0) {
        fprintf(stderr, PROG ": %s\n", err);
    } else {
        printf("%s: %s, %zu bytes\n", out, note, len);
        rc = 0;
    }
    free(bytes);
    psc_gltf_free(&g);
    return rc;
}
