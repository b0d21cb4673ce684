// SPDX-License-Identifier: Apache-2.0
// GyroLog: gcsv and plain CSV gyro logs into camera axes, the axis strings, the bias from still
// intervals, and every kind of bad log refused with the file, line and field named.
#include "test_common.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/dynblur.hpp>

#include <fstream>
#include <unistd.h>

using namespace cv;
using namespace cv::dynblur;

namespace {

const double kDeg = CV_PI / 180.0;

//! Writes `text` to a file of this test process's temp folder and returns its path.
std::string writeLog(const std::string& name, const std::string& text)
{
    const char* dir = std::getenv("TMPDIR");
    const std::string path = std::string(dir && *dir ? dir : "/tmp") + "/dynblur_gyro_" +
                             std::to_string(::getpid()) + "_" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

const char* const kGcsvHeader = "GYROFLOW IMU LOG\n"
                                "version,1.3\n"
                                "id,test_logger\n"
                                "orientation,YxZ\n"
                                "note,written by the test\n"
                                "frame_readout_time,15.23\n"
                                "tscale,0.001\n"
                                "gscale,0.01\n"
                                "ascale,0.00048828125\n";

TEST(GyroLog, ReadsGcsvIntoCameraAxes)
{
    const std::string path = writeLog("basic.gcsv", std::string(kGcsvHeader) +
                                                        "t,gx,gy,gz,ax,ay,az\n"
                                                        "0,10,20,30,1,2,3\n"
                                                        "5,-10,40,0,1,2,3\n"
                                                        "10,0,0,100,1,2,3\n");
    const GyroLog log = GyroLog::load(path);
    ASSERT_EQ(log.times.size(), 3u);
    EXPECT_DOUBLE_EQ(log.times[1], 0.005);
    EXPECT_EQ(log.id, "test_logger");
    EXPECT_EQ(log.orientation, "YxZ");
    // YxZ: camera x = gyro y, camera y = −gyro x, camera z = gyro z; gscale 0.01 rad/s per unit.
    EXPECT_NEAR(log.rates.at<double>(0, 0), 0.20, 1e-15);
    EXPECT_NEAR(log.rates.at<double>(0, 1), -0.10, 1e-15);
    EXPECT_NEAR(log.rates.at<double>(0, 2), 0.30, 1e-15);
    EXPECT_NEAR(log.rates.at<double>(1, 1), 0.10, 1e-15);
    EXPECT_EQ(log.cameraFromGyro, GyroLog::orientationMatrix("YxZ"));
    EXPECT_EQ(log.bias, Vec3d());
    const Ptr<CameraMotion> motion = log.toMotion();
    EXPECT_LT(norm(motion->angularVelocity(0.0) - Vec3d(0.2, -0.1, 0.3)), 1e-15);
    EXPECT_EQ(motion->getTimeSpan(), Vec2d(0.0, 0.01));
}

TEST(GyroLog, ReadsGcsvWithMagnetometerAndCameraImuLogHeader)
{
    const std::string path = writeLog("mag.gcsv", "CAMERA IMU LOG\nversion,1.3\norientation,XYZ\ntscale,1e-6\n"
                                                  "gscale,1\nmscale,0.001\nt,gx,gy,gz,ax,ay,az,mx,my,mz\n"
                                                  "1000000,0.1,0.2,0.3,0,0,1,5,5,5\n1005000,0.1,0.2,0.3,0,0,1,5,5,5\n");
    const GyroLog log = GyroLog::load(path);
    EXPECT_DOUBLE_EQ(log.times[0], 1.0);
    EXPECT_DOUBLE_EQ(log.times[1], 1.005);
    EXPECT_NEAR(log.rates.at<double>(1, 2), 0.3, 1e-15);
}

TEST(GyroLog, SkipsAByteOrderMark)
{
    const GyroLog log = GyroLog::load(writeLog("bom.gcsv", "\xEF\xBB\xBFGYROFLOW IMU LOG\r\nversion,1.3\r\n"
                                                           "orientation,XYZ\r\ntscale,1\r\ngscale,1\r\n"
                                                           "t,gx,gy,gz\r\n0,1,2,3\r\n1,1,2,3\r\n"));
    EXPECT_EQ(log.times.size(), 2u);
    EXPECT_EQ(log.rates.at<double>(1, 2), 3.0);
}

TEST(GyroLog, ReadsPlainCsvInDegreesWithAMountingRotation)
{
    const std::string path = writeLog("plain.csv", "# a phone's gyro, deg/s\nt,gx,gy,gz,temperature\n"
                                                   "0.000, 10, 0, 0, 31\n0.005, 10, 0, 0, 31\n0.010, 0, 90, 0, 31\n");
    GyroLogOptions options;
    options.rateScale = kDeg;
    options.orientation = "xyZ";  // rotated 180° about the optical axis
    Matx33d tilt;
    Rodrigues(Vec3d(0.1, 0, 0), tilt);
    options.cameraFromGyro = tilt;
    const GyroLog log = GyroLog::load(path, options);
    EXPECT_EQ(log.orientation, "xyZ");
    const Vec3d expected = tilt * Vec3d(0, -90 * kDeg, 0);
    EXPECT_LT(norm(Vec3d(log.rates.ptr<double>(2)) - expected), 1e-14);
    EXPECT_LT(norm(log.cameraFromGyro - tilt * Matx33d(-1, 0, 0, 0, -1, 0, 0, 0, 1), NORM_INF), 1e-15);
}

TEST(GyroLog, OrientationStrings)
{
    EXPECT_EQ(GyroLog::orientationMatrix("XYZ"), Matx33d::eye());
    EXPECT_EQ(GyroLog::orientationMatrix("YxZ"), Matx33d(0, 1, 0, -1, 0, 0, 0, 0, 1));
    EXPECT_EQ(GyroLog::orientationMatrix("zXy"), Matx33d(0, 0, -1, 1, 0, 0, 0, -1, 0));
    for (const char* bad : {"XYZW", "XY", "XXZ", "abc", "", "X Z"})
        dynblur_test::expectErrorNaming([&] { GyroLog::orientationMatrix(bad); }, "unknown orientation string");
    for (const char* mirrored : {"XYz", "xyz", "YXZ"})
        dynblur_test::expectErrorNaming([&] { GyroLog::orientationMatrix(mirrored); }, "left-handed");
}

TEST(GyroLog, BiasFromStillIntervals)
{
    // 1 s at rest, 1 s of shake, 1 s at rest, at 200 Hz, with noise and a 0.5 °/s bias per axis.
    const Vec3d bias(0.5 * kDeg, -0.5 * kDeg, 0.5 * kDeg);
    RNG rng(7);
    std::ostringstream text;
    text << "t,gx,gy,gz\n";
    for (int k = 0; k <= 600; ++k)
    {
        const double t = k / 200.0;
        const double move = (t > 1.0 && t < 2.0) ? 0.6 * std::sin(2 * CV_PI * 3 * t) : 0.0;
        text << format("%.6f,%.9f,%.9f,%.9f\n", t, move + bias[0] + rng.gaussian(0.003),
                       bias[1] + 0.5 * move + rng.gaussian(0.003), bias[2] + rng.gaussian(0.003));
    }
    GyroLogOptions options;
    options.estimateBias = true;
    const GyroLog log = GyroLog::load(writeLog("bias.csv", text.str()), options);
    EXPECT_LT(norm(log.bias - bias), 0.02 * kDeg);
    EXPECT_GT(log.biasStillSeconds, 1.8);
    EXPECT_LE(log.biasStillSeconds, 2.0);
    // The motion integrates rates − bias: at rest it stays put.
    const Ptr<CameraMotion> motion = log.toMotion();
    Vec3d drift;
    Rodrigues(motion->orientation(0.0).t() * motion->orientation(0.99), drift);
    EXPECT_LT(norm(drift), 0.02 * kDeg);

    GyroLog moving = log;
    dynblur_test::expectErrorNaming([&] { moving.estimateBias(0.05, 1.5); }, "stillMinDuration");
    dynblur_test::expectErrorNaming([&] { moving.estimateBias(-1, 0.5); }, "stillThreshold");
}

// ------------------------------------------------------------------------------------ bad logs

//! Expects GyroLog::load(text) to fail with a message naming the file and containing each of `words`.
void expectRefused(const std::string& name, const std::string& text, std::initializer_list<const char*> words,
                   const GyroLogOptions& options = GyroLogOptions())
{
    const std::string path = writeLog(name, text);
    try
    {
        GyroLog::load(path, options);
        ADD_FAILURE() << name << ": no exception";
    }
    catch (const cv::Exception& e)
    {
        const std::string what = e.what();
        EXPECT_NE(what.find(path), std::string::npos) << what;
        for (const char* word : words)
            EXPECT_NE(what.find(word), std::string::npos) << "'" << word << "' not in: " << what;
    }
}

TEST(GyroLogBadInput, RefusedWithFileLineAndField)
{
    const std::string gcsv = kGcsvHeader;
    const std::string columns = "t,gx,gy,gz\n";
    expectRefused("empty.csv", "", {"is empty"});
    expectRefused("blank.csv", "\n  \n", {"is empty"});
    expectRefused("count.gcsv", gcsv + columns + "0,1,2,3\n5,1,2\n", {":12:", "3 fields", "names 4"});
    expectRefused("nan.gcsv", gcsv + columns + "0,1,2,3\n5,1,nan,3\n", {":12:", "field 'gy'", "'nan'"});
    expectRefused("inf.csv", "t,gx,gy,gz\n0,1,2,3\n0.005,inf,2,3\n", {":3:", "field 'gx'"});
    expectRefused("text.csv", "t,gx,gy,gz\n0,1,2,3\n0.005,1,2,3x\n", {":3:", "field 'gz'", "not a finite number"});
    expectRefused("unsorted.csv", "t,gx,gy,gz\n0,0,0,0\n0.01,0,0,0\n0.005,0,0,0\n",
                  {":4:", "field 't'", "strictly increasing", "line 3"});
    expectRefused("repeated.csv", "t,gx,gy,gz\n0,0,0,0\n0.005,0,0,0\n0.005,0,0,0\n", {":4:", "strictly increasing"});
    expectRefused("gap.csv", "t,gx,gy,gz\n0,0,0,0\n0.005,0,0,0\n0.010,0,0,0\n0.030,0,0,0\n0.035,0,0,0\n",
                  {":5:", "gap", "line 4"});
    expectRefused("one.csv", "t,gx,gy,gz\n0,0,0,0\n", {"at least 2"});
    expectRefused("noheader.csv", "0,1,2,3\n0.005,1,2,3\n", {":1:", "missing header", "t,gx,gy,gz"});
    expectRefused("wrongheader.csv", "time,x,y,z\n0,1,2,3\n", {":1:", "missing header"});
    expectRefused("nocolumns.gcsv", gcsv + "0,1,2,3\n", {":10:", "data row before the column row"});
    expectRefused("nocolumns2.gcsv", gcsv, {"no column row"});
    expectRefused("badcolumns.gcsv", gcsv + "t,gx,gy,gz,ax\n0,1,2,3,4\n", {":10:", "column row must be"});
    expectRefused("notscale.gcsv", "GYROFLOW IMU LOG\nversion,1.3\norientation,XYZ\ngscale,1\n" + columns + "0,0,0,0\n",
                  {"lacks 'tscale'"});
    expectRefused("badgscale.gcsv", "GYROFLOW IMU LOG\nversion,1.3\norientation,XYZ\ntscale,1\ngscale,-2\n" + columns,
                  {":5:", "field 'gscale'", "> 0"});
    expectRefused("noorientation.gcsv", "GYROFLOW IMU LOG\nversion,1.3\ntscale,1\ngscale,1\n" + columns +
                                            "0,0,0,0\n1,0,0,0\n", {"lacks 'orientation'"});
    expectRefused("badorientation.gcsv", "GYROFLOW IMU LOG\nversion,1.3\norientation,XQZ\ntscale,1\ngscale,1\n" +
                                             columns + "0,0,0,0\n1,0,0,0\n",
                  {":3:", "field 'orientation'", "unknown orientation string 'XQZ'"});
    expectRefused("mirrored.gcsv", "GYROFLOW IMU LOG\nversion,1.3\norientation,XYz\ntscale,1\ngscale,1\n" + columns +
                                       "0,0,0,0\n1,0,0,0\n", {":3:", "left-handed"});
    expectRefused("version.gcsv", "GYROFLOW IMU LOG\nversion,2.0\n", {":2:", "version"});
    GyroLogOptions scaled;
    scaled.rateScale = kDeg;
    expectRefused("scaled.gcsv", gcsv + columns + "0,0,0,0\n1,0,0,0\n", {"options.rateScale"}, scaled);
    EXPECT_THROW(GyroLog::load("/nonexistent/dir/log.gcsv"), cv::Exception);
}

TEST(GyroLogBadInput, Options)
{
    const std::string path = writeLog("ok.csv", "t,gx,gy,gz\n0,0,0,0\n1,0,0,0\n");
    GyroLogOptions o;
    o.timeScale = 0;
    dynblur_test::expectErrorNaming([&] { GyroLog::load(path, o); }, "options.timeScale");
    o = GyroLogOptions();
    o.cameraFromGyro = Matx33d(1, 0, 0, 0, 1, 0, 0, 0, -1);
    dynblur_test::expectErrorNaming([&] { GyroLog::load(path, o); }, "options.cameraFromGyro");
    o = GyroLogOptions();
    o.orientation = "XYQ";
    dynblur_test::expectErrorNaming([&] { GyroLog::load(path, o); }, "unknown orientation string");
    o = GyroLogOptions();
    o.estimateBias = true;  // 1 s at rest but the default minimum is 0.5 s: accepted
    EXPECT_NO_THROW(GyroLog::load(path, o));
}

}  // namespace
