/* SPDX-License-Identifier: MIT */
/* bench_self.c - the running program's path (bench_self.h). */
#include "common/bench_self.h"

#include <unistd.h>

int bench_self_path(char *buf, size_t len)
{
    ssize_t n = readlink("/proc/self/exe", buf, len - 1);
    if (n <= 0)
        return -1;
    buf[n] = '\0';
    return 0;
}
