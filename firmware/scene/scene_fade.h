/* SPDX-License-Identifier: MIT */
/*
 * scene_fade.h - a cross-fade from the frame on screen to the next scene
 * (board key scene_fade_ms), as panorama viewers do between linked scenes
 * so a hotspot reads as a step rather than a cut. The last frame is copied
 * once when the scene changes; each frame of the fade blends it under the
 * new scene's frame with weight 1 - t / duration, per channel in integers
 * (t on the board's clock: deterministic on the sim board). The buffer is
 * allocated at start-up for the display's size; nothing after.
 */
#ifndef PSC_SCENE_FADE_H
#define PSC_SCENE_FADE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "base/psc_types.h"

typedef struct {
    psc_surface_t snap;        /* the frame faded from; pixels NULL when fading is off */
    uint32_t duration_us;
    uint64_t start_us;
    bool active;
    uint32_t fades;            /* fades begun, for tests */
} psc_scene_fade_t;

/** Fades of duration_ms (0: off, nothing allocated) on width x height frames of format. 0, or -1 with err. */
int psc_scene_fade_init(psc_scene_fade_t *f, uint32_t duration_ms, uint16_t width, uint16_t height,
                        psc_pixfmt_t format, char *err, size_t errlen);

/** The scene changes at now_us: last (the frame on screen) is what fades out. Ignored when off or mismatched. */
void psc_scene_fade_begin(psc_scene_fade_t *f, const psc_surface_t *last, uint64_t now_us);

/** Blend the fading frame into frame (the new scene's, just drawn) at now_us; ends the fade at its duration. */
void psc_scene_fade_apply(psc_scene_fade_t *f, const psc_surface_t *frame, uint64_t now_us);

/** Free the buffer. */
void psc_scene_fade_free(psc_scene_fade_t *f);

#endif
