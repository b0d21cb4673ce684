// PSF bank generation for a 1280x960 rolling-shutter frame during a 10° saccade.
#include <benchmark/benchmark.h>

#include <opencv2/dynblur.hpp>

using namespace cv;
using namespace cv::dynblur;

namespace {

struct SaccadeFrame
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180.0);
    Ptr<CameraModel> camera = CameraModel::create(1230, 1230, 640, 480, 1280, 960);
    SwitchSchedule schedule = SwitchSchedule({0.0, 0.0127, 0.0296}, {16, 4, 10}, 0);
    RollingShutter shutter = RollingShutter(0.0, 0.008, 1.0 / 30 / 960, 960);
};

void generateBank(benchmark::State& state, int model, int bandRows, Size grid)
{
    SaccadeFrame f;
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

void BM_PsfRowsPerRow(benchmark::State& s) { generateBank(s, PSF_ROWS, 1, Size()); }
void BM_PsfRowsAuto(benchmark::State& s) { generateBank(s, PSF_ROWS, 0, Size()); }
void BM_PsfTilesAuto(benchmark::State& s) { generateBank(s, PSF_TILES, 0, Size()); }
void BM_PsfTiles8x16(benchmark::State& s) { generateBank(s, PSF_TILES, 0, Size(8, 16)); }
void BM_PsfUniform(benchmark::State& s) { generateBank(s, PSF_UNIFORM, 0, Size()); }

}  // namespace

BENCHMARK(BM_PsfRowsPerRow)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PsfRowsAuto)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PsfTilesAuto)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PsfTiles8x16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PsfUniform)->Unit(benchmark::kMillisecond);
