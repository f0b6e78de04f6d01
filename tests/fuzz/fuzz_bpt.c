/* SPDX-License-Identifier: MIT */
/*
 * fuzz_bpt.c - Newell's Bezier patch files (.bpt, host_tools/lib/import/bpt.h)
 * as periscope-patch reads them: psc_bpt_parse, then for a file that parses
 * its patch pack (psc_bake_patch_pack), which must parse with core's
 * psc_patch_parse. Every refusal must name the file; everything is freed.
 */
#include <stdlib.h>

#include "import/bpt.h"
#include "fuzz_support.h"
#include "patch/psc_patch.h"
#include "import/patch_source.h"

#define NAME "fuzz/model.bpt"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    psc_patch_src_t src;
    char err[512] = "";

    if (psc_bpt_parse(NAME, (const char *)data, size, &src, err, sizeof err) != 0) {
        fuzz_require_message_names(err, NAME);
        return 0;
    }
    FUZZ_REQUIRE(src.face_count <= 3u * PSC_BPT_MAX_PATCHES);
    fuzz_require_patch_pack(&src, NAME);
    psc_patch_src_free(&src);
    return 0;
}
