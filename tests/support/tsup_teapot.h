/* SPDX-License-Identifier: MIT */
/* tsup_teapot.h - the Utah teapot as a Newell .bpt text (the tests' Bezier patch file; host only, heap). */
#ifndef TSUP_TEAPOT_H
#define TSUP_TEAPOT_H

#include <stddef.h>

/** The 32 patches as .bpt text (malloc'd, NUL-terminated); *len its length. */
char *tsup_teapot_bpt(size_t *len);

#endif
