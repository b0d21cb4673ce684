// SPDX-License-Identifier: Apache-2.0
// A clip in continuous motion calibrated against its gyro log from the frames alone (no still frame):
// ClipTimingCalibrator on clips rendered by the hand-held simulator.
#include "handheld_clip.hpp"
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
