/* SPDX-License-Identifier: MIT */
/*
 * viewer - how fast Periscope's viewer renders, side by side in one run with
 * OpenCV's cv::remap, FFmpeg's v360 filter and a naive float renderer (issues 4 and 14).
 *
 *   build/bench/viewer --out bench/results              the timed table (`make bench`)
 *   build/bench/viewer --callgrind --out bench/results  instructions per pixel (`make bench-callgrind`)
 *
 * Run from the repository root (it reads assets/pannellum-examplepano.jpg).
 */
#include "bench_support.h"
#include "common/bench_self.h"
#include "util/cli_values.h"
#include "psc_io_cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define PROG "viewer bench"
#define DEFAULT_REPS 3ul

static void usage(FILE *f)
{
    fprintf(f, "usage: build/bench/viewer [--out DIR] [--callgrind] [--quick] [--reps K]\n"
               "\n"
               "  --out DIR     where viewer.json / viewer-callgrind.json go (default bench/results)\n"
               "  --callgrind   instructions per output pixel per mode under valgrind's callgrind\n"
               "  --quick       one map, output size and field of view (for trying changes)\n"
               "  --reps K      timed passes per row, at least (default %lu; short rows get more)\n",
            DEFAULT_REPS);
}

int main(int argc, char **argv)
{
    const char *out = "bench/results";
    bool callgrind = false, quick = false;
    unsigned long reps = DEFAULT_REPS;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--callgrind-child") == 0 && i + 2 < argc)
            return bv_callgrind_child(argv[i + 1], argv[i + 2]);
        if (strcmp(a, "--out") == 0 && i + 1 < argc) {
            out = argv[++i];
        } else if (strcmp(a, "--reps") == 0 && i + 1 < argc) {
            if (psc_cli_parse_uint(argv[++i], 1, 7, &reps) != 0)
                return psc_io_cli_usage_error(PROG, "--reps '%s': expected 1..7", argv[i]);
        } else if (strcmp(a, "--callgrind") == 0) {
            callgrind = true;
        } else if (strcmp(a, "--quick") == 0) {
            quick = true;
        } else if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return 0;
        } else {
            usage(stderr);
            return 2;
        }
    }
    if (mkdir(out, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, PROG ": cannot create %s: %s\n", out, strerror(errno));
        return 1;
    }
    if (callgrind) {
        char self[4096];
        if (bench_self_path(self, sizeof self) != 0) { /* the callgrind children run it again */
            fprintf(stderr, PROG ": cannot find this program's path (/proc/self/exe)\n");
            return 1;
        }
        return bv_callgrind_main(self, out);
    }
    return bv_speed_main(out, quick, (unsigned)reps);
}
