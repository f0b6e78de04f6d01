/* SPDX-License-Identifier: MIT */
/*
 * psc_io_cli.h - the one command-line convention of every Periscope program,
 * the device's and the desktop tools': GNU long options through getopt_long,
 * so "--opt=value" and "--opt value" both work and options may come before
 * or after the files; -h/--help and --version everywhere; one wording for
 * mistakes:
 *   prog: unknown option '--scen'
 *   prog: option '--board' needs a value
 *   prog: option '--quiet' takes no value
 *   (try prog --help)
 *
 * A program lists its options as struct option entries ending with
 * PSC_IO_CLI_COMMON_OPTIONS, then loops on psc_io_cli_next.
 */
#ifndef PSC_IO_CLI_H
#define PSC_IO_CLI_H

#include <getopt.h>
#include <stdio.h>
#include <stddef.h>

/** Exit status of a program for a bad command line. */
#define PSC_IO_CLI_EXIT_USAGE 2

/** What psc_io_cli_next returns for --help and --version (an option's val otherwise). */
#define PSC_IO_CLI_HELP 'h'
#define PSC_IO_CLI_VERSION 0x7001

/** The options every program has; the last entries of its table. */
#define PSC_IO_CLI_COMMON_OPTIONS                                                                             \
    {"help", no_argument, NULL, PSC_IO_CLI_HELP}, {"version", no_argument, NULL, PSC_IO_CLI_VERSION},       \
    {NULL, 0, NULL, 0}

/** A parse in progress (getopt's state is global: one at a time). */
typedef struct {
    int argc;
    char **argv;
    const char *shortopts;     /* getopt's short options, e.g. "ho:" */
    const struct option *longopts;
    const char *arg;           /* the value of the option just returned, or NULL */
    const char *name;          /* how it was spelled, e.g. "--board" or "-o", for messages */
} psc_io_cli_t;

/** Start parsing argv[1..argc) (resets getopt, so a program or a test may parse several times). */
void psc_io_cli_begin(psc_io_cli_t *c, int argc, char **argv, const char *shortopts, const struct option *longopts);

/**
 * The next option's val (c->arg its value, c->name its spelling); 0 when the
 * options are over (the other arguments are argv[psc_io_cli_rest(c)..argc),
 * in order); -1 on a mistake, with err the message (without the program's
 * name).
 */
int psc_io_cli_next(psc_io_cli_t *c, char *err, size_t errlen);

/**
 * psc_io_cli_next with what every program does the same way: --help prints
 * usage(prog, stdout) and exits 0, --version prints the version and exits 0,
 * a mistake prints "prog: <why><mode>" (mode e.g. " (proxy mode)", or "")
 * and returns -PSC_IO_CLI_EXIT_USAGE. Otherwise the option's val (> 0: a
 * table's vals are never 0; its spelling in c->name, its value in c->arg), or
 * 0 when the options are over. Every program's option loop is this one:
 *     while ((opt = psc_io_cli_next_option(&c, PROG, "", usage)) > 0) { ... }
 *     if (opt < 0)
 *         return -opt;
 */
int psc_io_cli_next_option(psc_io_cli_t *c, const char *prog, const char *mode, void (*usage)(const char *, FILE *));

/** The index of the first argument that is not an option (after psc_io_cli_next returned 0). */
int psc_io_cli_rest(const psc_io_cli_t *c);

/**
 * The one file argument after the options (what names it in the mistakes:
 * "more than one model given (b.obj)", "no model given") into *file. 0, or
 * PSC_IO_CLI_EXIT_USAGE with the mistake said.
 */
int psc_io_cli_one_file(const psc_io_cli_t *c, const char *prog, const char *what, const char **file);

/**
 * "COMMAND FILE" after the options (periscope-shadow build MODEL): the
 * command must be command (else "expected the command 'build' (synopsis)"),
 * then the one file into *file, as psc_io_cli_one_file. 0, or
 * PSC_IO_CLI_EXIT_USAGE with the mistake said.
 */
int psc_io_cli_command_file(const psc_io_cli_t *c, const char *prog, const char *command, const char *synopsis,
                            const char *what, const char **file);

/** "prog (Periscope) VERSION" on stdout, for --version. */
void psc_io_cli_print_version(const char *prog);

/** Print "prog: <fmt...>" and "(try prog --help)" on stderr; returns PSC_IO_CLI_EXIT_USAGE. */
int psc_io_cli_usage_error(const char *prog, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
