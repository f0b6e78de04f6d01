/* SPDX-License-Identifier: MIT */
/*
 * psc_io_atomic.h - write a file so that nobody ever sees half of it: the
 * bytes go to a temporary beside the target (same directory, so the rename
 * stays on one file system), which is flushed to the disk (fsync) and renamed
 * over the target; the directory is flushed too, so the new name survives a
 * power cut. On any error the temporary is removed and the target is left as
 * it was. A signal that would end the program (SIGINT, SIGTERM, SIGHUP,
 * SIGQUIT, SIGXFSZ: a file-size limit) while a temporary exists removes it
 * first, unless the program handles or ignores that signal itself (then its
 * own handler decides, and the write finishes or fails as usual).
 *
 * A target that exists and is not a regular file (a FIFO, /dev/null, a
 * terminal) is written in place: there is nothing to rename over it.
 *
 * No allocation: the temporary's name lives in the writer, so the device
 * program's frame loop can use it (frame dumps).
 */
#ifndef PSC_IO_ATOMIC_H
#define PSC_IO_ATOMIC_H

#include <stdbool.h>
#include <stddef.h>

/* the longest target path, and room for ".tmp<pid>.<n>" after it */
#define PSC_IO_ATOMIC_PATH_MAX 4096u
#define PSC_IO_ATOMIC_SUFFIX_MAX 32u

typedef struct {
    int fd;              /* -1 when closed */
    int slot;            /* the signal clean-up's record of tmp, -1 when none */
    bool direct;         /* writing into a non-regular target in place */
    const char *path;    /* the target (the caller's string) */
    char tmp[PSC_IO_ATOMIC_PATH_MAX + PSC_IO_ATOMIC_SUFFIX_MAX];
} psc_io_atomic_t;

/** Start writing path. 0, or -1 with err naming the file and the problem (nothing created). */
int psc_io_atomic_begin(psc_io_atomic_t *w, const char *path, char *err, size_t errlen);

/** Append len bytes. 0, or -1 with err (the writer is aborted: the temporary is gone). */
int psc_io_atomic_write(psc_io_atomic_t *w, const void *data, size_t len, char *err, size_t errlen);

/** fsync, close and rename over the target, then fsync the directory. 0, or -1 with err (aborted). */
int psc_io_atomic_commit(psc_io_atomic_t *w, char *err, size_t errlen);

/** Give up: close and remove the temporary (safe after a failed call, and twice). */
void psc_io_atomic_abort(psc_io_atomic_t *w);

#endif
