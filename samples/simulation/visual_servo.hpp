// SPDX-License-Identifier: Apache-2.0
// The closed loop of the visual-servoing sample, shared by samples/visual_servo.cpp and
// tests/programs/test_visual_servo.cpp: a textured plane carrying a target (a column of AprilTags 36h11,
// ids 0..2), a camera on the tilt positioner, a rolling-shutter sensor rendered with renderBlurred +
// addSensorNoise, and each cycle: detect the target in the latest restored frame → vpServo
// (image-based, the target's centre) → ωx →
// angle increment → SwitchPlanner saccade (directly on the plant, or uploaded to the actuator
// controller over the bus) → the frames the camera takes meanwhile, classified (windows I–IV),
// restored with DynamicDeblurrer, and searched for the target both raw and restored.
// Two scenarios: "step" (the target sits startOffsetDeg off and stays; convergence) and "track" (it
// jumps to a new place every few cycles, 3..6° each way, and the saccade's phase against the
// camera's frames varies from cycle to cycle, so that many frames are taken in windows I, II and III;
// the detection figure raw vs restored).
// ViSP stays inside visual_servo.cpp: this header needs OpenCV only.
#ifndef DYNBLUR_SAMPLES_VISUAL_SERVO_HPP
#define DYNBLUR_SAMPLES_VISUAL_SERVO_HPP

#include "target_detector.hpp"

#include <opencv2/dynblur.hpp>

#include <functional>
#include <string>
#include <vector>

namespace dynblur_samples {

struct ServoConfig
{
    int cycles = 10;                 //!< servo cycles (each: measure, control, saccade, frames)
    int framesPerCycle = 3;          //!< frames the camera takes during one cycle
    double startOffsetDeg = 8.0;     //!< the target starts this far (tilt) from the image centre, degrees
    int tagCellPx = 4;               //!< size of one tag cell on the plane at θ = 0, pixels (tag: 8 cells + quiet zone)
    //! AprilTags in the target (36h11 ids 0, 1, ...; at most kTagIds), stacked in a column 9 cells
    //! apart (their quiet zones shared), so the target spans many sensor rows; the feature is their
    //! mean centre, and the target counts as found when every tag is.
    int targetTags = 3;
    double lambda = 1.0;             //!< vpServo gain, per cycle (Δθ = ωx · 1 cycle; 1: one-step correction)
    //! The servo holds still while the measured error is at most this, pixels: smaller corrections
    //! (a few levels of 0.26 px) chase the detector's noise and make the positioner hunt.
    double deadbandPx = 0.75;
    // Positioner: the seed's dynamics with a finer cell (0.05°/level ≈ 0.26 px at fx = 300 px,
    // ±20° with 400 levels); the seed's 1°/level would leave the tag up to 2.6 px off.
    double naturalFreqHz = 14.4;
    double dampingRatio = 0.12;
    double gainDegPerLevel = 0.05;
    int maxLevel = 400;
    int plannerMode = cv::dynblur::PLAN_ROBUST;  // PLAN_FAST tries every level: far too slow for a servo cycle at 400 levels (BM_PlanFastUncached in perf/perf_planner.cpp times it)
    // Camera: 320×240, fx = fy = 300 px, rolling shutter read out in 30 ms at 30 fps, 33 ms exposure
    // (a C270 indoors at 30 fps exposes each row for about the frame period).
    cv::Size imageSize = cv::Size(320, 240);
    double focalPx = 300.0;
    double fps = 30.0;
    double exposure = 0.033;         //!< seconds
    double lineDelay = 125e-6;       //!< seconds per row
    double latency = 0.004;          //!< from the end of a frame's readout to the saccade's start, seconds
    //! Each cycle's latency is latency + U[0, latencyJitter) seconds (seeded by noiseSeed): the
    //! processing time varies, and so does the saccade's phase against the camera's frames.
    double latencyJitter = 0.0;
    // Scenario. The target's successive places: its tilt from the image centre seen at θ = 0, degrees
    // (empty: the one place startOffsetDeg). The tag moves to the next place every cyclesPerTarget
    // cycles (0: never), between two frames; the camera then takes one frame, which the next cycle
    // measures, before it moves.
    std::vector<double> targetsDeg;
    int cyclesPerTarget = 0;
    // Hardware that is not the model: the positioner moves with these scales of the natural frequency
    // and damping ratio, and each frame starts clockOffset seconds later than its timestamp says. The
    // loop plans, classifies and restores with the nominal model (over the bus, give the simulator
    // the same truth).
    double trueFreqScale = 1.0;
    double trueDampingScale = 1.0;
    double clockOffset = 0.0;        //!< seconds
    // Restoration.
    //! Refine each moving frame against the last still frame (DynamicDeblurrer::setReferenceFrame).
    bool refine = true;
    int psfModel = cv::dynblur::PSF_ROWS;
    int rlIterations = 20;
    unsigned noiseSeed = 7u;
    bool keepImages = true;          //!< keep each frame (8-bit raw and restored) in the report
    std::string busUri;              //!< "" drives the plant directly; "tcp://127.0.0.1:PORT" the actuator controller
    double busTimeout = 0.5;         //!< seconds
};

struct ServoFrame
{
    int cycle = 0;                //!< the cycle whose saccade the frame saw (-1 or c − 1: taken before cycle c moved)
    int target = 0;               //!< index of the tag's place
    int index = 0;                //!< frame number since the start
    double frameStart = 0;        //!< seconds, simulation clock
    int window = 0;               //!< cv::dynblur::ExposureWindow
    double thetaDeg = 0;          //!< true tilt at mid-readout, degrees
    double tagMotionPx = 0;       //!< how far a tag's centre travelled (true motion) while its sensor row was exposed, pixels (the farthest of the target's tags)
    Detection raw, restored;
    double restoreSec = 0;        //!< DynamicDeblurrer::deblur time, seconds (0 when not called)
    cv::dynblur::MotionCorrection correction;  //!< the restoration's correction (default when not restored)
    cv::Mat rawImage, restoredImage;  //!< 8-bit grey (when ServoConfig::keepImages)
};

struct ServoCycle
{
    int cycle = 0;
    int target = 0;               //!< index of the tag's place
    int cycleOfTarget = 0;        //!< cycles since the tag moved to this place (0: the first)
    double measuredErrorPx = -1;  //!< |target centre − image centre| in the restored frame the control used (-1: not seen)
    double trueErrorPx = 0;       //!< the same from the scene geometry at the commanded resting angle
    int fromLevel = 0, toLevel = 0;
    double deltaDeg = 0;          //!< angle increment vpServo asked for, degrees
    double latencyMs = 0;         //!< from the end of the measured frame's readout to the planned start, ms
    size_t switches = 0;          //!< switches of the saccade
    double settleMs = 0;          //!< predicted settle time of the saccade, ms
    double startLatencyMs = 0;    //!< bus only: controller start minus planned start, ms
};

//! Frames of some kind and how many of them had the target detected (every tag), raw and restored.
struct DetectionTally
{
    int frames = 0, raw = 0, restored = 0;
    double rawRate() const { return frames ? double(raw) / frames : 0.0; }
    double restoredRate() const { return frames ? double(restored) / frames : 0.0; }
};

struct ServoReport
{
    std::vector<ServoCycle> cycles;
    std::vector<ServoFrame> frames;
    std::vector<double> targetsDeg;  //!< the target's places (tilt that centres each), degrees
    /** Cycles from the tag's arrival at place `target` until the first cycle whose error (true and
    measured) is ≤ px and stays so while the tag is there: 0 if already, 1 after one saccade; -1 if
    never. */
    int cyclesToWithin(double px, int target = 0) const;
    /** Frames in `window` (0: windows I–III together) whose tag travelled at least minTagMotionPx
    while its row was exposed, tallied raw and restored. */
    DetectionTally tally(int window, double minTagMotionPx = 0.0) const;
    double meanRestoreSec() const;   //!< over frames that were restored
};

/** The tracking scenario: the target visits `places` places, the first startOffsetDeg off, each next
one a jump of U[minJumpDeg, maxJumpDeg] up or down (random, within ±limitDeg), cyclesPerTarget cycles
each; each cycle's latency jitters over one frame period. Other fields keep their defaults. */
ServoConfig trackingScenario(int places, int cyclesPerTarget = 3, unsigned seed = 1u, double startOffsetDeg = 5.0,
                             double minJumpDeg = 3.0, double maxJumpDeg = 6.0, double limitDeg = 12.0);

/** Throws cv::Exception naming the field of `config` that no loop can run with (counts, gains, the
target's tags, its size against the frame, the dead band, the latency). */
void checkServoConfig(const ServoConfig& config);

/** Runs the loop. @param progress called after each cycle (may be empty). Throws cv::Exception or
std::runtime_error on bad configuration or a bus failure. */
ServoReport runVisualServo(const ServoConfig& config,
                           const std::function<void(const ServoReport&)>& progress = {});

//! A target whose tag travels at least this far while its sensor row is exposed counts as blurred,
//! pixels (half a tag cell at the default size).
constexpr double kTagBlurredPx = 2.0;

//! One row of the detection figure: all frames of a window, and those whose tag was blurred.
struct DetectionRow
{
    std::string window;           //!< "I", "II", "III" or "I-III"
    DetectionTally all;           //!< every frame of the window(s)
    DetectionTally tagBlurred;    //!< those where a tag moved at least kTagBlurredPx while its row was exposed
};

//! The detection figure of a run: windows I, II, III and I–III together.
std::vector<DetectionRow> detectionSummary(const ServoReport& report);

//! A 36h11 tag (id 0..kTagIds − 1) as a (cells·10)² 8-bit image: black 8×8 square with a white one-cell quiet zone.
cv::Mat aprilTag36h11(int id, int cellPx);
constexpr int kTagIds = 3;

/** Writes cycles.csv and frames.csv, error.png (plot of the error), strip.png (raw vs restored
frames of windows I–III with detections drawn: per window up to four frames whose target was
blurred, from the most to the least blurred) and detection.png (bar chart: target found raw vs
restored per window) into outDir. */
void writeServoOutputs(const ServoReport& report, const std::string& outDir);
//! What writeServoOutputs writes but cycles.csv: frames.csv, error.png, strip.png and detection.png.
void writeServoFigures(const ServoReport& report, const std::string& outDir);

}  // namespace dynblur_samples

#endif
