// SPDX-License-Identifier: Apache-2.0
// RollingShutter timing and the exposure windows I-IV, with a rolling and a global shutter.
#include "test_common.hpp"

#include <opencv2/dynblur.hpp>

using namespace cv;
using namespace cv::dynblur;

namespace {

const double kDeg = CV_PI / 180.0;

struct WindowFixture : public testing::TestWithParam<double /*lineDelay*/>
{
    // A well-damped plant and a single step: the move starts at 0 and is "still" from stillTime on.
    Ptr<Plant> plant = Plant::create(14.4, 0.7, kDeg);
    SwitchSchedule step = SwitchSchedule({0.0}, {10}, 0);
    double stillTime = 0;

    void SetUp() override
    {
        // The last instant the default tolerances call "moving", found by dense sampling.
        Mat t(1, 4001, CV_64F), theta, omega;
        for (int i = 0; i < t.cols; ++i)
            t.at<double>(i) = 0.4 * i / (t.cols - 1);
        plant->response(step, t, theta);
        plant->velocity(step, t, omega);
        for (int i = 0; i < t.cols; ++i)
            if (std::abs(theta.at<double>(i) - 10 * kDeg) > 2e-4 || std::abs(omega.at<double>(i)) > 0.02)
                stillTime = t.at<double>(i);
        ASSERT_GT(stillTime, 0.05);
        ASSERT_LT(stillTime, 0.35);
    }

    RollingShutter shutterAround(double frameStart) const
    {
        return RollingShutter(frameStart, 0.008, GetParam(), 960);
    }

    double readout() const { return shutterAround(0).readoutInterval()[1]; }
};

}  // namespace

TEST(ShutterTiming, RowIntervalsFollowTheLineDelay)
{
    RollingShutter shutter(0.025, 0.008, 62.5e-6, 480);
    const Vec2d first = shutter.rowInterval(0), last = shutter.rowInterval(479);
    EXPECT_DOUBLE_EQ(first[0], 0.025);
    EXPECT_DOUBLE_EQ(first[1], 0.033);
    EXPECT_NEAR(last[0], 0.025 + 479 * 62.5e-6, 1e-15);
    EXPECT_NEAR(shutter.readoutInterval()[1], 0.025 + 479 * 62.5e-6 + 0.008, 1e-15);
    RollingShutter global(0.0, 0.01, 0.0, 100);
    EXPECT_EQ(global.rowInterval(0), global.rowInterval(99));
}

TEST(ShutterTiming, FractionalRowsAndOverlappingRows)
{
    const RollingShutter shutter(0.025, 0.008, 62.5e-6, 480);
    for (int r : {0, 1, 240, 479})
        EXPECT_EQ(shutter.intervalAt(r), shutter.rowInterval(r)) << "row " << r;
    const Vec2d a = shutter.intervalAt(10), b = shutter.intervalAt(11), mid = shutter.intervalAt(10.5);
    EXPECT_NEAR(mid[0], 0.5 * (a[0] + b[0]), 1e-15);
    EXPECT_NEAR(mid[1] - mid[0], 0.008, 1e-15);

    // every row whose exposure overlaps a span is in the range, and at most one more at each end
    for (const Vec2d& span : {Vec2d(0.0, 0.026), Vec2d(0.030, 0.0301), Vec2d(0.05, 0.06), Vec2d(0.1, 0.2)})
    {
        const Range rows = shutter.rowsOverlapping(span[0], span[1]);
        int first = -1, last = -1;
        for (int r = 0; r < shutter.rows; r++)
        {
            const Vec2d in = shutter.rowInterval(r);
            if (std::min(span[1], in[1]) > std::max(span[0], in[0]))
            {
                if (first < 0)
                    first = r;
                last = r;
            }
        }
        if (first < 0)
            continue;
        EXPECT_LE(rows.start, first);
        EXPECT_GE(rows.start, first - 1);
        EXPECT_GE(rows.end, last + 1);
        EXPECT_LE(rows.end, last + 2);
    }
    const RollingShutter global(0.0, 0.01, 0.0, 100);
    EXPECT_EQ(global.rowsOverlapping(0.002, 0.003), Range(0, 100));
}

TEST(ShutterBadInput, OutOfRangeFieldsAreNamed)
{
    EXPECT_THROW(RollingShutter(0, 0.008, 0, 0).validate(), cv::Exception);
    EXPECT_THROW(RollingShutter(0, -0.001, 0, 10).validate(), cv::Exception);
    EXPECT_THROW(RollingShutter(0, 0.008, -1e-6, 10).validate(), cv::Exception);
    EXPECT_THROW(RollingShutter(std::nan(""), 0.008, 0, 10).validate(), cv::Exception);
    EXPECT_THROW(RollingShutter(0, 0.008, 0, 10).rowInterval(10), cv::Exception);
    EXPECT_THROW(RollingShutter(0, 0.008, 0, 10).rowInterval(-1), cv::Exception);
    try
    {
        RollingShutter(0, 0.008, -1.0, 10).validate();
        FAIL();
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(e.err.find("lineDelay"), std::string::npos) << e.err;
    }
    Ptr<Plant> plant = Plant::create();
    SwitchSchedule step({0.0}, {10});
    EXPECT_THROW(classifyExposure(Ptr<Plant>(), step, RollingShutter()), cv::Exception);
    EXPECT_THROW(classifyExposure(plant, step, RollingShutter(), 0.0), cv::Exception);
    EXPECT_THROW(classifyExposure(plant, step, RollingShutter(), 1e-4, -1.0), cv::Exception);
    EXPECT_THROW(classifyExposure(plant, SwitchSchedule({0.0, 0.0}, {1, 2}), RollingShutter()), cv::Exception);
}

TEST_P(WindowFixture, BeforeTheMoveIsStill)
{
    EXPECT_EQ(classifyExposure(plant, step, shutterAround(-1.0)), EXPOSURE_IV);
}

TEST_P(WindowFixture, LongAfterTheMoveIsStill)
{
    EXPECT_EQ(classifyExposure(plant, step, shutterAround(stillTime + 0.001)), EXPOSURE_IV);
}

TEST_P(WindowFixture, StillThenMovingIsWindowI)
{
    EXPECT_EQ(classifyExposure(plant, step, shutterAround(-readout() / 2)), EXPOSURE_I);
}

TEST_P(WindowFixture, MovingThroughoutIsWindowII)
{
    EXPECT_EQ(classifyExposure(plant, step, shutterAround(0.002)), EXPOSURE_II);
}

TEST_P(WindowFixture, MovingThenStillIsWindowIII)
{
    EXPECT_EQ(classifyExposure(plant, step, shutterAround(stillTime - readout() / 2)), EXPOSURE_III);
}

TEST_P(WindowFixture, AMoveInsideOneReadoutIsWindowI)
{
    // A fast plant whose whole move fits inside a 0.5 s exposure.
    Ptr<Plant> fast = Plant::create(100.0, 0.8, kDeg);
    RollingShutter longFrame(-0.1, 0.5, GetParam(), 960);
    EXPECT_EQ(classifyExposure(fast, step, longFrame), EXPOSURE_I);
}

TEST_P(WindowFixture, ARecordingsScheduleRestsBetweenItsMoves)
{
    // A recording's schedule holds its log's earlier lines and moves; the plant rests between them.
    const SwitchSchedule logged({-1.0, 0.0, 1.0}, {0, 10, 0}, 0);
    EXPECT_EQ(classifyExposure(plant, logged, shutterAround(-0.5)), EXPOSURE_IV);
    EXPECT_EQ(classifyExposure(plant, logged, shutterAround(-readout() / 2)), EXPOSURE_I);
    EXPECT_EQ(classifyExposure(plant, logged, shutterAround(stillTime - readout() / 2)), EXPOSURE_III);
    EXPECT_EQ(classifyExposure(plant, logged, shutterAround(0.7)), EXPOSURE_IV);
    EXPECT_EQ(classifyExposure(plant, logged, shutterAround(1.0 - readout() / 2)), EXPOSURE_I);
    EXPECT_EQ(classifyExposure(plant, logged, shutterAround(1.002)), EXPOSURE_II);
}

TEST_P(WindowFixture, AnEmptyScheduleIsStill)
{
    EXPECT_EQ(classifyExposure(plant, SwitchSchedule(), shutterAround(0.0)), EXPOSURE_IV);
}

INSTANTIATE_TEST_SUITE_P(RollingAndGlobal, WindowFixture, testing::Values(34.7e-6, 0.0),
                         [](const testing::TestParamInfo<double>& info) {
                             return info.param > 0 ? std::string("Rolling") : std::string("Global");
                         });
