// SPDX-License-Identifier: Apache-2.0
// How the frame-rate restoration's cost grows: DynamicDeblurrer with the row-wise model (the
// PSF_ROWS bank a C270-like camera sees in window III of a 10° saccade, scaled with the image)
// in its frame-rate setting (the luminance at full resolution, 3 color iterations at half
// resolution once there are more than 3; up to 3, every one in color) against image size and
// iteration count, and the machine's memory bandwidth, which bounds any
// restoration that streams its planes from DRAM. scripts/benchmark.py plots these beside the
// bandwidth line.
#include "perf_baseline.hpp"

#include <opencv2/dynblur.hpp>

#include <benchmark/benchmark.h>

#include <cstring>
#include <vector>

namespace {

using namespace cv;
using namespace cv::dynblur;

/* DynamicDeblurrer with PSF_ROWS for a camera of `width` × `height` with the C270's field of view,
   and a random frame in window III of a 10° saccade: the whole frame-rate path (classification,
   PSF bank, restoration into a reused output). */
struct ScaledDeblur
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    SwitchSchedule schedule = SwitchPlanner::create(plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
    RollingShutter shutter;
    Ptr<DynamicDeblurrer> deblurrer;
    Mat frame, restored;

    ScaledDeblur(int width, int height, int iterations) : shutter{0.012, 0.008, 1.0 / 30 / height, height}
    {
        const double scale = width / 1280.0;
        Ptr<CameraModel> camera = CameraModel::create(1230 * scale, 1230 * scale, (width - 1) / 2.0,
                                                      (height - 1) / 2.0, width, height);
        deblurrer = DynamicDeblurrer::create(plant, camera);
        dynblur_perf::setFrameRate(*deblurrer, iterations);
        frame.create(height, width, CV_32FC3);
        randu(frame, 0.05f, 0.95f);
    }

    void run(benchmark::State& state)
    {
        deblurrer->deblur(frame, schedule, shutter, restored);  // warm: buffers allocated once
        for (auto _ : state)
        {
            deblurrer->deblur(frame, schedule, shutter, restored);
            benchmark::DoNotOptimize(restored.data);
        }
        state.counters["megapixels"] = frame.total() / 1e6;
        state.counters["iterations"] = deblurrer->getRLParams().iterations;
    }
};

//! Time against size: 10 iterations, 320×240 to 2560×1920.
void BM_RestoreRowsVsSize(benchmark::State& state)
{
    const int width = static_cast<int>(state.range(0));
    ScaledDeblur(width, width * 3 / 4, 10).run(state);
}
BENCHMARK(BM_RestoreRowsVsSize)->ArgName("width")->Arg(320)->Arg(640)->Arg(1280)->Arg(1920)->Arg(2560)
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);

//! Time against iterations at 1280×960.
void BM_RestoreRowsVsIterations(benchmark::State& state)
{
    ScaledDeblur(1280, 960, static_cast<int>(state.range(0))).run(state);
}
BENCHMARK(BM_RestoreRowsVsIterations)->ArgName("iterations")->Arg(1)->Arg(2)->Arg(5)->Arg(10)->Arg(20)->Arg(40)
    ->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);

/* Sustained DRAM bandwidth: a 256 MiB copy (far beyond the caches), both cores, as
   bytes read + written per second. */
void BM_MemoryBandwidth(benchmark::State& state)
{
    const size_t floats = size_t(64) << 20;
    Mat source(1, int(floats), CV_32F, Scalar(1)), target(1, int(floats), CV_32F, Scalar(0));
    const int stripes = std::max(getNumThreads(), 1) * 4;
    for (auto _ : state)
    {
        parallel_for_(Range(0, stripes), [&](const Range& r) {
            const size_t begin = floats * size_t(r.start) / size_t(stripes);
            const size_t end = floats * size_t(r.end) / size_t(stripes);
            std::memcpy(target.ptr<float>() + begin, source.ptr<float>() + begin, (end - begin) * sizeof(float));
        });
        benchmark::DoNotOptimize(target.data);
    }
    state.SetBytesProcessed(int64_t(state.iterations()) * int64_t(2 * floats * sizeof(float)));
}
BENCHMARK(BM_MemoryBandwidth)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);

}  // namespace
