/* SPDX-License-Identifier: MIT */
/* scene_image.c - a JPEG or PNG scene, packed on loading (scene_image.h). */
#include <stdatomic.h>
#include <string.h>

#include "psc_io_log.h"
#include "psc_io_pack_image.h"
#include "scene/scene_image.h"

/* set once the program has said that it packs without a cache */
static atomic_flag image_said_no_cache = ATOMIC_FLAG_INIT;

bool psc_scene_image_is_image(const char *path)
{
    return psc_io_image_sniff(path);
}

/* Each note line on its own, prefixed like every message of the program: warnings as warnings. */
static void image_print_notes(const char *notes)
{
    while (*notes != '\0') {
        size_t n = strcspn(notes, "\n");
        psc_io_log(strncmp(notes, "warning:", 8) == 0 ? PSC_LOG_WARNING : PSC_LOG_INFO, "periscope: %.*s", (int)n,
                notes);
        notes += n + (notes[n] == '\n');
    }
}

int psc_scene_image_load(const psc_scene_t *s, psc_io_pack_t *pf, char *err, size_t errlen)
{
    const psc_scene_env_t *env = s->env;
    /* periscope-pack --format: the board's display_format, as the package packs the sample scene for a
     * board (mk/deb.mk); but an RGB565 display that dithers (display_dither, the default) gets the
     * 8-bit RGB888 map, or there would be nothing left to dither: the sky's bands are in a 565 map already */
    const psc_board_config_t *b = env->board;
    psc_pixfmt_t f = b != NULL ? b->display_format : env->format;
    if (b != NULL && f == PSC_PIX_RGB565 && b->display_dither != PSC_DITHER_NONE && !b->display_levels.on)
        f = PSC_PIX_RGB888;
    psc_io_pack_image_request_t rq = {
        .display_width = env->width,
        .display_height = env->height,
        .format = f == PSC_PIX_XRGB8888 || f == PSC_PIX_RGB888 ? f : PSC_PIX_RGB565,
        .cache_dir = NULL,
    };
    psc_io_pack_image_result_t res;
    char notes[1024] = "";

    int rc = psc_io_pack_image_load(s->path, &rq, pf, &res, notes, sizeof notes, err, errlen);
    image_print_notes(notes);
    if (rc != 0)
        return -1;
    if (res.cache_off && !atomic_flag_test_and_set(&image_said_no_cache))
        psc_io_log(PSC_LOG_NOTICE, "periscope: note: no pack cache (%s): images are packed in memory on every start "
                "(PERISCOPE_CACHE_DIR names a writable directory)", res.cache_problem);
    psc_io_log(PSC_LOG_INFO, "periscope: %s", res.line);
    return 0;
}
