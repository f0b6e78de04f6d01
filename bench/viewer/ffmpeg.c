/* SPDX-License-Identifier: MIT */
/*
 * ffmpeg.c - FFmpeg's v360 filter (equirect to flat), the other tool people
 * reach for, on the same map, output size and field of view, where ffmpeg is
 * installed.
 *
 * The map goes to ffmpeg once as a PPM file, converted once to planar RGB
 * (gbrp: v360 would otherwise have the packed frame converted before every
 * remap, four times its own cost); a `loop` filter keeps that one frame and
 * v360 redraws it, so a run of K frames costs start-up, decoding and v360's
 * own table set-up once plus K remaps. The time of a
 * frame is the difference between a run of FRAMES_LONG and one of
 * FRAMES_SHORT frames (best of TRIES each), divided by the difference in
 * frames (a difference within the start-up's noise is retried once more): what is left is v360's per-frame remap, its best case (the view
 * never changes), on -filter_threads threads.
 */
#include "bench_support.h"
#include "common/bench_time.h"

#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

#define FRAMES_SHORT 3
#define FRAMES_LONG 83
#define TRIES 3

/* Run argv with stdin, stdout and stderr on /dev/null; its exit status, or -1. */
static int run_quiet(char *const argv[])
{
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid;
    int rc = posix_spawnp(&pid, argv[0], &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0)
        return -1;
    int status;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status))
        return -1;
    return WEXITSTATUS(status);
}

bool bv_ffmpeg_available(void)
{
    static int have = -1;
    if (have < 0) {
        char *argv[] = {"ffmpeg", "-hide_banner", "-filters", NULL};
        have = run_quiet(argv) == 0;
    }
    return have == 1;
}

int bv_ffmpeg_write_map(const bv_image_t *src, const char *path)
{
    if (src->channels != 3)
        return -1;
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    /* the BGR bytes as they are: the timing does not depend on which channel is which */
    fprintf(f, "P6\n%d %d\n255\n", src->width, src->height);
    int ok = 1;
    for (int y = 0; y < src->height && ok; y++)
        ok = fwrite(src->data + (size_t)y * src->step, 3, (size_t)src->width, f) == (size_t)src->width;
    return fclose(f) == 0 && ok ? 0 : -1;
}

/* Seconds for one ffmpeg run of `frames` frames, or a negative value. */
static double run_frames(const char *map, const char *graph, int frames, int threads)
{
    char nframes[16], nthreads[16];
    snprintf(nframes, sizeof nframes, "%d", frames);
    snprintf(nthreads, sizeof nthreads, "%d", threads);
    char *argv[] = {"ffmpeg", "-nostdin", "-v", "error", "-threads", "1", "-filter_threads", nthreads, "-i",
                    (char *)map, "-vf", (char *)graph, "-frames:v", nframes, "-f", "null", "-", NULL};
    double t0 = bench_now_s();
    if (run_quiet(argv) != 0)
        return -1.0;
    return bench_now_s() - t0;
}

double bv_ffmpeg_v360_ns(const char *map, const bv_view_t *v, int out_w, int out_h, bool nearest, int threads)
{
    double vfov = 2.0 * atan(tan(v->hfov * M_PI / 360.0) * out_h / out_w) * 180.0 / M_PI;
    char graph[512];
    snprintf(graph, sizeof graph,
             "format=gbrp,loop=loop=-1:size=1,v360=input=e:output=flat:interp=%s:w=%d:h=%d:h_fov=%.4f:v_fov=%.4f:"
             "yaw=%.4f:pitch=%.4f",
             nearest ? "near" : "linear", out_w, out_h, v->hfov, vfov, v->yaw > 180.0 ? v->yaw - 360.0 : v->yaw,
             v->pitch);
    double best_short = 0.0, best_long = 0.0;
    for (int i = 0; i < TRIES || (i == TRIES && best_long <= best_short); i++) {
        double s = run_frames(map, graph, FRAMES_SHORT, threads), l = run_frames(map, graph, FRAMES_LONG, threads);
        if (s < 0.0 || l < 0.0)
            return -1.0;
        best_short = i == 0 || s < best_short ? s : best_short;
        best_long = i == 0 || l < best_long ? l : best_long;
    }
    double per_frame = (best_long - best_short) / (FRAMES_LONG - FRAMES_SHORT);
    return per_frame > 0.0 ? per_frame * 1e9 / ((double)out_w * out_h) : -1.0;
}
