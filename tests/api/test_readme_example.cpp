// SPDX-License-Identifier: Apache-2.0
// The C++ example of README.md ("Using it from C++"), compiled and run here so the README cannot
// drift from the API: the two functions below are the README's two code blocks, line for line.
#include "scene.hpp"

#include <gtest/gtest.h>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace {

// ---- README.md, "Using it from C++" (first block) ----
using namespace cv::dynblur;

cv::Mat restoreOneFrame(const cv::Mat& frame)  // 640×480, CV_8UC3 sRGB or CV_32FC3 linear in [0, 1]
{
    cv::Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);  // Hz, damping ratio, rad per level
    SwitchSchedule move = SwitchPlanner::create(plant, 16)->plan(0.0, 10 * CV_PI / 180, 0.0);  // rad, rad, s
    cv::Ptr<CameraModel> camera = CameraModel::create(615, 615, 319.5, 239.5, 640, 480);  // or CameraModel::load(xml)
    RollingShutter shutter(0.005, 0.008, 62.5e-6, 480);  // frame start, exposure, line delay (s); rows
    if (classifyExposure(plant, move, shutter) == EXPOSURE_IV)  // EXPOSURE_I .. EXPOSURE_IV
        return frame;                                             // IV: still throughout, nothing to undo
    cv::Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(plant, camera);
    cv::Mat restored;
    deblurrer->deblur(frame, move, shutter, restored);  // the view at the move's final angle
    return restored;
}

// ---- README.md, "Using it from C++" (second block: the frame-rate setting) ----
void useFrameRateSetting(DynamicDeblurrer& deblurrer)
{
    deblurrer.setPreset(DEBLUR_PRESET_FRAME_RATE);  // explicit setters still override it
}
// ---- README.md, "Using it from C++" (third block: a hand-held camera with a gyroscope) ----
cv::Mat restoreHandHeldFrame(const cv::Mat& frame, const cv::String& gyroLogPath)  // 640×480, a .gcsv or t,gx,gy,gz CSV
{
    GyroLogOptions options;
    options.orientation = "XYZ";   // gyro axes as camera axes (x right, y down, z forward); lowercase inverts
    options.estimateBias = true;   // from the log's still intervals
    cv::Ptr<CameraMotion> motion = GyroLog::load(gyroLogPath, options).toMotion();
    cv::Ptr<CameraModel> camera = CameraModel::create(615, 615, 319.5, 239.5, 640, 480);
    RollingShutter shutter(0.100, 0.020, 62.5e-6, 480);  // frame start on the log's clock, exposure, line delay (s)
    cv::Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(camera);  // no plant: the motion is measured
    cv::Mat restored;
    deblurrer->deblur(frame, motion, shutter, restored);  // the view at the frame's mid-exposure
    return restored;
}
// ---- end of the README's code ----

//! A 640×480 frame of the generated scene blurred by the README's move, in 8-bit sRGB.
cv::Mat blurredFrame(cv::Mat& sharpLinear)
{
    cv::Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    SwitchSchedule move = SwitchPlanner::create(plant, 16)->plan(0.0, 10 * CV_PI / 180, 0.0);
    cv::Ptr<CameraModel> camera = CameraModel::create(615, 615, 319.5, 239.5, 640, 480);
    RollingShutter shutter(0.005, 0.008, 62.5e-6, 480);
    const cv::Mat scene = dynblur_samples::makeScene(cv::Size(640, 480));
    srgbToLinear(scene, sharpLinear);
    cv::Mat blurred, out;
    renderBlurred(sharpLinear, plant, move, camera, shutter, blurred);
    linearToSrgb(blurred, out, CV_8U);
    return out;
}

/* Mean |a − truth| in linear intensity over the rows the move blurred: frame rows start every
   62.5 µs from 5 ms and the fast 10° move settles at about 15 ms, so the rows above ~160. */
double meanAbsError(const cv::Mat& a8, const cv::Mat& truthLinear)
{
    cv::Mat a;
    srgbToLinear(a8, a);
    const cv::Rect inner(20, 20, a.cols - 40, 140);
    return cv::norm(a(inner), truthLinear(inner), cv::NORM_L1) / double(inner.area() * a.channels());
}

}  // namespace

TEST(ReadmeExample, RestoresAFrameCloserToTheTruth)
{
    cv::Mat sharp;
    const cv::Mat frame = blurredFrame(sharp);
    const cv::Mat restored = restoreOneFrame(frame);
    ASSERT_EQ(restored.size(), frame.size());
    ASSERT_EQ(restored.type(), frame.type());
    const double blurredError = meanAbsError(frame, sharp), restoredError = meanAbsError(restored, sharp);
    std::printf("[ measured ] README example, blurred rows: mean |error| %.4f blurred, %.4f restored\n",
                blurredError, restoredError);
    EXPECT_LT(restoredError, 0.9 * blurredError);
}

TEST(ReadmeExample, FrameRateSettingRestoresAFrameCloserToTheTruth)
{
    cv::Mat sharp;
    const cv::Mat frame = blurredFrame(sharp);
    cv::Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    cv::Ptr<DynamicDeblurrer> deblurrer =
        DynamicDeblurrer::create(plant, CameraModel::create(615, 615, 319.5, 239.5, 640, 480));
    useFrameRateSetting(*deblurrer);
    EXPECT_EQ(deblurrer->getPsfModel(), PSF_AUTO);
    EXPECT_EQ(deblurrer->getRLParams().blurPrecision, RL_BLUR_BFLOAT16);
    cv::Mat restored;
    deblurrer->deblur(frame, SwitchPlanner::create(plant, 16)->plan(0.0, 10 * CV_PI / 180, 0.0),
                      RollingShutter(0.005, 0.008, 62.5e-6, 480), restored);
    const double blurredError = meanAbsError(frame, sharp), restoredError = meanAbsError(restored, sharp);
    std::printf("[ measured ] README frame-rate setting, blurred rows: mean |error| %.4f blurred, %.4f restored\n",
                blurredError, restoredError);
    EXPECT_LT(restoredError, 0.9 * blurredError);
}

TEST(ReadmeExample, HandHeldFrameRestoredFromAGyroLog)
{
    // A gcsv log of a shake about all three axes (rad/s at 200 Hz; still for the first 0.5 s, so the
    // bias has an interval to be estimated from), the frame rendered from its motion.
    const char* dir = std::getenv("TMPDIR");
    const std::string path = std::string(dir && *dir ? dir : "/tmp") + "/dynblur_readme_" + std::to_string(::getpid()) +
                             ".gcsv";
    {
        std::ofstream log(path);
        log << "GYROFLOW IMU LOG\nversion,1.3\norientation,XYZ\ntscale,0.001\ngscale,0.001\nt,gx,gy,gz\n";
        for (int k = 0; k <= 240; k++)
        {
            const double t = -0.5 + 0.005 * k, on = t > 0 ? 1.0 : 0.0;
            log << std::lround(t * 1000) << "," << std::lround(on * 600 * std::sin(2 * CV_PI * 3.1 * t)) << ","
                << std::lround(on * 500 * std::sin(2 * CV_PI * 4.7 * t + 1)) << ","
                << std::lround(on * 700 * std::sin(2 * CV_PI * 6.3 * t + 2)) << "\n";
        }
    }
    cv::Ptr<CameraModel> camera = CameraModel::create(615, 615, 319.5, 239.5, 640, 480);
    const cv::Mat scene = dynblur_samples::makeScene(cv::Size(640 + 96, 480 + 96));
    cv::Mat sharpLinear, blurred, frame;
    srgbToLinear(scene, sharpLinear);
    renderBlurred(sharpLinear, GyroLog::load(path).toMotion(), camera, RollingShutter(0.100, 0.020, 62.5e-6, 480),
                  blurred);
    linearToSrgb(blurred, frame, CV_8U);
    const cv::Mat restored = restoreHandHeldFrame(frame, path);
    std::remove(path.c_str());
    const cv::Mat truth = sharpLinear(cv::Rect(48, 48, 640, 480));
    auto error = [&](const cv::Mat& a8) {
        cv::Mat a;
        srgbToLinear(a8, a);
        const cv::Rect inner(20, 20, 600, 440);
        return cv::norm(a(inner), truth(inner), cv::NORM_L1) / double(inner.area() * a.channels());
    };
    const double blurredError = error(frame), restoredError = error(restored);
    std::printf("[ measured ] README hand-held example: mean |error| %.4f blurred, %.4f restored\n", blurredError,
                restoredError);
    EXPECT_LT(restoredError, 0.8 * blurredError);
}
