// SPDX-License-Identifier: Apache-2.0
// Whether a frame is sharp: the measure against a dense reference.
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
