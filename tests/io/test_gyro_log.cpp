// SPDX-License-Identifier: Apache-2.0
// GyroLog: gcsv and plain CSV gyro logs into camera axes, the axis strings, the bias from still
// intervals, and every kind of bad log refused with the file, line and field named.
#include "test_common.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/dynblur.hpp>

#include <fstream>
#include <limits>
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

//! Expects GyroLog::load(path, options) to fail with a message containing each of `words`.
void expectErrorNamingEach(const std::string& path, std::initializer_list<const char*> words,
                           const GyroLogOptions& options = GyroLogOptions())
{
    for (const char* word : words)
        dynblur_test::expectErrorNaming([&] { GyroLog::load(path, options); }, word);
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

TEST(GyroLog, GcsvReadoutTimeAndDirection)
{
    const GyroLog log = GyroLog::load(writeLog("readout.gcsv", std::string(kGcsvHeader) +
                                                                   "frame_readout_direction,1\nt,gx,gy,gz\n0,0,0,0\n"
                                                                   "5,0,0,0\n"));
    EXPECT_EQ(log.layout, "gcsv");
    EXPECT_DOUBLE_EQ(log.frameReadoutTime, 15.23e-3);  // the file's milliseconds, in seconds
    EXPECT_EQ(log.frameReadoutDirection, READOUT_BOTTOM_TO_TOP);
    const GyroLog bare = GyroLog::load(writeLog("bare.gcsv", "GYROFLOW IMU LOG\nversion,1.1\norientation,XYZ\n"
                                                             "tscale,1\ngscale,1\nt,gx,gy,gz\n0,0,0,0\n1,0,0,0\n"));
    EXPECT_TRUE(std::isnan(bare.frameReadoutTime));
    EXPECT_EQ(bare.frameReadoutDirection, READOUT_DIRECTION_UNKNOWN);
    EXPECT_EQ(bare.timeOrigin, 0.0);
}

TEST(GyroLog, GcsvInGyroflowAxes)
{
    // Gyroflow's frame is x up, y left, z backward: rates about those axes are −y, −x, −z in camera axes.
    const std::string text = "GYROFLOW IMU LOG\nversion,1.3\norientation,XYZ\ntscale,0.001\ngscale,1\nt,gx,gy,gz\n"
                             "0,1,0,0\n5,0,1,0\n10,0,0,1\n";
    GyroLogOptions options;
    options.gcsvAxes = "gyroflow";
    const GyroLog log = GyroLog::load(writeLog("gyroflow.gcsv", text), options);
    EXPECT_EQ(Vec3d(log.rates.ptr<double>(0)), Vec3d(0, -1, 0));
    EXPECT_EQ(Vec3d(log.rates.ptr<double>(1)), Vec3d(-1, 0, 0));
    EXPECT_EQ(Vec3d(log.rates.ptr<double>(2)), Vec3d(0, 0, -1));
    EXPECT_EQ(log.cameraFromGyro, GyroLog::orientationMatrix("yxz"));
    // The file's axis string applies first: YxZ takes gyro (gx, gy, gz) to Gyroflow's (gy, −gx, gz).
    options.orientation = "YxZ";
    const GyroLog turned = GyroLog::load(writeLog("gyroflow.gcsv", text), options);
    EXPECT_EQ(turned.cameraFromGyro, GyroLog::orientationMatrix("yxz") * GyroLog::orientationMatrix("YxZ"));
    EXPECT_EQ(Vec3d(turned.rates.ptr<double>(0)), Vec3d(1, 0, 0));  // gyro x: Gyroflow −y (right), camera +x
}

TEST(GyroLog, SensorLoggerGyroscopeCsvOnTheUnixEpoch)
{
    // Sensor Logger's column order (z, y, x), its epoch nanoseconds, 1 ns steps kept exactly.
    const std::string path = writeLog("Gyroscope.csv", "time,seconds_elapsed,z,y,x\n"
                                                       "1767620467350470700,0.143471,0.3,0.2,0.1\n"
                                                       "1767620467355470701,0.148471,0.3,0.2,0.1\n"
                                                       "1767620467360470702,0.153471,0.6,0.5,0.4\n");
    const GyroLog log = GyroLog::load(path);
    EXPECT_EQ(log.layout, "sensor-logger");
    EXPECT_EQ(log.orientation, "Xyz");  // phone x right, y up, z out of the screen → camera x, −y, −z
    EXPECT_EQ(log.timeOrigin, 1767620467.0);
    ASSERT_EQ(log.times.size(), 3u);
    EXPECT_NEAR(log.times[0], 0.350470700, 1e-15);
    EXPECT_NEAR(log.times[1] - log.times[0], 0.005000001, 1e-15);
    EXPECT_NEAR(log.times[2] - log.times[1], 0.005000001, 1e-15);
    EXPECT_LT(norm(Vec3d(log.rates.ptr<double>(0)) - Vec3d(0.1, -0.2, -0.3)), 1e-15);
    EXPECT_LT(norm(Vec3d(log.rates.ptr<double>(2)) - Vec3d(0.4, -0.5, -0.6)), 1e-15);
    GyroLogOptions asLogged;
    asLogged.orientation = "XYZ";
    EXPECT_LT(norm(Vec3d(GyroLog::load(path, asLogged).rates.ptr<double>(0)) - Vec3d(0.1, 0.2, 0.3)), 1e-15);
}

TEST(GyroLog, OpenCameraSensorsGyroCsv)
{
    // <video>_gyro.csv: x, y, z in rad/s, then the sensor timestamp in ns; no header row.
    const std::string path = writeLog("VID_20240101_120000_gyro.csv", "0.1,0.2,0.3,123456789012345\n"
                                                                     "0.1,0.2,0.3,123456794012345\n"
                                                                     "0.4,0.5,0.6,123456799012345\n");
    const GyroLog log = GyroLog::load(path);
    EXPECT_EQ(log.layout, "opencamera-sensors");
    EXPECT_EQ(log.orientation, "Xyz");
    EXPECT_EQ(log.timeOrigin, 0.0);  // a clock since boot: seconds as they are
    EXPECT_NEAR(log.times[0], 123456.789012345, 1e-9);
    EXPECT_NEAR(log.times[1] - log.times[0], 0.005, 1e-9);
    EXPECT_LT(norm(Vec3d(log.rates.ptr<double>(2)) - Vec3d(0.4, -0.5, -0.6)), 1e-15);
    // The same rows under another name are no known layout.
    expectErrorNamingEach(writeLog("phone.csv", "0.1,0.2,0.3,123456789012345\n0.1,0.2,0.3,123456794012345\n"),
                          {"missing header", "OpenCamera Sensors"});
}

TEST(GyroLog, ColumnsAndUnitsGivenByOptions)
{
    GyroLogOptions options;
    options.columns = " Timestamp_ms , wx,wy, WZ ";
    options.timeUnit = "ms";
    options.rateUnit = "deg/s";
    const GyroLog log = GyroLog::load(writeLog("named.csv", "# exported\ntimestamp_ms,temp,wz,wy,wx,label\n"
                                                            "1000,31,30,20,10,still\n1005,31,30,20,10,still\n"),
                                      options);
    EXPECT_EQ(log.layout, "columns");
    EXPECT_EQ(log.orientation, "XYZ");
    EXPECT_DOUBLE_EQ(log.times[1], 1.005);
    EXPECT_LT(norm(Vec3d(log.rates.ptr<double>(0)) - Vec3d(10, 20, 30) * kDeg), 1e-15);
    // Positions: a file without a header row, and one whose header row is skipped.
    options.columns = "4,1,2,3";
    options.timeUnit = "us";
    options.rateUnit = "";
    for (const char* header : {"", "a,b,c,d\n"})
    {
        const GyroLog byPosition = GyroLog::load(writeLog("positions.csv", std::string(header) +
                                                                              "0.1,0.2,0.3,1000\n0.1,0.2,0.3,6000\n"),
                                                 options);
        EXPECT_DOUBLE_EQ(byPosition.times[1], 0.006);
        EXPECT_EQ(Vec3d(byPosition.rates.ptr<double>(1)), Vec3d(0.1, 0.2, 0.3));
    }
    // A known layout's units replaced: t,gx,gy,gz in milliseconds and deg/s.
    GyroLogOptions units;
    units.timeUnit = "ms";
    units.rateUnit = "deg/s";
    const GyroLog csv = GyroLog::load(writeLog("units.csv", "t,gx,gy,gz\n0,90,0,0\n5,90,0,0\n"), units);
    EXPECT_EQ(csv.layout, "csv");
    EXPECT_DOUBLE_EQ(csv.times[1], 0.005);
    EXPECT_NEAR(csv.rates.at<double>(1, 0), CV_PI / 2, 1e-15);
}

TEST(GyroLog, EpochTimesKeepTheirPrecision)
{
    // Decimal epoch seconds and epoch milliseconds: the fraction survives the origin.
    GyroLogOptions options;
    options.columns = "t,x,y,z";
    const GyroLog seconds = GyroLog::load(writeLog("epoch_s.csv", "t,x,y,z\n1700000000.000000001,0,0,0\n"
                                                                  "1700000000.005000002,0,0,0\n"),
                                          options);
    EXPECT_EQ(seconds.timeOrigin, 1700000000.0);
    EXPECT_NEAR(seconds.times[0], 1e-9, 1e-18);
    EXPECT_NEAR(seconds.times[1], 0.005000002, 1e-15);
    options.timeUnit = "ms";
    const GyroLog ms = GyroLog::load(writeLog("epoch_ms.csv", "t,x,y,z\n1700000000999.5,0,0,0\n"
                                                              "1700000001004.5,0,0,0\n"),
                                     options);
    EXPECT_EQ(ms.timeOrigin, 1700000000.0);
    EXPECT_NEAR(ms.times[0], 0.9995, 1e-15);
    EXPECT_NEAR(ms.times[1], 1.0045, 1e-15);
    // Before 1970: the origin is the whole second below the first sample.
    options.timeUnit = "s";
    const GyroLog negative = GyroLog::load(writeLog("epoch_neg.csv", "t,x,y,z\n-2000000.25,0,0,0\n-2000000.2,0,0,0\n"),
                                           options);
    EXPECT_EQ(negative.timeOrigin, -2000001.0);
    EXPECT_NEAR(negative.times[0], 0.75, 1e-15);
    EXPECT_NEAR(negative.times[1], 0.8, 1e-15);
}

TEST(GyroLog, GivenTimeOrigin)
{
    // The origin a frame log counts from: whole seconds exactly, a fraction to the file's unit (ns).
    const std::string path = writeLog("origin.csv", "time,seconds_elapsed,z,y,x\n1767620467350470700,0,0,0,0\n"
                                                    "1767620467355470701,0.005,0,0,0\n");
    GyroLogOptions options;
    options.timeOrigin = 1767620460.0;
    const GyroLog whole = GyroLog::load(path, options);
    EXPECT_EQ(whole.timeOrigin, 1767620460.0);
    EXPECT_NEAR(whole.times[0], 7.3504707, 1e-14);
    EXPECT_NEAR(whole.times[1] - whole.times[0], 0.005000001, 1e-14);
    options.timeOrigin = 1767620467.25;
    const GyroLog fraction = GyroLog::load(path, options);
    EXPECT_EQ(fraction.timeOrigin, 1767620467.25);
    EXPECT_NEAR(fraction.times[0], 0.1004707, 1e-15);
    options.timeOrigin = 0;  // the clock as it reads, in doubles
    const GyroLog absolute = GyroLog::load(path, options);
    EXPECT_EQ(absolute.timeOrigin, 0.0);
    EXPECT_NEAR(absolute.times[0], 1767620467.3504707, 1e-6);
    options.timeOrigin = std::numeric_limits<double>::infinity();
    dynblur_test::expectErrorNaming([&] { GyroLog::load(path, options); }, "options.timeOrigin");
}

TEST(GyroLog, DropsWholeRepeatsOnRequest)
{
    const std::string text = "time,seconds_elapsed,z,y,x\n1000000000,0,0,0,1\n1005000000,0.005,0,0,1\n"
                             "1005000000,0.005,0,0,1\n1010000000,0.01,0,0,1\n";
    GyroLogOptions options;
    options.dropRepeatedSamples = true;
    const GyroLog log = GyroLog::load(writeLog("repeats.csv", text), options);
    EXPECT_EQ(log.times.size(), 3u);
    EXPECT_EQ(log.droppedSamples, 1);
    EXPECT_EQ(GyroLog::load(writeLog("norepeats.csv", "t,gx,gy,gz\n0,0,0,0\n1,0,0,0\n")).droppedSamples, 0);
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

TEST(GyroLogBadInput, LayoutsColumnsAndRepeats)
{
    // A header row of no known layout: the message lists the layouts and the options for another CSV.
    expectRefused("unknown.csv", "time,x,y,z\n0,1,2,3\n0.005,1,2,3\n",
                  {":1:", "missing header", "'time,x,y,z'", "t,gx,gy,gz", "Sensor Logger", "OpenCamera Sensors",
                   "options.columns", "options.timeUnit", "options.rateUnit", "--gyro-columns"});
    expectRefused("nox.csv", "time,seconds_elapsed,z,y\n1000000000,0,0,0\n", {":1:", "missing header"});
    expectRefused("comments.csv", "# nothing but a comment\n", {"only comment lines", "options.columns"});
    // Columns that options.columns names and the file lacks.
    GyroLogOptions columns;
    columns.columns = "t,x,y,w";
    expectRefused("missing.csv", "t,x,y,z\n0,1,2,3\n", {":1:", "no column 'w'", "'t,x,y,z'"}, columns);
    expectRefused("data.csv", "# rows only\n0,1,2,3\n0.005,1,2,3\n", {":2:", "first row is data", "positions"}, columns);
    columns.columns = "1,2,3,9";
    expectRefused("beyond.csv", "0,1,2,3\n0.005,1,2,3\n", {":1:", "position 9", "4 columns"}, columns);
    columns.columns = "t,x,X,z";
    expectRefused("twice.csv", "t,x,y,z\n0,1,2,3\n", {":1:", "twice"}, columns);
    columns.columns = "t,x,y,z";
    expectRefused("text.csv", "t,x,y,z,note\n0,1,2,3,ok\n0.005,1,two,3,ok\n", {":3:", "field 'y'", "'two'"}, columns);
    expectRefused("huge.csv", "t,x,y,z\n1e19,1,2,3\n2e19,1,2,3\n", {":2:", "beyond any clock"}, columns);
    // A Sensor Logger file with a short row, a repeated sample, a repeated time, a gap.
    const std::string phone = "time,seconds_elapsed,z,y,x\n1000000000,0,0,0,1\n1005000000,0.005,0,0,1\n";
    expectRefused("short_row.csv", phone + "1010000000,0.01,0,0\n", {":4:", "4 fields", "names 5"});
    expectRefused("short_gyro.csv", "0.1,0.2,0.3,1000000\n0.1,0.2,1005000\n", {":2:", "3 fields", "first row has 4"});
    expectRefused("repeat.csv", phone + "1005000000,0.005,0,0,1\n",
                  {":4:", "strictly increasing", "options.dropRepeatedSamples", "--gyro-drop-repeats"});
    GyroLogOptions drop;
    drop.dropRepeatedSamples = true;
    expectRefused("retimed.csv", phone + "1005000000,0.005,0,0,2\n", {":4:", "field 'time'", "strictly increasing"},
                  drop);
    expectRefused("phone_gap.csv", phone + "1010000000,0.01,0,0,1\n1030000000,0.03,0,0,1\n1035000000,0.035,0,0,1\n",
                  {":5:", "gap", "line 4"});
    // gcsv readout fields out of their range.
    const std::string head = "GYROFLOW IMU LOG\nversion,1.3\norientation,XYZ\ntscale,1\ngscale,1\n";
    const std::string rows = "t,gx,gy,gz\n0,0,0,0\n1,0,0,0\n";
    expectRefused("readout.gcsv", head + "frame_readout_time,-1\n" + rows, {":6:", "frame_readout_time", ">= 0"});
    expectRefused("readout2.gcsv", head + "frame_readout_time,fast\n" + rows, {":6:", "milliseconds"});
    expectRefused("direction.gcsv", head + "frame_readout_direction,4\n" + rows,
                  {":6:", "frame_readout_direction", "3 (right to left)"});
    // CSV options on a gcsv file.
    GyroLogOptions csvOnly;
    csvOnly.timeUnit = "ms";
    expectRefused("units.gcsv", head + rows, {"gcsv", "options.timeUnit = 'ms'"}, csvOnly);
}

TEST(GyroLogBadInput, UnitAndAxisOptions)
{
    const std::string path = writeLog("ok.csv", "t,gx,gy,gz\n0,0,0,0\n1,0,0,0\n");
    const auto refused = [&](const GyroLogOptions& o, std::initializer_list<const char*> words) {
        for (const char* word : words)
            dynblur_test::expectErrorNaming([&] { GyroLog::load(path, o); }, word);
    };
    GyroLogOptions o;
    o.timeUnit = "min";
    refused(o, {"options.timeUnit = 'min'", "'s', 'ms', 'us'", "'ns'"});
    o = GyroLogOptions();
    o.rateUnit = "rpm";
    refused(o, {"options.rateUnit = 'rpm'", "'rad/s', 'deg/s'"});
    o = GyroLogOptions();
    o.timeUnit = "ms";
    o.timeScale = 1e-3;
    refused(o, {"options.timeUnit", "options.timeScale", "give one"});
    o = GyroLogOptions();
    o.rateUnit = "deg/s";
    o.rateScale = kDeg;
    refused(o, {"options.rateUnit", "options.rateScale"});
    o = GyroLogOptions();
    o.gcsvAxes = "opencv";
    refused(o, {"options.gcsvAxes = 'opencv'", "'camera'", "'gyroflow'"});
    for (const char* bad : {"t,gx,gy", "t,,gy,gz", "t,gx,gy,gz,extra"})
    {
        o = GyroLogOptions();
        o.columns = bad;
        refused(o, {"options.columns", "four columns"});
    }
    // Every accepted spelling of a unit.
    for (const char* unit : {"s", "ms", "us", "\xC2\xB5s", "ns", " MS "})
    {
        o = GyroLogOptions();
        o.timeUnit = unit;
        EXPECT_NO_THROW(GyroLog::load(path, o)) << unit;
    }
}

}  // namespace
