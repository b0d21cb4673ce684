// SPDX-License-Identifier: Apache-2.0
// The clock offset, line delay and gyro bias of a measured motion, refined from the frames against
// still frames: per frame (DynamicDeblurrer) and over a recording (calibrateTiming).
#include "image_metrics.hpp"
#include "shake_scene.hpp"
#include "test_common.hpp"

#include <gtest/gtest.h>
#include <opencv2/dynblur.hpp>

#include <cstdio>

using namespace cv;
using namespace cv::dynblur;
using dynblur_samples::maskedPsnr;
using dynblur_test::ShakeScene;

namespace {

const double kDegree = CV_PI / 180;
const double kLogOffset = 0.005;  // s: the log's clock runs this far ahead of the camera's
const double kLineDelay = 0.030 / 480;  // s: a 30 ms readout

/* A 200 Hz gyroscope strapped to the shaking camera: its samples, on a clock `offset` seconds ahead
   of the camera's, read the true rates plus `bias` (rad/s) plus white noise of 0.1 °/s per axis
   (a phone's gyro at this rate). */
Ptr<CameraMotion> gyroLog(const CameraMotion& truth, double offset, const Vec3d& bias, uint64 seed)
{
    const double rate = 200, start = -0.9, end = 0.9;
    const int n = int(std::lround((end - start) * rate)) + 1;
    Mat times(n, 1, CV_64F), rates(n, 3, CV_64F);
    RNG rng(seed);
    for (int k = 0; k < n; k++)
    {
        times.at<double>(k) = start + k / rate;
        const Vec3d w = truth.angularVelocity(times.at<double>(k) - offset) + bias;
        for (int i = 0; i < 3; i++)
            rates.at<double>(k, i) = w[i] + rng.gaussian(0.1 * kDegree);
    }
    return CameraMotion::fromAngularVelocity(times, rates);
}

const Vec3d kBias(0.5 * kDegree, -0.5 * kDegree, 0.5 * kDegree);  // rad/s: 0.5 °/s on each axis

//! A still: the view held for 0.1 ms (global shutter) at t, with the frames' noise.
RollingShutter stillShutter(double t)
{
    return RollingShutter(t - 5e-5, 1e-4, 0.0, 480);
}

/* A recording: frames of a 20 ms rolling exposure every 0.1 s, each with a still 0.2 s before it
   (the still rendered relative to its frame's mid-exposure view, which `truth` shows). */
struct Recording
{
    std::vector<Mat> frames, stills;
    std::vector<RollingShutter> truth, told, stillShutters;
};

Recording record(const ShakeScene& scene, int count, double toldLineDelayScale)
{
    Recording r;
    for (int i = 0; i < count; i++)
    {
        const double start = -0.55 + 0.1 * i;
        r.truth.emplace_back(start, 0.020, kLineDelay, 480);
        r.told.emplace_back(start, 0.020, kLineDelay * toldLineDelayScale, 480);
        r.stillShutters.push_back(stillShutter(start - 0.2));
        r.frames.push_back(scene.capture(r.truth.back(), 100 + uint64(i)));
        const double mid = start + 0.5 * 479 * kLineDelay + 0.5 * 0.020;
        r.stills.push_back(scene.capture(r.stillShutters.back(), 200 + uint64(i), mid));
    }
    return r;
}

//! Pixels 16 px in from the border that `valid` observed.
Mat judged(const Mat& valid)
{
    Mat inside(480, 640, CV_8U, Scalar(0));
    inside(Rect(16, 16, 640 - 32, 480 - 32)).setTo(255);
    return inside & valid;
}

}  // namespace

/* Over a recording of 12 frames (3-axis shake of 30 °/s, rolling, 20 ms), each with a still 0.2 s
   before it, and a 200 Hz gyro log 5 ms ahead of the camera with 0.1 °/s noise and a 0.5 °/s bias:
   calibrateTiming finds the offset and the line delay (told 3 % short) and the bias. Figures in
   docs/camera-motion.md. */
TEST(GyroTiming, RecordingCalibratesOffsetLineDelayAndBias)
{
    DYNBLUR_REQUIRE_DATA(path, "building.jpg");
    const ShakeScene scene(path, 30);
    const Recording r = record(scene, 12, 0.97);
    const Ptr<CameraMotion> log = gyroLog(*scene.motion, kLogOffset, kBias, 1);
    {
        const int flags = REFINE_TIME_OFFSET | REFINE_LINE_DELAY | REFINE_GYRO_BIAS;
        const TimingCalibration c =
            calibrateTiming(log, scene.camera, r.stills, r.frames, r.told, r.stillShutters, flags, 0.02);
        const double lineDelayError = c.correction.lineDelayScale * 0.97 - 1;
        const Vec3d bias = c.correction.gyroBias / kDegree;
        std::printf("[ figure ] recording of 12 frames, flags %d: offset %.3f ms (truth 5, std %.3f), line delay "
                    "error %+.2f %%, bias (%.2f, %.2f, %.2f) deg/s (truth 0.5, -0.5, 0.5), consistency %.2f; %s\n",
                    flags, c.correction.timeOffset * 1e3, c.timeOffsetStd * 1e3, 100 * lineDelayError, bias[0], bias[1],
                    bias[2], c.correction.consistency, c.correction.reason.c_str());
        // Measured 0.017 ms, 0.18 % and 0.01 deg/s; the issue asks 0.5 ms and 1 %.
        EXPECT_NEAR(c.correction.timeOffset, kLogOffset, 0.05e-3);
        EXPECT_LT(std::abs(lineDelayError), 0.003);
        for (int i = 0; i < 3; i++)
            EXPECT_NEAR(c.correction.gyroBias[i], kBias[i], 0.05 * kDegree) << i;
        EXPECT_EQ(c.scanObjective.size(), c.scanTimeOffsets.size());
    }
}

/* Per frame, against its still (0.2 s before it), a 200 Hz log 5 ms ahead with noise and a 0.5 °/s
   bias: the deblurrer refines the clock offset and the line delay with the bias either refined too
   (from nothing) or known (a recording's calibration, or GyroLog's still intervals, gave it), and
   keeps ≥ 90 % of the gain of a restoration with the true motion and clock. With the bias known, each
   frame's offset is within 1 ms. Figures in docs/camera-motion.md. */
TEST(GyroTiming, PerFrameOffsetAndGain)
{
    for (const char* name : {"building.jpg", "fruits.jpg", "baboon.jpg"})
    {
        DYNBLUR_REQUIRE_DATA(path, name);
        const ShakeScene scene(path, 30);
        const Recording r = record(scene, 4, 1.0);
        const Ptr<CameraMotion> log = gyroLog(*scene.motion, kLogOffset, kBias, 2);
        for (size_t i = 0; i < r.frames.size(); i++)
        {
            const RollingShutter& shutter = r.truth[i];
            const double mid = shutter.frameStart + 0.5 * 479 * shutter.lineDelay + 0.5 * shutter.exposure;
            Mat valid, right, told;
            DynamicDeblurrer::create(scene.camera)->deblur(r.frames[i], scene.motion, shutter, right, mid, valid);
            DynamicDeblurrer::create(scene.camera)->deblur(r.frames[i], log, shutter, told);
            const Mat mask = judged(valid);
            const double blurred = maskedPsnr(scene.truth, r.frames[i], mask, 255),
                         truth = maskedPsnr(scene.truth, right, mask, 255),
                         asTold = maskedPsnr(scene.truth, told, mask, 255);
            for (bool biasKnown : {false, true})
            {
                Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(scene.camera);
                deblurrer->setReferenceFrame(r.stills[i], r.stillShutters[i]);
                if (biasKnown)
                {
                    MotionCorrection bias;
                    bias.gyroBias = kBias;
                    deblurrer->setCalibration(bias);
                }
                else
                    deblurrer->setRefinement(REFINE_ALL | REFINE_GYRO_BIAS);
                Mat refined;
                deblurrer->deblur(r.frames[i], log, shutter, refined);
                const MotionCorrection c = deblurrer->getLastCorrection();
                const double fitted = maskedPsnr(scene.truth, refined, mask, 255);
                std::printf("[ figure ] %s frame %zu, bias %s: offset %.3f ms (truth 5), line delay x%.4f, bias (%.2f "
                            "%.2f %.2f) deg/s; blurred %.2f, truth %.2f, log as told %.2f (%.0f %% of the gain), "
                            "refined %.2f dB (%.0f %%)\n",
                            name, i, biasKnown ? "known" : "refined", c.timeOffset * 1e3, c.lineDelayScale,
                            c.gyroBias[0] / kDegree, c.gyroBias[1] / kDegree, c.gyroBias[2] / kDegree, blurred, truth,
                            asTold, 100 * (asTold - blurred) / (truth - blurred), fitted,
                            100 * (fitted - blurred) / (truth - blurred));
                EXPECT_TRUE(c.applied) << name << " frame " << i << ": " << c.reason;
                if (biasKnown)  // measured within 0.12 ms; the issue asks 1 ms
                {
                    EXPECT_NEAR(c.timeOffset, kLogOffset, 0.15e-3) << name << " frame " << i;
                }
                EXPECT_GE(fitted - blurred, 0.9 * (truth - blurred)) << name << " frame " << i;
            }
        }
    }
}

/* tRef is a camera time, like frameStart and the still's capture time: the clock offset the
   refinement finds moves it onto the log's clock with them. A global-shutter frame (the offset is
   all its refinement finds) restored to the view at an explicit tRef, its own mid-exposure, must
   match the default reference, which is that same instant. */
TEST(GyroTiming, ExplicitReferenceTimeMovesWithTheRefinedOffset)
{
    DYNBLUR_REQUIRE_DATA(path, "building.jpg");
    const ShakeScene scene(path, 30);
    const Ptr<CameraMotion> log = gyroLog(*scene.motion, kLogOffset, Vec3d(), 5);
    const RollingShutter shutter(-0.15, 0.020, 0.0, 480);
    const double mid = shutter.frameStart + 0.5 * shutter.exposure;
    const Mat frame = scene.capture(shutter, 300);
    const RollingShutter still = stillShutter(shutter.frameStart - 0.2);
    const Mat stillFrame = scene.capture(still, 301, mid);
    const Mat mask = judged(Mat(480, 640, CV_8U, Scalar(255)));
    double psnr[2];
    for (int explicitReference = 0; explicitReference < 2; explicitReference++)
    {
        Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(scene.camera);
        deblurrer->setReferenceFrame(stillFrame, still);
        Mat restored;
        deblurrer->deblur(frame, log, shutter, restored, explicitReference ? mid : NAN);
        const MotionCorrection c = deblurrer->getLastCorrection();
        ASSERT_TRUE(c.applied) << c.reason;
        EXPECT_NEAR(c.timeOffset, kLogOffset, 0.5e-3);
        psnr[explicitReference] = maskedPsnr(scene.truth, restored, mask, 255);
    }
    const double blurred = maskedPsnr(scene.truth, frame, mask, 255);
    std::printf("[ figure ] global-shutter frame, log 5 ms ahead, refined against a still: blurred %.2f dB, "
                "restored to the default reference %.2f dB, to tRef = its mid-exposure %.2f dB\n",
                blurred, psnr[0], psnr[1]);
    EXPECT_NEAR(psnr[1], psnr[0], 0.2);
}

/* Frames whose log does not match them (another recording's log; the right log 50 ms off) come
   back no worse than they went in: refused, or held at the model as told where that is no worse. */
TEST(GyroTiming, MismatchedLogIsNeverWorse)
{
    DYNBLUR_REQUIRE_DATA(path, "building.jpg");
    const ShakeScene scene(path, 30);
    const Recording r = record(scene, 4, 1.0);
    const Ptr<CameraMotion> other = gyroLog(*dynblur_test::handShake(30), -0.35, kBias, 3);  // 0.35 s elsewhere
    const Ptr<CameraMotion> shifted = gyroLog(*scene.motion, 0.050, kBias, 4);
    for (size_t i = 0; i < r.frames.size(); i++)
        for (const Ptr<CameraMotion>& log : {other, shifted})
        {
            Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(scene.camera);
            deblurrer->setReferenceFrame(r.stills[i], r.stillShutters[i]);
            Mat restored, valid;
            deblurrer->deblur(r.frames[i], log, r.truth[i], restored, NAN, valid);
            const MotionCorrection c = deblurrer->getLastCorrection();
            const Mat mask = judged(Mat(480, 640, CV_8U, Scalar(255)));
            const double blurred = maskedPsnr(scene.truth, r.frames[i], mask, 255),
                         out = maskedPsnr(scene.truth, restored, mask, 255);
            std::printf("[ figure ] mismatched log (%s), frame %zu: applied %d, offset %.2f ms, consistency %.2f, "
                        "blurred %.2f dB, out %.2f dB; %s\n",
                        log == other ? "another recording" : "50 ms off", i, int(c.applied), c.timeOffset * 1e3,
                        c.consistency, blurred, out, c.reason.c_str());
            EXPECT_GE(out, blurred) << i;  // measured: every one refused, returned as it came
        }
}

/* Bad input to the measured motion's refinement: each refused with the argument's name. */
TEST(GyroTimingBadInput, ArgumentsAreNamed)
{
    using dynblur_test::expectErrorNaming;
    const Ptr<CameraModel> camera = CameraModel::create(120, 120, 31.5, 23.5, 64, 48);
    const Ptr<CameraMotion> log = gyroLog(*dynblur_test::handShake(30), 0, Vec3d(), 5);  // samples over [-0.9, 0.9] s
    const Mat frame(48, 64, CV_32F, Scalar(0.5));
    const RollingShutter shutter(0.1, 0.01, 2e-4, 48), still(0.0, 1e-4, 0, 48);
    const std::vector<Mat> two{frame, frame};
    const std::vector<RollingShutter> shutters{shutter, shutter}, stills{still, still};
    expectErrorNaming([&] { calibrateTiming(Ptr<CameraMotion>(), camera, two, two, shutters, stills); }, "'motion'");
    expectErrorNaming([&] { calibrateTiming(log, camera, two, two, shutters, {still}); }, "referenceShutters 1");
    expectErrorNaming([&] { calibrateTiming(log, camera, two, two, shutters, stills, REFINE_PLANT); }, "flags = 4");
    expectErrorNaming([&] { calibrateTiming(log, camera, two, two, shutters, stills, 32); }, "flags = 32");
    expectErrorNaming([&] { calibrateTiming(log, camera, two, two, shutters, stills, 3, 0.0); }, "maxTimeOffset");
    const Ptr<Plant> plant = Plant::create(14.4, 0.12, kDegree);
    expectErrorNaming(
        [&] {
            calibrateTiming(CameraMotion::fromPlant(plant, SwitchSchedule({0.0}, {1}, 0)), camera, two, two, shutters,
                            stills);
        },
        "calibrateTiming(plant");
    const std::vector<RollingShutter> late{shutter, RollingShutter(0.895, 0.01, 2e-4, 48)};
    expectErrorNaming([&] { calibrateTiming(log, camera, two, two, late, stills); }, "'frames[1]'");
    expectErrorNaming([&] { calibrateTiming(log, camera, two, two, shutters, {still, RollingShutter(0, 1e-4, 0, 47)}); },
                      "referenceShutters[1]");

    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(camera);
    Mat out;
    expectErrorNaming([&] { deblurrer->setReferenceFrame(frame, RollingShutter(0, 1e-4, 0, 47)); }, "stillShutter");
    expectErrorNaming([&] { deblurrer->setRefinement(32); }, "flags = 32");
    deblurrer->setReferenceFrame(frame, 0.0);  // an angle: a plant's still
    expectErrorNaming([&] { deblurrer->deblur(frame, log, shutter, out); }, "capture time");
    deblurrer->setReferenceFrame(frame, RollingShutter(-0.899, 1e-4, 0, 48));
    expectErrorNaming([&] { deblurrer->deblur(frame, log, shutter, out); }, "reference frame's capture time");
    deblurrer->setReferenceFrame(frame, still);
    expectErrorNaming([&] { deblurrer->deblur(frame, log, RollingShutter(0.89, 0.005, 0, 48), out); }, "'frame'");
    MotionCorrection wrong;
    wrong.gyroBias = Vec3d(0, NAN, 0);
    expectErrorNaming([&] { deblurrer->setCalibration(wrong); }, "gyroBias[1]");
    // A still placed by time does not serve a plant's frames.
    Ptr<DynamicDeblurrer> plantDeblurrer = DynamicDeblurrer::create(plant, camera);
    plantDeblurrer->setReferenceFrame(frame, still);
    expectErrorNaming([&] { plantDeblurrer->deblur(frame, SwitchSchedule({0.1}, {4}, 0), shutter, out); },
                      "setReferenceFrame(still, angle)");
}
