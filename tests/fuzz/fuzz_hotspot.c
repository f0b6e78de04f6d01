/* SPDX-License-Identifier: MIT */
/*
 * fuzz_hotspot.c - the value of a board's hotspot line ("0 45 -5 10 -> 1 180
 * 0 90", firmware/hotspots.h) through psc_hotspot_parse, as a NUL-terminated
 * string the way the board parser hands it over. A refusal gives a reason; a
 * parsed hotspot has its radius and view within the documented ranges and is
 * used as the kiosk uses it: picked, tested for containment and projected.
 */
#include <stdlib.h>

#include "fuzz_support.h"
#include "hotspots.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text_copy(data, size);
    psc_hotspot_t h;
    char why[256] = "";

    if (psc_hotspot_parse(text, &h, why, sizeof why) == 0) {
        FUZZ_REQUIRE(h.line == 0);
        FUZZ_REQUIRE(h.radius >= PSC_BAM_FROM_MDEG(100) && h.radius <= PSC_BAM_FROM_MDEG(90000));
        FUZZ_REQUIRE(h.to_hfov >= PSC_BAM_FROM_MDEG(1000) && h.to_hfov <= PSC_BAM_FROM_MDEG(170000));
        FUZZ_REQUIRE(h.pitch >= -(int32_t)PSC_BAM_90 && h.pitch <= (int32_t)PSC_BAM_90);
        FUZZ_REQUIRE(h.to_pitch >= -(int32_t)PSC_BAM_90 && h.to_pitch <= (int32_t)PSC_BAM_90);
        uint32_t pick = fuzz_hash(data, size);
        int32_t pitch = (int32_t)(pick % (2u * PSC_BAM_90 + 1u)) - (int32_t)PSC_BAM_90;
        int found = psc_hotspot_pick(&h, 1, h.from_scene, pick * 2654435761u, pitch);
        FUZZ_REQUIRE(found == -1 || found == 0);
        FUZZ_REQUIRE(psc_hotspot_contains(&h, h.yaw, h.pitch));
        psc_view_t view = {.yaw = h.to_yaw, .pitch = h.to_pitch, .hfov = h.to_hfov};
        int32_t x, y;
        (void)psc_hotspot_project(&view, 320, 240, h.yaw, h.pitch, &x, &y);
    } else {
        FUZZ_REQUIRE(why[0] != '\0');
    }
    free(text);
    return 0;
}
