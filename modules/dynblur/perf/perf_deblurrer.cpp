// The whole pipeline on one C270-sized frame: DynamicDeblurrer::deblur (exposure window, PSF bank,
// 10 RL iterations) for each PSF model, on a 1280x960 RGB rolling-shutter frame in window III of a
// 10° saccade. Compare with BM_RichardsonLucyFilter2DBaseline (perf_deconv.cpp) in the same run.
#include <benchmark/benchmark.h>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

using namespace cv;
using namespace cv::dynblur;

namespace {

struct SaccadeFrame
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    Ptr<CameraModel> camera = CameraModel::create(1230, 1230, 639.5, 479.5, 1280, 960);
    SwitchSchedule schedule = SwitchPlanner::create(plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
    RollingShutter shutter{0.012, 0.008, 1.0 / 30 / 960, 960};
    Mat frame;

    SaccadeFrame()
    {
        // A textured linear-intensity scene; rendering is the costly part, so it happens once.
        Mat sharp(960, 1280, CV_32FC3), blurred;
        randu(sharp, 0.05f, 0.95f);
        GaussianBlur(sharp, sharp, Size(0, 0), 1.5);
        renderBlurred(sharp, plant, schedule, camera, shutter, blurred);
        addSensorNoise(blurred, frame);
    }
};

const SaccadeFrame& saccadeFrame()
{
    static const SaccadeFrame frame;
    return frame;
}

void BM_DeblurFrame(benchmark::State& state)
{
    const SaccadeFrame& f = saccadeFrame();
    if (classifyExposure(f.plant, f.schedule, f.shutter) != EXPOSURE_III)
        state.SkipWithError("the benchmark frame is not in exposure window III");
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(f.plant, f.camera);
    deblurrer->setPsfModel(static_cast<int>(state.range(0)));
    RLParams params = deblurrer->getRLParams();
    params.iterations = 10;
    params.colorIterations = 3;  // the frame-rate setting; its quality is DeblurQuality's to check
    deblurrer->setRLParams(params);
    Mat restored;
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
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
