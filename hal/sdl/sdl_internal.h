/* SPDX-License-Identifier: MIT */
/*
 * sdl_internal.h - what the SDL2 display and input share: SDL start-up, and
 * whether an SDL input is open (so the display knows whether it must pump
 * the window's events itself). Not for the firmware.
 */
#ifndef PSC_SDL_INTERNAL_H
#define PSC_SDL_INTERNAL_H

#include <stdint.h>

#include "psc_hal_display.h"
#include "psc_hal_input.h"

/**
 * Start the SDL subsystems in flags (SDL_INIT_VIDEO, ...). SDL counts them,
 * so the display and the input each init and quit their own. Installs no
 * signal handlers: the firmware handles SIGTERM/SIGINT itself, the same on
 * every board. 0, or -ENODEV with err quoting SDL_GetError().
 */
int psc_sdl_init(uint32_t flags, const char *what, char *err, size_t errlen);

/** Quit subsystems started with psc_sdl_init. */
void psc_sdl_quit(uint32_t flags);

/** Open inputs of the SDL backend (they pump SDL's event queue; the display need not). */
extern unsigned psc_sdl_inputs_open;

/** F11: the display's window with this id goes fullscreen (desktop resolution) or back (sdl_display.c). */
void psc_sdl_toggle_fullscreen(uint32_t window_id);

/** Open the SDL window display (sdl_display.c). */
int psc_sdl_display_open(const psc_hal_display_config_t *cfg, psc_hal_display_t **out, char *err, size_t errlen);

/** Open the SDL keyboard/mouse/game controller input (sdl_input.c). */
int psc_sdl_input_open(const psc_hal_input_config_t *cfg, psc_hal_input_t **out, char *err, size_t errlen);

#endif
