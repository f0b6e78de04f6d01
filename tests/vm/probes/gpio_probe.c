/* SPDX-License-Identifier: MIT */
/*
 * gpio_probe - check a GPIO chip's lines through the kernel's GPIO character
 * device (uAPI v2, linux/gpio.h, no libgpiod: the probe tests the driver, the
 * backend tests libgpiod 1.6 and 2.x on top) the way the button backend
 * uses them: find a line by name across every chip, request it as an input
 * with edge events on both edges (optionally with debounce), and read events.
 *
 *   gpio_probe find NAME               "chip /dev/gpiochipN line K" or fail
 *   gpio_probe events NAME N [DEBOUNCE_US]
 *                                      print "ready", then the first N edges
 *                                      as "event rising|falling" and the
 *                                      line's value; ends early with
 *                                      "lost: ..." when the chip goes away
 *                                      (exit status 3)
 */
#include <dirent.h>
#include <fcntl.h>
#include <linux/gpio.h>
#include <poll.h>
#include <sys/ioctl.h>

#include "probe_util.h"

#define GPIO_PROBE_WAIT_MS 15000
#define GPIO_PROBE_SLICE_MS 100

/* Open the chip holding line NAME; its fd, *offset and *path set. */
static int gpio_find(const char *name, unsigned *offset, char *path, size_t pathlen)
{
    DIR *d = opendir("/dev");
    struct dirent *e;

    if (d == NULL)
        probe_fail(errno, "/dev");
    while ((e = readdir(d)) != NULL) {
        struct gpiochip_info info;
        int fd;

        if (strncmp(e->d_name, "gpiochip", 8) != 0)
            continue;
        snprintf(path, pathlen, "/dev/%s", e->d_name);
        fd = open(path, O_RDWR | O_CLOEXEC);
        if (fd < 0)
            continue;
        if (ioctl(fd, GPIO_GET_CHIPINFO_IOCTL, &info) == 0) {
            for (unsigned k = 0; k < info.lines; k++) {
                struct gpio_v2_line_info li = { .offset = k };

                if (ioctl(fd, GPIO_V2_GET_LINEINFO_IOCTL, &li) == 0 && strcmp(li.name, name) == 0) {
                    closedir(d);
                    *offset = k;
                    return fd;
                }
            }
        }
        close(fd);
    }
    closedir(d);
    probe_fail(0, "no GPIO line named '%s' on any /dev/gpiochip*", name);
    return -1;
}

static void gpio_events(const char *name, int count, uint32_t debounce_us)
{
    struct gpio_v2_line_request req = { 0 };
    struct gpio_v2_line_values vals = { .mask = 1 };
    char path[300];
    unsigned offset;
    int chip = gpio_find(name, &offset, path, sizeof path);

    req.offsets[0] = offset;
    req.num_lines = 1;
    req.event_buffer_size = 16;
    snprintf(req.consumer, sizeof req.consumer, "gpio_probe");
    req.config.flags = GPIO_V2_LINE_FLAG_INPUT | GPIO_V2_LINE_FLAG_EDGE_RISING | GPIO_V2_LINE_FLAG_EDGE_FALLING;
    if (debounce_us != 0) {
        req.config.num_attrs = 1;
        req.config.attrs[0].mask = 1;
        req.config.attrs[0].attr.id = GPIO_V2_LINE_ATTR_ID_DEBOUNCE;
        req.config.attrs[0].attr.debounce_period_us = debounce_us;
    }
    if (ioctl(chip, GPIO_V2_GET_LINE_IOCTL, &req) != 0)
        probe_fail(errno, "%s: request line %u ('%s') for edge events", path, offset, name);
    close(chip);
    printf("line %s: %s offset %u%s\n", name, path, offset, debounce_us ? " debounced" : "");
    printf("ready\n");
    fflush(stdout);
    for (int n = 0; n < count; n++) {
        struct pollfd pfd = { .fd = req.fd, .events = POLLIN };
        struct gpio_v2_line_event ev;
        int r = 0;
        ssize_t got;

        /* Poll in short slices, as a frame loop does: Linux 6.1 does not
         * wake a poller when the chip goes away (the next poll sees
         * POLLERR|POLLHUP), so one long poll would sleep through a removal. */
        for (int waited = 0; r == 0 && waited < GPIO_PROBE_WAIT_MS; waited += GPIO_PROBE_SLICE_MS)
            r = poll(&pfd, 1, GPIO_PROBE_SLICE_MS);
        if (r == 0)
            probe_fail(0, "no edge %d on '%s' within %d ms", n, name, GPIO_PROBE_WAIT_MS);
        if (r < 0)
            probe_fail(errno, "poll");
        got = read(req.fd, &ev, sizeof ev);
        if (got != (ssize_t)sizeof ev) {
            printf("lost: poll revents%s%s%s, read %s\n", (pfd.revents & POLLERR) ? " POLLERR" : "",
                   (pfd.revents & POLLHUP) ? " POLLHUP" : "", (pfd.revents & POLLIN) ? " POLLIN" : "",
                   got < 0 ? strerror(errno) : "short");
            exit(3);
        }
        printf("event %s\n", ev.id == GPIO_V2_LINE_EVENT_RISING_EDGE ? "rising" : "falling");
        fflush(stdout);
    }
    if (ioctl(req.fd, GPIO_V2_LINE_GET_VALUES_IOCTL, &vals) != 0)
        probe_fail(errno, "read the value of '%s'", name);
    printf("value %u\n", (unsigned)(vals.bits & 1));
    close(req.fd);
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "find") == 0) {
        char path[300];
        unsigned offset;

        close(gpio_find(argv[2], &offset, path, sizeof path));
        printf("chip %s line %u\n", path, offset);
    } else if ((argc == 4 || argc == 5) && strcmp(argv[1], "events") == 0) {
        gpio_events(argv[2], (int)probe_number("count", argv[3]),
                    argc == 5 ? (uint32_t)probe_number("debounce", argv[4]) : 0);
    } else {
        fprintf(stderr, "usage: gpio_probe find NAME | events NAME N [DEBOUNCE_US]\n");
        return 2;
    }
    return 0;
}
