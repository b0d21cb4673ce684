// SPDX-License-Identifier: Apache-2.0
// Mount: a chain of plant-driven axes (a pan-tilt head). Its orientation and body rates against
// numerical derivatives, pointing and its inverse, one axis against fromPlant, a pan-tilt move
// restored, and bad input.
#include "image_metrics.hpp"
#include "pan_tilt.hpp"
#include "shake_scene.hpp"
#include "test_common.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/dynblur.hpp>

#include <cstdio>
#include <functional>

using namespace cv;
using namespace cv::dynblur;
using dynblur_samples::maskedPsnr;
using dynblur_test::panTilt;
using dynblur_test::plannedMoves;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

double rotationDistance(const Matx33d& a, const Matx33d& b)
{
    Mat rvec;
    Rodrigues(Mat(a.t() * b), rvec);
    return norm(rvec);
}

}  // namespace

/* Q(t) is the chain's product at the plants' responses, and ω(t) its body rate Qᵀ·dQ/dt (central
   differences of 1 µs, away from the switches, where θ'' jumps) during a simultaneous pan and tilt. */
TEST(Mount, MotionIsTheChainAndItsBodyRate)
{
    Ptr<Mount> mount = panTilt();
    const std::vector<SwitchSchedule> schedules = plannedMoves(mount, {-10, 4}, {12, -6}, 0.1);
    Ptr<CameraMotion> motion = mount->motion(schedules);
    double worstRate = 0, peakRate = 0;
    for (double t = 0.1; t < 0.3; t += 0.0037)
    {
        bool nearSwitch = false;
        for (const SwitchSchedule& schedule : schedules)
            for (double switchTime : schedule.times)
                nearSwitch = nearSwitch || std::abs(t - switchTime) < 1e-5;
        if (nearSwitch)
            continue;
        std::vector<double> q(2);
        for (int i = 0; i < 2; i++)
        {
            Mat theta;
            mount->getPlant(i)->response(schedules[size_t(i)], Mat(1, 1, CV_64F, &t), theta);
            q[size_t(i)] = theta.at<double>(0);
        }
        EXPECT_LT(rotationDistance(motion->orientation(t), mount->orientation(q)), 1e-12);
        const double h = 1e-6;
        const Matx33d derivative = (motion->orientation(t + h) - motion->orientation(t - h)) * (1 / (2 * h));
        const Matx33d skew = motion->orientation(t).t() * derivative;
        const Vec3d numeric(skew(2, 1), skew(0, 2), skew(1, 0));
        worstRate = std::max(worstRate, norm(numeric - motion->angularVelocity(t)));
        peakRate = std::max(peakRate, norm(motion->angularVelocity(t)));
    }
    std::printf("[ measured ] pan-tilt move: body rate against Q^T dQ/dt, worst %.2e rad/s of a peak %.3f rad/s\n",
                worstRate, peakRate);
    EXPECT_GT(peakRate, 0.5);
    EXPECT_LT(worstRate, 1e-6);
    // At rest after the move: the reference view is the chain at both final resting angles.
    const Matx33d rest = motion->referenceOrientation(kNaN, RollingShutter(0, 0.01, 0, 480));
    EXPECT_LT(rotationDistance(rest, mount->orientation({mount->getPlant(0)->restingAngle(schedules[0].finalLevel()),
                                                         mount->getPlant(1)->restingAngle(schedules[1].finalLevel())})),
              1e-12);
    EXPECT_LT(rotationDistance(rest, motion->orientation(2.0)), 1e-6);
}

// A mount of one axis moves as fromPlant about that axis, and classifies its frames the same.
TEST(Mount, OneAxisIsThePlantsMotion)
{
    Ptr<Plant> plant = Plant::create();
    Ptr<Mount> mount = Mount::create();
    mount->addAxis(Vec3d(2, 0, 0), plant, -100, 100);
    const SwitchSchedule schedule = SwitchPlanner::create(plant, 100)->plan(0, 10 * CV_PI / 180, 0.05);
    Ptr<CameraMotion> byMount = mount->motion({schedule}), byPlant = CameraMotion::fromPlant(plant, schedule);
    EXPECT_FALSE(byMount->isPlantMotion());
    for (double t = 0; t < 0.4; t += 0.011)
    {
        EXPECT_LT(rotationDistance(byMount->orientation(t), byPlant->orientation(t)), 1e-12);
        EXPECT_LT(norm(byMount->angularVelocity(t) - byPlant->angularVelocity(t)), 1e-12);
    }
    for (double start : {0.03, 0.08, 0.2, 0.5})
    {
        const RollingShutter shutter(start, 0.008, 1.0 / 30 / 480, 480);
        EXPECT_EQ(classifyExposure(byMount, shutter) == EXPOSURE_IV, classifyExposure(byPlant, shutter) == EXPOSURE_IV)
            << start;
    }
}

/* anglesFor inverts pointing for directions across the head's reach, and returns the solution
   nearest the angles held; a direction out of reach is refused naming the ranges. */
TEST(Mount, AnglesForPointsTheOpticalAxis)
{
    Ptr<Mount> mount = panTilt();
    double worst = 0;
    for (double pan = -35; pan <= 35; pan += 7)
        for (double tilt = -25; tilt <= 25; tilt += 5)
        {
            const std::vector<double> target = {pan * CV_PI / 180, tilt * CV_PI / 180};
            const std::vector<double> found = mount->anglesFor(mount->pointing(target), {0, 0});
            worst = std::max(worst, norm(mount->pointing(found) - mount->pointing(target)));
            EXPECT_NEAR(found[0], target[0], 1e-9);
            EXPECT_NEAR(found[1], target[1], 1e-9);
        }
    EXPECT_LT(worst, 1e-12);
    // Straight up (−y) needs a tilt of 90°, beyond the tilt's 30°.
    try
    {
        mount->anglesFor(Vec3d(0, -1, 0));
        ADD_FAILURE() << "no error";
    }
    catch (const cv::Exception& e)
    {
        EXPECT_NE(std::string(e.what()).find("axis 1: [-0.5236, 0.5236] rad (levels -120 to 120)"), std::string::npos)
            << e.what();
    }
    // A roll carried by the tilt does not change where the camera points; it keeps its angle.
    mount->addAxis(Vec3d(0, 0, 1), Plant::create(), -50, 50);
    const std::vector<double> withRoll = mount->anglesFor(Vec3d(0.3, 0.1, 1), {0.1, 0.0, 0.05});
    EXPECT_DOUBLE_EQ(withRoll[2], 0.05);
    EXPECT_LT(norm(mount->pointing(withRoll) - Vec3d(0.3, 0.1, 1) * (1 / norm(Vec3d(0.3, 0.1, 1)))), 1e-12);
}

/* A simultaneous pan and tilt of a rolling-shutter webcam, ending at the scene's view: the frame
   restored from the mount's motion by the default (tiles), against the seed's single PSF (the
   centre's kernel), three images. */
TEST(Mount, PanTiltFrameRestoredBeyondTheSeedsSinglePsf)
{
    Ptr<Mount> mount = panTilt();
    const std::vector<SwitchSchedule> schedules = plannedMoves(mount, {-5, 4}, {0, 0}, 0.0);
    Ptr<CameraMotion> motion = mount->motion(schedules);
    // The first frame start (1 ms steps) whose frame sees the head come to rest: window III.
    RollingShutter shutter(0.0, 0.010, 0.030 / 480, 480);
    while (classifyExposure(motion, shutter) != EXPOSURE_III && shutter.frameStart < 0.5)
        shutter.frameStart += 0.001;
    ASSERT_EQ(classifyExposure(motion, shutter), EXPOSURE_III);
    double worstOverUniform = 1e9;
    for (const char* name : {"building.jpg", "fruits.jpg", "baboon.jpg"})
    {
        DYNBLUR_REQUIRE_DATA(path, name);
        dynblur_test::ShakeScene scene(path, 1.0);
        scene.motion = motion;  // its reference view (NaN: the final rest) is the scene's, Q = I
        const Mat frame = scene.capture(shutter, 3);
        Mat judged(480, 640, CV_8U, Scalar(0));
        judged(Rect(16, 16, 640 - 32, 480 - 32)).setTo(255);
        Mat restored[2];
        for (int k = 0; k < 2; k++)
        {
            Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(scene.camera);
            if (k == 0)
                deblurrer->setPsfModel(PSF_UNIFORM);
            Mat valid;
            deblurrer->deblur(frame, motion, shutter, restored[k], kNaN, valid);
            judged &= valid;
        }
        const double b = maskedPsnr(scene.truth, frame, judged, 255),
                     u = maskedPsnr(scene.truth, restored[0], judged, 255),
                     v = maskedPsnr(scene.truth, restored[1], judged, 255);
        std::printf("[ measured ] pan-tilt move (pan 5 deg, tilt 4 deg) ending in a rolling 10 ms frame at %.0f ms, "
                    "%s: blurred %.2f dB, seed uniform %.2f dB, default %.2f dB\n",
                    shutter.frameStart * 1e3, name, b, u, v);
        worstOverUniform = std::min(worstOverUniform, v - u);
    }
    // Measured: 3.28 dB at worst (fruits), up to 5.75 (building).
    EXPECT_GE(worstOverUniform, 3.1);
}

TEST(MountBadInput, ArgumentsAreCheckedAndNamed)
{
    Ptr<Mount> mount = Mount::create();
    const auto expectError = [](const std::function<void()>& call, const char* text) {
        try
        {
            call();
            ADD_FAILURE() << "no error for " << text;
        }
        catch (const cv::Exception& e)
        {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
    };
    expectError([&] { mount->pointing({}); }, "the mount has no axis");
    expectError([&] { mount->addAxis(Vec3d(0, 0, 0), Plant::create(), 0, 1); }, "axis (0, 0, 0) must be a finite non-zero");
    expectError([&] { mount->addAxis(Vec3d(1, 0, 0), Ptr<Plant>(), 0, 1); }, "plant is empty");
    expectError([&] { mount->addAxis(Vec3d(1, 0, 0), Plant::create(), 5, 1); }, "minLevel = 5 must be <= maxLevel = 1");
    mount->addAxis(Vec3d(0, 1, 0), Plant::create(), -10, 10);
    expectError([&] { mount->addAxis(Vec3d(0, -2, 1e-7), Plant::create(), -10, 10); },
                "axis (0, -2, 1e-07) is parallel to axis 0 (0, 1, 0) within 1e-6 rad");
    mount->addAxis(Vec3d(1, 0, 0), Plant::create(), -10, 10);
    expectError([&] { mount->addAxis(Vec3d(0, 1, 1e-7), Plant::create(), -10, 10); }, "is parallel to axis 0");
    expectError([&] { mount->orientation({0.1}); }, "angles has 1 values for 2 axes");
    expectError([&] { mount->pointing({0.1, kNaN}); }, "angles[1] = nan must be finite");
    expectError([&] { mount->getAxis(2); }, "index = 2 must be in [0, 2)");
    expectError([&] { mount->anglesFor(Vec3d(0, 0, 0)); }, "direction (0, 0, 0) must be a finite non-zero");
    expectError([&] { mount->anglesFor(Vec3d(0, 0, 1), {0, 0, 0}); }, "current has 3 values for 2 axes");
    SwitchSchedule far;
    far.times = {0.0};
    far.levels = {11};
    expectError([&] { mount->motion({far}); }, "1 schedules given for 2 axes");
    expectError([&] { mount->motion({far, far}); }, "schedules[0] takes level 11, outside axis 0's range [-10, 10]");
}
