// SPDX-License-Identifier: Apache-2.0
// The pan-tilt visual-servoing loop (samples/simulation/pan_tilt_servo.cpp, dynblur_visual_servo
// --mount): convergence after diagonal jumps and along a circle, the target's detection raw vs restored
// in the frames taken while the mount moves, drifted hardware, the bus, and the refusals.
#include "actuator_sim.hpp"
#include "pan_tilt_servo.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;

namespace {

void printDetection(const char* what, const ServoReport& report)
{
    for (const DetectionRow& row : detectionSummary(report))
        std::printf("[pan-tilt test] %s: window %-5s %3d frames: found raw %3d, restored %3d | a tag moved >= %.0f px: "
                    "%3d frames, raw %3d, restored %3d\n",
                    what, row.window.c_str(), row.all.frames, row.all.raw, row.all.restored, kTagBlurredPx,
                    row.tagBlurred.frames, row.tagBlurred.raw, row.tagBlurred.restored);
}

//! The worst number of cycles to ≤ 1 px over the places (-1: a place never reached it).
int worstConvergence(const ServoReport& report)
{
    int worst = 0;
    for (size_t t = 0; t < report.targetsDeg.size(); ++t)
    {
        const int n = report.cyclesToWithin(1.0, int(t));
        if (n < 0)
            return -1;
        worst = std::max(worst, n);
    }
    return worst;
}

std::string errorOf(const PanTiltConfig& config)
{
    try
    {
        runPanTiltServo(config);
    }
    catch (const cv::Exception& e)
    {
        return e.what();
    }
    return "accepted";
}

}  // namespace

TEST(PanTiltServoTrack, ConvergesAfterDiagonalJumpsAndRestorationFindsTheTargetTwiceAsOften)
{
    // The target jumps 3..6° along diagonals to 10 places, 3 cycles each; the latency jitters over a
    // frame period, so the moves start at every phase of the camera's frames.
    PanTiltConfig config = diagonalJumps(10);
    config.loop.keepImages = false;
    const PanTiltReport report = runPanTiltServo(config);
    ASSERT_EQ(report.loop.cycles.size(), 30u);
    for (int t = 0; t < 10; ++t)
    {
        const int n = report.loop.cyclesToWithin(1.0, t);
        EXPECT_GE(n, 0) << "place " << t;
        EXPECT_LE(n, 2) << "place " << t;
    }
    printDetection("diagonal jumps", report.loop);
    const DetectionTally all = report.loop.tally(0), blurred = report.loop.tally(0, kTagBlurredPx);
    std::printf("[pan-tilt test] diagonal jumps: <= 1 px within %d cycle(s) of every jump; restoration %.0f ms/frame\n",
                worstConvergence(report.loop), 1e3 * report.loop.meanRestoreSec());
    EXPECT_GE(all.frames, 25);
    for (const ServoFrame& f : report.loop.frames)
        EXPECT_TRUE(f.restored.found || !f.raw.found) << "frame " << f.index;
    // Measured (docs/quality.md): over the 30 I–III frames 14 raw, 28 restored (2.0×); over the 25
    // where a tag moved >= 2 px 9 raw, 23 restored (2.56×).
    EXPECT_GE(all.restoredRate(), 1.8 * all.rawRate());
    EXPECT_GE(all.restoredRate(), 0.85);
    EXPECT_GE(blurred.frames, 20);
    EXPECT_GE(blurred.restoredRate(), 2.3 * blurred.rawRate());
    EXPECT_GE(blurred.restoredRate(), 0.83);
}

/* The target steps along a 5° circle, 12 places per turn (2.6° apart, the first a 5° step from rest),
   2 cycles each: the loop follows it, and restoration keeps finding it while the mount moves. */
TEST(PanTiltServoCircle, FollowsATargetAlongACircleAndRestorationFindsItMoreOften)
{
    PanTiltConfig config = circleScenario(12);
    config.loop.keepImages = false;
    const PanTiltReport report = runPanTiltServo(config);
    ASSERT_EQ(report.loop.cycles.size(), 24u);
    double worstSettled = 0, sumSettled = 0;  // true error once the loop had one cycle at each place, px
    int settled = 0;
    for (const ServoCycle& c : report.loop.cycles)
        if (c.cycleOfTarget >= 1)
        {
            worstSettled = std::max(worstSettled, c.trueErrorPx);
            sumSettled += c.trueErrorPx;
            ++settled;
        }
    printDetection("circle", report.loop);
    const DetectionTally all = report.loop.tally(0), blurred = report.loop.tally(0, kTagBlurredPx);
    std::printf("[pan-tilt test] circle: <= 1 px within %d cycle(s) of every step; one cycle after a step: error "
                "mean %.2f px, worst %.2f px; restoration %.0f ms/frame\n",
                worstConvergence(report.loop), sumSettled / std::max(settled, 1), worstSettled,
                1e3 * report.loop.meanRestoreSec());
    for (int t = 0; t < 12; ++t)
    {
        const int n = report.loop.cyclesToWithin(1.0, t);
        EXPECT_GE(n, 0) << "place " << t;
        EXPECT_LE(n, 1) << "place " << t;
    }
    EXPECT_EQ(settled, 12);
    // Measured (docs/quality.md): 0.67 px mean, 0.85 px worst one cycle after a step.
    EXPECT_LE(sumSettled / settled, 0.75);
    EXPECT_LE(worstSettled, 0.95);
    for (const ServoFrame& f : report.loop.frames)
        EXPECT_TRUE(f.restored.found || !f.raw.found) << "frame " << f.index;
    // Measured: over the 33 I–III frames 9 raw, 29 restored (3.2×); over the 28 where a tag moved
    // >= 2 px 4 raw, 24 restored (6.0×).
    EXPECT_GE(all.frames, 30);
    EXPECT_GE(all.restoredRate(), 2.9 * all.rawRate());
    EXPECT_GE(all.restoredRate(), 0.79);
    EXPECT_GE(blurred.frames, 25);
    EXPECT_GE(blurred.restoredRate(), 5.4 * blurred.rawRate());
    EXPECT_GE(blurred.restoredRate(), 0.77);
}

/* Over the bus: the pan and the tilt are two axes of the actuator simulator on a loopback port
   (as dynblur_actuator_sim --axes 2 serves them); each move is uploaded to both, verified and started
   by one START, and the loop still centres the target. */
TEST(PanTiltServoBus, DrivesBothAxesOfTheActuatorSimulatorOverModbusTcp)
{
    PanTiltConfig config = diagonalJumps(1);  // one place 4°, 4° off
    config.loop.cycles = 3;
    config.loop.keepImages = false;
    SimConfig sim;
    sim.plant = Plant::create(config.loop.naturalFreqHz, config.loop.dampingRatio,
                              config.loop.gainDegPerLevel * CV_PI / 180.0);
    sim.axes = 2;
    sim.maxLevel = config.loop.maxLevel;
    sim.tcpPort = 0;  // a free loopback port
    ActuatorSim simulator(sim);
    simulator.start();
    config.loop.busUri = "tcp://127.0.0.1:" + std::to_string(simulator.tcpPort());

    const PanTiltReport report = runPanTiltServo(config);
    ASSERT_EQ(report.moves.size(), 3u);
    int moves = 0;
    for (size_t c = 0; c < report.moves.size(); ++c)
    {
        const PanTiltMove& m = report.moves[c];
        if (m.fromLevels == m.toLevels)
        {
            EXPECT_TRUE(m.starts.empty()) << "cycle " << c << ": nothing to move, nothing started";
            continue;
        }
        ++moves;
        // One START ran both axes: one controller instant, one host instant.
        ASSERT_EQ(m.starts.size(), 2u) << "cycle " << c;
        EXPECT_EQ(m.starts[1].controllerStartTime, m.starts[0].controllerStartTime) << "cycle " << c;
        EXPECT_EQ(m.starts[1].hostStartTime, m.starts[0].hostStartTime) << "cycle " << c;
        EXPECT_GE(report.loop.cycles[c].startLatencyMs, 0.0) << "cycle " << c;
    }
    EXPECT_GE(moves, 1);
    EXPECT_EQ(simulator.startCount(), moves);
    const std::vector<SimStartRecord> started = simulator.takeStarts();
    ASSERT_EQ(started.size(), size_t(2 * moves));  // every START started both axes
    EXPECT_EQ(simulator.lastStartHostTime(1), simulator.lastStartHostTime(0));
    // The controller holds the levels the servo commanded last, and the target is centred.
    EXPECT_EQ(simulator.currentLevel(0), report.moves.back().toLevels[0]);
    EXPECT_EQ(simulator.currentLevel(1), report.moves.back().toLevels[1]);
    EXPECT_LE(report.loop.cycles.back().trueErrorPx, 1.0);
    EXPECT_EQ(report.loop.cyclesToWithin(1.0, 0), 1);
    simulator.stop();
}

/* On a head whose axes are both 3 % stiffer than the model (ωn × 1.03 on the pan and on the tilt),
   refining each moving frame against the last still frame keeps the loop converging and keeps
   restoration's detection gain. */
TEST(PanTiltServoDrift, RefinementKeepsTheDetectionGainOnDriftedAxes)
{
    PanTiltConfig config = diagonalJumps(6);
    config.loop.keepImages = false;
    config.loop.trueFreqScale = 1.03;
    DetectionTally tallies[2];
    for (int refine = 0; refine < 2; refine++)
    {
        config.loop.refine = refine == 1;
        const PanTiltReport report = runPanTiltServo(config);
        for (int t = 0; t < 6; ++t)
        {
            const int n = report.loop.cyclesToWithin(1.0, t);
            EXPECT_GE(n, 0) << "place " << t << (refine ? ", refined" : ", nominal");
            EXPECT_LE(n, 2) << "place " << t << (refine ? ", refined" : ", nominal");
        }
        tallies[refine] = report.loop.tally(0, kTagBlurredPx);
        int rejected = 0;
        for (const ServoFrame& f : report.loop.frames)
            rejected += f.window != EXPOSURE_IV && !f.correction.applied ? 1 : 0;
        printDetection(refine ? "drifted, refined" : "drifted, nominal", report.loop);
        std::printf("[pan-tilt test] drifted axes, %s: %d moving frames returned unrestored; <= 1 px within %d "
                    "cycle(s) of every jump\n",
                    refine ? "refined against the last still frame" : "nominal model", rejected,
                    worstConvergence(report.loop));
    }
    // Measured (docs/quality.md): where a tag moved >= 2 px, 15 frames: raw 5, nominal 12, refined 14.
    EXPECT_GE(tallies[1].frames, 13);
    EXPECT_GE(tallies[1].restoredRate(), 2.5 * tallies[1].rawRate());
    EXPECT_GE(tallies[1].restoredRate(), 0.84);
    EXPECT_GT(tallies[1].restored, tallies[0].restored);
}

TEST(PanTiltServoConfigCheck, RefusesAMountOfOneAxisAPlaceOutOfReachAndAxesThatCannotPoint)
{
    PanTiltConfig config = diagonalJumps(1);
    config.loop.cycles = 1;
    config.loop.keepImages = false;

    PanTiltConfig oneAxis = config;
    oneAxis.mount = Mount::create();
    oneAxis.mount->addAxis(Vec3d(1, 0, 0), Plant::create(14.4, 0.12, CV_PI / 180), -16, 16);
    EXPECT_NE(errorOf(oneAxis).find("two axes or more"), std::string::npos) << errorOf(oneAxis);

    PanTiltConfig far = config;
    far.targetsDeg = {Vec2d(4, 25)};  // the tilt reaches ±20° (400 levels of 0.05°)
    const std::string farError = errorOf(far);
    EXPECT_NE(farError.find("axis 1 must turn to 25.00 deg"), std::string::npos) << farError;
    EXPECT_NE(farError.find("[-20.00, 20.00] deg"), std::string::npos) << farError;

    PanTiltConfig panRoll = config;
    panRoll.mount = Mount::create();
    panRoll.mount->addAxis(Vec3d(0, 1, 0), Plant::create(14.4, 0.12, CV_PI / 180), -16, 16);
    panRoll.mount->addAxis(Vec3d(0, 0, 1), Plant::create(14.4, 0.12, CV_PI / 180), -16, 16);
    EXPECT_NE(errorOf(panRoll).find("turn the optical axis both ways"), std::string::npos) << errorOf(panRoll);
}
