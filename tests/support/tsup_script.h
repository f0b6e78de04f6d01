/* SPDX-License-Identifier: MIT */
/*
 * tsup_script.h - the tests that drive a shell script (the cross-built
 * renderers under qemu-user, the boot images under qemu-system): which
 * boards a script applies to, where the build is, and the script's exit
 * status read the way those scripts write it (0 pass, 77 skip, else fail).
 * Host only; run from the repository root.
 */
#ifndef TSUP_SCRIPT_H
#define TSUP_SCRIPT_H

#include <stddef.h>

#define TSUP_BOARD_NAME_MAX 64

/** 1 if boards/<board>/board.conf has a line "<key> = ..." (blanks allowed). */
int tsup_board_has_key(const char *board, const char *key);

/**
 * The boards (sorted by name, at most max) whose board.conf has key, into
 * names; returns how many.
 */
size_t tsup_boards_with_key(const char *key, char names[][TSUP_BOARD_NAME_MAX], size_t max);

/** The make build directory: the parent of $PSC_BIN_DIR (build/bin by default). */
void tsup_build_dir(char *buf, size_t n);

/**
 * Runs cmd with system(), its output going to the test's. Returns its exit
 * status, or -1 if it did not run to its end.
 */
int tsup_script_status(const char *cmd);

/**
 * A cmocka case's verdict from a script (tests/portability, tests/image):
 * runs cmd; exit 0 passes, 77 skips (the script printed why), anything
 * else fails naming what.
 */
void tsup_script_case(const char *cmd, const char *what);

#endif
