// SPDX-License-Identifier: Apache-2.0
// A mount's recording (samples/support): the command log's level columns per axis, read and written,
// each axis's schedule around a frame, and the refusals of a log whose axes are not the mount's.
#include "bad_input_rows.hpp"

#include "commanded_motion.hpp"
#include "recording.hpp"

#include <gtest/gtest.h>
#include <opencv2/dynblur.hpp>

#include <string>
#include <vector>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;
using namespace dynblur_test;

namespace {

const double kDeg = CV_PI / 180.0;

Ptr<Mount> panTilt()
{
    Ptr<Mount> mount = Mount::create();
    mount->addAxis(Vec3d(0, 1, 0), Plant::create(14.4, 0.12, kDeg), -16, 16);
    mount->addAxis(Vec3d(1, 0, 0), Plant::create(14.4, 0.12, kDeg), -16, 16);
    return mount;
}

std::vector<FrameRecord> frames(int count)
{
    std::vector<FrameRecord> log;
    for (int k = 0; k < count; k++)
        log.push_back({k, k / 30.0, 0.008, 6.944e-5});
    return log;
}

}  // namespace

TEST(MountRecording, CommandLogCarriesEachAxisAndOneAxisReadsAsBefore)
{
    const CommandLog one = parseCommandLog("t,level\n0,0\n0.5,16\n0.51,10\n", "one.csv");
    ASSERT_EQ(one.axisCount(), 1);
    EXPECT_EQ(one.levels[0], std::vector<int>({0, 16, 10}));

    const CommandLog two = parseCommandLog("# pan, tilt\nt,level0,level1\n0,0,0\n0.5,16,0\n0.52,16,8\n", "two.csv");
    ASSERT_EQ(two.axisCount(), 2);
    EXPECT_EQ(two.levels[1], std::vector<int>({0, 0, 8}));
    const std::vector<SwitchSchedule> around = two.schedulesAround(0.4, 0.6);
    ASSERT_EQ(around.size(), 2u);
    EXPECT_EQ(around[0].finalLevel(), 16);
    EXPECT_EQ(around[1].finalLevel(), 8);

    const std::string path = tempPath("two_axes.csv");
    writeCommandLog(path, two);
    const CommandLog back = readCommandLog(path);
    EXPECT_EQ(back.times, two.times);
    EXPECT_EQ(back.levels, two.levels);
}

TEST(MountRecording, AppendMoveMergesTheAxesSwitches)
{
    CommandLog log;
    log.times = {0.0};
    log.levels = {{0}, {0}};
    log.appendMove({SwitchSchedule({0.5, 0.52}, {10, 6}, 0), SwitchSchedule()}, 1.0);
    EXPECT_EQ(log.times, std::vector<double>({0.0, 1.5, 1.52}));
    EXPECT_EQ(log.levels[0], std::vector<int>({0, 10, 6}));
    EXPECT_EQ(log.levels[1], std::vector<int>({0, 0, 0}));  // an empty schedule holds its axis
}

TEST(MountRecording, AxesThatAreNotTheMountsAreRefusedByName)
{
    const CommandLog one = parseCommandLog("t,level\n0,0\n0.5,10\n", "one.csv");
    const CommandLog two = parseCommandLog("t,level0,level1\n0,0,0\n0.5,10,6\n", "two.csv");
    refuseAll({
        {"checkFramesMeetCommands", "one axis logged for a pan-tilt mount",
         [&] { checkFramesMeetCommands(frames(30), one, CommandedMotion(Ptr<Plant>(), panTilt()), 480, "one.csv", "pan_tilt.yml"); },
         {"one.csv", "pan_tilt.yml", "--mount", "2 axes", "level0"}},
        {"checkFramesMeetCommands", "two axes logged without a mount",
         [&] { checkFramesMeetCommands(frames(30), two, CommandedMotion(Plant::create(14.4, 0.12, kDeg), Ptr<Mount>()), 480, "two.csv"); },
         {"two.csv", "--mount"}},
        {"parseCommandLog", "both level and level0", [] { parseCommandLog("t,level,level0\n0,0,0\n", "both.csv"); },
         {"both.csv", "level0"}},
        {"parseCommandLog", "no level column", [] { parseCommandLog("t,pan\n0,0\n", "none.csv"); },
         {"none.csv", "level0", "level"}},
        {"parseCommandLog", "an axis's level not an integer", [] { parseCommandLog("t,level0,level1\n0,0,0.5\n", "half.csv"); },
         {"half.csv:2", "level1", "integer"}},
    });
}

TEST(MountRecording, AMountFileWithAPlantMissingIsRefusedByName)
{
    const std::string path = writeFile("no_plant_mount.yml",
                                       "%YAML:1.0\n---\naxisCount: 2\naxis0: [0., 1., 0.]\naxis0_naturalFreqHz: 14.4\n"
                                       "axis0_dampingRatio: 0.12\naxis0_gain: 0.01745\naxis0_levels: [-16, 16]\n"
                                       "axis1: [1., 0., 0.]\naxis1_levels: [-16, 16]\n");
    refuseAll({{"Mount::load", "axis 1 without its plant", [&] { Mount::load(path); },
                {"no_plant_mount.yml", "axis1_naturalFreqHz"}}});
}

TEST(MountRecording, ScheduleFromAStillStartsAtThatStillsLevels)
{
    // Out to (16, 8) and back: a frame of the move back starts from the still at the far end.
    const CommandLog log = parseCommandLog("t,level0,level1\n0,0,0\n0.5,16,8\n1.1,0,0\n", "back.csv");
    const std::vector<SwitchSchedule> settled = log.schedulesAround(1.09, 1.15);
    EXPECT_EQ(settled[0].initialLevel, 0);  // 3 s of settling reach back past the move out
    const std::vector<SwitchSchedule> fromStill = log.schedulesAround(1.09, 1.15, 0.9);
    EXPECT_EQ(fromStill[0].initialLevel, 16);
    EXPECT_EQ(fromStill[1].initialLevel, 8);
    EXPECT_EQ(fromStill[1].finalLevel(), 0);
}
