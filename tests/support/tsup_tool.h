/* SPDX-License-Identifier: MIT */
/*
 * tsup_tool.h - running one of this build's programs ($PSC_BIN_DIR, build/bin
 * by default) from a cmocka test and taking what it said: the tests of the
 * command-line tools and of opening images directly share it. A program that
 * is missing, cannot start or dies of a signal fails the test, naming it.
 */
#ifndef TSUP_TOOL_H
#define TSUP_TOOL_H

typedef struct {
    int status;      /* the exit status */
    char *output;    /* stdout and stderr together, NUL-terminated (malloc'd) */
} tsup_tool_run_t;

/** The directory of the programs under test. */
const char *tsup_bin_dir(void);

/** Run tool with args (NULL-terminated, at most 30); prefix names its output file in $PSC_TEST_TMPDIR. */
tsup_tool_run_t tsup_run_tool(const char *prefix, const char *tool, const char *const *args);

#endif
