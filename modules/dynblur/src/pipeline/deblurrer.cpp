// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"

#include "imaging/psf_generator.hpp"
#include "motion/camera_motion.hpp"
#include "motion/corrected_motion.hpp"
#include "pipeline/blind_fit.hpp"
#include "pipeline/frame_rate_preset.hpp"
#include "pipeline/half_color.hpp"
#include "pipeline/motion_fit.hpp"
#include "motion/shutter_check.hpp"
#include "restore/arguments.hpp"
#include "restore/deconv_rl.hpp"

namespace cv {
namespace dynblur {

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();
}

class DynamicDeblurrerImpl CV_FINAL : public DynamicDeblurrer
{
public:
    DynamicDeblurrerImpl(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera)
        : plant_(plant), camera_(camera),
          generator_(plant ? PsfGenerator::create(plant, camera) : PsfGenerator::create(camera))
    {
        // Webcam frames carry shot and read noise: damp at the frame's own noise level.
        params_.damping = std::numeric_limits<double>::quiet_NaN();
        workspace_.persistent = true;
        halfWorkspace_.persistent = true;
    }

    /* One frame, stage by stage: the motion that happened (refined), the frame as light, its blur
       (the PSF bank), the restoration, and the restored frame in the input's encoding. */
    void deblur(InputArray frame, const SwitchSchedule& schedule, const RollingShutter& shutter, OutputArray restored,
                double thetaRef, OutputArray validMask) CV_OVERRIDE
    {
        if (plant_.empty())
            CV_Error(Error::StsBadArg, "DynamicDeblurrer::deblur: this deblurrer was created without a plant "
                                       "(DynamicDeblurrer::create(camera)); give it the frame's motion: "
                                       "deblur(frame, motion, shutter, restored, tRef)");
        const Mat input = frame.getMat();
        checkFrame(input, shutter);
        // thetaRef is checked before the refinement's work, and again on the corrected plant below.
        detail::ViewMotion::ofPlant("DynamicDeblurrer::deblur", plant_, schedule, camera_->getMountAxis(), thetaRef);

        lastCorrection_ = correctMotion(input, schedule, shutter);
        const Ptr<Plant> plant = lastCorrection_.correctPlant(plant_);
        const RollingShutter corrected = lastCorrection_.correctShutter(shutter);
        lastWindow_ = classifyExposure(plant, schedule, corrected);
        const detail::ViewMotion view =
            detail::ViewMotion::ofPlant("DynamicDeblurrer::deblur", plant, schedule, camera_->getMountAxis(), thetaRef);
        restoreFrame(input, view, corrected, restored, validMask);
    }

    void deblur(InputArray frame, const Ptr<CameraMotion>& motion, const RollingShutter& shutter,
                OutputArray restored, double tRef, OutputArray validMask) CV_OVERRIDE
    {
        const Mat input = frame.getMat();
        checkFrame(input, shutter);
        if (motion.empty())
            CV_Error(Error::StsNullPtr, "DynamicDeblurrer::deblur: motion is empty");
        if (std::isinf(tRef))
            CV_Error(Error::StsBadArg, "DynamicDeblurrer::deblur: tRef must be finite (seconds) or NaN (the motion's "
                                       "default reference: a plant's final rest, a sampled motion's mid-exposure)");
        if (const detail::PlantMotion* plantMotion = detail::asPlantMotion(*motion))
        {
            if (!samePlant(plantMotion->plant()) || norm(plantMotion->axis() - camera_->getMountAxis()) > 1e-12)
                CV_Error(Error::StsBadArg,
                         "DynamicDeblurrer::deblur: a plant's motion (CameraMotion::fromPlant) must use the "
                         "deblurrer's plant (the same object, or a linear plant of the same natural frequency, "
                         "damping ratio and gain) and the camera's mount axis: refinement corrects that plant; "
                         "create the deblurrer with the motion's plant, or set the camera's mount axis");
            return deblur(frame, plantMotion->schedule(), shutter, restored, plantMotion->referenceAngle(tRef),
                          validMask);
        }
        lastCorrection_ = correctMeasured(input, motion, shutter);
        const RollingShutter corrected = lastCorrection_.correctShutter(shutter);
        detail::checkMotionCovers(motion, corrected.readoutInterval(), "DynamicDeblurrer::deblur", "motion");
        lastWindow_ = classifyExposure(motion, corrected);
        restoreFrame(input, detail::correctedView(motion, lastCorrection_, tRef, corrected), corrected, restored,
                     validMask);
    }

    int getRefinement() const CV_OVERRIDE { return refinement_; }
    void setRefinement(int flags) CV_OVERRIDE
    {
        if (flags < REFINE_NONE || flags > (REFINE_ALL | REFINE_GYRO_BIAS))
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setRefinement: flags = %d must combine REFINE_TIME_OFFSET (1), "
                            "REFINE_LINE_DELAY (2), REFINE_PLANT (4) and REFINE_GYRO_BIAS (8): a value in [0, 15]",
                            flags));
        refinement_ = flags;
    }
    void setReferenceFrame(InputArray still, double angle) CV_OVERRIDE
    {
        const char* fn = "DynamicDeblurrer::setReferenceFrame";
        setStills(fn, still.getMat(), "still", angle, "angle", Mat(), "", kNaN, "");
        single_ = true;
    }
    void setReferenceFrame(InputArray still, const RollingShutter& stillShutter) CV_OVERRIDE
    {
        const char* fn = "DynamicDeblurrer::setReferenceFrame";
        const Mat image = still.getMat();
        detail::checkShutter(stillShutter, fn, "stillShutter.", image.empty() ? 0 : image.rows);
        setStills(fn, image, "still", kNaN, "angle", Mat(), "", kNaN, "");
        stills_[0].time = detail::midExposure(stillShutter);
        single_ = true;
    }
    void setReferenceFrames(InputArray before, InputArray after, double angleBefore, double angleAfter) CV_OVERRIDE
    {
        const char* fn = "DynamicDeblurrer::setReferenceFrames";
        const Mat first = before.getMat(), second = after.getMat();
        if (first.empty() && second.empty())
            CV_Error(Error::StsBadArg, format("%s: both 'before' and 'after' are empty; give at least one still "
                                              "frame (or call clearReferenceFrame)",
                                              fn));
        setStills(fn, first, "before", angleBefore, "angleBefore", second, "after", angleAfter, "angleAfter");
        single_ = false;
    }
    void setNoiseFrames(InputArray stillA, InputArray stillB) CV_OVERRIDE
    {
        const Mat a = stillA.getMat(), b = stillB.getMat();
        const bool forget = a.empty() && b.empty();
        noiseSigma_ = forget ? std::vector<double>()
                             : detail::measureNoise(a, b, camera_, "DynamicDeblurrer::setNoiseFrames");
        noiseType_ = forget ? -1 : a.type();
        weighStills();
    }
    // The noise each still's pyramid weighs residuals by: the noise frames' when given, else Immerkær's.
    void weighStills()
    {
        for (Still& still : stills_)
            still.pyramid.noiseSigma = noiseSigma_.empty() ? still.estimatedNoise : noiseSigma_;
    }
    void clearReferenceFrame() CV_OVERRIDE
    {
        stills_[0] = stills_[1] = Still();
        referenceType_ = -1;
    }
    MotionCorrection getLastCorrection() const CV_OVERRIDE { return lastCorrection_; }
    bool getBlindRefinement() const CV_OVERRIDE { return blind_; }
    void setBlindRefinement(bool enabled) CV_OVERRIDE { blind_ = enabled; }
    double getBlindConsistencyLimit() const CV_OVERRIDE { return blindLimit_; }
    void setBlindConsistencyLimit(double limit) CV_OVERRIDE
    {
        if (!(limit > 0))
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setBlindConsistencyLimit: limit = %g must be > 0 (or +inf: no check)",
                            limit));
        blindLimit_ = limit;
    }
    MotionCorrection getCalibration() const CV_OVERRIDE { return calibration_; }
    void setCalibration(const MotionCorrection& correction) CV_OVERRIDE
    {
        correction.validate();
        calibration_ = MotionCorrection();
        calibration_.timeOffset = correction.timeOffset;
        calibration_.lineDelayScale = correction.lineDelayScale;
        calibration_.naturalFreqScale = correction.naturalFreqScale;
        calibration_.dampingScale = correction.dampingScale;
        calibration_.gyroBias = correction.gyroBias;
        calibrated_ = true;
    }
    double getConsistencyLimit() const CV_OVERRIDE
    {
        if (!std::isnan(consistencyLimit_))
            return consistencyLimit_;
        return noiseSigma_.empty() ? kEstimatedNoiseLimit : kMeasuredNoiseLimit;
    }
    void setConsistencyLimit(double limit) CV_OVERRIDE
    {
        if (!(limit > 1))
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setConsistencyLimit: limit = %g must be > 1 (or +inf: no check)", limit));
        consistencyLimit_ = limit;
    }

    int getPsfModel() const CV_OVERRIDE { return psfModel_; }
    void setPsfModel(int model) CV_OVERRIDE
    {
        if (model != PSF_UNIFORM && model != PSF_ROWS && model != PSF_TILES && model != PSF_AUTO)
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setPsfModel: model = %d must be PSF_UNIFORM (0), PSF_ROWS (1), "
                            "PSF_TILES (2) or PSF_AUTO (3)", model));
        psfModel_ = model;
    }
    void setPreset(int preset) CV_OVERRIDE
    {
        if (preset != DEBLUR_PRESET_DEFAULT && preset != DEBLUR_PRESET_FRAME_RATE)
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setPreset: preset = %d must be DEBLUR_PRESET_DEFAULT (0) or "
                            "DEBLUR_PRESET_FRAME_RATE (1)", preset));
        RLParams params = preset == DEBLUR_PRESET_FRAME_RATE ? detail::frameRatePresetParams() : RLParams();
        params.damping = kNaN;
        psfModel_ = PSF_AUTO;
        method_ = DEBLUR_RICHARDSON_LUCY;
        colorResolution_ = DEBLUR_COLOR_FULL_RESOLUTION;
        iterationsByNeed_ = preset == DEBLUR_PRESET_FRAME_RATE;
        if (preset == DEBLUR_PRESET_FRAME_RATE)
        {
            const Size size = camera_->getImageSize();
            if (size.width % 2 == 0 && size.height % 2 == 0)
                colorResolution_ = DEBLUR_COLOR_HALF_RESOLUTION;
        }
        params_ = params;
    }
    PsfPlan getLastPlan() const CV_OVERRIDE { return lastPlan_; }
    int getMethod() const CV_OVERRIDE { return method_; }
    void setMethod(int method) CV_OVERRIDE
    {
        if (method != DEBLUR_RICHARDSON_LUCY && method != DEBLUR_WIENER)
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setMethod: method = %d must be DEBLUR_RICHARDSON_LUCY (0) or "
                            "DEBLUR_WIENER (1)", method));
        method_ = method;
    }
    int getColorResolution() const CV_OVERRIDE { return colorResolution_; }
    void setColorResolution(int resolution) CV_OVERRIDE
    {
        if (resolution != DEBLUR_COLOR_FULL_RESOLUTION && resolution != DEBLUR_COLOR_HALF_RESOLUTION)
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setColorResolution: resolution = %d must be "
                            "DEBLUR_COLOR_FULL_RESOLUTION (0) or DEBLUR_COLOR_HALF_RESOLUTION (1)",
                            resolution));
        const Size size = camera_->getImageSize();
        if (resolution == DEBLUR_COLOR_HALF_RESOLUTION && (size.width % 2 != 0 || size.height % 2 != 0))
            CV_Error(Error::StsBadSize,
                     format("DynamicDeblurrer::setColorResolution: DEBLUR_COLOR_HALF_RESOLUTION needs an even "
                            "image size; the camera's is %dx%d",
                            size.width, size.height));
        colorResolution_ = resolution;
    }
    int getUnobservedFill() const CV_OVERRIDE { return unobservedFill_; }
    void setUnobservedFill(int fill) CV_OVERRIDE
    {
        if (fill != UNOBSERVED_RECORDED && fill != UNOBSERVED_MARKED && fill != UNOBSERVED_NEAREST)
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setUnobservedFill: fill = %d must be UNOBSERVED_RECORDED (0), "
                            "UNOBSERVED_MARKED (1) or UNOBSERVED_NEAREST (2)", fill));
        unobservedFill_ = fill;
    }
    RLParams getRLParams() const CV_OVERRIDE { return params_; }
    void setRLParams(const RLParams& params) CV_OVERRIDE
    {
        checkRLParams(params, "DynamicDeblurrer::setRLParams");
        params_ = params;
        iterationsByNeed_ = false;  // the caller's iterations hold
    }
    int getLastExposureWindow() const CV_OVERRIDE { return lastWindow_; }
    PsfBank getLastPsfBank() const CV_OVERRIDE { return lastBank_; }
    Ptr<PsfGenerator> getPsfGenerator() const CV_OVERRIDE { return generator_; }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.DynamicDeblurrer"; }

private:
    //! True when `plant` is the deblurrer's, or a linear plant of the same ωn, ζ and gain.
    bool samePlant(const Ptr<Plant>& plant) const
    {
        if (plant == plant_)
            return true;
        if (plant_.empty())
            return false;
        const bool linear = plant.dynamicCast<OdePlant>().empty() && plant_.dynamicCast<OdePlant>().empty();
        return linear && plant->getNaturalFreqHz() == plant_->getNaturalFreqHz() &&
               plant->getDampingRatio() == plant_->getDampingRatio() && plant->getGain() == plant_->getGain();
    }

    /* The frame restored for the views of `view` read by `shutter` (corrected), after the motion
       stage has set lastCorrection_ and lastWindow_: the frame as light, its PSF bank, the
       restoration, and the restored frame in the input's encoding. */
    void restoreFrame(const Mat& input, const detail::ViewMotion& view, const RollingShutter& shutter,
                      OutputArray restored, OutputArray validMask)
    {
        lastBank_ = PsfBank();
        lastPlan_ = PsfPlan();
        if (lastWindow_ == EXPOSURE_IV || !lastCorrection_.applied)
            return passThrough(input, restored, validMask);  // still throughout, or no model explains it

        lastBank_ = detail::generatePsfBank(*generator_, psfModel_, view, shutter, &lastPlan_);
        if (psfModel_ != PSF_AUTO)
            lastPlan_.model = lastBank_.model;
        frameParams_ = iterationsByNeed_ ? detail::frameRateIterations(lastBank_, params_) : params_;

        Mat alpha;
        const Mat color = withoutAlpha(input, alpha);
        // The color at half resolution decodes an 8-bit frame as it reads it.
        const bool halfColor = method_ == DEBLUR_RICHARDSON_LUCY && colorAtHalfResolution(color.channels());
        const Mat linear = color.depth() == CV_8U && !halfColor ? linearized(color) : color;

        /* A frame without alpha is restored straight into the output (written last, after every
           read of the frame, so restoring in place works) when it is linear, or 8-bit with the
           color at half resolution (encoded as it is written); others go through latent_. */
        const bool direct = alpha.empty() && (input.depth() == CV_32F || halfColor);
        // Restoring in place overwrites the frame: the recorded pixels are kept for the fill first.
        const bool inPlace = restored.isMat() && !restored.empty() && restored.getMat().data == input.data;
        const Mat recorded = unobservedFill_ == UNOBSERVED_RECORDED && inPlace ? input.clone() : input;
        const Mat latent = restore(linear, view, shutter, halfColor, direct, input.depth(), restored);
        if (!direct)
            encode(latent, input.depth(), alpha, restored);
        fillUnobserved(recorded, restored.getMat());
        if (validMask.needed())
            mask_.copyTo(validMask);
    }

    //! The pixels the frame never saw (mask_ 0), as setUnobservedFill says; the restoration left
    //! them filled from the nearest observed pixels.
    void fillUnobserved(const Mat& recorded, Mat restored) const
    {
        if (unobservedFill_ == UNOBSERVED_NEAREST || countNonZero(mask_) == int(mask_.total()))
            return;
        const Mat unobserved = mask_ == 0;
        if (unobservedFill_ == UNOBSERVED_RECORDED)
            recorded.copyTo(restored, unobserved);
        else
            restored.setTo(Scalar(0, 0, 0, recorded.depth() == CV_8U ? 255 : 1), unobserved);
    }

    bool colorAtHalfResolution(int channels) const
    {
        return colorResolution_ == DEBLUR_COLOR_HALF_RESOLUTION && channels == 3 && frameParams_.colorIterations >= 0 &&
               frameParams_.colorIterations < frameParams_.iterations;
    }

    //! The frame returned as it came, every pixel valid.
    static void passThrough(const Mat& input, OutputArray restored, OutputArray validMask)
    {
        input.copyTo(restored);
        if (validMask.needed())
        {
            validMask.create(input.size(), CV_8U);
            validMask.setTo(Scalar::all(255));
        }
    }

    //! The frame's color planes; a fourth channel, alpha, goes to `alpha`: coverage, not light, it passes through.
    static Mat withoutAlpha(const Mat& input, Mat& alpha)
    {
        if (input.channels() != 4)
            return input;
        std::vector<Mat> planes;
        split(input, planes);
        alpha = planes[3];
        planes.pop_back();
        Mat color;
        merge(planes, color);
        return color;
    }

    //! An 8-bit sRGB frame as linear light, in a buffer kept between frames (a fresh one faults in its pages).
    Mat linearized(const Mat& color)
    {
        srgbToLinear(color, linear_);
        return linear_;
    }

    /* The restoration of `linear` by the method set, in [0, 1]: straight into `restored` when
       `direct` (8-bit there when the input is, with the color at half resolution), else into latent_. */
    Mat restore(const Mat& linear, const detail::ViewMotion& view, const RollingShutter& shutter, bool halfColor,
                bool direct, int inputDepth, OutputArray restored)
    {
        Mat latent = direct ? Mat() : latent_;
        _OutputArray target = direct ? restored : _OutputArray(latent);
        if (method_ == DEBLUR_WIENER)
        {
            wienerDeconvolve(linear, lastBank_, target, wienerNoiseToSignal_);
            mask_.create(linear.size(), CV_8U);
            mask_.setTo(Scalar::all(255));
        }
        else if (halfColor)
            restoreWithHalfColor(linear, view, shutter, target, direct ? inputDepth : CV_32F);
        else
            detail::restoreVariant(linear, lastBank_, frameParams_, workspace_, target, mask_, true);
        if (direct)
            latent = restored.getMat();
        else
            latent_ = latent;
        // Wiener may overshoot at edges; the output is an image in [0, 1] (RL's keeps itself there).
        if (method_ == DEBLUR_WIENER)
            parallel_for_(Range(0, latent.rows), [&](const Range& rows) {
                for (int y = rows.start; y < rows.end; y++)
                    detail::clampRowToUnit(latent.ptr<float>(y), latent.cols * latent.channels());
            });
        return latent;
    }

    //! `latent` (linear) into `restored` in the input's encoding (8-bit sRGB or linear), alpha put back.
    static void encode(const Mat& latent, int inputDepth, const Mat& alpha, OutputArray restored)
    {
        if (alpha.empty())
        {
            linearToSrgb(latent, restored, CV_8U);  // an 8-bit frame, encoded straight into the output
            return;
        }
        Mat encoded;
        if (inputDepth == CV_8U)
            linearToSrgb(latent, encoded, CV_8U);
        else
            encoded = latent;
        std::vector<Mat> planes;
        split(encoded, planes);
        planes.push_back(alpha);
        merge(planes, encoded);
        encoded.copyTo(restored);
    }

    /* Checks and keeps the stills (an empty Mat: none on that side), naming each argument as the
       caller `fn` calls it. */
    void setStills(const char* fn, const Mat& before, const char* beforeName, double angleBefore,
                   const char* angleBeforeName, const Mat& after, const char* afterName, double angleAfter,
                   const char* angleAfterName)
    {
        const Mat images[2] = {before, after};
        const char* names[2] = {beforeName, afterName};
        const double angles[2] = {angleBefore, angleAfter};
        const char* angleNames[2] = {angleBeforeName, angleAfterName};
        for (int k = 0; k < 2; k++)
        {
            if (!images[k].empty())
                detail::checkCameraFrame(images[k], *camera_, fn, names[k]);
            if (!std::isnan(angles[k]) && !(std::abs(angles[k]) <= CV_PI / 2))
                CV_Error(Error::StsOutOfRange,
                         format("%s: %s = %g rad must be within [-pi/2, pi/2] (or NaN: the schedule's %s resting "
                                "angle)",
                                fn, angleNames[k], angles[k], k == 0 ? "initial" : "final"));
        }
        if (!before.empty() && !after.empty() && before.type() != after.type())
            CV_Error(Error::StsUnmatchedFormats,
                     format("%s: '%s' is %s but '%s' is %s; both must come from the frames' stream", fn, beforeName,
                            typeToString(before.type()).c_str(), afterName, typeToString(after.type()).c_str()));
        for (int k = 0; k < 2; k++)
        {
            stills_[k] = Still();
            if (images[k].empty())
                continue;
            // Kept beyond the call: a linear one-channel still's luminance is the caller's buffer itself.
            Mat luminance = detail::linearLuminance(images[k]);
            if (luminance.data == images[k].data)
                luminance = luminance.clone();
            stills_[k].pyramid = detail::buildPyramid(luminance, camera_, detail::kFitCoarseWidth, true);
            stills_[k].estimatedNoise = stills_[k].pyramid.noiseSigma;
            stills_[k].angle = angles[k];
            referenceType_ = images[k].type();
        }
        weighStills();
    }

    /* A frame refined against the stills comes from their stream: the reference frames' type, and the
       noise frames' (setNoiseFrames measured the noise of frames of their own type only). */
    void checkStreamType(const char* fn, const Mat& input) const
    {
        if (input.type() != referenceType_)
            CV_Error(Error::StsUnmatchedFormats,
                     format("%s: 'frame' is %s but the reference frame is %s; both must come from the same stream "
                            "(or call clearReferenceFrame)",
                            fn, typeToString(input.type()).c_str(), typeToString(referenceType_).c_str()));
        if (noiseType_ >= 0 && input.type() != noiseType_)
            CV_Error(Error::StsUnmatchedFormats,
                     format("%s: 'frame' is %s but the noise frames are %s; both must come from the same stream "
                            "(or forget them: setNoiseFrames(noArray(), noArray()))",
                            fn, typeToString(input.type()).c_str(), typeToString(noiseType_).c_str()));
    }

    /* The correction for this frame: the calibration, refined against the reference frame when
       there is one and the frame moves, and refused (applied = false) when even the best
       correction leaves the frame inconsistent with the reference. */
    MotionCorrection correctMotion(const Mat& input, const SwitchSchedule& schedule, const RollingShutter& shutter)
    {
        MotionCorrection correction = calibration_;
        if (!stills_[0].present() && !stills_[1].present())
        {
            if (blind_ && (refinement_ & REFINE_TIME_OFFSET))
                return blindCorrection(input, schedule, shutter, correction);
            correction.reason = "no reference frame: the model as told (with the calibration)";
            return correction;
        }
        checkStreamType("DynamicDeblurrer::deblur", input);
        if (!std::isnan(stills_[0].time))
            CV_Error(Error::StsBadArg, "DynamicDeblurrer::deblur: the reference frame was placed by its capture time "
                                       "(setReferenceFrame(still, stillShutter)), which serves a measured motion; "
                                       "for a plant's frames give the angle it was taken at: "
                                       "setReferenceFrame(still, angle)");
        const int window =
            classifyExposure(correction.correctPlant(plant_), schedule, correction.correctShutter(shutter));
        if (window == EXPOSURE_IV)
        {
            correction.reason = "still frame: nothing to refine";
            return correction;
        }
        /* The still that observed the frame's moving rows: before the move for a frame that starts
           at rest, after it for one that ends at rest, both for one moving throughout. */
        std::vector<int> chosen;
        if (window == EXPOSURE_II && stills_[0].present() && stills_[1].present())
            chosen = {0, 1};
        else
        {
            const int preferred = window == EXPOSURE_I ? 0 : 1;
            chosen.push_back(stills_[preferred].present() ? preferred : 1 - preferred);
        }
        const detail::LuminancePyramid framePyramid =
            detail::buildPyramid(detail::linearLuminance(input), camera_, detail::kFitCoarseWidth, false);
        std::vector<detail::FitFrame> frames;
        for (int k : chosen)
        {
            detail::FitFrame fit;
            fit.reference = &stills_[k].pyramid;
            fit.frame = framePyramid;
            fit.schedule = schedule;
            fit.shutter = shutter;
            const double told = plant_->restingAngle(k == 0 ? schedule.initialLevel : schedule.finalLevel());
            fit.referenceAngle = std::isnan(stills_[k].angle) ? told : stills_[k].angle;
            frames.push_back(fit);
        }
        const String against = single_               ? "the reference frame"
                               : chosen.size() == 2 ? "the stills before and after the move"
                               : chosen[0] == 0   ? "the still before the move"
                                                  : "the still after the move";
        detail::FitSettings settings;
        settings.flags = refinement_ & REFINE_ALL;
        // From a recording's calibration only the frame's jitter is left to find: the fine level's fit alone.
        settings.coarse = !(settings.flags == REFINE_TIME_OFFSET && calibrated_);
        settings.deviation = false;
        return fitAgainst(frames, against, correction, settings);
    }

    /* The correction for a frame of a measured motion: the calibration (its clock offset, line delay
       and gyro bias), refined against the still placed by its capture time when there is one and the
       frame moves, and refused (applied = false) as fitAgainst decides. */
    MotionCorrection correctMeasured(const Mat& input, const Ptr<CameraMotion>& motion, const RollingShutter& shutter)
    {
        const char* fn = "DynamicDeblurrer::deblur";
        MotionCorrection correction = calibration_;
        correction.naturalFreqScale = correction.dampingScale = 1;  // no plant to scale
        const Still& still = stills_[0].present() ? stills_[0] : stills_[1];
        if (!still.present())
        {
            correction.reason = calibrated_ ? "a measured motion without a reference frame: the calibration's clock "
                                              "offset, line delay and gyro bias"
                                            : "a measured motion without a reference frame: restored as given";
            return correction;
        }
        checkStreamType(fn, input);
        if (std::isnan(still.time))
            CV_Error(Error::StsBadArg, format("%s: a measured motion's reference frame is placed by its capture "
                                              "time: set it with setReferenceFrame(still, stillShutter), not with "
                                              "an angle",
                                              fn));
        if (classifyExposure(motion, correction.correctShutter(shutter)) == EXPOSURE_IV)
        {
            correction.reason = "still frame: nothing to refine";
            return correction;
        }
        detail::FitSettings settings;
        settings.flags = refinement_ & (REFINE_TIME_OFFSET | REFINE_LINE_DELAY | REFINE_GYRO_BIAS);
        settings.maxTimeOffset = kMeasuredMaxTimeOffset;
        settings.scanStep = kMeasuredScanStep;
        settings.coarse = !(settings.flags == REFINE_TIME_OFFSET && calibrated_);
        settings.deviation = false;
        const double margin = settings.flags & REFINE_TIME_OFFSET ? settings.maxTimeOffset : 0.0;
        detail::checkMotionCoversSearch(motion, correction.correctShutter(shutter), margin, fn, "'frame'");
        const Vec2d span = motion->getTimeSpan();
        if (!(still.time + correction.timeOffset - margin >= span[0] &&
              still.time + correction.timeOffset + margin <= span[1]))
            CV_Error(Error::StsOutOfRange,
                     format("%s: the reference frame's capture time %.6f s (plus the clock offset %+.6f s, within "
                            "%.6f s of search) lies outside the time span of 'motion', [%.6f, %.6f] s",
                            fn, still.time, correction.timeOffset, margin, span[0], span[1]));
        detail::FitFrame fit;
        fit.reference = &still.pyramid;
        fit.frame = detail::buildPyramid(detail::linearLuminance(input), camera_, detail::kFitCoarseWidth, false);
        fit.shutter = shutter;
        fit.motion = motion;
        fit.referenceTime = still.time;
        return fitAgainst({fit}, "the reference frame", correction, settings);
    }

    /* The calibration refined against `frames` (each frame with its still) and the decision: refused
       (applied = false) when the fit stops at a search bound, or when even the best correction leaves
       the frame inconsistent with the still. */
    MotionCorrection fitAgainst(const std::vector<detail::FitFrame>& frames, const String& against,
                                MotionCorrection correction, const detail::FitSettings& settings) const
    {
        if (settings.flags != REFINE_NONE)
        {
            const detail::FitResult result = detail::fitMotionCorrection(plant_, frames, correction, settings);
            correction = result.correction;
            correction.held = result.held;
            correction.stillGain = result.gain;
            correction.reason = format("refined against %s (%d forward models; residual %.1f %% below the model as "
                                       "told)",
                                       against.c_str(), result.evaluations, 100 * result.improvement);
            if (result.unchanged)
                correction.reason += "; not significantly better than the model as told: kept";
            else if (result.unobserved)
                correction.reason += "; not determined by this frame, kept as told: " +
                                     detail::refinementFlagNames(result.unobserved) +
                                     " (the frame barely depends on it, or its moving rows see little the still "
                                     "saw)";
            if (!result.unchanged && result.ridge)
                correction.reason += "; " + detail::refinementFlagNames(result.ridge) +
                                     " trade against each other in this frame: kept as told along that ridge, only "
                                     "the combination the frame observes moved";
            if (result.pinned)
            {
                correction.applied = false;
                correction.reason = result.pinnedNote +
                                    ": no correction within the search explains the frame (a wrong schedule?); "
                                    "returned unchanged";
                return correction;
            }
        }
        else
        {
            correction.consistency = std::sqrt(
                detail::meanSquaredResiduals(plant_, frames, correction, {correction}, detail::kFitFineWidth)[0]);
            correction.reason = "checked against " + against;
        }
        const double limit = getConsistencyLimit();
        if (!(correction.consistency <= limit))
        {
            correction.applied = false;
            correction.reason =
                std::isnan(correction.consistency)
                    ? String("the frame and the reference frame observe no common pixel: returned unchanged")
                    : format("consistency %.2f exceeds the limit %.2f: no correction explains the frame (another "
                             "schedule, something moving, a bumped camera?); returned unchanged",
                             correction.consistency, limit);
        }
        return correction;
    }

    /* Without a reference frame: the time offset whose blur best predicts the differences between
       the frame's moving rows from the scene's statistics on its still rows (blind_fit.cpp), kept
       only when it explains them decisively better than the model as told. */
    MotionCorrection blindCorrection(const Mat& input, const SwitchSchedule& schedule, const RollingShutter& shutter,
                                     MotionCorrection correction) const
    {
        if (classifyExposure(correction.correctPlant(plant_), schedule, correction.correctShutter(shutter)) ==
            EXPOSURE_IV)
        {
            correction.reason = "blind: still frame, nothing to refine";
            return correction;
        }
        const detail::BlindResult result =
            detail::fitBlindTimeOffset(plant_, detail::prepareBlindFrame(input, camera_, detail::kFitFineWidth),
                                       schedule, shutter, correction, kBlindMaxTimeOffset, kBlindDecisive);
        correction = result.correction;
        correction.consistency = result.observed ? result.score : std::numeric_limits<double>::quiet_NaN();
        if (!result.observed)
            correction.reason = format("blind: fewer than %d rows stay still (a global shutter moving throughout the "
                                       "exposure, or window II), so nothing measures the scene's statistics: the "
                                       "model as told",
                                       detail::kBlindMinStillRows);
        else if (result.applied)
            correction.reason = format("blind: time offset %+.3f ms decided by the row variograms (criterion %.3f, "
                                       "%.0f %% better than the model as told; %d blur models)",
                                       (correction.timeOffset - calibration_.timeOffset) * 1e3, result.score,
                                       100 * result.decisiveness, result.candidates);
        else
            correction.reason = format("blind: the row variograms do not decide (criterion %.3f, the best offset only "
                                       "%.0f %% better, below the %.0f %% required): the model as told",
                                       result.score, 100 * result.decisiveness, 100 * kBlindDecisive);
        if (refinement_ & (REFINE_LINE_DELAY | REFINE_PLANT))
            correction.reason += "; line delay and plant are not observable blind: as told";
        if (result.observed && !(result.score <= blindLimit_))
        {
            correction.applied = false;
            correction.reason = format("blind: criterion %.3f exceeds the blind limit %.3f: no time offset explains "
                                       "the frame's rows (another schedule, something moving?); returned unchanged",
                                       result.score, blindLimit_);
        }
        return correction;
    }

    /* DEBLUR_COLOR_HALF_RESOLUTION: the color phase on the halved frame, with a half-size
       camera's kernels; the luminance with every iteration at full resolution; then one pass that
       upsamples the color, scales it to the luminance and writes it in `depth` (CV_8U: sRGB).
       `frame` is CV_32FC3 (linear) or CV_8UC3 (sRGB). */
    void restoreWithHalfColor(const Mat& frame, const detail::ViewMotion& view, const RollingShutter& shutter,
                              const _OutputArray& target, int depth)
    {
        const PsfBank halfBank =
            detail::generatePsfBank(*halfGenerator(), psfModel_, view, detail::halfResolutionShutter(shutter));
        // Both restorations run in place (restoreVariant writes its output after its last read of the frame).
        detail::halveAndAverageChannels(frame, halfColor_, luminance_);
        RLParams colorParams = frameParams_;
        colorParams.iterations = frameParams_.colorIterations;  // 0: the start, the frame moved back
        colorParams.colorIterations = -1;
        detail::restoreVariant(halfColor_, halfBank, colorParams, halfWorkspace_, halfColor_, noArray(), true);

        RLParams luminanceParams = frameParams_;
        luminanceParams.colorIterations = -1;
        detail::restoreVariant(luminance_, lastBank_, luminanceParams, workspace_, luminance_, mask_, true);
        // Written last: the frame may be the output (restoring in place). Below a millionth of
        // full well a pixel's color has no chromaticity to keep: the change is added.
        detail::combineLuminanceAndHalfColor(luminance_, halfColor_, 1e-6f, depth, target);
    }

    /* The generator of the half-size camera, with the settings of getPsfGenerator()'s,
       halved where they count pixels. A tile grid takes half lastBank_'s columns, the same node
       spacing in its own pixels, which is what the automatic rule gives at half the width below
       its cap of 16: neighbouring kernels then differ by as many (half-size) pixels as at full
       resolution. DeblurQuality measured 8 columns within 0.08 dB of 16 in window I, 4 columns 0.6 dB below. */
    const Ptr<PsfGenerator>& halfGenerator()
    {
        if (!halfCamera_)
        {
            halfCamera_ = detail::halfResolutionCamera(*camera_);
            halfGenerator_ = PsfGenerator::create(halfCamera_);
        }
        halfGenerator_->setMaxKernelSize(generator_->getMaxKernelSize());
        halfGenerator_->setAutoTolerance(0.5 * generator_->getAutoTolerance());
        const int bandRows = generator_->getBandRows(), gridRows = generator_->getTileGrid().height;
        halfGenerator_->setBandRows(bandRows > 0 ? std::max(1, bandRows / 2) : 0);
        halfGenerator_->setTileGrid(Size((int(lastBank_.nodeCols.size()) + 1) / 2,
                                         gridRows > 0 ? std::max(1, gridRows / 2) : 0));
        return halfGenerator_;
    }

    void checkFrame(const Mat& input, const RollingShutter& shutter) const
    {
        // Richardson–Lucy cannot take negative data, and a float frame scaled for another range
        // than [0, 1] would be restored wrongly: checkCameraFrame refuses both.
        detail::checkCameraFrame(input, *camera_, "DynamicDeblurrer::deblur", "frame");
        detail::checkShutter(shutter, "DynamicDeblurrer::deblur", "shutter.", input.rows);
    }

    Ptr<Plant> plant_;
    Ptr<CameraModel> camera_;
    Ptr<PsfGenerator> generator_;
    int psfModel_ = PSF_AUTO;  // tiles where the motion needs them; see the quality tests
    PsfPlan lastPlan_;
    int method_ = DEBLUR_RICHARDSON_LUCY;
    int colorResolution_ = DEBLUR_COLOR_FULL_RESOLUTION;
    int unobservedFill_ = UNOBSERVED_RECORDED;  // never streaks of the nearest pixel across a band
    Ptr<CameraModel> halfCamera_;  // created when first needed
    Ptr<PsfGenerator> halfGenerator_;
    /* Blind refinement scans the time offset this far around the model as told, seconds (the
       offsets RefinementBlind measures, ±2 ms, with margin) ... */
    static constexpr double kBlindMaxTimeOffset = 3e-3;
    /* ... and keeps the best offset when the model as told's criterion exceeds the best one by more
       than this fraction: told the truth, RefinementBlind measured at most 11 %; where the offset
       found restores worse than the model as told (a small offset, drifts of the plant) up to 62 %;
       where it restores better, from 91 % (most above 120 %). */
    static constexpr double kBlindDecisive = 0.8;
    /* A measured motion's frame is refined within this clock offset of its calibration, seconds: a
       gyro log's timestamps can be tens of milliseconds off the camera's (DeepGyro calibrated 22 ms),
       so a plant's ±3 ms will not do; a frame calibrated over its recording first needs less. */
    static constexpr double kMeasuredMaxTimeOffset = 0.015;
    // ... scanned in steps of this, seconds: a hand's shake changes the blur over milliseconds.
    static constexpr double kMeasuredScanStep = 0.001;
    int refinement_ = REFINE_ALL;
    bool blind_ = false;
    double blindLimit_ = std::numeric_limits<double>::infinity();
    /* The consistency limit in units of Immerkær's estimate on the still, which texture inflates: a
       right model measured 0.5 to 2.3 (RefinementQuality). */
    static constexpr double kEstimatedNoiseLimit = 3.0;
    /* ... and in units of the noise the noise frames measured: right models measured up to 6.3
       (building, window I, as rendered), wrong ones that restore worse from 8.8 (baboon, the other
       sign, after JPEG at quality 80; RefinementNoisePair, docs/refinement.md): their geometric middle. */
    static constexpr double kMeasuredNoiseLimit = 7.5;
    double consistencyLimit_ = kNaN;  // setConsistencyLimit's; NaN: by the noise's source, as above
    MotionCorrection calibration_, lastCorrection_;
    bool calibrated_ = false;  // setCalibration was called
    //! A still frame of the stream: its luminance, halved down to the fit's coarse width, and its angle.
    struct Still
    {
        detail::LuminancePyramid pyramid;
        double angle = kNaN;  // radians; NaN: the schedule's resting angle on its side of the move
        double time = kNaN;   // a measured motion's still: its capture time (mid-exposure), seconds; else NaN
        std::vector<double> estimatedNoise;  // Immerkær's estimate at each level
        bool present() const { return pyramid.levels() > 0; }
    };
    Still stills_[2];         // before the move, after it
    std::vector<double> noiseSigma_;  // setNoiseFrames: one frame's noise at each pyramid level; empty: Immerkær's
    int noiseType_ = -1;              // the noise frames' type
    int referenceType_ = -1;  // the stills' type
    bool single_ = false;     // setReferenceFrame: one still for every frame, whatever its window
    double wienerNoiseToSignal_ = 1e-2;
    RLParams params_;
    RLParams frameParams_;          // the last frame's: params_, or DEBLUR_PRESET_FRAME_RATE's by need
    bool iterationsByNeed_ = false;  // set by DEBLUR_PRESET_FRAME_RATE, cleared by setRLParams
    // Kept between frames, so a stream of frames faults in no fresh memory.
    detail::RLWorkspace workspace_, halfWorkspace_;
    Mat linear_, latent_, mask_;
    Mat halfColor_, luminance_;  // DEBLUR_COLOR_HALF_RESOLUTION's planes
    int lastWindow_ = 0;
    PsfBank lastBank_;
};

Ptr<DynamicDeblurrer> DynamicDeblurrer::create(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera)
{
    CV_Assert(!plant.empty() && "DynamicDeblurrer::create: 'plant' is null");
    CV_Assert(!camera.empty() && "DynamicDeblurrer::create: 'camera' is null");
    return makePtr<DynamicDeblurrerImpl>(plant, camera);
}

Ptr<DynamicDeblurrer> DynamicDeblurrer::create(const Ptr<CameraModel>& camera)
{
    CV_Assert(!camera.empty() && "DynamicDeblurrer::create: 'camera' is null");
    return makePtr<DynamicDeblurrerImpl>(Ptr<Plant>(), camera);
}

}  // namespace dynblur
}  // namespace cv
