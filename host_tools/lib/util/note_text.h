/* SPDX-License-Identifier: MIT */
/* note_text.h - remarks the host builders collect for the user ("a; b; c"), bounded. */
#ifndef PSC_UTIL_NOTE_TEXT_H
#define PSC_UTIL_NOTE_TEXT_H

#include <stddef.h>

/** Append a remark to note[0..notelen) (NUL-terminated; NULL or 0 ignores it), "; " between remarks. */
void psc_note_add(char *note, size_t notelen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

#endif
