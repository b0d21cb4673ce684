// SPDX-License-Identifier: Apache-2.0
// Shared by the quality tests: a 10-degree saccade seen by a C270-like webcam at half resolution,
// rendered with the physical forward model and sensor noise.
#ifndef DYNBLUR_TEST_SACCADE_SCENE_HPP
#define DYNBLUR_TEST_SACCADE_SCENE_HPP

#include "frame_timing.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace dynblur_test {

using namespace cv;
using namespace cv::dynblur;

inline const double kDeg = CV_PI / 180.0;

// A C270 at half resolution (same field of view): 640x480, fx = 615 px, 30 fps readout.
struct SaccadeScene
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    Ptr<CameraModel> camera;
    SwitchSchedule schedule;
    Mat sceneLinear;  // the view at θ_ref, wider than the frame
    Mat truth;        // 8-bit sRGB frame-sized view at θ_ref
    int marginX = 24, marginY = 0;

    /** `focalPx` and `moveDeg`: another lens (focal length, pixels) and saccade (degrees) than the
    C270's 615 px and 10°. */
    explicit SaccadeScene(const std::string& imagePath, double focalPx = 615.0, double moveDeg = 10)
        : camera(CameraModel::create(focalPx, focalPx, 319.5, 239.5, 640, 480))
    {
        schedule = SwitchPlanner::create(plant, 16)->plan(0.0, moveDeg * kDeg, 0.0);
        marginY = static_cast<int>(std::ceil(focalPx * std::tan(moveDeg * kDeg))) + 24;
        const Size sceneSize(640 + 2 * marginX, 480 + 2 * marginY);
        Mat image = imread(imagePath, IMREAD_COLOR), scaled;
        // Scale to cover the scene, keeping the aspect ratio, then take the centre.
        const double zoom = std::max(1.0 * sceneSize.width / image.cols, 1.0 * sceneSize.height / image.rows);
        resize(image, scaled, Size(), zoom, zoom, INTER_CUBIC);
        Mat scene = scaled(Rect((scaled.cols - sceneSize.width) / 2, (scaled.rows - sceneSize.height) / 2,
                                sceneSize.width, sceneSize.height)).clone();
        srgbToLinear(scene, sceneLinear);
        truth = scene(Rect(marginX, marginY, 640, 480)).clone();
    }

    RollingShutter shutterInWindow(int window, double lineDelay) const
    {
        RollingShutter shutter(0.0, 0.008, lineDelay, 480);
        EXPECT_TRUE(dynblur_samples::frameStartInWindow(plant, schedule, shutter, window, shutter.frameStart))
            << "no frame start gives window " << window;
        return shutter;
    }

    //! The 8-bit frame the camera delivers: physical blur, sensor noise, sRGB encoding.
    Mat capture(const RollingShutter& shutter, uint64 seed) const { return capture(shutter, seed, plant); }

    //! The same, with the positioner moving as `truePlant` does (one that drifted from the nominal plant).
    Mat capture(const RollingShutter& shutter, uint64 seed, const Ptr<Plant>& truePlant) const
    {
        Mat blurred, noisy, frame;
        renderBlurred(sceneLinear, truePlant, schedule, camera, shutter, blurred);
        addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, seed);
        linearToSrgb(noisy, frame, CV_8U);
        return frame;
    }

    //! Rows [first, first + count) with the largest total image motion, from the plant alone.
    Range mostBlurredRows(const RollingShutter& shutter, int count) const
    {
        std::vector<double> motion(static_cast<size_t>(shutter.rows));
        for (int r = 0; r < shutter.rows; ++r)
        {
            const Vec2d interval = shutter.rowInterval(r);
            Mat t(1, 64, CV_64F), omega;
            for (int k = 0; k < 64; ++k)
                t.at<double>(k) = interval[0] + (interval[1] - interval[0]) * (k + 0.5) / 64;
            plant->velocity(schedule, t, omega);
            motion[static_cast<size_t>(r)] = sum(abs(omega))[0];
        }
        double best = -1;
        int bestFirst = 0;
        for (int first = 0; first + count <= shutter.rows; ++first)
        {
            double total = 0;
            for (int r = first; r < first + count; ++r)
                total += motion[static_cast<size_t>(r)];
            if (total > best)
                best = total, bestFirst = first;
        }
        return Range(bestFirst, bestFirst + count);
    }
};

//! The pixels a quality figure is judged on: `rows` of the valid mask, less an 8-pixel border.
inline Mat judgedPixels(const Mat& valid, const Range& rows)
{
    Mat judged = Mat::zeros(valid.size(), CV_8U);
    valid.rowRange(rows).copyTo(judged.rowRange(rows));
    judged(Rect(0, 0, judged.cols, 8)).setTo(0);
    judged(Rect(0, judged.rows - 8, judged.cols, 8)).setTo(0);
    judged.colRange(0, 8).setTo(0);
    judged.colRange(judged.cols - 8, judged.cols).setTo(0);
    return judged;
}

}  // namespace dynblur_test

#endif
