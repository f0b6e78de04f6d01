/* SPDX-License-Identifier: MIT */
/* psc_io_file.c - whole files into aligned memory, atomic replacement (psc_io_file.h). */
#include "psc_io_file.h"
#include "psc_io_error.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#define HUGE_PAGE_BYTES ((size_t)2 << 20)
#define HUGE_FILE_BYTES ((size_t)4 << 20)

/*
 * A large buffer (a scene pack's map) on huge pages where the kernel offers
 * them: the viewer reads the map along curves, and each scanline of a new
 * view would otherwise walk the page tables for fresh 4 KiB pages (measured:
 * about 10% off the time of a frame of a new view, 800x480 of a 4096x2048
 * map). The advice is only advice: 4 KiB pages serve too.
 */
void *psc_io_alloc_large(size_t size)
{
    void *mem = NULL;
    size_t align = size >= HUGE_FILE_BYTES ? HUGE_PAGE_BYTES : PSC_IO_FILE_ALIGN;
    if (size == 0 || posix_memalign(&mem, align, size) != 0)
        return NULL;
#ifdef MADV_HUGEPAGE
    if (align == HUGE_PAGE_BYTES)
        (void)madvise(mem, size, MADV_HUGEPAGE);
#endif
    return mem;
}

int psc_io_open_regular(const char *path, uint64_t max_size, int *fd_out, uint64_t *size, char *err, size_t errlen)
{
    *fd_out = -1;
    *size = 0;
    if (!path)
        return psc_io_errorf(err, errlen, "(file)", "no file name");
    /* O_NONBLOCK: opening a FIFO for reading would wait for a writer forever */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0)
        return psc_io_errorf(err, errlen, path, "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return psc_io_errorf(err, errlen, path, "cannot stat: %s", strerror(e));
    }
    const char *kind = S_ISDIR(st.st_mode) ? "a directory" : S_ISFIFO(st.st_mode) ? "a FIFO"
                     : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device" : S_ISSOCK(st.st_mode) ? "a socket"
                     : NULL;
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return psc_io_errorf(err, errlen, path, "not a regular file (%s)", kind ? kind : "a special file");
    }
    if (st.st_size <= 0) {
        close(fd);
        return psc_io_errorf(err, errlen, path, "file is empty");
    }
    if ((uint64_t)st.st_size > max_size) {
        close(fd);
        return psc_io_errorf(err, errlen, path, "file is %llu bytes, larger than the limit of %llu bytes",
                             (unsigned long long)st.st_size, (unsigned long long)max_size);
    }
    /* back to blocking reads: a regular file never waits long */
    int flags = fcntl(fd, F_GETFL);
    if (flags >= 0)
        (void)fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    *fd_out = fd;
    *size = (uint64_t)st.st_size;
    return 0;
}

int psc_io_read_at(int fd, const char *path, void *dst, size_t len, uint64_t at, char *err, size_t errlen)
{
    size_t got = 0;
    while (got < len) {
        ssize_t n = pread(fd, (uint8_t *)dst + got, len - got, (off_t)(at + got));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return n == 0 ? psc_io_errorf(err, errlen, path, "file shrank while being read")
                          : psc_io_errorf(err, errlen, path, "read error: %s", strerror(errno));
        got += (size_t)n;
    }
    return 0;
}

FILE *psc_io_fopen_regular(const char *path, uint64_t max_size, char *err, size_t errlen)
{
    int fd;
    uint64_t size;
    if (psc_io_open_regular(path, max_size, &fd, &size, err, errlen) != 0)
        return NULL;
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        psc_io_errorf(err, errlen, path, "cannot open: %s", strerror(errno));
        close(fd);
    }
    return f;
}

int psc_io_read_fd_aligned(int fd, const char *path, uint64_t size, void **buf, size_t *len, char *err,
                           size_t errlen)
{
    *buf = NULL;
    *len = 0;
    if (size > SIZE_MAX)
        return psc_io_errorf(err, errlen, path, "file of %llu bytes does not fit in memory",
                             (unsigned long long)size);
    void *mem = psc_io_alloc_large((size_t)size);
    if (!mem)
        return psc_io_errorf(err, errlen, path, "out of memory for %llu bytes", (unsigned long long)size);
    if (psc_io_read_at(fd, path, mem, (size_t)size, 0, err, errlen) != 0) {
        free(mem);
        return -1;
    }
    *buf = mem;
    *len = (size_t)size;
    return 0;
}

int psc_io_read_aligned(const char *path, uint64_t max_size, void **buf, size_t *len, char *err, size_t errlen)
{
    int fd;
    uint64_t size;
    *buf = NULL;
    *len = 0;
    if (psc_io_open_regular(path, max_size, &fd, &size, err, errlen) != 0)
        return -1;
    int rc = psc_io_read_fd_aligned(fd, path, size, buf, len, err, errlen);
    close(fd);
    return rc;
}

bool psc_io_file_has_magic(const char *path, const char *magic, size_t n)
{
    char head[16];
    int fd;
    uint64_t size;

    /* a FIFO or a device is no file of ours: never opened for a blocking read */
    if (n > sizeof head || psc_io_open_regular(path, UINT64_MAX, &fd, &size, NULL, 0) != 0)
        return false;
    bool yes = size >= n && psc_io_read_at(fd, path, head, n, 0, NULL, 0) == 0 && memcmp(head, magic, n) == 0;
    close(fd);
    return yes;
}

bool psc_io_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}
