/* SPDX-License-Identifier: MIT */
/* tsup_faults.c - counting allocator and I/O shim (tsup_faults.h). glibc: the real calls are its __libc_* and RTLD_NEXT. */
#define _GNU_SOURCE
#include "tsup_faults.h"

#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <malloc.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

extern void *__libc_malloc(size_t size);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t size);
extern void __libc_free(void *p);
extern void *__libc_memalign(size_t align, size_t size);

static atomic_bool faults_on;
static atomic_uint_fast64_t faults_allocs, faults_frees, faults_io;
static uint64_t faults_fail_alloc, faults_fail_io;
static atomic_bool faults_fired;

/* The blocks allocated while counting and not yet freed, with their callers, to name a leak. */
#define LIVE_MAX TSUP_FAULTS_LIVE_MAX
static struct {
    void *p;
    void *caller;
} faults_live[LIVE_MAX];
static atomic_flag faults_live_lock = ATOMIC_FLAG_INIT;
static atomic_bool faults_live_overflow;   /* a block found the table full: the leak count cannot be trusted */

static void live_add(void *p, void *caller)
{
    bool kept = false;
    while (atomic_flag_test_and_set(&faults_live_lock))
        ;
    for (int i = 0; i < LIVE_MAX && !kept; i++)
        if (faults_live[i].p == NULL) {
            faults_live[i].p = p;
            faults_live[i].caller = caller;
            kept = true;
        }
    atomic_flag_clear(&faults_live_lock);
    if (!kept)
        atomic_store(&faults_live_overflow, true);
}

static void live_remove(void *p)
{
    while (atomic_flag_test_and_set(&faults_live_lock))
        ;
    for (int i = 0; i < LIVE_MAX; i++)
        if (faults_live[i].p == p) {
            faults_live[i].p = NULL;
            break;
        }
    atomic_flag_clear(&faults_live_lock);
}

/* The dynamic loader's own blocks (the TLS of thread stacks glibc caches for reuse, lazy binding) are not ours to free. */
static bool from_loader(void *caller)
{
    Dl_info where;
    return dladdr(caller, &where) && where.dli_fname && strstr(where.dli_fname, "/ld-linux") != NULL;
}

uint64_t tsup_faults_leaked(void)
{
    if (atomic_load(&faults_live_overflow))
        return UINT64_MAX;
    uint64_t n = 0;
    for (int i = 0; i < LIVE_MAX; i++)
        n += faults_live[i].p != NULL && !from_loader(faults_live[i].caller);
    return n;
}

void tsup_faults_print_live(FILE *f)
{
    for (int i = 0; i < LIVE_MAX; i++)
        if (faults_live[i].p != NULL) {
            Dl_info where;
            int known = dladdr(faults_live[i].caller, &where);
            fprintf(f, "  not freed: block %p allocated from %p (%s, %s)\n", faults_live[i].p, faults_live[i].caller,
                    known && where.dli_fname ? where.dli_fname : "?", known && where.dli_sname ? where.dli_sname : "?");
        }
}

void tsup_faults_start(uint64_t fail_alloc, uint64_t fail_io)
{
    memset(faults_live, 0, sizeof faults_live);
    atomic_store(&faults_live_overflow, false);
    atomic_store(&faults_allocs, 0);
    atomic_store(&faults_frees, 0);
    atomic_store(&faults_io, 0);
    atomic_store(&faults_fired, false);
    faults_fail_alloc = fail_alloc;
    faults_fail_io = fail_io;
    atomic_store(&faults_on, true);
}

tsup_faults_stats_t tsup_faults_now(void)
{
    return (tsup_faults_stats_t){atomic_load(&faults_allocs), atomic_load(&faults_frees), atomic_load(&faults_io),
                                 atomic_load(&faults_fired), atomic_load(&faults_live_overflow)};
}

tsup_faults_stats_t tsup_faults_stop(void)
{
    atomic_store(&faults_on, false);
    return tsup_faults_now();
}

/* Count one allocation; true if this one is to fail. */
static bool alloc_fails(void)
{
    if (!atomic_load(&faults_on))
        return false;
    uint64_t n = atomic_fetch_add(&faults_allocs, 1) + 1;
    if (n == faults_fail_alloc) {
        atomic_fetch_sub(&faults_allocs, 1);   /* a failed call allocated nothing */
        atomic_store(&faults_fired, true);
        errno = ENOMEM;
        return true;
    }
    return false;
}

static bool io_fails(void)
{
    if (!atomic_load(&faults_on))
        return false;
    uint64_t n = atomic_fetch_add(&faults_io, 1) + 1;
    if (n == faults_fail_io) {
        atomic_store(&faults_fired, true);
        errno = EIO;
        return true;
    }
    return false;
}

/* Record a block allocated while counting. */
static void *counted(void *p, void *caller)
{
    if (p != NULL && atomic_load(&faults_on))
        live_add(p, caller);
    return p;
}

void *malloc(size_t size)
{
    return alloc_fails() ? NULL : counted(__libc_malloc(size), __builtin_return_address(0));
}

void *calloc(size_t n, size_t size)
{
    return alloc_fails() ? NULL : counted(__libc_calloc(n, size), __builtin_return_address(0));
}

void *realloc(void *p, size_t size)
{
    if (p == NULL)
        return malloc(size);
    if (size == 0) {
        free(p);
        return NULL;
    }
    /* a growth counts as an allocation (and may fail); the old block stays */
    if (alloc_fails())
        return NULL;
    void *q = __libc_realloc(p, size);
    if (q != NULL && atomic_load(&faults_on)) {
        atomic_fetch_add(&faults_frees, 1);   /* the old block is gone, the new one counted above */
        live_remove(p);
        live_add(q, __builtin_return_address(0));
    }
    return q;
}

void free(void *p)
{
    if (p != NULL && atomic_load(&faults_on)) {
        atomic_fetch_add(&faults_frees, 1);
        live_remove(p);
    }
    __libc_free(p);
}

void *memalign(size_t align, size_t size)
{
    return alloc_fails() ? NULL : counted(__libc_memalign(align, size), __builtin_return_address(0));
}

void *aligned_alloc(size_t align, size_t size)
{
    return memalign(align, size);
}

int posix_memalign(void **out, size_t align, size_t size)
{
    if (align < sizeof(void *) || (align & (align - 1)) != 0)
        return EINVAL;
    void *p = memalign(align, size);
    if (p == NULL)
        return ENOMEM;
    *out = p;
    return 0;
}

/* The C library's own I/O calls, found once (dlsym may allocate: never from inside malloc). */
typedef int (*open_fn)(const char *, int, ...);
typedef int (*openat_fn)(int, const char *, int, ...);
typedef FILE *(*fopen_fn)(const char *, const char *);
typedef ssize_t (*read_fn)(int, void *, size_t);
typedef ssize_t (*pread_fn)(int, void *, size_t, off_t);
#define REAL(name)                  \
    static name##_fn real_##name;   \
    if (!real_##name)               \
        real_##name = (name##_fn)dlsym(RTLD_NEXT, #name)

int open(const char *path, int flags, ...)
{
    REAL(open);
    mode_t mode = 0;
    if (flags & (O_CREAT | O_TMPFILE)) {
        va_list ap;
        va_start(ap, flags);
        mode = (mode_t)va_arg(ap, int);
        va_end(ap);
    }
    return io_fails() ? -1 : real_open(path, flags, mode);
}

int openat(int dir, const char *path, int flags, ...)
{
    REAL(openat);
    mode_t mode = 0;
    if (flags & (O_CREAT | O_TMPFILE)) {
        va_list ap;
        va_start(ap, flags);
        mode = (mode_t)va_arg(ap, int);
        va_end(ap);
    }
    return io_fails() ? -1 : real_openat(dir, path, flags, mode);
}

FILE *fopen(const char *path, const char *how)
{
    REAL(fopen);
    return io_fails() ? NULL : real_fopen(path, how);
}

ssize_t read(int fd, void *buf, size_t n)
{
    REAL(read);
    return io_fails() ? -1 : real_read(fd, buf, n);
}

ssize_t pread(int fd, void *buf, size_t n, off_t at)
{
    REAL(pread);
    return io_fails() ? -1 : real_pread(fd, buf, n, at);
}
