/*
 * cli_parse.h - strict parsing of command-line values for the host tools.
 * Every parser accepts the whole string or nothing: "12abc" is an error, not 12.
 * They return 0 on success and -1 on a malformed or out-of-range value, and
 * never print or exit (the tool decides how to report).
 */
#ifndef PSC_CLI_PARSE_H
#define PSC_CLI_PARSE_H

#include <stdint.h>

/** Exit status of a tool for a bad command line. */
#define PSC_CLI_EXIT_USAGE 2

/** Print "prog: <fmt...>" and a hint to try --help on stderr; returns PSC_CLI_EXIT_USAGE. */
int psc_cli_usage_error(const char *prog, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/** Cursor over argv for the tools' option loops. */
typedef struct {
    int argc;
    char **argv;
    int index;   /* the argument being looked at */
} psc_cli_t;

/**
 * If argv[index] is option name ("--name VALUE" or "--name=VALUE"), set *value,
 * advance past the value and return 1. Return 0 if it is another argument,
 * -1 if it is this option but its value is missing.
 */
int psc_cli_take_value(psc_cli_t *c, const char *name, const char **value);

/** If argv[index] is the flag name exactly, advance and return 1; else 0. */
int psc_cli_take_flag(psc_cli_t *c, const char *name);

/** A finite decimal number. */
int psc_cli_parse_double(const char *s, double *out);

/** An unsigned integer in [min, max]. */
int psc_cli_parse_uint(const char *s, unsigned long min, unsigned long max, unsigned long *out);

/** "WxH" with both parts in [1, max]. */
int psc_cli_parse_size(const char *s, unsigned long max, uint16_t *w, uint16_t *h);

/** "A:B", two finite numbers (degrees in the tools). */
int psc_cli_parse_pair(const char *s, double *a, double *b);

#endif
