/* SPDX-License-Identifier: MIT */
/*
 * bench/occlusion - the self-shadowing on held-out models as a user measures
 * it (issue 29's table), the seed's spheres alone and the product side by
 * side in one run: for each model, `periscope-shadow build` with --no-rest
 * (the spheres alone) and as it is, then `periscope-render MODEL --shadow
 * M.pao --orbit 30,20,2.5 --size 320x240 --dump-ao ao.csv` (and --dump-obj
 * for a patch model's frame, culling off), each dumped vertex's occlusion
 * against ray-traced ambient occlusion there (docs/characters.md's
 * reference: 256 stratified cosine-weighted rays of unbounded length about
 * the vertex's own smooth normal, both sides of the triangles blocking,
 * against the frame's own triangles). Also the bakes' times. Accuracy
 * figures, not speed: the callgrind mode has nothing to count.
 */
#include "common/bench_cli.h"
#include "common/bench_time.h"
#include "import/gltf_model.h"
#include "measure/raycast.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define STRATA 16u   /* 256 rays a vertex, as the reference */

static char tmpdir[256];

static const char *tmp_file(const char *name)
{
    static char buf[8][512];
    static unsigned k;
    char *p = buf[k++ & 7u];
    snprintf(p, sizeof buf[0], "%s/%s", tmpdir, name);
    return p;
}

/* Run argv (its stdout to /dev/null; its messages shown): 0, or -1; *seconds its wall time. */
static int run(char *const argv[], double *seconds)
{
    double t0 = bench_now_s();
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        if (!freopen("/dev/null", "w", stdout))
            _exit(127);
        execv(argv[0], argv);
        _exit(127);
    }
    int status;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        fprintf(stderr, "occlusion: %s %s failed\n", argv[0], argv[1]);
        return -1;
    }
    if (seconds)
        *seconds = bench_now_s() - t0;
    return 0;
}

/* A (2,3) torus knot tube (the second model): 160 rings of 30 vertices, radius 0.4, as an OBJ. */
static int write_knot(const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    const unsigned rings = 160, around = 30;
    for (unsigned i = 0; i < rings; i++) {
        double t = 2 * M_PI * i / rings, c[3], d[3], dd[3];
        double r = 2 + cos(3 * t), dr = -3 * sin(3 * t), ddr = -9 * cos(3 * t);
        c[0] = r * cos(2 * t), c[1] = r * sin(2 * t), c[2] = sin(3 * t);
        d[0] = dr * cos(2 * t) - 2 * r * sin(2 * t), d[1] = dr * sin(2 * t) + 2 * r * cos(2 * t), d[2] = 3 * cos(3 * t);
        dd[0] = ddr * cos(2 * t) - 4 * dr * sin(2 * t) - 4 * r * cos(2 * t);
        dd[1] = ddr * sin(2 * t) + 4 * dr * cos(2 * t) - 4 * r * sin(2 * t);
        dd[2] = -9 * sin(3 * t);
        double lt = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), T[3], N[3], B[3];
        for (unsigned a = 0; a < 3; a++)
            T[a] = d[a] / lt;
        double k = dd[0] * T[0] + dd[1] * T[1] + dd[2] * T[2];
        for (unsigned a = 0; a < 3; a++)
            N[a] = dd[a] - k * T[a];
        double ln = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
        for (unsigned a = 0; a < 3; a++)
            N[a] /= ln;
        B[0] = T[1] * N[2] - T[2] * N[1], B[1] = T[2] * N[0] - T[0] * N[2], B[2] = T[0] * N[1] - T[1] * N[0];
        for (unsigned j = 0; j < around; j++) {
            double a = 2 * M_PI * j / around, n[3];
            for (unsigned q = 0; q < 3; q++)
                n[q] = cos(a) * N[q] + sin(a) * B[q];
            fprintf(f, "v %.6f %.6f %.6f\nvn %.6f %.6f %.6f\n", c[0] + 0.4 * n[0], c[1] + 0.4 * n[1],
                    c[2] + 0.4 * n[2], n[0], n[1], n[2]);
        }
    }
    for (unsigned i = 0; i < rings; i++)
        for (unsigned j = 0; j < around; j++) {
            unsigned a = i * around + j + 1, b = i * around + (j + 1) % around + 1;
            unsigned c = (i + 1) % rings * around + (j + 1) % around + 1, d = (i + 1) % rings * around + j + 1;
            fprintf(f, "f %u//%u %u//%u %u//%u\nf %u//%u %u//%u %u//%u\n", a, a, b, b, c, c, a, a, c, c, d, d);
        }
    return fclose(f) == 0 ? 0 : -1;
}

typedef struct {
    double (*pos)[3], (*nrm)[3];
    double *occ;
    size_t n;
} dump_t;

static void dump_free(dump_t *d)
{
    free(d->pos), free(d->nrm), free(d->occ);
    memset(d, 0, sizeof *d);
}

/* periscope-render's --dump-ao CSV: x,y,z,nx,ny,nz,occlusion a line. */
static int read_ao(const char *path, dump_t *d)
{
    FILE *f = fopen(path, "r");
    char line[256];
    size_t cap = 0;
    memset(d, 0, sizeof *d);
    if (!f || !fgets(line, sizeof line, f))
        return f ? fclose(f), -1 : -1;
    while (fgets(line, sizeof line, f)) {
        double v[7];
        if (sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf,%lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6]) != 7)
            continue;
        if (d->n == cap) {
            cap = cap ? 2 * cap : 4096;
            d->pos = realloc(d->pos, cap * sizeof *d->pos);
            d->nrm = realloc(d->nrm, cap * sizeof *d->nrm);
            d->occ = realloc(d->occ, cap * sizeof *d->occ);
            if (!d->pos || !d->nrm || !d->occ)
                return fclose(f), -1;
        }
        memcpy(d->pos[d->n], v, sizeof d->pos[0]);
        memcpy(d->nrm[d->n], v + 3, sizeof d->nrm[0]);
        d->occ[d->n++] = v[6];
    }
    fclose(f);
    return d->n ? 0 : -1;
}

/* periscope-render's --dump-obj (a patch frame, units of R): its vertices and normals into d (replacing the CSV's
 * positions and normals, in the same order) and its triangles. */
static int read_frame_obj(const char *path, dump_t *d, uint32_t **tri, size_t *nt)
{
    FILE *f = fopen(path, "r");
    char line[256];
    size_t nv = 0, nn = 0, cap = 0;
    *tri = NULL, *nt = 0;
    if (!f)
        return -1;
    while (fgets(line, sizeof line, f)) {
        double x, y, z;
        unsigned a, b, c;
        if (sscanf(line, "v %lf %lf %lf", &x, &y, &z) == 3 && nv < d->n) {
            d->pos[nv][0] = x, d->pos[nv][1] = y, d->pos[nv++][2] = z;
        } else if (sscanf(line, "vn %lf %lf %lf", &x, &y, &z) == 3 && nn < d->n) {
            d->nrm[nn][0] = x, d->nrm[nn][1] = y, d->nrm[nn++][2] = z;
        } else if (sscanf(line, "f %u//%*u %u//%*u %u//%*u", &a, &b, &c) == 3) {
            if (*nt == cap) {
                cap = cap ? 2 * cap : 8192;
                uint32_t *t = realloc(*tri, cap * 3 * sizeof *t);
                if (!t)
                    return fclose(f), -1;
                *tri = t;
            }
            (*tri)[3 * *nt] = a - 1, (*tri)[3 * *nt + 1] = b - 1, (*tri)[3 * (*nt)++ + 2] = c - 1;
        }
    }
    fclose(f);
    return nv == d->n && nn == d->n ? 0 : -1;   /* the frame the CSV shaded, vertex for vertex */
}

typedef struct {
    double mean, corr, mae;
} fig_t;

static fig_t figures(const double *x, const double *y, const bool *use, size_t n, double *ref_mean)
{
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, ae = 0, k = 0;
    for (size_t i = 0; i < n; i++)
        if (use[i]) {
            sx += x[i], sy += y[i], sxx += x[i] * x[i], syy += y[i] * y[i], sxy += x[i] * y[i];
            ae += fabs(x[i] - y[i]), k++;
        }
    double cov = sxy / k - sx / k * sy / k, vx = sxx / k - sx / k * sx / k, vy = syy / k - sy / k * sy / k;
    *ref_mean = sy / k;
    return (fig_t){sx / k, vx > 0 && vy > 0 ? cov / sqrt(vx * vy) : 0, ae / k};
}

typedef struct {
    const char *label, *path, *play, *time, *pose;
    bool patch;
} model_t;

static int measure(const model_t *m)
{
    static const char *const pao[2] = {"before.pao", "after.pao"}, *const csv[2] = {"before.csv", "after.csv"};
    double bake_s[2];
    dump_t d[2] = {{0}};
    uint32_t *tri = NULL;
    size_t nt = 0;
    for (unsigned k = 0; k < 2; k++) {
        char *build[] = {"build/bin/periscope-shadow", "build", (char *)m->path, "-o", (char *)tmp_file(pao[k]),
                         k ? NULL : "--no-rest", NULL};
        if (run(build, &bake_s[k]) != 0)
            return -1;
        char *argv[32] = {"build/bin/periscope-render", (char *)m->path, "--shadow", (char *)tmp_file(pao[k]),
                          "--orbit", "30,20,2.5", "--size", "320x240", "--dump-ao", (char *)tmp_file(csv[k]), "-o",
                          (char *)tmp_file("frame.png")};
        unsigned n = 12;
        if (m->play)
            argv[n++] = "--play", argv[n++] = (char *)m->play, argv[n++] = "--time", argv[n++] = (char *)m->time;
        if (m->pose)
            argv[n++] = "--pose", argv[n++] = (char *)m->pose;
        if (m->patch)
            argv[n++] = "--cull", argv[n++] = "none", argv[n++] = "--dump-obj",
            argv[n++] = (char *)tmp_file("frame-tessellation.txt");   /* (not .obj: it would pick the OBJ mode) */
        argv[n] = NULL;
        if (run(argv, NULL) != 0 || read_ao(tmp_file(csv[k]), &d[k]) != 0)
            return -1;
    }
    int rc = -1;
    psc_gltf_t g = {0};
    char note[256], err[512];
    if (d[0].n != d[1].n)
        goto done;
    if (m->patch) {   /* the frame's own triangles, in units of R (the CSV's positions are in the model's) */
        if (read_frame_obj(tmp_file("frame-tessellation.txt"), &d[1], &tri, &nt) != 0)
            goto done;
    } else {   /* the model's triangles over the posed vertices the CSV gives */
        if (psc_gltf_load(m->path, &g, note, sizeof note, err, sizeof err) != 0 || g.mesh.vertex_count != d[1].n) {
            fprintf(stderr, "occlusion: %s\n", err);
            goto done;
        }
        tri = malloc((size_t)g.mesh.triangle_count * 3 * sizeof *tri);
        if (!tri)
            goto done;
        memcpy(tri, g.mesh.index, (size_t)g.mesh.triangle_count * 3 * sizeof *tri);
        nt = g.mesh.triangle_count;
    }
    size_t n = d[1].n;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < n; i++)
        for (unsigned a = 0; a < 3; a++)
            lo[a] = fmin(lo[a], d[1].pos[i][a]), hi[a] = fmax(hi[a], d[1].pos[i][a]);
    double r = sqrt(pow(hi[0] - lo[0], 2) + pow(hi[1] - lo[1], 2) + pow(hi[2] - lo[2], 2)) / 2;
    psc_measure_bvh_t *bvh = psc_measure_bvh_new((const double(*)[3])d[1].pos, n, (const uint32_t(*)[3])tri, nt);
    double *y = malloc(n * sizeof *y);
    bool *use = malloc(n * sizeof *use);
    if (!bvh || !y || !use) {
        psc_measure_bvh_free(bvh);
        free(y), free(use);
        goto done;
    }
    size_t left = 0, buried = 0;
    for (size_t i = 0; i < n; i++) {
        double *nv = d[1].nrm[i], l = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]), u[3];
        use[i] = l >= 0.5;
        if (!use[i]) {
            left++;
            continue;
        }
        for (unsigned a = 0; a < 3; a++)
            u[a] = nv[a] / l;
        y[i] = psc_measure_ao(bvh, d[1].pos[i], u, STRATA, 1e-4 * r, INFINITY);
        buried += y[i] >= 1.0;
    }
    double ref;
    fig_t before = figures(d[0].occ, y, use, n, &ref), after = figures(d[1].occ, y, use, n, &ref);
    printf("| %s | %zu | %zu | %.1f %% | %.3f | %.3f / %.2f / %.3f | **%.3f / %.2f / %.3f** | %.1f / %.1f s |\n",
           m->label, n, left, 100.0 * buried / n, ref, before.mean, before.corr, before.mae, after.mean, after.corr,
           after.mae, bake_s[0], bake_s[1]);
    psc_measure_bvh_free(bvh);
    free(y), free(use);
    rc = 0;
done:
    psc_gltf_free(&g);
    free(tri);
    dump_free(&d[0]);
    dump_free(&d[1]);
    return rc;
}

static int table(const char *out_dir)
{
    (void)out_dir;
    const char *base = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
    snprintf(tmpdir, sizeof tmpdir, "%s/periscope-bench-occlusion-XXXXXX", base);
    static char knot[512];
    if (!mkdtemp(tmpdir))
        return 1;
    snprintf(knot, sizeof knot, "%s", tmp_file("knot.obj"));
    if (write_knot(knot) != 0)
        return 1;
    const model_t models[] = {
        {"spider (thin legs; assimp's test model), static", "tests/data/assimp/spider.obj", NULL, NULL, NULL, false},
        {"(2,3) torus knot tube, static", knot, NULL, NULL, NULL, false},
        {"human (BCN_Epileptic.X), skinned, t=1.6 s", "tests/data/assimp/BCN_Epileptic.X", NULL, NULL, "t=1.6", false},
        {"the Utah teapot (.bpt), large patches", "tests/fuzz/corpus/bpt/teapot.bpt", NULL, NULL, NULL, true},
        {"A:M's torus (CC0), large patches", "tests/data/am/Torus.mdl", NULL, NULL, NULL, true},
        {"Thom walking, 0.5 s", "out/thom.ppk", "ResoluteWalk", "0.5", NULL, true},
        {"Thom waving, 1.1 s", "out/thom.ppk", "Wave", "1.1", NULL, true},
    };
    printf("self-shadowing against ray-traced occlusion (256 rays a vertex), every vertex of the frame "
           "(periscope-render --orbit 30,20,2.5 --size 320x240 --dump-ao); before: the seed's spheres alone "
           "(periscope-shadow --no-rest); after: the product\n\n"
           "| model | vertices | left out | buried | ray-traced mean | before: mean / correlation / MAE | after | "
           "bake before / after |\n|---|---|---|---|---|---|---|---|\n");
    int rc = 0;
    for (size_t k = 0; k < sizeof models / sizeof models[0] && rc == 0; k++)
        rc = measure(&models[k]);
    const char *names[] = {"before.pao", "after.pao", "before.csv", "after.csv", "frame.png", "frame-tessellation.txt",
                           "knot.obj"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
        unlink(tmp_file(names[k]));
    rmdir(tmpdir);
    return rc ? 1 : 0;
}

static int callgrind(const char *self, const char *out_dir)
{
    (void)self, (void)out_dir;
    printf("occlusion: accuracy figures only, no instruction counts\n");
    return 0;
}

static int child(void)
{
    return 0;
}

int main(int argc, char **argv)
{
    const bench_cli_t b = {"occlusion", table, callgrind, child};
    return bench_cli_main(&b, argc, argv);
}
