// SPDX-License-Identifier: Apache-2.0
// DynamicDeblurrer: its settings, and deblur() as the pipeline's stages, one call each: correct the
// predicted motion (frame_correction), the views it gives, their PSF bank, restore and encode
// (frame_restoration).
#include "precomp.hpp"

#include "imaging/camera_frame.hpp"
#include "imaging/psf_generator.hpp"
#include "motion/axis_chain_motion.hpp"
#include "motion/camera_motion.hpp"
#include "motion/corrected_motion.hpp"
#include "motion/shutter_check.hpp"
#include "pipeline/frame_correction.hpp"
#include "pipeline/frame_rate_preset.hpp"
#include "pipeline/frame_restoration.hpp"
#include "pipeline/frame_sharpness.hpp"
#include "refine/fit_parameters.hpp"
#include "restore/arguments.hpp"

namespace cv {
namespace dynblur {

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const char* const kDeblur = "DynamicDeblurrer::deblur";
/* A sharp frame displaced from the reference view by less than this (pixels) is returned as it
   came: moving it back would gain some hundredths of a dB (+0.02 to +0.16 dB at 0.06 px, less as the
   square of the shift below; docs/quality.md, "Nearly sharp frames") for the resampling's time. */
const double kNegligibleShiftPx = 0.05;
}

class DynamicDeblurrerImpl CV_FINAL : public DynamicDeblurrer
{
public:
    DynamicDeblurrerImpl(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera)
        : plant_(plant), camera_(camera),
          generator_(plant ? PsfGenerator::create(plant, camera) : PsfGenerator::create(camera)),
          corrector_(plant, camera), restorer_(camera)
    {
        // Webcam frames carry shot and read noise: damp at the frame's own noise level.
        restoration_.params.damping = kNaN;
    }

    void deblur(InputArray frame, const SwitchSchedule& schedule, const RollingShutter& shutter, OutputArray restored,
                double thetaRef, OutputArray validMask) CV_OVERRIDE
    {
        deblurPlantFrame(frame, schedule, shutter, restored, thetaRef, kNaN, validMask);
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
            return deblurPlantFrame(frame, plantMotion->schedule(), shutter, restored, kNaN, tRef, validMask);
        }
        const detail::FrameCorrection corrected = corrector_.correct(input, motion, shutter);
        const MotionCorrection& c = corrected.correction;
        const RollingShutter correctedShutter = c.correctShutter(shutter);
        // A mount's view is its corrected chain's, at its final rest for a NaN tRef, as a plant's.
        const detail::ViewMotion view =
            detail::asAxisChainMotion(*motion)
                ? detail::ViewMotion::of(c.correctMotion(motion), tRef + c.timeOffset, correctedShutter)
                : detail::correctedView(motion, c, tRef, correctedShutter);
        restoreFrame(input, corrected, view, correctedShutter, restored, validMask);
    }

    int getRefinement() const CV_OVERRIDE { return corrector_.settings.refinement; }
    void setRefinement(int flags) CV_OVERRIDE
    {
        const int all = detail::allRefinementFlags();
        if (flags < REFINE_NONE || (flags & ~all) != 0)
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setRefinement: flags = %d must combine %s: a value in [0, %d]", flags,
                            detail::refinementFlagList(all).c_str(), all));
        corrector_.settings.refinement = flags;
    }
    void setReferenceFrame(InputArray still, double angle) CV_OVERRIDE
    {
        corrector_.setStills("DynamicDeblurrer::setReferenceFrame", still.getMat(), "still", angle, "angle", Mat(), "",
                             kNaN, "", true);
    }
    void setReferenceFrame(InputArray still, const RollingShutter& stillShutter) CV_OVERRIDE
    {
        corrector_.setTimedStill("DynamicDeblurrer::setReferenceFrame", still.getMat(), stillShutter);
    }
    void setReferenceFrames(InputArray before, InputArray after, double angleBefore, double angleAfter) CV_OVERRIDE
    {
        const char* fn = "DynamicDeblurrer::setReferenceFrames";
        const Mat first = before.getMat(), second = after.getMat();
        if (first.empty() && second.empty())
            CV_Error(Error::StsBadArg, format("%s: both 'before' and 'after' are empty; give at least one still "
                                              "frame (or call clearReferenceFrame)",
                                              fn));
        corrector_.setStills(fn, first, "before", angleBefore, "angleBefore", second, "after", angleAfter,
                             "angleAfter", false);
    }
    void setNoiseFrames(InputArray stillA, InputArray stillB) CV_OVERRIDE
    {
        corrector_.setNoiseFrames(stillA.getMat(), stillB.getMat());
    }
    void setNeighbourFrame(InputArray frame, const RollingShutter& shutter) CV_OVERRIDE
    {
        const char* fn = "DynamicDeblurrer::setNeighbourFrame";
        const Mat image = frame.getMat();
        if (!image.empty())
        {
            detail::checkCameraFrame(image, *camera_, fn, "frame");
            detail::checkShutter(shutter, fn, "shutter.", image.rows);
        }
        corrector_.setNeighbour(image, shutter);
    }
    double getNeighbourLimit() const CV_OVERRIDE { return corrector_.settings.neighbourLimitPx; }
    void setNeighbourLimit(double limitPx) CV_OVERRIDE
    {
        if (!(limitPx > 0))
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setNeighbourLimit: limitPx = %g must be > 0 pixels (or +inf: no check)",
                            limitPx));
        corrector_.settings.neighbourLimitPx = limitPx;
    }
    void clearReferenceFrame() CV_OVERRIDE { corrector_.clearStills(); }
    MotionCorrection getLastCorrection() const CV_OVERRIDE { return lastCorrection_; }
    bool getBlindRefinement() const CV_OVERRIDE { return corrector_.settings.blind; }
    void setBlindRefinement(bool enabled) CV_OVERRIDE { corrector_.settings.blind = enabled; }
    double getBlindConsistencyLimit() const CV_OVERRIDE { return corrector_.settings.blindLimit; }
    void setBlindConsistencyLimit(double limit) CV_OVERRIDE
    {
        if (!(limit > 0))
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setBlindConsistencyLimit: limit = %g must be > 0 (or +inf: no check)",
                            limit));
        corrector_.settings.blindLimit = limit;
    }
    MotionCorrection getCalibration() const CV_OVERRIDE { return corrector_.settings.calibration; }
    void setCalibration(const MotionCorrection& correction) CV_OVERRIDE
    {
        correction.validate();
        MotionCorrection& calibration = corrector_.settings.calibration;
        calibration = MotionCorrection();
        calibration.timeOffset = correction.timeOffset;
        calibration.lineDelayScale = correction.lineDelayScale;
        calibration.naturalFreqScale = correction.naturalFreqScale;
        calibration.dampingScale = correction.dampingScale;
        calibration.gyroBias = correction.gyroBias;
        calibration.rateScale = correction.rateScale;
        corrector_.settings.calibrated = true;
    }
    double getConsistencyLimit() const CV_OVERRIDE { return corrector_.effectiveConsistencyLimit(); }
    void setConsistencyLimit(double limit) CV_OVERRIDE
    {
        if (!(limit > 1))
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setConsistencyLimit: limit = %g must be > 1 (or +inf: no check)", limit));
        corrector_.settings.consistencyLimit = limit;
    }

    double getSharpThreshold() const CV_OVERRIDE { return sharpThreshold_; }
    void setSharpThreshold(double px) CV_OVERRIDE
    {
        if (!(px >= 0) || std::isinf(px))
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setSharpThreshold: px = %g must be finite and >= 0 (pixels; 0: deconvolve "
                            "every moving frame)",
                            px));
        sharpThreshold_ = px;
    }

    int getPsfModel() const CV_OVERRIDE { return restoration_.psfModel; }
    void setPsfModel(int model) CV_OVERRIDE
    {
        if (model != PSF_UNIFORM && model != PSF_ROWS && model != PSF_TILES && model != PSF_AUTO)
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setPsfModel: model = %d must be PSF_UNIFORM (0), PSF_ROWS (1), "
                            "PSF_TILES (2) or PSF_AUTO (3)", model));
        restoration_.psfModel = model;
    }
    void setPreset(int preset) CV_OVERRIDE
    {
        if (preset != DEBLUR_PRESET_DEFAULT && preset != DEBLUR_PRESET_FRAME_RATE)
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setPreset: preset = %d must be DEBLUR_PRESET_DEFAULT (0) or "
                            "DEBLUR_PRESET_FRAME_RATE (1)", preset));
        RLParams params = preset == DEBLUR_PRESET_FRAME_RATE ? detail::frameRatePresetParams() : RLParams();
        params.damping = kNaN;
        restoration_.psfModel = PSF_AUTO;
        restoration_.method = DEBLUR_RICHARDSON_LUCY;
        restoration_.colorResolution = DEBLUR_COLOR_FULL_RESOLUTION;
        restoration_.iterationsByNeed = preset == DEBLUR_PRESET_FRAME_RATE;
        if (preset == DEBLUR_PRESET_FRAME_RATE)
        {
            const Size size = camera_->getImageSize();
            if (size.width % 2 == 0 && size.height % 2 == 0)
                restoration_.colorResolution = DEBLUR_COLOR_HALF_RESOLUTION;
        }
        restoration_.params = params;
    }
    PsfPlan getLastPlan() const CV_OVERRIDE { return lastPlan_; }
    int getMethod() const CV_OVERRIDE { return restoration_.method; }
    void setMethod(int method) CV_OVERRIDE
    {
        if (method != DEBLUR_RICHARDSON_LUCY && method != DEBLUR_WIENER)
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setMethod: method = %d must be DEBLUR_RICHARDSON_LUCY (0) or "
                            "DEBLUR_WIENER (1)", method));
        restoration_.method = method;
    }
    int getColorResolution() const CV_OVERRIDE { return restoration_.colorResolution; }
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
        restoration_.colorResolution = resolution;
    }
    int getUnobservedFill() const CV_OVERRIDE { return restoration_.unobservedFill; }
    void setUnobservedFill(int fill) CV_OVERRIDE
    {
        if (fill != UNOBSERVED_RECORDED && fill != UNOBSERVED_MARKED && fill != UNOBSERVED_NEAREST)
            CV_Error(Error::StsOutOfRange,
                     format("DynamicDeblurrer::setUnobservedFill: fill = %d must be UNOBSERVED_RECORDED (0), "
                            "UNOBSERVED_MARKED (1) or UNOBSERVED_NEAREST (2)", fill));
        restoration_.unobservedFill = fill;
    }
    RLParams getRLParams() const CV_OVERRIDE { return restoration_.params; }
    void setRLParams(const RLParams& params) CV_OVERRIDE
    {
        checkRLParams(params, "DynamicDeblurrer::setRLParams");
        restoration_.params = params;
        restoration_.iterationsByNeed = false;  // the caller's iterations hold
    }
    int getLastExposureWindow() const CV_OVERRIDE { return lastWindow_; }
    PsfBank getLastPsfBank() const CV_OVERRIDE { return lastBank_; }
    Ptr<PsfGenerator> getPsfGenerator() const CV_OVERRIDE { return generator_; }
    String getDefaultName() const CV_OVERRIDE { return "dynblur.DynamicDeblurrer"; }

private:
    /* A plant's frame, stage by stage: the motion that happened (the correction), the views it gives,
       their blur (the PSF bank), the restoration in the frame's own encoding. The view restored is at
       thetaRef, or, for a finite tRef (a camera time, which the correction's clock offset moves as it
       moves the frame), at the corrected plant's angle then. */
    void deblurPlantFrame(InputArray frame, const SwitchSchedule& schedule, const RollingShutter& shutter,
                          OutputArray restored, double thetaRef, double tRef, OutputArray validMask)
    {
        if (plant_.empty())
            CV_Error(Error::StsBadArg, "DynamicDeblurrer::deblur: this deblurrer was created without a plant "
                                       "(DynamicDeblurrer::create(camera)); give it the frame's motion: "
                                       "deblur(frame, motion, shutter, restored, tRef)");
        const Mat input = frame.getMat();
        checkFrame(input, shutter);
        const Vec3d axis = camera_->getMountAxis();
        // thetaRef is checked before the correction's work, and again on the corrected plant below.
        detail::ViewMotion::ofPlant(kDeblur, plant_, schedule, axis, std::isnan(tRef) ? thetaRef : angleAt(plant_, schedule, tRef));

        const detail::FrameCorrection corrected = corrector_.correct(input, schedule, shutter);
        const Ptr<Plant> plant = corrected.correction.correctPlant(plant_);
        if (!std::isnan(tRef))
            thetaRef = angleAt(plant, schedule, tRef + corrected.correction.timeOffset);
        const detail::ViewMotion view = detail::ViewMotion::ofPlant(kDeblur, plant, schedule, axis, thetaRef);
        restoreFrame(input, corrected, view, corrected.correction.correctShutter(shutter), restored, validMask);
    }

    //! The angle of `plant` under `schedule` at time t on the schedule's clock, radians.
    static double angleAt(const Ptr<Plant>& plant, const SwitchSchedule& schedule, double t)
    {
        return detail::asPlantMotion(*CameraMotion::fromPlant(plant, schedule))->referenceAngle(t);
    }

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

    /* The last stages for a corrected frame: its PSF bank for `view` read by `shutter` (corrected),
       then the restoration in the frame's encoding. A frame still throughout, or one no correction
       explains, is returned as it came; one whose motion keeps it sharp is not deconvolved (returned
       as it came, or its rows moved back). The getters' report of the frame is written here. */
    void restoreFrame(const Mat& input, const detail::FrameCorrection& corrected, const detail::ViewMotion& view,
                      const RollingShutter& shutter, OutputArray restored, OutputArray validMask)
    {
        lastCorrection_ = corrected.correction;
        lastWindow_ = corrected.window;
        lastBank_ = PsfBank();
        lastPlan_ = PsfPlan();
        if (corrected.window == EXPOSURE_IV || !corrected.correction.applied)
            return detail::passThrough(input, restored, validMask);
        /* Deconvolving a nearly sharp frame gains little, and on fine texture ends below the frame
           (docs/quality.md, "Nearly sharp frames"); a blur longer than the kernels reach (a log in the
           wrong units) has no restoration: both decided from the motion, before any kernel is made. */
        const detail::FrameSharpness sharpness = detail::measureSharpness(view, shutter, *camera_);
        if (!(sharpness.blurPx < generator_->getMaxKernelSize()))
        {
            lastCorrection_.applied = false;
            lastCorrection_.reason =
                format("the motion predicts %.0f px of blur at (%.0f, %.0f), more than the kernels reach (%d px, "
                       "PsfGenerator::setMaxKernelSize): is the motion right (its units?); returned unchanged",
                       sharpness.blurPx, sharpness.blurAt.x, sharpness.blurAt.y, generator_->getMaxKernelSize());
            return detail::passThrough(input, restored, validMask);
        }
        if (sharpThreshold_ > 0)
        {
            if (sharpness.within(sharpThreshold_))
            {
                const auto report = [&](const char* what) {
                    lastCorrection_.reason =
                        format("sharp: blur %.2f px at (%.0f, %.0f), shift %.2f px at (%.0f, %.0f), both below %g px: %s",
                               sharpness.blurPx, sharpness.blurAt.x, sharpness.blurAt.y, sharpness.shiftPx,
                               sharpness.shiftAt.x, sharpness.shiftAt.y, sharpThreshold_, what) +
                        (corrected.correction.reason.empty() ? String() : "; " + corrected.correction.reason);
                };
                if (sharpness.shiftPx < kNegligibleShiftPx)
                {
                    report("returned as it came");
                    return detail::passThrough(input, restored, validMask);
                }
                if (restorer_.moveBack(input, sharpness, restoration_.unobservedFill, restored, validMask))
                    return report("rows moved back to the reference view without deconvolution");
                // Rows folded over one another (a vibration faster than the readout): deconvolved as any frame.
            }
        }

        PsfPlan plan;
        const PsfBank bank = detail::generatePsfBank(*generator_, restoration_.psfModel, view, shutter, &plan);
        if (restoration_.psfModel != PSF_AUTO)
            plan.model = bank.model;
        restorer_.restore(input, bank, view, shutter, *generator_, restoration_, restored, validMask);
        lastBank_ = bank;
        lastPlan_ = plan;
    }

    void checkFrame(const Mat& input, const RollingShutter& shutter) const
    {
        // Richardson–Lucy cannot take negative data, and a float frame scaled for another range
        // than [0, 1] would be restored wrongly: checkCameraFrame refuses both.
        detail::checkCameraFrame(input, *camera_, kDeblur, "frame");
        detail::checkShutter(shutter, kDeblur, "shutter.", input.rows);
    }

    Ptr<Plant> plant_;
    Ptr<CameraModel> camera_;
    Ptr<PsfGenerator> generator_;
    detail::FrameCorrector corrector_;        // the stills, the noise and the refinement's settings
    detail::RestorationSettings restoration_;  // PSF_AUTO: tiles where the motion needs them; see the quality tests
    detail::FrameRestorer restorer_;          // its workspaces, kept between frames
    double sharpThreshold_ = 1.0;             // pixels; frames sharper than this are not deconvolved (0: none)
    // What the last frame's stages found (the getters' report).
    MotionCorrection lastCorrection_;
    int lastWindow_ = 0;
    PsfBank lastBank_;
    PsfPlan lastPlan_;
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
