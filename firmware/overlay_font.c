/* SPDX-License-Identifier: MIT */
/*
 * overlay_font.c - the 5x7 font and clipped integer drawing (overlay_font.h).
 * The glyphs were drawn for this file, row by row below ('#' = on).
 */
#include <stddef.h>

#include "overlay_font.h"
#include "base/psc_pixel.h"

typedef struct {
    char c;
    const char *rows;   /* 7 rows of 5 characters */
} glyph_art_t;

static const glyph_art_t glyph_art[] = {
    { ' ', "....." "....." "....." "....." "....." "....." "....." },
    { '-', "....." "....." "....." ".###." "....." "....." "....." },
    { ':', "....." "..#.." "..#.." "....." "..#.." "..#.." "....." },
    { '.', "....." "....." "....." "....." "....." ".##.." ".##.." },
    { '/', "....#" "....#" "...#." "..#.." ".#..." "#...." "#...." },
    { '!', "..#.." "..#.." "..#.." "..#.." "..#.." "....." "..#.." },
    { '?', ".###." "#...#" "....#" "...#." "..#.." "....." "..#.." },
    { ',', "....." "....." "....." "....." ".##.." "..#.." ".#..." },
    { '\'', "..#.." "..#.." ".#..." "....." "....." "....." "....." },
    { '&', ".##.." "#..#." "#.#.." ".#..." "#.#.#" "#..#." ".##.#" },
    { '(', "...#." "..#.." ".#..." ".#..." ".#..." "..#.." "...#." },
    { ')', ".#..." "..#.." "...#." "...#." "...#." "..#.." ".#..." },
    { '0', ".###." "#...#" "#..##" "#.#.#" "##..#" "#...#" ".###." },
    { '1', "..#.." ".##.." "..#.." "..#.." "..#.." "..#.." ".###." },
    { '2', ".###." "#...#" "....#" "...#." "..#.." ".#..." "#####" },
    { '3', "####." "....#" "....#" ".###." "....#" "....#" "####." },
    { '4', "...#." "..##." ".#.#." "#..#." "#####" "...#." "...#." },
    { '5', "#####" "#...." "####." "....#" "....#" "#...#" ".###." },
    { '6', "..##." ".#..." "#...." "####." "#...#" "#...#" ".###." },
    { '7', "#####" "....#" "...#." "..#.." ".#..." ".#..." ".#..." },
    { '8', ".###." "#...#" "#...#" ".###." "#...#" "#...#" ".###." },
    { '9', ".###." "#...#" "#...#" ".####" "....#" "...#." ".##.." },
    { 'A', ".###." "#...#" "#...#" "#####" "#...#" "#...#" "#...#" },
    { 'B', "####." "#...#" "#...#" "####." "#...#" "#...#" "####." },
    { 'C', ".###." "#...#" "#...." "#...." "#...." "#...#" ".###." },
    { 'D', "####." "#...#" "#...#" "#...#" "#...#" "#...#" "####." },
    { 'E', "#####" "#...." "#...." "####." "#...." "#...." "#####" },
    { 'F', "#####" "#...." "#...." "####." "#...." "#...." "#...." },
    { 'G', ".###." "#...#" "#...." "#.###" "#...#" "#...#" ".####" },
    { 'H', "#...#" "#...#" "#...#" "#####" "#...#" "#...#" "#...#" },
    { 'I', ".###." "..#.." "..#.." "..#.." "..#.." "..#.." ".###." },
    { 'J', "..###" "...#." "...#." "...#." "...#." "#..#." ".##.." },
    { 'K', "#...#" "#..#." "#.#.." "##..." "#.#.." "#..#." "#...#" },
    { 'L', "#...." "#...." "#...." "#...." "#...." "#...." "#####" },
    { 'M', "#...#" "##.##" "#.#.#" "#.#.#" "#...#" "#...#" "#...#" },
    { 'N', "#...#" "#...#" "##..#" "#.#.#" "#..##" "#...#" "#...#" },
    { 'O', ".###." "#...#" "#...#" "#...#" "#...#" "#...#" ".###." },
    { 'P', "####." "#...#" "#...#" "####." "#...." "#...." "#...." },
    { 'Q', ".###." "#...#" "#...#" "#...#" "#.#.#" "#..#." ".##.#" },
    { 'R', "####." "#...#" "#...#" "####." "#.#.." "#..#." "#...#" },
    { 'S', ".####" "#...." "#...." ".###." "....#" "....#" "####." },
    { 'T', "#####" "..#.." "..#.." "..#.." "..#.." "..#.." "..#.." },
    { 'U', "#...#" "#...#" "#...#" "#...#" "#...#" "#...#" ".###." },
    { 'V', "#...#" "#...#" "#...#" "#...#" "#...#" ".#.#." "..#.." },
    { 'W', "#...#" "#...#" "#...#" "#.#.#" "#.#.#" "#.#.#" ".#.#." },
    { 'X', "#...#" "#...#" ".#.#." "..#.." ".#.#." "#...#" "#...#" },
    { 'Y', "#...#" "#...#" ".#.#." "..#.." "..#.." "..#.." "..#.." },
    { 'Z', "#####" "....#" "...#." "..#.." ".#..." "#...." "#####" },
};

#define GLYPH_COUNT (sizeof glyph_art / sizeof glyph_art[0])

static uint8_t glyph_bits[GLYPH_COUNT][PSC_FONT_GLYPH_H];
static int glyphs_ready;

/* Pack the art into bit rows once; a few hundred bytes, no allocation. */
static void font_prepare(void)
{
    for (size_t g = 0; g < GLYPH_COUNT; g++)
        for (unsigned r = 0; r < PSC_FONT_GLYPH_H; r++) {
            uint8_t bits = 0;
            for (unsigned c = 0; c < PSC_FONT_GLYPH_W; c++)
                if (glyph_art[g].rows[r * PSC_FONT_GLYPH_W + c] == '#')
                    bits |= (uint8_t)(1u << (PSC_FONT_GLYPH_W - 1u - c));
            glyph_bits[g][r] = bits;
        }
    glyphs_ready = 1;
}

const uint8_t *psc_font_glyph(char c)
{
    size_t question = 0;

    if (!glyphs_ready)
        font_prepare();
    if (c >= 'a' && c <= 'z')
        c = (char)(c - 'a' + 'A');
    for (size_t g = 0; g < GLYPH_COUNT; g++) {
        if (glyph_art[g].c == c)
            return glyph_bits[g];
        if (glyph_art[g].c == '?')
            question = g;
    }
    return glyph_bits[question];
}

uint32_t psc_font_text_width(const char *text, uint32_t scale)
{
    uint32_t n = 0;

    while (text[n] != '\0')
        n++;
    return n * PSC_FONT_CELL_W * scale;
}

/* Colour 0xRRGGBB in the surface's format. */
static uint32_t surface_colour(const psc_surface_t *s, uint32_t rgb)
{
    return s->format == PSC_PIX_RGB565 ? psc_xrgb_to_rgb565(rgb) : 0xFF000000u | rgb;
}

void psc_overlay_fill(const psc_surface_t *s, int32_t x, int32_t y, uint32_t w, uint32_t h, uint32_t rgb)
{
    int64_t x0 = x < 0 ? 0 : x, y0 = y < 0 ? 0 : y;
    int64_t x1 = (int64_t)x + w, y1 = (int64_t)y + h;
    uint32_t colour = surface_colour(s, rgb);

    if (s->format != PSC_PIX_RGB565 && s->format != PSC_PIX_XRGB8888)
        return;
    if (x1 > s->width)
        x1 = s->width;
    if (y1 > s->height)
        y1 = s->height;
    for (int64_t yy = y0; yy < y1; yy++) {
        uint8_t *row = (uint8_t *)s->pixels + (size_t)yy * s->stride;
        for (int64_t xx = x0; xx < x1; xx++) {
            if (s->format == PSC_PIX_RGB565)
                ((uint16_t *)(void *)row)[xx] = (uint16_t)colour;
            else
                ((uint32_t *)(void *)row)[xx] = colour;
        }
    }
}

void psc_overlay_text(const psc_surface_t *s, int32_t x, int32_t y, uint32_t scale, const char *text, uint32_t rgb)
{
    for (size_t i = 0; text[i] != '\0'; i++) {
        const uint8_t *g = psc_font_glyph(text[i]);
        int32_t gx = x + (int32_t)(i * PSC_FONT_CELL_W * scale);

        for (uint32_t r = 0; r < PSC_FONT_GLYPH_H; r++)
            for (uint32_t c = 0; c < PSC_FONT_GLYPH_W; c++)
                if (g[r] & (1u << (PSC_FONT_GLYPH_W - 1u - c)))
                    psc_overlay_fill(s, gx + (int32_t)(c * scale), y + (int32_t)(r * scale), scale, scale, rgb);
    }
}
