// SPDX-License-Identifier: Apache-2.0
// MountPlanner: a diagonal saccade of a pan-tilt head, coordinated against independent; robustness to
// an ωn error on either axis; pointing at a direction and a pixel; bad input refused.
#include <gtest/gtest.h>

#include <opencv2/dynblur.hpp>

#include "pan_tilt.hpp"
#include "test_common.hpp"

#include <cstdio>

using namespace cv;
using namespace cv::dynblur;
using dynblur_test::seedPanTilt;

namespace {

const double kDeg = CV_PI / 180;

//! The settle time of the slower of the two axes' own fastest moves, s.
double slowerSingleAxisSettle(const Ptr<Mount>& mount, int mode, const std::vector<double>& to)
{
    double slower = 0;
    for (int i = 0; i < 2; i++)
    {
        const Ptr<SwitchPlanner> planner = SwitchPlanner::create(mount->getPlant(i), 16, mode);
        slower = std::max(slower, planner->plan(0, to[size_t(i)]).settleTime);
    }
    return slower;
}

struct SaccadeCase
{
    const char* name;
    double tiltHz;
    int mode;
    double maxPathDeviationDeg;  //!< the coordinated path's floor, ~10 % above the measured figure
};

}  // namespace

// Figures: docs/quality.md, "A move of several axes".
TEST(MountPlannerFigures, DiagonalSaccadeArrivesTogetherAlongAStraighterPath)
{
    const std::vector<double> to = {10 * kDeg, 6 * kDeg};
    // Measured path deviations: 0.039, 0.346, 0.050 and 1.148 deg (independent: 1.54, 2.93, 1.51, 2.66 deg).
    const SaccadeCase cases[] = {{"14.4/14.4 Hz fast", 14.4, PLAN_FAST, 0.043},
                                 {"14.4/20 Hz fast", 20.0, PLAN_FAST, 0.38},
                                 {"14.4/14.4 Hz robust", 14.4, PLAN_ROBUST, 0.055},
                                 {"14.4/20 Hz robust", 20.0, PLAN_ROBUST, 1.27}};
    for (const SaccadeCase& c : cases)
    {
        SCOPED_TRACE(c.name);
        const Ptr<Mount> mount = seedPanTilt(14.4, c.tiltHz);
        const MountMove together = MountPlanner::create(mount, c.mode)->plan({0, 0}, to);
        const MountMove apart = MountPlanner::create(mount, c.mode, 0.002, MOUNT_INDEPENDENT)->plan({0, 0}, to);
        const double slower = slowerSingleAxisSettle(mount, c.mode, to);
        double worstDetuned = 0;
        for (size_t i = 0; i < 2; i++)
            for (double scale : {0.9, 1.1})
            {
                const double hz = scale * mount->getPlant(int(i))->getNaturalFreqHz();
                worstDetuned = std::max(worstDetuned, residualVibration(together.schedules[i], hz, 0.12));
            }
        std::printf("[ measured ] 10 deg pan + 6 deg tilt, %s: coordinated settle %.1f ms (axes %.1f, %.1f; slower "
                    "single axis %.1f), residual %.2g / %.2g, worst at +-10%% wn %.2f %%, path off its great circle "
                    "%.3f deg (independent %.3f deg), peak |w| %.0f deg/s (independent %.0f)\n",
                    c.name, together.settleTime * 1e3, together.axisSettleTimes[0] * 1e3,
                    together.axisSettleTimes[1] * 1e3, slower * 1e3, together.residualVibration[0],
                    together.residualVibration[1], worstDetuned * 100, together.pathDeviation / kDeg,
                    apart.pathDeviation / kDeg, together.peakRate / kDeg, apart.peakRate / kDeg);
        for (size_t i = 0; i < 2; i++)
            EXPECT_LE(together.residualVibration[i], 0.01) << "axis " << i;
        EXPECT_LE(together.settleTime, 1.10 * slower);
        if (c.mode == PLAN_ROBUST)
        {
            EXPECT_LE(worstDetuned, 0.03);
        }
        EXPECT_LE(together.pathDeviation, c.maxPathDeviationDeg * kDeg);
        EXPECT_LE(together.pathDeviation, 0.5 * apart.pathDeviation);
        EXPECT_NEAR(together.toAngles[0], to[0], 1e-12);
        EXPECT_NEAR(together.toAngles[1], to[1], 1e-12);
    }
}

TEST(MountPlanner, PointsAtADirectionAndAPixel)
{
    const Ptr<Mount> mount = seedPanTilt(14.4, 14.4);
    const Ptr<MountPlanner> planner = MountPlanner::create(mount);
    const std::vector<double> from = {2 * kDeg, -3 * kDeg};
    const std::vector<double> target = {-7 * kDeg, 5 * kDeg};
    const MountMove toDirection = planner->planToDirection(mount->pointing(target), from, 0.1);
    EXPECT_NEAR(toDirection.toAngles[0], target[0], 1e-9);
    EXPECT_NEAR(toDirection.toAngles[1], target[1], 1e-9);
    EXPECT_DOUBLE_EQ(toDirection.schedules[0].times.front(), 0.1);

    // The pixel the target direction is seen at now: the move brings it to the optical axis.
    const Ptr<CameraModel> camera = CameraModel::create(615, 615, 319.5, 239.5, 640, 480);
    const Vec3d seen = mount->orientation(from).t() * mount->pointing(target);
    const Point2d pixel = camera->normalizedToPixel(Point2d(seen[0] / seen[2], seen[1] / seen[2]));
    const MountMove toPixel = planner->planToPixel(camera, pixel, from);
    EXPECT_NEAR(toPixel.toAngles[0], target[0], 1e-9);
    EXPECT_NEAR(toPixel.toAngles[1], target[1], 1e-9);

    // An axis that holds still gets a one-switch schedule to its own level.
    const MountMove panOnly = planner->plan({0, 3 * kDeg}, {5 * kDeg, 3 * kDeg});
    EXPECT_EQ(panOnly.schedules[1].levels, std::vector<int>{3});
    EXPECT_EQ(panOnly.axisSettleTimes[1], 0.0);
    EXPECT_GT(panOnly.axisSettleTimes[0], 0.0);
    EXPECT_EQ(panOnly.settleTime, panOnly.axisSettleTimes[0]);
}

TEST(MountPlanner, OneAxisMoveIsTheSwitchPlanners)
{
    const Ptr<Mount> mount = seedPanTilt(14.4, 20.0);
    const MountMove move = MountPlanner::create(mount)->plan({0, 0}, {0, 6 * kDeg});
    const SwitchSchedule alone = SwitchPlanner::create(mount->getPlant(1), 16)->plan(0, 6 * kDeg);
    EXPECT_EQ(move.schedules[1].levels, alone.levels);
    EXPECT_EQ(move.schedules[1].times, alone.times);
    EXPECT_EQ(move.settleTime, alone.settleTime);
}

TEST(MountPlannerBadInput, ArgumentsAreCheckedAndNamed)
{
    using dynblur_test::expectErrorNaming;
    const Ptr<Mount> mount = seedPanTilt(14.4, 14.4);
    const Ptr<MountPlanner> planner = MountPlanner::create(mount);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    expectErrorNaming([&] { planner->plan({0, 0}, {0, 20 * kDeg}); },
                      "toAngles[1] = 0.349066 rad (20 deg) is outside axis 1's range [-0.279253, 0.279253] rad");
    expectErrorNaming([&] { planner->plan({-17 * kDeg, 0}, {0, 0}); }, "fromAngles[0]");
    expectErrorNaming([&] { planner->plan({0}, {0, 0}); }, "fromAngles has 1 values for 2 axes");
    expectErrorNaming([&] { planner->plan({0, 0}, {0, 0, 0}); }, "toAngles has 3 values for 2 axes");
    expectErrorNaming([&] { planner->plan({0, nan}, {0, 0}); }, "fromAngles[1] = nan must be finite");
    expectErrorNaming([&] { planner->plan({0, 0}, {0, 0}, nan); }, "startTime = nan must be finite");
    expectErrorNaming([&] { planner->planToDirection(Vec3d(0, 0, -1), {0, 0}); }, "no joint angles the axes reach");
    expectErrorNaming([&] { planner->planToPixel(Ptr<CameraModel>(), Point2d(1, 1), {0, 0}); }, "camera is empty");
    const Ptr<CameraModel> camera = CameraModel::create(615, 615, 319.5, 239.5, 640, 480);
    expectErrorNaming([&] { planner->planToPixel(camera, Point2d(nan, 1), {0, 0}); }, "pixel (nan, 1) must be finite");
    expectErrorNaming([&] { MountPlanner::create(Ptr<Mount>()); }, "mount is empty");
    expectErrorNaming([&] { MountPlanner::create(Mount::create()); }, "the mount has no axis");
    expectErrorNaming([&] { MountPlanner::create(mount, 2); }, "mode = 2 must be PLAN_FAST (0) or PLAN_ROBUST (1)");
    expectErrorNaming([&] { MountPlanner::create(mount, PLAN_FAST, -1); }, "minDwell = -1 must be finite and >= 0");
    expectErrorNaming([&] { MountPlanner::create(mount, PLAN_FAST, 0.002, 5); }, "coordination = 5 must be");
    Ptr<Mount> oneSided = Mount::create();
    oneSided->addAxis(Vec3d(1, 0, 0), Plant::create(), 0, 16);
    expectErrorNaming([&] { MountPlanner::create(oneSided); }, "axis 0's level range [0, 16] must hold [-1, 1]");
}
