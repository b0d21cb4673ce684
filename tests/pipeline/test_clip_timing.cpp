// SPDX-License-Identifier: Apache-2.0
// A clip in continuous motion calibrated against its gyro log from the frames alone (no still frame):
// ClipTimingCalibrator on clips rendered by the hand-held simulator.
#include "handheld_clip.hpp"
#include "refine/clip_sync.hpp"
#include "test_common.hpp"

#include <gtest/gtest.h>
#include <opencv2/dynblur.hpp>

#include <cstdio>

using namespace cv;
using namespace cv::dynblur;
using dynblur_samples::HandHeldClip;
using dynblur_samples::HandHeldSimulator;
using dynblur_test::expectErrorNaming;

namespace {

const double kDegree = CV_PI / 180;

//! A clip of `frames` 640×480 frames at 30 fps, shaken by hand, its log `offset` seconds ahead.
HandHeldClip handHeldClip(const std::string& image, int frames, double readout, double offset, uint64 seed)
{
    HandHeldClip clip;
    clip.image = image;
    clip.frames = frames;
    clip.exposure = 0.010;
    clip.readoutTime = readout;
    clip.rotation.maxBlurPx = 20;
    clip.gyro.rateHz = 200;
    clip.gyro.noise = 0.1 * kDegree;
    clip.gyro.bias = Vec3d(0.5, -0.3, 0.2) * kDegree;
    clip.gyro.timeOffset = offset;
    clip.gyro.leadSeconds = 2.5;
    clip.seed = seed;
    return clip;
}

struct Calibrated
{
    TimingCalibration calibration;
    double offsetError, lineDelayError;
    Vec3d biasError;  // rad/s
};

//! The clip calibrated with its readout told as `toldReadout` seconds.
Calibrated calibrate(const HandHeldSimulator& sim, const GyroLog& log, double toldReadout,
                     const ClipTimingOptions& options = ClipTimingOptions())
{
    const HandHeldClip& clip = sim.clip();
    const Ptr<ClipTimingCalibrator> calibrator = ClipTimingCalibrator::create(sim.camera(), log, options);
    for (int k = 0; k < clip.frames; k++)
    {
        RollingShutter told = sim.truth(k).shutter;
        told.lineDelay = toldReadout / clip.frameSize.height;
        calibrator->addFrame(sim.render(k).image, told);
    }
    Calibrated c;
    c.calibration = calibrator->calibrate();
    const MotionCorrection& m = c.calibration.correction;
    c.offsetError = m.timeOffset - clip.gyro.timeOffset;
    c.lineDelayError = clip.readoutTime > 0 ? m.lineDelayScale * toldReadout / clip.readoutTime - 1 : 0;
    c.biasError = m.gyroBias - clip.gyro.bias;
    return c;
}

}  // namespace

/* A 2 s clip (60 frames) in continuous hand-held motion, no still frame, its 200 Hz log (noise
   0.1 °/s, bias up to 0.5 °/s) 1.3 s ahead and its readout told as half the truth: the offset, the
   line delay and the bias from the frames alone. */
TEST(ClipTiming, OffsetReadoutAndBiasFromTheFramesAlone)
{
    DYNBLUR_REQUIRE_DATA(path, "building.jpg");
    const HandHeldSimulator sim(handHeldClip(path, 60, 0.030, 1.3, 7));
    const Calibrated c = calibrate(sim, sim.gyroLog(), 0.015);
    const TimingCalibration& t = c.calibration;
    std::printf("[ figure ] 60 frames, log 1.3 s ahead, readout told x0.5: offset error %+.3f ms (std %.3f), line "
                "delay error %+.2f %%, bias error (%+.3f, %+.3f, %+.3f) deg/s, explained %.3f, tracks %.2f px; %s\n",
                c.offsetError * 1e3, t.timeOffsetStd * 1e3, 100 * c.lineDelayError, c.biasError[0] / kDegree,
                c.biasError[1] / kDegree, c.biasError[2] / kDegree, t.explainedMotion, t.trackResidualPx,
                t.correction.reason.c_str());
    EXPECT_LT(std::abs(c.offsetError), 1e-3);
    EXPECT_LT(std::abs(c.lineDelayError), 0.03);
    EXPECT_EQ(t.axisCorrection, Matx33d::eye());
}

namespace {

//! A clip rendered whole: each frame as recorded, its truth view and its timing.
struct RenderedClip
{
    explicit RenderedClip(const HandHeldClip& description) : sim(description)
    {
        for (int k = 0; k < description.frames; k++)
        {
            dynblur_samples::ClipFrame f = sim.render(k);
            frames.push_back(f.image);
            truths.push_back(f.truth);
            shutters.push_back(f.shutter);
            references.push_back(f.referenceTime);
            blurPx.push_back(f.blurPx);
        }
    }
    HandHeldSimulator sim;
    std::vector<Mat> frames, truths;
    std::vector<RollingShutter> shutters;
    std::vector<double> references, blurPx;
};

//! PSNR of `image` against `truth` over the pixels 16 px in from the border.
double innerPsnr(const Mat& truth, const Mat& image)
{
    const Rect inner(16, 16, truth.cols - 32, truth.rows - 32);
    return PSNR(truth(inner), image(inner), 255);
}

/* Each frame restored with `motion` corrected by `calibration`, checked against a neighbour when
   `refused` is given (and the refused frames listed there); PSNRs. */
std::vector<double> restoreClip(const RenderedClip& clip, const Ptr<CameraMotion>& motion,
                                const MotionCorrection& calibration, const std::vector<RollingShutter>& shutters,
                                std::vector<int>* refused = nullptr)
{
    const Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(clip.sim.camera());
    deblurrer->setPreset(DEBLUR_PRESET_FRAME_RATE);
    deblurrer->setCalibration(calibration);
    std::vector<double> psnr;
    Mat restored;
    for (size_t k = 0; k < clip.frames.size(); k++)
    {
        const size_t neighbour = k > 0 ? k - 1 : 1;  // the first frame is checked against the second
        if (refused)
            deblurrer->setNeighbourFrame(clip.frames[neighbour], shutters[neighbour]);
        deblurrer->deblur(clip.frames[k], motion, shutters[k], restored);
        psnr.push_back(innerPsnr(clip.truths[k], restored));
        if (refused && !deblurrer->getLastCorrection().applied)
            refused->push_back(int(k));
    }
    return psnr;
}

}  // namespace

class ClipRestoration : public testing::TestWithParam<std::string>
{
};

/* A hand-held clip calibrated from its own frames and restored with its log: against the same frames
   restored with the true motion and clock, the restored clip keeps ≥ 90 % of the gain, and no frame
   ends worse than its input by more than 0.1 dB. One clip per image: rolling 33 ms with a 200 Hz log,
   rolling 10 ms with a 100 Hz log, and a global shutter; blur up to 40 px; clocks across ±2 s. */
TEST_P(ClipRestoration, CalibratedClipKeepsTheGainNeverWorse)
{
    DYNBLUR_REQUIRE_DATA(path, GetParam());
    const int which = GetParam() == "building.jpg" ? 0 : GetParam() == "fruits.jpg" ? 1 : 2;
    const double readouts[3] = {0.033, 0.010, 0.0}, rates[3] = {200, 100, 200}, offsets[3] = {-1.8, 0.7, 1.9};
    HandHeldClip description = handHeldClip(path, 30, readouts[which], offsets[which], 11 + uint64(which));
    description.rotation.maxBlurPx = 40;
    description.gyro.rateHz = rates[which];
    const RenderedClip clip(description);
    // Told: the container's frame times, a readout of 20 ms when there is one (unknown to the user).
    std::vector<RollingShutter> told = clip.shutters;
    for (RollingShutter& s : told)
        s.lineDelay = readouts[which] > 0 ? 0.020 / s.rows : 0.0;
    const TimingCalibration calibration = calibrateTiming(clip.sim.gyroLog(), clip.sim.camera(), clip.frames, told);

    MotionCorrection truth;
    truth.timeOffset = description.gyro.timeOffset;
    truth.gyroBias = description.gyro.bias;
    const std::vector<double> right = restoreClip(clip, clip.sim.gyroLog().toMotion(), truth, clip.shutters);
    std::vector<int> refused;
    const std::vector<double> restored =
        restoreClip(clip, clip.sim.gyroLog().withAxisCorrection(calibration.axisCorrection).toMotion(),
                    calibration.correction, told, &refused);
    double blurredSum = 0, rightSum = 0, restoredSum = 0, worst = 1e9;
    for (size_t k = 0; k < clip.frames.size(); k++)
    {
        const double blurred = innerPsnr(clip.truths[k], clip.frames[k]);
        blurredSum += blurred, rightSum += right[k], restoredSum += restored[k];
        worst = std::min(worst, restored[k] - blurred);
    }
    const double n = double(clip.frames.size());
    const double kept = (restoredSum - blurredSum) / (rightSum - blurredSum);
    std::printf("[ figure ] %s clip (readout %.0f ms, %.0f Hz log %+.1f s off, blur %.1f-%.1f px): offset error %+.3f "
                "ms, line delay error %+.2f %%; mean PSNR blurred %.2f, true calibration %.2f, calibrated %.2f dB: %.1f "
                "%% of the gain kept; worst frame %+.2f dB; %zu frames refused\n",
                GetParam().c_str(), readouts[which] * 1e3, rates[which], offsets[which],
                *std::min_element(clip.blurPx.begin(), clip.blurPx.end()),
                *std::max_element(clip.blurPx.begin(), clip.blurPx.end()),
                (calibration.correction.timeOffset - offsets[which]) * 1e3,
                readouts[which] > 0 ? 100 * (calibration.correction.lineDelayScale * 0.020 / readouts[which] - 1) : 0.0,
                blurredSum / n, rightSum / n, restoredSum / n, 100 * kept, worst, refused.size());
    EXPECT_LT(std::abs(calibration.correction.timeOffset - offsets[which]), 1e-3);
    EXPECT_GE(kept, 0.9);
    EXPECT_GE(worst, -0.1);
}

INSTANTIATE_TEST_CASE_P(SharedImages, ClipRestoration, testing::Values("building.jpg", "fruits.jpg", "baboon.jpg"),
                        [](const testing::TestParamInfo<std::string>& info) {
                            return info.param.substr(0, info.param.find('.'));
                        });

namespace {

//! `log` with its rates (and bias) replaced: a fresh matrix, so the original keeps its own.
GyroLog withRates(const GyroLog& log, const Mat& rates)
{
    GyroLog changed = log;
    changed.rates = rates.clone();
    return changed;
}

//! The message of the exception `f` throws, or "" when it throws none.
template <typename F>
std::string errorOf(F f)
{
    try
    {
        f();
    }
    catch (const cv::Exception& e)
    {
        return e.err;
    }
    return std::string();
}

}  // namespace

/* Wrong logs: rates in deg/s read as rad/s, a time unit of ms read as s, another clip's log, and 16 of
   the 47 wrong signed mappings of the axes. The calibration refuses each, naming the likely mistake,
   or corrects a proper mapping of the axes (detectAxes; refused as contradicted without it), so no
   frame is restored with a wrong log: 0 worse. Restored as told with no calibration, each frame is
   checked against a neighbour: every frame of a gross mistake (the units, another clip) comes back
   unchanged; a mapping of the axes that nearly agrees with the images over a frame can pass that
   check, which is why the programs calibrate first (the figures are printed). */
TEST(ClipTiming, WrongLogsAreRefusedOrNeverWorse)
{
    DYNBLUR_REQUIRE_DATA(path, "building.jpg");
    const RenderedClip clip(handHeldClip(path, 30, 0.030, 0.4, 21));
    const GyroLog right = clip.sim.gyroLog();
    struct Wrong
    {
        std::string name;
        GyroLog log;
        const char* refusal;  // what the calibration's message names; "" for a mapping it corrects
        Matx33d mapping;
        bool gross;           // every frame restored as told must come back unchanged
    };
    std::vector<Wrong> wrongs;
    wrongs.push_back({"deg/s read as rad/s", withRates(right, right.rates * (180 / CV_PI)), "degrees per second",
                      Matx33d::eye(), true});
    GyroLog milliseconds = right;
    for (double& t : milliseconds.times)
        t *= 1000;
    wrongs.push_back({"ms read as s", milliseconds, "time unit", Matx33d::eye(), true});
    HandHeldClip other = clip.sim.clip();
    other.seed = 99;
    wrongs.push_back({"another clip's log", HandHeldSimulator(other).gyroLog(), "this clip's log", Matx33d::eye(), true});
    const std::vector<Matx33d>& mappings = cv::dynblur::detail::signedPermutations();
    for (size_t m = 1; m < mappings.size(); m += 3)  // 16 of the 47 wrong mappings, proper and mirrored
        wrongs.push_back({format("axes mapped by permutation %zu", m), withRates(right, right.rates * Mat(mappings[m]).t()),
                          determinant(mappings[m]) < 0 ? "mirrored" : "", mappings[m], false});
    const std::vector<RollingShutter>& told = clip.shutters;
    int refused = 0, corrected = 0, workflowWorse = 0, asToldRestored = 0, asToldWorse = 0;
    for (const Wrong& w : wrongs)
    {
        const std::string calibrationError = errorOf([&] { calibrateTiming(w.log, clip.sim.camera(), clip.frames, told); });
        if (*w.refusal)
        {
            EXPECT_NE(calibrationError.find(w.refusal), std::string::npos) << w.name << ": " << calibrationError;
            refused += !calibrationError.empty();
        }
        else
        {
            // A proper mapping the images correct: the calibration undoes it, within a millisecond.
            ClipTimingOptions strict;
            strict.detectAxes = false;
            EXPECT_NE(errorOf([&] { calibrateTiming(w.log, clip.sim.camera(), clip.frames, told, strict); })
                          .find("contradict"),
                      std::string::npos)
                << w.name;
            const TimingCalibration c = calibrateTiming(w.log, clip.sim.camera(), clip.frames, told);
            EXPECT_LT(norm(c.axisCorrection * w.mapping - Matx33d::eye()), 1e-9) << w.name;
            EXPECT_LT(std::abs(c.correction.timeOffset - 0.4), 1e-3) << w.name;
            corrected++;
            std::vector<int> unused;
            const std::vector<double> psnr =
                restoreClip(clip, w.log.withAxisCorrection(c.axisCorrection).toMotion(), c.correction, told, &unused);
            for (size_t k = 0; k < psnr.size(); k++)
                workflowWorse += psnr[k] < innerPsnr(clip.truths[k], clip.frames[k]) - 0.1;
        }
        // Restored as told, no calibration: each frame checked against a neighbour.
        Ptr<CameraMotion> motion;
        const std::string motionError = errorOf([&] { motion = w.log.toMotion(); });
        std::vector<int> refusedFrames;
        std::vector<double> psnr;
        if (motion)
        {
            MotionCorrection asTold;
            asTold.timeOffset = 0.4;  // even told the clock: only the log is wrong
            psnr = restoreClip(clip, motion, asTold, told, &refusedFrames);
        }
        int worse = 0;
        for (size_t k = 0; k < psnr.size(); k++)
            worse += psnr[k] < innerPsnr(clip.truths[k], clip.frames[k]) - 0.1;
        asToldRestored += int(psnr.size() - refusedFrames.size());
        asToldWorse += worse;
        if (w.gross)
        {
            EXPECT_EQ(refusedFrames.size(), psnr.size()) << w.name;
        }
        std::printf("[ figure ] %s: calibration %s; restored as told, %s\n", w.name.c_str(),
                    calibrationError.empty() ? "corrected it" : calibrationError.substr(0, 100).c_str(),
                    motion ? format("%zu of %zu frames refused, %d worse", refusedFrames.size(), psnr.size(), worse).c_str()
                           : ("no motion: " + motionError.substr(0, 80)).c_str());
    }
    std::printf("[ figure ] %zu wrong logs: %d refused by the calibration, %d mappings corrected (%d frames worse than "
                "their input after it); restored as told with the neighbour check, %d frames restored, %d worse than "
                "their input by more than 0.1 dB\n",
                wrongs.size(), refused, corrected, workflowWorse, asToldRestored, asToldWorse);
    EXPECT_EQ(refused + corrected, int(wrongs.size()));
    EXPECT_EQ(workflowWorse, 0);
}

/* A motion whose blur no kernel reaches (here a log in °/s read as rad/s, with no neighbour to check
   against) returns the frame unchanged with the reason, rather than failing the stream. */
TEST(ClipTiming, BlurBeyondTheKernelsIsReturnedUnchanged)
{
    const Ptr<CameraModel> camera = CameraModel::create(150, 150, 79.5, 59.5, 160, 120);
    Mat times(1001, 1, CV_64F), rates(1001, 3, CV_64F, Scalar(0));
    for (int k = 0; k < times.rows; k++)
        times.at<double>(k) = k * 1e-3, rates.at<double>(k, 1) = 150;  // 150 rad/s: 450 px over 20 ms at 150 px
    Mat frame(120, 160, CV_32F);
    randu(frame, 0.1, 0.9);
    Mat restored;
    const Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(camera);
    deblurrer->deblur(frame, CameraMotion::fromAngularVelocity(times, rates), RollingShutter(0.4, 0.02, 0, 120),
                      restored);
    const MotionCorrection c = deblurrer->getLastCorrection();
    EXPECT_FALSE(c.applied);
    EXPECT_NE(c.reason.find("more than the kernels reach"), std::string::npos) << c.reason;
    EXPECT_EQ(norm(restored, frame, NORM_INF), 0);
}

/* A sweep about the arm: the camera turns about a pivot 0.3 m behind it over a plane 1 m away, so
   the image moves about 1.3 times as far as the gyro says. The clip's calibration with
   REFINE_RATE_SCALE finds the scale, and the restored clip gains more with it than without. */
TEST(ClipTiming, SweepAboutTheArmWithTheRateScale)
{
    DYNBLUR_REQUIRE_DATA(path, "building.jpg");
    HandHeldClip description = handHeldClip(path, 30, 0.030, 0.6, 31);
    description.translation.planeDepth = 1.0;
    description.translation.pivotDistance = 0.3;
    const RenderedClip clip(description);
    ClipTimingOptions withScale;
    withScale.flags |= REFINE_RATE_SCALE;
    const TimingCalibration scaled = calibrateTiming(clip.sim.gyroLog(), clip.sim.camera(), clip.frames,
                                                     clip.shutters, withScale);
    MotionCorrection unscaled = scaled.correction;
    unscaled.rateScale = 1;
    const Ptr<CameraMotion> motion = clip.sim.gyroLog().toMotion();
    std::vector<int> refusedScaled, refusedUnscaled;
    const std::vector<double> a = restoreClip(clip, motion, scaled.correction, clip.shutters, &refusedScaled);
    const std::vector<double> b = restoreClip(clip, motion, unscaled, clip.shutters, &refusedUnscaled);
    double blurred = 0, withGain = 0, withoutGain = 0, worst = 1e9;
    for (size_t k = 0; k < clip.frames.size(); k++)
    {
        const double input = innerPsnr(clip.truths[k], clip.frames[k]);
        blurred += input, withGain += a[k] - input, withoutGain += b[k] - input;
        worst = std::min(worst, a[k] - input);
    }
    const double n = double(clip.frames.size());
    double ratio = 0;
    for (size_t k = 0; k < clip.frames.size(); k++)
        ratio += clip.blurPx[k] / std::max(1e-9, clip.sim.truth(int(k)).rotationBlurPx) / n;
    std::printf("[ figure ] sweep about the arm (pivot 0.3 m, plane 1 m; blur %.2fx the rotation's on average): rate "
                "scale %.3f (std %.3f), offset error %+.3f ms; mean gain over the blurred clip (%.2f dB) %+.2f dB with "
                "the rate scale (%zu frames refused), %+.2f dB without (%zu refused); worst frame %+.2f dB\n",
                ratio, scaled.correction.rateScale, scaled.rateScaleStd,
                (scaled.correction.timeOffset - description.gyro.timeOffset) * 1e3, blurred / n, withGain / n,
                refusedScaled.size(), withoutGain / n, refusedUnscaled.size(), worst);
    EXPECT_NEAR(scaled.correction.rateScale, ratio, 0.1);
    EXPECT_GT(withGain, withoutGain);
    EXPECT_GE(worst, -0.1);
}
