/* SPDX-License-Identifier: MIT */
/* pose_json_none.c - the pose-file reader of a build without libjson-c (pose_file.h): it says so. */
#include "import/pose_file.h"
#include "psc_io_error.h"

#include <string.h>

int psc_pose_file_load(const char *path, psc_pose_file_t *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    return psc_io_errorf(err, errlen, path, "this build reads no pose files: it was made without libjson-c "
                         "(install libjson-c-dev and rebuild)");
}
