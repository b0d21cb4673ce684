// SPDX-License-Identifier: Apache-2.0
// The refinement's parameters as one table (refinementParameters): its flags agree with
// MotionRefinement, a command line's names read through it, and every flags check follows it.
#include "test_common.hpp"

#include <opencv2/dynblur.hpp>

using namespace cv;
using namespace cv::dynblur;
using dynblur_test::expectErrorNaming;

TEST(RefinementParameters, TableAgreesWithTheFlags)
{
    const std::vector<RefinementParameter> table = refinementParameters();
    ASSERT_EQ(table.size(), 12u);
    int all = 0, inAll = 0, plant = 0, measured = 0;
    for (const RefinementParameter& p : table)
    {
        SCOPED_TRACE(p.name);
        EXPECT_FALSE(p.name.empty());
        EXPECT_FALSE(p.key.empty());
        EXPECT_EQ(refinementFlags(p.key), p.flag);
        EXPECT_TRUE(p.plantMotion || p.mountMotion || p.measuredMotion);
        EXPECT_GE(p.searchHalfWidth, 0);
        all |= p.flag;
        inAll |= p.inRefineAll ? p.flag : 0;
        plant |= p.plantMotion ? p.flag : 0;
        measured |= p.measuredMotion ? p.flag : 0;
    }
    EXPECT_EQ(all, REFINE_ALL | REFINE_GYRO_BIAS | REFINE_RATE_SCALE);
    EXPECT_EQ(inAll, REFINE_ALL);
    EXPECT_EQ(plant, REFINE_ALL);
    EXPECT_EQ(measured, REFINE_TIME_OFFSET | REFINE_LINE_DELAY | REFINE_GYRO_BIAS | REFINE_RATE_SCALE);
    EXPECT_EQ(table[0].flagName, "REFINE_TIME_OFFSET");
    EXPECT_EQ(table[0].unit, "s");
    EXPECT_EQ(table[0].searchHalfWidth, 0);  // the caller's maxTimeOffset
    EXPECT_TRUE(table[1].rollingShutterOnly);
    EXPECT_NEAR(table[1].searchHalfWidth, 0.15, 1e-12);  // the line delay's ±15 %
    EXPECT_EQ(table[4].unit, "rad/s");
}

TEST(RefinementParameters, NamesReadAsFlags)
{
    EXPECT_EQ(refinementFlags("offset,line-delay"), REFINE_TIME_OFFSET | REFINE_LINE_DELAY);
    EXPECT_EQ(refinementFlags("all"), REFINE_ALL);
    EXPECT_EQ(refinementFlags("none"), REFINE_NONE);
    EXPECT_EQ(refinementFlags("offset,bias"), REFINE_TIME_OFFSET | REFINE_GYRO_BIAS);
    EXPECT_EQ(refinementFlags("plant,plant"), REFINE_PLANT);
    expectErrorNaming([] { refinementFlags("offest"); }, "'offest' in 'offest'");
    expectErrorNaming([] { refinementFlags("offset,"); }, "offset, line-delay, plant, bias, rate-scale, all or none");
}

TEST(RefinementParameters, FlagChecksFollowTheTable)
{
    const Ptr<CameraModel> camera = CameraModel::create(150, 150, 79.5, 59.5, 160, 120);
    const Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(Plant::create(14.4, 0.12, 0.01), camera);
    deblurrer->setRefinement(REFINE_ALL | REFINE_GYRO_BIAS | REFINE_RATE_SCALE);
    EXPECT_EQ(deblurrer->getRefinement(), 31);
    expectErrorNaming([&] { deblurrer->setRefinement(32); },
                      "flags = 32 must combine REFINE_TIME_OFFSET (1), REFINE_LINE_DELAY (2), REFINE_PLANT (4), "
                      "REFINE_GYRO_BIAS (8) and REFINE_RATE_SCALE (16): a value in [0, 31]");
    expectErrorNaming([&] { deblurrer->setRefinement(-1); }, "flags = -1");

    const Mat frame(120, 160, CV_32F, Scalar(0.5));
    const std::vector<Mat> two{frame, frame};
    const std::vector<RollingShutter> shutters(2, RollingShutter(0.1, 0.01, 0, 120));
    const Mat t = (Mat_<double>(3, 1) << 0, 0.5, 1), rates = Mat::zeros(3, 3, CV_64F);
    const Ptr<CameraMotion> motion = CameraMotion::fromAngularVelocity(t, rates);
    expectErrorNaming([&] { calibrateTiming(motion, camera, two, two, shutters, shutters, REFINE_PLANT); },
                      "flags = 4 must combine REFINE_TIME_OFFSET (1), REFINE_LINE_DELAY (2), REFINE_GYRO_BIAS (8) "
                      "and REFINE_RATE_SCALE (16), at least one of them (REFINE_PLANT (4) is ignored for this "
                      "motion): a value in [1, 31]");
    const SwitchSchedule schedule;
    expectErrorNaming(
        [&] {
            calibrateTiming(Plant::create(14.4, 0.12, 0.01), camera, two, two, {schedule, schedule}, shutters,
                            REFINE_GYRO_BIAS);
        },
        "flags = 8 must combine REFINE_TIME_OFFSET (1), REFINE_LINE_DELAY (2) and REFINE_PLANT (4), at least one of "
        "them: a value in [1, 7]");
}
