// SPDX-License-Identifier: Apache-2.0
// The visual-servoing loop on a mount of two axes or more (a pan-tilt head), shared by
// samples/visual_servo.cpp (--mount) and tests/programs/test_pan_tilt_servo.cpp. The world, the camera,
// the target and the restoration are the one-axis loop's (visual_servo.hpp); each cycle
//   detect the target in the latest restored frame → vpServo (image-based, the target's centre,
//   eye-in-hand, ωx and ωy) → joint increments of the first two axes through the mount's chain
//   → MountPlanner (coordinated) → the plants directly, or every axis over the bus (MultiAxisDriver)
//   → the frames taken meanwhile, classified from the mount's CameraMotion, restored with
//     DynamicDeblurrer (that motion) and searched for the target raw and restored.
// Two scenarios: diagonal jumps (convergence after each jump) and places along a circle.
#ifndef DYNBLUR_SAMPLES_PAN_TILT_SERVO_HPP
#define DYNBLUR_SAMPLES_PAN_TILT_SERVO_HPP

#include "visual_servo.hpp"

#include <opencv2/dynblur.hpp>

#include <functional>
#include <string>
#include <vector>

namespace dynblur_samples {

struct PanTiltConfig
{
    /** Camera, target, control law, planner mode, restoration, latency, hardware drift (applied to
    every axis), cycles per place and bus. Its one-axis positioner (naturalFreqHz, dampingRatio,
    gainDegPerLevel, maxLevel) builds the default mount; its startOffsetDeg and targetsDeg are unused. */
    ServoConfig loop;
    //! At least two axes; the first two point the camera, the others hold 0. Empty: panTiltMount(loop).
    cv::Ptr<cv::dynblur::Mount> mount;
    //! The target's places: the angles of axes 0 and 1 (pan, tilt) that centre it, degrees.
    std::vector<cv::Vec2d> targetsDeg;
};

//! What a cycle's move did to each axis (the first two; further axes hold).
struct PanTiltMove
{
    cv::Vec2i fromLevels, toLevels;
    cv::Vec2d deltaDeg;              //!< joint increments vpServo's ωx, ωy turned into, degrees
    double peakRateDegS = 0;         //!< MountMove::peakRate, degrees per second
    double pathDeviationDeg = 0;     //!< MountMove::pathDeviation, degrees
    //! Over the bus: each axis's report of the one START that ran the move (empty otherwise).
    std::vector<cv::dynblur::StartReport> starts;
};

struct PanTiltReport
{
    //! Cycles and frames as the one-axis loop reports them (ServoFrame::thetaDeg: the optical axis's
    //! angle from rest; targetsDeg: each place's angle from rest), with its tallies.
    ServoReport loop;
    std::vector<cv::Vec2d> targetsDeg;  //!< the places (pan, tilt), degrees
    std::vector<PanTiltMove> moves;     //!< one per cycle
};

//! Pan (0, 1, 0) carrying tilt (1, 0, 0), each axis the one-axis loop's positioner (±maxLevel levels).
cv::Ptr<cv::dynblur::Mount> panTiltMount(const ServoConfig& positioner);

/** The target visits `places` places, the first at `startDeg` (pan, tilt), each next one a jump of
U[minJumpDeg, maxJumpDeg] along a diagonal (pan and tilt each by the jump over √2, signs at random,
turned back within ±limitDeg on each axis), cyclesPerTarget cycles each; each cycle's latency jitters over one frame
period, as in the one-axis tracking scenario. */
PanTiltConfig diagonalJumps(int places, int cyclesPerTarget = 3, unsigned seed = 1u,
                            cv::Vec2d startDeg = cv::Vec2d(4, 4), double minJumpDeg = 3.0, double maxJumpDeg = 6.0,
                            double limitDeg = 10.0);

/** The target steps along a circle of radiusDeg about (0, 0) (pan, tilt), `places` places per turn
starting at (radiusDeg, 0), cyclesPerTarget cycles each; latency jitters as in diagonalJumps. */
PanTiltConfig circleScenario(int places, double radiusDeg = 5.0, int cyclesPerTarget = 2, unsigned seed = 1u);

/** Throws cv::Exception naming the problem: what checkServoConfig refuses, a mount of fewer than two
axes, first two axes that do not turn the optical axis both ways, no place, or a place beyond an
axis's range (naming the axis and its range). */
void checkPanTiltConfig(const PanTiltConfig& config);

/** Runs the loop (checkPanTiltConfig first). @param progress called after each cycle (may be empty). */
PanTiltReport runPanTiltServo(const PanTiltConfig& config,
                              const std::function<void(const PanTiltReport&)>& progress = {});

/** cycles.csv (each cycle with both axes' levels and increments, the move's peak rate and path
deviation), then writeServoFigures. */
void writePanTiltOutputs(const PanTiltReport& report, const std::string& outDir);

}  // namespace dynblur_samples

#endif
