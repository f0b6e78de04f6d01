/* SPDX-License-Identifier: MIT */
/*
 * psc_gpio_lines.h - GPIO input lines found by NAME on whichever chip has
 * them, requested for both-edge events, read without blocking. The only
 * part of the GPIO backend that talks to libgpiod: one source for libgpiod
 * 1.6 (Debian 12; kernel uAPI v1, no kernel debounce) and 2.x (uAPI v2,
 * kernel debounce), picked at compile time by PSC_GPIOD_MAJOR (the Makefile
 * sets it from pkg-config; 0 = libgpiod absent, every open fails -ENOSYS).
 *
 * Chips are searched in number order (/dev/gpiochip0, 1, ...); the first
 * chip that has a line of the wanted name wins. Lines are requested as
 * inputs with edge detection on both edges, the given bias and active-low
 * setting, so events carry the logical level (pressed = 1 for a button to
 * ground with active_low). Edge timestamps are CLOCK_MONOTONIC nanoseconds.
 */
#ifndef PSC_GPIO_LINES_H
#define PSC_GPIO_LINES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define PSC_GPIO_MAX_LINES 16u     /* lines per input backend */
#define PSC_GPIO_MAX_CHIPS 32u     /* chips searched */

typedef enum {
    PSC_GPIO_BIAS_AS_IS = 0,
    PSC_GPIO_BIAS_DISABLED,
    PSC_GPIO_BIAS_PULL_UP,
    PSC_GPIO_BIAS_PULL_DOWN
} psc_gpio_bias_t;

/** How every line is requested. */
typedef struct {
    bool active_low;
    psc_gpio_bias_t bias;
    uint32_t debounce_us;          /* asked of the kernel where it can (v2); 0 = none */
    const char *consumer;          /* shown by gpioinfo as the lines' user */
    const char *dev_dir;           /* where gpiochipN nodes are; NULL = "/dev" */
} psc_gpio_settings_t;

/** One edge: line index (into the names given at open), new logical level, when. */
typedef struct {
    uint8_t line;
    bool level;
    uint64_t time_ns;
} psc_gpio_edge_t;

typedef struct psc_gpio_lines psc_gpio_lines_t;

/**
 * Find names[0..count) (count <= PSC_GPIO_MAX_LINES) across all chips and
 * request them. Returns 0 with *out set; -ENOENT when a name is on no chip
 * (err lists the missing names and the chips searched); -EBUSY when a line is
 * used by another program; -ENOSYS without libgpiod; other negative errno
 * values for other failures, always with err saying which line and chip.
 */
int psc_gpio_lines_open(const char *const *names, size_t count, const psc_gpio_settings_t *settings,
                        psc_gpio_lines_t **out, char *err, size_t errlen);

/** Release the lines and free everything (NULL is ignored). */
void psc_gpio_lines_close(psc_gpio_lines_t *lines);

/** True when the kernel debounces the lines (v2 with debounce_us > 0 accepted). */
bool psc_gpio_lines_kernel_debounce(const psc_gpio_lines_t *lines);

/** The logical level of line i now: 0 or 1, or a negative errno. */
int psc_gpio_lines_get(psc_gpio_lines_t *lines, size_t i);

/**
 * Read pending edges without blocking into out[0..max): returns how many
 * (0 when none), or -ENODEV when a chip went away (unplugged, gpio-sim chip
 * removed), or another negative errno.
 */
int psc_gpio_lines_read(psc_gpio_lines_t *lines, psc_gpio_edge_t *out, size_t max);

/** "gpiochip0 [pinctrl-bcm2711]" for the chips in use (NUL-terminated, truncated). */
void psc_gpio_lines_describe(const psc_gpio_lines_t *lines, char *buf, size_t len);

#endif
