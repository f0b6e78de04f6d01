/* SPDX-License-Identifier: MIT */
/*
 * periscope-fisheye - build the dual-fisheye table (core/fisheye/psc_fisheye.h) that
 * turns a dual-fisheye camera's frames into an equirectangular environment
 * map on the device (board key camera_fisheye_table).
 *
 *   periscope-fisheye --frame WxH --front CX:CY:R[:FOV] --back CX:CY:R[:FOV]
 *                     [--front-rot YAW:PITCH:ROLL] [--back-rot YAW:PITCH:ROLL]
 *                     [--map WxH] -o table.pfish
 *
 * The lens model (equidistant, r = f * theta), the axes and the choice in the
 * overlap are described in host_tools/lib/bake/fisheye.h.
 * Exit status: 0 done, 1 the work failed, 2 bad arguments.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/cli_values.h"
#include "psc_io_cli.h"
#include "bake/fisheye.h"
#include "psc_io_pack_build.h"
#include "psc_io_file.h"

#define PROG "periscope-fisheye"
#define DEFAULT_FOV 190.0

static void print_usage(const char *prog, FILE *f)
{
    (void)prog;   /* the same as PROG */
    fprintf(f,
            "usage: " PROG " --frame WxH --front CX:CY:R[:FOV] --back CX:CY:R[:FOV]\n"
            "       [--front-rot YAW:PITCH:ROLL] [--back-rot YAW:PITCH:ROLL] [--map WxH] -o table.pfish\n"
            "\n"
            "Build the table that maps a dual-fisheye camera frame (WxH pixels) to an\n"
            "equirectangular environment map (--map WxH, default 2H x H for a frame H high).\n"
            "Each lens: circle centre CX:CY and radius R in frame pixels (pixel\n"
            "centres are integers, (0,0) the top-left pixel), field of view FOV in degrees\n"
            "(default %g). The front lens looks ahead (+Z), the back lens behind (-Z);\n"
            "--*-rot corrects small mounting errors (degrees, within +-45). Equidistant\n"
            "fisheye model r = f*theta with f = R / (FOV/2).\n"
            "Options take their value as --opt VALUE or --opt=VALUE; --version, --help.\n",
            DEFAULT_FOV);
}

#define usage_error(...) psc_io_cli_usage_error(PROG, __VA_ARGS__)

/* "a:b:c[:d]": between min_n and max_n finite numbers separated by ':'. */
static int parse_numbers(const char *s, double *v, unsigned min_n, unsigned max_n)
{
    char buf[128];
    unsigned n = 0;
    if (strlen(s) >= sizeof buf)
        return -1;
    strcpy(buf, s);
    char *save = NULL;
    for (char *tok = strtok_r(buf, ":", &save); tok; tok = strtok_r(NULL, ":", &save)) {
        if (n == max_n || psc_cli_parse_double(tok, &v[n]) != 0)
            return -1;
        n++;
    }
    return n >= min_n ? 0 : -1;
}

static const struct option fisheye_options[] = {
    {"frame", required_argument, NULL, 'f'},      {"map", required_argument, NULL, 'm'},
    {"front", required_argument, NULL, 'F'},      {"back", required_argument, NULL, 'B'},
    {"front-rot", required_argument, NULL, 'R'},  {"back-rot", required_argument, NULL, 'r'},
    PSC_IO_CLI_COMMON_OPTIONS,
};

int main(int argc, char **argv)
{
    psc_io_cli_t c;
    psc_bake_fisheye_rig_t rig;
    const char *out = NULL;
    uint16_t map_w = 0, map_h = 0;
    int have_frame = 0, have_lens[2] = {0, 0}, opt;

    memset(&rig, 0, sizeof rig);
    psc_io_cli_begin(&c, argc, argv, "ho:", fisheye_options);
    while ((opt = psc_io_cli_next_option(&c, PROG, "", print_usage)) > 0) {
        const char *v = c.arg;
        unsigned k = opt == 'B' || opt == 'r';   /* the back lens */
        double n[4] = {0, 0, 0, DEFAULT_FOV};
        switch (opt) {
        case 'o':
            out = v;
            break;
        case 'f':
            if (psc_cli_parse_size(v, PSC_FISHEYE_MAX_FRAME_DIM, &rig.frame_width, &rig.frame_height) != 0)
                return usage_error("--frame: expected WxH, each 1..%u", PSC_FISHEYE_MAX_FRAME_DIM);
            have_frame = 1;
            break;
        case 'm':
            if (psc_cli_parse_size(v, PSC_MAX_MAP_DIM, &map_w, &map_h) != 0 || map_w < 2 || map_h < 2)
                return usage_error("--map: expected WxH, each 2..%u", PSC_MAX_MAP_DIM);
            break;
        case 'F':
        case 'B':
            if (parse_numbers(v, n, 3, 4) != 0)
                return usage_error("%s: expected CX:CY:R or CX:CY:R:FOV (pixels, degrees)", k ? "--back" : "--front");
            rig.lens[k].cx = n[0];
            rig.lens[k].cy = n[1];
            rig.lens[k].radius = n[2];
            rig.lens[k].fov_deg = n[3];
            have_lens[k] = 1;
            break;
        case 'R':
        case 'r':
            if (parse_numbers(v, n, 3, 3) != 0)
                return usage_error("%s: expected YAW:PITCH:ROLL in degrees", k ? "--back-rot" : "--front-rot");
            rig.lens[k].yaw_deg = n[0];
            rig.lens[k].pitch_deg = n[1];
            rig.lens[k].roll_deg = n[2];
            break;
        }
    }
    if (opt < 0)
        return -opt;   /* the mistake, said */
    if (psc_io_cli_rest(&c) < argc)
        return usage_error("unexpected argument '%s'", argv[psc_io_cli_rest(&c)]);
    if (!out)
        return usage_error("no output given (-o table.pfish)");
    if (!have_frame)
        return usage_error("no frame size given (--frame WxH)");
    if (!have_lens[0] || !have_lens[1])
        return usage_error("both lenses are needed (--front CX:CY:R[:FOV] --back CX:CY:R[:FOV])");
    if (map_w == 0) {
        unsigned h = rig.frame_height < 2 ? 2u : rig.frame_height;
        map_w = (uint16_t)(2u * h > PSC_MAX_MAP_DIM ? PSC_MAX_MAP_DIM : 2u * h);
        map_h = (uint16_t)(map_w / 2u);
    }

    char err[512];
    uint8_t *table = NULL;
    size_t len = 0;
    if (psc_bake_fisheye(&rig, map_w, map_h, out, &table, &len, err, sizeof err) != 0 ||
        psc_io_write_atomic(out, table, len, err, sizeof err) != 0) {
        fprintf(stderr, PROG ": %s\n", err);
        free(table);
        return 1;
    }
    free(table);
    printf("%s: %ux%u frame -> %ux%u map, %zu bytes\n", out, rig.frame_width, rig.frame_height, map_w, map_h, len);
    return 0;
}
