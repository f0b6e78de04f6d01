/* SPDX-License-Identifier: MIT */
/*
 * cli.h - the command line of the device program:
 *
 *   periscope --board NAME [--boards-dir DIR] [--scene PACK] [--out DIR]
 *             [--tour FILE] [--frames-every K] [--max-frames N] [--quiet]
 *             [--dump-frame N:PATH]...
 *   periscope [--board NAME] [options] FILE...
 *   periscope --board NAME --print-key KEY
 *   periscope --help | --version
 *
 * Options follow the programs' one convention (io/psc_io_cli.h): --opt VALUE
 * or --opt=VALUE, whole option names only.
 * The board file is DIR/NAME/board.conf: DIR is --boards-dir, else the first
 * place that has the board (board_find.h: ./boards, the build tree's boards
 * beside the program, /etc/periscope/boards, PSC_CLI_INSTALLED_BOARDS), which
 * the program looks up once it runs (boards_dir stays NULL here). --scene
 * replaces the board's scene list with one pack (or JPEG or PNG panorama);
 * files named after the options replace it with those, in order (up to
 * PSC_CLI_MAX_FILES; scene packs, JPEGs, PNGs), and then the board defaults
 * to "desktop": the first of those places with a desktop board, else the
 * installed boards' (PSC_CLI_INSTALLED_BOARDS: the one board installed);
 * --tour replaces its tour;
 * --out is where the sim display captures frames and the contact sheet goes
 * (default out/NAME); --frames-every overrides the board's capture period
 * (0 = no captures); --max-frames stops after N frames (0 = no limit), so a
 * real board can be smoke-tested without a tour; --dump-frame writes the
 * raw pixels of frame N (from 0) as presented to PATH (frame_dump.h), up to
 * PSC_CLI_MAX_DUMPS times, for comparing a real display with the sim board.
 */
#ifndef PSC_CLI_H
#define PSC_CLI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define PSC_CLI_MAX_DUMPS 8u
/* as many files as a board's scene lines (PSC_BOARD_MAX_SCENES) */
#define PSC_CLI_MAX_FILES 8u
/* where the Debian package installs the board descriptions (packaging/deb) */
#define PSC_CLI_INSTALLED_BOARDS "/etc/periscope/boards"

/** One --dump-frame request. */
typedef struct {
    uint32_t frame;
    const char *path;
} psc_cli_dump_t;

/** Parsed command line; strings point into argv. */
typedef struct {
    const char *board;
    const char *boards_dir;     /* --boards-dir; NULL = look for the board (board_find.h) */
    const char *scene;          /* NULL = the board's scenes */
    const char *out_dir;        /* NULL = out/<board> */
    const char *tour;           /* NULL = the board's tour */
    int64_t frames_every;       /* -1 = the board's */
    uint32_t max_frames;        /* 0 = until the input says quit */
    bool quiet;                 /* no per-event log lines */
    bool help;                  /* --help: print usage, run nothing */
    bool version;               /* --version: print the version, run nothing */
    const char *print_key;      /* --print-key KEY: print the board file's KEY, run nothing */
    psc_cli_dump_t dumps[PSC_CLI_MAX_DUMPS];   /* --dump-frame N:PATH */
    unsigned dump_count;
    const char *files[PSC_CLI_MAX_FILES];      /* FILE...: the scene list, in order */
    unsigned file_count;
    char board_buf[256];        /* the installed board's name, when board defaults to it */
    char boards_dir_buf[256];   /* where the default desktop board was found */
} psc_cli_options_t;

/**
 * Parse argv[1..argc) (getopt may reorder argv). Returns 0 (with help or
 * version set for --help / --version, and then nothing else checked), or -1
 * with err naming the bad argument and what was expected.
 */
int psc_cli_parse(int argc, char *const *argv, psc_cli_options_t *o, char *err, size_t errlen);

/** The usage text, for --help and after a command-line error. */
const char *psc_cli_usage(void);

#endif
