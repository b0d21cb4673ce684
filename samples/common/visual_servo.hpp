// The closed loop of the visual-servoing sample, shared by samples/visual_servo.cpp and
// tests/test_visual_servo.cpp: a textured plane carrying an AprilTag (36h11, id 0), a camera on the
// tilt positioner, a rolling-shutter sensor rendered with renderBlurred + addSensorNoise, and each
// cycle: detect the tag in the latest restored frame → vpServo (image-based, tag centre) → ωx →
// angle increment → SwitchPlanner saccade (directly on the plant, or uploaded to the actuator
// controller over the bus) → the frames the camera takes meanwhile, classified (windows I–IV),
// restored with DynamicDeblurrer, and searched for the tag both raw and restored.
// ViSP stays inside visual_servo.cpp: this header needs OpenCV only.
#ifndef DYNBLUR_SAMPLES_VISUAL_SERVO_HPP
#define DYNBLUR_SAMPLES_VISUAL_SERVO_HPP

#include <opencv2/dynblur.hpp>

#include <functional>
#include <string>
#include <vector>

namespace dynblur_samples {

struct ServoConfig
{
    int cycles = 10;                 //!< servo cycles (each: measure, control, saccade, frames)
    int framesPerCycle = 3;          //!< frames the camera takes during one cycle
    double startOffsetDeg = 8.0;     //!< the tag starts this far (tilt) from the image centre, degrees
    int tagCellPx = 4;               //!< size of one tag cell on the plane at θ = 0, pixels (tag: 8 cells + quiet zone)
    double lambda = 1.0;             //!< vpServo gain, per cycle (Δθ = ωx · 1 cycle; 1: one-step correction)
    // Positioner: the seed's dynamics with a finer cell (0.05°/level ≈ 0.26 px at fx = 300 px,
    // ±20° with 400 levels); the seed's 1°/level would leave the tag up to 2.6 px off.
    double naturalFreqHz = 14.4;
    double dampingRatio = 0.12;
    double gainDegPerLevel = 0.05;
    int maxLevel = 400;
    int plannerMode = cv::dynblur::PLAN_ROBUST;  // PLAN_FAST tries every level: ~10 s per plan at 400 levels
    // Camera: 320×240, fx = fy = 300 px, rolling shutter read out in 30 ms at 30 fps, 8 ms exposure.
    cv::Size imageSize = cv::Size(320, 240);
    double focalPx = 300.0;
    double fps = 30.0;
    double exposure = 0.008;         //!< seconds
    double lineDelay = 125e-6;       //!< seconds per row
    double latency = 0.004;          //!< from the end of a frame's readout to the saccade's start, seconds
    // Restoration.
    int psfModel = cv::dynblur::PSF_ROWS;
    int rlIterations = 20;
    unsigned noiseSeed = 7u;
    bool keepImages = true;          //!< keep each frame (8-bit raw and restored) in the report
    std::string busUri;              //!< "" drives the plant directly; "tcp://127.0.0.1:PORT" the actuator controller
    double busTimeout = 0.5;         //!< seconds
};

struct Detection
{
    bool found = false;
    cv::Point2d centre;                 //!< pixels
    std::vector<cv::Point2d> corners;   //!< pixels
};

struct ServoFrame
{
    int cycle = 0;
    int index = 0;                //!< frame number since the start
    double frameStart = 0;        //!< seconds, simulation clock
    int window = 0;               //!< cv::dynblur::ExposureWindow
    double thetaDeg = 0;          //!< true tilt at mid-readout, degrees
    Detection raw, restored;
    double restoreSec = 0;        //!< DynamicDeblurrer::deblur time, seconds (0 when not called)
    cv::Mat rawImage, restoredImage;  //!< 8-bit grey (when ServoConfig::keepImages)
};

struct ServoCycle
{
    int cycle = 0;
    double measuredErrorPx = -1;  //!< |tag centre − image centre| in the restored frame the control used (-1: not seen)
    double trueErrorPx = 0;       //!< the same from the scene geometry at the commanded resting angle
    int fromLevel = 0, toLevel = 0;
    double deltaDeg = 0;          //!< angle increment vpServo asked for, degrees
    size_t switches = 0;          //!< switches of the saccade
    double settleMs = 0;          //!< predicted settle time of the saccade, ms
    double startLatencyMs = 0;    //!< bus only: controller start minus planned start, ms
};

struct ServoReport
{
    std::vector<ServoCycle> cycles;
    std::vector<ServoFrame> frames;
    double targetDeg = 0;         //!< tilt that centres the tag, degrees
    std::string detector = "vpDetectorAprilTag 36h11 id 0";
    //! First cycle whose true error is ≤ px and stays so until the end; -1 if none.
    int cyclesToWithin(double px) const;
    //! Frames in window (0: windows I–III together) and how many had the tag detected raw / restored.
    void detectionCounts(int window, int& frames, int& raw, int& restored) const;
    double meanRestoreSec() const;   //!< over frames that were restored
};

/** Runs the loop. @param progress called after each cycle (may be empty). Throws cv::Exception or
std::runtime_error on bad configuration or a bus failure. */
ServoReport runVisualServo(const ServoConfig& config,
                           const std::function<void(const ServoReport&)>& progress = {});

//! The 36h11 tag id 0 as a (cells·10)² 8-bit image: black 8×8 square with a white one-cell quiet zone.
cv::Mat aprilTag36h11Id0(int cellPx);

/** Writes cycles.csv and frames.csv, error.png (plot of the error) and strip.png (raw vs restored
frames of windows I–III with detections drawn) into outDir. */
void writeServoOutputs(const ServoReport& report, const std::string& outDir);

}  // namespace dynblur_samples

#endif
