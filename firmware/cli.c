/* SPDX-License-Identifier: MIT */
/*
 * cli.c - parse the device program's command line (see cli.h) with the
 * programs' one convention (io/psc_io_cli.h). Kept out of main.c so tests
 * can feed it argument vectors.
 */
#include <dirent.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "board_config.h"
#include "board_find.h"
#include "cli.h"
#include "frame_dump.h"
#include "psc_hal.h"
#include "psc_hal_parse.h"
#include "psc_io_cli.h"

const char *psc_cli_usage(void)
{
    return "usage: periscope --board NAME [--boards-dir DIR] [--scene PACK] [--out DIR]\n"
           "                 [--tour FILE] [--frames-every K] [--max-frames N] [--quiet]\n"
           "                 [--dump-frame N:PATH]...\n"
           "       periscope [--board NAME] [options] FILE...\n"
           "       periscope --board NAME --print-key KEY\n"
           "  FILE...             show these files as the scene list: scene packs, or JPEG or PNG\n"
           "                      panoramas (packed for the display, kept in the pack cache:\n"
           "                      $PERISCOPE_CACHE_DIR, else $XDG_CACHE_HOME/periscope or\n"
           "                      ~/.cache/periscope); up to 8; the board defaults to desktop\n"
           "  --board NAME        read DIR/NAME/board.conf\n"
           "  --boards-dir DIR    where board descriptions live (default: the first of ./boards,\n"
           "                      the build tree's boards beside the program and\n"
           "                      " PSC_BOARD_FIND_ETC " that has the board; with FILEs and no\n"
           "                      desktop board there, the one board in " PSC_CLI_INSTALLED_BOARDS ")\n"
           "  --scene PACK        show this scene pack (or JPEG or PNG panorama) instead of the\n"
           "                      board's scene list\n"
           "  --out DIR           captured frames and contact sheet (default: out/NAME)\n"
           "  --tour FILE         replay this tour script instead of the board's\n"
           "  --frames-every K    capture every K-th frame (0: none; default: the board's)\n"
           "  --max-frames N      stop after N frames (default: when the input quits)\n"
           "  --quiet             no log line per input or quality event\n"
           "  --dump-frame N:PATH write frame N (from 0) as presented to PATH: raw pixels, rows of\n"
           "                      width x bytes per pixel, no header (repeatable, up to 8)\n"
           "  --print-key KEY     print the board file's value of KEY as written, and run nothing\n"
           "                      (the build and image scripts read board files this way)\n"
           "  --version           the program's version\n"
           "  --help              this text\n"
           "Options take their value as --opt VALUE or --opt=VALUE.\n";
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

enum {
    OPT_BOARD = 0x100, OPT_BOARDS_DIR, OPT_SCENE, OPT_OUT, OPT_TOUR, OPT_FRAMES_EVERY, OPT_MAX_FRAMES, OPT_QUIET,
    OPT_DUMP_FRAME, OPT_PRINT_KEY,
};

static const struct option cli_options[] = {
    {"board", required_argument, NULL, OPT_BOARD},
    {"boards-dir", required_argument, NULL, OPT_BOARDS_DIR},
    {"scene", required_argument, NULL, OPT_SCENE},
    {"out", required_argument, NULL, OPT_OUT},
    {"tour", required_argument, NULL, OPT_TOUR},
    {"frames-every", required_argument, NULL, OPT_FRAMES_EVERY},
    {"max-frames", required_argument, NULL, OPT_MAX_FRAMES},
    {"quiet", no_argument, NULL, OPT_QUIET},
    {"dump-frame", required_argument, NULL, OPT_DUMP_FRAME},
    {"print-key", required_argument, NULL, OPT_PRINT_KEY},
    PSC_IO_CLI_COMMON_OPTIONS,
};

/* One option and its value into o. */
static int cli_take(psc_cli_options_t *o, int opt, const char *name, const char *v, char *err, size_t errlen)
{
    int64_t n;

    if (v != NULL && v[0] == '\0') {
        psc_hal_error_set(err, errlen, "option '%s' needs a value", name);
        return -1;
    }
    switch (opt) {
    case OPT_BOARD: o->board = v; break;
    case OPT_BOARDS_DIR: o->boards_dir = v; break;
    case OPT_SCENE: o->scene = v; break;
    case OPT_OUT: o->out_dir = v; break;
    case OPT_TOUR: o->tour = v; break;
    case OPT_QUIET: o->quiet = true; break;
    case OPT_PRINT_KEY: o->print_key = v; break;
    case OPT_FRAMES_EVERY:
        if (cli_number(name, v, 1000000, &n, err, errlen) != 0)
            return -1;
        o->frames_every = n;
        break;
    case OPT_MAX_FRAMES:
        if (cli_number(name, v, UINT32_MAX, &n, err, errlen) != 0)
            return -1;
        o->max_frames = (uint32_t)n;
        break;
    case OPT_DUMP_FRAME:
        if (o->dump_count == PSC_CLI_MAX_DUMPS) {
            psc_hal_error_set(err, errlen, "--dump-frame is given more than %u times", PSC_CLI_MAX_DUMPS);
            return -1;
        }
        if (psc_frame_dump_parse(v, &o->dumps[o->dump_count].frame, &o->dumps[o->dump_count].path) != 0) {
            psc_hal_error_set(err, errlen, "--dump-frame needs FRAME:PATH (e.g. 30:/tmp/frame30.raw), got '%s'", v);
            return -1;
        }
        o->dump_count++;
        break;
    }
    return 0;
}

static bool cli_has_board(const char *dir, const char *name)
{
    char path[PSC_BOARD_PATH_MAX * 2];

    snprintf(path, sizeof path, "%s/%s/board.conf", dir, name);
    return access(path, R_OK) == 0;
}

/*
 * Files to show and no --board: the desktop board, from --boards-dir or the
 * first place that has one (board_find.h), else, when the package installed
 * one board only, that one (a kiosk's own display).
 */
static int cli_default_board(psc_cli_options_t *o, char *err, size_t errlen)
{
    char why[600];

    o->board = "desktop";
    if (o->boards_dir != NULL)
        return 0;
    if (psc_board_find_default("desktop", o->boards_dir_buf, sizeof o->boards_dir_buf, why, sizeof why) == 0) {
        o->boards_dir = o->boards_dir_buf;
        return 0;
    }
    unsigned found = 0;
    DIR *d = opendir(PSC_CLI_INSTALLED_BOARDS);
    struct dirent *e;
    while (d != NULL && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.' || strlen(e->d_name) >= sizeof o->board_buf ||
            !cli_has_board(PSC_CLI_INSTALLED_BOARDS, e->d_name))
            continue;
        if (found++ == 0)
            snprintf(o->board_buf, sizeof o->board_buf, "%s", e->d_name);
    }
    if (d != NULL)
        closedir(d);
    if (found == 1) {
        o->board = o->board_buf;
        o->boards_dir = PSC_CLI_INSTALLED_BOARDS;
        return 0;
    }
    psc_board_places_t p;
    char places[1200];
    psc_board_places_default(&p);
    psc_board_places_text(p.dirs, p.count, places, sizeof places);
    psc_hal_error_set(err, errlen, "no board to show %s on: no desktop/board.conf in %s, and %s in %s; "
                      "name one with --board NAME (and --boards-dir DIR)", o->files[0], places,
                      found == 0 ? "no board installed" : "more than one board installed", PSC_CLI_INSTALLED_BOARDS);
    return -1;
}

int psc_cli_parse(int argc, char *const *argv, psc_cli_options_t *o, char *err, size_t errlen)
{
    psc_io_cli_t c;
    int opt;

    *o = (psc_cli_options_t){ .frames_every = -1 };
    /* getopt moves the arguments that are not options behind the options */
    psc_io_cli_begin(&c, argc, (char **)argv, "h", cli_options);
    while ((opt = psc_io_cli_next(&c, err, errlen)) != 0) {
        if (opt < 0)
            return -1;
        if (opt == PSC_IO_CLI_HELP || opt == PSC_IO_CLI_VERSION) {
            o->help = opt == PSC_IO_CLI_HELP;
            o->version = opt == PSC_IO_CLI_VERSION;
            return 0;
        }
        if (cli_take(o, opt, c.name, c.arg, err, errlen) != 0)
            return -1;
    }
    for (int i = psc_io_cli_rest(&c); i < argc; i++) {
        if (o->file_count == PSC_CLI_MAX_FILES) {
            psc_hal_error_set(err, errlen, "more than %u files to show ('%s'): a board has at most %u scenes",
                              PSC_CLI_MAX_FILES, argv[i], PSC_CLI_MAX_FILES);
            return -1;
        }
        o->files[o->file_count++] = argv[i];
    }
    if (o->file_count != 0 && o->scene != NULL) {
        psc_hal_error_set(err, errlen, "--scene and files to show (%s) are given: the files are the scene list, "
                          "so give one or the other", o->files[0]);
        return -1;
    }
    if (o->board == NULL && o->file_count != 0 && cli_default_board(o, err, errlen) != 0)
        return -1;
    if (o->board == NULL) {
        psc_hal_error_set(err, errlen, "--board NAME is required (e.g. --board sim), or files to show");
        return -1;
    }
    /* the board name becomes a path component: keep it one */
    if (strchr(o->board, '/') != NULL || strcmp(o->board, "..") == 0 || strcmp(o->board, ".") == 0) {
        psc_hal_error_set(err, errlen, "board name '%s' must be a directory name under %s, not a path",
                          o->board, o->boards_dir != NULL ? o->boards_dir : "the boards directory");
        return -1;
    }
    return 0;
}
