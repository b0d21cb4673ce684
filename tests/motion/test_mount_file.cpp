// SPDX-License-Identifier: Apache-2.0
// Mount::save and Mount::load: the round trip, the shipped pan-tilt file and every refusal.
#include <gtest/gtest.h>

#include <opencv2/dynblur.hpp>

#include "test_common.hpp"

#include <cstdio>
#include <fstream>
#include <string>

using namespace cv;
using namespace cv::dynblur;

namespace {

std::string repoRoot()
{
    const std::string file = __FILE__;
    return file.substr(0, file.rfind("/tests/motion/"));
}

std::string tempFile(const std::string& name)
{
    return (std::string(::testing::TempDir()) + "dynblur_mount_") + name;
}

//! The two-axis file of `pan_tilt.yml` with `line` of it replaced by `replacement` ("" drops it).
std::string editedPanTilt(const std::string& line, const std::string& replacement)
{
    std::ifstream in(repoRoot() + "/samples/data/pan_tilt.yml");
    std::string text, l;
    bool found = false;
    while (std::getline(in, l))
    {
        if (l.rfind(line, 0) == 0)
        {
            found = true;
            if (!replacement.empty())
                text += replacement + "\n";
            continue;
        }
        text += l + "\n";
    }
    EXPECT_TRUE(found) << line;
    const std::string path = tempFile("edited.yml");
    std::ofstream(path) << text;
    return path;
}

}  // namespace

TEST(MountFile, ShippedPanTiltIsTheSeedOnPanAndTilt)
{
    const Ptr<Mount> mount = Mount::load(repoRoot() + "/samples/data/pan_tilt.yml");
    ASSERT_EQ(mount->getAxisCount(), 2);
    EXPECT_EQ(mount->getAxis(0), Vec3d(0, 1, 0));
    EXPECT_EQ(mount->getAxis(1), Vec3d(1, 0, 0));
    for (int i = 0; i < 2; i++)
    {
        EXPECT_DOUBLE_EQ(mount->getPlant(i)->getNaturalFreqHz(), 14.4);
        EXPECT_DOUBLE_EQ(mount->getPlant(i)->getDampingRatio(), 0.12);
        EXPECT_DOUBLE_EQ(mount->getPlant(i)->getGain(), CV_PI / 180);
        EXPECT_EQ(mount->getLevelRange(i), Vec2i(-16, 16));
    }
}

TEST(MountFile, RoundTripKeepsEveryValueInEveryFormat)
{
    Ptr<Mount> mount = Mount::create();
    mount->addAxis(Vec3d(0.1, 1, 0), Plant::create(14.4, 0.12, 0.2 * CV_PI / 180), -200, 150);
    mount->addAxis(Vec3d(1, 0, 0.2), Plant::create(11.0, 0.15, -0.25 * CV_PI / 180), -120, 120);
    mount->addAxis(Vec3d(0, 0, 1), Plant::create(31.7, 0.05, 1e-3), 0, 40);
    for (const char* ext : {".yml", ".xml", ".json"})
    {
        const std::string path = tempFile(std::string("round") + ext);
        mount->save(path);
        const Ptr<Mount> back = Mount::load(path);
        ASSERT_EQ(back->getAxisCount(), 3) << ext;
        for (int i = 0; i < 3; i++)
        {
            // addAxis normalises again: the unit vector read back may differ in its last bit.
            EXPECT_LT(norm(back->getAxis(i) - mount->getAxis(i)), 1e-15) << ext << " axis " << i;
            EXPECT_EQ(back->getPlant(i)->getNaturalFreqHz(), mount->getPlant(i)->getNaturalFreqHz());
            EXPECT_EQ(back->getPlant(i)->getDampingRatio(), mount->getPlant(i)->getDampingRatio());
            EXPECT_EQ(back->getPlant(i)->getGain(), mount->getPlant(i)->getGain());
            EXPECT_EQ(back->getLevelRange(i), mount->getLevelRange(i));
        }
        std::remove(path.c_str());
    }
}

TEST(MountFileBadInput, EveryRefusalNamesTheFileAndEntry)
{
    using dynblur_test::expectErrorNaming;
    const std::pair<std::pair<const char*, const char*>, const char*> cases[] = {
        {{"axis1: ", "axis1: [ 1., 0.002, 0. ]"}, "axis1 = [1, 0.002, 0] has norm 1.000002"},
        {{"axis1: ", "axis1: [ 0., 0., 0. ]"}, "axis1 = [0, 0, 0] has norm 0"},
        {{"axis1: ", "axis1: [ 1., 0. ]"}, "axis1 has 2 values; 3 are expected"},
        {{"axis1: ", "axis1: [ 0., -1., 0. ]"}, "is parallel to axis 0"},
        {{"axis1_gain", ""}, "has no entry 'axis1_gain'"},
        {{"axis0_naturalFreqHz", ""}, "has no entry 'axis0_naturalFreqHz'"},
        {{"axis1_dampingRatio", "axis1_dampingRatio: 1.5"}, "axis 1's plant"},
        {{"axis0_levels", "axis0_levels: [ 16, -16 ]"}, "axis0_levels must be [min, max] with min <= max"},
        {{"axis0_levels", ""}, "has no entry 'axis0_levels'"},
        {{"axisCount", "axisCount: 3"}, "axisCount = 3 but the file has no entry 'axis2'"},
        {{"axisCount", "axisCount: 1"}, "axisCount = 1 but the file has an entry 'axis1'"},
        {{"axisCount", "axisCount: 0"}, "axisCount = 0 must lie in [1, 16]"},
        {{"axisCount", ""}, "has no entry 'axisCount'"},
        {{"axisCount", "axisCount: two"}, "axisCount"},
    };
    for (const auto& c : cases)
    {
        const std::string path = editedPanTilt(c.first.first, c.first.second);
        SCOPED_TRACE(c.second);
        expectErrorNaming([&] { Mount::load(path); }, c.second);
        expectErrorNaming([&] { Mount::load(path); }, path);
    }
    expectErrorNaming([] { Mount::load(tempFile("absent.yml")); }, "absent.yml");
    expectErrorNaming([] { Mount::create()->save(tempFile("empty.yml")); }, "the mount has no axis");
    Ptr<Mount> ode = Mount::create();
    ode->addAxis(Vec3d(1, 0, 0), OdePlant::createLinear(), -1, 1);
    expectErrorNaming([&] { ode->save(tempFile("ode.yml")); }, "axis 0's plant (dynblur.OdePlant) has no file form");
    expectErrorNaming([&] { ode->save("/nonexistent-folder/mount.yml"); }, "dynblur.OdePlant");
    Ptr<Mount> good = Mount::load(repoRoot() + "/samples/data/pan_tilt.yml");
    expectErrorNaming([&] { good->save("/nonexistent-folder/mount.yml"); }, "/nonexistent-folder/mount");
}
