/* SPDX-License-Identifier: MIT */
/*
 * fuzz_am_model.c - Animation:Master models (.mdl text,
 * host_tools/lib/import/am_model.h) as periscope-patch reads them: psc_am_model_parse,
 * then for a model that parses the patch character built from it
 * (psc_patch_from_am) and its patch pack (psc_bake_patch_pack), which must
 * parse with core's psc_patch_parse. Every refusal along the way must name
 * the file; everything is freed.
 */
#include <stdlib.h>

#include "import/am_model.h"
#include "fuzz_support.h"
#include "patch/psc_patch.h"
#include "import/patch_source.h"

#define NAME "fuzz/model.mdl"

static void build_pack(const psc_am_model_t *am)
{
    psc_patch_src_t src;
    psc_patch_skin_opts_t skin = {NULL, NULL};
    char note[512] = "", err[512] = "";

    if (psc_patch_from_am(am, &skin, NAME, &src, note, sizeof note, err, sizeof err) != 0) {
        fuzz_require_message_names(err, NAME);
        return;
    }
    fuzz_require_patch_pack(&src, NAME);
    psc_patch_src_free(&src);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    psc_am_model_t am;
    char err[512] = "";

    if (psc_am_model_parse(NAME, (const char *)data, size, &am, err, sizeof err) == 0) {
        build_pack(&am);
        psc_am_model_free(&am);
    } else {
        fuzz_require_message_names(err, NAME);
        psc_am_model_free(&am);
    }
    return 0;
}
