// SPDX-License-Identifier: Apache-2.0
// The hand-held clip simulator: a camera held by a shaking hand (band-limited rotation, optionally a
// translation in front of a plane), its gyro log on a clock of its own, and its frames rendered one at a
// time with their truth, for the calibration tests, the benchmarks and the command-line rehearsals.
// clip_writer.hpp puts a clip on disk as a device would; dynblur_simulate_clip is its program.
#ifndef DYNBLUR_SAMPLES_HANDHELD_CLIP_HPP
#define DYNBLUR_SAMPLES_HANDHELD_CLIP_HPP

#include "hand_motion.hpp"

#include <opencv2/dynblur.hpp>

#include <string>

namespace dynblur_samples {

/** @brief The camera's rotation: band-limited noise whose rate spectrum is flat between lowHz and
highHz, scaled by exactly one of peakRate and maxBlurPx. */
struct RotationShake
{
    double lowHz = 1.0;    //!< Hz, > 0: no content (and no drift) below it
    double highHz = 20.0;  //!< Hz, in (lowHz, 200]
    double peakRate = 0;   //!< rad/s, ≥ 0: the largest |ω| over the clip's frames (0: set by maxBlurPx)
    double maxBlurPx = 0;  //!< pixels, ≥ 0: the largest rotation blur of a frame (frameBlurPx; 0: set by peakRate)
    cv::Vec3d axisWeights{1.0, 1.0, 0.5};  //!< relative RMS rate about x (tilt), y (pan), z (roll), each ≥ 0
};

/** @brief The camera's translation in front of a plane facing the home view, band-limited as the
rotation is (flat speed spectrum). planeDepth = 0: none (a scene at infinity). */
struct TranslationShake
{
    double planeDepth = 0;   //!< m, 0 (none) or in [0.1, 1000]
    double lowHz = 1.0;      //!< Hz, > 0
    double highHz = 20.0;    //!< Hz, in (lowHz, 200]
    double peakSpeed = 0.05; //!< m/s, > 0: the largest |c'(t)| over the clip's frames
    cv::Vec3d axisWeights{1.0, 1.0, 0.5};  //!< relative RMS speed along x, y, z, each ≥ 0
    /** m, in [0, 2]: a sweep about the arm or the body: the camera turns about a pivot this far behind
        it, so its centre rides on the rotation, c(t) = (Q(t) − I)·(0, 0, pivotDistance), instead of the
        band-limited translation above (peakSpeed, the band and the weights then unused). Over a plane at
        depth d the image moves about 1 + pivotDistance / d times as far as the rotation turns it. */
    double pivotDistance = 0;
};

/** @brief The gyroscope rigidly fixed to the camera: samples at rateHz on the log's clock, which reads
camera time + timeOffset. A sample is rateScale·ω(t) + bias + noise, in camera axes (the writer maps it
to the sensor's). */
struct GyroModel
{
    double rateHz = 200;       //!< samples per second, in [10, 10000]
    double noise = 0;          //!< rad/s, ≥ 0: standard deviation of each sample's white noise, per axis
    cv::Vec3d bias;            //!< rad/s, camera axes, each within ±0.2
    double rateScale = 1.0;    //!< the gyro's sensitivity over the truth, in [0.5, 2]
    double timeOffset = 0;     //!< s, within ±10: the log's clock minus the camera's
    double leadSeconds = 1.0;  //!< s, in [0, 60]: the log starts this long before the first frame and ends after the last
};

/** @brief A hand-held clip, described. The camera clock's zero is the first frame's start: frame k
starts (row 0's exposure) at k / fps, as a container's constant-rate timestamps say. */
struct HandHeldClip
{
    std::string image;                 //!< the scene: an image file, scaled and cropped to cover the view; "": generated (makeScene)
    cv::Size frameSize{640, 480};      //!< pixels, each in [16, 8192]
    double focalPx = 600;              //!< focal length fx = fy, pixels, in [10, 100000]; principal point at the centre
    double fps = 30;                   //!< frames per second, in (0, 1000]
    double exposure = 0.010;           //!< s, in [0, 1/fps]
    double readoutTime = 0.020;        //!< s, in [0, 1/fps]: line delay = readoutTime / rows; 0: global shutter
    int frames = 30;                   //!< number of frames, in [1, 10^6]
    RotationShake rotation;
    TranslationShake translation;
    ShakeStretches stretches;          //!< still and shaky stretches (default: shaky throughout)
    GyroModel gyro;
    double fullWellElectrons = 4000;   //!< sensor noise (addSensorNoise), electrons at full scale, ≥ 0; 0: no noise
    double readNoiseElectrons = 8;     //!< electrons, ≥ 0
    double darkElectrons = 5;          //!< electrons, ≥ 0
    double maxStepPx = 0.5;            //!< the renderers' time step, pixels of image motion, in (0, 1]
    uint64 seed = 1;               //!< motion, gyro noise and sensor noise

    /** Throws cv::Exception naming the first field out of range ("HandHeldClip: fps = 0 must be in
    (0, 1000] (frames per second)"). */
    void validate() const;
    //! Row-to-row delay, seconds.
    double lineDelay() const { return readoutTime / frameSize.height; }
    //! The camera-clock instant the last frame's readout ends, seconds.
    double end() const;
};

//! What the simulator knows of a frame without rendering it.
struct FrameTruth
{
    int index = 0;
    cv::dynblur::RollingShutter shutter;  //!< the frame's true timing, camera clock
    double referenceTime = 0;  //!< s, camera clock: the middle row's mid-exposure, the view a restoration returns
    double blurPx = 0;         //!< the largest extent of a point's path during its row's exposure, pixels (frameBlurPx)
    double rotationBlurPx = 0; //!< the same for the rotation alone (what a gyro log predicts)
    bool still = false;        //!< the hand held still over the whole readout
};

//! A rendered frame and its truth.
struct ClipFrame : FrameTruth
{
    cv::Mat image;  //!< CV_8UC3 sRGB: what the camera recorded (forward model, sensor noise)
    cv::Mat truth;  //!< CV_8UC3 sRGB: the sharp, noise-free view at referenceTime
};

/** @brief A hand-held clip, simulated: the motion and the gyro log are made on construction (a 60 s
clip's motion is a few MB), each frame is rendered on request and nothing of it is kept, so a long
clip streams: render, restore, drop. */
class HandHeldSimulator
{
public:
    //! Validates the description, makes the motion (scaled as asked) and the scene. Throws cv::Exception.
    explicit HandHeldSimulator(const HandHeldClip& clip);

    const HandHeldClip& clip() const { return clip_; }
    //! The camera: clip.focalPx, principal point at the frame's centre, no distortion.
    cv::Ptr<cv::dynblur::CameraModel> camera() const { return camera_; }
    //! The true rotation Q(t) on the camera's clock (the identity at the home view, before the clip).
    cv::Ptr<cv::dynblur::CameraMotion> motion() const { return path_.rotation; }
    //! The rotation and the translation.
    const CameraPath& path() const { return path_; }
    /** The gyro log: times on the log's clock (camera time + gyro.timeOffset) every 1/gyro.rateHz,
    covering the frames' readouts and gyro.leadSeconds on both sides; rates in camera axes,
    rateScale·ω + bias + noise (GyroLog::bias left 0: the truth is in the description). */
    const cv::dynblur::GyroLog& gyroLog() const { return gyroLog_; }

    //! The frame's timing, reference time and blur, without rendering. @param index in [0, frames).
    FrameTruth truth(int index) const;
    //! The frame rendered (rotation: renderBlurred; with translation: renderPlaneBlurred) and its truth view.
    ClipFrame render(int index) const;

    //! The rotation's largest |ω| over the frames' readouts, rad/s (what peakRate asks for).
    double peakRate() const { return peakRate_; }
    //! The translation's largest speed over the frames' readouts, m/s (0 without).
    double peakSpeed() const { return peakSpeed_; }
    //! Pixels the scene extends beyond the frame on each side: how far the view strays, and more.
    int margin() const { return margin_; }

private:
    cv::dynblur::RollingShutter shutter(int index) const;
    void scaleMotion(const HandShake& shake);
    void makeScene();
    void makeGyroLog();

    HandHeldClip clip_;
    cv::Ptr<cv::dynblur::CameraModel> camera_;
    cv::Matx33d K_;
    CameraPath path_;
    cv::dynblur::GyroLog gyroLog_;
    cv::Mat sceneLinear_;
    int margin_ = 0;
    double peakRate_ = 0, peakSpeed_ = 0;
};

}  // namespace dynblur_samples

#endif
