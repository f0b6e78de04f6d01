/* SPDX-License-Identifier: MIT */
/* psc_io_log.c - log lines with journald priorities (psc_io_log.h). */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include <sys/stat.h>
#include <unistd.h>

#include "psc_io_log.h"

static bool log_detected, log_journal_out, log_journal_err;

/* Is fd the stream systemd says it connected to the journal ("DEV:INO")? */
static bool log_fd_is_journal(int fd, const char *stream)
{
    unsigned long long dev, ino;
    struct stat st;
    char tail;

    if (stream == NULL || sscanf(stream, "%llu:%llu%c", &dev, &ino, &tail) != 2 || fstat(fd, &st) != 0)
        return false;
    return (unsigned long long)st.st_dev == dev && (unsigned long long)st.st_ino == ino;
}

void psc_io_log_detect(void)
{
    const char *stream = getenv("JOURNAL_STREAM");

    log_journal_out = log_fd_is_journal(STDOUT_FILENO, stream);
    log_journal_err = log_fd_is_journal(STDERR_FILENO, stream);
    log_detected = true;
}

bool psc_io_log_to_journal(FILE *stream)
{
    if (!log_detected)
        psc_io_log_detect();
    return stream == stderr ? log_journal_err : stream == stdout ? log_journal_out : false;
}

void psc_io_log(psc_log_level_t level, const char *fmt, ...)
{
    FILE *stream = level <= PSC_LOG_WARNING ? stderr : stdout;
    char line[PSC_LOG_LINE_MAX + 8];
    size_t n = 0, len;
    va_list ap;
    int w;

    if (psc_io_log_to_journal(stream))
        n = (size_t)snprintf(line, sizeof line, "<%d>", (int)level);
    va_start(ap, fmt);
    w = vsnprintf(line + n, PSC_LOG_LINE_MAX - n, fmt, ap);
    va_end(ap);
    if (w < 0)
        return;
    len = strlen(line);
    if ((size_t)w >= PSC_LOG_LINE_MAX - n)
        memcpy(line + len - 3, "...", 3);   /* cut, and saying so */
    while (len > n && line[len - 1] == '\n')
        len--;
    /* one event, one line: inner newlines become "; " (a tab would do, but reads worse) */
    char out[2 * PSC_LOG_LINE_MAX + 8];
    size_t o = 0;
    for (size_t i = 0; i < len; i++) {
        if (line[i] == '\n') {
            out[o++] = ';';
            out[o++] = ' ';
        } else {
            out[o++] = line[i];
        }
    }
    out[o++] = '\n';
    fflush(stream);   /* what stdio holds goes first: lines stay in order */
    for (size_t done = 0; done < o;) {
        ssize_t r = write(fileno(stream), out + done, o - done);
        if (r <= 0)
            break;   /* a log that cannot be written is not the kiosk's failure */
        done += (size_t)r;
    }
}
