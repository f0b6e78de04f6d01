/* SPDX-License-Identifier: MIT */
/*
 * psc_hal_backends.h - every backend this tree can build, as one const
 * descriptor each. A porter adding a backend declares it here and lists it in
 * psc_hal_registry.c; nothing else in the firmware changes, because the board
 * file picks backends by name.
 */
#ifndef PSC_HAL_BACKENDS_H
#define PSC_HAL_BACKENDS_H

#include "psc_hal.h"

/** The simulated board: memory display with PNG capture, tour-script input,
 *  deterministic clock, test-pattern camera, recording watchdog (hal/sim/). */
extern const psc_hal_backend_t psc_hal_sim_backend;

/** The skeleton a porter copies (psc_hal_template.c). Every open fails with
 *  -ENODEV, so it is built and type-checked but never registered. */
extern const psc_hal_backend_t psc_hal_template_backend;

/** CLOCK_MONOTONIC clock with absolute-time sleeps (hal/linux/). */
extern const psc_hal_backend_t psc_hal_linux_backend;

/** systemd service watchdog over sd_notify, no libsystemd (hal/linux/). */
extern const psc_hal_backend_t psc_hal_systemd_backend;

/** V4L2 capture camera, YUYV or MJPEG, frames as the live map (hal/v4l2/). */
extern const psc_hal_backend_t psc_hal_v4l2_backend;

/** USB joysticks and gamepads through libusb-1.0, read by their HID report
 *  descriptors, with hotplug (hal/usb/). */
extern const psc_hal_backend_t psc_hal_usb_backend;

/** Linux framebuffer display, pan-display double buffering (hal/fbdev/). */
extern const psc_hal_backend_t psc_hal_fbdev_backend;

/** DRM/KMS display: dumb buffers, page flips on vblank (hal/drm/). */
extern const psc_hal_backend_t psc_hal_drm_backend;

/** Push buttons on GPIO lines found by name, libgpiod 1.6 or 2.x (hal/gpio/). */
extern const psc_hal_backend_t psc_hal_gpio_backend;

/** The kernel's input devices through libevdev: touch screens (multitouch), keyboards, mice and
 *  gamepads, hot-plugged by inotify (hal/evdev/). */
extern const psc_hal_backend_t psc_hal_evdev_backend;

/** SDL2 window display and keyboard/mouse/game-controller input, for the desktop (hal/sdl/). */
extern const psc_hal_backend_t psc_hal_sdl_backend;

#endif
