// SPDX-License-Identifier: Apache-2.0
// Blur of any camera rotation (CameraMotion): the one-axis path through fromPlant, and 3-axis
// motions through the PSF generator and the forward model.
#include "rotation_motion.hpp"
#include "test_common.hpp"

#include <gtest/gtest.h>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>

using namespace cv;
using namespace cv::dynblur;
using dynblur_test::handShake;

namespace {

Ptr<Plant> seedPlant() { return Plant::create(14.4, 0.12, CV_PI / 180.0); }
SwitchSchedule saccade() { return SwitchSchedule({0.0, 0.0127, 0.0296}, {16, 4, 10}, 0); }

bool sameBank(const PsfBank& a, const PsfBank& b)
{
    if (a.model != b.model || a.nodeRows != b.nodeRows || a.nodeCols != b.nodeCols || a.shifts != b.shifts ||
        a.kernels.size() != b.kernels.size())
        return false;
    for (size_t i = 0; i < a.kernels.size(); i++)
        if (a.kernels[i].size() != b.kernels[i].size() || norm(a.kernels[i], b.kernels[i], NORM_INF) != 0)
            return false;
    return true;
}

//! A grid of unit points (CV_32F), `margin` pixels from the edges, corners included.
Mat pointGrid(Size size, int cols, int rows, int margin, std::vector<Point>& points)
{
    Mat image(size, CV_32F, Scalar(0));
    for (int j = 0; j < rows; j++)
        for (int i = 0; i < cols; i++)
        {
            const Point p(margin + (size.width - 1 - 2 * margin) * i / (cols - 1),
                          margin + (size.height - 1 - 2 * margin) * j / (rows - 1));
            image.at<float>(p) = 1.0f;
            points.push_back(p);
        }
    return image;
}

//! Centroid of `image` inside `window`, pixels; `mass` receives its sum.
Point2d centroid(const Mat& image, const Rect& window, double& mass)
{
    const Moments m = moments(image(window));
    mass = m.m00;
    return Point2d(window.x + m.m10 / m.m00, window.y + m.m01 / m.m00);
}

}  // namespace

TEST(RotationBlur, FromPlantIsTheOneAxisPathToTheBit)
{
    Ptr<CameraModel> camera = CameraModel::create(615, 615, 159.5, 119.5, 320, 240);
    Mat sharp(240, 320, CV_32FC3);
    randu(sharp, 0, 1);
    GaussianBlur(sharp, sharp, Size(0, 0), 2.0);
    const Ptr<CameraMotion> motion = CameraMotion::fromPlant(seedPlant(), saccade());
    EXPECT_TRUE(motion->isPlantMotion());
    Ptr<PsfGenerator> plantGenerator = PsfGenerator::create(seedPlant(), camera);
    Ptr<PsfGenerator> motionGenerator = PsfGenerator::create(camera);
    Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(seedPlant(), camera);  // an equal plant
    for (double frameStart : {-0.02, 0.004})
        for (double lineDelay : {125e-6, 0.0})
        {
            const RollingShutter shutter(frameStart, 0.008, lineDelay, 240);
            SCOPED_TRACE(cv::format("frameStart %g s, lineDelay %g s", frameStart, lineDelay));
            EXPECT_EQ(classifyExposure(motion, shutter), classifyExposure(seedPlant(), saccade(), shutter));
            for (int model : {PSF_UNIFORM, PSF_ROWS, PSF_TILES})
                EXPECT_TRUE(sameBank(motionGenerator->generate(model, motion, shutter),
                                     plantGenerator->generate(model, saccade(), shutter)))
                    << "model " << model;
            // A reference time: the view at θ(tRef).
            Mat theta;
            seedPlant()->response(saccade(), Mat(1, 1, CV_64F, Scalar(0.01)), theta);
            EXPECT_TRUE(sameBank(motionGenerator->generate(PSF_ROWS, motion, shutter, 0.01),
                                 plantGenerator->generate(PSF_ROWS, saccade(), shutter, theta.at<double>(0))));
            Mat fromMotion, fromPlant;
            renderBlurred(sharp, motion, camera, shutter, fromMotion);
            renderBlurred(sharp, seedPlant(), saccade(), camera, shutter, fromPlant);
            EXPECT_EQ(norm(fromMotion, fromPlant, NORM_INF), 0.0);
            Mat restoredFromMotion, restoredFromPlant;
            deblurrer->deblur(fromPlant, motion, shutter, restoredFromMotion);
            deblurrer->deblur(fromPlant, saccade(), shutter, restoredFromPlant);
            EXPECT_EQ(norm(restoredFromMotion, restoredFromPlant, NORM_INF), 0.0);
        }
}

TEST(RotationBlur, ThreeAxisPointSourcesMatchTheRendererEverywhere)
{
    // 640×480 at f = 600 px (a 56° field of view: the corners turn most differently from the
    // centre), shakes of 30 and 120 °/s about every axis, rolling readout of 30 ms or a global
    // shutter, 20 ms exposure.
    const Size size(640, 480);
    Ptr<CameraModel> camera = CameraModel::create(600, 600, 319.5, 239.5, size.width, size.height);
    std::vector<Point> points;
    const Mat latent = pointGrid(size, 5, 4, 24, points);
    for (double peakRate : {30.0, 120.0})
    for (double lineDelay : {0.030 / 480, 0.0})
    {
        const Ptr<dynblur_test::WaveMotion> shake = handShake(peakRate);
        double worst = 0;
        const RollingShutter shutter(0.1, 0.020, lineDelay, size.height);
        Mat rendered, predicted;
        Mat latent64;
        latent.convertTo(latent64, CV_64F);
        renderBlurred(latent64, shake, camera, shutter, rendered, NAN, 0.1, BORDER_CONSTANT);
        Ptr<PsfGenerator> generator = PsfGenerator::create(camera);
        generator->setTileGrid(Size(32, 0));
        const PsfBank bank = generator->generate(PSF_TILES, shake, shutter);
        applyPsfBank(latent, bank, predicted);
        predicted.convertTo(predicted, CV_64F);
        double longest = 0;
        for (const Mat& k : bank.kernels)
            longest = std::max(longest, double(std::max(k.cols, k.rows)));
        int checked = 0;
        for (const Point& q : points)
        {
            // The spot lies within the kernels' reach of q plus the view's turn from the reference.
            const Rect window = Rect(q.x - 70, q.y - 70, 141, 141) & Rect(Point(0, 0), size);
            double massRendered, massPredicted;
            const Point2d a = centroid(rendered, window, massRendered);
            const Point2d b = centroid(predicted, window, massPredicted);
            if (massRendered < 0.5)
                continue;  // most of the spot left the frame
            checked++;
            const double error = norm(a - b);
            worst = std::max(worst, error);
            EXPECT_LT(error, 0.25) << "point " << q << ", line delay " << lineDelay;
            EXPECT_NEAR(massPredicted, massRendered, 0.02) << "point " << q;
        }
        std::printf("[ measured ] 3-axis shake of %.0f deg/s, %s shutter: %d point sources, longest kernel %.0f px, "
                    "worst centroid difference renderer vs PSF tiles %.3f px\n",
                    peakRate, lineDelay > 0 ? "rolling" : "global", checked, longest, worst);
        EXPECT_GE(checked, 18);
        EXPECT_GE(longest, peakRate / 4) << "the shake must blur";
    }
}

TEST(RotationBlur, ClassifiesSampledMotionByItsRate)
{
    const Ptr<dynblur_test::WaveMotion> shake = handShake(40);
    EXPECT_EQ(classifyExposure(shake, RollingShutter(0.1, 0.02, 62.5e-6, 480)), EXPOSURE_II);
    EXPECT_EQ(classifyExposure(CameraMotion::fromPlant(seedPlant(), saccade()), RollingShutter(1.0, 0.008, 0, 480)),
              EXPOSURE_IV);
    dynblur_test::expectErrorNaming(
        [&] { classifyExposure(shake, RollingShutter(0.99, 0.02, 62.5e-6, 480)); }, "time span");
}

TEST(RotationBlur, BadMotionArgumentsNameTheArgument)
{
    Ptr<CameraModel> camera = CameraModel::create(600, 600, 319.5, 239.5, 640, 480);
    const Ptr<dynblur_test::WaveMotion> shake = handShake(40);
    const RollingShutter shutter(0.1, 0.02, 62.5e-6, 480);
    Ptr<PsfGenerator> plantless = PsfGenerator::create(camera);
    dynblur_test::expectErrorNaming([&] { plantless->generate(PSF_ROWS, saccade(), shutter); }, "without a plant");
    dynblur_test::expectErrorNaming([&] { plantless->generate(PSF_ROWS, Ptr<CameraMotion>(), shutter); }, "motion");
    dynblur_test::expectErrorNaming([&] { plantless->generate(PSF_ROWS, shake, shutter, INFINITY); }, "tRef");
    dynblur_test::expectErrorNaming(
        [&] { plantless->generate(PSF_ROWS, shake, RollingShutter(0.98, 0.02, 62.5e-6, 480)); }, "time span");
    Mat out, sharp(480, 640, CV_32F, Scalar(0.5));
    dynblur_test::expectErrorNaming(
        [&] { renderBlurred(sharp, shake, camera, RollingShutter(-1.5, 0.02, 62.5e-6, 480), out); }, "time span");
    dynblur_test::expectErrorNaming([&] { CameraMotion::fromPlant(seedPlant(), saccade(), Vec3d(0, 0, 0)); }, "axis");
    dynblur_test::expectErrorNaming([&] { CameraMotion::fromPlant(Ptr<Plant>(), saccade()); }, "plant");
    dynblur_test::expectErrorNaming(
        [&] { camera->viewToReference(Mat(1, 1, CV_64FC2, Scalar(1, 1)), Matx33d(1, 0, 0, 0, 1, 0, 0, 0, -1), out); },
        "rotation");
}
