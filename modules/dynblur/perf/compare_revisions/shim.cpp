// SPDX-License-Identifier: Apache-2.0
// One revision's side of scripts/compare_revisions.sh: compiled once per revision, against that
// revision's public headers, into its own shared object linked to that revision's library (a copy
// whose soname names the side, see the script). The driver dlopens one shim per side and reaches it
// only through the extern "C" functions below, so the two libraries never meet. The move, camera and
// frame-rate setting come from ../perf_baseline.hpp of the tree the script runs from, the same for
// both sides, and reach the library through its public API only.
#include "../perf_baseline.hpp"

#include <opencv2/core.hpp>
#include <opencv2/dynblur.hpp>

#include <dlfcn.h>

#include <cstring>

#ifndef COMPARE_REVISION
#error "compile with -DCOMPARE_REVISION=\"<the revision this shim's library was built from>\""
#endif

namespace {

struct Side
{
    dynblur_perf::SaccadeScene scene;
    cv::Ptr<cv::dynblur::DynamicDeblurrer> deblurrer;
    cv::Mat frame, restored;
};

}  // namespace

extern "C" {

//! The revision this shim was built for (a commit, or "worktree").
const char* compare_revision()
{
    return COMPARE_REVISION;
}

/* The file and load address of the library whose DynamicDeblurrer::create this shim calls, as the
   dynamic linker resolved it: the driver checks that the two sides differ. */
const char* compare_library(const void** base)
{
    Dl_info info{};
    const auto create = &cv::dynblur::DynamicDeblurrer::create;
    if (!dladdr(reinterpret_cast<const void*>(create), &info) || !info.dli_fname)
        return "?";
    *base = info.dli_fbase;
    return info.dli_fname;
}

/* Renders the frame-rate benchmarks' frame (dynblur_perf::SaccadeFrame, linear float, 3 channels)
   into `out`, rows*cols*3 floats; returns 0, or -1 when its size is not rows x cols. The driver asks
   one side for it and gives both the same frame. */
int compare_render_frame(float* out, int rows, int cols)
{
    const dynblur_perf::SaccadeFrame f;
    if (f.frame.rows != rows || f.frame.cols != cols || f.frame.type() != CV_32FC3)
        return -1;
    f.frame.copyTo(cv::Mat(rows, cols, CV_32FC3, out));
    return 0;
}

/* A DynamicDeblurrer in the frame-rate setting (`frameRate` non-zero) or as created (the default:
   tile-wise float blurs, 20 iterations), restoring `frame` (copied) once to warm up. */
void* compare_setup(const float* frame, int rows, int cols, int frameRate)
{
    Side* side = new Side;
    side->frame = cv::Mat(rows, cols, CV_32FC3, const_cast<float*>(frame)).clone();
    side->deblurrer = cv::dynblur::DynamicDeblurrer::create(side->scene.plant, side->scene.camera);
    if (frameRate)
        dynblur_perf::setFrameRate(*side->deblurrer);
    side->deblurrer->deblur(side->frame, side->scene.schedule, side->scene.shutter, side->restored);
    return side;
}

//! Restores the frame once.
void compare_run(void* handle)
{
    Side* side = static_cast<Side*>(handle);
    side->deblurrer->deblur(side->frame, side->scene.schedule, side->scene.shutter, side->restored);
}

/* The last restoration: its pixels (continuous), their size in bytes, and its OpenCV type. */
const void* compare_result(void* handle, size_t* bytes, int* type)
{
    Side* side = static_cast<Side*>(handle);
    if (!side->restored.isContinuous())
        side->restored = side->restored.clone();
    *bytes = side->restored.total() * side->restored.elemSize();
    *type = side->restored.type();
    return side->restored.data;
}

void compare_teardown(void* handle)
{
    delete static_cast<Side*>(handle);
}

}  // extern "C"
