// SPDX-License-Identifier: Apache-2.0
// The speed targets (docs/performance.md): the frame the frame-rate benchmarks restore, the frame-rate
// setting they time, and the reference, Richardson–Lucy written plainly with cv::filter2D.
#ifndef DYNBLUR_PERF_BASELINE_HPP
#define DYNBLUR_PERF_BASELINE_HPP

#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

namespace dynblur_perf {

/* The frame-rate benchmarks' move and camera: a C270-sized camera (1280x960, fx = `focalPx`) on the
   speed targets' plant, a robust saccade of `moveDeg` degrees, and a rolling shutter that puts the
   exposure of the 10° saccade in window III. */
struct SaccadeScene
{
    explicit SaccadeScene(double focalPx = 1230, double moveDeg = 10)
        : camera(cv::dynblur::CameraModel::create(focalPx, focalPx, 639.5, 479.5, 1280, 960)),
          schedule(cv::dynblur::SwitchPlanner::create(plant, 16, cv::dynblur::PLAN_ROBUST)
                       ->plan(0.0, moveDeg * CV_PI / 180, 0.0))
    {
    }
    cv::Ptr<cv::dynblur::Plant> plant = cv::dynblur::Plant::create(14.4, 0.12, CV_PI / 180);
    cv::Ptr<cv::dynblur::CameraModel> camera;
    cv::dynblur::SwitchSchedule schedule;
    cv::dynblur::RollingShutter shutter{0.012, 0.008, 1.0 / 30 / 960, 960};
};

//! SaccadeScene's blurred frame, rendered once (rendering is the costly part).
struct SaccadeFrame : SaccadeScene
{
    cv::Mat frame, frame8;  // linear float, and as a webcam delivers it: 8-bit sRGB

    /** `timing`: the frame's shutter instead of SaccadeScene's (its rows must be 960); `focalPx` and
    `moveDeg`: SaccadeScene's. */
    explicit SaccadeFrame(const cv::dynblur::RollingShutter* timing = nullptr, double focalPx = 1230, double moveDeg = 10)
        : SaccadeScene(focalPx, moveDeg)
    {
        if (timing)
            shutter = *timing;
        // A textured linear-intensity scene.
        cv::Mat sharp(960, 1280, CV_32FC3), blurred;
        cv::randu(sharp, 0.05f, 0.95f);
        cv::GaussianBlur(sharp, sharp, cv::Size(0, 0), 1.5);
        cv::dynblur::renderBlurred(sharp, plant, schedule, camera, shutter, blurred);
        cv::dynblur::addSensorNoise(blurred, frame);
        cv::dynblur::linearToSrgb(frame, frame8, CV_8U);
    }
};

/* The frame-rate setting (its quality is DeblurQuality's to check): row bands, `iterations` on the
   luminance, 3 on the color planes of the frame halved (with 3 or fewer iterations every one is
   in color), bfloat16 blurs; `blurPrecision` and `colorResolution` vary it. */
inline void setFrameRate(cv::dynblur::DynamicDeblurrer& deblurrer, int iterations = 10,
                         int blurPrecision = cv::dynblur::RL_BLUR_BFLOAT16,
                         int colorResolution = cv::dynblur::DEBLUR_COLOR_HALF_RESOLUTION)
{
    deblurrer.setPsfModel(cv::dynblur::PSF_ROWS);
    deblurrer.setColorResolution(colorResolution);
    cv::dynblur::RLParams params = deblurrer.getRLParams();  // defaults: automatic damping, TV, acceleration
    params.iterations = iterations;
    params.colorIterations = 3;
    params.blurPrecision = blurPrecision;
    deblurrer.setRLParams(params);
}

//! The reference kernel: uniform, 21 pixels wide, one row.
inline cv::Mat uniformKernel21x1()
{
    return cv::Mat(1, 21, CV_32F, cv::Scalar(1.0 / 21));
}

//! `iterations` of x ← x ⊙ (k ★ (b / (k ⊛ x))) from x = b, with cv::filter2D (its own SIMD and threads).
inline void filter2DRichardsonLucy(const cv::Mat& blurred, const cv::Mat& kernel, int iterations, cv::Mat& estimate)
{
    cv::Mat flipped, reblurred, ratio, correction;
    cv::flip(kernel, flipped, -1);
    blurred.copyTo(estimate);
    for (int i = 0; i < iterations; i++)
    {
        cv::filter2D(estimate, reblurred, CV_32F, flipped, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
        cv::divide(blurred, reblurred + cv::Scalar::all(1e-12), ratio);
        cv::filter2D(ratio, correction, CV_32F, kernel, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
        cv::multiply(estimate, correction, estimate);
    }
}

}  // namespace dynblur_perf

#endif
