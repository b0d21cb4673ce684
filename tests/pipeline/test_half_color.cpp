// SPDX-License-Identifier: Apache-2.0
// DynamicDeblurrer's color phase at half resolution (DEBLUR_COLOR_HALF_RESOLUTION): the half-size
// camera and shutter, the fused upsampling, and what the deblurrer makes of them. Its quality
// figures are in DeblurQuality (test_deblurrer.cpp).
#include "test_common.hpp"

#include "restore/deconv_rl.hpp"
#include "pipeline/half_color.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgproc.hpp>

using namespace cv;
using namespace cv::dynblur;

namespace {

const double kDeg = CV_PI / 180.0;

//! Mean absolute difference of two CV_32F images over their interior (`border` pixels left out).
double interiorMeanError(const Mat& a, const Mat& b, int border)
{
    const Rect inner(border, border, a.cols - 2 * border, a.rows - 2 * border);
    const Scalar m = mean(abs(a(inner) - b(inner)));
    return m[0];
}

}  // namespace

/* The frame a camera records, halved with INTER_AREA, is the frame the half-size camera records of
   the halved scene: same motion, same rolling shutter. Two plausible mistakes do much worse: the
   line delay not doubled, and the focal lengths not halved. (The half-pixel and half-line offsets
   move this motion's image by hundredths of a pixel, below the renderer's resampling error: they
   are checked as values.) */
TEST(HalfColor, HalvedCameraAndShutterRecordTheHalvedFrame)
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    Ptr<CameraModel> camera = CameraModel::create(615.0, 600.0, 319.5, 239.5, 640, 480, 0.05, -0.05);
    camera->setMountAxis(Vec3d(1, 0.3, 0));
    const SwitchSchedule schedule = SwitchPlanner::create(plant, 16)->plan(0.0, 4 * kDeg, 0.0);
    const RollingShutter shutter(0.004, 0.004, 1.0 / 30 / 480, 480);
    ASSERT_EQ(classifyExposure(plant, schedule, shutter), EXPOSURE_III);

    const Ptr<CameraModel> halfCamera = cv::dynblur::detail::halfResolutionCamera(*camera);
    const RollingShutter halfShutter = cv::dynblur::detail::halfResolutionShutter(shutter);
    EXPECT_EQ(halfCamera->getImageSize(), Size(320, 240));
    EXPECT_DOUBLE_EQ(halfCamera->getFx(), 307.5);
    EXPECT_DOUBLE_EQ(halfCamera->getFy(), 300.0);
    EXPECT_DOUBLE_EQ(halfCamera->getCx(), 159.5);  // (319.5 − 0.5) / 2: half-size pixel 0 is centred at 0.5
    EXPECT_DOUBLE_EQ(halfCamera->getCy(), 119.5);
    EXPECT_DOUBLE_EQ(halfCamera->getKud(), 0.05);
    EXPECT_DOUBLE_EQ(halfCamera->getKdu(), -0.05);
    EXPECT_LT(norm(halfCamera->getMountAxis() - camera->getMountAxis()), 1e-12);
    EXPECT_EQ(halfShutter.rows, 240);
    EXPECT_DOUBLE_EQ(halfShutter.frameStart, shutter.frameStart + shutter.lineDelay / 2);
    EXPECT_DOUBLE_EQ(halfShutter.lineDelay, 2 * shutter.lineDelay);
    EXPECT_DOUBLE_EQ(halfShutter.exposure, shutter.exposure);

    const int margin = 64;
    Mat scene(480 + 2 * margin, 640 + 2 * margin, CV_32FC1), halfScene;
    theRNG().state = 7;
    randu(scene, 0.0f, 1.0f);
    GaussianBlur(scene, scene, Size(0, 0), 2.0);
    resize(scene, halfScene, Size(scene.cols / 2, scene.rows / 2), 0, 0, INTER_AREA);
    const double nan = std::numeric_limits<double>::quiet_NaN(), step = 0.05;  // px between time samples
    Mat frame, halvedFrame;
    renderBlurred(scene, plant, schedule, camera, shutter, frame, nan, step);
    resize(frame, halvedFrame, Size(320, 240), 0, 0, INTER_AREA);
    const auto errorOf = [&](const Ptr<CameraModel>& c, const RollingShutter& sh) {
        Mat half;
        renderBlurred(halfScene, plant, schedule, c, sh, half, nan, step);
        return interiorMeanError(halvedFrame, half, 8);
    };
    RollingShutter sameDelay = halfShutter;
    sameDelay.lineDelay = shutter.lineDelay;
    const Ptr<CameraModel> sameFocal = CameraModel::create(615.0, 600.0, 159.5, 119.5, 320, 240, 0.05, -0.05);
    sameFocal->setMountAxis(camera->getMountAxis());
    const double error = errorOf(halfCamera, halfShutter), delayError = errorOf(halfCamera, sameDelay),
                 focalError = errorOf(sameFocal, halfShutter);
    std::printf("[ measured ] halved frame against the half-size camera's: mean error %.5f; with the line delay "
                "not doubled %.5f; with the focal lengths not halved %.5f\n",
                error, delayError, focalError);
    EXPECT_LT(error, 5e-4);
    EXPECT_LT(error, 0.2 * delayError);
    EXPECT_LT(error, 0.2 * focalError);
}

/* The one pass that starts the phases gives what OpenCV gives: the frame halved by cv::resize with
   INTER_AREA, to the bit, and each pixel's channel mean; from an 8-bit frame, what its linear values
   give. */
TEST(HalfColor, HalvingAndChannelMeanAreResizeAndTheMean)
{
    for (const Size size : {Size(2, 2), Size(14, 6), Size(322, 240)})
    {
        Mat frame(size, CV_32FC3);
        theRNG().state = 5;
        randu(frame, 0.0f, 1.0f);
        Mat halfColor, luminance, expectedHalf;
        cv::dynblur::detail::halveAndAverageChannels(frame, halfColor, luminance);
        resize(frame, expectedHalf, Size(size.width / 2, size.height / 2), 0, 0, INTER_AREA);
        ASSERT_EQ(halfColor.type(), CV_32FC3);
        EXPECT_EQ(norm(halfColor, expectedHalf, NORM_INF), 0.0) << size;
        ASSERT_EQ(luminance.type(), CV_32FC1);
        ASSERT_EQ(luminance.size(), size);
        double worst = 0;
        for (int y = 0; y < size.height; y++)
            for (int x = 0; x < size.width; x++)
            {
                const Vec3f c = frame.at<Vec3f>(y, x);
                worst = std::max(worst, double(std::abs(luminance.at<float>(y, x) - (c[0] + c[1] + c[2]) / 3)));
            }
        EXPECT_LT(worst, 1e-7) << size;

        Mat frame8, decoded, halfFrom8, luminanceFrom8, halfFromDecoded, luminanceFromDecoded;
        frame.convertTo(frame8, CV_8U, 255);
        srgbToLinear(frame8, decoded);
        cv::dynblur::detail::halveAndAverageChannels(frame8, halfFrom8, luminanceFrom8);
        cv::dynblur::detail::halveAndAverageChannels(decoded, halfFromDecoded, luminanceFromDecoded);
        EXPECT_EQ(norm(halfFrom8, halfFromDecoded, NORM_INF), 0.0) << size;
        EXPECT_EQ(norm(luminanceFrom8, luminanceFromDecoded, NORM_INF), 0.0) << size;
    }
}

/* The fused pass equals its definition written with OpenCV: the color upsampled by cv::resize
   (INTER_LINEAR), each pixel's channels scaled by the luminance over their mean (the change added
   where the mean is black), clamped to [0, 1]. */
TEST(HalfColor, CombinationUpsamplesAsResizeAndScalesToTheLuminance)
{
    for (const Size halfSize : {Size(1, 1), Size(7, 3), Size(160, 120)})
    {
        Mat halfColor(halfSize, CV_32FC3), luminance(halfSize * 2, CV_32FC1);
        theRNG().state = 11;
        randu(halfColor, 0.0f, 1.0f);
        randu(luminance, 0.0f, 1.2f);  // past 1: the clamp acts
        halfColor.at<Vec3f>(0, 0) = Vec3f(0, 0, 0);  // black: the change is added
        const float black = 1e-3f;

        Mat restored;
        cv::dynblur::detail::combineLuminanceAndHalfColor(luminance, halfColor, black, CV_32F, restored);
        ASSERT_EQ(restored.type(), CV_32FC3);
        ASSERT_EQ(restored.size(), luminance.size());
        // An 8-bit result is the linear one encoded by linearToSrgb.
        Mat restored8, encoded;
        cv::dynblur::detail::combineLuminanceAndHalfColor(luminance, halfColor, black, CV_8U, restored8);
        linearToSrgb(restored, encoded, CV_8U);
        ASSERT_EQ(restored8.type(), CV_8UC3);
        EXPECT_EQ(norm(restored8, encoded, NORM_INF), 0.0) << halfSize;

        Mat upsampled;
        resize(halfColor, upsampled, luminance.size(), 0, 0, INTER_LINEAR);
        double worst = 0;
        for (int y = 0; y < luminance.rows; y++)
            for (int x = 0; x < luminance.cols; x++)
            {
                const Vec3f c = upsampled.at<Vec3f>(y, x);
                const float before = (c[0] + c[1] + c[2]) / 3, after = luminance.at<float>(y, x);
                for (int k = 0; k < 3; k++)
                {
                    const float expected =
                        std::min(std::max(before > black ? c[k] * after / before : c[k] + after - before, 0.f), 1.f);
                    worst = std::max(worst, double(std::abs(restored.at<Vec3f>(y, x)[k] - expected)));
                }
            }
        EXPECT_LT(worst, 1e-5) << halfSize;
    }
}

/* The luminance is restored with every iteration at full resolution: the result's channel mean is
   the one-channel restoration of the frame's channel mean (where no channel was clamped), so the
   color at half resolution costs no luminance detail. */
TEST(HalfColor, DeblurrerKeepsTheFullResolutionLuminance)
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    Ptr<CameraModel> camera = CameraModel::create(300.0, 300.0, 79.5, 59.5, 160, 120);
    const SwitchSchedule schedule = SwitchPlanner::create(plant, 16)->plan(0.0, 6 * kDeg, 0.0);
    const RollingShutter shutter(0.006, 0.008, 1.0 / 30 / 120, 120);
    Mat sharp(120, 160, CV_32FC3), frame;
    theRNG().state = 3;
    randu(sharp, 0.1f, 0.9f);
    GaussianBlur(sharp, sharp, Size(0, 0), 1.0);
    renderBlurred(sharp, plant, schedule, camera, shutter, frame);
    Mat luminanceFrame, unused;
    cv::dynblur::detail::halveAndAverageChannels(frame, unused, luminanceFrame);

    // colorIterations 0: the color is the half-size frame moved back, without an iteration.
    for (const auto& setting : {std::make_pair(int(PSF_ROWS), 2), std::make_pair(int(PSF_TILES), 2),
                                std::make_pair(int(PSF_ROWS), 0)})
    {
        const int model = setting.first;
        Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(plant, camera);
        deblurrer->setPsfModel(model);
        RLParams params = deblurrer->getRLParams();
        params.iterations = 6;
        params.colorIterations = setting.second;
        deblurrer->setRLParams(params);
        deblurrer->setColorResolution(DEBLUR_COLOR_HALF_RESOLUTION);
        Mat restored, luminance, restoredMean, valid;
        deblurrer->deblur(frame, schedule, shutter, restored, std::numeric_limits<double>::quiet_NaN(), valid);
        ASSERT_EQ(restored.type(), CV_32FC3);
        deblurrer->deblur(luminanceFrame, schedule, shutter, luminance);
        cv::dynblur::detail::halveAndAverageChannels(restored, unused, restoredMean);

        Mat unclamped;  // no channel at 0 or 1
        inRange(restored, Scalar::all(1e-6), Scalar::all(1 - 1e-6), unclamped);
        ASSERT_GT(countNonZero(unclamped), int(restored.total() * 9 / 10));
        double worst = 0;
        minMaxLoc(abs(restoredMean - luminance), nullptr, &worst, nullptr, nullptr, unclamped);
        EXPECT_LT(worst, 1e-5) << "model " << model << ", colorIterations " << setting.second;

        // The color phase ran: the result is not the luminance times the frame's chromaticity.
        deblurrer->setColorResolution(DEBLUR_COLOR_FULL_RESOLUTION);
        Mat full;
        deblurrer->deblur(frame, schedule, shutter, full);
        EXPECT_GT(norm(full, restored, NORM_INF), 1e-3) << "model " << model << ", colorIterations " << setting.second;
        // and in place, the frame being its own output
        deblurrer->setColorResolution(DEBLUR_COLOR_HALF_RESOLUTION);
        Mat inPlace = frame.clone();
        deblurrer->deblur(inPlace, schedule, shutter, inPlace);
        EXPECT_EQ(norm(inPlace, restored, NORM_INF), 0.0) << "model " << model << ", colorIterations " << setting.second;
    }
}

/* Grey frames and settings where no color phase runs take the full-resolution path unchanged;
   8-bit frames are restored like their linear values. (Alpha passes through: DeblurChannels.) */
TEST(HalfColor, OtherFramesAndSettingsAreUnchanged)
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    Ptr<CameraModel> camera = CameraModel::create(300.0, 300.0, 79.5, 59.5, 160, 120);
    const SwitchSchedule schedule({0.0, 0.0127, 0.0296}, {16, 4, 10});
    const RollingShutter shutter(0.0, 0.008, 1.0 / 30 / 120, 120);
    Mat bgr(120, 160, CV_8UC3), grey;
    theRNG().state = 5;
    randu(bgr, 0, 256);
    cvtColor(bgr, grey, COLOR_BGR2GRAY);
    Ptr<DynamicDeblurrer> full = DynamicDeblurrer::create(plant, camera), half = DynamicDeblurrer::create(plant, camera);
    RLParams params = full->getRLParams();
    params.iterations = 4;
    params.colorIterations = 1;
    full->setRLParams(params);
    half->setRLParams(params);
    half->setColorResolution(DEBLUR_COLOR_HALF_RESOLUTION);
    EXPECT_EQ(half->getColorResolution(), DEBLUR_COLOR_HALF_RESOLUTION);
    EXPECT_EQ(full->getColorResolution(), DEBLUR_COLOR_FULL_RESOLUTION);

    Mat a, b;
    full->deblur(grey, schedule, shutter, a);
    half->deblur(grey, schedule, shutter, b);
    EXPECT_EQ(norm(a, b, NORM_INF), 0.0) << "grey";

    Mat restoredBgr;
    half->deblur(bgr, schedule, shutter, restoredBgr);
    full->deblur(bgr, schedule, shutter, a);
    EXPECT_GT(norm(a, restoredBgr, NORM_INF), 0.0) << "the half-resolution color phase did not run";
    Mat linear, restoredLinear, encoded;
    srgbToLinear(bgr, linear);
    half->deblur(linear, schedule, shutter, restoredLinear);
    linearToSrgb(restoredLinear, encoded, CV_8U);
    EXPECT_EQ(norm(encoded, restoredBgr, NORM_INF), 0.0);
    Mat inPlace = bgr.clone();  // the 8-bit frame is read before the output is written
    half->deblur(inPlace, schedule, shutter, inPlace);
    EXPECT_EQ(norm(inPlace, restoredBgr, NORM_INF), 0.0) << "8-bit in place";

    // Every iteration in color: no color phase of its own, so the resolution does not apply.
    params.colorIterations = -1;
    full->setRLParams(params);
    half->setRLParams(params);
    full->deblur(bgr, schedule, shutter, a);
    half->deblur(bgr, schedule, shutter, b);
    EXPECT_EQ(norm(a, b, NORM_INF), 0.0) << "colorIterations -1";
    half->setMethod(DEBLUR_WIENER);
    full->setMethod(DEBLUR_WIENER);
    params.colorIterations = 1;
    half->setRLParams(params);
    full->deblur(bgr, schedule, shutter, a);
    half->deblur(bgr, schedule, shutter, b);
    EXPECT_EQ(norm(a, b, NORM_INF), 0.0) << "Wiener";
}

/* The half-size camera follows the camera it halves: a mount axis set after the first frame
   moves the color's kernels as it moves the luminance's (a fresh deblurrer gives the same). */
TEST(HalfColor, FollowsTheCamerasMountAxis)
{
    Ptr<Plant> plant = Plant::create(14.4, 0.12, kDeg);
    Ptr<CameraModel> camera = CameraModel::create(300.0, 300.0, 79.5, 59.5, 160, 120);
    const SwitchSchedule schedule = SwitchPlanner::create(plant, 16)->plan(0.0, 6 * kDeg, 0.0);
    const RollingShutter shutter(0.006, 0.008, 1.0 / 30 / 120, 120);
    Mat frame(120, 160, CV_32FC3);
    theRNG().state = 9;
    randu(frame, 0.1f, 0.9f);
    const auto halfColorDeblurrer = [&] {
        Ptr<DynamicDeblurrer> deblurrer = DynamicDeblurrer::create(plant, camera);
        deblurrer->setPsfModel(PSF_TILES);
        RLParams params = deblurrer->getRLParams();
        params.iterations = 4;
        params.colorIterations = 2;
        deblurrer->setRLParams(params);
        deblurrer->setColorResolution(DEBLUR_COLOR_HALF_RESOLUTION);
        return deblurrer;
    };
    Ptr<DynamicDeblurrer> stream = halfColorDeblurrer();
    Mat before, after, fresh;
    stream->deblur(frame, schedule, shutter, before);
    camera->setMountAxis(Vec3d(0.6, 0.8, 0));  // tilt and pan: the blur turns
    stream->deblur(frame, schedule, shutter, after);
    halfColorDeblurrer()->deblur(frame, schedule, shutter, fresh);
    EXPECT_GT(norm(before, after, NORM_INF), 1e-2);
    EXPECT_EQ(norm(after, fresh, NORM_INF), 0.0);
}

TEST(HalfColor, BadSettingsAreRefusedWithTheirRange)
{
    Ptr<Plant> plant = Plant::create();
    Ptr<DynamicDeblurrer> deblurrer =
        DynamicDeblurrer::create(plant, CameraModel::create(615.0, 615.0, 319.5, 239.5, 640, 480));
    for (int bad : {-1, 2})
    {
        dynblur_test::expectErrorNaming([&] { deblurrer->setColorResolution(bad); },
                                        "resolution = " + std::to_string(bad));
        dynblur_test::expectErrorNaming([&] { deblurrer->setColorResolution(bad); }, "DEBLUR_COLOR_HALF_RESOLUTION (1)");
    }
    EXPECT_EQ(deblurrer->getColorResolution(), DEBLUR_COLOR_FULL_RESOLUTION);
    Ptr<DynamicDeblurrer> odd =
        DynamicDeblurrer::create(plant, CameraModel::create(615.0, 615.0, 320.0, 239.5, 641, 480));
    dynblur_test::expectErrorNaming([&] { odd->setColorResolution(DEBLUR_COLOR_HALF_RESOLUTION); },
                                    "even image size; the camera's is 641x480");
    EXPECT_EQ(odd->getColorResolution(), DEBLUR_COLOR_FULL_RESOLUTION);
    odd->setColorResolution(DEBLUR_COLOR_FULL_RESOLUTION);
}
