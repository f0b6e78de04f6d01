/* SPDX-License-Identifier: MIT */
/*
 * hexwrite - write bytes given in hex to a file, one write(2) per argument:
 * a HID report descriptor into the gadget's configfs `report_desc`, or
 * reports into /dev/hidgN, where each write is one report and so must not
 * be split (a shell's printf may split or reorder nothing, but it cannot
 * write a NUL byte portably).
 *
 *   hexwrite [-w] FILE HEX...     e.g. hexwrite /dev/hidg0 "80 80 80 80 00 00 0f"
 *
 * Spaces inside an argument are ignored. With -w hexwrite returns only once
 * the last write has been taken (poll POLLOUT: for /dev/hidgN, the host has
 * read the report and the zero-length packet that may follow it), so a
 * program reading the device with transfers in flight has it by the time
 * hexwrite exits. A write that cannot complete (a
 * gadget whose host stopped reading) fails after HEXWRITE_WAIT_MS instead of
 * blocking the case for ever.
 */
#include <fcntl.h>
#include <poll.h>

#include "probe_util.h"

#define HEXWRITE_MAX 4096
#define HEXWRITE_WAIT_MS 15000

static int hex_digit(char c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

/* Parse hex pairs of s into out; the byte count. */
static size_t hex_parse(const char *s, uint8_t *out)
{
    size_t n = 0;
    int hi = -1;

    for (; *s; s++) {
        int d;

        if (*s == ' ' || *s == ':')
            continue;
        d = hex_digit(*s);
        if (d < 0)
            probe_fail(0, "'%c' is not a hex digit", *s);
        if (hi < 0) {
            hi = d;
            continue;
        }
        if (n == HEXWRITE_MAX)
            probe_fail(0, "more than %d bytes in one argument", HEXWRITE_MAX);
        out[n++] = (uint8_t)(hi << 4 | d);
        hi = -1;
    }
    if (hi >= 0)
        probe_fail(0, "odd number of hex digits");
    return n;
}

int main(int argc, char **argv)
{
    static uint8_t buf[HEXWRITE_MAX];
    int fd, wait_taken = 0;

    if (argc > 1 && strcmp(argv[1], "-w") == 0) {
        wait_taken = 1;
        argv++;
        argc--;
    }
    if (argc < 3) {
        fprintf(stderr, "usage: hexwrite [-w] FILE HEX...\n");
        return 2;
    }
    fd = open(argv[1], O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        probe_fail(errno, "open %s", argv[1]);
    for (int i = 2; i < argc; i++) {
        size_t n = hex_parse(argv[i], buf);
        ssize_t w;

        while ((w = write(fd, buf, n)) < 0 && (errno == EAGAIN || errno == EINTR)) {
            struct pollfd pfd = { .fd = fd, .events = POLLOUT };

            if (errno == EAGAIN && poll(&pfd, 1, HEXWRITE_WAIT_MS) == 0)
                probe_fail(0, "%s: report %d not taken within %d ms (is anything reading?)", argv[1], i - 1,
                           HEXWRITE_WAIT_MS);
        }
        if (w < 0)
            probe_fail(errno, "%s: write %zu bytes", argv[1], n);
        if ((size_t)w != n)
            probe_fail(0, "%s: wrote %zd of %zu bytes", argv[1], w, n);
    }
    /* wait until the last write was taken (a gadget's report reached the
     * host): the case lets the firmware go next and counts on it seeing the
     * report at its very next poll */
    while (wait_taken) {
        struct pollfd pfd = { .fd = fd, .events = POLLOUT };
        int r = poll(&pfd, 1, HEXWRITE_WAIT_MS);

        if (r < 0 && errno == EINTR)
            continue;
        if (r == 0)
            probe_fail(0, "%s: the last report was not taken within %d ms", argv[1], HEXWRITE_WAIT_MS);
        break;
    }
    if (close(fd) != 0)
        probe_fail(errno, "close %s", argv[1]);
    return 0;
}
