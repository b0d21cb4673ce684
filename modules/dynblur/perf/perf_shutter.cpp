// SPDX-License-Identifier: Apache-2.0
// How long classifyExposure takes for one 1280x960 rolling-shutter frame (30 fps readout, 8 ms
// exposure) of the robust 10° saccade, with the frame placed in each exposure window.
#include <benchmark/benchmark.h>

#include <opencv2/dynblur.hpp>

using namespace cv;
using namespace cv::dynblur;

namespace {

struct SaccadeMove
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    SwitchSchedule schedule = SwitchPlanner::create(plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
};

const SaccadeMove& saccadeMove()
{
    static const SaccadeMove move;
    return move;
}

// Argument: the window the frame is placed in (frame starts chosen for this move).
void BM_ClassifyExposure(benchmark::State& state)
{
    const SaccadeMove& m = saccadeMove();
    const int window = static_cast<int>(state.range(0));
    const double frameStart[5] = {0, -0.020, 0.003, 0.012, 0.200};
    const RollingShutter shutter(frameStart[window], 0.008, 1.0 / 30 / 960, 960);
    if (classifyExposure(m.plant, m.schedule, shutter) != window)
        state.SkipWithError("the frame is not in the intended exposure window");
    for (auto _ : state)
        benchmark::DoNotOptimize(classifyExposure(m.plant, m.schedule, shutter));
}

}  // namespace

BENCHMARK(BM_ClassifyExposure)->ArgName("window")->DenseRange(EXPOSURE_I, EXPOSURE_IV)->Unit(benchmark::kMicrosecond);
