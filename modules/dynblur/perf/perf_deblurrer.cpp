// SPDX-License-Identifier: Apache-2.0
// The whole pipeline on one C270-sized frame: DynamicDeblurrer::deblur (exposure window, PSF bank,
// 10 RL iterations, bfloat16 blurs) for each PSF model, on a 1280x960 RGB rolling-shutter frame in
// window III of a 10° saccade; and the speed targets' ratios, from rounds that time the row-wise and
// tile-wise restorations, the filter2D reference and the float-blur row-wise one back to back.
#include "paired_rounds.hpp"
#include "perf_baseline.hpp"
#include "pipeline/frame_rate_preset.hpp"
#include "restore/kernels/kernel_table.hpp"

#include <benchmark/benchmark.h>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

using namespace cv;
using namespace cv::dynblur;
using dynblur_perf::median;
using dynblur_perf::medianRatio;
using dynblur_perf::SaccadeFrame;
using dynblur_perf::SaccadeScene;

namespace {

const SaccadeFrame& saccadeFrame()
{
    static const SaccadeFrame frame;
    return frame;
}

/* DynamicDeblurrer in the frame-rate setting (dynblur_perf::setFrameRate) with `psfModel`, or with
   float blurs or the color at full resolution. */
Ptr<DynamicDeblurrer> frameRateDeblurrer(const SaccadeFrame& f, int psfModel, int blurPrecision = RL_BLUR_BFLOAT16,
                                         int colorResolution = DEBLUR_COLOR_HALF_RESOLUTION)
{
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(f.plant, f.camera);
    dynblur_perf::setFrameRate(*deblurrer, 10, blurPrecision, colorResolution);
    deblurrer->setPsfModel(psfModel);
    return deblurrer;
}

void BM_DeblurFrame(benchmark::State& state)
{
    const SaccadeFrame& f = saccadeFrame();
    if (classifyExposure(f.plant, f.schedule, f.shutter) != EXPOSURE_III)
        state.SkipWithError("the benchmark frame is not in exposure window III");
    Ptr<DynamicDeblurrer> deblurrer = frameRateDeblurrer(f, static_cast<int>(state.range(0)));
    Mat restored;
    deblurrer->deblur(f.frame, f.schedule, f.shutter, restored);  // warm: a stream's workspace is set up once
    for (auto _ : state)
    {
        deblurrer->deblur(f.frame, f.schedule, f.shutter, restored);
        benchmark::DoNotOptimize(restored.data);
    }
    const PsfBank bank = deblurrer->getLastPsfBank();
    state.counters["kernels"] = static_cast<double>(bank.kernels.size());
}

}  // namespace

BENCHMARK(BM_DeblurFrame)->ArgName("psfModel")->Arg(PSF_UNIFORM)->Arg(PSF_ROWS)->Arg(PSF_TILES)
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);

/* The row-wise frame-rate deblur of the same frame in 8-bit sRGB, as a webcam delivers it: the
   float benchmark plus decoding the frame and encoding the result. */
void BM_DeblurFrame8Bit(benchmark::State& state)
{
    const SaccadeFrame& f = saccadeFrame();
    Ptr<DynamicDeblurrer> deblurrer = frameRateDeblurrer(f, PSF_ROWS);
    Mat restored;
    deblurrer->deblur(f.frame8, f.schedule, f.shutter, restored);
    for (auto _ : state)
    {
        deblurrer->deblur(f.frame8, f.schedule, f.shutter, restored);
        benchmark::DoNotOptimize(restored.data);
    }
}
BENCHMARK(BM_DeblurFrame8Bit)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);

/* The targets' ratios: each round restores the frame row-wise and tile-wise, runs the filter2D
   reference (10 iterations, uniform 21×1 kernel) on it and restores it row-wise with float blurs
   and with the color at full resolution, in an order that rotates from round to round; each ratio is the median of the rounds' ratios.
   This machine's speed drifts by ±20 % over minutes, which ratios of medians taken minutes apart
   carry in full; within a round the four see nearly the same machine. Counters: the medians (ms)
   and the ratios. */
void BM_FrameRatePaired(benchmark::State& state)
{
    const SaccadeFrame& f = saccadeFrame();
    Ptr<DynamicDeblurrer> rows = frameRateDeblurrer(f, PSF_ROWS), tiles = frameRateDeblurrer(f, PSF_TILES),
                          rowsFloat = frameRateDeblurrer(f, PSF_ROWS, RL_BLUR_FLOAT32),
                          rowsFullColor = frameRateDeblurrer(f, PSF_ROWS, RL_BLUR_BFLOAT16, DEBLUR_COLOR_FULL_RESOLUTION);
    const Mat kernel = dynblur_perf::uniformKernel21x1();
    Mat restored, estimate;
    const std::vector<std::vector<double>> ms = dynblur_perf::timePairedRounds(
        state, {[&] { rows->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { tiles->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { dynblur_perf::filter2DRichardsonLucy(f.frame, kernel, 10, estimate); },
                [&] { rowsFloat->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { rowsFullColor->deblur(f.frame, f.schedule, f.shutter, restored); }});
    //! Median over the rounds of workload `which`'s time over the row-wise one's.
    const auto overRows = [&](int which) { return medianRatio(ms[size_t(which)], ms[0]); };
    state.counters["rows_ms"] = median(ms[0]);
    state.counters["tiles_ms"] = median(ms[1]);
    state.counters["filter2d_ms"] = median(ms[2]);
    state.counters["rows_float32_ms"] = median(ms[3]);
    state.counters["tiles_over_rows"] = overRows(1);
    state.counters["filter2d_over_rows"] = overRows(2);
    state.counters["float32_over_rows"] = overRows(3);
    state.counters["rows_full_color_ms"] = median(ms[4]);
    state.counters["full_color_over_rows"] = overRows(4);
}
BENCHMARK(BM_FrameRatePaired)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(15)->Repetitions(1);

/* PSF_AUTO and the frame-rate preset against the fixed models, paired per round, on the frame of a
   window: 0 the benchmark's window III rolling frame, 1 window I rolling (starts 20.7 ms before the
   move), 2 window III global (starts 42.9 ms after it starts; the demo's frames), 3 a frame late in
   the settling (rolling, starts 40 ms after), whose blur is short, 4 a window III rolling frame of a
   zoomed lens (15° field of view) 25 ms into a 1° saccade, whose rows mostly need one kernel, 5 the
   same lens 50 ms into it, where one kernel per row suffices everywhere. Each round restores it with the
   default settings (20 iterations, full color) as PSF_AUTO, PSF_ROWS and PSF_TILES, with
   DEBLUR_PRESET_FRAME_RATE, with the frame-rate setting of old (setFrameRate: rows, 10 iterations)
   and with the filter2D reference. Counters: the medians (ms), the median ratios, and the share of
   rows PSF_AUTO gave rows and tiles (the default's, then the preset's). */
void BM_AutoPaired(benchmark::State& state)
{
    static const RollingShutter timings[6] = {SaccadeScene().shutter,
                                              RollingShutter(-0.0207, 0.008, 1.0 / 30 / 960, 960),
                                              RollingShutter(0.0429, 0.008, 0, 960),
                                              RollingShutter(0.040, 0.008, 1.0 / 30 / 960, 960),
                                              RollingShutter(0.025, 0.008, 1.0 / 30 / 960, 960),
                                              RollingShutter(0.050, 0.008, 1.0 / 30 / 960, 960)};
    const int window = static_cast<int>(state.range(0));
    const bool zoomed = window >= 4;
    const SaccadeFrame f(&timings[window], zoomed ? 4920 : 1230, zoomed ? 1 : 10);
    const int expected[6] = {EXPOSURE_III, EXPOSURE_I, EXPOSURE_III, EXPOSURE_III, EXPOSURE_III, EXPOSURE_III};
    if (classifyExposure(f.plant, f.schedule, f.shutter) != expected[window])
        state.SkipWithError("the frame is not in the window it stands for");
    const auto withModel = [&](int model) {
        Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(f.plant, f.camera);
        deblurrer->setPsfModel(model);
        return deblurrer;
    };
    Ptr<DynamicDeblurrer> automatic = withModel(PSF_AUTO), rows = withModel(PSF_ROWS), tiles = withModel(PSF_TILES),
                          preset = withModel(PSF_AUTO), old = frameRateDeblurrer(f, PSF_ROWS);
    preset->setPreset(DEBLUR_PRESET_FRAME_RATE);
    const Mat kernel = dynblur_perf::uniformKernel21x1();
    Mat restored, estimate;
    const std::vector<std::vector<double>> ms = dynblur_perf::timePairedRounds(
        state, {[&] { automatic->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { rows->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { tiles->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { preset->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { old->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { dynblur_perf::filter2DRichardsonLucy(f.frame, kernel, 10, estimate); }});
    const char* names[6] = {"auto_ms", "rows_ms", "tiles_ms", "preset_ms", "frame_rate_ms", "filter2d_ms"};
    for (size_t i = 0; i < 6; i++)
        state.counters[names[i]] = median(ms[i]);
    state.counters["auto_over_rows"] = medianRatio(ms[0], ms[1]);
    state.counters["auto_over_tiles"] = medianRatio(ms[0], ms[2]);
    state.counters["preset_over_frame_rate"] = medianRatio(ms[3], ms[4]);
    state.counters["filter2d_over_preset"] = medianRatio(ms[5], ms[3]);
    const PsfPlan plan = automatic->getLastPlan(), fast = preset->getLastPlan();
    state.counters["auto_rows_share"] = plan.rowShare(PSF_ROWS) + plan.rowShare(PSF_UNIFORM);
    state.counters["auto_tiles_share"] = plan.rowShare(PSF_TILES);
    state.counters["preset_tiles_share"] = fast.rowShare(PSF_TILES);
    // What the preset's iterations are decided by: the longest kernel L and the most spread one's N.
    const PsfBank bank = preset->getLastPsfBank();
    state.counters["preset_longest_kernel_px"] = std::max(bank.maxKernelSize().width, bank.maxKernelSize().height);
    state.counters["preset_most_spread_px"] = cv::dynblur::detail::mostSpreadKernelPx(bank);
}
BENCHMARK(BM_AutoPaired)->ArgName("window")->DenseRange(0, 5)->Unit(benchmark::kMillisecond)->UseRealTime()
    ->Iterations(5)->Repetitions(1);

/* The test command's short speed check (scripts/benchmark.sh --ci): the row-wise restoration and the
   filter2D reference alone, paired as in BM_FrameRatePaired (order alternating by round), over a few
   rounds, with OpenCV's pool set to state.range(0) threads. The filter2D peer runs on one thread
   whatever the setting, the restoration on all of them: on a machine whose other core another job
   holds now and then, the two-thread ratio falls with the neighbour's load and the one-thread ratio
   does not. Counters: the medians (ms) and the median of the rounds' ratios. */
void BM_RowsVsFilter2DPaired(benchmark::State& state)
{
    const int threadsBefore = getNumThreads();
    setNumThreads(int(state.range(0)));
    const SaccadeFrame& f = saccadeFrame();
    Ptr<DynamicDeblurrer> rows = frameRateDeblurrer(f, PSF_ROWS);
    const Mat kernel = dynblur_perf::uniformKernel21x1();
    Mat restored, estimate;
    const std::vector<std::vector<double>> ms = dynblur_perf::timePairedRounds(
        state, {[&] { rows->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { dynblur_perf::filter2DRichardsonLucy(f.frame, kernel, 10, estimate); }});
    state.counters["rows_ms"] = median(ms[0]);
    state.counters["filter2d_ms"] = median(ms[1]);
    state.counters["filter2d_over_rows"] = medianRatio(ms[1], ms[0]);
    setNumThreads(threadsBefore);
}
BENCHMARK(BM_RowsVsFilter2DPaired)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()
    ->Iterations(9)->Repetitions(1);

/* The frame-rate restoration on each instruction set's gather kernels this CPU runs (forceKernelIsa),
   paired rounds: what a CPU without AVX512-BF16 (avx512: the packed gather widened to floats) or
   without AVX-512 (avx2) would run, here. Counters: each set's median (ms) and its median ratio to
   the CPU's best kernels. Only the gathers change; the element-wise loops keep this CPU's clones. */
void BM_FrameRateByKernels(benchmark::State& state)
{
    using namespace cv::dynblur::kernels;
    const SaccadeFrame& f = saccadeFrame();
    Ptr<DynamicDeblurrer> rows = frameRateDeblurrer(f, PSF_ROWS);
    std::vector<KernelIsa> isas = availableKernelIsas();
    isas.erase(isas.begin());  // the reference kernels: a correctness check, not a speed
    Mat restored;
    std::vector<std::function<void()>> workloads;
    for (KernelIsa isa : isas)
        workloads.push_back([&, isa] {
            forceKernelIsa(isa);
            rows->deblur(f.frame, f.schedule, f.shutter, restored);
        });
    const std::vector<std::vector<double>> ms = dynblur_perf::timePairedRounds(state, workloads);
    forceKernelIsa(KERNELS_ISA_COUNT);
    for (size_t i = 0; i < isas.size(); i++)
    {
        state.counters[std::string(kernelIsaName(isas[i])) + "_ms"] = median(ms[i]);
        state.counters[std::string(kernelIsaName(isas[i])) + "_over_best"] = medianRatio(ms[i], ms.back());
    }
}
BENCHMARK(BM_FrameRateByKernels)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(9)->Repetitions(1);

/* A nearly sharp frame (DynamicDeblurrer::setSharpThreshold): the saccade's last frame before its
   frames are still (1 ms steps), 8-bit, in the frame-rate setting. Arg 0: returned as it came (the
   reference at the final rest, shift 0); 1: its rows moved back to a reference 0.5 px away (4e-4
   rad); 2: deconvolved anyway (setSharpThreshold(0)). The first two cost the measure of the frame's
   motion (and the resampling); the third the PSF bank and Richardson–Lucy. */
void BM_SharpFrame(benchmark::State& state)
{
    static const SaccadeFrame f = [] {
        const SaccadeScene scene;
        RollingShutter shutter = scene.shutter;
        while (classifyExposure(scene.plant, scene.schedule, shutter) != EXPOSURE_IV)
            shutter.frameStart += 0.001;
        shutter.frameStart -= 0.001;
        return SaccadeFrame(&shutter);
    }();
    const int variant = static_cast<int>(state.range(0));
    Ptr<DynamicDeblurrer> deblurrer = frameRateDeblurrer(f, PSF_AUTO);
    if (variant == 2)
        deblurrer->setSharpThreshold(0.0);
    const double thetaRef = f.plant->restingAngle(f.schedule.finalLevel()) + (variant == 1 ? 4e-4 : 0.0);
    Mat restored;
    deblurrer->deblur(f.frame8, f.schedule, f.shutter, restored, thetaRef);
    const std::string reason = deblurrer->getLastCorrection().reason;
    const bool moved = reason.find("moved back") != std::string::npos;
    if ((reason.rfind("sharp:", 0) == 0) != (variant != 2) || moved != (variant == 1))
        state.SkipWithError(("not the frame this variant needs: " + reason).c_str());
    for (auto _ : state)
    {
        deblurrer->deblur(f.frame8, f.schedule, f.shutter, restored, thetaRef);
        benchmark::DoNotOptimize(restored.data);
    }
}
BENCHMARK(BM_SharpFrame)->ArgName("passed_moved_deconvolved")->DenseRange(0, 2)->Unit(benchmark::kMillisecond)
    ->UseRealTime()->Iterations(5);
