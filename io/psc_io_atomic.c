/* SPDX-License-Identifier: MIT */
/* psc_io_atomic.c - temporary, fsync, rename; temporaries removed on fatal signals (psc_io_atomic.h). */
#include "psc_io_atomic.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The temporaries being written right now, for the signal handler: a few
 * threads may write at once (the host tools' workers do not, but nothing
 * forbids it); a writer that finds no free slot still works, unprotected. */
#define ATOMIC_SLOTS 8
static _Atomic(const char *) atomic_live[ATOMIC_SLOTS];
static const int atomic_fatal_signals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGXFSZ};

/* Async-signal-safe: unlink, sigaction and raise only. SA_RESETHAND has put
 * the default action back, so the signal raised again ends the program as it
 * would have without us. */
static void atomic_on_fatal_signal(int sig)
{
    for (int i = 0; i < ATOMIC_SLOTS; i++) {
        const char *tmp = atomic_load(&atomic_live[i]);
        if (tmp)
            unlink(tmp);
    }
    raise(sig);
}

/* Only where the program left the default action: a program that handles
 * SIGTERM itself (the device program stops its loop) keeps its handler.
 * Checked at every write (five sigaction calls), since a program may have
 * put a default back in between. */
static void atomic_catch_fatal_signals(void)
{
    for (size_t i = 0; i < sizeof atomic_fatal_signals / sizeof atomic_fatal_signals[0]; i++) {
        struct sigaction old, sa;
        if (sigaction(atomic_fatal_signals[i], NULL, &old) != 0 || old.sa_handler != SIG_DFL ||
            (old.sa_flags & SA_SIGINFO))
            continue;
        memset(&sa, 0, sizeof sa);
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = SA_RESETHAND;
        sa.sa_handler = atomic_on_fatal_signal;
        sigaction(atomic_fatal_signals[i], &sa, NULL);
    }
}

static int atomic_claim_slot(const char *tmp)
{
    for (int i = 0; i < ATOMIC_SLOTS; i++) {
        const char *none = NULL;
        if (atomic_compare_exchange_strong(&atomic_live[i], &none, tmp))
            return i;
    }
    return -1;
}

static void atomic_release_slot(psc_io_atomic_t *w)
{
    if (w->slot >= 0)
        atomic_store(&atomic_live[w->slot], NULL);
    w->slot = -1;
}

void psc_io_atomic_abort(psc_io_atomic_t *w)
{
    if (w->fd >= 0)
        close(w->fd);
    w->fd = -1;
    if (!w->direct && w->tmp[0] != '\0')
        unlink(w->tmp);
    atomic_release_slot(w);
    w->tmp[0] = '\0';
}

/* A target that exists but is no regular file: a FIFO or a device is written in place. */
static bool atomic_target_is_special(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

int psc_io_atomic_begin(psc_io_atomic_t *w, const char *path, char *err, size_t errlen)
{
    w->fd = -1;
    w->slot = -1;
    w->direct = false;
    w->path = path;
    w->tmp[0] = '\0';
    if (!path || !path[0])
        return psc_io_errorf(err, errlen, "(file)", "no file name to write");
    size_t plen = strlen(path);
    if (plen >= PSC_IO_ATOMIC_PATH_MAX)
        return psc_io_errorf(err, errlen, path, "file name longer than %u bytes", PSC_IO_ATOMIC_PATH_MAX - 1u);
    if (atomic_target_is_special(path)) {
        w->direct = true;
        w->fd = open(path, O_WRONLY | O_CLOEXEC | O_NOCTTY);
        if (w->fd < 0)
            return psc_io_errorf(err, errlen, path, "cannot open for writing: %s", strerror(errno));
        return 0;
    }
    atomic_catch_fatal_signals();
    for (unsigned attempt = 0; attempt < 100 && w->fd < 0; attempt++) {
        snprintf(w->tmp, sizeof w->tmp, "%s.tmp%ld.%u", path, (long)getpid(), attempt);
        /* recorded before it exists: a signal between open and the record would leave it behind */
        if (w->slot < 0)
            w->slot = atomic_claim_slot(w->tmp);
        w->fd = open(w->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (w->fd < 0 && errno != EEXIST)
            break;
    }
    if (w->fd < 0) {
        int e = errno;
        atomic_release_slot(w);
        w->tmp[0] = '\0';
        return psc_io_errorf(err, errlen, path, "cannot create a temporary file beside it: %s", strerror(e));
    }
    return 0;
}

int psc_io_atomic_write(psc_io_atomic_t *w, const void *data, size_t len, char *err, size_t errlen)
{
    const uint8_t *p = data;
    if (w->fd < 0)
        return psc_io_errorf(err, errlen, w->path, "write after an earlier error");
    while (len > 0) {
        ssize_t n = write(w->fd, p, len);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            int e = n < 0 ? errno : ENOSPC;
            psc_io_atomic_abort(w);
            return psc_io_errorf(err, errlen, w->path, "write error: %s%s", strerror(e),
                                 w->direct ? "" : " (nothing written: the file is as it was)");
        }
        p += n;
        len -= (size_t)n;
    }
    return 0;
}

/* The rename is on the disk only once the directory is: fsync it (some file
 * systems cannot, which is no error of ours). */
static void atomic_sync_directory(const char *path)
{
    char dir[PSC_IO_ATOMIC_PATH_MAX];
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else if (slash == path)
        snprintf(dir, sizeof dir, "/");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        (void)fsync(fd);
        close(fd);
    }
}

int psc_io_atomic_commit(psc_io_atomic_t *w, char *err, size_t errlen)
{
    if (w->fd < 0)
        return psc_io_errorf(err, errlen, w->path, "commit after an earlier error");
    if (w->direct) {
        int rc = close(w->fd) == 0 ? 0 : psc_io_errorf(err, errlen, w->path, "write error on close: %s",
                                                       strerror(errno));
        w->fd = -1;
        return rc;
    }
    /* fsync before rename: otherwise a power cut can leave the new name on an empty file */
    if (fsync(w->fd) != 0 && errno != EINVAL) {
        int e = errno;
        psc_io_atomic_abort(w);
        return psc_io_errorf(err, errlen, w->path, "cannot flush to the disk: %s (the file is as it was)",
                             strerror(e));
    }
    int rc = close(w->fd);
    w->fd = -1;
    if (rc != 0) {
        int e = errno;
        psc_io_atomic_abort(w);
        return psc_io_errorf(err, errlen, w->path, "write error on close: %s (the file is as it was)", strerror(e));
    }
    if (rename(w->tmp, w->path) != 0) {
        int e = errno;
        psc_io_atomic_abort(w);
        return psc_io_errorf(err, errlen, w->path, "cannot replace the file: %s", strerror(e));
    }
    atomic_release_slot(w);
    w->tmp[0] = '\0';
    atomic_sync_directory(w->path);
    return 0;
}

int psc_io_write_atomic(const char *path, const void *data, size_t len, char *err, size_t errlen)
{
    psc_io_atomic_t w;
    if (!data && len > 0)
        return psc_io_errorf(err, errlen, path ? path : "(file)", "no data to write");
    if (psc_io_atomic_begin(&w, path, err, errlen) != 0 || psc_io_atomic_write(&w, data, len, err, errlen) != 0)
        return -1;
    return psc_io_atomic_commit(&w, err, errlen);
}
