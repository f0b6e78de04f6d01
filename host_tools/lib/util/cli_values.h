/* SPDX-License-Identifier: MIT */
/*
 * cli_values.h - strict parsing of command-line values for the host tools
 * (the options themselves: io/psc_io_cli.h).
 * Every parser accepts the whole string or nothing: "12abc" is an error, not 12.
 * They return 0 on success and -1 on a malformed or out-of-range value, and
 * never print or exit (the tool decides how to report).
 */
#ifndef PSC_UTIL_CLI_VALUES_H
#define PSC_UTIL_CLI_VALUES_H

#include <stdint.h>

/** A finite decimal number. */
int psc_cli_parse_double(const char *s, double *out);

/** An unsigned integer in [min, max]. */
int psc_cli_parse_uint(const char *s, unsigned long min, unsigned long max, unsigned long *out);

/** "WxH" with both parts in [1, max]. */
int psc_cli_parse_size(const char *s, unsigned long max, uint16_t *w, uint16_t *h);

/** "A:B", two finite numbers (degrees in the tools). */
int psc_cli_parse_pair(const char *s, double *a, double *b);

/** "YAW,PITCH,DIST" for --orbit: degrees, pitch -90..90, distance 1/64..256 (in R). 0, or -1. */
int psc_cli_parse_orbit(const char *s, double *yaw, double *pitch, double *dist);

#endif
