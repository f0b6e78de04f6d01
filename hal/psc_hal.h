/* SPDX-License-Identifier: MIT */
/*
 * psc_hal.h - conventions shared by every part of Periscope's hardware
 * abstraction layer (HAL), and the backend registry.
 *
 * Shape (read this before porting):
 *  - Five device kinds, each in its own header: display (psc_hal_display.h),
 *    input (psc_hal_input.h), camera (psc_hal_camera.h), clock
 *    (psc_hal_clock.h) and watchdog (psc_hal_watchdog.h).
 *  - A device is a small struct whose first member is a pointer to a const
 *    table of callbacks (ops). A backend embeds that struct as the FIRST member
 *    of its own private state struct, so the callbacks get their state back
 *    with a cast. Const configuration (psc_hal_*_config_t) is kept apart from
 *    the backend's mutable state.
 *  - Every callback is marked mandatory or optional in its header. Callers
 *    never touch ops directly: they use the static inline wrappers, which
 *    return -ENOSYS for a missing optional callback.
 *  - A backend is a named set of open functions (psc_hal_backend_t). The board
 *    file names one per device kind ("display = sim"); psc_hal_*_open() finds
 *    it in the registry (psc_hal_registry.c) and calls it.
 *  - Lifetimes are symmetric: psc_hal_X_open() allocates everything the device
 *    will ever need (this is start-up), psc_hal_X_close() releases all of it
 *    and accepts NULL. No callback other than open allocates memory.
 *
 * Return values: 0 on success, or a negative errno value. The ones used:
 *   -EINVAL  a configuration value or argument is out of range
 *   -ENOSYS  an optional operation this backend does not provide
 *   -ENODEV  no such backend, or the hardware is not there
 *   -ENOMEM  start-up allocation failed
 *   -EIO     the device failed (the err text says how)
 *   -EAGAIN  nothing ready yet (camera dequeue)
 *   -EBUSY   the operation conflicts with the device's state (e.g. start twice)
 * open functions also fill err[errlen] with a sentence naming the device, the
 * backend and, for a bad board option, the board file and line it came from.
 *
 * Times are microseconds on the monotonic psc_hal_clock_t given to each device
 * (uint64_t, never wrapping in practice). Angles and pixels follow core's
 * conventions (psc_types.h); axis values are Q1.15 (psc_hal_input.h).
 */
#ifndef PSC_HAL_H
#define PSC_HAL_H

#include <errno.h>
#include <stddef.h>
#include <stdint.h>
#include <stdbool.h>
#include "base/psc_types.h"

/**
 * One backend-specific setting, taken from a board file line "display.NAME =
 * VALUE" (or made up by the firmware, e.g. from a command-line flag). origin
 * says where it came from ("boards/sim/board.conf:12" or "--tour") so that a
 * backend which rejects it can point the user at the right line. The strings
 * are owned by the caller and only read during open.
 */
typedef struct {
    const char *key;
    const char *value;
    const char *origin;
} psc_hal_option_t;

/** A list of backend-specific settings; items may be NULL when count is 0. */
typedef struct {
    const psc_hal_option_t *items;
    size_t count;
} psc_hal_options_t;

typedef struct psc_hal_display psc_hal_display_t;
typedef struct psc_hal_input psc_hal_input_t;
typedef struct psc_hal_camera psc_hal_camera_t;
typedef struct psc_hal_clock psc_hal_clock_t;
typedef struct psc_hal_watchdog psc_hal_watchdog_t;

struct psc_hal_display_config;
struct psc_hal_input_config;
struct psc_hal_camera_config;
struct psc_hal_clock_config;
struct psc_hal_watchdog_config;

/**
 * A backend: its name as written in board files and one open function per
 * device kind it drives. A NULL open function means the backend does not
 * drive that kind of device (opening it then fails with -ENODEV and a message
 * saying so). Each open function allocates its device, fills *out and returns
 * 0, or returns a negative errno with err filled and *out left NULL.
 */
typedef struct {
    const char *name;
    const char *description;
    int (*display_open)(const struct psc_hal_display_config *cfg, psc_hal_display_t **out,
                        char *err, size_t errlen);
    int (*input_open)(const struct psc_hal_input_config *cfg, psc_hal_input_t **out,
                      char *err, size_t errlen);
    int (*camera_open)(const struct psc_hal_camera_config *cfg, psc_hal_camera_t **out,
                       char *err, size_t errlen);
    int (*clock_open)(const struct psc_hal_clock_config *cfg, psc_hal_clock_t **out,
                      char *err, size_t errlen);
    int (*watchdog_open)(const struct psc_hal_watchdog_config *cfg, psc_hal_watchdog_t **out,
                         char *err, size_t errlen);
} psc_hal_backend_t;

/**
 * Find a backend compiled into this build by its board-file name (exact,
 * case-sensitive). Returns NULL when there is none; psc_hal_backend_list()
 * then gives the names to suggest in the error message.
 */
const psc_hal_backend_t *psc_hal_backend_find(const char *name);

/**
 * Write the names of every compiled-in backend, separated by ", ", into
 * buf[len] (always NUL-terminated, truncated if needed), so that an error
 * about an unknown backend can tell the user what would have worked.
 */
void psc_hal_backend_list(char *buf, size_t len);

/**
 * Format an error message into err[errlen] like snprintf (err may be NULL or
 * errlen 0, then nothing is written). Backends use it so that every message
 * is bounded and NUL-terminated however long the paths in it are.
 */
void psc_hal_error_set(char *err, size_t errlen, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/**
 * The option named key in opts, or NULL. When a key appears more than once
 * the last one wins, as later board lines override earlier ones.
 */
const psc_hal_option_t *psc_hal_options_find(const psc_hal_options_t *opts, const char *key);

/**
 * Check that every option in opts is one of the NULL-terminated known keys of
 * a backend. A typo in a board file then fails at start-up with the file and
 * line of the bad key, instead of being silently ignored. device and backend
 * name the device kind and backend in the message. 0 or -EINVAL.
 */
int psc_hal_options_check(const psc_hal_options_t *opts, const char *const *known,
                          const char *device, const char *backend, char *err, size_t errlen);

/**
 * Read option key as a decimal unsigned integer in [min, max]. Absent: *out =
 * def and 0. Present but not a number or out of range: -EINVAL with err naming
 * the option's origin and the accepted range.
 */
int psc_hal_options_get_u32(const psc_hal_options_t *opts, const char *key, uint32_t min,
                            uint32_t max, uint32_t def, uint32_t *out, char *err, size_t errlen);

#endif
