/* SPDX-License-Identifier: MIT */
/* tsup_tool.c - running this build's programs from a test (tsup_tool.h). */
#include "tsup_tool.h"

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tsup_files.h"

extern char **environ;

const char *tsup_bin_dir(void)
{
    const char *d = getenv("PSC_BIN_DIR");
    return d && *d ? d : "build/bin";
}

tsup_tool_run_t tsup_run_tool(const char *prefix, const char *tool, const char *const *args)
{
    char exe[512], log[512];
    snprintf(exe, sizeof exe, "%s/%s", tsup_bin_dir(), tool);
    if (access(exe, X_OK) != 0)
        fail_msg("%s is not there: build the tools first (make all), or set PSC_BIN_DIR", exe);
    tsup_tmp_path(log, sizeof log, prefix, "tool-output.txt");
    const char *argv[32];
    size_t n = 0;
    argv[n++] = exe;
    for (; args[n - 1] && n < 31; n++)
        argv[n] = args[n - 1];
    argv[n] = NULL;

    posix_spawn_file_actions_t fa;
    assert_int_equal(posix_spawn_file_actions_init(&fa), 0);
    assert_int_equal(posix_spawn_file_actions_addopen(&fa, 1, log, O_WRONLY | O_CREAT | O_TRUNC, 0644), 0);
    assert_int_equal(posix_spawn_file_actions_adddup2(&fa, 1, 2), 0);
    pid_t pid;
    int rc = posix_spawn(&pid, exe, &fa, NULL, (char *const *)argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0)
        fail_msg("cannot start %s: %s", exe, strerror(rc));
    int ws;
    while (waitpid(pid, &ws, 0) < 0)
        assert_int_equal(errno, EINTR);
    tsup_tool_run_t r;
    size_t len;
    r.output = (char *)tsup_read_bytes(log, &len);
    assert_non_null(r.output);
    unlink(log);
    if (!WIFEXITED(ws))
        fail_msg("%s died of signal %d; its output:\n%s", tool, WIFSIGNALED(ws) ? WTERMSIG(ws) : -1, r.output);
    r.status = WEXITSTATUS(ws);
    return r;
}
