/* SPDX-License-Identifier: MIT */
/*
 * v4l2_probe - check a V4L2 capture driver (vivid in the VM) the way the
 * camera backend will use it: format negotiation, mmap streaming with poll,
 * frame sizes and sequence numbers, and what an unplug looks like to a
 * streaming program (vivid's "Disconnect" control).
 *
 *   v4l2_probe info DEV                    capabilities, formats and controls
 *   v4l2_probe stream DEV W H N OUT        YUYV W x H, N frames, the last one to OUT
 *   v4l2_probe disconnect DEV              stream, press "Disconnect", report
 *                                          what poll/DQBUF/QUERYCAP return then
 *   v4l2_probe press DEV NAME              press the button control NAME (while
 *                                          another program streams: an unplug
 *                                          under the firmware's feet)
 *
 * Waits are poll(2) with a bound (a driver that stops delivering fails the
 * probe rather than hanging the VM).
 */
#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include "probe_util.h"

#define V4L2_PROBE_BUFFERS 3
#define V4L2_PROBE_POLL_MS 20000

typedef struct {
    int fd;
    const char *dev;
    void *mem[V4L2_PROBE_BUFFERS];
    size_t len[V4L2_PROBE_BUFFERS];
    uint32_t count;
    struct v4l2_format fmt;
} v4l2_probe_t;

/* ioctl, retried on EINTR. */
static int xioctl(int fd, unsigned long req, void *arg)
{
    int r;

    do
        r = ioctl(fd, req, arg);
    while (r < 0 && errno == EINTR);
    return r;
}

static void fourcc_str(uint32_t f, char out[5])
{
    for (int i = 0; i < 4; i++)
        out[i] = (char)((f >> (8 * i)) & 0xff);
    out[4] = '\0';
}

static void v4l2_info(const char *dev)
{
    struct v4l2_capability cap = { 0 };
    struct v4l2_fmtdesc fd = { .type = V4L2_BUF_TYPE_VIDEO_CAPTURE };
    struct v4l2_queryctrl qc = { .id = V4L2_CTRL_FLAG_NEXT_CTRL };
    int fdv = open(dev, O_RDWR | O_CLOEXEC);
    char cc[5];

    if (fdv < 0)
        probe_fail(errno, "open %s", dev);
    if (xioctl(fdv, VIDIOC_QUERYCAP, &cap) != 0)
        probe_fail(errno, "%s: VIDIOC_QUERYCAP", dev);
    printf("driver %s\ncard %s\n", (const char *)cap.driver, (const char *)cap.card);
    printf("capture %s streaming %s\n", (cap.device_caps & V4L2_CAP_VIDEO_CAPTURE) ? "yes" : "no",
           (cap.device_caps & V4L2_CAP_STREAMING) ? "yes" : "no");
    while (xioctl(fdv, VIDIOC_ENUM_FMT, &fd) == 0) {
        fourcc_str(fd.pixelformat, cc);
        printf("format %s\n", cc);
        fd.index++;
    }
    while (xioctl(fdv, VIDIOC_QUERYCTRL, &qc) == 0) {
        if (!(qc.flags & V4L2_CTRL_FLAG_DISABLED))
            printf("control %s\n", (const char *)qc.name);
        qc.id |= V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND;
    }
    close(fdv);
}

static void v4l2_start(v4l2_probe_t *p, const char *dev, uint32_t w, uint32_t h)
{
    struct v4l2_requestbuffers req = { .count = V4L2_PROBE_BUFFERS, .type = V4L2_BUF_TYPE_VIDEO_CAPTURE,
                                       .memory = V4L2_MEMORY_MMAP };
    enum v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;

    memset(p, 0, sizeof *p);
    p->dev = dev;
    p->fd = open(dev, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (p->fd < 0)
        probe_fail(errno, "open %s", dev);
    p->fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    p->fmt.fmt.pix.width = w;
    p->fmt.fmt.pix.height = h;
    p->fmt.fmt.pix.pixelformat = V4L2_PIX_FMT_YUYV;
    p->fmt.fmt.pix.field = V4L2_FIELD_NONE;
    if (xioctl(p->fd, VIDIOC_S_FMT, &p->fmt) != 0)
        probe_fail(errno, "%s: VIDIOC_S_FMT YUYV %ux%u", dev, w, h);
    if (p->fmt.fmt.pix.pixelformat != V4L2_PIX_FMT_YUYV || p->fmt.fmt.pix.width != w || p->fmt.fmt.pix.height != h)
        probe_fail(0, "%s: asked for YUYV %ux%u, got %ux%u", dev, w, h, p->fmt.fmt.pix.width,
                   p->fmt.fmt.pix.height);
    printf("format YUYV %ux%u bytesperline %u sizeimage %u\n", p->fmt.fmt.pix.width, p->fmt.fmt.pix.height,
           p->fmt.fmt.pix.bytesperline, p->fmt.fmt.pix.sizeimage);
    if (xioctl(p->fd, VIDIOC_REQBUFS, &req) != 0)
        probe_fail(errno, "%s: VIDIOC_REQBUFS", dev);
    if (req.count < 2 || req.count > V4L2_PROBE_BUFFERS)
        probe_fail(0, "%s: the driver gave %u buffers", dev, req.count);
    p->count = req.count;
    for (uint32_t i = 0; i < p->count; i++) {
        struct v4l2_buffer b = { .index = i, .type = V4L2_BUF_TYPE_VIDEO_CAPTURE, .memory = V4L2_MEMORY_MMAP };

        if (xioctl(p->fd, VIDIOC_QUERYBUF, &b) != 0)
            probe_fail(errno, "%s: VIDIOC_QUERYBUF %u", dev, i);
        p->len[i] = b.length;
        p->mem[i] = mmap(NULL, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, p->fd, b.m.offset);
        if (p->mem[i] == MAP_FAILED)
            probe_fail(errno, "%s: mmap buffer %u", dev, i);
        if (xioctl(p->fd, VIDIOC_QBUF, &b) != 0)
            probe_fail(errno, "%s: VIDIOC_QBUF %u", dev, i);
    }
    if (xioctl(p->fd, VIDIOC_STREAMON, &type) != 0)
        probe_fail(errno, "%s: VIDIOC_STREAMON", dev);
}

/* Wait for and dequeue one frame: 0 with *b filled, else the errno (revents in *revents). */
static int v4l2_next(v4l2_probe_t *p, struct v4l2_buffer *b, short *revents)
{
    struct pollfd pfd = { .fd = p->fd, .events = POLLIN };
    int r = poll(&pfd, 1, V4L2_PROBE_POLL_MS);

    *revents = pfd.revents;
    if (r < 0)
        return errno;
    if (r == 0)
        return ETIMEDOUT;
    memset(b, 0, sizeof *b);
    b->type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b->memory = V4L2_MEMORY_MMAP;
    if (xioctl(p->fd, VIDIOC_DQBUF, b) != 0)
        return errno;
    return 0;
}

/* How many different luma values the first row of a YUYV frame holds. */
static unsigned yuyv_row_lumas(const uint8_t *frame, uint32_t width)
{
    uint8_t seen[256] = { 0 };
    unsigned n = 0;

    for (uint32_t x = 0; x < width; x++) {
        uint8_t y = frame[2 * x];

        n += !seen[y];
        seen[y] = 1;
    }
    return n;
}

static void v4l2_stream(const char *dev, uint32_t w, uint32_t h, uint32_t frames, const char *out)
{
    v4l2_probe_t p;
    struct v4l2_buffer b;
    uint32_t last_seq = 0;
    short rev;
    FILE *f;

    v4l2_start(&p, dev, w, h);
    for (uint32_t n = 0; n < frames; n++) {
        int e = v4l2_next(&p, &b, &rev);

        if (e != 0)
            probe_fail(e, "%s: frame %u (poll revents 0x%x)", dev, n, (unsigned)rev);
        if (b.bytesused != p.fmt.fmt.pix.sizeimage)
            probe_fail(0, "%s: frame %u has %u bytes, not %u", dev, n, b.bytesused, p.fmt.fmt.pix.sizeimage);
        if (n > 0 && b.sequence <= last_seq)
            probe_fail(0, "%s: sequence went from %u to %u", dev, last_seq, b.sequence);
        last_seq = b.sequence;
        printf("frame %u sequence %u bytes %u lumas %u\n", n, b.sequence, b.bytesused,
               yuyv_row_lumas(p.mem[b.index], w));
        if (n + 1 == frames) {
            f = fopen(out, "wb");
            if (f == NULL || fwrite(p.mem[b.index], 1, b.bytesused, f) != b.bytesused || fclose(f) != 0)
                probe_fail(errno, "writing %s", out);
        }
        if (xioctl(p.fd, VIDIOC_QBUF, &b) != 0)
            probe_fail(errno, "%s: VIDIOC_QBUF", dev);
    }
    close(p.fd);
}

/* The id of the control named name, or fail. */
static uint32_t v4l2_control_by_name(int fd, const char *dev, const char *name)
{
    struct v4l2_queryctrl qc = { .id = V4L2_CTRL_FLAG_NEXT_CTRL };

    while (xioctl(fd, VIDIOC_QUERYCTRL, &qc) == 0) {
        if (strcmp((const char *)qc.name, name) == 0)
            return qc.id;
        qc.id |= V4L2_CTRL_FLAG_NEXT_CTRL;
    }
    probe_fail(0, "%s: no control named '%s'", dev, name);
    return 0;
}

static void v4l2_disconnect(const char *dev)
{
    v4l2_probe_t p;
    struct v4l2_buffer b;
    struct v4l2_control ctl = { 0 };
    struct v4l2_capability cap;
    short rev;
    int e, fdv;

    v4l2_start(&p, dev, 640, 480);
    for (int n = 0; n < 2; n++) {
        e = v4l2_next(&p, &b, &rev);
        if (e != 0)
            probe_fail(e, "%s: frame %d before the disconnect", dev, n);
        if (xioctl(p.fd, VIDIOC_QBUF, &b) != 0)
            probe_fail(errno, "%s: VIDIOC_QBUF", dev);
    }
    printf("streaming: 2 frames\n");
    ctl.id = v4l2_control_by_name(p.fd, dev, "Disconnect");
    if (xioctl(p.fd, VIDIOC_S_CTRL, &ctl) != 0)
        probe_fail(errno, "%s: pressing Disconnect", dev);
    printf("pressed Disconnect\n");
    /* after an unplug poll must wake at once with an error, never time out */
    e = v4l2_next(&p, &b, &rev);
    printf("after: poll revents%s%s%s, dequeue %s\n", (rev & POLLERR) ? " POLLERR" : "",
           (rev & POLLHUP) ? " POLLHUP" : "", (rev & POLLIN) ? " POLLIN" : "", e == 0 ? "ok" : strerror(e));
    if (e == ETIMEDOUT)
        probe_fail(0, "%s: poll timed out after the disconnect", dev);
    e = xioctl(p.fd, VIDIOC_QUERYCAP, &cap) == 0 ? 0 : errno;
    printf("after: VIDIOC_QUERYCAP %s\n", e == 0 ? "ok" : strerror(e));
    if (e != ENODEV)
        probe_fail(0, "%s: VIDIOC_QUERYCAP after the disconnect should fail with ENODEV", dev);
    close(p.fd);
    /* vivid keeps the node but refuses it, as a USB camera's node may linger */
    fdv = open(dev, O_RDWR | O_CLOEXEC);
    e = fdv >= 0 ? 0 : errno;
    printf("after close: reopen %s %s\n", dev, e == 0 ? "ok" : strerror(e));
    if (fdv >= 0)
        close(fdv);
}

static void v4l2_press(const char *dev, const char *name)
{
    struct v4l2_control ctl = { 0 };
    int fd = open(dev, O_RDWR | O_CLOEXEC);

    if (fd < 0)
        probe_fail(errno, "open %s", dev);
    ctl.id = v4l2_control_by_name(fd, dev, name);
    if (xioctl(fd, VIDIOC_S_CTRL, &ctl) != 0)
        probe_fail(errno, "%s: pressing '%s'", dev, name);
    printf("pressed %s\n", name);
    close(fd);
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "info") == 0) {
        v4l2_info(argv[2]);
    } else if (argc == 7 && strcmp(argv[1], "stream") == 0) {
        v4l2_stream(argv[2], (uint32_t)probe_number("width", argv[3]), (uint32_t)probe_number("height", argv[4]),
                    (uint32_t)probe_number("frames", argv[5]), argv[6]);
    } else if (argc == 3 && strcmp(argv[1], "disconnect") == 0) {
        v4l2_disconnect(argv[2]);
    } else if (argc == 4 && strcmp(argv[1], "press") == 0) {
        v4l2_press(argv[2], argv[3]);
    } else {
        fprintf(stderr, "usage: v4l2_probe info DEV | stream DEV W H N OUT | disconnect DEV | press DEV NAME\n");
        return 2;
    }
    return 0;
}
