// SPDX-License-Identifier: Apache-2.0
// Test support: a natural image seen by a 640×480 camera held by a shaking hand (rotation tests).
#ifndef DYNBLUR_TEST_SHAKE_SCENE_HPP
#define DYNBLUR_TEST_SHAKE_SCENE_HPP

#include "rotation_motion.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <limits>
#include <string>

namespace dynblur_test {

/* A 640×480 camera at f = 600 px (56° across) held by a shaking hand: the view at Q_ref of a
   natural image, wider than the frame by kMargin on each side so the shake never looks past it. */
struct ShakeScene
{
    static constexpr int kMargin = 64;
    cv::Ptr<cv::dynblur::CameraModel> camera = cv::dynblur::CameraModel::create(600, 600, 319.5, 239.5, 640, 480);
    cv::Ptr<cv::dynblur::CameraMotion> motion;
    cv::Mat sceneLinear, truth;

    ShakeScene(const std::string& imagePath, double peakRateDegPerSec) : motion(handShake(peakRateDegPerSec))
    {
        const cv::Size sceneSize(640 + 2 * kMargin, 480 + 2 * kMargin);
        const cv::Mat image = cv::imread(imagePath, cv::IMREAD_COLOR);
        cv::Mat scaled;
        const double zoom = std::max(1.0 * sceneSize.width / image.cols, 1.0 * sceneSize.height / image.rows);
        cv::resize(image, scaled, cv::Size(), zoom, zoom, cv::INTER_AREA);
        const cv::Mat scene = scaled(cv::Rect((scaled.cols - sceneSize.width) / 2,
                                              (scaled.rows - sceneSize.height) / 2, sceneSize.width, sceneSize.height));
        cv::dynblur::srgbToLinear(scene, sceneLinear);
        truth = scene(cv::Rect(kMargin, kMargin, 640, 480)).clone();
    }

    /* The 8-bit frame: the forward model, Poisson and read noise, sRGB. The image is the view at
       Q(tRef) (NaN: the frame's own mid-exposure, so `truth` is what a restoration should give). */
    cv::Mat capture(const cv::dynblur::RollingShutter& shutter, uint64 seed,
                    double tRef = std::numeric_limits<double>::quiet_NaN()) const
    {
        cv::Mat blurred, noisy, frame;
        cv::dynblur::renderBlurred(sceneLinear, motion, camera, shutter, blurred, tRef);
        cv::dynblur::addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, seed);
        cv::dynblur::linearToSrgb(noisy, frame, CV_8U);
        return frame;
    }
};

}  // namespace dynblur_test

#endif
