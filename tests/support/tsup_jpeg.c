/* SPDX-License-Identifier: MIT */
/* tsup_jpeg.c - JPEGs written for the tests (tsup_jpeg.h). libjpeg exits on its own errors: the inputs are valid. */
#include "tsup_jpeg.h"

int tsup_write_jpeg(const char *path, const uint8_t *pix, unsigned w, unsigned h, const tsup_jpeg_spec_t *spec)
{
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    jpeg_stdio_dest(&c, f);
    c.image_width = w;
    c.image_height = h;
    c.input_components = spec->components;
    c.in_color_space = spec->in_space;
    jpeg_set_defaults(&c);
    if (spec->rgb_space)
        jpeg_set_colorspace(&c, JCS_RGB);
    jpeg_set_quality(&c, spec->quality, TRUE);
    if (spec->full_chroma)
        for (int i = 0; i < c.num_components; i++)
            c.comp_info[i].h_samp_factor = c.comp_info[i].v_samp_factor = 1;
    if (spec->progressive)
        jpeg_simple_progression(&c);
    if (spec->no_adobe)
        c.write_Adobe_marker = FALSE;
    c.restart_in_rows = spec->restart_rows;
    jpeg_start_compress(&c, TRUE);
    while (c.next_scanline < c.image_height) {
        JSAMPROW row = (JSAMPROW)(pix + (size_t)c.next_scanline * w * (unsigned)spec->components);
        jpeg_write_scanlines(&c, &row, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    return fclose(f) == 0 ? 0 : -1;
}
