/* SPDX-License-Identifier: MIT */
/* path.c - file name suffixes (path.h). */
#include "util/path.h"

#include <string.h>
#include <strings.h>

bool psc_path_has_suffix(const char *path, const char *suffix)
{
    size_t n = strlen(path), k = strlen(suffix);
    return n > k && strcasecmp(path + n - k, suffix) == 0;
}
