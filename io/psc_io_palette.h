/* SPDX-License-Identifier: MIT */
/*
 * psc_io_palette.h - choose a 256-colour palette for an image and map colours to it
 * (for PAL8 maps). The quantizer is a variance-based median cut refined by a
 * few Lloyd rounds; colours are mapped through an inverse table of 7 bits per
 * channel whose entries are found on first use.
 */
#ifndef PSC_PALETTE_H
#define PSC_PALETTE_H

#include <stdbool.h>
#include <stdint.h>
#include "psc_io_image.h"

#define PSC_PALETTE_SIZE 256u

typedef struct {
    uint32_t colors[PSC_PALETTE_SIZE];  /* 0xFFRRGGBB; entries past count are 0xFF000000 */
    unsigned count;                     /* 1..256 colours in use */
    bool exact;                         /* the image has exactly these colours (sorted) */
} psc_palette_t;

/**
 * Choose the palette: the image's own colours when it has at most 256,
 * otherwise up to 256 colours by median cut. 0, or -1 when out of memory.
 */
int psc_io_palette_build(const psc_image_t *img, psc_palette_t *pal);

/** Nearest-colour lookup for a palette (keeps a pointer to it). */
typedef struct {
    const psc_palette_t *pal;
    int16_t *inverse;   /* 2^21 entries by the colour's top 7 bits per channel; -1 = not yet known */
} psc_palette_mapper_t;

/** Build the lookup. 0, or -1 when out of memory. */
int psc_io_palette_mapper_init(psc_palette_mapper_t *m, const psc_palette_t *pal);
void psc_io_palette_mapper_free(psc_palette_mapper_t *m);

/** Palette index for a colour: exact for colours of an exact palette, else the entry nearest its cell. */
uint8_t psc_io_palette_index(psc_palette_mapper_t *m, uint32_t xrgb);

#endif
