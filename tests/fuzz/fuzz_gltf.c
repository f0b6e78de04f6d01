/* SPDX-License-Identifier: MIT */
/*
 * fuzz_gltf.c - glTF files (their buffers inline, as data: URIs) through the
 * host tools' importer (host_tools/lib/import/gltf_model.h, libassimp), and
 * their blend shapes through core's morph (host_tools/lib/anim/gltf_morph.h,
 * core/morph): the input written to a .gltf file of its own and read as
 * periscope-render reads a model. A refusal must name the file; a model read
 * has triangles, indices below its vertex count, finite rest positions, its
 * targets' vertices inside the mesh, and its rest mesh morphed at the
 * animation's start, middle and after its end, and at weights of +-16 (the
 * limit) and beyond (clamped), stays finite.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "fuzz_support.h"
#include "anim/gltf_morph.h"
#include "import/gltf_model.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[] = "/tmp/periscope-fuzz-gltf-XXXXXX.gltf";
    int fd = mkstemps(path, 5);
    if (fd < 0)
        return 0;
    FILE *f = fdopen(fd, "wb");
    if (!f) {
        close(fd);
        unlink(path);
        return 0;
    }
    bool written = fwrite(data, 1, size, f) == size;
    if (fclose(f) != 0 || !written) {
        unlink(path);
        return 0;
    }
    psc_gltf_t g;
    char note[512] = "", err[768] = "";
    if (psc_gltf_load(path, &g, note, sizeof note, err, sizeof err) != 0) {
        fuzz_require_message_names(err, path);
        unlink(path);
        return 0;
    }
    unlink(path);
    FUZZ_REQUIRE(g.mesh.vertex_count > 0 && g.mesh.triangle_count > 0);
    for (size_t i = 0; i < (size_t)g.mesh.triangle_count * 3u; i++)
        FUZZ_REQUIRE(g.mesh.index[i] < g.mesh.vertex_count);
    uint32_t targets = 0;
    for (uint32_t k = 0; k < g.morph_count; k++) {
        FUZZ_REQUIRE((uint64_t)g.morphs[k].v0 + g.morphs[k].nv <= g.mesh.vertex_count);
        targets += g.morphs[k].target_count;
    }
    FUZZ_REQUIRE(targets == g.target_count && targets <= PSC_GLTF_MAX_TARGETS);
    double c[3], r;
    psc_gltf_frame(&g, c, &r);
    psc_gltf_morpher_t mm;
    if (g.target_count && isfinite(r) && r > 0 &&
        psc_gltf_morpher_new(&mm, &g, c, r, "fuzz.gltf", err, sizeof err) == 0) {
        double *w = calloc(g.target_count, sizeof *w), *pos = malloc(g.mesh.vertex_count * 3u * sizeof *pos),
               *nrm = malloc(g.mesh.vertex_count * 3u * sizeof *nrm);
        if (w && pos && nrm) {
            const double times[] = {0.0, g.duration / 2, g.duration + 1, -1.0};
            for (unsigned k = 0; k < 6; k++) {
                if (k < 4)
                    psc_gltf_weights(&g, times[k], w);
                else
                    for (uint32_t t = 0; t < g.target_count; t++)
                        w[t] = k == 4 ? (t & 1 ? -16.0 : 16.0) : 1e9;
                psc_gltf_morph_rest(&mm, &g, w, pos, nrm);
                for (size_t i = 0; i < (size_t)g.mesh.vertex_count * 3u; i++)
                    FUZZ_REQUIRE(isfinite(pos[i]) && isfinite(nrm[i]));
            }
        }
        free(w);
        free(pos);
        free(nrm);
        psc_gltf_morpher_free(&mm);
    }
    psc_gltf_free(&g);
    return 0;
}
