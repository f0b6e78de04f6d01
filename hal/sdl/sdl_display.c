/* SPDX-License-Identifier: MIT */
/*
 * sdl_display.c - the SDL2 window display. Frames are drawn into buffers in
 * memory (so get_front_buffer can read back exactly what was shown) and
 * uploaded at present into a streaming texture in the surface's own format
 * (SDL_PIXELFORMAT_RGB565 or SDL_PIXELFORMAT_RGB888, which is XRGB8888), so
 * nothing is converted on the way.
 *
 * Options (board lines "display.KEY = VALUE"):
 *   scale   window size as a multiple of the display size (1..8, default 1),
 *           nearest-neighbour scaling, to see a small panel's pixels
 *   vsync   yes (default) / no: present waits for the desktop's vblank
 *   title   the window title (default "periscope")
 *   fullscreen  yes / no (default): start fullscreen at the desktop's
 *           resolution; F11 or f toggles it either way (sdl_input.c)
 * The window can be resized: the frame keeps its size and aspect and is
 * scaled to fit, black bars beside it (SDL's logical size, which also maps
 * the mouse back to the frame's pixels); nearest-neighbour at whole
 * multiples, linear otherwise.
 * Without an SDL input, present pumps the window's events itself so the
 * desktop does not consider the window hung.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <SDL.h>

#include "psc_hal_option_bool.h"
#include "psc_hal_buffer_ring.h"
#include "sdl_internal.h"

#define SDL_DISPLAY_MAX_BUFFERS PSC_HAL_RING_MAX_BUFFERS

typedef struct {
    psc_hal_display_t base;     /* first: the HAL hands this pointer back to us */
    bool sdl_started;
    SDL_Window *window;
    SDL_Renderer *renderer;
    SDL_Texture *texture;
    psc_hal_buffer_ring_t ring;   /* mode, buffers, front */
    char title[64];
} sdl_display_t;

static const char *const sdl_display_known_options[] = { "scale", "vsync", "title", "fullscreen", NULL };

void psc_sdl_toggle_fullscreen(uint32_t window_id)
{
    SDL_Window *w = SDL_GetWindowFromID(window_id);

    if (w != NULL)
        SDL_SetWindowFullscreen(w, (SDL_GetWindowFlags(w) & SDL_WINDOW_FULLSCREEN) ? 0
                                                                                   : SDL_WINDOW_FULLSCREEN_DESKTOP);
}

static sdl_display_t *to_sdl(psc_hal_display_t *d)
{
    return (sdl_display_t *)d;
}

static int sdl_display_get_mode(psc_hal_display_t *d, psc_hal_display_mode_t *mode)
{
    *mode = to_sdl(d)->ring.mode;
    return 0;
}

static int sdl_display_get_back_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    sdl_display_t *s = to_sdl(d);

    psc_hal_buffer_ring_surface(&s->ring, psc_hal_buffer_ring_back(&s->ring), surface);
    return 0;
}

static int sdl_display_get_front_buffer(psc_hal_display_t *d, psc_surface_t *surface)
{
    psc_hal_buffer_ring_surface(&to_sdl(d)->ring, to_sdl(d)->ring.front, surface);
    return 0;
}

static int sdl_display_present(psc_hal_display_t *d)
{
    sdl_display_t *s = to_sdl(d);
    uint8_t back = psc_hal_buffer_ring_back(&s->ring);

    if (SDL_UpdateTexture(s->texture, NULL, s->ring.buffers[back], (int)s->ring.mode.stride) != 0 ||
        SDL_RenderClear(s->renderer) != 0 || SDL_RenderCopy(s->renderer, s->texture, NULL, NULL) != 0)
        return -EIO;
    SDL_RenderPresent(s->renderer);
    s->ring.front = back;
    if (psc_sdl_inputs_open == 0) {
        /* nobody reads the window's events: keep the desktop happy, drop them */
        SDL_PumpEvents();
        SDL_FlushEvents(SDL_FIRSTEVENT, SDL_LASTEVENT);
    }
    return 0;
}

static int sdl_display_set_blank(psc_hal_display_t *d, bool blank)
{
    sdl_display_t *s = to_sdl(d);

    /* a desktop window cannot power the panel down: show black instead */
    if (blank) {
        memset(s->ring.buffers[s->ring.front], 0, (size_t)s->ring.mode.stride * s->ring.mode.height);
        SDL_RenderClear(s->renderer);
        SDL_RenderPresent(s->renderer);
    }
    return 0;
}

static void sdl_display_close(psc_hal_display_t *d)
{
    sdl_display_t *s = to_sdl(d);

    if (s->texture != NULL)
        SDL_DestroyTexture(s->texture);
    if (s->renderer != NULL)
        SDL_DestroyRenderer(s->renderer);
    if (s->window != NULL)
        SDL_DestroyWindow(s->window);
    if (s->sdl_started)
        psc_sdl_quit(SDL_INIT_VIDEO);
    for (unsigned i = 0; i < SDL_DISPLAY_MAX_BUFFERS; i++)
        free(s->ring.buffers[i]);
    free(s);
}

static const psc_hal_display_ops_t sdl_display_ops = {
    .get_mode = sdl_display_get_mode,
    .get_back_buffer = sdl_display_get_back_buffer,
    .present = sdl_display_present,
    .set_blank = sdl_display_set_blank,
    .get_front_buffer = sdl_display_get_front_buffer,
    .close = sdl_display_close,
};

int psc_sdl_display_open(const psc_hal_display_config_t *cfg, psc_hal_display_t **out, char *err, size_t errlen)
{
    const psc_hal_option_t *title;
    sdl_display_t *s;
    uint32_t scale;
    bool vsync, fullscreen;
    int rc;

    *out = NULL;
    if (cfg->width == 0 || cfg->height == 0 || cfg->width > PSC_MAX_OUT_DIM || cfg->height > PSC_MAX_OUT_DIM ||
        cfg->buffer_count < 1 || cfg->buffer_count > SDL_DISPLAY_MAX_BUFFERS ||
        (cfg->format != PSC_PIX_RGB565 && cfg->format != PSC_PIX_XRGB8888)) {
        psc_hal_error_set(err, errlen, "sdl display: %ux%u, %u buffers, format %d: sizes 1..%u, 1..3 buffers of "
                          "rgb565 or xrgb8888 are supported", (unsigned)cfg->width, (unsigned)cfg->height,
                          (unsigned)cfg->buffer_count, (int)cfg->format, PSC_MAX_OUT_DIM);
        return -EINVAL;
    }
    s = calloc(1, sizeof *s);
    if (s == NULL) {
        psc_hal_error_set(err, errlen, "sdl display: out of memory");
        return -ENOMEM;
    }
    s->base.ops = &sdl_display_ops;
    s->base.backend = "sdl";
    if ((rc = psc_hal_options_check(&cfg->options, sdl_display_known_options, "display", "sdl", err, errlen)) ||
        (rc = psc_hal_options_get_u32(&cfg->options, "scale", 1, 8, 1, &scale, err, errlen)) ||
        (rc = psc_hal_options_get_bool(&cfg->options, "vsync", "display", true, &vsync, err, errlen)) ||
        (rc = psc_hal_options_get_bool(&cfg->options, "fullscreen", "display", false, &fullscreen, err, errlen)))
        goto fail;
    title = psc_hal_options_find(&cfg->options, "title");
    snprintf(s->title, sizeof s->title, "%s", title != NULL && title->value != NULL ? title->value : "periscope");

    s->ring.mode = (psc_hal_display_mode_t){
        .width = cfg->width, .height = cfg->height, .format = cfg->format, .buffer_count = cfg->buffer_count,
        .stride = cfg->width * psc_pixfmt_bytes(cfg->format), .refresh_mhz = 0,
    };
    for (unsigned i = 0; i < cfg->buffer_count; i++) {
        s->ring.buffers[i] = calloc(cfg->height, s->ring.mode.stride);
        if (s->ring.buffers[i] == NULL) {
            psc_hal_error_set(err, errlen, "sdl display: out of memory for %ux%u buffers", (unsigned)cfg->width,
                              (unsigned)cfg->height);
            rc = -ENOMEM;
            goto fail;
        }
    }
    if ((rc = psc_sdl_init(SDL_INIT_VIDEO, "display", err, errlen)) != 0)
        goto fail;
    s->sdl_started = true;
    SDL_SetHint(SDL_HINT_RENDER_SCALE_QUALITY, scale > 1 ? "nearest" : "linear");   /* a panel's pixels, or smooth */
    s->window = SDL_CreateWindow(s->title, SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED, (int)(cfg->width * scale),
                                 (int)(cfg->height * scale),
                                 SDL_WINDOW_SHOWN | SDL_WINDOW_RESIZABLE |
                                     (fullscreen ? SDL_WINDOW_FULLSCREEN_DESKTOP : 0u));
    if (s->window != NULL)
        s->renderer = SDL_CreateRenderer(s->window, -1, vsync ? SDL_RENDERER_PRESENTVSYNC : 0);
    /* the frame keeps its size whatever the window's: scaled to fit, mouse mapped back */
    if (s->renderer != NULL && SDL_RenderSetLogicalSize(s->renderer, cfg->width, cfg->height) != 0) {
        SDL_DestroyRenderer(s->renderer);
        s->renderer = NULL;
    }
    if (s->renderer != NULL)
        s->texture = SDL_CreateTexture(s->renderer,
                                       cfg->format == PSC_PIX_RGB565 ? SDL_PIXELFORMAT_RGB565 : SDL_PIXELFORMAT_RGB888,
                                       SDL_TEXTUREACCESS_STREAMING, cfg->width, cfg->height);
    if (s->texture == NULL) {
        psc_hal_error_set(err, errlen, "sdl display: cannot create a %ux%u window (video driver %s): %s",
                          (unsigned)cfg->width, (unsigned)cfg->height,
                          SDL_GetCurrentVideoDriver() ? SDL_GetCurrentVideoDriver() : "none", SDL_GetError());
        rc = -ENODEV;
        goto fail;
    }
    *out = &s->base;
    return 0;
fail:
    sdl_display_close(&s->base);
    return rc;
}
