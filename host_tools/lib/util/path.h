/* SPDX-License-Identifier: MIT */
/* path.h - what a file's name says: its suffix, compared without case (".OBJ" is an OBJ file). */
#ifndef PSC_UTIL_PATH_H
#define PSC_UTIL_PATH_H

#include <stdbool.h>

/** Whether path ends with suffix (e.g. ".gltf"), in any case, and has something before it. */
bool psc_path_has_suffix(const char *path, const char *suffix);

#endif
