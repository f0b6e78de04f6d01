/* SPDX-License-Identifier: MIT */
/*
 * evdev_input.c - the "evdev" input backend: the kernel's input devices
 * (/dev/input/event*) through libevdev: touch screens, keyboards, mice and
 * the gamepads the kernel drives, plugged and unplugged at any time.
 *
 * Finding devices. At open and whenever inotify reports an event* node in
 * the directory created, moved in or changed (IN_ATTRIB: udev sets a node's
 * group and mode after the kernel made it, so a node we could not open yet
 * may be openable now), the node is opened O_RDONLY | O_NONBLOCK and its
 * capabilities are read with plain ioctls (no allocation); evdev_caps.c
 * says what it is. A node of no wanted kind (a power button, a lid switch,
 * the PC speaker, a device the name pattern does not match) is closed and
 * remembered by its device number, so it is looked at once. A wanted one
 * gets a device slot and a libevdev handle (libevdev_new_from_fd allocates:
 * bounded by the PSC_HAL_INPUT_MAX_DEVICES slots) and DEVICE_ARRIVE. Every
 * rescan_ms the directory is also listed (getdents64 on a descriptor opened
 * once, no allocation) in case inotify missed something, or the directory
 * did not exist yet (devtmpfs makes /dev/input with the first device).
 *
 * Reading. Each poll reads every open device with libevdev_next_event until
 * it has nothing more (-EAGAIN), keeping room in the event queue for what
 * one SYN_REPORT can produce (the rest waits in the kernel's buffer).
 * SYN_DROPPED: libevdev's resync (LIBEVDEV_READ_FLAG_SYNC) brings the state
 * up to date (evdev_device.c). A read failing with ENODEV (unplugged) or any
 * other error, or the node's IN_DELETE, closes the device: DEVICE_LEAVE,
 * and the firmware releases what it held (no UP follows). Never blocks.
 * Events are stamped with the time of the poll that reads them (the
 * frame's), not the kernel's: what a frame sees is then a function of the
 * inputs that came before it, as with the sim's tours (the VM case compares
 * frames bit for bit), and long presses count in the input clock's time.
 *
 * Memory: the slot table, the queue and the buffers are allocated at open;
 * libevdev allocates when a device is plugged in (libevdev_new_from_fd),
 * bounded by the slots, and frees at unplug; poll itself allocates nothing.
 *
 * Options: see psc_evdev_known below and boards/README.md (Input, evdev).
 * Keys may be given as "KEY" or "evdev.KEY" (input = evdev alone passes
 * input.evdev.KEY on as evdev.KEY); errors name them input.evdev.KEY.
 */
#define _GNU_SOURCE   /* getdents64 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <fnmatch.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/inotify.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <libevdev/libevdev.h>

#include "evdev_internal.h"
#include "psc_hal_backends.h"
#include "psc_hal_clock.h"
#include "psc_io_log.h"

#define EVDEV_QUEUE_LEN 256u
#define EVDEV_IGNORED_MAX 48u            /* nodes looked at and not used, remembered */
#define EVDEV_NODE_MAX 32u
#define EVDEV_DEFAULT_RESCAN_MS 1000u

typedef struct {
    bool used;
    int fd;
    struct libevdev *dev;
    bool syncing;                         /* reading libevdev's resync after SYN_DROPPED */
    char node[EVDEV_NODE_MAX];            /* "event3" */
    dev_t rdev;
    psc_evdev_caps_t caps;
    psc_evdev_dev_t tr;
} evdev_slot_t;

typedef struct {
    char node[EVDEV_NODE_MAX];
    dev_t rdev;
} evdev_ignored_t;

typedef struct {
    psc_hal_input_t base;                 /* first: the HAL hands this pointer back */
    psc_hal_clock_t *clock;
    psc_evdev_map_t map;
    psc_evdev_shared_t shared;
    unsigned kinds;
    char pattern[128];
    char dir[256];
    bool grab;
    int dir_fd, inotify_fd, watch;
    uint64_t rescan_us, next_scan_us, now_us;
    evdev_slot_t slots[PSC_HAL_INPUT_MAX_DEVICES];
    evdev_ignored_t ignored[EVDEV_IGNORED_MAX];
    unsigned ignored_count;
    bool full_reported;
    psc_hal_input_event_t queue_store[EVDEV_QUEUE_LEN];
    psc_hal_event_queue_t queue;
    char inotify_buf[4096] __attribute__((aligned(__alignof__(struct inotify_event))));
    char dirent_buf[4096];
} evdev_input_t;

static void evdev_log(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* What the firmware's log does not show: why a device was not used. */
static void evdev_log(const char *fmt, ...)
{
    char line[PSC_LOG_LINE_MAX];
    va_list ap;

    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    psc_io_log(PSC_LOG_NOTICE, "periscope: evdev input: %s", line);
}

static void evdev_push_device(evdev_input_t *s, uint8_t slot, psc_hal_input_type_t type)
{
    psc_hal_input_event_t ev = { .type = type, .device = slot, .time_us = s->now_us };

    (void)psc_hal_event_queue_push(&s->queue, &ev);
}

static void evdev_slot_close(evdev_input_t *s, evdev_slot_t *sl, bool announce)
{
    if (!sl->used)
        return;
    if (sl->dev != NULL)
        libevdev_free(sl->dev);   /* a grab ends with the descriptor */
    if (sl->fd >= 0)
        close(sl->fd);
    sl->dev = NULL;
    sl->fd = -1;
    sl->used = false;
    sl->syncing = false;
    if (announce)
        evdev_push_device(s, (uint8_t)(sl - s->slots), PSC_HAL_INPUT_DEVICE_LEAVE);
    s->full_reported = false;
}

/* ---- capabilities by ioctl (no allocation) ------------------------------------------------ */

static int evdev_read_caps(int fd, psc_evdev_caps_t *c)
{
    memset(c, 0, sizeof *c);
    if (ioctl(fd, EVIOCGBIT(0, sizeof c->ev), c->ev) < 0)
        return -errno;
    if (ioctl(fd, EVIOCGNAME(sizeof c->name - 1), c->name) < 0)
        snprintf(c->name, sizeof c->name, "unnamed input device");
    struct input_id id;
    if (ioctl(fd, EVIOCGID, &id) == 0)
        c->bustype = id.bustype;
    (void)ioctl(fd, EVIOCGBIT(EV_KEY, sizeof c->key), c->key);
    (void)ioctl(fd, EVIOCGBIT(EV_REL, sizeof c->rel), c->rel);
    (void)ioctl(fd, EVIOCGBIT(EV_ABS, sizeof c->abs), c->abs);
    (void)ioctl(fd, EVIOCGPROP(sizeof c->prop), c->prop);
    for (unsigned code = 0; code < ABS_CNT; code++) {
        struct input_absinfo ai;
        if (!psc_evdev_bit(c->abs, code))
            continue;
        if (ioctl(fd, EVIOCGABS(code), &ai) == 0) {
            c->abs_min[code] = ai.minimum;
            c->abs_max[code] = ai.maximum;
        }
    }
    return 0;
}

/* ---- finding devices ---------------------------------------------------------------------- */

static bool evdev_is_node_name(const char *name)
{
    return strncmp(name, "event", 5) == 0 && name[5] >= '0' && name[5] <= '9' && strlen(name) < EVDEV_NODE_MAX;
}

static evdev_ignored_t *evdev_ignored_find(evdev_input_t *s, const char *node)
{
    for (unsigned i = 0; i < s->ignored_count; i++)
        if (strcmp(s->ignored[i].node, node) == 0)
            return &s->ignored[i];
    return NULL;
}

static void evdev_ignored_forget(evdev_input_t *s, const char *node)
{
    evdev_ignored_t *g = evdev_ignored_find(s, node);

    if (g != NULL)
        *g = s->ignored[--s->ignored_count];
}

static void evdev_ignore(evdev_input_t *s, const char *node, dev_t rdev)
{
    evdev_ignored_t *g = evdev_ignored_find(s, node);

    if (g == NULL) {
        if (s->ignored_count == EVDEV_IGNORED_MAX)
            return;   /* more nodes than remembered: the rest are looked at again by each rescan */
        g = &s->ignored[s->ignored_count++];
    }
    snprintf(g->node, sizeof g->node, "%s", node);
    g->rdev = rdev;
}

static evdev_slot_t *evdev_slot_of_node(evdev_input_t *s, const char *node)
{
    for (unsigned i = 0; i < PSC_HAL_INPUT_MAX_DEVICES; i++)
        if (s->slots[i].used && strcmp(s->slots[i].node, node) == 0)
            return &s->slots[i];
    return NULL;
}

/* Open the device of one event node if it is one we want. */
static void evdev_probe(evdev_input_t *s, const char *node)
{
    evdev_slot_t *sl = evdev_slot_of_node(s, node), *free_slot = NULL;
    evdev_ignored_t *g;
    psc_evdev_caps_t *caps;
    struct stat st;
    unsigned kinds;
    char what[64];
    int fd, rc;

    if (s->dir_fd < 0 || fstatat(s->dir_fd, node, &st, 0) != 0 || !S_ISCHR(st.st_mode))
        return;
    if (sl != NULL) {
        if (sl->rdev == st.st_rdev)
            return;   /* already ours */
        evdev_slot_close(s, sl, true);   /* the node now is another device: the old one left */
    }
    g = evdev_ignored_find(s, node);
    if (g != NULL && g->rdev == st.st_rdev)
        return;
    for (unsigned i = 0; i < PSC_HAL_INPUT_MAX_DEVICES && free_slot == NULL; i++)
        if (!s->slots[i].used)
            free_slot = &s->slots[i];
    fd = openat(s->dir_fd, node, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        /* EACCES until udev has given the node its group: IN_ATTRIB brings us back */
        if (g == NULL)
            evdev_log("%s/%s: cannot open it (%s)%s", s->dir, node, strerror(errno),
                      errno == EACCES ? "; the kiosk user needs read access to the input devices "
                                        "(boards/README.md, evdev)" : "");
        evdev_ignore(s, node, st.st_rdev);
        return;
    }
    caps = free_slot != NULL ? &free_slot->caps : NULL;
    if (caps == NULL) {
        if (!s->full_reported)
            evdev_log("%s/%s: every one of the %u device slots is in use; it waits for one", s->dir, node,
                      (unsigned)PSC_HAL_INPUT_MAX_DEVICES);
        s->full_reported = true;
        close(fd);
        return;
    }
    if ((rc = evdev_read_caps(fd, caps)) != 0) {
        evdev_log("%s/%s: not an input device (%s)", s->dir, node, strerror(-rc));
        close(fd);
        evdev_ignore(s, node, st.st_rdev);
        return;
    }
    kinds = psc_evdev_classify(caps, &s->map);
    if ((kinds & s->kinds) == 0 || (s->pattern[0] != '\0' && fnmatch(s->pattern, caps->name, 0) != 0)) {
        psc_evdev_describe_kinds(kinds, what, sizeof what);
        evdev_log("%s/%s (%s): not used: %s", s->dir, node, caps->name,
                  kinds == 0 ? "not a touch screen, keyboard, mouse or gamepad"
                  : (kinds & s->kinds) == 0 ? "a kind of device the board does not take (input.evdev.devices)"
                                            : "its name does not match input.evdev.name");
        close(fd);
        evdev_ignore(s, node, st.st_rdev);
        return;
    }
    rc = libevdev_new_from_fd(fd, &free_slot->dev);
    if (rc < 0) {
        evdev_log("%s/%s (%s): libevdev cannot read it (%s)", s->dir, node, caps->name, strerror(-rc));
        free_slot->dev = NULL;
        close(fd);
        evdev_ignore(s, node, st.st_rdev);
        return;
    }
    if (s->grab && (rc = libevdev_grab(free_slot->dev, LIBEVDEV_GRAB)) < 0)
        evdev_log("%s/%s (%s): cannot grab it (%s); the console sees its events too", s->dir, node, caps->name,
                  strerror(-rc));
    evdev_ignored_forget(s, node);
    free_slot->used = true;
    free_slot->fd = fd;
    free_slot->rdev = st.st_rdev;
    free_slot->syncing = false;
    snprintf(free_slot->node, sizeof free_slot->node, "%s", node);
    psc_evdev_dev_init(&free_slot->tr, &s->shared, caps, psc_evdev_taken_kinds(kinds, s->kinds),
                       (uint8_t)(free_slot - s->slots), s->now_us);
    evdev_push_device(s, (uint8_t)(free_slot - s->slots), PSC_HAL_INPUT_DEVICE_ARRIVE);
}

/* The directory: open it and watch it, once it exists. */
static void evdev_watch_dir(evdev_input_t *s)
{
    if (s->dir_fd < 0)
        s->dir_fd = open(s->dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (s->dir_fd >= 0 && s->inotify_fd >= 0 && s->watch < 0)
        s->watch = inotify_add_watch(s->inotify_fd, s->dir, IN_CREATE | IN_ATTRIB | IN_DELETE | IN_MOVED_TO |
                                                               IN_MOVED_FROM | IN_DELETE_SELF | IN_ONLYDIR);
}

/* List the directory: probe new nodes; devices whose node is gone left. */
static void evdev_scan(evdev_input_t *s)
{
    bool seen[PSC_HAL_INPUT_MAX_DEVICES] = { false };
    ssize_t n;

    evdev_watch_dir(s);
    if (s->dir_fd < 0)
        return;
    if (lseek(s->dir_fd, 0, SEEK_SET) < 0)
        return;
    while ((n = getdents64(s->dir_fd, s->dirent_buf, sizeof s->dirent_buf)) > 0) {
        for (ssize_t off = 0; off < n;) {
            const struct dirent64 *d = (const struct dirent64 *)(const void *)(s->dirent_buf + off);
            evdev_slot_t *sl;

            off += d->d_reclen;
            if (!evdev_is_node_name(d->d_name))
                continue;
            evdev_probe(s, d->d_name);
            if ((sl = evdev_slot_of_node(s, d->d_name)) != NULL)
                seen[sl - s->slots] = true;
        }
    }
    if (n < 0)
        return;   /* the listing failed: say nothing about what is gone */
    for (unsigned i = 0; i < PSC_HAL_INPUT_MAX_DEVICES; i++)
        if (s->slots[i].used && !seen[i])
            evdev_slot_close(s, &s->slots[i], true);
}

static void evdev_read_inotify(evdev_input_t *s)
{
    ssize_t n;

    if (s->inotify_fd < 0)
        return;
    while ((n = read(s->inotify_fd, s->inotify_buf, sizeof s->inotify_buf)) > 0) {
        for (ssize_t off = 0; off < n;) {
            const struct inotify_event *e = (const struct inotify_event *)(const void *)(s->inotify_buf + off);

            off += (ssize_t)(sizeof *e + e->len);
            if (e->mask & (IN_IGNORED | IN_DELETE_SELF | IN_Q_OVERFLOW)) {
                if (e->mask & (IN_IGNORED | IN_DELETE_SELF)) {   /* the directory went: look for it again */
                    s->watch = -1;
                    if (s->dir_fd >= 0)
                        close(s->dir_fd);
                    s->dir_fd = -1;
                }
                s->next_scan_us = s->now_us;   /* something was missed: list the directory */
                continue;
            }
            if (e->len == 0 || !evdev_is_node_name(e->name))
                continue;
            if (e->mask & (IN_DELETE | IN_MOVED_FROM)) {
                evdev_slot_t *sl = evdev_slot_of_node(s, e->name);
                if (sl != NULL)
                    evdev_slot_close(s, sl, true);
                evdev_ignored_forget(s, e->name);
            } else {
                evdev_ignored_forget(s, e->name);   /* a new node, or new permissions: look again */
                evdev_probe(s, e->name);
            }
        }
    }
}

/* ---- reading ------------------------------------------------------------------------------ */

static void evdev_read_device(evdev_input_t *s, evdev_slot_t *sl)
{
    while (s->queue.count + PSC_EVDEV_EVENTS_PER_REPORT <= s->queue.capacity) {
        struct input_event ev;
        int rc = libevdev_next_event(sl->dev, sl->syncing ? LIBEVDEV_READ_FLAG_SYNC : LIBEVDEV_READ_FLAG_NORMAL,
                                     &ev);

        if (rc == LIBEVDEV_READ_STATUS_SUCCESS || rc == LIBEVDEV_READ_STATUS_SYNC) {
            /* SYNC: first the SYN_DROPPED, then (with FLAG_SYNC) the resync's events */
            if (rc == LIBEVDEV_READ_STATUS_SYNC)
                sl->syncing = true;
            psc_evdev_dev_feed(&sl->tr, &ev, s->now_us, &s->queue);
        } else if (rc == -EAGAIN) {
            if (!sl->syncing)
                return;
            sl->syncing = false;   /* the resync is done: back to the kernel's events */
        } else {
            if (rc != -ENODEV)
                evdev_log("%s (%s/%s): reading failed (%s); closing it", sl->caps.name, s->dir, sl->node,
                          strerror(-rc));
            evdev_slot_close(s, sl, true);
            return;
        }
    }
}

static int evdev_poll(psc_hal_input_t *in, uint64_t now_us, psc_hal_input_event_t *ev)
{
    evdev_input_t *s = (evdev_input_t *)in;

    s->now_us = now_us;
    evdev_read_inotify(s);
    if (now_us >= s->next_scan_us) {
        evdev_scan(s);
        s->next_scan_us = now_us + (s->rescan_us != 0 ? s->rescan_us
                                    : s->dir_fd < 0 ? EVDEV_DEFAULT_RESCAN_MS * 1000u : UINT64_MAX - now_us);
    }
    for (unsigned i = 0; i < PSC_HAL_INPUT_MAX_DEVICES; i++) {
        evdev_slot_t *sl = &s->slots[i];
        if (!sl->used)
            continue;
        evdev_read_device(s, sl);
        if (sl->used)
            psc_evdev_dev_tick(&sl->tr, now_us, &s->queue);
    }
    return psc_hal_event_queue_pop(&s->queue, now_us, ev);
}

static int evdev_get_device_name(psc_hal_input_t *in, uint8_t device, char *buf, size_t len)
{
    evdev_input_t *s = (evdev_input_t *)in;

    if (device >= PSC_HAL_INPUT_MAX_DEVICES || !s->slots[device].used)
        return -ENODEV;
    snprintf(buf, len, "%s", s->slots[device].caps.name);
    return 0;
}

static void evdev_close(psc_hal_input_t *in)
{
    evdev_input_t *s = (evdev_input_t *)in;

    for (unsigned i = 0; i < PSC_HAL_INPUT_MAX_DEVICES; i++)
        evdev_slot_close(s, &s->slots[i], false);
    if (s->inotify_fd >= 0)
        close(s->inotify_fd);
    if (s->dir_fd >= 0)
        close(s->dir_fd);
    free(s);
}

static const psc_hal_input_ops_t evdev_input_ops = {
    .poll = evdev_poll,
    .get_device_name = evdev_get_device_name,
    .close = evdev_close,
};

/* ---- options ------------------------------------------------------------------------------ */

static const char *evdev_origin(const psc_hal_option_t *o)
{
    return o->origin != NULL ? o->origin : "(built-in)";
}

/* The key as this backend reads it: "evdev.grab" and "grab" are both "grab". */
static const char *evdev_key(const psc_hal_option_t *o)
{
    const char *k = o->key != NULL ? o->key : "";

    return strncmp(k, "evdev.", 6) == 0 ? k + 6 : k;
}

static int evdev_bool(const psc_hal_option_t *o, bool *out, char *err, size_t errlen)
{
    static const char *const yes[] = { "yes", "true", "on", "1" }, *const no[] = { "no", "false", "off", "0" };
    const char *v = o->value != NULL ? o->value : "";

    for (unsigned i = 0; i < 4; i++) {
        if (strcmp(v, yes[i]) == 0 || strcmp(v, no[i]) == 0) {
            *out = strcmp(v, yes[i]) == 0;
            return 0;
        }
    }
    psc_hal_error_set(err, errlen, "%s: input.evdev.%s must be yes or no, got '%s'", evdev_origin(o), evdev_key(o), v);
    return -EINVAL;
}

static int evdev_setting(evdev_input_t *s, const psc_hal_option_t *o, bool *quit_keys, char *err, size_t errlen)
{
    const char *k = evdev_key(o), *v = o->value != NULL ? o->value : "";
    char board_key[96];

    snprintf(board_key, sizeof board_key, "input.evdev.%s", k);
    if (strcmp(k, "devices") == 0)
        return psc_evdev_parse_kinds(v, &s->kinds, evdev_origin(o), board_key, err, errlen);
    if (strcmp(k, "grab") == 0)
        return evdev_bool(o, &s->grab, err, errlen);
    if (strcmp(k, "quit_keys") == 0)
        return evdev_bool(o, quit_keys, err, errlen);
    if (strcmp(k, "name") == 0 || strcmp(k, "dir") == 0) {
        char *dst = k[0] == 'n' ? s->pattern : s->dir;
        size_t cap = k[0] == 'n' ? sizeof s->pattern : sizeof s->dir;
        if (v[0] == '\0' || strlen(v) >= cap) {
            psc_hal_error_set(err, errlen, "%s: %s must be 1 to %u characters", evdev_origin(o), board_key,
                              (unsigned)cap - 1u);
            return -EINVAL;
        }
        snprintf(dst, cap, "%s", v);
        return 0;
    }
    if (strcmp(k, "rescan_ms") == 0) {
        char *end;
        unsigned long ms = strtoul(v, &end, 10);
        if (v[0] < '0' || v[0] > '9' || *end != '\0' || (ms != 0 && (ms < 50 || ms > 60000))) {
            psc_hal_error_set(err, errlen, "%s: %s must be 0 (only inotify) or 50 to 60000, got '%s'",
                              evdev_origin(o), board_key, v);
            return -EINVAL;
        }
        s->rescan_us = (uint64_t)ms * 1000u;
        return 0;
    }
    if (strncmp(k, "key.", 4) == 0)
        return 0;   /* after quit_keys, which sets up the map they change */
    psc_hal_error_set(err, errlen, "%s: %s is not known to the evdev input backend (it knows: devices, name, dir, "
                      "grab, quit_keys, key.NAME, rescan_ms)", evdev_origin(o), board_key);
    return -EINVAL;
}

static int evdev_parse_options(evdev_input_t *s, const psc_hal_options_t *opts, char *err, size_t errlen)
{
    bool quit_keys = false;
    int rc;

    for (size_t i = 0; opts->items != NULL && i < opts->count; i++)
        if ((rc = evdev_setting(s, &opts->items[i], &quit_keys, err, errlen)) != 0)
            return rc;
    psc_evdev_map_default(&s->map, quit_keys);
    for (size_t i = 0; opts->items != NULL && i < opts->count; i++) {
        const psc_hal_option_t *o = &opts->items[i];
        const char *k = evdev_key(o);
        char board_key[96];

        if (strncmp(k, "key.", 4) != 0)
            continue;
        snprintf(board_key, sizeof board_key, "input.evdev.%s", k);
        rc = psc_evdev_map_set(&s->map, k + 4, o->value != NULL ? o->value : "", evdev_origin(o), board_key, err,
                               errlen);
        if (rc != 0)
            return rc;
    }
    return 0;
}

static int evdev_input_open(const psc_hal_input_config_t *cfg, psc_hal_input_t **out, char *err, size_t errlen)
{
    evdev_input_t *s;
    int rc;

    *out = NULL;
    s = calloc(1, sizeof *s);
    if (s == NULL) {
        psc_hal_error_set(err, errlen, "evdev input: out of memory");
        return -ENOMEM;
    }
    s->base.ops = &evdev_input_ops;
    s->base.backend = "evdev";
    s->clock = cfg->clock;
    s->dir_fd = s->inotify_fd = s->watch = -1;
    for (unsigned i = 0; i < PSC_HAL_INPUT_MAX_DEVICES; i++)
        s->slots[i].fd = -1;
    s->kinds = PSC_EVDEV_ALL_KINDS;
    s->rescan_us = EVDEV_DEFAULT_RESCAN_MS * 1000u;
    snprintf(s->dir, sizeof s->dir, "/dev/input");
    psc_hal_event_queue_init(&s->queue, s->queue_store, EVDEV_QUEUE_LEN);
    rc = evdev_parse_options(s, &cfg->options, err, errlen);
    if (rc != 0) {
        evdev_close(&s->base);
        return rc;
    }
    s->shared = (psc_evdev_shared_t){
        .map = &s->map,
        .timing = { 0, (cfg->long_press_ms ? cfg->long_press_ms : 800u) * 1000u },
        .display_width = cfg->display_width,
        .display_height = cfg->display_height,
    };
    s->inotify_fd = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (s->inotify_fd < 0)
        evdev_log("no inotify (%s): new devices are found by the rescan only", strerror(errno));
    /* the devices there now arrive at open; a missing directory is looked for again at every rescan */
    s->now_us = cfg->clock != NULL ? psc_hal_clock_now_us(cfg->clock) : 0;
    evdev_scan(s);
    if (s->dir_fd < 0)
        evdev_log("%s: %s; looking for it every %u ms", s->dir, strerror(errno),
                  (unsigned)(s->rescan_us != 0 ? s->rescan_us / 1000u : EVDEV_DEFAULT_RESCAN_MS));
    s->next_scan_us = s->now_us + (s->rescan_us != 0 ? s->rescan_us : EVDEV_DEFAULT_RESCAN_MS * 1000u);
    *out = &s->base;
    return 0;
}

const psc_hal_backend_t psc_hal_evdev_backend = {
    .name = "evdev",
    .description = "the kernel's input devices through libevdev: touch screens, keyboards, mice, gamepads; hotplug",
    .input_open = evdev_input_open,
};
