// SPDX-License-Identifier: Apache-2.0
// PSF bank generation for a 1280x960 rolling-shutter frame (30 fps readout, 8 ms exposure) during a
// 10° saccade. Two frames: the hand-made three-switch saccade starting with the frame (window I/II,
// paths up to 187 px), and the window-III frame of perf_deblurrer.cpp (robust plan, frame 12 ms
// into the move: the frame the frame-rate restoration sees). Wall-clock time: generation runs on
// all cores.
#include <benchmark/benchmark.h>

#include <opencv2/dynblur.hpp>

using namespace cv;
using namespace cv::dynblur;

namespace {

struct Frame
{
    Ptr<Plant> plant;
    Ptr<CameraModel> camera;
    SwitchSchedule schedule;
    RollingShutter shutter;
};

const Frame& saccadeFrame()
{
    static const Frame f{Plant::create(14.4, 0.12, CV_PI / 180.0), CameraModel::create(1230, 1230, 640, 480, 1280, 960),
                         SwitchSchedule({0.0, 0.0127, 0.0296}, {16, 4, 10}, 0),
                         RollingShutter(0.0, 0.008, 1.0 / 30 / 960, 960)};
    return f;
}

const Frame& windowIIIFrame()
{
    static const Frame f = [] {
        Frame w;
        w.plant = Plant::create(14.4, 0.12, CV_PI / 180);
        w.camera = CameraModel::create(1230, 1230, 639.5, 479.5, 1280, 960);
        w.schedule = SwitchPlanner::create(w.plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
        w.shutter = RollingShutter{0.012, 0.008, 1.0 / 30 / 960, 960};
        return w;
    }();
    return f;
}

void generateBank(benchmark::State& state, const Frame& f, int model, int bandRows, Size grid)
{
    Ptr<PsfGenerator> gen = PsfGenerator::create(f.plant, f.camera);
    gen->setBandRows(bandRows);
    gen->setTileGrid(grid);
    size_t kernels = 0;
    for (auto _ : state)
    {
        PsfBank bank = gen->generate(model, f.schedule, f.shutter);
        kernels = bank.kernels.size();
        benchmark::DoNotOptimize(bank.kernels.data());
    }
    state.counters["kernels"] = (double)kernels;
}

void BM_PsfRowsPerRow(benchmark::State& s) { generateBank(s, saccadeFrame(), PSF_ROWS, 1, Size()); }
void BM_PsfRowsAuto(benchmark::State& s) { generateBank(s, saccadeFrame(), PSF_ROWS, 0, Size()); }
void BM_PsfTilesAuto(benchmark::State& s) { generateBank(s, saccadeFrame(), PSF_TILES, 0, Size()); }
void BM_PsfTiles8x16(benchmark::State& s) { generateBank(s, saccadeFrame(), PSF_TILES, 0, Size(8, 16)); }
void BM_PsfUniform(benchmark::State& s) { generateBank(s, saccadeFrame(), PSF_UNIFORM, 0, Size()); }
void BM_PsfRowsAutoWindowIII(benchmark::State& s) { generateBank(s, windowIIIFrame(), PSF_ROWS, 0, Size()); }
void BM_PsfTilesAutoWindowIII(benchmark::State& s) { generateBank(s, windowIIIFrame(), PSF_TILES, 0, Size()); }
void BM_PsfUniformWindowIII(benchmark::State& s) { generateBank(s, windowIIIFrame(), PSF_UNIFORM, 0, Size()); }
void BM_PsfAutoWindowIII(benchmark::State& s) { generateBank(s, windowIIIFrame(), PSF_AUTO, 0, Size()); }

//! PSF_AUTO's choice alone (PsfGenerator::plan: the tile nodes and the sampled displacements), window III frame.
void BM_PsfPlanWindowIII(benchmark::State& state)
{
    const Frame& f = windowIIIFrame();
    Ptr<PsfGenerator> gen = PsfGenerator::create(f.camera);
    const Ptr<CameraMotion> motion = CameraMotion::fromPlant(f.plant, f.schedule);
    for (auto _ : state)
    {
        PsfPlan plan = gen->plan(motion, f.shutter);
        benchmark::DoNotOptimize(plan.bandModel.data());
    }
}

}  // namespace

BENCHMARK(BM_PsfRowsPerRow)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PsfRowsAuto)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PsfTilesAuto)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PsfTiles8x16)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PsfUniform)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PsfRowsAutoWindowIII)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PsfTilesAutoWindowIII)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PsfUniformWindowIII)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PsfAutoWindowIII)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PsfPlanWindowIII)->Unit(benchmark::kMillisecond)->UseRealTime();
