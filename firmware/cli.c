/*
 * cli.c - parse the device program's command line (see cli.h). Kept out of
 * main.c so tests can feed it argument vectors.
 */
#include <string.h>

#include "cli.h"
#include "frame_dump.h"
#include "psc_hal.h"
#include "psc_hal_parse.h"

const char *psc_cli_usage(void)
{
    return "usage: periscope --board NAME [--boards-dir DIR] [--scene PACK] [--out DIR]\n"
           "                 [--tour FILE] [--frames-every K] [--max-frames N] [--quiet]\n"
           "                 [--dump-frame N:PATH]...\n"
           "  --board NAME        read DIR/NAME/board.conf\n"
           "  --boards-dir DIR    where board descriptions live (default: boards)\n"
           "  --scene PACK        show this scene pack instead of the board's scene list\n"
           "  --out DIR           captured frames and contact sheet (default: out/NAME)\n"
           "  --tour FILE         replay this tour script instead of the board's\n"
           "  --frames-every K    capture every K-th frame (0: none; default: the board's)\n"
           "  --max-frames N      stop after N frames (default: when the input quits)\n"
           "  --quiet             no log line per input or quality event\n"
           "  --dump-frame N:PATH write frame N (from 0) as presented to PATH: raw pixels, rows of\n"
           "                      width x bytes per pixel, no header (repeatable, up to 8)\n";
}

/* A whole number for --frames-every / --max-frames. */
static int cli_number(const char *flag, const char *value, int64_t max, int64_t *out, char *err, size_t errlen)
{
    if (psc_hal_parse_decimal(value, 0, out) != 0 || *out < 0 || *out > max || value[0] == '+') {
        psc_hal_error_set(err, errlen, "%s needs a whole number from 0 to %lld, got '%s'", flag,
                          (long long)max, value);
        return -1;
    }
    return 0;
}

int psc_cli_parse(int argc, char *const *argv, psc_cli_options_t *o, char *err, size_t errlen)
{
    *o = (psc_cli_options_t){ .boards_dir = "boards", .frames_every = -1 };
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int64_t n;

        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            o->help = true;
            return 0;
        }
        if (strcmp(a, "--quiet") == 0) {
            o->quiet = true;
            continue;
        }
        if (strncmp(a, "--", 2) != 0) {
            psc_hal_error_set(err, errlen, "unexpected argument '%s' (options start with --)", a);
            return -1;
        }
        if (v == NULL || v[0] == '\0') {
            psc_hal_error_set(err, errlen, "%s needs a value", a);
            return -1;
        }
        i++;
        if (strcmp(a, "--board") == 0) {
            o->board = v;
        } else if (strcmp(a, "--boards-dir") == 0) {
            o->boards_dir = v;
        } else if (strcmp(a, "--scene") == 0) {
            o->scene = v;
        } else if (strcmp(a, "--out") == 0) {
            o->out_dir = v;
        } else if (strcmp(a, "--tour") == 0) {
            o->tour = v;
        } else if (strcmp(a, "--frames-every") == 0) {
            if (cli_number(a, v, 1000000, &n, err, errlen) != 0)
                return -1;
            o->frames_every = n;
        } else if (strcmp(a, "--dump-frame") == 0) {
            if (o->dump_count == PSC_CLI_MAX_DUMPS) {
                psc_hal_error_set(err, errlen, "--dump-frame is given more than %u times", PSC_CLI_MAX_DUMPS);
                return -1;
            }
            if (psc_frame_dump_parse(v, &o->dumps[o->dump_count].frame, &o->dumps[o->dump_count].path) != 0) {
                psc_hal_error_set(err, errlen, "--dump-frame needs FRAME:PATH (e.g. 30:/tmp/frame30.raw), got '%s'", v);
                return -1;
            }
            o->dump_count++;
        } else if (strcmp(a, "--max-frames") == 0) {
            if (cli_number(a, v, UINT32_MAX, &n, err, errlen) != 0)
                return -1;
            o->max_frames = (uint32_t)n;
        } else {
            psc_hal_error_set(err, errlen, "unknown option '%s'", a);
            return -1;
        }
    }
    if (o->board == NULL) {
        psc_hal_error_set(err, errlen, "--board NAME is required (e.g. --board sim)");
        return -1;
    }
    /* the board name becomes a path component: keep it one */
    if (strchr(o->board, '/') != NULL || strcmp(o->board, "..") == 0 || strcmp(o->board, ".") == 0) {
        psc_hal_error_set(err, errlen, "board name '%s' must be a directory name under %s, not a path",
                          o->board, o->boards_dir);
        return -1;
    }
    return 0;
}
