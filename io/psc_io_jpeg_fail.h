/* SPDX-License-Identifier: MIT */
/*
 * psc_io_jpeg_fail.h - what io's two JPEG readers share (internal to io):
 * the whole image (psc_io_jpeg.c) and row by row (psc_io_image_rows.c) must
 * refuse the same files and give the same pixels. libjpeg reports fatal
 * errors through error_exit, which must not return: ours longjmps back with
 * the message. Warnings that mean lost pixel data (a truncated or damaged
 * stream) are errors too, so a broken file is refused instead of being shown
 * with grey blocks.
 */
#ifndef PSC_IO_JPEG_FAIL_H
#define PSC_IO_JPEG_FAIL_H

#include <setjmp.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <jpeglib.h>

typedef struct {
    struct jpeg_error_mgr mgr;   /* first: libjpeg hands us a pointer to it */
    jmp_buf jump;
    char msg[JMSG_LENGTH_MAX];
} psc_io_jpeg_fail_t;

/** Give cinfo the error manager fail (before jpeg_create_decompress); fail->jump must be set before any call. */
void psc_io_jpeg_fail_init(struct jpeg_decompress_struct *cinfo, psc_io_jpeg_fail_t *fail);

/** A CMYK or YCCK pixel (4 samples) as 0xFFRRGGBB: Adobe's files store inverted ink amounts, plain ones ink. */
uint32_t psc_io_jpeg_cmyk_to_xrgb(const JSAMPLE *p, bool inverted);

#endif
