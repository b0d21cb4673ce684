// SPDX-License-Identifier: Apache-2.0
// The gyro log's command-line options (samples/support/gyro_recording.hpp, gyroLogOptions and
// gyroOptions): each read into GyroLogOptions, each bad value refused naming the option.
#include "gyro_recording.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

using namespace dynblur_samples;

namespace {

CliArgs parse(std::vector<std::string> words)
{
    CliOptions options("dynblur_gyro_example");
    options.group(gyroLogOptions("Gyro:", "A hand-held recording."));
    words.insert(words.begin(), "dynblur_gyro_example");
    std::vector<char*> argv;
    for (std::string& word : words)
        argv.push_back(&word[0]);
    return options.parse(int(argv.size()), argv.data());
}

cv::dynblur::GyroLogOptions read(const std::vector<std::string>& words)
{
    cv::Vec3d bias;
    return gyroOptions(parse(words), bias);
}

// The message of the std::runtime_error reading `words` throws ("" when it throws none).
std::string refusal(const std::vector<std::string>& words)
{
    try
    {
        read(words);
    }
    catch (const std::runtime_error& e)
    {
        return e.what();
    }
    return "";
}

TEST(GyroOptions, ColumnsUnitsAxesAndRepeats)
{
    const cv::dynblur::GyroLogOptions plain = read({});
    EXPECT_EQ(plain.columns, "");
    EXPECT_EQ(plain.timeUnit, "");
    EXPECT_EQ(plain.rateUnit, "");
    EXPECT_EQ(plain.gcsvAxes, "camera");
    EXPECT_TRUE(std::isnan(plain.timeOrigin));
    EXPECT_FALSE(plain.dropRepeatedSamples);
    const cv::dynblur::GyroLogOptions given = read({"--gyro-columns", "ts,wx,wy,wz", "--gyro-time-unit=ms",
                                                    "--gyro-rate-unit", "deg/s", "--gyro-gcsv-axes", "gyroflow",
                                                    "--gyro-drop-repeats", "--gyro-orientation", "Xyz",
                                                    "--gyro-time-origin", "1.7e9"});
    EXPECT_EQ(given.columns, "ts,wx,wy,wz");
    EXPECT_EQ(given.timeUnit, "ms");
    EXPECT_EQ(given.rateUnit, "deg/s");
    EXPECT_EQ(given.gcsvAxes, "gyroflow");
    EXPECT_TRUE(given.dropRepeatedSamples);
    EXPECT_EQ(given.orientation, "Xyz");
    EXPECT_EQ(given.timeOrigin, 1.7e9);
}

TEST(GyroOptions, BadValuesNameTheOption)
{
    EXPECT_EQ(refusal({"--gyro-time-unit", "min"}), "--gyro-time-unit 'min' is not one of s, ms, us, ns");
    EXPECT_EQ(refusal({"--gyro-rate-unit", "rpm"}), "--gyro-rate-unit 'rpm' is not one of rad/s, deg/s");
    EXPECT_EQ(refusal({"--gyro-gcsv-axes", "opencv"}), "--gyro-gcsv-axes 'opencv' is not one of camera, gyroflow");
    EXPECT_EQ(refusal({"--gyro-gcsv-axes="}), "--gyro-gcsv-axes takes camera or gyroflow");
    EXPECT_NE(refusal({"--gyro-drop-repeats=yes"}), "");  // a flag takes no value
    EXPECT_EQ(refusal({"--gyro-time-origin", "inf"}), "--gyro-time-origin expects a number, got 'inf'");
}

TEST(GyroOptions, UsageShowsEachOptionWithItsValue)
{
    CliOptions options("dynblur_gyro_example");
    options.group(gyroLogOptions("Gyro:", ""));
    const std::string usage = options.usage();
    for (const char* entry : {"--gyro-columns T,X,Y,Z", "--gyro-time-unit UNIT", "--gyro-rate-unit UNIT",
                              "--gyro-gcsv-axes FRAME", "--gyro-time-origin S", "--gyro-drop-repeats"})
        EXPECT_NE(usage.find(entry), std::string::npos) << entry << " not in:\n" << usage;
}

}  // namespace
