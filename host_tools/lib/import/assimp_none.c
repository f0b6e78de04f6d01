/* SPDX-License-Identifier: MIT */
/* assimp_none.c - the model importer of a build without libassimp (gltf_model.h): it says so (OBJ files are
 * still read, by obj.c). */
#include "import/gltf_model.h"
#include "psc_io_error.h"

#include <string.h>

int psc_assimp_load(const char *path, psc_gltf_t *out, char *note, size_t notelen, char *err, size_t errlen)
{
    (void)note;
    (void)notelen;
    memset(out, 0, sizeof *out);
    return psc_io_errorf(err, errlen, path, "this build reads no glTF models: it was made without libassimp "
                         "(install libassimp-dev and rebuild)");
}
