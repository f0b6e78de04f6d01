/* SPDX-License-Identifier: MIT */
/*
 * psc_io_pack_image.h - a JPEG or PNG panorama as a scene pack, the way
 * periscope-pack builds one (psc_io_pack_build.h) and the device program
 * shows one given directly (firmware/scene/scene_image.c), so that both make the
 * same bytes: periscope-pack's default options for the display's size and
 * pixel format, and the coverage the image's GPano XMP states.
 *
 * The device keeps what it packed in a cache directory, one file per
 * source image and display:
 *   $PERISCOPE_CACHE_DIR (empty: no cache), else $XDG_CACHE_HOME/periscope,
 *   else $HOME/.cache/periscope (a kiosk: PERISCOPE_CACHE_DIR=/var/cache/periscope).
 * A cache file is named by a 64-bit hash of the source's absolute path, size
 * and modification time (ns), the display size and format, the pack format's
 * version and the program's; it is written atomically (psc_io_atomic.h) and
 * read like any pack (header, size, CRC-32), then checked against the
 * request: a file that fails is packed again and replaced, never used.
 */
#ifndef PSC_IO_PACK_IMAGE_H
#define PSC_IO_PACK_IMAGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "psc_io_load.h"
#include "psc_io_pack_build.h"

/** The longest cache file path. */
#define PSC_IO_PACK_CACHE_PATH_MAX 1024u

/** True when the file starts like a JPEG or a PNG (its magic bytes, not its name). */
bool psc_io_image_sniff(const char *path);

/**
 * Complete o for the equirectangular image at path, w x h pixels: for each
 * axis the caller did not set (lon_given: --lon-range, lat_given:
 * --lat-range) the coverage its GPano XMP states. Appends notes, one line
 * each ending in '\n', naming the file: what the XMP said, an XMP ignored
 * and why, and a warning when the image is not 2:1 (within 2 pixels or
 * 0.5 %) and nothing says what it covers.
 */
void psc_io_pack_image_coverage(const char *path, uint32_t w, uint32_t h, bool lon_given, bool lat_given,
                                psc_pack_options_t *o, char *notes, size_t noteslen);

/** What the device asks for: its display, and where to cache (NULL: the environment's choice). */
typedef struct {
    uint16_t display_width, display_height;
    psc_pixfmt_t format;            /* the map format: the display's own (rgb565 or xrgb8888), or rgb888 */
    const char *cache_dir;          /* NULL: the environment (above); "": no cache */
} psc_io_pack_image_request_t;

/** How it went. */
typedef struct {
    bool from_cache;                /* the cache file was used as it was */
    bool cache_off;                 /* no cache could be used: cache_problem says why */
    char cache_path[PSC_IO_PACK_CACHE_PATH_MAX];   /* "" when cache_off */
    char cache_problem[PSC_IO_PACK_CACHE_PATH_MAX + 128];
    uint64_t build_us;              /* time spent decoding and packing (0 from the cache) */
    char line[PSC_IO_PACK_CACHE_PATH_MAX + 256];   /* the one log line: packed (and how long) or cached */
} psc_io_pack_image_result_t;

/**
 * The pack of the image at path for rq's display: from the cache when it
 * holds a good one, else decoded, packed (with the notes of
 * psc_io_pack_image_coverage), parsed back and written to the cache. 0 with
 * *pf loaded (psc_io_pack_free), or -1 with err naming the file and the
 * problem. notes may be NULL.
 */
int psc_io_pack_image_load(const char *path, const psc_io_pack_image_request_t *rq, psc_io_pack_t *pf,
                           psc_io_pack_image_result_t *res, char *notes, size_t noteslen, char *err,
                           size_t errlen);

/** The cache directory the environment names ("" when none), into dir. */
void psc_io_pack_cache_dir(char *dir, size_t len);

#endif
