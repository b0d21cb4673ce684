// SPDX-License-Identifier: Apache-2.0
// Refinement of a mount's motion (Mount::motion): the clock, the line delay and each axis's ωn and ζ,
// per frame against the stills at rest (DynamicDeblurrer) and over a recording (calibrateTiming).
#include "test_common.hpp"

#include "image_metrics.hpp"
#include "mount_scene.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>

using namespace cv;
using namespace cv::dynblur;
using dynblur_samples::maskedPsnr;
using dynblur_test::expectErrorNaming;
using dynblur_test::MountScene;
using dynblur_test::shutterInWindow;

namespace {

const double kDeg = CV_PI / 180, kNaN = std::numeric_limits<double>::quiet_NaN();

//! Each axis's drift from the nominal plant: ωn and ζ scales.
struct AxisDrift
{
    double naturalFreqScale = 1, dampingScale = 1;
};

/* The pan-tilt head: pan (0, 1, 0) carries tilt (1, 0, 0), each the seed's positioner (14.4 Hz,
   ζ 0.12, 1° per level), its plants drifted by `pan` and `tilt`. */
Ptr<Mount> seedPanTilt(const AxisDrift& pan = AxisDrift(), const AxisDrift& tilt = AxisDrift())
{
    Ptr<Mount> mount = Mount::create();
    mount->addAxis(Vec3d(0, 1, 0), Plant::create(14.4 * pan.naturalFreqScale, 0.12 * pan.dampingScale, kDeg), -16, 16);
    mount->addAxis(Vec3d(1, 0, 0), Plant::create(14.4 * tilt.naturalFreqScale, 0.12 * tilt.dampingScale, kDeg), -16,
                   16);
    return mount;
}

//! One saccade per axis from rest at 0 to `panDeg`, `tiltDeg`, planned for the nominal plants; 0: the axis holds.
std::vector<SwitchSchedule> saccade(double panDeg, double tiltDeg)
{
    const Ptr<Mount> nominal = seedPanTilt();
    std::vector<SwitchSchedule> schedules;
    const double degrees[2] = {panDeg, tiltDeg};
    for (int i = 0; i < 2; i++)
        schedules.push_back(degrees[i] == 0 ? SwitchSchedule(std::vector<double>{0.0}, std::vector<int>{0})
                                            : SwitchPlanner::create(nominal->getPlant(i), 16)
                                                  ->plan(0.0, degrees[i] * kDeg, 0.0));
    return schedules;
}

// The truth: pan ωn +3 %, ζ +10 %; tilt ωn −3 %, ζ −10 %; the camera's clock 1 ms late.
const AxisDrift kPanDrift{1.03, 1.10}, kTiltDrift{0.97, 0.90};
const double kClockOffset = 1e-3;

//! A frame of a drifted mount's move, its stills at rest before and after it, and the motions told and true.
struct MountFrame
{
    String what;
    Ptr<CameraMotion> told, truth;
    RollingShutter shutter;  // as reported
    Mat frame, before, after;
    int window = 0;
};

MountFrame captureMountFrame(const MountScene& scene, double panDeg, double tiltDeg, int window, double lineDelay,
                             uint64 seed)
{
    MountFrame f;
    const std::vector<SwitchSchedule> schedules = saccade(panDeg, tiltDeg);
    f.told = seedPanTilt()->motion(schedules);
    f.truth = seedPanTilt(kPanDrift, kTiltDrift)->motion(schedules);
    f.window = window;
    f.shutter = shutterInWindow(f.told, window, lineDelay);
    RollingShutter happened = f.shutter;
    happened.frameStart += kClockOffset;
    f.frame = scene.capture(f.truth, happened, seed);
    f.before = scene.capture(f.truth, RollingShutter(-0.2, 0.008, lineDelay, 480), seed + 1);
    f.after = scene.capture(f.truth, RollingShutter(1.0, 0.008, lineDelay, 480), seed + 2);
    f.what = format("pan %.0f tilt %.0f deg, window %s%s", panDeg, tiltDeg, window == EXPOSURE_I ? "I" : "III",
                    lineDelay > 0 ? "" : " global");
    return f;
}

//! The table's rows of mount axis `axis`, as heldParameters bits.
int axisBits(int axis)
{
    const std::vector<RefinementParameter> table = refinementParameters();
    int bits = 0;
    for (size_t j = 0; j < table.size(); j++)
        if (table[j].mountAxis == axis)
            bits |= 1 << j;
    return bits;
}

class MountRefinementQuality : public testing::TestWithParam<std::string>
{
};

}  // namespace

TEST(MountRefinement, TableHasEachAxisUnderRefinePlant)
{
    int axes = 0;
    for (const RefinementParameter& p : refinementParameters())
        if (p.mountAxis >= 0)
        {
            EXPECT_EQ(p.flag, REFINE_PLANT) << p.name;
            EXPECT_TRUE(p.mountMotion) << p.name;
            EXPECT_EQ(p.plantMotion, p.mountAxis == 0) << p.name;
            axes |= 1 << p.mountAxis;
        }
    EXPECT_EQ(axes, 7);  // axes 0, 1 and 2
    EXPECT_EQ(__builtin_popcount(axisBits(1)), 2);
}

TEST(MountRefinement, CorrectMotionScalesEachAxisPlant)
{
    const std::vector<SwitchSchedule> schedules = saccade(10, 6);
    const Ptr<CameraMotion> told = seedPanTilt()->motion(schedules);
    MotionCorrection c;
    EXPECT_EQ(c.correctMotion(told), told);  // nothing to scale: the motion itself
    c.naturalFreqScale = kPanDrift.naturalFreqScale;
    c.dampingScale = kPanDrift.dampingScale;
    c.axisNaturalFreqScales = Vec2d(kTiltDrift.naturalFreqScale, 1);
    c.axisDampingScales = Vec2d(kTiltDrift.dampingScale, 1);
    const Ptr<CameraMotion> corrected = c.correctMotion(told);
    const Ptr<CameraMotion> truth = seedPanTilt(kPanDrift, kTiltDrift)->motion(schedules);
    for (double t = 0; t < 0.1; t += 0.007)
    {
        EXPECT_LT(norm(corrected->orientation(t) - truth->orientation(t)), 1e-12) << t;
        EXPECT_LT(norm(corrected->angularVelocity(t) - truth->angularVelocity(t)), 1e-9) << t;
    }
    EXPECT_LT(norm(corrected->referenceOrientation(kNaN, RollingShutter()) - told->referenceOrientation(kNaN, RollingShutter())),
              1e-15);  // the gains, and so the rests, are kept
}

TEST(MountRefinement, BadInputNamesTheArgument)
{
    MotionCorrection c;
    c.axisDampingScales[1] = 0;
    expectErrorNaming([&] { c.validate(); }, "axisDampingScales[1] = 0 must be in (0, 10)");

    const Ptr<CameraModel> camera = CameraModel::create(150, 150, 79.5, 59.5, 160, 120);
    const Mat frame(120, 160, CV_32F, Scalar(0.5));
    const std::vector<Mat> two{frame, frame};
    const std::vector<RollingShutter> shutters(2, RollingShutter(0.01, 0.008, 0, 120));
    const Ptr<CameraMotion> mount = seedPanTilt()->motion(saccade(10, 6));
    const Mat t = (Mat_<double>(3, 1) << 0, 0.5, 1), rates = Mat::zeros(3, 3, CV_64F);
    const Ptr<CameraMotion> gyro = CameraMotion::fromAngularVelocity(t, rates);
    expectErrorNaming([&] { calibrateTiming({mount, gyro}, camera, two, two, shutters, REFINE_ALL); },
                      "motions[1] is not a mount's");
    expectErrorNaming([&] { calibrateTiming({mount}, camera, two, two, shutters, REFINE_ALL); },
                      "frames has 2 entries but motions 1");
    expectErrorNaming([&] { calibrateTiming({mount, mount}, camera, two, two, shutters, REFINE_GYRO_BIAS); },
                      "flags = 8 must combine REFINE_TIME_OFFSET (1), REFINE_LINE_DELAY (2) and REFINE_PLANT (4)");

    const Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(camera);
    deblurrer->setReferenceFrame(frame, 0.1);
    Mat restored;
    expectErrorNaming([&] { deblurrer->deblur(frame, mount, shutters[0], restored); }, "without an angle");
}

TEST(MountRefinement, AxisScalesSurviveSaveAndLoad)
{
    TimingCalibration calibration;
    calibration.correction.axisNaturalFreqScales = Vec2d(0.97, 1.01);
    calibration.correction.axisDampingScales = Vec2d(0.9, 1.2);
    calibration.axisNaturalFreqScaleStd = Vec2d(0.002, 0.003);
    const std::string file = tempfile(".yml");
    calibration.save(file);
    const TimingCalibration loaded = TimingCalibration::load(file);
    std::remove(file.c_str());
    EXPECT_EQ(loaded.correction.axisNaturalFreqScales, calibration.correction.axisNaturalFreqScales);
    EXPECT_EQ(loaded.correction.axisDampingScales, calibration.correction.axisDampingScales);
    EXPECT_EQ(loaded.axisNaturalFreqScaleStd, calibration.axisNaturalFreqScaleStd);
}

/* The figure: a pan-tilt head whose axes drifted (pan ωn +3 %, ζ +10 %; tilt ωn −3 %, ζ −10 %)
   and whose clock is 1 ms late, told the nominal mount; each frame refined against the stills at rest on
   both sides of its move keeps at least 90 % of the gain over the blurred frame that a deblurrer told
   the truth reaches (mean over the frames of an image), no frame ends below its input, and a move that
   does not turn the tilt reports the tilt's parameters held. Prints the fitted scales against the truth. */
TEST_P(MountRefinementQuality, DriftedAxesKeepTheGainOfTheTruth)
{
    DYNBLUR_REQUIRE_DATA(path, GetParam());
    const MountScene scene(path);
    struct Case
    {
        double panDeg, tiltDeg;
        int window;
        double lineDelay;
    };
    const double rolling = 1.0 / 30 / 480;
    const Case cases[] = {{10, 6, EXPOSURE_I, rolling}, {10, 6, EXPOSURE_III, rolling}, {10, 6, EXPOSURE_III, 0.0},
                          {10, 0, EXPOSURE_III, rolling}};
    double keptSum = 0;
    int count = 0;
    for (const Case& k : cases)
    {
        const MountFrame f = captureMountFrame(scene, k.panDeg, k.tiltDeg, k.window, k.lineDelay, 7);
        const Ptr<DynamicDeblurrer> truth = DynamicDeblurrer::create(scene.camera);
        RollingShutter happened = f.shutter;
        happened.frameStart += kClockOffset;
        Mat truthRestored, valid, refined;
        truth->deblur(f.frame, f.truth, happened, truthRestored, kNaN, valid);
        const Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(scene.camera);
        deblurrer->setReferenceFrames(f.before, f.after);
        deblurrer->deblur(f.frame, f.told, f.shutter, refined);
        const MotionCorrection c = deblurrer->getLastCorrection();
        const double blurred = maskedPsnr(scene.truth, f.frame, valid, 255),
                     told = maskedPsnr(scene.truth, truthRestored, valid, 255),
                     gained = maskedPsnr(scene.truth, refined, valid, 255);
        const double kept = (gained - blurred) / (told - blurred);
        std::printf("[ measured ] %s, %s: blurred %.2f dB, told the truth %.2f, refined %.2f (%.0f %% of the "
                    "truth's gain) | dt %+.3f ms (true %+.3f), pan wn x%.4f (%.2f) zeta x%.3f (%.2f), tilt wn "
                    "x%.4f (%.2f) zeta x%.3f (%.2f), line delay x%.3f, held 0x%x, consistency %.2f\n",
                    GetParam().c_str(), f.what.c_str(), blurred, told, gained, 100 * kept, c.timeOffset * 1e3,
                    kClockOffset * 1e3, c.naturalFreqScale, kPanDrift.naturalFreqScale, c.dampingScale,
                    kPanDrift.dampingScale, c.axisNaturalFreqScales[0], kTiltDrift.naturalFreqScale,
                    c.axisDampingScales[0], kTiltDrift.dampingScale, c.lineDelayScale, c.heldParameters,
                    c.consistency);
        EXPECT_TRUE(c.applied) << f.what << ": " << c.reason;
        EXPECT_GE(gained, blurred) << f.what << ": worse than its input";
        if (k.tiltDeg == 0)
        {
            EXPECT_EQ(c.heldParameters & axisBits(1), axisBits(1)) << f.what << ": " << c.reason;
            EXPECT_EQ(c.axisNaturalFreqScales, Vec2d(1, 1));
            EXPECT_NE(c.reason.find("natural frequency, axis 1"), std::string::npos) << c.reason;
        }
        keptSum += kept;
        count++;
    }
    const double meanKept = keptSum / count;
    std::printf("[ measured ] %s: refined keeps %.1f %% of the truth's gain on average (floor 90 %%)\n",
                GetParam().c_str(), 100 * meanKept);
    EXPECT_GE(meanKept, 0.9);
}

INSTANTIATE_TEST_SUITE_P(SharedImages, MountRefinementQuality,
                         testing::Values("building.jpg", "fruits.jpg", "baboon.jpg"),
                         [](const testing::TestParamInfo<std::string>& info) {
                             return info.param.substr(0, info.param.find('.'));
                         });

/* Over a recording: diagonal saccades out and back, frames in windows I and III, each with the still
   that saw its moving rows; calibrateTiming recovers the clock and each axis's scales. */
TEST(MountCalibrateTiming, RecordingCalibratesEachAxis)
{
    DYNBLUR_REQUIRE_DATA(path, "building.jpg");
    const MountScene scene(path);
    std::vector<Ptr<CameraMotion>> motions;
    std::vector<Mat> references, frames;
    std::vector<RollingShutter> shutters;
    std::vector<int> after;
    const double rolling = 1.0 / 30 / 480;
    uint64 seed = 100;
    for (int window : {EXPOSURE_I, EXPOSURE_III})
        for (double lineDelay : {rolling, 0.0})
        {
            if (window == EXPOSURE_I && lineDelay == 0)
                continue;  // a global frame that starts at rest and moves later is rare (exposure 8 ms)
            const MountFrame f = captureMountFrame(scene, 10, 6, window, lineDelay, seed += 3);
            motions.push_back(f.told);
            references.push_back(window == EXPOSURE_I ? f.before : f.after);
            after.push_back(window == EXPOSURE_I ? 0 : 1);
            frames.push_back(f.frame);
            shutters.push_back(f.shutter);
        }
    const TimingCalibration t = calibrateTiming(motions, scene.camera, references, frames, shutters, REFINE_ALL, after);
    const MotionCorrection& c = t.correction;
    std::printf("[ measured ] recording of %zu frames: dt %+.3f ms (true %+.3f, std %.2g), line delay x%.4f, pan wn "
                "x%.4f (%.2f, std %.2g) zeta x%.3f (%.2f, std %.2g), tilt wn x%.4f (%.2f, std %.2g) zeta x%.3f "
                "(%.2f, std %.2g), held 0x%x; %s\n",
                frames.size(), c.timeOffset * 1e3, kClockOffset * 1e3, t.timeOffsetStd * 1e3, c.lineDelayScale,
                c.naturalFreqScale, kPanDrift.naturalFreqScale, t.naturalFreqScaleStd, c.dampingScale,
                kPanDrift.dampingScale, t.dampingScaleStd, c.axisNaturalFreqScales[0], kTiltDrift.naturalFreqScale,
                t.axisNaturalFreqScaleStd[0], c.axisDampingScales[0], kTiltDrift.dampingScale, t.axisDampingScaleStd[0],
                c.heldParameters, c.reason.c_str());
    // Measured: δt 0.05 ms, ωn 0.11 % (pan) and 0.06 % (tilt), ζ 0.6 % and 0.4 % from the truth.
    EXPECT_NEAR(c.timeOffset, kClockOffset, 0.1e-3);
    EXPECT_NEAR(c.naturalFreqScale, kPanDrift.naturalFreqScale, 0.003);
    EXPECT_NEAR(c.axisNaturalFreqScales[0], kTiltDrift.naturalFreqScale, 0.003);
    EXPECT_NEAR(c.dampingScale, kPanDrift.dampingScale, 0.02);
    EXPECT_NEAR(c.axisDampingScales[0], kTiltDrift.dampingScale, 0.02);
    EXPECT_EQ(c.heldParameters, 0) << c.reason;
}
