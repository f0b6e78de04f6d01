/* SPDX-License-Identifier: MIT */
/*
 * cli.h - the command line of periscope-render's 3D modes (models, patch
 * characters, glTF models, proxy packs), read in one place: the view options
 * they all take (render/view.h: --orbit, --hfov, --size, --cull, --format,
 * --repeat and the look), -o, --help and --version, the one model file, and
 * each mode's own options through its callback.
 */
#ifndef PSC_RENDER_CLI_H
#define PSC_RENDER_CLI_H

#include <getopt.h>
#include <stdbool.h>
#include <stdio.h>

#include "render/view.h"

/* The options of render/view.h, for the parser's table. */
#define PSC_RENDER_VIEW_OPTIONS                                                                   \
    {"orbit", required_argument, NULL, 1}, {"hfov", required_argument, NULL, 1},                  \
        {"size", required_argument, NULL, 1}, {"cull", required_argument, NULL, 1},               \
        {"format", required_argument, NULL, 1}, {"repeat", required_argument, NULL, 1},           \
        PSC_RENDER_VIEW_LOOK_OPTIONS

/* The most options a mode adds. */
#define PSC_RENDER_CLI_MAX_OPTIONS 32

typedef struct {
    const char *mode;                         /* " (model mode)": said after a mistake */
    const char *what;                         /* the file it draws, in mistakes: "no model given" */
    void (*usage)(const char *prog, FILE *f); /* --help */
    const struct option *options;             /* the mode's own, ended by an entry with a NULL name */
    /* the mode's option name (as written, e.g. "--pose") with value v into args: 0, or the exit status of a
     * mistake it has said (psc_io_cli_usage_error) */
    int (*option)(const char *prog, const char *name, const char *v, void *args);
} psc_render_cli_t;

/** Whether an argument of argv that is not an option, nor the file an output option names (-o, --dump-obj,
 *  --dump-ao, --depth, --ids), is a file is() takes (a mode's wanted()). */
bool psc_render_cli_has_file(int argc, char **argv, bool (*is)(const char *path));

/** Whether argv has the option name ("--orbit", as --orbit V or --orbit=V). */
bool psc_render_cli_has_option(int argc, char **argv, const char *name);

/**
 * Read argv: the view's options into *view, the mode's into args, -o into
 * *out, the one model file into *model. 0, or the exit status (2) of a
 * mistake, said as prog; --help and --version exit.
 */
int psc_render_cli_parse(const psc_render_cli_t *cli, const char *prog, int argc, char **argv, psc_render_view_t *view,
                         const char **model, const char **out, void *args);

#endif
