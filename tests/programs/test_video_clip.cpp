// SPDX-License-Identifier: Apache-2.0
// A hand-held clip as the programs read it: a video's frame times from its container or its rate
// (samples/support/video_clip.hpp), and the timing file of a clip's calibration with the shutter it
// was told (gyro_recording.hpp).
#include "gyro_recording.hpp"
#include "test_common.hpp"
#include "video_clip.hpp"

#include <gtest/gtest.h>
#include <opencv2/dynblur.hpp>
#include <opencv2/videoio.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <unistd.h>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;
using dynblur_test::expectErrorNaming;

namespace {

std::string scratch(const std::string& name)
{
    return ::testing::TempDir() + format("dynblur_video_clip_%d_", (int)::getpid()) + name;
}

}  // namespace

TEST(VideoClip, ClockFromTimestampsElseTheRate)
{
    EXPECT_EQ(chooseFrameClock(0, 33.3667, 29.97, "--video", "a.mp4"), FrameClock::Timestamps);
    // A container that stamps every frame 0 (or not at all) is timed by its rate.
    EXPECT_EQ(chooseFrameClock(0, 0, 30, "--video", "a.avi"), FrameClock::FrameIndex);
    EXPECT_EQ(chooseFrameClock(NAN, NAN, 25, "--video", "a.avi"), FrameClock::FrameIndex);
    EXPECT_EQ(chooseFrameClock(40, 40, 25, "--video", "a.avi"), FrameClock::FrameIndex);
    // Neither: refused, naming the option, the file and the way out.
    const auto neither = [] { chooseFrameClock(0, 0, 0, "--video", "raw.h264"); };
    expectErrorNaming(neither, "--video: 'raw.h264' has no frame timestamps and no frame rate");
    expectErrorNaming(neither, "--frames FRAMES.csv");
    expectErrorNaming([] { chooseFrameClock(0, 0, 5000, "--video", "a.avi"); }, "no frame rate");
}

TEST(VideoClip, ReadsAVideoWithItsFrameTimes)
{
    const std::string path = scratch("times.avi");
    {
        VideoWriter writer(path, VideoWriter::fourcc('M', 'J', 'P', 'G'), 25.0, Size(64, 48), true);
        ASSERT_TRUE(writer.isOpened());
        for (int k = 0; k < 6; k++)
            writer.write(Mat(48, 64, CV_8UC3, Scalar(40 * k, 0, 0)));
    }
    VideoClip clip;
    clip.open(path, "--video");
    EXPECT_EQ(clip.frameSize(), Size(64, 48));
    EXPECT_DOUBLE_EQ(clip.framePeriod(), 0.04);
    Mat image, previous;
    double seconds = 0;
    int frames = 0;
    while (clip.read(image, seconds))
    {
        // Each frame at k / 25 s, in its own buffer (a caller may keep the one before).
        EXPECT_NEAR(seconds, frames * 0.04, 1e-6) << "frame " << frames;
        EXPECT_NEAR(mean(image)[0], 40 * frames, 3.0) << "frame " << frames;
        EXPECT_NE(image.data, previous.data);
        previous = image;
        frames++;
    }
    EXPECT_EQ(frames, 6);
    EXPECT_EQ(clip.framesRead(), 6);
    EXPECT_EQ(clip.clock(), FrameClock::Timestamps);
    std::remove(path.c_str());
}

/* A phone's portrait clip: stored sideways, with a 90-degree display matrix in its track header. It is
   read as stored (64 wide, its first row bright as written), since its rows are the sensor's. */
TEST(VideoClip, ReadsAPortraitClipAsStored)
{
    const std::string path = scratch("portrait.mp4");
    {
        VideoWriter writer(path, VideoWriter::fourcc('m', 'p', '4', 'v'), 30.0, Size(64, 48), true);
        ASSERT_TRUE(writer.isOpened());
        Mat frame(48, 64, CV_8UC3, Scalar::all(0));
        frame.rowRange(0, 8).setTo(Scalar::all(255));
        for (int k = 0; k < 3; k++)
            writer.write(frame);
    }
    // The 'tkhd' box (ISO/IEC 14496-12 8.3.2, version 0): its 3x3 matrix, 16.16 fixed point, starts
    // 48 bytes into the box; {0, 1, 0; -1, 0, 0; 0, 0, 1} is a turn of 90 degrees.
    std::string bytes;
    {
        std::ifstream in(path, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const size_t box = bytes.find("tkhd");
    ASSERT_NE(box, std::string::npos);
    ASSERT_EQ(bytes[box + 4], 0) << "a version-0 track header";
    const unsigned char matrix[36] = {0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0xff, 0xff, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                      0, 0, 0, 0, 0, 0, 0, 0, 0x40, 0, 0, 0};
    bytes.replace(box - 4 + 48, 36, reinterpret_cast<const char*>(matrix), 36);
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out << bytes;
    }
    VideoClip clip;
    clip.open(path, "--video");
    EXPECT_EQ(clip.storedTurnDegrees() % 180, 90);
    EXPECT_EQ(clip.frameSize(), Size(64, 48));
    Mat image;
    double seconds = 0;
    ASSERT_TRUE(clip.read(image, seconds));
    EXPECT_GT(mean(image.rowRange(0, 6))[0], 200.0);
    EXPECT_NE(clip.clockText().find("read and written as stored"), std::string::npos) << clip.clockText();
    std::remove(path.c_str());
}

TEST(VideoClip, RefusesWhatHasNoTimes)
{
    VideoClip clip;
    expectErrorNaming([&] { clip.open("frames/frame_%04d.png", "--video"); },
                      "--video: 'frames/frame_%04d.png' is an image sequence");
    const std::string missing = scratch("missing.mp4");
    expectErrorNaming([&] { clip.open(missing, "--video"); }, "--video: '" + missing + "' does not exist");
    const std::string garbage = scratch("garbage.mp4");
    {
        FILE* f = std::fopen(garbage.c_str(), "w");
        ASSERT_NE(f, nullptr);
        std::fputs("not a video\n", f);
        std::fclose(f);
    }
    expectErrorNaming([&] { clip.open(garbage, "--video"); }, "--video: cannot open '" + garbage + "'");
    std::remove(garbage.c_str());
}

/* The timing file of a clip keeps the shutter the calibration was told beside the correction, so that
   the restorer's line delay is the calibrated one whatever it is told; the library reads it as ever. */
TEST(ClipCalibrationFile, KeepsTheShutterItWasTold)
{
    TimingCalibration t;
    t.correction.timeOffset = 1.3;
    t.correction.lineDelayScale = 1.19;
    t.axisCorrection = Matx33d(0, 1, 0, -1, 0, 0, 0, 0, 1);
    ToldShutter told;
    told.exposure = 0.01;
    told.lineDelay = 1.0 / 30 / 2 / 480;
    const std::string path = scratch("timing.yml");
    saveClipCalibration(t, told, path);
    const TimingCalibration read = TimingCalibration::load(path);
    EXPECT_DOUBLE_EQ(read.correction.timeOffset, 1.3);
    EXPECT_DOUBLE_EQ(read.correction.lineDelayScale, 1.19);
    EXPECT_EQ(read.axisCorrection, t.axisCorrection);
    const ToldShutter back = toldShutterOf(path);
    EXPECT_NEAR(back.exposure, 0.01, 1e-12);
    EXPECT_NEAR(back.lineDelay, told.lineDelay, 1e-15);
    EXPECT_NE(back.lineDelayFrom.find("--timing"), std::string::npos);
    std::remove(path.c_str());
    // A calibration against stills records no shutter: its frame log tells it.
    t.save(path);
    EXPECT_TRUE(std::isnan(toldShutterOf(path).lineDelay));
    EXPECT_TRUE(std::isnan(toldShutterOf(path).exposure));
    std::remove(path.c_str());
    // Only YAML takes the extra keys.
    const std::string xml = scratch("timing.xml");
    expectErrorNaming([&] { saveClipCalibration(t, told, xml); }, "--out: '" + xml + "'");
    EXPECT_FALSE(std::ifstream(xml).good());
}
