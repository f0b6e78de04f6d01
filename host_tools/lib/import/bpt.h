/* SPDX-License-Identifier: MIT */
/*
 * bpt.h - Newell's Bezier patch files (.bpt, the Utah teapot's format)
 * as Hash patches: the number of patches, then for each "3 3" (the degrees)
 * and its 16 control points, row by row. Each patch keeps its 12 boundary
 * points: four cubic boundary curves with their handles fixed as given
 * (PSC_PATCH_CP_FIXED), the 4 inner points dropped (Hash patches have no
 * twist vectors). Corners at the same position are one point; a boundary
 * curve two patches share (either way round) is one edge; a side collapsed
 * to a point makes the patch three-sided. Errors name file:line.
 */
#ifndef PSC_IMPORT_BPT_H
#define PSC_IMPORT_BPT_H

#include <stddef.h>

#include "import/patch_source.h"

#define PSC_BPT_MAX_PATCHES 4096u

/** Parse text[0..len) named name. 0, or -1 with err. */
int psc_bpt_parse(const char *name, const char *text, size_t len, psc_patch_src_t *out, char *err, size_t errlen);

/** Read and parse a .bpt file. */
int psc_bpt_load(const char *path, psc_patch_src_t *out, char *err, size_t errlen);

#endif
