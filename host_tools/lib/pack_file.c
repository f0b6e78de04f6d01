/*
 * pack_file.c - load a scene pack from disk into an aligned buffer and parse
 * it with core's psc_pack_parse (exactly what the device does), and write
 * files atomically.
 */
#include "pack_build.h"
#include "errmsg.h"
#include "file_read.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int psc_pack_file_load(const char *path, psc_pack_file_t *pf, char *err, size_t errlen)
{
    if (!path || !pf)
        return psc_errorf(err, errlen, path ? path : "(pack)", "no file or no pack to load into");
    memset(pf, 0, sizeof *pf);
    if (psc_read_file_aligned(path, UINT32_MAX, &pf->buf, &pf->len, err, errlen) != 0)
        return -1;
    psc_container_error_t perr = {0};
    psc_status_t s = psc_pack_parse(pf->buf, pf->len, &pf->pack, &perr);
    if (s != PSC_OK) {
        psc_errorf(err, errlen, path, "%s (offset %u): %s", perr.what ? perr.what : "invalid pack",
                  (unsigned)perr.offset, psc_status_str(s));
        psc_pack_file_free(pf);
        return -1;
    }
    return 0;
}

void psc_pack_file_free(psc_pack_file_t *pf)
{
    if (!pf)
        return;
    free(pf->buf);
    memset(pf, 0, sizeof *pf);
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

int psc_write_file(const char *path, const void *data, size_t len, char *err, size_t errlen)
{
    /* The temporary sits beside the target so that rename() stays within one
     * file system and readers never see a half-written file. */
    if (!path || (!data && len > 0))
        return psc_errorf(err, errlen, path ? path : "(file)", "no file name or no data to write");
    size_t plen = strlen(path);
    char *tmp = malloc(plen + 32);
    if (!tmp)
        return psc_errorf(err, errlen, path, "out of memory");
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
        return psc_errorf(err, errlen, path, "cannot create a temporary file beside it: %s", strerror(e));
    }
    int rc = 0;
    if (write_all(fd, data, len) != 0)
        rc = psc_errorf(err, errlen, path, "write error: %s", strerror(errno));
    if (close(fd) != 0 && rc == 0)
        rc = psc_errorf(err, errlen, path, "write error on close: %s", strerror(errno));
    if (rc == 0 && rename(tmp, path) != 0)
        rc = psc_errorf(err, errlen, path, "cannot replace the file: %s", strerror(errno));
    if (rc != 0)
        unlink(tmp);
    free(tmp);
    return rc;
}
