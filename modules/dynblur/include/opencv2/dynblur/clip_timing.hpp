// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_CLIP_TIMING_HPP
#define OPENCV_DYNBLUR_CLIP_TIMING_HPP

#include <opencv2/dynblur/camera.hpp>
#include <opencv2/dynblur/gyro_log.hpp>
#include <opencv2/dynblur/refinement.hpp>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_restoration
//! @{

/** @brief Settings of ClipTimingCalibrator: the calibration of a clip against its gyro log from the
frames alone, with no still frame. */
struct CV_EXPORTS_W_SIMPLE ClipTimingOptions
{
    CV_WRAP ClipTimingOptions();
    /** half-width of the clock offset's search, seconds, in (0, 60] (default 2): how far the log's
        clock may be from the video's. The search is clipped to the offsets at which the log covers
        at least half of the frames. */
    CV_PROP_RW double maxTimeOffset;
    /** MotionRefinement flags the fine stage refines, among REFINE_TIME_OFFSET, REFINE_LINE_DELAY,
        REFINE_GYRO_BIAS and REFINE_RATE_SCALE, REFINE_TIME_OFFSET included (default the first three) */
    CV_PROP_RW int flags;
    /** search the readout too: the coarse stage tries line delays from a quarter to twice the
        shutters' (at most one frame period), for a camera whose readout is unknown (default true;
        ignored for a global shutter, lineDelay 0) */
    CV_PROP_RW bool scanReadout;
    /** adopt the gyro's axes the images show: of the 24 signed permutations of the log's camera
        axes, the one whose rotations match the image motion best (default true); false: a log whose
        axes the images contradict is refused */
    CV_PROP_RW bool detectAxes;
    /** the frames are measured at this width, pixels, in [160, 4096] (default 640; frames narrower
        are measured at their own width) */
    CV_PROP_RW int analysisWidth;
};

/** @brief Calibrates a clip in continuous motion against its gyro log, with no still frame: the
clock offset between the log and the video (seconds apart, not milliseconds), the line delay (the
readout may be unknown), the gyro bias, optionally a rate scale, and the log's axes.

Frames are added one at a time, in order (addFrame), so a long clip is never held in memory: of
each, only a reduced luminance and what was measured on it are kept. Two stages, both on the
frame-to-frame geometry @cite Karpenko2011Digital @cite Hu2016Image:
1. *coarse*: between consecutive frames, phase correlation in a grid of patches gives the image's
   turn in each band of rows; the log's rates, integrated over the same intervals, must match it.
   The offset is scanned over ±maxTimeOffset in 1 ms steps against every signed permutation of the
   log's axes and a free scale, then the readout near the best offset. What does not match refuses
   the log, naming the likely mistake: rates in °/s read as rad/s, a time unit read as another, axes
   the images contradict, another clip's log.
2. *fine*: features tracked across frames (pyramidal Lucas–Kanade @cite Lucas1981Iterative, checked
   forward and backward) under the rolling-shutter model: the point seen at row y of frame a, at the
   instant its row was exposed, is carried by the log's rotation to frame b. Levenberg–Marquardt on
   the flagged parameters (the refinement's table) minimises the reprojection error, tracks that no
   rotation explains (moving objects, parallax) left out; a parameter the tracks do not determine keeps its
   start and is reported held.

Why the geometry and not the blur: a blurred feature's position is its mid-exposure position, so
the tracks observe the clock, the readout and the bias with no restoration in the loop, at the cost
of a few thousand rotations per evaluation; the blur observes the same parameters only against a
still frame (calibrateTiming with references), which a clip in continuous motion does not have.
*/
class CV_EXPORTS_W ClipTimingCalibrator : public Algorithm
{
public:
    /** @param camera the clip's camera (its image size is the frames').
    @param log the gyro log, its rates in camera axes as read (GyroLog::load), its bias subtracted.
    @param options the settings, checked here. */
    CV_WRAP static Ptr<ClipTimingCalibrator> create(const Ptr<CameraModel>& camera, const GyroLog& log,
                                                    const ClipTimingOptions& options = ClipTimingOptions());

    /** @brief Adds the clip's next frame. A frame that does not follow the previous one within 1.5
    of the clip's frame period starts a new run (nothing is measured across the gap).
    @param frame the frame: CV_8U (sRGB) or CV_32F (linear, [0, 1]), 1, 3 or 4 channels, the
           camera's image size.
    @param shutter its timing on the video's clock (frameStart from the container's timestamps),
           rows = its height; its lineDelay is the readout's first guess, its frameStart after the
           previous frame's. */
    CV_WRAP virtual void addFrame(InputArray frame, const RollingShutter& shutter) = 0;

    //! @brief The number of frames added.
    CV_WRAP virtual int getFrameCount() const = 0;

    /** @brief The calibration of the frames added: TimingCalibration::correction holds the clock
    offset (seconds, the log's clock minus the video's), the line delay's scale over the shutters',
    the gyro bias and the rate scale; axisCorrection the axes the images showed; explainedMotion and
    trackResidualPx how well it fits. Throws cv::Exception when the frames cannot calibrate it
    (fewer than 10 frames, too little motion) or the log does not explain them, naming the likely
    mistake. */
    CV_WRAP virtual TimingCalibration calibrate() = 0;
};

/** @brief ClipTimingCalibrator over frames already in memory: create, addFrame for each, calibrate.
@param log the gyro log (see ClipTimingCalibrator::create).
@param camera the clip's camera.
@param frames the clip's frames, in order.
@param shutters each frame's timing on the video's clock.
@param options the settings. */
CV_EXPORTS_W TimingCalibration calibrateTiming(const GyroLog& log, const Ptr<CameraModel>& camera,
                                               InputArrayOfArrays frames, const std::vector<RollingShutter>& shutters,
                                               const ClipTimingOptions& options = ClipTimingOptions());

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
