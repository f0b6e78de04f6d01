/* SPDX-License-Identifier: MIT */
/*
 * fuzz_board.c - board files (board.conf, firmware/board_config.h) through
 * psc_board_config_parse on top of the defaults, as the device reads them.
 * A refusal must be "FILE:LINE: problem" naming the file; a parsed board
 * keeps its scene, hotspot, object and option counts within their caps, its
 * strings terminated, every object in a scene it declares (a linked one's
 * target a scene of it, its title cut to a terminated label), and hands out
 * its backends' options for every device kind.
 */
#include <stdlib.h>
#include <string.h>

#include "board_config.h"
#include "fuzz_support.h"

#define NAME "fuzz/board.conf"

static bool terminated(const char *s, size_t size)
{
    return memchr(s, '\0', size) != NULL;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static psc_board_config_t cfg; /* some 20 KB: kept off the stack */
    char err[512] = "";

    psc_board_config_defaults(&cfg);
    if (psc_board_config_parse((const char *)data, size, NAME, &cfg, err, sizeof err) == 0) {
        FUZZ_REQUIRE(cfg.scene_count <= PSC_BOARD_MAX_SCENES && cfg.hotspot_count <= PSC_HOTSPOT_MAX);
        FUZZ_REQUIRE(cfg.option_count <= PSC_BOARD_MAX_OPTIONS);
        FUZZ_REQUIRE(terminated(cfg.display_backend, sizeof cfg.display_backend));
        FUZZ_REQUIRE(terminated(cfg.input_backend, sizeof cfg.input_backend));
        FUZZ_REQUIRE(terminated(cfg.tour, sizeof cfg.tour));
        for (unsigned i = 0; i < cfg.scene_count; i++)
            FUZZ_REQUIRE(terminated(cfg.scenes[i], sizeof cfg.scenes[i]));
        FUZZ_REQUIRE(cfg.object_count <= PSC_BOARD_MAX_OBJECTS);
        for (unsigned i = 0; i < cfg.object_count; i++) {
            const psc_board_object_t *o = &cfg.objects[i];
            FUZZ_REQUIRE(o->scene < cfg.scene_count && o->line > 0);
            FUZZ_REQUIRE(terminated(o->spec.path, sizeof o->spec.path) && o->spec.path[0] != '\0');
            FUZZ_REQUIRE(terminated(o->spec.title, sizeof o->spec.title));
            FUZZ_REQUIRE(!o->linked || (o->link.to_scene < cfg.scene_count + 1u &&
                                        terminated(o->link.label, sizeof o->link.label)));
            FUZZ_REQUIRE(o->spec.place.dist_q16 >= PSC_3D_PLACE_DIST_MIN_Q16 &&
                         o->spec.place.dist_q16 <= PSC_3D_PLACE_DIST_MAX_Q16);
        }
        for (unsigned d = 0; d < PSC_BOARD_DEV_COUNT; d++) {
            psc_hal_option_t items[PSC_BOARD_MAX_OPTIONS];
            size_t n = psc_board_config_options(&cfg, (psc_board_dev_t)d, items, PSC_BOARD_MAX_OPTIONS);
            FUZZ_REQUIRE(n <= cfg.option_count);
        }
    } else {
        fuzz_require_message_names(err, NAME ":");
    }
    return 0;
}
