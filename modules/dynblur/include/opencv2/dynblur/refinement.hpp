// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_REFINEMENT_HPP
#define OPENCV_DYNBLUR_REFINEMENT_HPP

#include <opencv2/dynblur/camera.hpp>
#include <opencv2/dynblur/camera_motion.hpp>
#include <opencv2/dynblur/plant.hpp>
#include <opencv2/dynblur/shutter.hpp>

#include <limits>
#include <vector>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_restoration
//! @{

/** @brief What DynamicDeblurrer::setRefinement and calibrateTiming estimate from the frames
(flags, combined with |). The schedule and the plant's gain are known exactly and never refined.
For a measured motion (a gyro log: a CameraMotion that is not a plant's) REFINE_PLANT has no
meaning and is ignored, and REFINE_GYRO_BIAS may be added. */
enum MotionRefinement
{
    REFINE_NONE = 0,         //!< use the model as told
    REFINE_TIME_OFFSET = 1,  //!< the offset between the camera's clock and the actuator's (or the motion log's)
    REFINE_LINE_DELAY = 2,   //!< the rolling shutter's line delay (ignored for a global shutter)
    /** the plant's natural frequency and damping ratio; for a mount's motion (Mount::motion), each
        axis's (up to three axes, base first; further axes are used as told) */
    REFINE_PLANT = 4,
    REFINE_ALL = 7,          //!< the three above
    /** a measured motion's constant gyro bias (3 components; ignored for a plant's motion). Not in
        REFINE_ALL: a frame observes it mostly through the turn it adds between the still and the
        frame, which needs stills some time away from their frames. */
    REFINE_GYRO_BIAS = 8,
    /** a measured motion's rate scale (MotionCorrection::rateScale: the image moves further than the
        rotation alone turns it when the camera also translates, as in a sweep about the arm or the
        body); ignored for a plant's motion, not in REFINE_ALL */
    REFINE_RATE_SCALE = 16
};

/** @brief One parameter the refinement estimates (refinementParameters): the MotionCorrection field
it sets, the MotionRefinement flag that turns it on, and where it applies. */
struct CV_EXPORTS_W_SIMPLE RefinementParameter
{
    CV_WRAP RefinementParameter();
    CV_PROP_RW String name;      //!< what it is: "time offset", "natural frequency", "gyro bias x"
    CV_PROP_RW String group;     //!< its flag's name in messages: "time offset", "plant", "gyro bias"
    CV_PROP_RW String key;       //!< its flag's short name in command lines: "offset", "line-delay", "plant", "bias"
    CV_PROP_RW String flagName;  //!< "REFINE_TIME_OFFSET"
    CV_PROP_RW int flag;         //!< the MotionRefinement flag (several parameters may share one)
    CV_PROP_RW String unit;      //!< the field's unit: "s", "" (a scale of a nominal value) or "rad/s"
    /** how far from its value as told the refinement searches it, `unit`; 0 for the time offset,
        whose search the caller sets (maxTimeOffset) */
    CV_PROP_RW double searchHalfWidth;
    CV_PROP_RW bool plantMotion;         //!< it corrects a plant's motion
    CV_PROP_RW bool mountMotion;         //!< it corrects a mount's motion (Mount::motion)
    CV_PROP_RW bool measuredMotion;      //!< it corrects a measured motion (a gyro log, orientations)
    /** the mount axis (0 = base) whose plant it scales; the plant's own scales are axis 0's; -1: it
        scales no plant */
    CV_PROP_RW int mountAxis;
    CV_PROP_RW bool rollingShutterOnly;  //!< only a rolling shutter observes it (a global one holds it)
    CV_PROP_RW bool inRefineAll;         //!< REFINE_ALL includes its flag
};

/** @brief The parameters the refinement estimates, in the order it fits them: the table that
DynamicDeblurrer::setRefinement, calibrateTiming and their reports read. */
CV_EXPORTS_W std::vector<RefinementParameter> refinementParameters();

/** @brief MotionRefinement flags from a comma-separated list of RefinementParameter::key values,
"all" (REFINE_ALL) and "none": "offset,line-delay" gives REFINE_TIME_OFFSET | REFINE_LINE_DELAY.
Throws cv::Exception naming the unknown item and the allowed ones.
@param names the list, e.g. from a command line. */
CV_EXPORTS_W int refinementFlags(const String& names);

/** @brief A correction of the predicted motion: the difference between the model a deblurrer is
told and the one that moved the camera (DESIGN §2, "What is known on real hardware").

The corrected shutter starts `timeOffset` later and reads its rows with `lineDelayScale` times the
line delay (for a measured motion: the frame lies `timeOffset` later on the motion's clock); a
measured motion turns at `rateScale` times its rates minus `gyroBias`; the corrected plant is the
linear second-order plant with `naturalFreqScale` times the natural frequency and `dampingScale` times
the damping ratio, and the same gain. A mount's motion (Mount::motion) is corrected axis by axis: its
base (axis 0) by naturalFreqScale and dampingScale, axes 1 and 2 by axisNaturalFreqScales and
axisDampingScales (correctMotion). */
struct CV_EXPORTS_W_SIMPLE MotionCorrection
{
    CV_WRAP MotionCorrection();
    CV_PROP_RW double timeOffset;        //!< seconds, added to the shutter's frameStart
    CV_PROP_RW double lineDelayScale;    //!< × the shutter's lineDelay
    CV_PROP_RW double naturalFreqScale;  //!< × the plant's natural frequency ωn
    CV_PROP_RW double dampingScale;      //!< × the plant's damping ratio ζ
    /** × the natural frequency of a mount's axes 1 and 2 (the base, axis 0, takes naturalFreqScale);
        unused for one plant */
    CV_PROP_RW Vec2d axisNaturalFreqScales;
    //! × the damping ratio of a mount's axes 1 and 2 (the base takes dampingScale); unused for one plant
    CV_PROP_RW Vec2d axisDampingScales;
    /** a measured motion's constant gyro bias, rad/s, camera axes: the rates it reports minus the
        true ones, removed from them (to first order about the reference time: the orientation becomes
        Q(t)·exp(−[gyroBias·(t − t_ref)]×)); 0 for a plant's motion */
    CV_PROP_RW Vec3d gyroBias;
    /** a measured motion's rates × this about the reference time (1: the rotation as measured). A
        camera that translates while it turns (a sweep about the arm or the body, a walk) moves the
        image of a scene at depth d further than its rotation alone: by about t/d radians more for a
        translation t. Over a frame the blur and the frame-to-frame motion then look like a rotation
        `rateScale` times the gyro's; 1 for a plant's motion */
    CV_PROP_RW double rateScale;
    /** How well the corrected model explains the frame: the RMS of the frame minus the still
        reference frame carried through the corrected blur (times stillGain), over the pixels both frames observe, in
        units of the sensor noise's standard deviation (estimated on the reference). About 1 where the
        model is right (up to √2 on rows that do not move, where both frames' noise adds); a wrong
        schedule, a moving object or a bumped camera gives several. Refined blind (no reference
        frame, DynamicDeblurrer::setBlindRefinement): blindMotionConsistency's criterion at the
        correction kept, another scale. NaN when it was not measured (no reference frame and no blind
        refinement, or too few still rows). */
    CV_PROP_RW double consistency;
    /** MotionRefinement flags of the parameters the frames did not determine, kept at their prior
        (the value as told, or the calibration): a parameter the frame does not observe at all, or
        one that trades against another along a ridge (a later clock against a stiffer plant in a
        global-shutter frame at the end of a move), where only the combination the frame observes
        moved; or one the fit ran to its search bound although the frame barely depends on it (ζ in
        a frame that shows no ringing). REFINE_NONE when every refined parameter was determined. */
    CV_PROP_RW int held;
    /** the held parameters one by one: bit j set when refinementParameters()[j] was held (`held` names
        their flags only: a mount's tilt held while its pan was fitted shares REFINE_PLANT with it) */
    CV_PROP_RW int heldParameters;
    /** the frame's brightness over its still's (least squares at the fit's result: a webcam's
        automatic exposure, a change of lighting); 1 without a still */
    CV_PROP_RW double stillGain;
    /** false: the correction was refused and the frame returned unrestored (see reason); a frame
        still throughout, or sharp (DynamicDeblurrer::setSharpThreshold: returned as it came or its
        rows only moved back), has applied true */
    CV_PROP_RW bool applied;
    /** why it was not applied, or how the correction was found; "sharp: ..." for a frame not
        deconvolved because its motion keeps it sharp */
    CV_PROP_RW String reason;

    /** @brief The shutter as corrected: frameStart + timeOffset, lineDelay × lineDelayScale.
    @param shutter the shutter as told. */
    CV_WRAP RollingShutter correctShutter(const RollingShutter& shutter) const;
    /** @brief The plant as corrected: `plant` itself when both scales are 1, otherwise
    Plant::create(ωn·naturalFreqScale, ζ·dampingScale, gain) (a user-defined OdePlant is replaced
    by the linear plant of its nominal parameters).
    @param plant the plant as told. */
    CV_WRAP Ptr<Plant> correctPlant(const Ptr<Plant>& plant) const;
    /** @brief A plant-driven motion as corrected: a mount's motion (Mount::motion) with each axis's
    plant scaled (axis 0 by naturalFreqScale and dampingScale, axes 1 and 2 by axisNaturalFreqScales
    and axisDampingScales, as correctPlant does; further axes as told), a plant's motion
    (CameraMotion::fromPlant) with correctPlant's plant; any other motion returned as given (its gyro
    bias and rate scale apply about a reference time: DynamicDeblurrer and the refinement apply them).
    The clock offset is not applied here: it moves the shutter (correctShutter).
    @param motion the motion as told. */
    CV_WRAP Ptr<CameraMotion> correctMotion(const Ptr<CameraMotion>& motion) const;
    /** @brief Throws cv::Exception naming the field when a value is not finite, a scale is not in
    (0, 10) or a gyroBias component exceeds 1 rad/s. */
    CV_WRAP void validate() const;
};

/** @brief The clock offset, line delay and plant of a recording, estimated jointly from several
frames (calibrateTiming). */
struct CV_EXPORTS_W_SIMPLE TimingCalibration
{
    CV_WRAP TimingCalibration();
    /** the common correction; consistency: over all frames; `held`: the parameters the frames cannot
        separate (they sit at the same phase of their moves), kept at their nominal values, which
        `reason` names */
    CV_PROP_RW MotionCorrection correction;
    /** standard deviations of the four parameters (seconds, then dimensionless scales), from the
        fit's curvature and its residual, treating pixel noise as independent (blur correlates
        neighbouring residuals, so the true spread can be larger); 0 for a parameter not refined */
    CV_PROP_RW double timeOffsetStd;
    CV_PROP_RW double lineDelayScaleStd;    //!< see timeOffsetStd
    CV_PROP_RW double naturalFreqScaleStd;  //!< see timeOffsetStd
    CV_PROP_RW double dampingScaleStd;      //!< see timeOffsetStd
    CV_PROP_RW Vec2d axisNaturalFreqScaleStd;  //!< see timeOffsetStd (a mount's axes 1 and 2)
    CV_PROP_RW Vec2d axisDampingScaleStd;      //!< see timeOffsetStd (a mount's axes 1 and 2)
    CV_PROP_RW Vec3d gyroBiasStd;           //!< rad/s, see timeOffsetStd (a measured motion's bias)
    CV_PROP_RW double rateScaleStd;         //!< see timeOffsetStd (a measured motion's rate scale)
    /** the rotation from the gyro log's camera axes (as read) to the camera's that the images
        showed: ω_camera = axisCorrection · ω_log, a signed permutation; the identity when the log's
        axes were right, or not measured (ClipTimingCalibrator measures it) */
    CV_PROP_RW Matx33d axisCorrection;
    /** the share of the frame-to-frame image motion (its squared turn, per band of rows) that the log
        explains at the clock offset found, in [0, 1]; NaN when not measured (ClipTimingCalibrator) */
    CV_PROP_RW double explainedMotion;
    /** RMS reprojection error of the tracked features under the calibrated motion, pixels; NaN when
        not measured (ClipTimingCalibrator) */
    CV_PROP_RW double trackResidualPx;
    CV_PROP_RW std::vector<int> frameUsed;  //!< 1 for each input frame that entered the fit, else 0 (still, or inconsistent)
    CV_PROP_RW std::vector<double> frameConsistency;  //!< MotionCorrection::consistency of each frame at the result
    /** time offsets scanned around the result, seconds, and the objective (mean squared residual
        in noise units over every used frame) at each, the other parameters at the result */
    CV_PROP_RW std::vector<double> scanTimeOffsets;
    CV_PROP_RW std::vector<double> scanObjective;  //!< see scanTimeOffsets

    /** @brief Writes the calibration to a YAML/XML/JSON file (by extension), atomically (a
    temporary file renamed over the target). @param filename output path. */
    CV_WRAP void save(const String& filename) const;
    /** @brief Reads a file written by save() (only the correction and the deviations are needed).
    @param filename input path. */
    CV_WRAP static TimingCalibration load(const String& filename);
};

/** @brief Estimates one clock offset, line delay (and optionally ωn, ζ) that hold for a whole
recording, from several frames each paired with a still frame taken before it: the sensorless
identification the seed's approach calls for @cite DynblurSeed, with no encoder, only frames.

Each reference is carried through the blur the corrected model predicts for its frame (reduced
resolution, row-wise kernels, only pixels both frames observe) and the parameters minimise the
summed squared difference to the frames, in units of the noise: a scan of the offset, then
Levenberg–Marquardt @cite Marquardt1963Algorithm, coarse to fine. Frames in window IV carry no
information and are left out, and so are frames whose own consistency stays above
`maxConsistency` at the joint result (a wrong schedule, something moving).

@param plant the nominal plant.
@param camera the camera (its image size is the frames').
@param references still frames, one per frame, at `referenceAngles` (8-bit sRGB or CV_32F linear
       [0, 1], 1, 3 or 4 channels, the camera's image size, the same type as their frame).
@param frames the blurred frames.
@param schedules each frame's command (on the actuator's clock).
@param shutters each frame's timing as the camera reports it (on its own clock).
@param flags MotionRefinement flags; REFINE_NONE is refused.
@param referenceAngles each reference's angle, radians; empty: each schedule's initial resting angle.
@param maxTimeOffset half-width of the offset scan, seconds, in (0, 1].
@param maxConsistency frames above it at the result are left out of the final fit, > 1. */
CV_EXPORTS_W TimingCalibration calibrateTiming(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera,
                                               InputArrayOfArrays references, InputArrayOfArrays frames,
                                               const std::vector<SwitchSchedule>& schedules,
                                               const std::vector<RollingShutter>& shutters,
                                               int flags = REFINE_TIME_OFFSET | REFINE_LINE_DELAY,
                                               const std::vector<double>& referenceAngles = std::vector<double>(),
                                               double maxTimeOffset = 0.02, double maxConsistency = 3.0);

/** @brief The clock offset, line delay (and optionally the gyro bias) of a recording whose motion
was measured (a gyro log, CameraMotion::fromAngularVelocity or GyroLog::toMotion), estimated jointly
from several frames each paired with a still frame of the same stream: calibrateTiming's fit
with the motion's blur in place of the plant's.

Each still is placed on the motion by its capture time: the orientation at the middle row's
mid-exposure instant of its shutter, on the frames' clock (so the offset moves it with the frames).
Take stills held steady (their own blur is not modelled) and, to observe a bias, some tenths of a
second from their frames: the bias shows as the turn it adds between the two.
@param motion the measured motion (not a plant's: calibrateTiming(plant, ...) refines the plant too);
       its time span must cover every frame's and still's readout, widened by maxTimeOffset.
@param camera the camera (its image size is the frames').
@param references still frames, one per frame (see calibrateTiming).
@param frames the blurred frames, the same type as their still.
@param shutters each frame's timing as the camera reports it.
@param referenceShutters each still's timing as the camera reports it (its rows are the frame height).
@param flags MotionRefinement flags among REFINE_TIME_OFFSET, REFINE_LINE_DELAY and REFINE_GYRO_BIAS
       (REFINE_PLANT is ignored); none of them is refused.
@param maxTimeOffset half-width of the offset scan, seconds, in (0, 1].
@param maxConsistency frames above it at the result are left out of the final fit, > 1. */
CV_EXPORTS_W TimingCalibration calibrateTiming(const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera,
                                               InputArrayOfArrays references, InputArrayOfArrays frames,
                                               const std::vector<RollingShutter>& shutters,
                                               const std::vector<RollingShutter>& referenceShutters,
                                               int flags = REFINE_TIME_OFFSET | REFINE_LINE_DELAY,
                                               double maxTimeOffset = 0.02, double maxConsistency = 3.0);

/** @brief The clock offset, line delay and each axis's natural frequency and damping ratio of a
recording made with a mount (Mount::motion, one motion per frame: its move), estimated jointly from
several frames each paired with a still frame taken at rest before or after its move:
calibrateTiming's fit with the mount's blur in place of one plant's.

A frame's still is the view with every axis at its resting angle before the move (the initial levels)
or, where `referencesAfter` says so, after it (the final levels). A frame that starts at rest is best
compared with the still before its move, one that ends at rest with the one after it
(DynamicDeblurrer::setReferenceFrames). With REFINE_PLANT an axis that no frame's move turns is held at
its nominal plant (MotionCorrection::heldParameters).
@param motions each frame's motion, made by Mount::motion (its schedules on the actuators' clock).
@param camera the camera (its image size is the frames').
@param references still frames, one per frame (see calibrateTiming).
@param frames the blurred frames, the same type as their still.
@param shutters each frame's timing as the camera reports it.
@param flags MotionRefinement flags among REFINE_TIME_OFFSET, REFINE_LINE_DELAY and REFINE_PLANT;
       none of them is refused.
@param referencesAfter one per frame, non-zero: its still was taken after its move; empty: every still
       before its move.
@param maxTimeOffset half-width of the offset scan, seconds, in (0, 1].
@param maxConsistency frames above it at the result are left out of the final fit, > 1. */
CV_EXPORTS_W TimingCalibration calibrateTiming(const std::vector<Ptr<CameraMotion>>& motions,
                                               const Ptr<CameraModel>& camera, InputArrayOfArrays references,
                                               InputArrayOfArrays frames, const std::vector<RollingShutter>& shutters,
                                               int flags = REFINE_TIME_OFFSET | REFINE_LINE_DELAY,
                                               const std::vector<int>& referencesAfter = std::vector<int>(),
                                               double maxTimeOffset = 0.02, double maxConsistency = 3.0);

/** @brief The consistency (MotionCorrection::consistency) of candidate corrections with one frame:
the objective calibrateTiming and DynamicDeblurrer minimise, for plots and diagnostics.
@param plant the nominal plant.
@param camera the camera.
@param reference the still frame (see calibrateTiming).
@param frame the blurred frame, the same type as reference.
@param schedule the frame's command.
@param shutter the frame's timing as reported.
@param candidates corrections to evaluate.
@param referenceAngle the reference's angle, radians; NaN: the schedule's initial resting angle.
@param maxWidth the frames are halved (as cv::resize with INTER_AREA) until at most this wide, pixels, ≥ 16.
@return one consistency per candidate. */
CV_EXPORTS_W std::vector<double> motionConsistency(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera,
                                                   InputArray reference, InputArray frame,
                                                   const SwitchSchedule& schedule, const RollingShutter& shutter,
                                                   const std::vector<MotionCorrection>& candidates,
                                                   double referenceAngle = std::numeric_limits<double>::quiet_NaN(),
                                                   int maxWidth = 320);

/** @brief The blind criterion of candidate corrections for one frame without a reference frame:
the objective DynamicDeblurrer::setBlindRefinement minimises, for plots and diagnostics.

A blurred row is a weighted sum of scene rows; for a scene with vertical semivariogram γ the mean
squared difference of two rows follows from their two kernels and γ. The rows that stay still under
every candidate measure γ; the criterion is the mean squared log ratio of the moving rows' measured
differences (lags of 1 to 8 rows, at most `maxWidth` wide) to the ones each candidate's blur
predicts, at the scene contrast that fits best. It has no unit: 0 is a perfect fit, measured about
0.02 to 0.1 where the model is right. Every value is NaN when fewer than 24 rows (at that width) are
still under every candidate: a global shutter in motion throughout the readout, window II, or a
rolling frame whose moving rows cover it.
@param plant the nominal plant.
@param camera the camera.
@param frame the blurred frame (8-bit sRGB or CV_32F linear [0, 1], 1, 3 or 4 channels, the camera's size).
@param schedule the frame's command.
@param shutter the frame's timing as reported.
@param candidates corrections to evaluate (the rows still under all of them measure the scene).
@param maxWidth the frame is halved (as cv::resize with INTER_AREA) until at most this wide, pixels, in [64, 4096].
@return one value per candidate. */
CV_EXPORTS_W std::vector<double> blindMotionConsistency(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera,
                                                        InputArray frame, const SwitchSchedule& schedule,
                                                        const RollingShutter& shutter,
                                                        const std::vector<MotionCorrection>& candidates,
                                                        int maxWidth = 320);

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
