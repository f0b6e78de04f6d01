/* SPDX-License-Identifier: MIT */
/* gltf_load_none.c - the model importer of a build without libassimp (gltf_load.h): it says so. */
#include "import/gltf_model.h"
#include "psc_io_error.h"

#include <string.h>

int psc_gltf_load(const char *path, psc_gltf_t *out, char *note, size_t notelen, char *err, size_t errlen)
{
    (void)note;
    (void)notelen;
    memset(out, 0, sizeof *out);
    return psc_io_errorf(err, errlen, path, "this build reads no glTF models: it was made without libassimp "
                         "(install libassimp-dev and rebuild)");
}
