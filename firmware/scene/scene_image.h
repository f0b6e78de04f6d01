/* SPDX-License-Identifier: MIT */
/*
 * scene_image.h - a JPEG or PNG given as a scene (a board's scene line,
 * --scene, or a file on the command line): packed for the display on
 * loading, as periscope-pack would by default for it, through the pack
 * cache (io/psc_io_pack_image.h), then shown as any panorama. The panorama
 * scene (scene_panorama.c) hands such files here, recognised by their
 * first bytes.
 */
#ifndef PSC_SCENE_IMAGE_H
#define PSC_SCENE_IMAGE_H

#include <stdbool.h>
#include <stddef.h>

#include "psc_io_load.h"
#include "scene/scene.h"

/** True when s->path is a JPEG or PNG image (by its magic bytes). */
bool psc_scene_image_is_image(const char *path);

/**
 * Pack the image s->path for s->env's display into *pf (from the cache when
 * it holds a good one). Logs one line (packed and how long, or from the
 * cache), the notes (GPano XMP, the 2:1 warning), and once per program that
 * no cache can be used. 0, or -1 with err naming the file and the problem.
 */
int psc_scene_image_load(const psc_scene_t *s, psc_io_pack_t *pf, char *err, size_t errlen);

#endif
