/* SPDX-License-Identifier: MIT */
/*
 * fuzz_image_rows.c - JPEG and PNG files read row by row
 * (io/psc_io_image_rows.h). The reader takes a path, so the input is written
 * to one temporary file (made once, under $TMPDIR or /tmp, removed at exit).
 * The limits are a 4096 x 2048 panorama's, so the fuzzer spends its time on
 * the decoders, not on huge images (larger ones are refused from the header).
 * A refusal or a failed row must name the file; an opened image lies within
 * the limits, every row's pixels have 0xFF in the top byte, a failed read
 * stays failed, and reading past the last row fails; everything is freed.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_support.h"
#include "psc_io_image_rows.h"

#define MAX_W 4096u
#define MAX_H 2048u

static char fuzz_rows_path[4096];
static int fuzz_rows_fd = -1;

static void fuzz_rows_cleanup(void)
{
    if (fuzz_rows_fd >= 0) {
        close(fuzz_rows_fd);
        unlink(fuzz_rows_path);
        fuzz_rows_fd = -1;
    }
}

/* The temporary file, holding exactly the input. */
static const char *fuzz_rows_file(const uint8_t *data, size_t size)
{
    if (fuzz_rows_fd < 0) {
        const char *dir = getenv("TMPDIR");
        snprintf(fuzz_rows_path, sizeof fuzz_rows_path, "%s/fuzz_image_rows_XXXXXX", dir && *dir ? dir : "/tmp");
        fuzz_rows_fd = mkstemp(fuzz_rows_path);
        FUZZ_REQUIRE(fuzz_rows_fd >= 0);
        atexit(fuzz_rows_cleanup);
    }
    FUZZ_REQUIRE(ftruncate(fuzz_rows_fd, 0) == 0);
    for (size_t done = 0; done < size;) {
        ssize_t n = pwrite(fuzz_rows_fd, data + done, size - done, (off_t)done);
        FUZZ_REQUIRE(n > 0);
        done += (size_t)n;
    }
    return fuzz_rows_path;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_rows_file(data, size);
    psc_io_image_rows_t *r = NULL;
    char err[512] = "";

    if (psc_io_image_rows_open(path, MAX_W, MAX_H, &r, err, sizeof err) != 0) {
        FUZZ_REQUIRE(r == NULL);
        fuzz_require_message_names(err, path);
        return 0;
    }
    FUZZ_REQUIRE(r != NULL);
    uint32_t w = 0, h = 0;
    psc_io_image_rows_size(r, &w, &h);
    FUZZ_REQUIRE(w >= 1 && w <= MAX_W && h >= 1 && h <= MAX_H);
    uint32_t *row = malloc((size_t)w * sizeof *row);
    FUZZ_REQUIRE(row != NULL);
    uint32_t y = 0;
    for (; y < h; y++) {
        if (psc_io_image_rows_next(r, row, err, sizeof err) != 0) {
            fuzz_require_message_names(err, path);
            FUZZ_REQUIRE(strstr(err, "row") != NULL);
            break;
        }
        for (uint32_t x = 0; x < w; x++)
            FUZZ_REQUIRE((row[x] >> 24) == 0xFFu);
    }
    /* Past the last row, or after a failure: an error, never a row. */
    err[0] = '\0';
    FUZZ_REQUIRE(psc_io_image_rows_next(r, row, err, sizeof err) == -1);
    fuzz_require_message_names(err, path);
    free(row);
    psc_io_image_rows_close(r);
    return 0;
}
