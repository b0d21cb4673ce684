// SPDX-License-Identifier: Apache-2.0
// Nearly sharp frames (sub-pixel to 1 px of blur) on the three paths, a plant's saccade, a pan-tilt
// mount and a gyro log, against the truth: with the default sharp threshold none ends below the
// recorded frame, deconvolved (setSharpThreshold(0)) some do. And two measurements behind the
// design (docs/quality.md, "Nearly sharp frames").
#include "image_metrics.hpp"
#include "pan_tilt.hpp"
#include "pipeline/frame_sharpness.hpp"
#include "saccade_scene.hpp"
#include "shake_scene.hpp"
#include "test_common.hpp"

#include <gtest/gtest.h>
#include <opencv2/dynblur.hpp>

#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

using namespace cv;
using namespace cv::dynblur;
using cv::dynblur::detail::FrameSharpness;
using cv::dynblur::detail::measureSharpness;
using cv::dynblur::detail::ViewMotion;
using dynblur_samples::maskedPsnr;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

//! One frame of a path, with what restores it and what judges it.
struct PathFrame
{
    std::string path;  // "plant", "mount" or "gyro"
    std::string what;  // the frame, for the printout
    RollingShutter shutter;
    Mat frame, truth;
    int border = 8;            // pixels left out at the edges when judging
    ViewMotion view;           // its motion as the deblurrer sees it (nothing refines it here)
    Ptr<CameraModel> camera;
    std::function<Ptr<DynamicDeblurrer>()> create;
    std::function<void(DynamicDeblurrer&, const Mat&, Mat&, Mat&)> deblur;  // frame, restored, validMask
};

//! The frame restored by `deblurrer`, PSNR against the truth over `judged`, and what it did.
struct Result
{
    Mat restored, valid;
    std::string reason;
};

Result restore(const PathFrame& f, double threshold)
{
    Ptr<DynamicDeblurrer> deblurrer = f.create();
    deblurrer->setSharpThreshold(threshold);
    Result r;
    f.deblur(*deblurrer, f.frame, r.restored, r.valid);
    r.reason = deblurrer->getLastCorrection().reason;
    return r;
}

ViewMotion plantView(const Ptr<Plant>& plant, const SwitchSchedule& schedule)
{
    ViewMotion view;
    view.plant = plant;
    view.schedule = schedule;
    view.axis = Vec3d(1, 0, 0);
    view.thetaRef = plant->restingAngle(schedule.finalLevel());
    return view;
}

ViewMotion motionView(const Ptr<CameraMotion>& motion, const RollingShutter& shutter)
{
    ViewMotion view;
    view.motion = motion;
    view.reference = motion->referenceOrientation(kNaN, shutter);
    return view;
}

//! A frame of `s`'s plant read by `shutter` (seed 5), restored with that plant.
PathFrame plantFrame(const std::shared_ptr<dynblur_test::SaccadeScene>& s, const RollingShutter& shutter,
                     const std::string& what)
{
    PathFrame f;
    f.path = "plant";
    f.what = what + (shutter.lineDelay > 0 ? ", rolling" : ", global") + format(" at %.1f ms", shutter.frameStart * 1e3);
    f.shutter = shutter;
    f.frame = s->capture(shutter, 5);
    f.truth = s->truth;
    f.view = plantView(s->plant, s->schedule);
    f.camera = s->camera;
    f.create = [s] { return DynamicDeblurrer::create(s->plant, s->camera); };
    f.deblur = [s, shutter](DynamicDeblurrer& d, const Mat& frame, Mat& out, Mat& valid) {
        d.deblur(frame, s->schedule, shutter, out, kNaN, valid);
    };
    return f;
}

//! A frame of `scene` (rendered from its own motion) read by `shutter`, restored from `motion`: that motion or its gyro log.
PathFrame motionFrame(const std::shared_ptr<dynblur_test::ShakeScene>& scene, const Ptr<CameraMotion>& motion,
                      const RollingShutter& shutter, const std::string& path, const std::string& what, uint64 seed)
{
    PathFrame f;
    f.path = path;
    f.what = what;
    f.shutter = shutter;
    f.frame = scene->capture(shutter, seed);
    f.truth = scene->truth;
    f.border = 16;
    f.view = motionView(motion, shutter);
    f.camera = scene->camera;
    f.create = [scene] { return DynamicDeblurrer::create(scene->camera); };
    f.deblur = [motion, shutter](DynamicDeblurrer& d, const Mat& frame, Mat& out, Mat& valid) {
        d.deblur(frame, motion, shutter, out, kNaN, valid);
    };
    return f;
}

//! The last frame start (1 ms steps from `shutter`'s) whose frame is not still throughout.
template <typename Window>
RollingShutter lastMovingFrame(RollingShutter shutter, const Window& window)
{
    while (window(shutter) != EXPOSURE_IV)
        shutter.frameStart += 0.001;
    shutter.frameStart -= 0.001;
    return shutter;
}

/* The plant's frames, C270 at half resolution (SaccadeScene), rolling (33 ms readout) and global,
   8 ms: (1) the last frame (1 ms steps) before the planned 10° saccade's frames are still, and (2)
   the settling of a positioner 3 % stiffer and 10 % more damped than planned, which still swings
   after the move (the deblurrer told the truth, as a calibrated plant would be): the 30 fps frames
   from 143 to 310 ms, 0.85 px of blur down to 0.05 px. */
void addPlantFrames(const std::string& path, std::vector<PathFrame>& frames)
{
    const auto planned = std::make_shared<dynblur_test::SaccadeScene>(path);
    for (double lineDelay : {1.0 / 30 / 480, 0.0})
        frames.push_back(plantFrame(planned,
                                    lastMovingFrame(planned->shutterInWindow(EXPOSURE_III, lineDelay),
                                                    [&](const RollingShutter& sh) {
                                                        return classifyExposure(planned->plant, planned->schedule, sh);
                                                    }),
                                    "saccade's end"));
    const auto swinging = std::make_shared<dynblur_test::SaccadeScene>(path);
    swinging->plant = Plant::create(14.4 * 1.03, 0.12 * 1.10, dynblur_test::kDeg);  // after the plan
    for (double lineDelay : {1.0 / 30 / 480, 0.0})
        for (int k = 4; k <= 9; k++)
            frames.push_back(
                plantFrame(swinging, RollingShutter(0.010 + k / 30.0, 0.008, lineDelay, 480), "settling swing"));
}

//! The pan-tilt head's move (pan 5°, tilt 4°, test_mount.cpp's), made `scene`'s motion: its final rest is the scene.
Ptr<CameraMotion> panTiltMove(dynblur_test::ShakeScene& scene)
{
    const Ptr<Mount> mount = dynblur_test::panTilt();
    scene.motion = mount->motion(dynblur_test::plannedMoves(mount, {-5, 4}, {0, 0}, 0.0));
    return scene.motion;
}

/* A pan-tilt head's move, rolling (30 ms readout) and global, 10 ms: the last frame (1 ms steps)
   before its frames are still, restored from Mount::motion. */
void addMountFrames(const std::string& path, std::vector<PathFrame>& frames)
{
    auto scene = std::make_shared<dynblur_test::ShakeScene>(path, 1.0);
    const Ptr<CameraMotion> motion = panTiltMove(*scene);
    for (double lineDelay : {0.030 / 480, 0.0})
    {
        const auto window = [&](const RollingShutter& sh) { return classifyExposure(motion, sh); };
        const RollingShutter shutter = lastMovingFrame(RollingShutter(0.0, 0.010, lineDelay, 480), window);
        frames.push_back(motionFrame(scene, motion, shutter, "mount",
                                     format("pan-tilt move's end, %s at %.0f ms", lineDelay > 0 ? "rolling" : "global",
                                            shutter.frameStart * 1e3),
                                     3));
    }
}

/* A hand-held camera (ShakeScene, f = 600 px) shaken at up to 2, 4 and 6 °/s, restored from its
   rates sampled as a 1 kHz gyro log: rolling (30 ms readout) and global, 10 ms (and 20 ms at 2 °/s),
   at 0.1 and 0.3 s; the frames still throughout (window IV) left out. */
void addGyroFrames(const std::string& path, std::vector<PathFrame>& frames)
{
    for (double rate : {2.0, 4.0, 6.0})
    {
        auto scene = std::make_shared<dynblur_test::ShakeScene>(path, rate);
        Mat t(1, 1001, CV_64F), rates(1001, 3, CV_64F);
        for (int k = 0; k < t.cols; k++)
        {
            t.at<double>(k) = k / 1000.0;
            const Vec3d w = scene->motion->angularVelocity(k / 1000.0);
            for (int i = 0; i < 3; i++)
                rates.at<double>(k, i) = w[i];
        }
        const Ptr<CameraMotion> gyro = CameraMotion::fromAngularVelocity(t, rates, scene->motion->orientation(0.0));
        for (double exposure : rate == 2.0 ? std::vector<double>{0.010, 0.020} : std::vector<double>{0.010})
            for (double lineDelay : {0.030 / 480, 0.0})
                for (double start : {0.1, 0.3})
                {
                    const RollingShutter shutter(start, exposure, lineDelay, 480);
                    if (classifyExposure(gyro, shutter) != EXPOSURE_IV)
                        frames.push_back(motionFrame(scene, gyro, shutter, "gyro",
                                                     format("shake %.0f deg/s, %s, %.0f ms at %.1f s", rate,
                                                            lineDelay > 0 ? "rolling" : "global", exposure * 1e3, start),
                                                     7));
                }
    }
}

//! The pixels judged: the frame less `border`, where both restorations observed the view.
Mat judgedPixels(const PathFrame& f, const Mat& validA, const Mat& validB)
{
    Mat judged(f.frame.size(), CV_8U, Scalar(0));
    judged(Rect(f.border, f.border, f.frame.cols - 2 * f.border, f.frame.rows - 2 * f.border)).setTo(255);
    return judged & validA & validB;
}

/* Measured: 22 of the 124 frames end more than 0.05 dB below the recorded frame when deconvolved
   (the frames prove the problem), and the 68 whose rows are moved back gain 3.20 dB on average over
   it. Floors at 90 %. */
const int kWorseWhenDeconvolvedFloor = 20;
const double kMovedBackGainFloor = 2.9;

}  // namespace

/* The figure: nearly sharp frames (blur under 1 px by the measure) of the plant, mount and
   gyro paths on four images end no more than 0.05 dB below the recorded frame with the default
   threshold (1 px), while with setSharpThreshold(0) (every frame deconvolved) some end below it.
   Prints, per path and image, the frames, how many were passed through, moved back and
   deconvolved, and the worst change against the recorded frame in both settings. */
TEST(SharpQuality, NearlySharpFramesNeverEndBelowTheRecordedFrame)
{
    struct Tally
    {
        int frames = 0, passed = 0, moved = 0, deconvolved = 0, worseWhenDeconvolved = 0;
        double worst = 1e9, worstDeconvolved = 1e9, movedGain = 0;
    };
    std::map<std::string, Tally> tallies;
    Tally total;
    for (const char* name : {"building.jpg", "fruits.jpg", "board.jpg", "baboon.jpg"})
    {
        DYNBLUR_REQUIRE_DATA(path, name);
        std::vector<PathFrame> frames;
        addPlantFrames(path, frames);
        addMountFrames(path, frames);
        addGyroFrames(path, frames);
        for (const PathFrame& f : frames)
        {
            const FrameSharpness sharpness = measureSharpness(f.view, f.shutter, *f.camera);
            ASSERT_LT(sharpness.blurPx, 1.0) << f.what << ": not a nearly sharp frame";
            const Result byDefault = restore(f, 1.0), deconvolved = restore(f, 0.0);
            const Mat judged = judgedPixels(f, byDefault.valid, deconvolved.valid);
            const double recorded = maskedPsnr(f.truth, f.frame, judged, 255),
                         change = maskedPsnr(f.truth, byDefault.restored, judged, 255) - recorded,
                         changeDeconvolved = maskedPsnr(f.truth, deconvolved.restored, judged, 255) - recorded;
            const bool sharp = byDefault.reason.rfind("sharp:", 0) == 0,
                       moved = byDefault.reason.find("moved back") != std::string::npos;
            std::printf("[ measured ] %s, %s: blur %.2f px, shift %.2f px, recorded %.2f dB; default %+.2f dB (%s), "
                        "deconvolved %+.2f dB\n",
                        name, f.what.c_str(), sharpness.blurPx, sharpness.shiftPx, recorded, change,
                        moved ? "moved back" : sharp ? "passed through" : "deconvolved", changeDeconvolved);
            EXPECT_GE(change, -0.05) << name << ", " << f.what << ": " << byDefault.reason;
            for (Tally* t : {&tallies[f.path + ", " + name], &total})
            {
                t->frames++;
                t->passed += sharp && !moved;
                t->moved += moved;
                t->deconvolved += !sharp;
                t->worseWhenDeconvolved += changeDeconvolved < -0.05;
                t->worst = std::min(t->worst, change);
                t->worstDeconvolved = std::min(t->worstDeconvolved, changeDeconvolved);
                t->movedGain += moved ? change : 0.0;
            }
        }
    }
    for (const auto& [key, t] : tallies)
        std::printf("[ measured ] %s: %d frames, %d passed through, %d moved back, %d deconvolved; worst against the "
                    "recorded frame %+.2f dB; every frame deconvolved: worst %+.2f dB, %d below it\n",
                    key.c_str(), t.frames, t.passed, t.moved, t.deconvolved, t.worst, t.worstDeconvolved,
                    t.worseWhenDeconvolved);
    std::printf("[ measured ] all: %d frames, %d passed through, %d moved back (mean gain %+.2f dB), %d deconvolved; "
                "worst %+.2f dB; every frame deconvolved: worst %+.2f dB, %d below the recorded frame (floor %d)\n",
                total.frames, total.passed, total.moved, total.moved ? total.movedGain / total.moved : 0.0,
                total.deconvolved, total.worst, total.worstDeconvolved, total.worseWhenDeconvolved,
                kWorseWhenDeconvolvedFloor);
    EXPECT_GE(total.worseWhenDeconvolved, kWorseWhenDeconvolvedFloor) << "fewer frames suffer from deconvolution: "
                                                                          "the test no longer shows why they are skipped";
    ASSERT_GT(total.moved, 0);
    EXPECT_GE(total.movedGain / total.moved, kMovedBackGainFloor);
}

/* Why rows are not skipped band by band (docs/quality.md, "Nearly sharp frames"): frames at the end
   of a move whose first rows catch its tail (the plant's window III frames, rolling, in 2 ms steps
   until still; the pan-tilt head's likewise), deconvolved whole against the same frame with its sharp
   rows (both neighbouring grid rows within 1 px of blur and of shift) kept as recorded; the largest
   shift among them is printed. Deconvolving whole is the best case for the other rows, which a
   band-wise restoration would see only with a margin. A measurement, not a check: run with
   --gtest_also_run_disabled_tests. */
TEST(SharpQuality, DISABLED_SharpRowsOfDeconvolvedFrames)
{
    for (const char* name : {"building.jpg", "fruits.jpg", "board.jpg", "baboon.jpg"})
    {
        DYNBLUR_REQUIRE_DATA(path, name);
        std::vector<PathFrame> frames;
        const auto planned = std::make_shared<dynblur_test::SaccadeScene>(path);
        for (RollingShutter shutter = planned->shutterInWindow(EXPOSURE_III, 1.0 / 30 / 480);
             classifyExposure(planned->plant, planned->schedule, shutter) != EXPOSURE_IV; shutter.frameStart += 0.002)
            frames.push_back(plantFrame(planned, shutter, "window III"));
        auto scene = std::make_shared<dynblur_test::ShakeScene>(path, 1.0);
        const Ptr<CameraMotion> motion = panTiltMove(*scene);
        RollingShutter shutter(0.0, 0.010, 0.030 / 480, 480);
        while (classifyExposure(motion, shutter) != EXPOSURE_III)
            shutter.frameStart += 0.001;
        for (; classifyExposure(motion, shutter) != EXPOSURE_IV; shutter.frameStart += 0.002)
            frames.push_back(motionFrame(scene, motion, shutter, "mount",
                                         format("pan-tilt move's end, rolling at %.0f ms", shutter.frameStart * 1e3), 3));
        for (const PathFrame& f : frames)
        {
            const FrameSharpness sharpness = measureSharpness(f.view, f.shutter, *f.camera);
            const Result whole = restore(f, 0.0);
            Mat bands = whole.restored.clone();
            int sharpRows = 0;
            double largestShift = 0;
            for (int y = 0; y < f.frame.rows; y++)
            {
                const size_t r = size_t(std::min(y / 8, int(sharpness.rows.size()) - 2));
                const double shift = std::max(sharpness.rowShiftPx[r], sharpness.rowShiftPx[r + 1]);
                if (std::max({sharpness.rowBlurPx[r], sharpness.rowBlurPx[r + 1], shift}) < 1.0)
                {
                    f.frame.row(y).copyTo(bands.row(y));
                    sharpRows++;
                    largestShift = std::max(largestShift, shift);
                }
            }
            const Mat judged = judgedPixels(f, whole.valid, whole.valid);
            const double recorded = maskedPsnr(f.truth, f.frame, judged, 255);
            std::printf("[ measured ] %s, %s: blur %.2f px, %.0f %% of the rows sharp (shift up to %.2f px); recorded "
                        "%.2f dB, deconvolved whole %+.2f dB, sharp rows kept %+.2f dB\n",
                        name, f.what.c_str(), sharpness.blurPx, 100.0 * sharpRows / f.frame.rows, largestShift, recorded,
                        maskedPsnr(f.truth, whole.restored, judged, 255) - recorded,
                        maskedPsnr(f.truth, bands, judged, 255) - recorded);
        }
    }
}

/* Where a sharp frame's shift is worth moving back (the 0.05 px below which it is returned as it
   came): a global-shutter frame of a 2 °/s shake (0.31 px of blur) restored to reference views
   0.5–12 ms from its mid-exposure, moved back and deconvolved, against the truth at that view. A
   measurement, not a check: run with --gtest_also_run_disabled_tests. */
TEST(SharpQuality, DISABLED_SmallShifts)
{
    for (const char* name : {"building.jpg", "fruits.jpg", "board.jpg", "baboon.jpg"})
    {
        DYNBLUR_REQUIRE_DATA(path, name);
        const dynblur_test::ShakeScene scene(path, 2.0);
        const RollingShutter shutter(0.1, 0.010, 0.0, 480);
        for (double offset : {0.0005, 0.001, 0.002, 0.003, 0.005, 0.008, 0.012})
        {
            const double tRef = shutter.frameStart + 0.5 * shutter.exposure + offset;
            const Mat frame = scene.capture(shutter, 7, tRef);  // the truth is the view at Q(tRef)
            Mat restored[2], valid[2];
            std::string reason;
            for (int k = 0; k < 2; k++)
            {
                Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(scene.camera);
                deblurrer->setSharpThreshold(k == 0 ? 1e6 : 0.0);
                deblurrer->deblur(frame, scene.motion, shutter, restored[k], tRef, valid[k]);
                if (k == 0)
                    reason = deblurrer->getLastCorrection().reason;
            }
            Mat judged(frame.size(), CV_8U, Scalar(0));
            judged(Rect(16, 16, frame.cols - 32, frame.rows - 32)).setTo(255);
            judged = judged & valid[0] & valid[1];
            const double recorded = maskedPsnr(scene.truth, frame, judged, 255);
            std::printf("[ measured ] %s, reference %.1f ms from mid-exposure: %s; recorded %.2f dB, moved back "
                        "%+.2f dB, deconvolved %+.2f dB\n",
                        name, offset * 1e3, reason.substr(0, reason.find(", both")).c_str(), recorded,
                        maskedPsnr(scene.truth, restored[0], judged, 255) - recorded,
                        maskedPsnr(scene.truth, restored[1], judged, 255) - recorded);
        }
    }
}
