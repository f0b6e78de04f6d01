/* SPDX-License-Identifier: MIT */
/*
 * modes.h - periscope-render's modes, in one table: what each draws, the
 * files it takes, whether a command line is its, and its main. The first
 * mode whose wanted() says yes runs; the panorama mode, last, takes the rest.
 */
#ifndef PSC_RENDER_MODES_H
#define PSC_RENDER_MODES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef struct {
    const char *name;                                    /* "proxy", "gltf", "patch", "model", "panorama" */
    const char *files;                                   /* the files it takes, as the usage names them */
    const char *what;                                    /* what it draws, one line */
    bool (*wanted)(int argc, char **argv);               /* whether this command line is this mode's */
    int (*main)(const char *prog, int argc, char **argv); /* 0 done, 1 the work failed, 2 bad arguments */
} psc_render_mode_t;

/** The modes, in the order they are asked; *count receives how many. */
const psc_render_mode_t *psc_render_modes(size_t *count);

/** The mode that draws this command line (the panorama mode when no other takes it). */
const psc_render_mode_t *psc_render_mode_for(int argc, char **argv);

/** The usage lines of every mode, as prog: a line a mode with its files, and how to see a mode's options. */
void psc_render_modes_usage(const char *prog, FILE *f);

#endif
