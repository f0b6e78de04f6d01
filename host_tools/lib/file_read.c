/* file_read.c - whole files into aligned memory for the in-place parsers (file_read.h). */
#include "file_read.h"
#include "errmsg.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int psc_read_file_aligned(const char *path, uint64_t max_size, void **buf, size_t *len, char *err, size_t errlen)
{
    *buf = NULL;
    *len = 0;
    int fd = open(path, O_RDONLY);
    if (fd < 0)
        return psc_errorf(err, errlen, path, "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return psc_errorf(err, errlen, path, "cannot stat: %s", strerror(e));
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return psc_errorf(err, errlen, path, "not a regular file");
    }
    if (st.st_size <= 0 || (uint64_t)st.st_size > max_size) {
        close(fd);
        if (st.st_size <= 0)
            return psc_errorf(err, errlen, path, "file is empty");
        return psc_errorf(err, errlen, path, "file is larger than %llu bytes", (unsigned long long)max_size);
    }
    size_t size = (size_t)st.st_size;
    void *mem = NULL;
    if (posix_memalign(&mem, PSC_FILE_ALIGN, size) != 0) {
        close(fd);
        return psc_errorf(err, errlen, path, "out of memory for %zu bytes", size);
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
            return n == 0 ? psc_errorf(err, errlen, path, "file shrank while being read")
                          : psc_errorf(err, errlen, path, "read error: %s", strerror(e));
        }
        got += (size_t)n;
    }
    close(fd);
    *buf = mem;
    *len = size;
    return 0;
}

