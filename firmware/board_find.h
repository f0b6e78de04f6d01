/* SPDX-License-Identifier: MIT */
/*
 * board_find.h - where the device program finds boards/NAME/board.conf when
 * no --boards-dir is given: the first of these places that has it,
 *
 *   1. boards            (the working directory's: `make run` in the repository)
 *   2. REPO/boards       beside the program in a build tree: the program is
 *                        REPO/build/bin/periscope or REPO/build/SUB/bin/periscope
 *                        (from /proc/self/exe; the first of the bin directory's
 *                        grandparent and great-grandparent that has a boards/)
 *   3. /etc/periscope/boards        (a device maker's own boards; the package's)
 *   4. PSC_CLI_INSTALLED_BOARDS     (cli.h: where the package installs boards,
 *                                    listed once when it is 3)
 *
 * A place that is the same directory as an earlier one is left out. When none
 * has the board, the message names the board and every place looked. A board
 * file's relative paths are its own folder's (board_config.c), wherever it is
 * found. An explicit --boards-dir is taken as it is, without looking.
 */
#ifndef PSC_BOARD_FIND_H
#define PSC_BOARD_FIND_H

#include <stddef.h>

#include "board_config.h"

#define PSC_BOARD_FIND_MAX 4u
#define PSC_BOARD_FIND_ETC "/etc/periscope/boards"

/** The places to look, in order; dirs point at literals or into tree. */
typedef struct {
    const char *dirs[PSC_BOARD_FIND_MAX];
    unsigned count;
    char tree[PSC_BOARD_PATH_MAX];   /* place 2, when the program is in a build tree */
} psc_board_places_t;

/**
 * The build tree's boards directory for the program at exe (an absolute
 * path, as /proc/self/exe gives it): when exe's directory is named "bin", the
 * first of its grandparent and great-grandparent that has a boards/
 * directory, as "<that>/boards" in out. 0, or -1 when exe is not in a build
 * tree (or the path does not fit).
 */
int psc_board_find_tree(const char *exe, char *out, size_t outlen);

/** The default places 1-4 above, for this program (/proc/self/exe). */
void psc_board_places_default(psc_board_places_t *p);

/** The places as the message names them: "./boards, /x/boards, ..." (a relative DIR as ./DIR). */
void psc_board_places_text(const char *const *dirs, unsigned count, char *buf, size_t n);

/**
 * The first of dirs[0..count) with board/board.conf in it: its index, or -1
 * with err = "board 'NAME': no NAME/board.conf in PLACES (--boards-dir DIR
 * names another)". Only looks (stat); reading the file is the loader's.
 */
int psc_board_find(const char *const *dirs, unsigned count, const char *board, char *err, size_t errlen);

/**
 * psc_board_find over the default places: 0 with the place in dir (dirlen
 * bytes), or -1 with err as psc_board_find's.
 */
int psc_board_find_default(const char *board, char *dir, size_t dirlen, char *err, size_t errlen);

#endif
