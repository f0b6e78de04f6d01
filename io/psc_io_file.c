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

int psc_io_read_aligned(const char *path, uint64_t max_size, void **buf, size_t *len, char *err, size_t errlen)
{
    *buf = NULL;
    *len = 0;
    int fd = open(path, O_RDONLY);
    if (fd < 0)
        return psc_io_errorf(err, errlen, path, "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return psc_io_errorf(err, errlen, path, "cannot stat: %s", strerror(e));
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return psc_io_errorf(err, errlen, path, "not a regular file");
    }
    if (st.st_size <= 0 || (uint64_t)st.st_size > max_size) {
        close(fd);
        if (st.st_size <= 0)
            return psc_io_errorf(err, errlen, path, "file is empty");
        return psc_io_errorf(err, errlen, path, "file is larger than %llu bytes", (unsigned long long)max_size);
    }
    size_t size = (size_t)st.st_size;
    void *mem = NULL;
    if (!(mem = psc_io_alloc_large(size))) {
        close(fd);
        return psc_io_errorf(err, errlen, path, "out of memory for %zu bytes", size);
    }
    size_t got = 0;
    while (got < size) {
        ssize_t n = read(fd, (uint8_t *)mem + got, size - got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            int e = errno;
            close(fd);
            free(mem);
            return n == 0 ? psc_io_errorf(err, errlen, path, "file shrank while being read")
                          : psc_io_errorf(err, errlen, path, "read error: %s", strerror(e));
        }
        got += (size_t)n;
    }
    close(fd);
    *buf = mem;
    *len = size;
    return 0;
}

static int write_all(int fd, const void *data, size_t len)
{
    const uint8_t *p = data;
    while (len > 0) {
        ssize_t n = write(fd, p, len);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return -1;
        p += n;
        len -= (size_t)n;
    }
    return 0;
}

int psc_io_write_atomic(const char *path, const void *data, size_t len, char *err, size_t errlen)
{
    /* The temporary sits beside the target so that rename() stays within one
     * file system and readers never see a half-written file. */
    if (!path || (!data && len > 0))
        return psc_io_errorf(err, errlen, path ? path : "(file)", "no file name or no data to write");
    size_t plen = strlen(path);
    char *tmp = malloc(plen + 32);
    if (!tmp)
        return psc_io_errorf(err, errlen, path, "out of memory");
    int fd = -1;
    for (unsigned attempt = 0; attempt < 100 && fd < 0; attempt++) {
        snprintf(tmp, plen + 32, "%s.tmp%ld.%u", path, (long)getpid(), attempt);
        fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd < 0 && errno != EEXIST)
            break;
    }
    if (fd < 0) {
        int e = errno;
        free(tmp);
        return psc_io_errorf(err, errlen, path, "cannot create a temporary file beside it: %s", strerror(e));
    }
    int rc = 0;
    if (write_all(fd, data, len) != 0)
        rc = psc_io_errorf(err, errlen, path, "write error: %s", strerror(errno));
    if (close(fd) != 0 && rc == 0)
        rc = psc_io_errorf(err, errlen, path, "write error on close: %s", strerror(errno));
    if (rc == 0 && rename(tmp, path) != 0)
        rc = psc_io_errorf(err, errlen, path, "cannot replace the file: %s", strerror(errno));
    if (rc != 0)
        unlink(tmp);
    free(tmp);
    return rc;
}

bool psc_io_file_has_magic(const char *path, const char *magic, size_t n)
{
    char head[16];
    FILE *f;
    bool yes;

    if (n > sizeof head || (f = fopen(path, "rb")) == NULL)
        return false;
    yes = fread(head, 1, n, f) == n && memcmp(head, magic, n) == 0;
    fclose(f);
    return yes;
}

bool psc_io_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}
