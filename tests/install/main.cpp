// SPDX-License-Identifier: Apache-2.0
// An application using the installed dynblur package: plans a 5° saccade, renders the frame a
// rolling-shutter camera takes while the mount settles (window III), restores it and checks that
// the restoration is closer to the sharp view than the blurred frame. Exit status 0 only then.
// Built by scripts/install_check.sh with find_package(dynblur) and with pkg-config, and by
// scripts/contrib_check.sh against an OpenCV build tree that contains the module.
#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

using namespace cv;
using namespace cv::dynblur;

namespace {

const double kDeg = CV_PI / 180.0;

//! A synthetic sRGB scene with edges in every direction: a checkerboard with discs and lines on it.
Mat syntheticScene(Size size)
{
    Mat scene(size, CV_8UC3);
    for (int y = 0; y < size.height; ++y)
        for (int x = 0; x < size.width; ++x)
            scene.at<Vec3b>(y, x) = ((x / 24 + y / 24) % 2) ? Vec3b(200, 180, 150) : Vec3b(60, 80, 40);
    RNG rng(7);
    for (int i = 0; i < 40; ++i)
    {
        // Braces: their values are drawn left to right with every compiler.
        const Point centre{rng.uniform(0, size.width), rng.uniform(0, size.height)};
        const Scalar color{double(rng.uniform(0, 256)), double(rng.uniform(0, 256)), double(rng.uniform(0, 256))};
        if (i % 2)
            circle(scene, centre, rng.uniform(4, 20), color, FILLED, LINE_AA);
        else
        {
            const Point end{rng.uniform(0, size.width), rng.uniform(0, size.height)};
            line(scene, centre, end, color, 2, LINE_AA);
        }
    }
    return scene;
}

//! PSNR (dB, 8-bit) of `test` against `reference` over the non-zero pixels of `mask`.
double maskedPsnr(const Mat& reference, const Mat& test, const Mat& mask)
{
    Mat difference;
    absdiff(reference, test, difference);
    difference.convertTo(difference, CV_64F);
    difference = difference.mul(difference);
    const Scalar meanSquared = mean(difference, mask);
    const double mse = (meanSquared[0] + meanSquared[1] + meanSquared[2]) / 3.0;
    return 10.0 * std::log10(255.0 * 255.0 / std::max(mse, 1e-12));
}

}  // namespace

int main()
{
    const Size frameSize(320, 240);
    Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);  // ωn = 2π·14.4 rad/s, ζ = 0.12, 1° per cell level
    Ptr<CameraModel> camera = CameraModel::create(307.5, 307.5, 159.5, 119.5, frameSize.width, frameSize.height);
    const SwitchSchedule schedule = SwitchPlanner::create(plant, 16)->plan(0.0, 5 * kDeg, 0.0);

    // The sharp view at the final angle, wider than the frame by the image motion of the move.
    const int margin = static_cast<int>(std::ceil(307.5 * std::tan(5 * kDeg))) + 16;
    const Mat scene = syntheticScene(Size(frameSize.width + 2 * margin, frameSize.height + 2 * margin));
    const Mat truth = scene(Rect(margin, margin, frameSize.width, frameSize.height)).clone();

    // A 30 fps rolling shutter, 8 ms exposure, at the earliest frame start (1 ms steps) that gives
    // window III: moving at the start of the readout, still before its end; the most blurred of them.
    RollingShutter shutter(0.0, 0.008, 1.0 / 30 / frameSize.height, frameSize.height);
    std::vector<double> windowIII;
    for (double start = -0.05; start < 0.25; start += 0.001)
    {
        shutter.frameStart = start;
        if (classifyExposure(plant, schedule, shutter) == EXPOSURE_III)
            windowIII.push_back(start);
    }
    if (windowIII.empty())
    {
        std::fprintf(stderr, "dynblur_consumer: no window III frame for this move\n");
        return 1;
    }
    shutter.frameStart = windowIII.front();

    Mat sceneLinear, blurredLinear, frame;
    srgbToLinear(scene, sceneLinear);
    renderBlurred(sceneLinear, plant, schedule, camera, shutter, blurredLinear);
    linearToSrgb(blurredLinear, frame, CV_8U);

    const auto start = std::chrono::steady_clock::now();
    Mat restored, valid;
    DynamicDeblurrer::create(plant, camera)->deblur(frame, schedule, shutter, restored,
                                                    std::numeric_limits<double>::quiet_NaN(), valid);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    // Judged where the frame observed the scene, 8 px inside the border.
    Mat judged = Mat::zeros(valid.size(), CV_8U);
    const Rect inner(8, 8, frameSize.width - 16, frameSize.height - 16);
    valid(inner).copyTo(judged(inner));
    const double blurredPsnr = maskedPsnr(truth, frame, judged);
    const double restoredPsnr = maskedPsnr(truth, restored, judged);
    std::printf("dynblur_consumer: %d switches, frame start %.1f ms (window III), restored in %.0f ms\n",
                static_cast<int>(schedule.times.size()), 1e3 * shutter.frameStart, ms);
    std::printf("dynblur_consumer: PSNR blurred %.2f dB, restored %.2f dB over %d pixels\n", blurredPsnr,
                restoredPsnr, countNonZero(judged));
    if (!(restoredPsnr > blurredPsnr))
    {
        std::fprintf(stderr, "dynblur_consumer: FAIL: the restoration is not closer to the sharp view\n");
        return 1;
    }
    std::printf("dynblur_consumer: OK\n");
    return 0;
}
