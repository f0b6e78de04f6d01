/* SPDX-License-Identifier: MIT */
/* psc_io_cli.c - the command-line convention (psc_io_cli.h), on getopt_long. */
#include "psc_io_cli.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef PSC_VERSION
#define PSC_VERSION "unknown"
#endif

void psc_io_cli_begin(psc_io_cli_t *c, int argc, char **argv, const char *shortopts, const struct option *longopts)
{
    *c = (psc_io_cli_t){ .argc = argc, .argv = argv, .shortopts = shortopts, .longopts = longopts };
    optind = 0;   /* glibc: start afresh, re-reading the environment */
    opterr = 0;   /* the messages are ours */
}

int psc_io_cli_next(psc_io_cli_t *c, char *err, size_t errlen)
{
    static char spelled[64];
    int longindex = -1, r;
    char shortopts[96];

    /* a leading ':' makes getopt tell a missing value (':') from an unknown option ('?') */
    snprintf(shortopts, sizeof shortopts, ":%s", c->shortopts);
    c->arg = NULL;
    c->name = NULL;
    r = getopt_long(c->argc, c->argv, shortopts, c->longopts, &longindex);
    if (r == -1)
        return 0;
    if (longindex >= 0) {
        snprintf(spelled, sizeof spelled, "--%s", c->longopts[longindex].name);
    } else if (r != '?' && r != ':') {
        snprintf(spelled, sizeof spelled, "-%c", r);
    } else {
        /* getopt has stepped past the argument at fault: a long option is
         * named as written (without "=value"), a short one by its letter */
        const char *a = optind > 0 && optind <= c->argc ? c->argv[optind - 1] : "";
        if (strncmp(a, "--", 2) == 0)
            snprintf(spelled, sizeof spelled, "%.*s", (int)strcspn(a, "="), a);
        else
            snprintf(spelled, sizeof spelled, "-%c", optopt);
    }
    c->name = spelled;
    if (r == ':') {
        snprintf(err, errlen, "option '%s' needs a value", spelled);
        return -1;
    }
    if (r == '?') {
        /* glibc leaves optopt 0 for a long option it does not know, and sets
         * it to the option's value for one given a value it does not take */
        if (optopt != 0 && strncmp(spelled, "--", 2) == 0)
            snprintf(err, errlen, "option '%s' takes no value", spelled);
        else
            snprintf(err, errlen, "unknown option '%s'", spelled);
        return -1;
    }
    /* getopt takes unambiguous abbreviations ("--scen" for "--scene"); a
     * typo should not quietly become another option, so names must be whole */
    if (longindex >= 0) {
        const char *tok = optarg != NULL && optind >= 2 && optarg == c->argv[optind - 1] ? c->argv[optind - 2]
                                                                                        : c->argv[optind - 1];
        size_t n = strcspn(tok + 2, "=");
        if (strncmp(tok, "--", 2) != 0 || strlen(c->longopts[longindex].name) != n) {
            snprintf(err, errlen, "unknown option '%.*s' (did you mean '--%s'?)", (int)(n + 2), tok,
                     c->longopts[longindex].name);
            return -1;
        }
    }
    c->arg = optarg;
    return r;
}

int psc_io_cli_rest(const psc_io_cli_t *c)
{
    (void)c;
    return optind;
}

int psc_io_cli_one_file(const psc_io_cli_t *c, const char *prog, const char *what, const char **file)
{
    *file = NULL;
    for (int i = psc_io_cli_rest(c); i < c->argc; i++) {
        if (*file)
            return psc_io_cli_usage_error(prog, "more than one %s given (%s)", what, c->argv[i]);
        *file = c->argv[i];
    }
    if (!*file)
        return psc_io_cli_usage_error(prog, "no %s given", what);
    return 0;
}

int psc_io_cli_command_file(const psc_io_cli_t *c, const char *prog, const char *command, const char *synopsis,
                            const char *what, const char **file)
{
    int first = psc_io_cli_rest(c);
    *file = NULL;
    if (first >= c->argc || strcmp(c->argv[first], command) != 0)
        return psc_io_cli_usage_error(prog, "expected the command '%s' (%s)", command, synopsis);
    for (int i = first + 1; i < c->argc; i++) {
        if (*file)
            return psc_io_cli_usage_error(prog, "more than one %s given (%s)", what, c->argv[i]);
        *file = c->argv[i];
    }
    if (!*file)
        return psc_io_cli_usage_error(prog, "no %s given", what);
    return 0;
}

void psc_io_cli_print_version(const char *prog)
{
    printf("%s (Periscope) %s\n", prog, PSC_VERSION);
}

int psc_io_cli_next_option(psc_io_cli_t *c, const char *prog, const char *mode, void (*usage)(const char *, FILE *))
{
    char why[160];
    int opt = psc_io_cli_next(c, why, sizeof why);
    if (opt == 0)
        return 0;
    if (opt < 0)
        return -psc_io_cli_usage_error(prog, "%s%s", why, mode);
    if (opt == PSC_IO_CLI_HELP) {
        usage(prog, stdout);
        exit(0);
    }
    if (opt == PSC_IO_CLI_VERSION) {
        psc_io_cli_print_version(prog);
        exit(0);
    }
    return opt;
}

int psc_io_cli_usage_error(const char *prog, const char *fmt, ...)
{
    va_list ap;

    va_start(ap, fmt);
    fprintf(stderr, "%s: ", prog);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n(try %s --help)\n", prog);
    va_end(ap);
    return PSC_IO_CLI_EXIT_USAGE;
}
