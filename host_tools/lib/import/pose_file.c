/* SPDX-License-Identifier: MIT */
/* pose_file.c - what of a pose file needs no JSON reader (pose_file.h): telling it from rest and t=, freeing it,
 * its matrices. */
#include "import/pose_file.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/cli_values.h"
#include "psc_io_cli.h"

bool psc_pose_is_file(const char *arg)
{
    return strcmp(arg, "rest") != 0 && strncmp(arg, "t=", 2) != 0;
}

int psc_pose_option(const char *prog, const char *arg, const char **file, double *t)
{
    *file = psc_pose_is_file(arg) ? arg : NULL;
    if (*file)
        return 0;
    double v = -1.0;
    if (strcmp(arg, "rest") != 0 &&
        (psc_cli_parse_double(arg + 2, &v) != 0 || !(v >= 0.0 && v <= 3600.0)))
        return psc_io_cli_usage_error(prog, "--pose '%s': expected rest, t=SECONDS (0..3600) or POSE.json", arg);
    *t = v;
    return 0;
}

void psc_pose_file_free(psc_pose_file_t *p)
{
    free(p->nodes);
    memset(p, 0, sizeof *p);
}

void psc_pose_node_matrices(const psc_pose_node_t *n, double pre[12], double post[12])
{
    static const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    memcpy(pre, id, sizeof id);
    memcpy(post, id, sizeof id);
    if (n->translate)
        for (unsigned a = 0; a < 3; a++)
            pre[4 * a + 3] = n->t[a];
    if (n->rotate) {   /* Rodrigues: the rotation by degrees about the unit axis */
        double th = n->degrees * M_PI / 180.0, c = cos(th), s = sin(th), C = 1 - c;
        double x = n->axis[0], y = n->axis[1], z = n->axis[2];
        double r[9] = {c + x * x * C,     x * y * C - z * s, x * z * C + y * s,
                       y * x * C + z * s, c + y * y * C,     y * z * C - x * s,
                       z * x * C - y * s, z * y * C + x * s, c + z * z * C};
        for (unsigned i = 0; i < 3; i++)
            for (unsigned j = 0; j < 3; j++)
                post[4 * i + j] = r[3 * i + j];
    }
}
