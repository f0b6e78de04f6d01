/* SPDX-License-Identifier: MIT */
/* tsup_pack.c - small packs of the synthetic scene on disk (tsup_pack.h). */
#include <stddef.h>
#include <stdlib.h>

#include "psc_io_pack_build.h"
#include "psc_testsupport.h"
#include "tsup_pack.h"
#include "psc_io_file.h"

int tsup_write_synth_pack(const char *path, uint32_t map_w, uint32_t map_h, uint16_t disp_w, uint16_t disp_h,
                          uint16_t lut_rows, uint16_t lut_cols, char *err, size_t errlen)
{
    psc_image_t img = {map_w, map_h, malloc((size_t)map_w * map_h * 4)};
    if (!img.xrgb)
        return -1;
    for (uint32_t y = 0; y < map_h; y++)
        for (uint32_t x = 0; x < map_w; x++) {
            double rgb[3]; /* each pixel the colour of its centre's direction */
            tsup_synth_color(((x + 0.5) / map_w - 0.5) * 2 * TSUP_PI, (0.5 - (y + 0.5) / map_h) * TSUP_PI, rgb);
            img.xrgb[(size_t)y * map_w + x] =
                0xFF000000u | ((uint32_t)rgb[0] << 16) | ((uint32_t)rgb[1] << 8) | (uint32_t)rgb[2];
        }
    psc_pack_options_t o;
    psc_io_pack_options_default(&o);
    o.display_width = disp_w;
    o.display_height = disp_h;
    o.lut_rows = lut_rows;
    o.lut_cols = lut_cols;
    uint8_t *buf;
    size_t len;
    int rc = psc_io_pack_build(&img, &o, &buf, &len, err, errlen);
    free(img.xrgb);
    if (rc != 0)
        return -1;
    rc = psc_io_write_atomic(path, buf, len, err, errlen);
    free(buf);
    return rc;
}
