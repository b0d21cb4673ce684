// SPDX-License-Identifier: Apache-2.0
// The cost of refining the predicted motion against a reference frame, paired with the restoration
// it precedes, on a 1280x960 RGB rolling-shutter frame in window III of a 10° saccade whose camera
// clock runs 1 ms late. The targets (docs/refinement.md): refining all four parameters costs at most one default
// restoration; refining the offset alone (after a sequence calibration) adds at most half of the
// frame-rate setting's restoration. Blind refinement (no reference frame) is timed alike, over both.
#include "paired_rounds.hpp"
#include "perf_baseline.hpp"

#include <benchmark/benchmark.h>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

#include <vector>

using namespace cv;
using namespace cv::dynblur;

namespace {

struct DriftedSaccade
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, CV_PI / 180);
    Ptr<CameraModel> camera = CameraModel::create(1230, 1230, 639.5, 479.5, 1280, 960);
    SwitchSchedule schedule = SwitchPlanner::create(plant, 16, PLAN_ROBUST)->plan(0.0, 10 * CV_PI / 180, 0.0);
    RollingShutter shutter{0.012, 0.008, 1.0 / 30 / 960, 960};  // as the camera reports it
    Mat frame, still;  // 8-bit sRGB, as a webcam delivers them
    double stillAngle = 10 * CV_PI / 180;

    DriftedSaccade()
    {
        // A textured scene with room for the move; the clock runs 1 ms late.
        Mat sharp(960 + 2 * 260, 1280 + 2 * 32, CV_32FC3), blurred, noisy;
        randu(sharp, 0.05f, 0.95f);
        GaussianBlur(sharp, sharp, Size(0, 0), 1.5);
        RollingShutter late = shutter;
        late.frameStart += 1e-3;
        renderBlurred(sharp, plant, schedule, camera, late, blurred);
        addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, 1);
        linearToSrgb(noisy, frame, CV_8U);
        renderBlurred(sharp, plant, schedule, camera, RollingShutter(1.0, 0.008, shutter.lineDelay, 960), blurred);
        addSensorNoise(blurred, noisy, 4000.0, 8.0, 5.0, 2);
        linearToSrgb(noisy, still, CV_8U);
    }
};

/* Each round runs the four workloads in an order that rotates from round to round: the default
   restoration with and without refining all four parameters, and the frame-rate setting with and
   without refining the offset alone (from a calibration 0.3 ms off, as a sequence leaves it), and
   both settings refined blind. The refinement's cost is the difference, over the restoration's
   time, median over the rounds. */
void BM_RefinementCostPaired(benchmark::State& state)
{
    static const DriftedSaccade f;
    if (classifyExposure(f.plant, f.schedule, f.shutter) != EXPOSURE_III)
        state.SkipWithError("the benchmark frame is not in exposure window III");
    Ptr<DynamicDeblurrer> plain = DynamicDeblurrer::create(f.plant, f.camera);
    Ptr<DynamicDeblurrer> refined = DynamicDeblurrer::create(f.plant, f.camera);
    refined->setReferenceFrame(f.still, f.stillAngle);
    Ptr<DynamicDeblurrer> fast = DynamicDeblurrer::create(f.plant, f.camera);
    dynblur_perf::setFrameRate(*fast);
    Ptr<DynamicDeblurrer> fastOffset = DynamicDeblurrer::create(f.plant, f.camera);
    dynblur_perf::setFrameRate(*fastOffset);
    fastOffset->setReferenceFrame(f.still, f.stillAngle);
    fastOffset->setRefinement(REFINE_TIME_OFFSET);
    MotionCorrection calibration;
    calibration.timeOffset = 0.7e-3;
    fastOffset->setCalibration(calibration);
    Ptr<DynamicDeblurrer> blind = DynamicDeblurrer::create(f.plant, f.camera);
    blind->setBlindRefinement(true);
    Ptr<DynamicDeblurrer> fastBlind = DynamicDeblurrer::create(f.plant, f.camera);
    dynblur_perf::setFrameRate(*fastBlind);
    fastBlind->setBlindRefinement(true);
    Mat restored;
    const std::vector<std::vector<double>> ms = dynblur_perf::timePairedRounds(
        state, {[&] { plain->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { refined->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { fast->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { fastOffset->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { blind->deblur(f.frame, f.schedule, f.shutter, restored); },
                [&] { fastBlind->deblur(f.frame, f.schedule, f.shutter, restored); }});
    //! The median over the rounds of the time workload `with` adds to `without`, over the latter's.
    const auto addedOver = [&](int with, int without) {
        return dynblur_perf::medianRatio(ms[size_t(with)], ms[size_t(without)]) - 1;
    };
    const MotionCorrection all = refined->getLastCorrection(), offset = fastOffset->getLastCorrection();
    if (!all.applied || !offset.applied)
        state.SkipWithError("a refined frame was rejected: the benchmark would time the wrong path");
    using dynblur_perf::median;
    state.counters["default_ms"] = median(ms[0]);
    state.counters["default_refine_all_ms"] = median(ms[1]);
    state.counters["refine_all_over_default"] = addedOver(1, 0);
    state.counters["frame_rate_ms"] = median(ms[2]);
    state.counters["frame_rate_refine_offset_ms"] = median(ms[3]);
    state.counters["refine_offset_over_frame_rate"] = addedOver(3, 2);
    state.counters["found_offset_ms"] = all.timeOffset * 1e3;
    state.counters["found_offset_fast_ms"] = offset.timeOffset * 1e3;
    state.counters["blind_over_default"] = addedOver(4, 0);
    state.counters["blind_over_frame_rate"] = addedOver(5, 2);
    state.counters["found_offset_blind_ms"] = blind->getLastCorrection().timeOffset * 1e3;
}
BENCHMARK(BM_RefinementCostPaired)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5)->Repetitions(1);

}  // namespace
