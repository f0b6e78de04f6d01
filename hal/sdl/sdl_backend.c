/* SPDX-License-Identifier: MIT */
/*
 * sdl_backend.c - the "sdl" backend: an SDL2 window as the display and its
 * keyboard, mouse and SDL game controllers as the input, for developing on a
 * desktop (board: "display = sdl", "input = sdl"). Works headless with
 * SDL_VIDEODRIVER=dummy (or offscreen), which is how the tests run it.
 */
#include <SDL.h>

#include "psc_hal_backends.h"
#include "sdl_internal.h"

unsigned psc_sdl_inputs_open;

int psc_sdl_init(uint32_t flags, const char *what, char *err, size_t errlen)
{
    SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");
    if (SDL_InitSubSystem(flags) != 0) {
        psc_hal_error_set(err, errlen, "sdl %s: SDL could not start: %s (no display? SDL_VIDEODRIVER=dummy runs "
                          "without one)", what, SDL_GetError());
        return -ENODEV;
    }
    return 0;
}

void psc_sdl_quit(uint32_t flags)
{
    SDL_QuitSubSystem(flags);
}

const psc_hal_backend_t psc_hal_sdl_backend = {
    .name = "sdl",
    .description = "SDL2 window (display) and keyboard, mouse and game controllers (input), for the desktop",
    .display_open = psc_sdl_display_open,
    .input_open = psc_sdl_input_open,
};
