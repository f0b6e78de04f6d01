/* SPDX-License-Identifier: MIT */
/* note_text.c - remarks for the user (note_text.h). */
#include "util/note_text.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

void psc_note_add(char *note, size_t notelen, const char *fmt, ...)
{
    if (note == NULL || notelen == 0)
        return;
    size_t used = strnlen(note, notelen);
    if (used + 3 >= notelen)
        return;
    if (used)
        used += (size_t)snprintf(note + used, notelen - used, "; ");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(note + used, notelen - used, fmt, ap);
    va_end(ap);
}
