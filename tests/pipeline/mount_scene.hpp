// SPDX-License-Identifier: Apache-2.0
// Shared by the pan-tilt quality tests: a natural image before a pan-tilt head's camera, rendered with
// the physical forward model and sensor noise, and a frame start in a given exposure window.
#ifndef DYNBLUR_TEST_MOUNT_SCENE_HPP
#define DYNBLUR_TEST_MOUNT_SCENE_HPP

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

namespace dynblur_test {

/* A C270 at half resolution (640×480, f = 615 px) before a natural image that covers every view of a
   10° pan and 6° tilt; the sharp view is the mount's orientation at the capture's tRef (NaN: the final
   rest). */
struct MountScene
{
    static constexpr int marginX = 140, marginY = 96;
    cv::Ptr<cv::dynblur::CameraModel> camera = cv::dynblur::CameraModel::create(615, 615, 319.5, 239.5, 640, 480);
    cv::Mat sceneLinear, truth;

    explicit MountScene(const std::string& path)
    {
        const cv::Size size(640 + 2 * marginX, 480 + 2 * marginY);
        const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
        cv::Mat scaled;
        const double zoom = std::max(1.0 * size.width / image.cols, 1.0 * size.height / image.rows);
        cv::resize(image, scaled, cv::Size(), zoom, zoom, cv::INTER_CUBIC);
        const cv::Mat scene = scaled(
            cv::Rect((scaled.cols - size.width) / 2, (scaled.rows - size.height) / 2, size.width, size.height));
        cv::dynblur::srgbToLinear(scene, sceneLinear);
        truth = scene(cv::Rect(marginX, marginY, 640, 480)).clone();
    }

    //! A synthetic scene: `linear`, CV_32FC3, of the frame's size widened by the margins.
    explicit MountScene(const cv::Mat& linear) : sceneLinear(linear)
    {
        cv::dynblur::linearToSrgb(linear(cv::Rect(marginX, marginY, 640, 480)), truth, CV_8U);
    }

    /* The 8-bit frame `motion` blurs, read by `shutter`: physical blur, sensor noise, sRGB. `truth` is
       the view at Q(tRef), seconds (NaN: the final rest). */
    cv::Mat capture(const cv::Ptr<cv::dynblur::CameraMotion>& motion, const cv::dynblur::RollingShutter& shutter,
                    uint64 seed, double tRef = std::numeric_limits<double>::quiet_NaN()) const
    {
        cv::Mat blurred, noisy, frame;
        cv::dynblur::renderBlurred(sceneLinear, motion, camera, shutter, blurred, tRef);
        cv::dynblur::addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, seed);
        cv::dynblur::linearToSrgb(noisy, frame, CV_8U);
        return frame;
    }
};

//! The middle of the run of frame starts (0.25 ms steps) whose frame under `motion` is in `window`.
inline cv::dynblur::RollingShutter shutterInWindow(const cv::Ptr<cv::dynblur::CameraMotion>& motion, int window,
                                                   double lineDelay)
{
    cv::dynblur::RollingShutter shutter(0.0, 0.008, lineDelay, 480);
    double first = 0, last = 0;
    bool found = false;
    for (double start = -0.05; start < 0.3; start += 2.5e-4)
    {
        shutter.frameStart = start;
        const bool in = cv::dynblur::classifyExposure(motion, shutter) == window;
        if (in && !found)
            first = start, found = true;
        if (found && !in)
            break;
        last = start;
    }
    EXPECT_TRUE(found) << "no frame start gives window " << window;
    shutter.frameStart = 0.5 * (first + last);
    return shutter;
}

}  // namespace dynblur_test

#endif
