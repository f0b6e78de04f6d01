/* SPDX-License-Identifier: MIT */
/* tsup_files.c - scratch files and message checks for the file-parser tests (see tsup_files.h). */
#include "tsup_files.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void tsup_tmp_path(char *buf, size_t n, const char *prefix, const char *name)
{
    const char *dir = getenv("PSC_TEST_TMPDIR");
    snprintf(buf, n, "%s/%s_%ld_%s", dir && *dir ? dir : "/tmp", prefix, (long)getpid(), name);
}

int tsup_write_bytes(const char *path, const void *data, size_t len)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    size_t put = len ? fwrite(data, 1, len, f) : 0;
    int rc = fclose(f);
    return put == len && rc == 0 ? 0 : -1;
}

uint8_t *tsup_read_bytes(const char *path, size_t *len)
{
    *len = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 4096, n = 0;
    uint8_t *buf = malloc(cap + 1);
    while (buf) {
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (n < cap) {
            if (ferror(f)) {
                free(buf);
                buf = NULL;
            }
            break;
        }
        uint8_t *grown = realloc(buf, 2 * cap + 1);
        if (!grown) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = grown;
        cap *= 2;
    }
    fclose(f);
    if (buf) {
        buf[n] = 0;
        *len = n;
    }
    return buf;
}

int tsup_file_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

int tsup_msg_starts_with_path(const char *msg, const char *path)
{
    size_t n = strlen(path);
    return msg && strncmp(msg, path, n) == 0 && msg[n] == ':' && msg[n + 1] == ' ' && msg[n + 2] != '\0';
}

unsigned tsup_count_names(const char *dir, const char *prefix, const char *part)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    unsigned n = 0;
    size_t plen = strlen(prefix);

    if (d == NULL)
        return 0;
    while ((e = readdir(d)) != NULL)
        n += strncmp(e->d_name, prefix, plen) == 0 && strstr(e->d_name + plen, part) != NULL;
    closedir(d);
    return n;
}

int tsup_same_file(const char *a, const char *b)
{
    size_t la, lb;
    uint8_t *pa = tsup_read_bytes(a, &la), *pb = tsup_read_bytes(b, &lb);
    int same = pa && pb && la == lb && memcmp(pa, pb, la) == 0;
    free(pa);
    free(pb);
    return same;
}

const char *tsup_thom_scene_line(void)
{
    static char line[540];
    char cwd[512];

    if (access("out/thom.ppk", R_OK) != 0 || getcwd(cwd, sizeof cwd) == NULL)
        return "";
    snprintf(line, sizeof line, "scene = %s/out/thom.ppk\n", cwd);
    return line;
}
