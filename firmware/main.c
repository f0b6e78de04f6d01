/* SPDX-License-Identifier: MIT */
/*
 * main.c - the device program `periscope`: parse the command line, run the
 * board (firmware/app.c does the work, so tests can drive it without this
 * file), and report.
 */
#include <signal.h>
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "board_file.h"
#include "board_find.h"
#include "cli.h"
#include "psc_io_cli.h"
#include "psc_io_log.h"

static void main_report(const psc_app_stats_t *st, const char *out_dir)
{
    /* frames per second x 100, in integers: the firmware has no float */
    uint64_t fps_x100 = st->wall_time_us ? (uint64_t)st->frames * 100000000u / st->wall_time_us : 0;

    psc_io_log(PSC_LOG_INFO, "periscope: %u frames rendered, %llu.%03llu s of board time, %llu.%03llu s wall clock, "
           "%llu.%02llu frames/s",
           (unsigned)st->frames, (unsigned long long)(st->sim_time_us / 1000000u),
           (unsigned long long)(st->sim_time_us / 1000u % 1000u),
           (unsigned long long)(st->wall_time_us / 1000000u),
           (unsigned long long)(st->wall_time_us / 1000u % 1000u),
           (unsigned long long)(fps_x100 / 100u), (unsigned long long)(fps_x100 % 100u));
    psc_io_log(PSC_LOG_INFO, "periscope: adaptive quality: %u frames fast, %u switches", (unsigned)st->fast_frames,
           (unsigned)st->quality_switches);
    if (st->watchdog_known)
        psc_io_log(PSC_LOG_INFO, "periscope: watchdog: %u kicks, longest gap %llu ms%s", (unsigned)st->watchdog.kicks,
               (unsigned long long)(st->watchdog.longest_gap_us / 1000u),
               st->watchdog.would_have_fired ? " (a real one would have fired)" : "");
    if (st->reloads != 0 || st->reload_failures != 0)
        psc_io_log(PSC_LOG_INFO, "periscope: reloads (SIGHUP): %u taken, %u refused", (unsigned)st->reloads,
               (unsigned)st->reload_failures);
    if (out_dir[0] != '\0')
        psc_io_log(PSC_LOG_INFO, "periscope: output directory: %s (every %u-th frame)", out_dir, (unsigned)st->capture_every);
}

/* SIGTERM (systemd stopping the service) and SIGINT (Ctrl-C) end the frame
 * loop cleanly, so the display's previous mode comes back and the watchdog
 * says STOPPING=1. SA_RESETHAND: a second signal ends the program at once.
 * SIGHUP (systemctl reload) loads the scenes again, SIGUSR1 logs a status
 * line; both are taken between frames and lose none. */
static void main_on_signal(int sig)
{
    if (sig == SIGHUP)
        psc_app_request_reload();
    else if (sig == SIGUSR1)
        psc_app_request_status();
    else
        psc_app_request_stop();
}

static void main_catch_signals(void)
{
    struct sigaction sa;

    memset(&sa, 0, sizeof sa);
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sa.sa_handler = main_on_signal;
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    sa.sa_flags = SA_RESTART;   /* again and again, and no read interrupted */
    sigaction(SIGHUP, &sa, NULL);
    sigaction(SIGUSR1, &sa, NULL);
}

/* --print-key: a board file's value as the device reads it (0 found, 1 not set, 2 unreadable). */
static int main_print_key(const psc_cli_options_t *opt)
{
    char path[PSC_BOARD_LINE_MAX * 2], value[PSC_BOARD_LINE_MAX], err[1400], dir[PSC_BOARD_PATH_MAX];
    const char *boards_dir = opt->boards_dir;
    int rc;

    /* no --boards-dir: the first place that has the board (board_find.h) */
    if (boards_dir == NULL) {
        if (psc_board_find_default(opt->board, dir, sizeof dir, err, sizeof err) != 0) {
            psc_io_log(PSC_LOG_ERR, "periscope: %s", err);
            return 2;
        }
        boards_dir = dir;
    }
    snprintf(path, sizeof path, "%s/%s/board.conf", boards_dir, opt->board);
    rc = psc_board_file_value(path, opt->print_key, value, sizeof value, err, sizeof err);
    if (rc < 0) {
        psc_io_log(PSC_LOG_ERR, "periscope: %s", err);
        return 2;
    }
    if (rc == 0) {
        psc_io_log(PSC_LOG_ERR, "periscope: %s sets no %s", path, opt->print_key);
        return 1;
    }
    printf("%s\n", value);
    return 0;
}

/* stdio would allocate stdout's buffer at the first log line, which comes
 * from inside the frame loop; giving it one now keeps the loop allocation-free. */
static char main_stdout_buffer[4096];

int main(int argc, char **argv)
{
    psc_cli_options_t opt;
    psc_app_stats_t stats;
    psc_app_t *app;
    char err[1400] = "";
    int rc;

    setvbuf(stdout, main_stdout_buffer, _IOLBF, sizeof main_stdout_buffer);
    if (psc_cli_parse(argc, argv, &opt, err, sizeof err) != 0)
        return psc_io_cli_usage_error("periscope", "%s", err);
    if (opt.help) {
        fputs(psc_cli_usage(), stdout);
        return 0;
    }
    if (opt.version) {
        psc_io_cli_print_version("periscope");
        return 0;
    }
    if (opt.print_key != NULL)
        return main_print_key(&opt);
    main_catch_signals();
    if (psc_app_open(&opt, &app, err, sizeof err) != 0) {
        psc_io_log(PSC_LOG_ERR, "periscope: %s", err);
        return 1;
    }
    rc = psc_app_run(app, &stats, err, sizeof err);
    main_report(&stats, psc_app_out_dir(app));
    if (rc != 0)
        psc_io_log(PSC_LOG_ERR, "periscope: %s", err);
    psc_app_close(app);
    return rc == 0 ? 0 : 1;
}
