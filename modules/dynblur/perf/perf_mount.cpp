// SPDX-License-Identifier: Apache-2.0
// The cost of a pan-tilt head's frame: the default and the frame-rate preset on a 1280x960 RGB
// rolling-shutter frame of a coordinated 10 deg pan + 6 deg tilt, against the same settings on the
// one-axis saccade frame of perf_deblurrer.cpp, in paired rounds (docs/performance.md).
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

/* The saccade frame's camera and shutter on a pan-tilt head: pan about y carries tilt about x, each
   the seed's positioner (14.4 Hz, ζ 0.12, 1° per level, ±16), moved 10° and 6° together by
   MountPlanner (robust, as the one-axis frame's plan). */
struct PanTiltFrame : dynblur_perf::SaccadeScene
{
    Ptr<CameraMotion> motion;
    Mat frame;

    PanTiltFrame()
    {
        Ptr<Mount> mount = Mount::create();
        mount->addAxis(Vec3d(0, 1, 0), Plant::create(14.4, 0.12, CV_PI / 180), -16, 16);
        mount->addAxis(Vec3d(1, 0, 0), Plant::create(14.4, 0.12, CV_PI / 180), -16, 16);
        const MountMove move =
            MountPlanner::create(mount, PLAN_ROBUST)->plan({0, 0}, {10 * CV_PI / 180, 6 * CV_PI / 180});
        motion = mount->motion(move.schedules);
        Mat sharp(960 + 2 * 256, 1280 + 2 * 256, CV_32FC3), blurred;
        randu(sharp, 0.05f, 0.95f);
        GaussianBlur(sharp, sharp, Size(0, 0), 1.5);
        renderBlurred(sharp, motion, camera, shutter, blurred);
        addSensorNoise(blurred, frame);
    }
};

/* Each round restores the one-axis saccade frame and the pan-tilt frame, each with the default and
   with DEBLUR_PRESET_FRAME_RATE. Counters: the medians (ms) and the median ratios pan-tilt / one-axis. */
void BM_PanTiltPaired(benchmark::State& state)
{
    static const dynblur_perf::SaccadeFrame one;
    static const PanTiltFrame two;
    Ptr<DynamicDeblurrer> oneDefault = DynamicDeblurrer::create(one.plant, one.camera),
                          twoDefault = DynamicDeblurrer::create(two.camera),
                          onePreset = DynamicDeblurrer::create(one.plant, one.camera),
                          twoPreset = DynamicDeblurrer::create(two.camera);
    onePreset->setPreset(DEBLUR_PRESET_FRAME_RATE);
    twoPreset->setPreset(DEBLUR_PRESET_FRAME_RATE);
    Mat restored;
    const std::vector<std::vector<double>> ms = dynblur_perf::timePairedRounds(
        state, {[&] { oneDefault->deblur(one.frame, one.schedule, one.shutter, restored); },
                [&] { twoDefault->deblur(two.frame, two.motion, two.shutter, restored); },
                [&] { onePreset->deblur(one.frame, one.schedule, one.shutter, restored); },
                [&] { twoPreset->deblur(two.frame, two.motion, two.shutter, restored); }});
    state.counters["one_axis_default_ms"] = median(ms[0]);
    state.counters["pan_tilt_default_ms"] = median(ms[1]);
    state.counters["one_axis_preset_ms"] = median(ms[2]);
    state.counters["pan_tilt_preset_ms"] = median(ms[3]);
    state.counters["default_pan_tilt_over_one_axis"] = medianRatio(ms[1], ms[0]);
    state.counters["preset_pan_tilt_over_one_axis"] = medianRatio(ms[3], ms[2]);
    state.counters["pan_tilt_tiles_share"] = twoDefault->getLastPlan().rowShare(PSF_TILES);
}

}  // namespace

BENCHMARK(BM_PanTiltPaired)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5)->Repetitions(1);
