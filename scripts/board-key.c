/* SPDX-License-Identifier: MIT */
/*
 * board-key.c - the build's reader of board files: the device program's own
 * (firmware/board_file.c), built for the machine that builds, so make and
 * the cross and image scripts read a key exactly as the device does, before
 * anything else is built. scripts/board-key builds and runs it.
 *
 *   board-key FILE KEY    print KEY's value; exit 0, 1 when no line sets it,
 *                         2 when the file cannot be read or is malformed
 */
#include <stdio.h>

#include "board_file.h"

int main(int argc, char **argv)
{
    char value[PSC_BOARD_LINE_MAX], err[512];
    int rc;

    if (argc != 3) {
        fprintf(stderr, "usage: board-key FILE KEY\n");
        return 2;
    }
    rc = psc_board_file_value(argv[1], argv[2], value, sizeof value, err, sizeof err);
    if (rc < 0) {
        fprintf(stderr, "board-key: %s\n", err);
        return 2;
    }
    if (rc == 0)
        return 1;
    printf("%s\n", value);
    return 0;
}
