/* SPDX-License-Identifier: MIT */
/* text_out.c - text files written whole (text_out.h). */
#include "util/text_out.h"
#include "psc_io_error.h"
#include "psc_io_file.h"

#include <stdlib.h>

int psc_text_out_begin(psc_text_out_t *t, const char *path, char *err, size_t errlen)
{
    t->text = NULL;
    t->len = 0;
    t->f = open_memstream(&t->text, &t->len);
    return t->f ? 0 : psc_io_errorf(err, errlen, path, "out of memory");
}

int psc_text_out_finish(psc_text_out_t *t, const char *path, char *err, size_t errlen)
{
    int rc = fclose(t->f) != 0 ? psc_io_errorf(err, errlen, path, "out of memory")
                               : psc_io_write_atomic(path, t->text, t->len, err, errlen);
    free(t->text);
    t->text = NULL;
    t->f = NULL;
    return rc;
}
