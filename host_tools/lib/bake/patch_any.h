/* SPDX-License-Identifier: MIT */
/*
 * patch_any.h - a patch character from whatever file the author has: an
 * Animation:Master model (.mdl, with .act actions, .bvh motion capture and a
 * donor model for its skin), a Newell Bezier patch file (.bpt), or a patch pack (.ppk); built
 * into a pack in memory when it is not one, so what the host tools show is
 * what the device draws.
 */
#ifndef PSC_BAKE_PATCH_ANY_H
#define PSC_BAKE_PATCH_ANY_H

#include <stdbool.h>
#include <stddef.h>

#include "psc_io_load.h"

#define PSC_BAKE_PATCH_MAX_ACTIONS 8u

typedef struct {
    const char *actions[PSC_BAKE_PATCH_MAX_ACTIONS];   /* .act files for an A:M model */
    unsigned action_count;
    const char *captures[PSC_BAKE_PATCH_MAX_ACTIONS];  /* .bvh motion capture, retargeted by bone name */
    unsigned capture_count;
    const char *capture_map;     /* "bvh_joint = bone" lines (NULL: the built-in map) */
    const char *skin_from;       /* an A:M model of the same character whose CP assignments to take */
    const char *deform;          /* comma-separated deforming bones, for a model that assigns no CP */
    const char *write_pack;      /* also write the pack here */
    bool quiet;                  /* no notes on stderr */
} psc_bake_patch_opts_t;

/** True for a file this loader takes: .mdl, .bpt, or the patch pack magic. */
bool psc_bake_patch_wanted(const char *path);

/** Load path into pf (psc_io_patch_free). 0, or -1 with err naming the file and the problem. */
int psc_bake_patch_any(const char *path, const psc_bake_patch_opts_t *opts, psc_io_patch_t *pf, char *err,
                       size_t errlen);

#endif
