/* SPDX-License-Identifier: MIT */
/*
 * fuzz_bvh.c - BVH motion captures (host_tools/lib/import/bvh.h) through
 * psc_bvh_parse. A refusal must name the file; a parsed capture has joints
 * whose parents come before them, channel ranges inside a frame's values,
 * and poses its first and last frames to finite rotations and positions; it
 * is freed.
 */
#include <math.h>
#include <stdlib.h>

#include "import/bvh.h"
#include "fuzz_support.h"

#define NAME "fuzz/capture.bvh"

static void pose_frame(const psc_bvh_t *b, size_t f)
{
    double (*rot)[4] = calloc(b->joint_count, sizeof *rot);
    double (*pos)[3] = calloc(b->joint_count, sizeof *pos);

    FUZZ_REQUIRE(rot != NULL && pos != NULL);
    psc_bvh_pose(b, f, rot, pos);
    for (size_t j = 0; j < b->joint_count; j++)
        for (unsigned k = 0; k < 4; k++)
            FUZZ_REQUIRE(isfinite(rot[j][k]) && (k == 3 || isfinite(pos[j][k])));
    free(rot);
    free(pos);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    psc_bvh_t b = {0};
    char err[512] = "";

    if (psc_bvh_parse(NAME, (const char *)data, size, &b, err, sizeof err) == 0) {
        FUZZ_REQUIRE(b.joint_count >= 1);
        for (size_t j = 0; j < b.joint_count; j++) {
            const psc_bvh_joint_t *jt = &b.joint[j];
            FUZZ_REQUIRE(jt->parent >= -1 && jt->parent < (int)j);
            FUZZ_REQUIRE(jt->channel_count == 0 || jt->channel_count == 3 || jt->channel_count == 6);
            FUZZ_REQUIRE(jt->channel_first + jt->channel_count <= b.channels);
        }
        if (b.frames) {
            pose_frame(&b, 0);
            pose_frame(&b, b.frames - 1);
        }
    } else {
        fuzz_require_message_names(err, NAME);
    }
    psc_bvh_free(&b);
    return 0;
}
