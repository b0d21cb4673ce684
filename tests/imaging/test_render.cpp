// SPDX-License-Identifier: Apache-2.0
// renderBlurred (the physical forward model), sensor noise and the sRGB transfer functions.
#include "test_common.hpp"

#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <chrono>

using namespace cv;
using namespace cv::dynblur;

namespace {

//! θ(t) = rate·(t − tMid) + bump(t): constant velocity, optionally with a bump in [bumpStart, bumpEnd].
class RampPlant CV_FINAL : public Plant
{
public:
    RampPlant(double rate, double tMid, double bumpStart = 0, double bumpEnd = 0, double bump = 0)
        : rate_(rate), tMid_(tMid), b0_(bumpStart), b1_(bumpEnd), bump_(bump)
    {
    }
    void response(const SwitchSchedule&, InputArray t, OutputArray theta) const CV_OVERRIDE
    {
        Mat tm;
        t.getMat().convertTo(tm, CV_64F);
        theta.create(tm.size(), CV_64F);
        Mat out = theta.getMat();
        for (int i = 0; i < (int)tm.total(); i++)
        {
            const double ti = tm.at<double>(i);
            double v = rate_ * (ti - tMid_);
            if (ti > b0_ && ti < b1_)
                v += bump_ * std::sin(CV_PI * (ti - b0_) / (b1_ - b0_));
            out.at<double>(i) = v;
        }
    }
    void velocity(const SwitchSchedule&, InputArray t, OutputArray omega) const CV_OVERRIDE
    {
        Mat tm;
        t.getMat().convertTo(tm, CV_64F);
        omega.create(tm.size(), CV_64F);
        Mat out = omega.getMat();
        for (int i = 0; i < (int)tm.total(); i++)
        {
            const double ti = tm.at<double>(i);
            double v = rate_;
            if (ti > b0_ && ti < b1_)
                v += bump_ * CV_PI / (b1_ - b0_) * std::cos(CV_PI * (ti - b0_) / (b1_ - b0_));
            out.at<double>(i) = v;
        }
    }
    double getNaturalFreqHz() const CV_OVERRIDE { return 14.4; }
    double getDampingRatio() const CV_OVERRIDE { return 0.12; }
    double getGain() const CV_OVERRIDE { return CV_PI / 180; }

private:
    double rate_, tMid_, b0_, b1_, bump_;
};

SwitchSchedule saccade() { return SwitchSchedule({0.0, 0.0127, 0.0296}, {16, 4, 10}, 0); }

Ptr<Plant> seedPlant() { return Plant::create(14.4, 0.12, CV_PI / 180.0); }

Mat testPattern(Size size, int type)
{
    Mat img(size, CV_32FC3);
    RNG rng(7);
    for (int y = 0; y < size.height; y++)
        for (int x = 0; x < size.width; x++)
            img.at<Vec3f>(y, x) = Vec3f(0.5f + 0.4f * std::sin(x * 0.11f + y * 0.05f), ((x / 7 + y / 5) % 2) * 0.8f + 0.1f,
                                        (float)rng.uniform(0.0, 1.0));
    Mat out;
    img.convertTo(out, type, CV_MAT_DEPTH(type) == CV_8U ? 255.0 : 1.0);
    return out;
}

}  // namespace

TEST(RenderSrgb, RoundTripAndEndpoints)
{
    Mat all(1, 256, CV_8U);
    for (int i = 0; i < 256; i++)
        all.at<uchar>(i) = (uchar)i;
    Mat lin, back;
    srgbToLinear(all, lin);
    EXPECT_EQ(lin.type(), CV_32F);
    EXPECT_EQ(lin.at<float>(0), 0.0f);
    EXPECT_NEAR(lin.at<float>(255), 1.0f, 1e-6);
    EXPECT_NEAR(lin.at<float>(128), 0.2158605f, 1e-5);  // sRGB mid-grey
    linearToSrgb(lin, back, CV_8U);
    EXPECT_EQ(norm(all, back, NORM_INF), 0.0);
    Mat f;
    linearToSrgb(lin, f, CV_32F);
    EXPECT_NEAR(f.at<float>(128), 128 / 255.0, 1e-5);
    EXPECT_THROW(linearToSrgb(lin, f, CV_16U), cv::Exception);
}

/* The 8-bit encoding (tables) is 255·srgb(v) rounded to nearest, computed here with pow in double:
   on a million random values, on every code's threshold and the floats beside it, and past both
   ends (clamped; NaN encodes as 0). Also through 3 channels and CV_64F input. */
TEST(RenderSrgb, EightBitEncodingRoundsTheCurveToNearest)
{
    const auto exact = [](double l) {
        l = std::min(1.0, std::max(0.0, l));
        const double s = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
        return int(std::floor(255.0 * s + 0.5));
    };
    std::vector<float> values;
    RNG rng(17);
    for (int i = 0; i < 1000000; i++)
        values.push_back(rng.uniform(0.f, 1.f));
    for (int k = 1; k < 256; k++)
    {
        // the threshold: the inverse of the curve at (k − 0.5) / 255
        const double c = (k - 0.5) / 255.0;
        const float t = (float)(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        float below = t, above = t;
        for (int step = 0; step < 4; step++)
        {
            values.push_back(below = std::nextafter(below, -1.f));
            values.push_back(above = std::nextafter(above, 2.f));
        }
        values.push_back(t);
    }
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    for (float v : {0.f, 1.f, -0.5f, 1.5f, -inf, inf, nan, 1e-30f, std::nextafter(1.f, 0.f)})
        values.push_back(v);
    Mat linear(1, int(values.size()), CV_32F, values.data()), encoded;
    linearToSrgb(linear, encoded, CV_8U);
    ASSERT_EQ(encoded.type(), CV_8U);
    int wrong = 0;
    for (size_t i = 0; i < values.size(); i++)
    {
        const int expected = std::isnan(values[i]) ? 0 : exact(values[i]);
        if (encoded.at<uchar>(int(i)) != expected && wrong++ < 5)
            ADD_FAILURE() << "linear " << values[i] << " encoded " << int(encoded.at<uchar>(int(i))) << ", expected "
                          << expected;
    }
    EXPECT_EQ(wrong, 0);

    Mat three = linear.colRange(0, 30000).reshape(3), threeEncoded, wide, wideEncoded;
    linearToSrgb(three, threeEncoded, CV_8U);
    ASSERT_EQ(threeEncoded.type(), CV_8UC3);
    EXPECT_EQ(norm(threeEncoded.reshape(1), encoded.colRange(0, 30000), NORM_INF), 0.0);
    linear.colRange(0, 30000).convertTo(wide, CV_64F);
    linearToSrgb(wide, wideEncoded, CV_8U);
    EXPECT_EQ(norm(wideEncoded, encoded.colRange(0, 30000), NORM_INF), 0.0);
}

TEST(RenderNoise, DeterministicAndPhysical)
{
    Mat flat(200, 200, CV_32F, Scalar(0.25)), a, b, c;
    addSensorNoise(flat, a, 4000, 8, 5, 42);
    addSensorNoise(flat, b, 4000, 8, 5, 42);
    addSensorNoise(flat, c, 4000, 8, 5, 43);
    EXPECT_EQ(norm(a, b, NORM_INF), 0.0);
    EXPECT_GT(norm(a, c, NORM_INF), 0.0);
    Scalar mean, sd;
    meanStdDev(a, mean, sd);
    EXPECT_NEAR(mean[0], 0.25, 2e-3);
    const double expectSd = std::sqrt(0.25 * 4000 + 5 + 64) / 4000;  // shot + dark + read, electrons
    EXPECT_NEAR(sd[0], expectSd, 0.05 * expectSd);
    double mn, mx;
    Mat bright(50, 50, CV_32F, Scalar(0.999)), d;
    addSensorNoise(bright, d);
    minMaxLoc(d, &mn, &mx);
    EXPECT_LE(mx, 1.0);
    EXPECT_THROW(addSensorNoise(flat, d, 0.0), cv::Exception);
    EXPECT_THROW(addSensorNoise(flat, d, 4000, -1), cv::Exception);
}

TEST(RenderBlurred, StillWindowIVReturnsInput)
{
    Ptr<CameraModel> cam = CameraModel::create(300, 300, 80, 60, 160, 120);
    const RollingShutter late(3.0, 0.008, 1.0 / 30 / 120, 120);  // long after the move: window IV
    ASSERT_EQ(classifyExposure(seedPlant(), saccade(), late), EXPOSURE_IV);
    for (int type : {CV_32FC3, CV_64FC1, CV_8UC3})
    {
        Mat sharp = testPattern(Size(160, 120), CV_MAT_DEPTH(type));
        if (CV_MAT_CN(type) == 1)
        {
            extractChannel(sharp, sharp, 1);
        }
        Mat out;
        renderBlurred(sharp, seedPlant(), saccade(), cam, late, out);
        ASSERT_EQ(out.type(), sharp.type());
        EXPECT_EQ(norm(out, sharp, NORM_INF), 0.0) << "type " << type;
    }
    // A wider sharp view: the frame is its centre.
    Mat wide = testPattern(Size(200, 160), CV_32FC3), out;
    renderBlurred(wide, seedPlant(), saccade(), cam, late, out);
    EXPECT_EQ(norm(out, wide(Rect(20, 20, 160, 120)), NORM_INF), 0.0);
}

TEST(RenderBlurred, GlobalShutterConstantVelocityIsABoxBlur)
{
    // Long focal length, rows near the principal point: the image translates by f·Δθ along y.
    const double f = 2000, lengthPx = 12, exposure = 0.01;
    Ptr<CameraModel> cam = CameraModel::create(f, f, 160, 120, 320, 240);
    const RollingShutter global(0.0, exposure, 0.0, 240);
    Ptr<Plant> ramp = makePtr<RampPlant>(lengthPx / f / exposure, exposure / 2);
    const double edge = 120;
    Mat sharp(240 + 80, 320 + 80, CV_32F, Scalar(0));
    sharp.rowRange((int)edge + 40, sharp.rows).setTo(1.0);  // step edge at row 120 of the frame
    Mat out;
    renderBlurred(sharp, ramp, SwitchSchedule(), cam, global, out, 0.0);
    // Bilinear sampling turns the step into a ramp r(u) = clamp(u − edge + 1, 0, 1); its box
    // average over [y − L/2, y + L/2] has the closed form (F(y + L/2) − F(y − L/2))/L.
    auto F = [&](double u) {
        const double s = u - edge + 1;
        return s < 0 ? 0.0 : (s < 1 ? 0.5 * s * s : s - 0.5);
    };
    double worst = 0;
    for (int y = 100; y < 140; y++)
    {
        const double expect = (F(y + lengthPx / 2) - F(y - lengthPx / 2)) / lengthPx;
        for (int x : {150, 160, 170})
            worst = std::max(worst, std::abs(out.at<float>(y, x) - expect));
    }
    EXPECT_LT(worst, 5e-3);
}

TEST(RenderBlurred, RowDependsOnlyOnItsInterval)
{
    Ptr<CameraModel> cam = CameraModel::create(300, 300, 80, 60, 160, 120);
    const double ld = 1e-4, exposure = 0.002;
    const RollingShutter rs(0.0, exposure, ld, 120);
    // The bump perturbs θ during [5 ms, 6 ms]: only rows whose interval overlaps it may change.
    Ptr<Plant> a = makePtr<RampPlant>(0.5, 0.006);
    Ptr<Plant> b = makePtr<RampPlant>(0.5, 0.006, 0.005, 0.006, 0.01);
    Mat sharp = testPattern(Size(200, 160), CV_32FC3), ra, rb;
    renderBlurred(sharp, a, SwitchSchedule(), cam, rs, ra, 0.0, 0.05);
    renderBlurred(sharp, b, SwitchSchedule(), cam, rs, rb, 0.0, 0.05);
    for (int r = 0; r < 120; r++)
    {
        const double s = r * ld, e = s + exposure;
        const bool touched = e > 0.005 && s < 0.006;
        const double d = norm(ra.row(r), rb.row(r), NORM_INF);
        if (touched)
        {
            if (s >= 0.0045 && s <= 0.005)  // most of the bump inside the interval
            {
                EXPECT_GT(d, 0.05) << "row " << r;
            }
        }
        else
        {
            EXPECT_LT(d, 2e-3) << "row " << r;  // same up to the time-sampling pattern
        }
    }
}

TEST(RenderBlurred, EightBitIsAveragedInLinearLight)
{
    Ptr<CameraModel> cam = CameraModel::create(300, 300, 80, 60, 160, 120);
    const RollingShutter rs(0.0, 0.008, 1.0 / 30 / 120, 120);
    Mat sharp8 = testPattern(Size(160, 120), CV_8UC3), lin, out8, outLin, expect;
    srgbToLinear(sharp8, lin);
    renderBlurred(sharp8, seedPlant(), saccade(), cam, rs, out8);
    renderBlurred(lin, seedPlant(), saccade(), cam, rs, outLin);
    linearToSrgb(outLin, expect, CV_8U);
    ASSERT_EQ(out8.type(), CV_8UC3);
    EXPECT_LE(norm(out8, expect, NORM_INF), 1.0);
    // and it is really blurred
    EXPECT_GT(norm(out8, sharp8, NORM_L1) / sharp8.total(), 10.0);
}

TEST(RenderBlurred, BadArgumentsNameTheArgument)
{
    Ptr<CameraModel> cam = CameraModel::create(300, 300, 80, 60, 160, 120);
    const RollingShutter rs(0.0, 0.008, 1e-4, 120);
    Mat sharp = testPattern(Size(160, 120), CV_32FC3), out;
    Ptr<Plant> p = seedPlant();
    const SwitchSchedule s = saccade();
    dynblur_test::expectErrorNaming([&] { renderBlurred(Mat(), p, s, cam, rs, out); }, "sharp");
    dynblur_test::expectErrorNaming([&] { renderBlurred(Mat(120, 160, CV_16UC1, Scalar(0)), p, s, cam, rs, out); }, "sharp");
    dynblur_test::expectErrorNaming([&] { renderBlurred(Mat(120, 160, CV_32FC(5), Scalar(0)), p, s, cam, rs, out); }, "sharp");
    dynblur_test::expectErrorNaming([&] { renderBlurred(sharp(Rect(0, 0, 150, 120)), p, s, cam, rs, out); }, "sharp");
    dynblur_test::expectErrorNaming([&] { renderBlurred(Mat(121, 161, CV_32FC1, Scalar(0)), p, s, cam, rs, out); }, "sharp");
    dynblur_test::expectErrorNaming([&] { renderBlurred(sharp, p, s, cam, RollingShutter(0, 0.008, 1e-4, 100), out); },
                      "shutter.rows");
    dynblur_test::expectErrorNaming([&] { renderBlurred(sharp, p, s, cam, rs, out, INFINITY); }, "thetaRef");
    dynblur_test::expectErrorNaming([&] { renderBlurred(sharp, p, s, cam, rs, out, NAN, 0.0); }, "maxStepPx");
    dynblur_test::expectErrorNaming([&] { renderBlurred(sharp, p, s, cam, rs, out, NAN, 1.5); }, "maxStepPx");
    dynblur_test::expectErrorNaming([&] { renderBlurred(sharp, p, s, cam, rs, out, NAN, 0.25, 99); }, "borderMode");
    EXPECT_THROW(renderBlurred(sharp, Ptr<Plant>(), s, cam, rs, out), cv::Exception);
    EXPECT_THROW(renderBlurred(sharp, p, s, Ptr<CameraModel>(), rs, out), cv::Exception);
    // NaN thetaRef is allowed (the final resting angle)
    EXPECT_NO_THROW(renderBlurred(sharp, p, s, cam, rs, out, NAN));
}

TEST(RenderBlurred, FullFrameSaccadeSpeed)
{
    DYNBLUR_REQUIRE_DATA(path, "fruits.jpg");
    Mat img = imread(path, IMREAD_COLOR), sharp;
    ASSERT_FALSE(img.empty());
    resize(img, sharp, Size(1280, 960), 0, 0, INTER_CUBIC);
    Ptr<CameraModel> cam = CameraModel::create(1230, 1230, 640, 480, 1280, 960);
    const RollingShutter rs(0.0, 0.008, 1.0 / 30 / 960, 960);  // the saccade starts with the frame
    Mat out;
    const auto t0 = std::chrono::steady_clock::now();
    renderBlurred(sharp, seedPlant(), saccade(), cam, rs, out);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << "[ INFO     ] renderBlurred 1280x960 RGB 8-bit, 10 deg saccade, rolling shutter: " << sec << " s"
              << std::endl;
    EXPECT_EQ(out.size(), Size(1280, 960));  // the time is printed, not bounded: machines differ
}
