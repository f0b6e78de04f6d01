/* SPDX-License-Identifier: MIT */
/*
 * psc_gpio_lines.c - named GPIO input lines through libgpiod 1.6 or 2.x
 * (psc_gpio_lines.h). The chip search and the bookkeeping are shared; the
 * three places where the two APIs differ (find a line, request, read
 * events) are each one #if block, so both versions stay side by side.
 *
 *   libgpiod 1.6: gpiod_chip_find_line, gpiod_line_request_bulk_both_edges_
 *                 events_flags (one event fd per line), gpiod_line_event_
 *                 read_multiple; uAPI v1 has no debounce: the backend
 *                 debounces in software.
 *   libgpiod 2.x: gpiod_chip_get_line_offset_from_name, one
 *                 gpiod_line_request per chip with debounce in its line
 *                 settings, gpiod_line_request_read_edge_events.
 */
#include <dirent.h>
#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "psc_gpio_lines.h"

#ifndef PSC_GPIOD_MAJOR
#define PSC_GPIOD_MAJOR 0
#endif

#if PSC_GPIOD_MAJOR >= 1
#include <gpiod.h>
#endif

#define GPIO_EVENTS_PER_READ 16u

typedef struct {
    char path[96];
    char label[64];                   /* "gpiochip0 [pinctrl-bcm2711]" */
#if PSC_GPIOD_MAJOR == 1
    struct gpiod_chip *chip;
    struct gpiod_line_bulk bulk;
#elif PSC_GPIOD_MAJOR >= 2
    struct gpiod_chip *chip;
    struct gpiod_line_request *request;
    struct gpiod_edge_event_buffer *events;
#endif
} gpio_chip_t;

typedef struct {
    uint8_t chip;                     /* index into chips */
    unsigned offset;
#if PSC_GPIOD_MAJOR == 1
    struct gpiod_line *line;
#endif
} gpio_line_t;

struct psc_gpio_lines {
    size_t count;
    unsigned chip_count;
    gpio_chip_t chips[PSC_GPIO_MAX_LINES];   /* at most one chip per line */
    gpio_line_t lines[PSC_GPIO_MAX_LINES];
    bool kernel_debounce;
};

/* ---- the chips, in number order ------------------------------------------ */

static int gpio_cmp_unsigned(const void *a, const void *b)
{
    unsigned x = *(const unsigned *)a, y = *(const unsigned *)b;
    return x < y ? -1 : x > y;
}

/* The N of every dir/gpiochipN, sorted; how many (at most max). */
static size_t gpio_list_chips(const char *dir, unsigned *numbers, size_t max)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    size_t n = 0;

    if (d == NULL)
        return 0;
    while ((e = readdir(d)) != NULL && n < max) {
        unsigned v = 0;
        const char *p = e->d_name;
        if (strncmp(p, "gpiochip", 8) != 0 || p[8] == '\0')
            continue;
        for (p += 8; *p >= '0' && *p <= '9' && v < 100000u; p++)
            v = v * 10u + (unsigned)(*p - '0');
        if (*p == '\0')
            numbers[n++] = v;
    }
    closedir(d);
    qsort(numbers, n, sizeof numbers[0], gpio_cmp_unsigned);
    return n;
}

#if PSC_GPIOD_MAJOR >= 1

/* ---- version-specific: open a chip, find a line, name the chip ----------- */

/* Open a chip; label keeps what the caller put there unless the chip names itself. */
static struct gpiod_chip *gpio_chip_open(const char *path, char *label, size_t len)
{
    struct gpiod_chip *chip = gpiod_chip_open(path);

    if (chip == NULL)
        return NULL;
#if PSC_GPIOD_MAJOR == 1
    snprintf(label, len, "%s [%s]", gpiod_chip_name(chip), gpiod_chip_label(chip));
#else
    struct gpiod_chip_info *info = gpiod_chip_get_info(chip);
    if (info != NULL) {
        snprintf(label, len, "%s [%s]", gpiod_chip_info_get_name(info), gpiod_chip_info_get_label(info));
        gpiod_chip_info_free(info);
    }
#endif
    return chip;
}

/* The offset of line name on chip, or -1. */
static int gpio_find(struct gpiod_chip *chip, const char *name, gpio_line_t *line)
{
#if PSC_GPIOD_MAJOR == 1
    struct gpiod_line *l = gpiod_chip_find_line(chip, name);

    if (l == NULL)
        return -1;
    line->line = l;
    line->offset = gpiod_line_offset(l);
    return (int)line->offset;
#else
    int off = gpiod_chip_get_line_offset_from_name(chip, name);

    if (off >= 0)
        line->offset = (unsigned)off;
    return off;
#endif
}

/* ---- version-specific: request a chip's lines ------------------------------- */

#if PSC_GPIOD_MAJOR == 1
static int gpio_request_chip(psc_gpio_lines_t *gl, unsigned c, const psc_gpio_settings_t *st)
{
    gpio_chip_t *chip = &gl->chips[c];
    int flags = st->active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;

    switch (st->bias) {
    case PSC_GPIO_BIAS_DISABLED: flags |= GPIOD_LINE_REQUEST_FLAG_BIAS_DISABLE; break;
    case PSC_GPIO_BIAS_PULL_UP: flags |= GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP; break;
    case PSC_GPIO_BIAS_PULL_DOWN: flags |= GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN; break;
    case PSC_GPIO_BIAS_AS_IS: break;
    }
    gpiod_line_bulk_init(&chip->bulk);
    for (size_t i = 0; i < gl->count; i++)
        if (gl->lines[i].chip == c)
            gpiod_line_bulk_add(&chip->bulk, gl->lines[i].line);
    if (gpiod_line_request_bulk_both_edges_events_flags(&chip->bulk, st->consumer, flags) != 0)
        return -errno;
    return 0;
}
#else
static struct gpiod_line_request *gpio_request_v2(struct gpiod_chip *chip, const unsigned *offsets, size_t n,
                                                  const psc_gpio_settings_t *st, uint32_t debounce_us)
{
    struct gpiod_line_settings *ls = gpiod_line_settings_new();
    struct gpiod_line_config *lc = gpiod_line_config_new();
    struct gpiod_request_config *rc = gpiod_request_config_new();
    struct gpiod_line_request *req = NULL;
    enum gpiod_line_bias bias = GPIOD_LINE_BIAS_AS_IS;
    int saved;

    switch (st->bias) {
    case PSC_GPIO_BIAS_DISABLED: bias = GPIOD_LINE_BIAS_DISABLED; break;
    case PSC_GPIO_BIAS_PULL_UP: bias = GPIOD_LINE_BIAS_PULL_UP; break;
    case PSC_GPIO_BIAS_PULL_DOWN: bias = GPIOD_LINE_BIAS_PULL_DOWN; break;
    case PSC_GPIO_BIAS_AS_IS: break;
    }
    if (ls != NULL && lc != NULL && rc != NULL &&
        gpiod_line_settings_set_direction(ls, GPIOD_LINE_DIRECTION_INPUT) == 0 &&
        gpiod_line_settings_set_edge_detection(ls, GPIOD_LINE_EDGE_BOTH) == 0 &&
        gpiod_line_settings_set_bias(ls, bias) == 0) {
        gpiod_line_settings_set_active_low(ls, st->active_low);
        gpiod_line_settings_set_debounce_period_us(ls, debounce_us);
        gpiod_request_config_set_consumer(rc, st->consumer);
        if (gpiod_line_config_add_line_settings(lc, offsets, n, ls) == 0)
            req = gpiod_chip_request_lines(chip, rc, lc);
    } else {
        errno = ENOMEM;
    }
    saved = errno;
    gpiod_line_settings_free(ls);
    gpiod_line_config_free(lc);
    gpiod_request_config_free(rc);
    errno = saved;
    return req;
}

static int gpio_request_chip(psc_gpio_lines_t *gl, unsigned c, const psc_gpio_settings_t *st)
{
    gpio_chip_t *chip = &gl->chips[c];
    unsigned offsets[PSC_GPIO_MAX_LINES];
    size_t n = 0;

    for (size_t i = 0; i < gl->count; i++)
        if (gl->lines[i].chip == c)
            offsets[n++] = gl->lines[i].offset;
    chip->request = gpio_request_v2(chip->chip, offsets, n, st, st->debounce_us);
    if (chip->request == NULL && st->debounce_us != 0 && errno == EINVAL) {
        /* a kernel or chip without debounce: fall back to software debounce */
        chip->request = gpio_request_v2(chip->chip, offsets, n, st, 0);
        gl->kernel_debounce = false;
    }
    if (chip->request == NULL)
        return -errno;
    chip->events = gpiod_edge_event_buffer_new(GPIO_EVENTS_PER_READ);
    return chip->events != NULL ? 0 : -ENOMEM;
}
#endif

static void gpio_release_chip(gpio_chip_t *chip)
{
#if PSC_GPIOD_MAJOR == 1
    if (chip->bulk.num_lines > 0)
        gpiod_line_release_bulk(&chip->bulk);
#else
    if (chip->events != NULL)
        gpiod_edge_event_buffer_free(chip->events);
    if (chip->request != NULL)
        gpiod_line_request_release(chip->request);
#endif
    if (chip->chip != NULL)
        gpiod_chip_close(chip->chip);
}

/* ---- open / close ------------------------------------------------------------ */

void psc_gpio_lines_close(psc_gpio_lines_t *gl)
{
    if (gl == NULL)
        return;
    for (unsigned c = 0; c < gl->chip_count; c++)
        gpio_release_chip(&gl->chips[c]);
    free(gl);
}

int psc_gpio_lines_open(const char *const *names, size_t count, const psc_gpio_settings_t *st,
                        psc_gpio_lines_t **out, char *err, size_t errlen)
{
    const char *dir = st->dev_dir != NULL ? st->dev_dir : "/dev";
    unsigned numbers[PSC_GPIO_MAX_CHIPS];
    size_t nchips = gpio_list_chips(dir, numbers, PSC_GPIO_MAX_CHIPS), found = 0, used;
    bool have[PSC_GPIO_MAX_LINES] = { false };
    char searched[256] = "";
    psc_gpio_lines_t *gl;
    int rc = 0;

    *out = NULL;
    if (count == 0 || count > PSC_GPIO_MAX_LINES) {
        snprintf(err, errlen, "%zu lines asked for, 1 to %u possible", count, (unsigned)PSC_GPIO_MAX_LINES);
        return -EINVAL;
    }
    gl = calloc(1, sizeof *gl);
    if (gl == NULL) {
        snprintf(err, errlen, "out of memory");
        return -ENOMEM;
    }
    gl->count = count;
    gl->kernel_debounce = PSC_GPIOD_MAJOR >= 2 && st->debounce_us != 0;
    used = 0;
    for (size_t k = 0; k < nchips && found < count; k++) {
        char path[96], label[64];
        struct gpiod_chip *chip;
        bool mine = false;
        unsigned c = gl->chip_count;

        snprintf(path, sizeof path, "%s/gpiochip%u", dir, numbers[k]);
        snprintf(label, sizeof label, "gpiochip%u", numbers[k]);
        chip = gpio_chip_open(path, label, sizeof label);
        if (used < sizeof searched) {
            int n = snprintf(searched + used, sizeof searched - used, "%s%s%s", used ? ", " : "", label,
                             chip == NULL ? " (cannot open)" : "");
            used = n > 0 ? used + (size_t)n : used;
        }
        if (chip == NULL)
            continue;
        for (size_t i = 0; i < count; i++) {
            if (have[i] || gpio_find(chip, names[i], &gl->lines[i]) < 0)
                continue;
            have[i] = true;
            gl->lines[i].chip = (uint8_t)c;
            found++;
            mine = true;
        }
        if (!mine) {
            gpiod_chip_close(chip);
            continue;
        }
        gl->chips[c].chip = chip;
        snprintf(gl->chips[c].path, sizeof gl->chips[c].path, "%s", path);
        snprintf(gl->chips[c].label, sizeof gl->chips[c].label, "%s", label);
        gl->chip_count++;
    }
    if (found < count) {
        char missing[160] = "";
        size_t m = 0;
        for (size_t i = 0; i < count; i++) {
            if (have[i] || m >= sizeof missing)
                continue;
            int n = snprintf(missing + m, sizeof missing - m, "%s'%s'", m ? ", " : "", names[i]);
            m = n > 0 ? m + (size_t)n : m;
        }
        if (nchips > 0)
            snprintf(err, errlen, "line%s %s on no GPIO chip (searched %s)", count - found == 1 ? "" : "s",
                     missing, searched);
        else
            snprintf(err, errlen, "line%s %s on no GPIO chip (there is no gpiochip in %s)",
                     count - found == 1 ? "" : "s", missing, dir);
        psc_gpio_lines_close(gl);
        return -ENOENT;
    }
    for (unsigned c = 0; c < gl->chip_count && rc == 0; c++) {
        rc = gpio_request_chip(gl, c, st);
        if (rc != 0)
            snprintf(err, errlen, "cannot request the lines on %s: %s%s", gl->chips[c].label, strerror(-rc),
                     rc == -EBUSY ? " (another program uses them: see gpioinfo)" : "");
    }
    if (rc != 0) {
        psc_gpio_lines_close(gl);
        return rc;
    }
    *out = gl;
    return 0;
}

/* ---- values and events ---------------------------------------------------------- */

int psc_gpio_lines_get(psc_gpio_lines_t *gl, size_t i)
{
    int v;

    if (i >= gl->count)
        return -EINVAL;
#if PSC_GPIOD_MAJOR == 1
    v = gpiod_line_get_value(gl->lines[i].line);
#else
    v = (int)gpiod_line_request_get_value(gl->chips[gl->lines[i].chip].request, gl->lines[i].offset);
#endif
    return v < 0 ? -errno : v;
}

int psc_gpio_lines_read(psc_gpio_lines_t *gl, psc_gpio_edge_t *out, size_t max)
{
    struct pollfd pfd[PSC_GPIO_MAX_LINES];
    size_t nfd = 0, n = 0;

#if PSC_GPIOD_MAJOR == 1
    for (size_t i = 0; i < gl->count; i++)   /* uAPI v1: one event fd per line */
        pfd[nfd++] = (struct pollfd){ .fd = gpiod_line_event_get_fd(gl->lines[i].line), .events = POLLIN };
#else
    for (unsigned c = 0; c < gl->chip_count; c++)   /* uAPI v2: one fd per request */
        pfd[nfd++] = (struct pollfd){ .fd = gpiod_line_request_get_fd(gl->chips[c].request), .events = POLLIN };
#endif
    if (poll(pfd, nfd, 0) < 0)
        return errno == EINTR ? 0 : -errno;
    for (size_t k = 0; k < nfd && n < max; k++) {
        if (pfd[k].revents & (POLLERR | POLLHUP | POLLNVAL))
            return -ENODEV;   /* the chip went away */
        if (!(pfd[k].revents & POLLIN))
            continue;
#if PSC_GPIOD_MAJOR == 1
        struct gpiod_line_event ev[GPIO_EVENTS_PER_READ];
        size_t room = max - n < GPIO_EVENTS_PER_READ ? max - n : GPIO_EVENTS_PER_READ;
        int got = gpiod_line_event_read_multiple(gl->lines[k].line, ev, (unsigned)room);
        if (got < 0)
            return errno == EAGAIN ? 0 : -(errno == ENODEV || errno == EIO ? ENODEV : errno);
        for (int e = 0; e < got; e++)
            out[n++] = (psc_gpio_edge_t){ (uint8_t)k, ev[e].event_type == GPIOD_LINE_EVENT_RISING_EDGE,
                                          (uint64_t)ev[e].ts.tv_sec * 1000000000u + (uint64_t)ev[e].ts.tv_nsec };
#else
        gpio_chip_t *chip = &gl->chips[k];
        size_t room = max - n < GPIO_EVENTS_PER_READ ? max - n : GPIO_EVENTS_PER_READ;
        int got = gpiod_line_request_read_edge_events(chip->request, chip->events, room);
        if (got < 0)
            return errno == EAGAIN ? 0 : -(errno == ENODEV || errno == EIO ? ENODEV : errno);
        for (int e = 0; e < got; e++) {
            struct gpiod_edge_event *ev = gpiod_edge_event_buffer_get_event(chip->events, (unsigned long)e);
            unsigned off = gpiod_edge_event_get_line_offset(ev);
            for (size_t i = 0; i < gl->count; i++) {
                if (gl->lines[i].chip != k || gl->lines[i].offset != off)
                    continue;
                out[n++] = (psc_gpio_edge_t){ (uint8_t)i,
                                              gpiod_edge_event_get_event_type(ev) == GPIOD_EDGE_EVENT_RISING_EDGE,
                                              gpiod_edge_event_get_timestamp_ns(ev) };
                break;
            }
        }
#endif
    }
    return (int)n;
}

#else /* PSC_GPIOD_MAJOR == 0: built without libgpiod */

void psc_gpio_lines_close(psc_gpio_lines_t *gl)
{
    free(gl);
}

int psc_gpio_lines_open(const char *const *names, size_t count, const psc_gpio_settings_t *st,
                        psc_gpio_lines_t **out, char *err, size_t errlen)
{
    unsigned numbers[1];

    (void)names;
    (void)count;
    (void)gpio_list_chips(st->dev_dir != NULL ? st->dev_dir : "/dev", numbers, 0);
    *out = NULL;
    snprintf(err, errlen, "this build has no libgpiod (install libgpiod-dev and rebuild)");
    return -ENOSYS;
}

int psc_gpio_lines_get(psc_gpio_lines_t *gl, size_t i)
{
    (void)gl;
    (void)i;
    return -ENOSYS;
}

int psc_gpio_lines_read(psc_gpio_lines_t *gl, psc_gpio_edge_t *out, size_t max)
{
    (void)gl;
    (void)out;
    (void)max;
    return -ENOSYS;
}

#endif

bool psc_gpio_lines_kernel_debounce(const psc_gpio_lines_t *gl)
{
    return gl != NULL && gl->kernel_debounce;
}

void psc_gpio_lines_describe(const psc_gpio_lines_t *gl, char *buf, size_t len)
{
    size_t used = 0;

    if (buf == NULL || len == 0)
        return;
    buf[0] = '\0';
    for (unsigned c = 0; gl != NULL && c < gl->chip_count && used < len; c++) {
        int n = snprintf(buf + used, len - used, "%s%s", c ? ", " : "", gl->chips[c].label);
        if (n < 0)
            break;
        used += (size_t)n;
    }
}
