// SPDX-License-Identifier: Apache-2.0
// The cost of a 3-axis camera motion: the frame-rate setting and the default on a 1280x960 RGB
// rolling-shutter frame shaken about all three axes, against the same settings on the one-axis
// saccade frame of perf_deblurrer.cpp, in paired rounds (docs/performance.md).
#include "paired_rounds.hpp"
#include "perf_baseline.hpp"

#include <benchmark/benchmark.h>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

#include <vector>

using namespace cv;
using namespace cv::dynblur;
using dynblur_perf::median;
using dynblur_perf::medianRatio;

namespace {

/* A hand-held frame at the saccade frame's camera and shutter: a gyroscope's 200 Hz log of a shake
   whose rate peaks near 45 deg/s about each axis (one sinusoid per axis, 3.7, 6.1 and 9.3 Hz), the
   frame rendered from it with a 20 ms exposure (blur paths up to ~40 px at f = 1230 px). */
struct ShakeFrame : dynblur_perf::SaccadeScene
{
    Ptr<CameraMotion> motion;
    RollingShutter handHeld{0.2, 0.020, 1.0 / 30 / 960, 960};
    Mat frame;

    ShakeFrame()
    {
        const double hz[3] = {3.7, 6.1, 9.3}, peak = 45 * CV_PI / 180;
        std::vector<double> times;
        Mat rates(0, 3, CV_64F);
        for (int k = 0; k <= 100; k++)
        {
            times.push_back(0.005 * k);
            Mat row(1, 3, CV_64F);
            for (int i = 0; i < 3; i++)
                row.at<double>(i) = peak * std::sin(2 * CV_PI * hz[i] * times.back() + i);
            rates.push_back(row);
        }
        motion = CameraMotion::fromAngularVelocity(times, rates);
        Mat sharp(960 + 2 * 64, 1280 + 2 * 64, CV_32FC3), blurred;
        randu(sharp, 0.05f, 0.95f);
        GaussianBlur(sharp, sharp, Size(0, 0), 1.5);
        renderBlurred(sharp, motion, camera, handHeld, blurred);
        addSensorNoise(blurred, frame);
    }
};

const dynblur_perf::SaccadeFrame& saccadeFrame()
{
    static const dynblur_perf::SaccadeFrame frame;
    return frame;
}

const ShakeFrame& shakeFrame()
{
    static const ShakeFrame frame;
    return frame;
}

/* Each round restores the one-axis saccade frame and the 3-axis frame, each in the frame-rate
   setting and in the default (tiles, 20 iterations, full color), and the 3-axis frame with
   DEBLUR_PRESET_FRAME_RATE. Counters: the medians (ms), the median ratios 3-axis / one-axis of each
   setting and the preset's over the default on the 3-axis frame. */
void BM_ThreeAxisPaired(benchmark::State& state)
{
    const dynblur_perf::SaccadeFrame& one = saccadeFrame();
    const ShakeFrame& three = shakeFrame();
    Ptr<DynamicDeblurrer> oneFast = DynamicDeblurrer::create(one.plant, one.camera),
                          threeFast = DynamicDeblurrer::create(three.camera),
                          oneDefault = DynamicDeblurrer::create(one.plant, one.camera),
                          threeDefault = DynamicDeblurrer::create(three.camera),
                          threePreset = DynamicDeblurrer::create(three.camera);
    threePreset->setPreset(DEBLUR_PRESET_FRAME_RATE);
    dynblur_perf::setFrameRate(*oneFast);
    dynblur_perf::setFrameRate(*threeFast);
    Mat restored;
    const std::vector<std::vector<double>> ms = dynblur_perf::timePairedRounds(
        state, {[&] { oneFast->deblur(one.frame, one.schedule, one.shutter, restored); },
                [&] { threeFast->deblur(three.frame, three.motion, three.handHeld, restored); },
                [&] { oneDefault->deblur(one.frame, one.schedule, one.shutter, restored); },
                [&] { threeDefault->deblur(three.frame, three.motion, three.handHeld, restored); },
                [&] { threePreset->deblur(three.frame, three.motion, three.handHeld, restored); }});
    state.counters["one_axis_frame_rate_ms"] = median(ms[0]);
    state.counters["three_axis_frame_rate_ms"] = median(ms[1]);
    state.counters["one_axis_default_ms"] = median(ms[2]);
    state.counters["three_axis_default_ms"] = median(ms[3]);
    state.counters["frame_rate_three_over_one"] = medianRatio(ms[1], ms[0]);
    state.counters["default_three_over_one"] = medianRatio(ms[3], ms[2]);
    state.counters["three_axis_preset_ms"] = median(ms[4]);
    state.counters["three_axis_preset_over_default"] = medianRatio(ms[4], ms[3]);
    state.counters["three_axis_default_kernels"] = double(threeDefault->getLastPsfBank().kernels.size());
}

}  // namespace

BENCHMARK(BM_ThreeAxisPaired)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5)->Repetitions(1);
