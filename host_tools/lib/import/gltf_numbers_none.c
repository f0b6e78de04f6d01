/* SPDX-License-Identifier: MIT */
/* gltf_numbers_none.c - a build without libjson-c knows no glTF node numbers (gltf_model.h): every joint -1, and a
 * pose file (which such a build cannot read anyway) numbers the joints in the importer's order. */
#include "import/gltf_model.h"

int psc_gltf_node_numbers(const char *path, psc_gltf_t *g, char *err, size_t errlen)
{
    (void)path, (void)err, (void)errlen;
    for (uint32_t j = 0; j < g->joint_count; j++)
        g->joints[j].node = -1;
    return 0;
}
