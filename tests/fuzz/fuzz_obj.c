/* SPDX-License-Identifier: MIT */
/*
 * fuzz_obj.c - Wavefront OBJ text (host_tools/lib/import/obj.h) through
 * psc_obj_parse, as the host tools read a model, and again with its groups
 * as parts (psc_obj_parse_parts: every vertex on a part that exists, a
 * triangle's corners on one part, a colour a vertex). The file is named in a
 * directory that does not exist, so a relative mtllib opens nothing. A
 * refusal must be "NAME:LINE: problem" (or "NAME: problem") naming the file;
 * a parsed model has triangles, every index below the vertex count, and
 * finite positions and normals; it is freed.
 */
#include <math.h>
#include <stdlib.h>

#include "fuzz_support.h"
#include "import/model.h"
#include "import/obj.h"

#define NAME "/nonexistent-fuzz-dir/model.obj"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    psc_model_t m = {0};
    char note[512] = "", err[512] = "";

    if (psc_obj_parse(NAME, (const char *)data, size, &m, note, sizeof note, err, sizeof err) == 0) {
        FUZZ_REQUIRE(m.vertex_count > 0 && m.triangle_count > 0 && m.pos != NULL && m.index != NULL);
        for (size_t i = 0; i < (size_t)m.triangle_count * 3u; i++)
            FUZZ_REQUIRE(m.index[i] < m.vertex_count);
        for (size_t i = 0; i < (size_t)m.vertex_count * 3u; i++) {
            FUZZ_REQUIRE(isfinite(m.pos[i]));
            FUZZ_REQUIRE(m.normal == NULL || isfinite(m.normal[i]));
        }
    } else {
        fuzz_require_message_names(err, NAME);
    }
    psc_model_free(&m);

    psc_obj_parts_t parts;
    if (psc_obj_parse_parts(NAME, (const char *)data, size, &m, &parts, note, sizeof note, err, sizeof err) == 0) {
        FUZZ_REQUIRE(parts.count > 0 && parts.count <= PSC_OBJ_MAX_PARTS && m.color != NULL);
        for (uint32_t v = 0; v < m.vertex_count; v++)
            FUZZ_REQUIRE(parts.vertex_part[v] < parts.count);
        for (size_t t = 0; t < m.triangle_count; t++)
            for (unsigned k = 0; k < 3; k++) {
                FUZZ_REQUIRE(m.index[3 * t + k] < m.vertex_count);
                FUZZ_REQUIRE(parts.vertex_part[m.index[3 * t + k]] == parts.vertex_part[m.index[3 * t]]);
            }
        psc_obj_parts_free(&parts);
        psc_model_free(&m);
    } else {
        fuzz_require_message_names(err, NAME);
    }
    return 0;
}
