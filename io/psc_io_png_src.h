/* SPDX-License-Identifier: MIT */
/*
 * psc_io_png_src.h - what io's two PNG readers share (internal to io): the
 * whole image (psc_io_png.c) and row by row (psc_io_image_rows.c) must
 * refuse the same files with the same messages. libpng's error callback
 * must not return: it keeps the message and longjmps.
 */
#ifndef PSC_IO_PNG_SRC_H
#define PSC_IO_PNG_SRC_H

#include <stdio.h>
#include <png.h>

/** A PNG being read from a file: libpng's error and read pointer (a reader's struct may start with one). */
typedef struct {
    FILE *file;
    char msg[200];   /* libpng's last error */
} psc_io_png_src_t;

/** libpng's callbacks on a psc_io_png_src_t as error pointer (and read pointer: psc_io_png_on_read). */
void psc_io_png_on_error(png_structp png, png_const_charp msg);
void psc_io_png_on_warning(png_structp png, png_const_charp msg);
void psc_io_png_on_read(png_structp png, png_bytep data, size_t len);

#endif
