/* SPDX-License-Identifier: MIT */
/*
 * fb_probe - check the fbdev driver behind a /dev/fbN the way the fbdev
 * backend will use it: mode query, switching the depth (XRGB8888 and
 * RGB565), a virtual screen twice as tall with pan-display, and pixels
 * written through mmap read back through read(2).
 *
 *   fb_probe info DEV             print the mode as "key value" lines
 *   fb_probe setbpp DEV BPP       set the depth (16 or 32) asking for red on top,
 *                                 print the mode the driver chose
 *   fb_probe pan DEV              yres_virtual = 2 * yres, pan to the lower
 *                                 half and back, checking the driver's yoffset
 *   fb_probe draw DEV             fill the visible screen with the test pattern
 *   fb_probe dump DEV             write the visible screen to stdout (rows
 *                                 without line padding) using read(2)
 *   fb_probe pattern W H BPP      write the expected dump to stdout (the host runs this)
 *   fb_probe kdgraphics TTY       put the virtual terminal TTY in graphics mode
 *
 * The kernel's framebuffer console (fbcon, built into Debian's kernels) takes
 * over every new framebuffer: it clears it, redraws it on a mode change and
 * blinks a cursor into it, so a test pattern races with it. A kiosk program
 * does what `kdgraphics` does (KDSETMODE KD_GRAPHICS on its terminal), and
 * the console keeps its hands off the screen until the mode goes back.
 */
#include <fcntl.h>
#include <linux/fb.h>
#include <linux/kd.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include "probe_util.h"

static int fb_open(const char *dev, struct fb_var_screeninfo *var, struct fb_fix_screeninfo *fix)
{
    int fd = open(dev, O_RDWR | O_CLOEXEC);

    if (fd < 0)
        probe_fail(errno, "open %s", dev);
    if (ioctl(fd, FBIOGET_VSCREENINFO, var) != 0)
        probe_fail(errno, "%s: FBIOGET_VSCREENINFO", dev);
    if (ioctl(fd, FBIOGET_FSCREENINFO, fix) != 0)
        probe_fail(errno, "%s: FBIOGET_FSCREENINFO", dev);
    return fd;
}

static void fb_print(const struct fb_var_screeninfo *var, const struct fb_fix_screeninfo *fix)
{
    printf("id %.16s\n", fix->id);
    printf("mode %ux%u\n", var->xres, var->yres);
    printf("virtual %ux%u\n", var->xres_virtual, var->yres_virtual);
    printf("bpp %u\n", var->bits_per_pixel);
    printf("red %u/%u green %u/%u blue %u/%u\n", var->red.offset, var->red.length, var->green.offset,
           var->green.length, var->blue.offset, var->blue.length);
    printf("line_length %u\n", fix->line_length);
    printf("smem_len %u\n", fix->smem_len);
    printf("ypanstep %u\n", fix->ypanstep);
    printf("visual %u\n", fix->visual);
}

static void fb_pattern(uint8_t *row, uint32_t y, uint32_t width, unsigned bytes_per_pixel)
{
    for (uint32_t x = 0; x < width; x++)
        probe_store_pixel(row + (size_t)x * bytes_per_pixel, probe_pattern(x, y), bytes_per_pixel);
}

static void fb_setbpp(const char *dev, unsigned bpp)
{
    struct fb_var_screeninfo var;
    struct fb_fix_screeninfo fix;
    int fd = fb_open(dev, &var, &fix);

    /* ask for the layout the project calls RGB565 / XRGB8888 (red on top);
     * drivers may answer with another one (vfb always puts red at offset 0),
     * which is printed for the case to check */
    var.bits_per_pixel = bpp;
    var.red = (struct fb_bitfield){ .offset = bpp == 16 ? 11 : 16, .length = bpp == 16 ? 5 : 8 };
    var.green = (struct fb_bitfield){ .offset = bpp == 16 ? 5 : 8, .length = bpp == 16 ? 6 : 8 };
    var.blue = (struct fb_bitfield){ .offset = 0, .length = bpp == 16 ? 5 : 8 };
    var.transp = (struct fb_bitfield){ 0 };
    if (ioctl(fd, FBIOPUT_VSCREENINFO, &var) != 0)
        probe_fail(errno, "%s: FBIOPUT_VSCREENINFO bits_per_pixel=%u", dev, bpp);
    if (ioctl(fd, FBIOGET_VSCREENINFO, &var) != 0 || ioctl(fd, FBIOGET_FSCREENINFO, &fix) != 0)
        probe_fail(errno, "%s: reading the mode back", dev);
    if (var.bits_per_pixel != bpp)
        probe_fail(0, "%s: asked for %u bits per pixel, the driver kept %u", dev, bpp, var.bits_per_pixel);
    fb_print(&var, &fix);
    close(fd);
}

static void fb_pan(const char *dev)
{
    struct fb_var_screeninfo var;
    struct fb_fix_screeninfo fix;
    int fd = fb_open(dev, &var, &fix);
    uint32_t yres = var.yres;

    var.yres_virtual = 2 * yres;
    var.yoffset = 0;
    if (ioctl(fd, FBIOPUT_VSCREENINFO, &var) != 0)
        probe_fail(errno, "%s: FBIOPUT_VSCREENINFO yres_virtual=%u", dev, 2 * yres);
    if (ioctl(fd, FBIOGET_VSCREENINFO, &var) != 0)
        probe_fail(errno, "%s: FBIOGET_VSCREENINFO", dev);
    if (var.yres_virtual < 2 * yres)
        probe_fail(0, "%s: the driver gave yres_virtual %u, not %u", dev, var.yres_virtual, 2 * yres);
    for (int i = 0; i < 2; i++) {
        uint32_t want = i == 0 ? yres : 0;

        var.yoffset = want;
        if (ioctl(fd, FBIOPAN_DISPLAY, &var) != 0)
            probe_fail(errno, "%s: FBIOPAN_DISPLAY yoffset=%u", dev, want);
        if (ioctl(fd, FBIOGET_VSCREENINFO, &var) != 0)
            probe_fail(errno, "%s: FBIOGET_VSCREENINFO", dev);
        if (var.yoffset != want)
            probe_fail(0, "%s: panned to yoffset %u, the driver reports %u", dev, want, var.yoffset);
        printf("panned yoffset %u\n", var.yoffset);
    }
    close(fd);
}

static void fb_draw(const char *dev)
{
    struct fb_var_screeninfo var;
    struct fb_fix_screeninfo fix;
    int fd = fb_open(dev, &var, &fix);
    unsigned bpp = var.bits_per_pixel / 8;
    uint8_t *mem;

    if ((size_t)fix.line_length * var.yres > fix.smem_len || var.xres * bpp > fix.line_length)
        probe_fail(0, "%s: mode %ux%u does not fit line_length %u / smem_len %u", dev, var.xres, var.yres,
                   fix.line_length, fix.smem_len);
    mem = mmap(NULL, fix.smem_len, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (mem == MAP_FAILED)
        probe_fail(errno, "%s: mmap %u bytes", dev, fix.smem_len);
    for (uint32_t y = 0; y < var.yres; y++)
        fb_pattern(mem + (size_t)(y + var.yoffset) * fix.line_length, y, var.xres, bpp);
    munmap(mem, fix.smem_len);
    close(fd);
}

static void fb_dump(const char *dev)
{
    struct fb_var_screeninfo var;
    struct fb_fix_screeninfo fix;
    int fd = fb_open(dev, &var, &fix);
    size_t row_bytes = (size_t)var.xres * (var.bits_per_pixel / 8);
    uint8_t *row = malloc(fix.line_length);

    if (row == NULL)
        probe_fail(ENOMEM, "row buffer");
    if (lseek(fd, (off_t)var.yoffset * fix.line_length, SEEK_SET) < 0)
        probe_fail(errno, "%s: seek", dev);
    for (uint32_t y = 0; y < var.yres; y++) {
        size_t got = 0;

        while (got < fix.line_length) {
            ssize_t n = read(fd, row + got, fix.line_length - got);

            if (n <= 0)
                probe_fail(n < 0 ? errno : 0, "%s: read row %u", dev, y);
            got += (size_t)n;
        }
        if (fwrite(row, 1, row_bytes, stdout) != row_bytes)
            probe_fail(errno, "stdout");
    }
    free(row);
    close(fd);
}

static void fb_expected(uint32_t width, uint32_t height, unsigned bpp)
{
    uint8_t *row = malloc((size_t)width * 4);

    if (row == NULL)
        probe_fail(ENOMEM, "row buffer");
    for (uint32_t y = 0; y < height; y++) {
        fb_pattern(row, y, width, bpp / 8);
        if (fwrite(row, bpp / 8, width, stdout) != width)
            probe_fail(errno, "stdout");
    }
    free(row);
}

static void fb_kdgraphics(const char *tty)
{
    int fd = open(tty, O_RDWR | O_CLOEXEC);

    if (fd < 0)
        probe_fail(errno, "open %s", tty);
    if (ioctl(fd, KDSETMODE, KD_GRAPHICS) != 0)
        probe_fail(errno, "%s: KDSETMODE KD_GRAPHICS", tty);
    close(fd);
}

int main(int argc, char **argv)
{
    struct fb_var_screeninfo var;
    struct fb_fix_screeninfo fix;

    if (argc == 3 && strcmp(argv[1], "info") == 0) {
        close(fb_open(argv[2], &var, &fix));
        fb_print(&var, &fix);
    } else if (argc == 4 && strcmp(argv[1], "setbpp") == 0) {
        fb_setbpp(argv[2], (unsigned)probe_number("bpp", argv[3]));
    } else if (argc == 3 && strcmp(argv[1], "pan") == 0) {
        fb_pan(argv[2]);
    } else if (argc == 3 && strcmp(argv[1], "draw") == 0) {
        fb_draw(argv[2]);
    } else if (argc == 3 && strcmp(argv[1], "dump") == 0) {
        fb_dump(argv[2]);
    } else if (argc == 3 && strcmp(argv[1], "kdgraphics") == 0) {
        fb_kdgraphics(argv[2]);
    } else if (argc == 5 && strcmp(argv[1], "pattern") == 0) {
        fb_expected((uint32_t)probe_number("width", argv[2]), (uint32_t)probe_number("height", argv[3]),
                    (unsigned)probe_number("bpp", argv[4]));
    } else {
        fprintf(stderr, "usage: fb_probe info|setbpp|pan|draw|dump DEV [BPP] | pattern W H BPP | kdgraphics TTY\n");
        return 2;
    }
    return 0;
}
