/* SPDX-License-Identifier: MIT */
/*
 * psc_io_log.h - the device program's log lines, one line per event, with
 * the priority systemd's journal reads when it is the one listening.
 *
 * Under systemd (StandardOutput/StandardError=journal) the service manager
 * sets JOURNAL_STREAM to "DEVICE:INODE" of the stream it connected; when
 * stdout or stderr is that very stream, each line starts with the
 * sd-daemon(3) prefix "<N>" (3 err, 4 warning, 5 notice, 6 info, 7 debug), so
 * `journalctl -p err` finds the errors and `-p warning` the warnings. On a
 * terminal, a pipe or a file nothing is added: the lines read as before.
 *
 * Errors and warnings go to stderr, notices and information to stdout (where
 * the frame-by-frame lines have always been). A message's own newlines
 * become "; " so an event stays one journal entry, and each line is written
 * with one write(2), so threads do not interleave inside a line. No
 * allocation (a line is at most PSC_LOG_LINE_MAX bytes, longer ones cut
 * with "...").
 */
#ifndef PSC_IO_LOG_H
#define PSC_IO_LOG_H

#include <stdbool.h>
#include <stdio.h>

#define PSC_LOG_LINE_MAX 1024u

typedef enum {
    PSC_LOG_ERR = 3,
    PSC_LOG_WARNING = 4,
    PSC_LOG_NOTICE = 5,
    PSC_LOG_INFO = 6,
    PSC_LOG_DEBUG = 7
} psc_log_level_t;

/** Log one event at level (printf format, no trailing newline needed). */
void psc_io_log(psc_log_level_t level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/**
 * Look again at JOURNAL_STREAM and the two streams (done once, on the first
 * line, by itself; tests that swap the streams call it).
 */
void psc_io_log_detect(void);

/** True when lines on stream (stdout or stderr) get the journal's "<N>" prefix. */
bool psc_io_log_to_journal(FILE *stream);

#endif
