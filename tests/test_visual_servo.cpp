// The visual-servoing loop (samples/common/visual_servo.cpp, the dynblur_visual_servo program):
// convergence from 8° off, tag detection raw vs restored while moving, and the loop over the
// actuator bus against the in-process simulator on a loopback port.
#include "actuator_sim.hpp"
#include "visual_servo.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

using namespace cv::dynblur;
using namespace dynblur_samples;

namespace {

double seconds(std::chrono::steady_clock::time_point since)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

}  // namespace

TEST(ServoLoop, ConvergesFromEightDegreesAndRestorationFindsTheTagWhileMoving)
{
    ServoConfig config;  // 8° off, λ = 1, 0.05°/level, robust planner, 320×240 at 30 fps, PSF_ROWS
    config.cycles = 5;
    config.keepImages = false;
    const auto start = std::chrono::steady_clock::now();
    const ServoReport report = runVisualServo(config);
    ASSERT_EQ(report.cycles.size(), 5u);

    // The error reaches ≤ 1 px (true geometry and as measured in the restored frame) within
    // 2 cycles and stays there.
    const int converged = report.cyclesToWithin(1.0);
    EXPECT_GE(converged, 0);
    EXPECT_LE(converged, 2);
    EXPECT_GT(report.cycles.front().trueErrorPx, 40.0);  // 8° at fx = 300 px
    EXPECT_LE(report.cycles.back().trueErrorPx, 1.0);

    // Frames taken while the mechanism moves (windows I–III): the tag is found in the restored
    // frames at least twice as often as in the raw ones.
    int frames = 0, raw = 0, restored = 0;
    report.detectionCounts(0, frames, raw, restored);
    std::printf("[servo test] converged (<= 1 px) from cycle %d; windows I-III: %d frames, tag raw %d, restored %d; "
                "restoration %.0f ms/frame; %.1f s\n",
                converged, frames, raw, restored, 1e3 * report.meanRestoreSec(), seconds(start));
    EXPECT_GT(frames, 0);
    EXPECT_GT(restored, 0);
    EXPECT_GE(restored, 2 * raw);
    // Restoration is well under a second per frame.
    EXPECT_LT(report.meanRestoreSec(), 0.5);
}

TEST(ServoBus, DrivesTheActuatorSimulatorOverModbusTcp)
{
    SimConfig sim;
    sim.plant = Plant::create(14.4, 0.12, 0.05 * CV_PI / 180.0);
    sim.maxLevel = 400;
    sim.tcpPort = 0;  // a free loopback port
    ActuatorSim simulator(sim);
    simulator.start();

    ServoConfig config;
    config.cycles = 3;
    config.keepImages = false;
    config.busUri = "tcp://127.0.0.1:" + std::to_string(simulator.tcpPort());
    const ServoReport report = runVisualServo(config);
    ASSERT_EQ(report.cycles.size(), 3u);
    EXPECT_GE(simulator.startCount(), 1);
    // The controller holds the level the servo commanded last.
    EXPECT_EQ(simulator.currentLevel(), report.cycles.back().toLevel);
    for (const ServoCycle& c : report.cycles)
    {
        EXPECT_GE(c.startLatencyMs, 0.0);
        EXPECT_LT(c.startLatencyMs, 100.0);
    }
    EXPECT_LE(report.cycles.back().trueErrorPx, 1.0);
    simulator.stop();
}
