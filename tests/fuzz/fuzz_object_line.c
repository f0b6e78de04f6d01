/* SPDX-License-Identifier: MIT */
/*
 * fuzz_object_line.c - an object line (board.conf's scene.ID.object value with
 * spaces, periscope-render's --object with commas; io/psc_io_object.h) through
 * psc_io_object_spec_parse, with each separator. A refusal names where it was
 * ("fuzz:1") and why; a parsed line has its file, terminated strings and a
 * placement within the documented ranges, which core places without a fault:
 * a unit box and one far from its origin, seen from the poles and the seam,
 * and depth planes the pipeline takes.
 */
#include <stdlib.h>
#include <string.h>

#include "3d/psc_3d_place.h"
#include "fuzz_support.h"
#include "psc_io_object.h"

static bool terminated(const char *s, size_t size)
{
    return memchr(s, '\0', size) != NULL;
}

static void check(const char *text, char sep)
{
    psc_io_object_spec_t spec;
    char err[1024] = "";

    if (psc_io_object_spec_parse(text, sep, "fuzz:1", &spec, err, sizeof err) != 0) {
        fuzz_require_message_names(err, "fuzz:1: ");
        return;
    }
    FUZZ_REQUIRE(spec.path[0] != '\0' && terminated(spec.path, sizeof spec.path));
    FUZZ_REQUIRE(terminated(spec.shadow, sizeof spec.shadow) && terminated(spec.action, sizeof spec.action));
    FUZZ_REQUIRE(terminated(spec.hotspot, sizeof spec.hotspot) && terminated(spec.title, sizeof spec.title));
    const psc_3d_place_t *pl = &spec.place;
    FUZZ_REQUIRE(pl->pitch >= -(int32_t)PSC_BAM_90 && pl->pitch <= (int32_t)PSC_BAM_90);
    FUZZ_REQUIRE(pl->dist_q16 >= PSC_3D_PLACE_DIST_MIN_Q16 && pl->dist_q16 <= PSC_3D_PLACE_DIST_MAX_Q16);
    FUZZ_REQUIRE(pl->scale_q16 >= PSC_3D_PLACE_SCALE_MIN_Q16 && pl->scale_q16 <= PSC_3D_PLACE_SCALE_MAX_Q16);
    FUZZ_REQUIRE(spec.time_s >= 0.0 && spec.time_s <= 3600.0);
    static const psc_vec3_q16_t lo[2] = {{-65536, -65536, -65536}, {1000 << 16, 0, -(2000 << 16)}};
    static const psc_vec3_q16_t hi[2] = {{65536, 65536, 65536}, {1001 << 16, 3 << 16, -(1999 << 16)}};
    static const int32_t pitches[3] = {-(int32_t)PSC_BAM_90, 0, (int32_t)PSC_BAM_90};
    for (unsigned b = 0; b < 2; b++)
        for (unsigned k = 0; k < 3; k++) {
            psc_mat4_q16_t m;
            psc_status_t s = psc_3d_place(pl, lo[b], hi[b], PSC_BAM_180 + k, pitches[k], &m);
            FUZZ_REQUIRE(s == PSC_OK || s == PSC_ERR_ARG);
            if (s == PSC_OK && b == 0) {   /* a unit box's corners stay in range */
                psc_vec3_q16_t o;
                FUZZ_REQUIRE(psc_mat4_apply(&m, lo[0], &o) && psc_mat4_apply(&m, hi[0], &o));
            }
        }
    int32_t near = 0, far = 0;
    psc_3d_place_depth(pl, &near, &far);
    psc_3d_place_depth_finish(&near, &far);
    FUZZ_REQUIRE(near >= 1 && far >= 2 * near && far / 4096 <= near);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text_copy(data, size);
    check(text, ' ');
    check(text, ',');
    free(text);
    return 0;
}
