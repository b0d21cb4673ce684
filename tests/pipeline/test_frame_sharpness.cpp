// SPDX-License-Identifier: Apache-2.0
// Whether a frame is sharp (DynamicDeblurrer::setSharpThreshold): the measure against a dense
// reference, frames just under and just over the threshold (a plant's and a measured motion, global
// and rolling shutter), the rows of a sharp frame moved back to the reference view, and the checks.
#include "pipeline/frame_sharpness.hpp"
#include "rotation_motion.hpp"
#include "test_common.hpp"

#include <gtest/gtest.h>
#include <opencv2/dynblur.hpp>

#include <cstdio>
#include <functional>
#include <string>

using namespace cv;
using namespace cv::dynblur;
using cv::dynblur::detail::FrameSharpness;
using cv::dynblur::detail::measureSharpness;
using cv::dynblur::detail::ViewMotion;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kDeg = CV_PI / 180;

//! A frame's motion in both forms: the pipeline's view, and R(t) relative to the reference for the reference.
struct FrameMotion
{
    ViewMotion view;
    std::function<Matx33d(double)> rotation;
};

FrameMotion plantMotion(const Ptr<Plant>& plant, const SwitchSchedule& schedule)
{
    FrameMotion m;
    m.view.plant = plant;
    m.view.schedule = schedule;
    m.view.axis = Vec3d(1, 0, 0);
    m.view.thetaRef = plant->restingAngle(schedule.finalLevel());
    const double thetaRef = m.view.thetaRef;
    m.rotation = [plant, schedule, thetaRef](double t) {
        Mat time(1, 1, CV_64F, Scalar(t)), theta;
        plant->response(schedule, time, theta);
        const double a = theta.at<double>(0) - thetaRef, c = std::cos(a), s = std::sin(a);
        return Matx33d(1, 0, 0, 0, c, -s, 0, s, c);
    };
    return m;
}

FrameMotion measuredMotion(const Ptr<CameraMotion>& motion, const RollingShutter& shutter, double tRef = kNaN)
{
    FrameMotion m;
    m.view.motion = motion;
    m.view.reference = motion->referenceOrientation(tRef, shutter);
    const Matx33d reference = m.view.reference;
    m.rotation = [motion, reference](double t) { return Matx33d(reference.t() * motion->orientation(t)); };
    return m;
}

/* The definition computed densely through the public CameraModel::viewToReference: every 4th row
   and the last, every 8th column and the last, 129 instants of each row's exposure. */
std::pair<double, double> denseBlurAndShift(const CameraModel& camera, const RollingShutter& shutter,
                                            const std::function<Matx33d(double)>& rotation)
{
    const Size size = camera.getImageSize();
    const int instants = 129;
    double blur = 0, shift = 0;
    std::vector<Point2d> path(instants);
    for (int y = 0; y < size.height; y = y + 4 < size.height || y == size.height - 1 ? y + 4 : size.height - 1)
    {
        const Vec2d interval = shutter.intervalAt(y);
        std::vector<Matx33d> R(instants);
        for (int s = 0; s < instants; s++)
            R[size_t(s)] = rotation(interval[0] + (interval[1] - interval[0]) * s / (instants - 1));
        for (int x = 0; x < size.width; x = x + 8 < size.width || x == size.width - 1 ? x + 8 : size.width - 1)
        {
            Point2d mean(0, 0);
            for (int s = 0; s < instants; s++)
            {
                path[size_t(s)] = Point2d(x, y) - camera.viewToReference(Point2d(x, y), R[size_t(s)]);
                mean += path[size_t(s)] * ((s == 0 || s == instants - 1 ? 0.5 : 1.0) / (instants - 1));
            }
            for (int s = 0; s < instants; s++)
                for (int u = s + 1; u < instants; u++)
                    blur = std::max(blur, norm(path[size_t(s)] - path[size_t(u)]));
            shift = std::max(shift, norm(mean));
        }
    }
    return {blur, shift};
}

/* A 160×120 camera (f = 150 px), the seed's positioner and a 10° saccade, and a hand-held shake of
   up to 3 °/s: frames in their last moving instants. */
struct SmallRig
{
    Ptr<CameraModel> camera = CameraModel::create(150, 150, 79.5, 59.5, 160, 120);
    Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    SwitchSchedule schedule = SwitchPlanner::create(plant, 16)->plan(0.0, 10 * kDeg, 0.0);
    Ptr<CameraMotion> shake = dynblur_test::handShake(3.0);

    //! The last frame start (1 ms steps) before the saccade's frames are still throughout.
    RollingShutter lastMovingFrame(double lineDelay) const
    {
        RollingShutter shutter(0.0, 0.008, lineDelay, 120);
        while (classifyExposure(plant, schedule, shutter) != EXPOSURE_IV)
            shutter.frameStart += 0.001;
        shutter.frameStart -= 0.001;
        return shutter;
    }
};

}  // namespace

/* The grid measure against the definition computed densely: within 1/16 of the dense figure (what
   17 instants miss of a path at constant speed) plus 0.01 px, on a plant's frames during and at the
   end of a saccade and on a shaken camera's, rolling and global. */
TEST(FrameSharpness, MatchesADenseReference)
{
    const Ptr<CameraModel> camera = CameraModel::create(615, 615, 319.5, 239.5, 640, 480);
    const Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    const SwitchSchedule schedule = SwitchPlanner::create(plant, 16)->plan(0.0, 10 * kDeg, 0.0);
    const Ptr<CameraMotion> shake = dynblur_test::handShake(10.0);
    struct Case
    {
        const char* name;
        RollingShutter shutter;
        bool plant;
    };
    const Case cases[] = {
        {"plant, rolling, during the move", RollingShutter(0.004, 0.008, 1.0 / 30 / 480, 480), true},
        {"plant, global, at the end of the move", RollingShutter(0.0155, 0.008, 0.0, 480), true},
        {"plant, rolling, at the end of the move", RollingShutter(0.0150, 0.008, 1.0 / 30 / 480, 480), true},
        {"shake, rolling", RollingShutter(0.1, 0.010, 0.030 / 480, 480), false},
        {"shake, global", RollingShutter(0.1, 0.010, 0.0, 480), false},
    };
    for (const Case& c : cases)
    {
        const FrameMotion m = c.plant ? plantMotion(plant, schedule) : measuredMotion(shake, c.shutter);
        const FrameSharpness measured = measureSharpness(m.view, c.shutter, *camera);
        const auto [blur, shift] = denseBlurAndShift(*camera, c.shutter, m.rotation);
        std::printf("[ measured ] %s: blur %.4f px (dense %.4f), shift %.4f px (dense %.4f)\n", c.name,
                    measured.blurPx, blur, measured.shiftPx, shift);
        EXPECT_NEAR(measured.blurPx, blur, blur / 16 + 0.01) << c.name;
        EXPECT_NEAR(measured.shiftPx, shift, shift / 16 + 0.01) << c.name;
        EXPECT_GT(blur, 0.0) << c.name;
    }
}

/* A frame whose larger figure (blur or shift) is m passes the threshold 1.02·m as sharp and is
   deconvolved under 0.98·m and under 0 (no skip), for a plant's frame and a measured motion's,
   rolling and global: the sharp one is reported ("sharp:", applied, the figures), has no plan and
   no bank, and is the input itself when its shift is under 0.05 px. */
TEST(FrameSharpness, JustUnderAndJustOverTheThreshold)
{
    const SmallRig rig;
    Mat frame(120, 160, CV_8UC3);
    randu(frame, 0, 256);
    for (int measured = 0; measured < 2; measured++)
        for (double lineDelay : {0.030 / 120, 0.0})
        {
            const RollingShutter shutter =
                measured ? RollingShutter(0.1, 0.010, lineDelay, 120) : rig.lastMovingFrame(lineDelay);
            const FrameMotion m = measured ? measuredMotion(rig.shake, shutter) : plantMotion(rig.plant, rig.schedule);
            const FrameSharpness sharpness = measureSharpness(m.view, shutter, *rig.camera);
            const double larger = std::max(sharpness.blurPx, sharpness.shiftPx);
            const std::string what =
                std::string(measured ? "measured motion" : "plant") + (lineDelay > 0 ? ", rolling" : ", global");
            std::printf("[ measured ] %s: blur %.3f px, shift %.3f px\n", what.c_str(), sharpness.blurPx,
                        sharpness.shiftPx);
            ASSERT_GT(larger, 0.05) << what << ": the frame barely moves, the test proves little";
            ASSERT_LT(sharpness.blurPx, 1.0) << what << ": not a nearly sharp frame";
            for (double threshold : {1.02 * larger, 0.98 * larger, 0.0})
            {
                Ptr<DynamicDeblurrer> deblurrer =
                    measured ? DynamicDeblurrer::create(rig.camera) : DynamicDeblurrer::create(rig.plant, rig.camera);
                deblurrer->setSharpThreshold(threshold);
                Mat restored, valid;
                if (measured)
                    deblurrer->deblur(frame, rig.shake, shutter, restored, kNaN, valid);
                else
                    deblurrer->deblur(frame, rig.schedule, shutter, restored, kNaN, valid);
                const MotionCorrection c = deblurrer->getLastCorrection();
                const bool skipped = c.reason.rfind("sharp:", 0) == 0;
                EXPECT_EQ(skipped, threshold > larger) << what << ", threshold " << threshold << ": " << c.reason;
                EXPECT_TRUE(c.applied) << what << ": " << c.reason;
                EXPECT_EQ(deblurrer->getLastPsfBank().kernels.empty(), skipped) << what << ", threshold " << threshold;
                EXPECT_EQ(deblurrer->getLastPlan().bandStart.empty(), skipped) << what << ", threshold " << threshold;
                if (!skipped)
                    continue;
                EXPECT_NE(c.reason.find(format("blur %.2f px", sharpness.blurPx)), std::string::npos) << c.reason;
                EXPECT_NE(c.reason.find(format("shift %.2f px", sharpness.shiftPx)), std::string::npos) << c.reason;
                const bool untouched = norm(restored, frame, NORM_INF) == 0;
                EXPECT_EQ(untouched, sharpness.shiftPx < 0.05) << what << ": " << c.reason;
                EXPECT_EQ(c.reason.find("moved back") != std::string::npos, !untouched) << c.reason;
            }
        }
}

/* A sharp frame of a smooth pattern (periods of 12 px and more), a rolling shutter and a 0.1 ms
   exposure, each row the pattern where the view at that row's instant sees it, restored to a
   reference view up to 0.64 px from where the frame saw it: the rows are moved back to within a
   seventh of the error they had (measured 7.5×: cv::remap places its taps to 1/32 px, and the map
   itself is right to 0.002 px), in place as out of place, and where the frame never saw the view
   the pixels are black when marked. */
TEST(FrameSharpness, RowsMovedBackToTheReferenceView)
{
    const Ptr<CameraModel> camera = CameraModel::create(150, 150, 79.5, 59.5, 160, 120);
    const auto pattern = [](const Point2d& p) {
        const double v = 0.5 + 0.2 * std::sin(2 * CV_PI * p.x / 12) * std::cos(2 * CV_PI * p.y / 17) +
                         0.15 * std::sin(2 * CV_PI * (p.x + 2 * p.y) / 29);
        return Vec3f(float(v), float(0.9 * v), float(1.1 * v - 0.05));
    };
    // A slow tilt and pan (about 1 °/s): the rows turn by up to 0.3 px over the 30 ms readout.
    const Ptr<CameraMotion> pan = makePtr<dynblur_test::WaveMotion>(
        std::vector<dynblur_test::Wave>{{1.2 * kDeg / CV_PI, 0.5, 0.0}},
        std::vector<dynblur_test::Wave>{{0.8 * kDeg / CV_PI, 0.5, 0.3}}, std::vector<dynblur_test::Wave>{});
    const RollingShutter shutter(0.1, 1e-4, 0.030 / 120, 120);
    const double tRef = 0.26;
    const Matx33d reference = pan->orientation(tRef);
    Mat frame(120, 160, CV_32FC3), truth(120, 160, CV_32FC3);
    for (int y = 0; y < 120; y++)
    {
        const Vec2d interval = shutter.intervalAt(y);
        const Matx33d R = reference.t() * pan->orientation(0.5 * (interval[0] + interval[1]));
        for (int x = 0; x < 160; x++)
        {
            frame.at<Vec3f>(y, x) = pattern(camera->viewToReference(Point2d(x, y), R));
            truth.at<Vec3f>(y, x) = pattern(Point2d(x, y));
        }
    }
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(camera);
    Mat restored, valid;
    deblurrer->deblur(frame, pan, shutter, restored, tRef, valid);
    const std::string reason = deblurrer->getLastCorrection().reason;
    ASSERT_NE(reason.find("moved back"), std::string::npos) << reason;
    const Rect r(4, 4, 152, 112);
    ASSERT_EQ(countNonZero(valid(r)), r.area()) << "the frame saw the view away from its edges";
    const double before = norm(frame(r), truth(r), NORM_L2) / std::sqrt(3.0 * r.area()),
                 after = norm(restored(r), truth(r), NORM_L2) / std::sqrt(3.0 * r.area());
    std::printf("[ measured ] %s: RMS error against the reference view %.5f as recorded, %.5f moved back\n",
                reason.substr(0, reason.find(';')).c_str(), before, after);
    EXPECT_LT(after, before / 6.8);

    deblurrer->setUnobservedFill(UNOBSERVED_MARKED);
    Mat inPlace = frame.clone();
    deblurrer->deblur(inPlace, pan, shutter, inPlace, tRef);
    ASSERT_GT(countNonZero(valid == 0), 0) << "no unobserved pixel: the fill is not tested";
    EXPECT_EQ(norm(inPlace, restored, NORM_INF, valid), 0.0);
    EXPECT_EQ(norm(inPlace, NORM_INF, valid == 0), 0.0);
}

/* Rows whose displacements fold over one another cannot be moved back: a 50 Hz vibration of ±4 px
   read out over 120 ms (1 ms a row, so 1.3 px from row to row) in 0.05 ms exposures, sharp under a
   threshold of 9 px, is deconvolved as any frame. */
TEST(FrameSharpness, FoldedRowsAreDeconvolved)
{
    const SmallRig rig;
    const Ptr<CameraMotion> vibration = makePtr<dynblur_test::WaveMotion>(
        std::vector<dynblur_test::Wave>{{4.0 / 150, 50.0, 0.0}}, std::vector<dynblur_test::Wave>{},
        std::vector<dynblur_test::Wave>{});
    const RollingShutter shutter(0.1, 5e-5, 1e-3, 120);
    const FrameSharpness sharpness = measureSharpness(measuredMotion(vibration, shutter).view, shutter, *rig.camera);
    std::printf("[ measured ] blur %.3f px, shift %.2f px\n", sharpness.blurPx, sharpness.shiftPx);
    ASSERT_TRUE(sharpness.within(9.0));
    ASSERT_GT(sharpness.shiftPx, 0.05);
    Mat frame(120, 160, CV_8UC3), restored;
    randu(frame, 0, 256);
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(rig.camera);
    deblurrer->setSharpThreshold(9.0);
    deblurrer->deblur(frame, vibration, shutter, restored);
    EXPECT_EQ(deblurrer->getLastCorrection().reason.rfind("sharp", 0), std::string::npos)
        << deblurrer->getLastCorrection().reason;
    EXPECT_FALSE(deblurrer->getLastPsfBank().kernels.empty());
}

/* The threshold's default and range; a refused value leaves it as it was (BadInput.Deblurrer tries
   the refusals and their messages). */
TEST(FrameSharpness, ThresholdDefaultsToOnePixel)
{
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(CameraModel::create(150, 150, 79.5, 59.5, 160, 120));
    EXPECT_EQ(deblurrer->getSharpThreshold(), 1.0);
    EXPECT_THROW(deblurrer->setSharpThreshold(-0.5), cv::Exception);
    EXPECT_EQ(deblurrer->getSharpThreshold(), 1.0);
    deblurrer->setSharpThreshold(0.0);
    EXPECT_EQ(deblurrer->getSharpThreshold(), 0.0);
    deblurrer->setSharpThreshold(2.5);
    EXPECT_EQ(deblurrer->getSharpThreshold(), 2.5);
}
