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
   whose rate peaks near `peakDegPerSec` about each axis (one sinusoid per axis, 3.7, 6.1 and
   9.3 Hz), the frame rendered from it with a 20 ms exposure (at 45 deg/s blur paths up to ~40 px at
   f = 1230 px, kernels up to 21x31 px; at 8 deg/s kernels up to 5x7 px). */
struct ShakeFrame : dynblur_perf::SaccadeScene
{
    Ptr<CameraMotion> motion;
    RollingShutter handHeld{0.2, 0.020, 1.0 / 30 / 960, 960};
    Mat frame;

    explicit ShakeFrame(double peakDegPerSec)
    {
        const double hz[3] = {3.7, 6.1, 9.3}, peak = peakDegPerSec * CV_PI / 180;
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
    static const ShakeFrame frame(45);
    return frame;
}

const ShakeFrame& gentleShakeFrame()
{
    static const ShakeFrame frame(8);
    return frame;
}

/* DEBLUR_PRESET_FRAME_RATE with `iterations` fixed, `colorIterations` of them in color at half
   resolution: what the preset would run on a frame whose kernels decided those. */
Ptr<DynamicDeblurrer> presetWith(const Ptr<CameraModel>& camera, int iterations, int colorIterations)
{
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(camera);
    deblurrer->setPreset(DEBLUR_PRESET_FRAME_RATE);
    RLParams params = deblurrer->getRLParams();
    params.iterations = iterations;
    params.colorIterations = colorIterations;
    deblurrer->setRLParams(params);
    return deblurrer;
}

/* Each round restores the one-axis saccade frame and the 3-axis frame, each in the frame-rate
   setting and in the default (tiles, 20 iterations, full color); the 3-axis frame with
   DEBLUR_PRESET_FRAME_RATE (its kernels' N = 49 px: 20 iterations) and with it at 10 iterations;
   and the gentle shake's frame with the default, the preset (L = 7 px: 8 iterations, every one in
   color at full resolution) and the preset with 10 iterations, 3 in color at half resolution.
   Counters: the medians (ms), the median ratios 3-axis / one-axis of each setting, and the preset's
   ratios. */
void BM_ThreeAxisPaired(benchmark::State& state)
{
    const dynblur_perf::SaccadeFrame& one = saccadeFrame();
    const ShakeFrame& three = shakeFrame();
    Ptr<DynamicDeblurrer> oneFast = DynamicDeblurrer::create(one.plant, one.camera),
                          threeFast = DynamicDeblurrer::create(three.camera),
                          oneDefault = DynamicDeblurrer::create(one.plant, one.camera),
                          threeDefault = DynamicDeblurrer::create(three.camera),
                          threePreset = DynamicDeblurrer::create(three.camera),
                          threeTen = presetWith(three.camera, 10, 5),
                          gentleDefault = DynamicDeblurrer::create(three.camera),
                          gentlePreset = DynamicDeblurrer::create(three.camera),
                          gentleHalf = presetWith(three.camera, 10, 3);
    threePreset->setPreset(DEBLUR_PRESET_FRAME_RATE);
    gentlePreset->setPreset(DEBLUR_PRESET_FRAME_RATE);
    const ShakeFrame& gentle = gentleShakeFrame();
    dynblur_perf::setFrameRate(*oneFast);
    dynblur_perf::setFrameRate(*threeFast);
    Mat restored;
    const std::vector<std::vector<double>> ms = dynblur_perf::timePairedRounds(
        state, {[&] { oneFast->deblur(one.frame, one.schedule, one.shutter, restored); },
                [&] { threeFast->deblur(three.frame, three.motion, three.handHeld, restored); },
                [&] { oneDefault->deblur(one.frame, one.schedule, one.shutter, restored); },
                [&] { threeDefault->deblur(three.frame, three.motion, three.handHeld, restored); },
                [&] { threePreset->deblur(three.frame, three.motion, three.handHeld, restored); },
                [&] { threeTen->deblur(three.frame, three.motion, three.handHeld, restored); },
                [&] { gentleDefault->deblur(gentle.frame, gentle.motion, gentle.handHeld, restored); },
                [&] { gentlePreset->deblur(gentle.frame, gentle.motion, gentle.handHeld, restored); },
                [&] { gentleHalf->deblur(gentle.frame, gentle.motion, gentle.handHeld, restored); }});
    state.counters["one_axis_frame_rate_ms"] = median(ms[0]);
    state.counters["three_axis_frame_rate_ms"] = median(ms[1]);
    state.counters["one_axis_default_ms"] = median(ms[2]);
    state.counters["three_axis_default_ms"] = median(ms[3]);
    state.counters["frame_rate_three_over_one"] = medianRatio(ms[1], ms[0]);
    state.counters["default_three_over_one"] = medianRatio(ms[3], ms[2]);
    state.counters["three_axis_preset_ms"] = median(ms[4]);
    state.counters["three_axis_preset_over_default"] = medianRatio(ms[4], ms[3]);
    state.counters["three_axis_preset_over_10_iterations"] = medianRatio(ms[4], ms[5]);
    state.counters["gentle_default_ms"] = median(ms[6]);
    state.counters["gentle_preset_ms"] = median(ms[7]);
    state.counters["gentle_preset_over_default"] = medianRatio(ms[7], ms[6]);
    state.counters["gentle_preset_over_half_color"] = medianRatio(ms[7], ms[8]);
    state.counters["three_axis_default_kernels"] = double(threeDefault->getLastPsfBank().kernels.size());
}

}  // namespace

BENCHMARK(BM_ThreeAxisPaired)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5)->Repetitions(1);
