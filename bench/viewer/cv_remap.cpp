/* SPDX-License-Identifier: MIT */
// cv_remap.cpp - the OpenCV side of the viewer benchmark: cv::remap through
// fixed-point maps, what an engineer would reach for instead of Periscope.
// C entry points (bench_viewer.h); C++ exceptions never cross into C.
#include "bench_viewer.h"

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <new>

struct bv_cv_maps {
    cv::Mat xy;   // CV_16SC2: integer map position (rounded for nearest, floored for bilinear)
    cv::Mat frac; // CV_16UC1: index into OpenCV's 32x32 bilinear weight table; empty for nearest
};

static cv::Mat header_of(const bv_image_t *im)
{
    return cv::Mat(im->height, im->width, CV_8UC(im->channels), im->data, im->step);
}

static int fail(const char *what, const cv::Exception &e)
{
    std::fprintf(stderr, "viewer bench: OpenCV %s failed: %s\n", what, e.what());
    return -1;
}

extern "C" int bv_cv_init(char *version, size_t len)
{
    // 0 = run every function sequentially (no worker threads): Periscope is single-threaded too.
    cv::setNumThreads(0);
    std::snprintf(version, len, "%s", CV_VERSION);
    return 0;
}

extern "C" void bv_cv_threads(int n)
{
    cv::setNumThreads(n <= 1 ? 0 : n);
}

extern "C" bv_cv_maps_t *bv_cv_maps_new(void)
{
    return new (std::nothrow) bv_cv_maps();
}

extern "C" void bv_cv_maps_free(bv_cv_maps_t *m)
{
    delete m;
}

extern "C" size_t bv_cv_maps_bytes(const bv_cv_maps_t *m)
{
    return m->xy.total() * m->xy.elemSize() + m->frac.total() * m->frac.elemSize();
}

extern "C" int bv_cv_maps_convert(bv_cv_maps_t *m, const float *mapx, const float *mapy, int out_w, int out_h,
                                  int nearest)
{
    try {
        // Headers only: the float maps stay where the caller computed them.
        cv::Mat fx(out_h, out_w, CV_32FC1, const_cast<float *>(mapx));
        cv::Mat fy(out_h, out_w, CV_32FC1, const_cast<float *>(mapy));
        // Nearest wants rounded positions and no weights (nninterpolation);
        // bilinear keeps 1/32-pixel fractions in the CV_16UC1 table.
        cv::convertMaps(fx, fy, m->xy, m->frac, CV_16SC2, nearest != 0);
        if (nearest)
            m->frac.release();
        return 0;
    } catch (const cv::Exception &e) {
        return fail("convertMaps", e);
    }
}

extern "C" int bv_cv_remap(const bv_image_t *src, const bv_cv_maps_t *m, bv_image_t *dst, int nearest)
{
    try {
        cv::Mat s = header_of(src), d = header_of(dst);
        // dst already has the right size and type, so remap writes into the caller's buffer.
        // BORDER_WRAP joins the 360 degree seam; rows never leave the map (the float map clamps them).
        cv::remap(s, d, m->xy, m->frac, nearest ? cv::INTER_NEAREST : cv::INTER_LINEAR, cv::BORDER_WRAP);
        if (d.data != dst->data) {
            std::fprintf(stderr, "viewer bench: cv::remap reallocated its output\n");
            return -1;
        }
        return 0;
    } catch (const cv::Exception &e) {
        return fail("remap", e);
    }
}
