// SPDX-License-Identifier: Apache-2.0
#ifndef OPENCV_DYNBLUR_DEBLURRER_HPP
#define OPENCV_DYNBLUR_DEBLURRER_HPP

#include <opencv2/dynblur/deconv.hpp>
#include <opencv2/dynblur/psf.hpp>
#include <opencv2/dynblur/refinement.hpp>

namespace cv {
namespace dynblur {

//! @addtogroup dynblur_restoration
//! @{

//! Restoration method used by DynamicDeblurrer.
enum DeblurMethod
{
    DEBLUR_RICHARDSON_LUCY = 0,  //!< spatially variant Richardson–Lucy (default)
    DEBLUR_WIENER = 1            //!< Wiener: fast, non-iterative
};

/** @brief Resolution of DynamicDeblurrer's color phase: the RLParams::colorIterations that run on
every color plane of a 3- or 4-channel frame. */
enum DeblurColorResolution
{
    /** the color iterations run on the frame's planes, then the luminance (the planes' mean) takes
        the remaining ones and its change scales every plane (RLParams::colorIterations) */
    DEBLUR_COLOR_FULL_RESOLUTION = 0,
    /** the color iterations run on the frame halved (cv::INTER_AREA), with the kernels of a
        half-size camera and shutter, as video codecs subsample chroma @cite Poynton2012Digital; the
        luminance takes every iteration at full resolution from the start, and each pixel's
        upsampled color is scaled to it. Color costs a quarter; fine detail, which is mostly
        luminance, is kept (DeblurQuality holds its gain over DEBLUR_COLOR_FULL_RESOLUTION in the
        frame-rate setting; BM_FrameRatePaired's full_color_over_rows in perf/perf_deblurrer.cpp
        measures the time it saves). The camera's image size must be even. */
    DEBLUR_COLOR_HALF_RESOLUTION = 1
};

/** @brief Settings of DynamicDeblurrer chosen together (DynamicDeblurrer::setPreset). */
enum DeblurPreset
{
    /** PSF_AUTO, Richardson–Lucy, 20 iterations in full color, automatic damping (the deblurrer's
        defaults) */
    DEBLUR_PRESET_DEFAULT = 0,
    /** PSF_AUTO, iterations by need, per frame from its PSF bank: where its longest kernel L is at
        most 8 px, 8 iterations in color at full resolution; else 10 where L ≤ 32 px and its most
        spread kernel spreads a point's light over N = 1 / Σk² ≤ 12 px, 20 otherwise, and
        ceil(L / 6.5) of them (3 to 14) in color at half resolution (DEBLUR_COLOR_HALF_RESOLUTION,
        when the image size is even); bfloat16 blurs (RL_BLUR_BFLOAT16), automatic damping and the
        automatic stop (RLParams::tolerance 2e-3).
        getRLParams() returns the long blur's iterations; setRLParams fixes them again. */
    DEBLUR_PRESET_FRAME_RATE = 1
};

/** @brief What DynamicDeblurrer writes where the frame never saw the restored view (content beyond
the frame's edges at the reference angle; the validMask's 0 pixels). */
enum UnobservedFill
{
    UNOBSERVED_RECORDED = 0,  //!< the frame's own pixel there, as recorded (default)
    UNOBSERVED_MARKED = 1,    //!< black (alpha, if any, opaque): visibly unrestored
    UNOBSERVED_NEAREST = 2    //!< the nearest observed pixel: smooth at a seam, streaks across a wide band
};

/** @brief Restores frames taken while the positioner moves: the blur of every pixel is predicted
from the plant and the commands, then undone @cite DynblurSeed.

deblur() follows one frame through the pipeline: the correction of the predicted motion (a
calibration, refined per frame against a still reference frame), the exposure window
(classifyExposure), the kernels (PsfGenerator), the restoration (richardsonLucyVariant). The result
is the global-shutter, motion-free view at θ_ref: rolling-shutter geometry and blur are undone
together.

Real hardware is never exactly the model: the camera's clock is offset from the actuator's by an
unknown latency, the line delay is nominal, and the plant's ωn and ζ drift. With still frames of the
same stream (setReferenceFrames: the still before the move and the one after it; the deblurrer
chooses per frame the one that observed the frame's moving rows), every frame is first explained by
the still carried through the predicted blur; the correction that explains it best (setRefinement)
is used for the restoration, and a frame that no correction explains (a fit stopped at a search
bound, or a consistency above setConsistencyLimit: a wrong schedule, something moving in the scene,
a bumped camera) is returned unchanged rather than made worse. Without a still the model is used as
told (with setCalibration's correction), or, with setBlindRefinement, the time offset is estimated
from the frame alone.

A frame whose motion keeps it sharp (within setSharpThreshold, 1 px by default) is not
deconvolved, which gains little there and can end below the recorded frame: it is returned as it
came, or, displaced from the reference view, its rows are moved back by resampling.
*/
class CV_EXPORTS_W DynamicDeblurrer : public Algorithm
{
public:
    /** @param plant the positioner. @param camera the camera. */
    CV_WRAP static Ptr<DynamicDeblurrer> create(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera);

    /** @brief Restores one frame.
    @param frame CV_8U (sRGB, linearised for restoration and encoded back) or CV_32F (linear,
           [0,1], as a sensor delivers it: clip noisy data first), 1, 3 or 4 channels, the camera's
           image size.
    @param schedule the command in force around the frame.
    @param shutter the frame's timing (rows = frame height).
    @param restored output, same size, type and channels as frame. A frame in window IV comes
           back unchanged; one its motion keeps sharp is not deconvolved (setSharpThreshold).
    @param thetaRef reference angle, radians; NaN: the schedule's final resting angle.
    @param validMask optional output, CV_8U, 255 where the frame observed the restored pixel (the
           others hold what setUnobservedFill says). */
    CV_WRAP virtual void deblur(InputArray frame, const SwitchSchedule& schedule, const RollingShutter& shutter,
                                OutputArray restored, double thetaRef = std::numeric_limits<double>::quiet_NaN(),
                                OutputArray validMask = noArray()) = 0;

    /** @brief A deblurrer for measured motion (a gyroscope, encoders): it needs no plant, and
    restores frames with deblur(frame, motion, shutter, ...).
    @param camera the camera. */
    CV_WRAP static Ptr<DynamicDeblurrer> create(const Ptr<CameraModel>& camera);

    /** @brief Restores one frame of any camera motion (DESIGN §2, Rotation): the view at the
    orientation Q(tRef).

    A plant's motion (CameraMotion::fromPlant, with the deblurrer's plant and the camera's mount
    axis) is restored exactly as deblur(frame, schedule, shutter, restored, θ(tRef)), refinement
    included. A measured motion starts from setCalibration's clock offset, line delay and gyro bias
    (none: as told); with a still placed by its capture time (setReferenceFrame(still, stillShutter))
    the clock offset (within ±15 ms of the calibration), the line delay and, with REFINE_GYRO_BIAS,
    the gyro bias are refined against it (getRefinement; REFINE_PLANT is ignored), and the frame is
    refused or kept as told exactly as for a plant's (the significance test, bound-pinned fits,
    setConsistencyLimit). The exposure window comes from its rates (classifyExposure). A mount's
    motion (Mount::motion) is plant-driven and restored as a plant's frame is: from the calibration's
    clock offset, line delay and each axis's plant scales (MotionCorrection::correctMotion), refined
    against the stills at rest before and after its move (setReferenceFrames without angles: every
    axis at its resting angle), an axis its move does not turn held (MotionCorrection::heldParameters);
    a NaN tRef restores the view at every axis's final rest.
    @param frame as for the schedule overload.
    @param motion the camera's motion; its time span must cover the frame's readout (same clock as
           shutter.frameStart), widened by the refinement's search when a still is set.
    @param shutter the frame's timing (rows = frame height).
    @param restored output, same size, type and channels as frame.
    @param tRef reference time, seconds, on the shutter's clock (a camera time, like frameStart: the
           clock offset of setCalibration and of the refinement moves it as it moves the frame); NaN:
           a plant's final rest, a sampled motion's orientation at the middle of the frame's exposure
           (middle row, mid-exposure).
    @param validMask optional output, CV_8U, 255 where the frame observed the restored pixel. */
    CV_WRAP virtual void deblur(InputArray frame, const Ptr<CameraMotion>& motion, const RollingShutter& shutter,
                                OutputArray restored, double tRef = std::numeric_limits<double>::quiet_NaN(),
                                OutputArray validMask = noArray()) = 0;

    /** @brief MotionRefinement flags: what each frame's correction may change (default REFINE_ALL).
    It runs only while a reference frame is set; REFINE_NONE keeps the consistency check. */
    CV_WRAP virtual int getRefinement() const = 0;
    /** @param flags MotionRefinement flags, in [0, 7]. */
    CV_WRAP virtual void setRefinement(int flags) = 0;
    /** @brief Sets one still frame that every next frame is compared with, whatever its window
    (setReferenceFrames(still, noArray(), angle) does the same).
    @param still a frame of the same stream (its type and channels) taken at rest, the camera's image size.
    @param angle the angle it was taken at, radians, within [-π/2, π/2]; NaN: each frame's schedule's
           initial resting angle (the frame before a move). For a measured motion the still is placed
           by its capture time instead: use the overload that takes the still's shutter. */
    CV_WRAP virtual void setReferenceFrame(InputArray still,
                                           double angle = std::numeric_limits<double>::quiet_NaN()) = 0;
    /** @brief Sets one still frame for frames of a measured motion (deblur(frame, motion, ...) with a
    motion that is not a plant's), placed on the motion by its capture time: the view at the
    orientation Q(t_s + δt), t_s the middle row's mid-exposure instant of `stillShutter` on the frames'
    clock and δt the clock offset being refined (a camera timestamp, the offset moves it with the
    frames). The still's own blur is not modelled: take one held steady. A gyro bias shows as the turn
    it adds between t_s and the frame, so refining it (REFINE_GYRO_BIAS) needs a still some tenths
    of a second from the frames. A still placed this way does not serve a plant's frames (refused).
    @param still a frame of the same stream (its type and channels), the camera's image size.
    @param stillShutter its timing as the camera reports it (rows = its height). */
    CV_WRAP virtual void setReferenceFrame(InputArray still, const RollingShutter& stillShutter) = 0;
    /** @brief Sets the still frames on both sides of a move; each next frame is compared with the one
    that observed its moving rows. A frame that starts at rest (window I) moves in its later rows,
    which see the view before the move only where the move has not yet begun: it takes `before`. A
    frame that ends at rest (window III, and a global-shutter frame that settles) takes `after`:
    after a 10° tilt the top hundred rows of the final view show content the view before the move
    never saw, and in a rolling window III frame those are the rows that move (given `before`
    instead, window III kept 56 % of the truth's gain rather than 97 %). A frame moving throughout
    (window II) is compared with both. Where the chosen still is missing the other serves.
    getLastCorrection().reason says which still was used. These stills serve a plant's frames; a
    measured motion's still is placed by its capture time (setReferenceFrame(still, stillShutter)).
    @param before the still frame before the move (empty: none), same stream and size as the frames.
    @param after the still frame after the move (empty: none), the same type as `before`.
    @param angleBefore the angle `before` was taken at, radians, within [-π/2, π/2]; NaN: each frame's
           schedule's initial resting angle.
    @param angleAfter the angle `after` was taken at, radians, within [-π/2, π/2]; NaN: each frame's
           schedule's final resting angle. */
    CV_WRAP virtual void setReferenceFrames(InputArray before, InputArray after,
                                            double angleBefore = std::numeric_limits<double>::quiet_NaN(),
                                            double angleAfter = std::numeric_limits<double>::quiet_NaN()) = 0;
    /** @brief Measures the noise the refinement weighs its residuals by from two stills at rest at
    the same view (consecutive frames of the stream, nothing moving between them): both are reduced as
    the fit reduces a frame (linear luminance, halved to 320 and 160 px), and at each of those scales
    the robust standard deviation of their difference (1.4826 × its median absolute deviation; clipped
    pixels left out) over √2 is the noise of one frame there, with the camera's own correlation and a
    codec's (MJPEG) included. Without them the noise is Immerkær's estimate on the reference still at
    each scale @cite Immerkaer1996Noise, which its texture inflates (docs/refinement.md). In these
    units a right model measures a consistency up to about 6, and the default consistency limit is
    7.5 (getConsistencyLimit). The stills may be the reference frames themselves; the measurement
    holds for every still set before or after it, until setNoiseFrames(noArray(), noArray()).
    @param stillA a still frame of the frames' stream (their type and channels), the camera's image
           size, intensities as the frames' (CV_8U sRGB or linear CV_32F in [0, 1]).
    @param stillB the next still at the same view, the type and size of `stillA`; it must differ
           from `stillA` in most pixels (the same capture twice measures no noise: refused). Both
           empty: forget the measurement (Immerkær's estimate again). */
    CV_WRAP virtual void setNoiseFrames(InputArray stillA, InputArray stillB) = 0;
    /** @brief Sets a neighbour of the next frame of a measured motion's stream (a video's previous
    frame, or for the first frame the one after it): with no still frame set, the next frame is
    checked against it. A grid of patches of the neighbour is looked for in the frame where the
    motion, with setCalibration's clock offset, line delay, bias and rate scale, carries it (each
    from the instant its row was exposed in the neighbour to the instant its row was exposed in the
    frame); phase correlation finds how far off the content is. The median error, times the frame's
    exposure over the interval between the two frames, is the error it implies in the frame's blur
    (getLastCorrection().consistency, pixels). Where it exceeds both getNeighbourLimit and 0.6 of the
    frame's blur as the images show it (measurement between heavily blurred frames errs in proportion
    to their blur) the frame is returned unchanged, reason saying so: a wrong log (rates in °/s read
    as rad/s, another clip's log, swapped axes, a clock off) or something moving across the view. It
    catches what is grossly wrong; a mapping of the axes that nearly agrees with the images over a
    frame can pass it, which ClipTimingCalibrator (the clip's calibration) does not let through. A
    frame with fewer than 6 textured patches is not judged. Call it before each frame with its
    neighbour; an empty frame forgets it. Not used for a plant's frames, nor while a still frame is
    set.
    @param frame a neighbouring frame of the stream (its type and channels), the camera's image size.
    @param shutter its timing as the camera reports it (rows = its height), frameStart other than the
           next frame's. */
    CV_WRAP virtual void setNeighbourFrame(InputArray frame, const RollingShutter& shutter) = 0;
    /** @brief The blur error, pixels, that setNeighbourFrame's check accepts whatever the frame's blur
    (default 1 px: an error below it does not harm a restoration). */
    CV_WRAP virtual double getNeighbourLimit() const = 0;
    /** @param limitPx > 0, pixels (+inf: no check). */
    CV_WRAP virtual void setNeighbourLimit(double limitPx) = 0;
    /** @brief Forgets the still frames (not the noise frames): frames are restored with the model as told. */
    CV_WRAP virtual void clearReferenceFrame() = 0;
    /** @brief Whether a frame without a reference frame is refined blind (default false: the
    model as told). Blind, only the time offset is estimated (with REFINE_TIME_OFFSET among the
    flags): the one whose blur best predicts how the frame's moving rows differ from one another,
    given the scene's statistics measured on its still rows (blindMotionConsistency). It is kept
    only when it explains them decisively better than the model as told, and it needs still rows: a
    global-shutter frame or one in window II is restored as told. getLastCorrection().reason starts
    with "blind" and says what decided. */
    CV_WRAP virtual bool getBlindRefinement() const = 0;
    /** @param enabled refine frames without a reference frame blind. */
    CV_WRAP virtual void setBlindRefinement(bool enabled) = 0;
    /** @brief Blind frames whose criterion at the correction kept (getLastCorrection().consistency,
    blindMotionConsistency's scale) exceeds it are returned unchanged (default +inf: no check).
    Measured 0.05 to 0.73 on consistent frames; a schedule shifted by 10 ms gave 3.7 and 5.2, another
    move or a moving object 1.0 in window I but 0.05 to 0.13 in window III (RefinementBlindRejection):
    a limit of 0.9 catches the first and only some of the others. */
    CV_WRAP virtual double getBlindConsistencyLimit() const = 0;
    /** @param limit > 0, or +inf. */
    CV_WRAP virtual void setBlindConsistencyLimit(double limit) = 0;
    /** @brief The correction used for the last frame, its consistency, and whether it was applied. */
    CV_WRAP virtual MotionCorrection getLastCorrection() const = 0;
    /** @brief The correction every frame starts from (default none): a recording's calibration
    (calibrateTiming), refined per frame from there. With a calibration and REFINE_TIME_OFFSET
    alone, a frame's refinement looks for the frame's jitter only (a fraction of a millisecond
    around the calibrated offset) and costs a few forward models. */
    CV_WRAP virtual MotionCorrection getCalibration() const = 0;
    /** @param correction the calibrated correction (its consistency, applied and reason are ignored). */
    CV_WRAP virtual void setCalibration(const MotionCorrection& correction) = 0;
    /** @brief Frames whose corrected model's MotionCorrection::consistency exceeds it are returned
    unchanged (noise units; +inf turns the check off). Default 3 in units of Immerkær's estimate on
    the still (measured 0.5 to 2.3 where the model is right), 7.5 in units of the noise
    setNoiseFrames measured (right models 1.4 to 6.3, wrong ones that would restore worse from 8.8).
    It is the user's cap: a fit stopped at one of its search bounds is refused whatever its
    consistency (docs/refinement.md, "The decision"). Needs a reference frame. */
    CV_WRAP virtual double getConsistencyLimit() const = 0;
    /** @param limit > 1, or +inf. */
    CV_WRAP virtual void setConsistencyLimit(double limit) = 0;

    /** @brief Frames whose corrected motion keeps them sharp to this many pixels are not
    deconvolved: no PSF bank, no Richardson–Lucy (default 1 px; 0: every moving frame is).

    Decided from the motion before any kernel is made, over a grid of points (17 columns edge to
    edge, every 8th row and the last): a frame is sharp when, for every point, both the extent of
    its path during its row's exposure (the greatest distance between two of its positions, at 17
    instants: its blur) and the distance of that path's mean (its kernel's centre of mass) from where
    the reference view has it (its shift: the rolling-shutter geometry and the offset from the
    reference view) stay strictly below the threshold. A sharp frame whose shift stays below 0.05 px
    is returned as it came; otherwise its rows are moved back to the reference view by bicubic
    resampling (the validMask and setUnobservedFill as for a restored frame), since a tenth of a
    pixel of misplacement already costs a few tenths of a dB against the reference view.
    Deconvolving a frame this sharp gains little, and on fine texture its regularisation costs more
    than that: such frames ended up to 2.6 dB below the recorded frame (docs/quality.md, "Nearly
    sharp frames"). For a frame not deconvolved, getLastCorrection() has applied = true (the
    correction stands: the frame needs no more) and a reason that starts with "sharp:", gives both
    figures and says whether the rows were moved back; getLastPlan() and getLastPsfBank() are empty,
    as for a frame still throughout. Rows whose displacements fold over one another (a vibration
    faster than the readout) cannot be moved back: such a frame is deconvolved. */
    CV_WRAP virtual double getSharpThreshold() const = 0;
    /** @param px the threshold, pixels, finite and ≥ 0 (0: every moving frame is deconvolved). */
    CV_WRAP virtual void setSharpThreshold(double px) = 0;

    /** @brief PsfModel (default PSF_AUTO: per band of rows the cheapest model within
    getPsfGenerator()->getAutoTolerance() of the exact blur; getLastPlan says what it chose). */
    CV_WRAP virtual int getPsfModel() const = 0;
    /** @param model PSF_UNIFORM, PSF_ROWS, PSF_TILES or PSF_AUTO. */
    CV_WRAP virtual void setPsfModel(int model) = 0;
    /** @brief Sets the PSF model, the method, the color resolution and the RLParams of `preset`
    together; each stays settable afterwards.
    @param preset DeblurPreset. */
    CV_WRAP virtual void setPreset(int preset) = 0;
    /** @brief What PSF_AUTO chose for the last restored frame (PsfPlan); with a fixed model, only
    PsfPlan::model is set (empty bands). A frame returned unchanged leaves PsfPlan() (no bands). */
    CV_WRAP virtual PsfPlan getLastPlan() const = 0;
    CV_WRAP virtual int getMethod() const = 0;              //!< DeblurMethod
    CV_WRAP virtual void setMethod(int method) = 0;
    /** @brief DeblurColorResolution (default DEBLUR_COLOR_FULL_RESOLUTION). It applies to
    Richardson–Lucy on 3- and 4-channel frames when RLParams::colorIterations is in [0, iterations);
    otherwise every iteration runs at full resolution. */
    CV_WRAP virtual int getColorResolution() const = 0;
    /** @param resolution DeblurColorResolution; DEBLUR_COLOR_HALF_RESOLUTION needs an even image size. */
    CV_WRAP virtual void setColorResolution(int resolution) = 0;
    /** @brief UnobservedFill: what the restored frame holds where the frame never saw the view
    (default UNOBSERVED_RECORDED). */
    CV_WRAP virtual int getUnobservedFill() const = 0;
    /** @param fill UnobservedFill. */
    CV_WRAP virtual void setUnobservedFill(int fill) = 0;
    /** @brief Restoration options; default RLParams() with automatic damping (damping = NaN: 3σ of
    the frame's estimated noise). For frame rate, setPreset(DEBLUR_PRESET_FRAME_RATE). */
    CV_WRAP virtual RLParams getRLParams() const = 0;
    CV_WRAP virtual void setRLParams(const RLParams& params) = 0;
    /** @brief Exposure window of the last frame passed to deblur() (0 before the first). */
    CV_WRAP virtual int getLastExposureWindow() const = 0;
    /** @brief Kernels used for the last frame (with DEBLUR_COLOR_HALF_RESOLUTION, the full-resolution
    ones, which the luminance took). */
    CV_WRAP virtual PsfBank getLastPsfBank() const = 0;
    CV_WRAP virtual Ptr<PsfGenerator> getPsfGenerator() const = 0;
};

//! @}

}  // namespace dynblur
}  // namespace cv

#endif
