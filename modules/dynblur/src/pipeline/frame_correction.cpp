// SPDX-License-Identifier: Apache-2.0
// DynamicDeblurrer's correction stage: each frame's correction of the predicted motion, fitted against
// the still that observed its moving rows (or blind), and the decision to refuse it.
#include "precomp.hpp"

#include "imaging/camera_frame.hpp"
#include "motion/axis_chain_motion.hpp"
#include "motion/camera_motion.hpp"
#include "motion/corrected_motion.hpp"
#include "motion/shutter_check.hpp"
#include "pipeline/frame_correction.hpp"
#include "refine/blind_fit.hpp"
#include "refine/motion_fit.hpp"

namespace cv {
namespace dynblur {
namespace detail {

namespace {

/* Blind refinement scans the time offset this far around the model as told, seconds (the
   offsets RefinementBlind measures, ±2 ms, with margin) ... */
const double kBlindMaxTimeOffset = 3e-3;
/* ... and keeps the best offset when the model as told's criterion exceeds the best one by more
   than this fraction: told the truth, RefinementBlind measured at most 11 %; where the offset
   found restores worse than the model as told (a small offset, drifts of the plant) up to 62 %;
   where it restores better, from 91 % (most above 120 %). */
const double kBlindDecisive = 0.8;
/* A measured motion's frame is refined within this clock offset of its calibration, seconds: a
   gyro log's timestamps can be tens of milliseconds off the camera's (DeepGyro calibrated 22 ms),
   so a plant's ±3 ms will not do; a frame calibrated over its recording first needs less. */
const double kMeasuredMaxTimeOffset = 0.015;
// ... scanned in steps of this, seconds: a hand's shake changes the blur over milliseconds.
const double kMeasuredScanStep = 0.001;
/* The consistency limit in units of Immerkær's estimate on the still, which texture inflates: a
   right model measured 0.5 to 2.3 (RefinementQuality). */
const double kEstimatedNoiseLimit = 3.0;
/* ... and in units of the noise the noise frames measured: right models measured up to 6.3
   (building, window I, as rendered), wrong ones that restore worse from 8.8 (baboon, the other
   sign, after JPEG at quality 80; RefinementNoisePair, docs/refinement.md): their geometric middle. */
const double kMeasuredNoiseLimit = 7.5;
/* A frame checked against its neighbour may carry a blur error up to this share of its blur beyond the
   limit (medians over its patches, the blur as the images show it): shifts between heavily blurred
   frames err in proportion to their blur. On rendered hand-held clips (blur up to 40 px) a right log
   lost 2 of 90 frames at 0.6 (4 to 9 at 0.4, with 8 % of the clips' gain), while logs in the wrong
   units or of another clip lost every frame. A log whose axes are wrong but nearly agree with the
   images over a frame can pass it; the clip's calibration (ClipTimingCalibrator) does not let it. */
const double kNeighbourShare = 0.6;
// Fewer textured patches than this decide nothing.
const int kNeighbourMinPatches = 6;

}  // namespace

FrameCorrector::FrameCorrector(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera)
    : plant_(plant), camera_(camera), neighbour_(camera)
{
}

FrameCorrection FrameCorrector::correct(const Mat& frame, const SwitchSchedule& schedule,
                                        const RollingShutter& shutter) const
{
    FrameCorrection result;
    result.correction = correctPlantFrame(frame, schedule, shutter);
    result.window = classifyExposure(result.correction.correctPlant(plant_), schedule,
                                     result.correction.correctShutter(shutter));
    return result;
}

FrameCorrection FrameCorrector::correct(const Mat& frame, const Ptr<CameraMotion>& motion,
                                        const RollingShutter& shutter) const
{
    FrameCorrection result;
    if (asAxisChainMotion(*motion))
    {
        result.correction = correctMountFrame(frame, motion, shutter);
        result.window = classifyExposure(result.correction.correctMotion(motion),
                                         result.correction.correctShutter(shutter));
        return result;
    }
    result.correction = correctMeasuredFrame(frame, motion, shutter);
    const RollingShutter corrected = result.correction.correctShutter(shutter);
    checkMotionCovers(motion, corrected.readoutInterval(), "DynamicDeblurrer::deblur", "motion");
    result.window = classifyExposure(motion, corrected);
    return result;
}

double FrameCorrector::effectiveConsistencyLimit() const
{
    if (!std::isnan(settings.consistencyLimit))
        return settings.consistencyLimit;
    return noiseSigma_.empty() ? kEstimatedNoiseLimit : kMeasuredNoiseLimit;
}

void FrameCorrector::setStills(const char* fn, const Mat& before, const char* beforeName, double angleBefore,
                               const char* angleBeforeName, const Mat& after, const char* afterName,
                               double angleAfter, const char* angleAfterName, bool single)
{
    const Mat images[2] = {before, after};
    const char* names[2] = {beforeName, afterName};
    const double angles[2] = {angleBefore, angleAfter};
    const char* angleNames[2] = {angleBeforeName, angleAfterName};
    for (int k = 0; k < 2; k++)
    {
        if (!images[k].empty())
            checkCameraFrame(images[k], *camera_, fn, names[k]);
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
        Mat luminance = linearLuminance(images[k]);
        if (luminance.data == images[k].data)
            luminance = luminance.clone();
        stills_[k].pyramid = buildPyramid(luminance, camera_, kFitCoarseWidth, true);
        stills_[k].estimatedNoise = stills_[k].pyramid.noiseSigma;
        stills_[k].angle = angles[k];
        referenceType_ = images[k].type();
    }
    single_ = single;
    weighStills();
}

void FrameCorrector::setTimedStill(const char* fn, const Mat& still, const RollingShutter& stillShutter)
{
    checkShutter(stillShutter, fn, "stillShutter.", still.empty() ? 0 : still.rows);
    setStills(fn, still, "still", std::numeric_limits<double>::quiet_NaN(), "angle", Mat(), "",
              std::numeric_limits<double>::quiet_NaN(), "", true);
    stills_[0].time = midExposure(stillShutter);
}

void FrameCorrector::setNoiseFrames(const Mat& stillA, const Mat& stillB)
{
    const bool forget = stillA.empty() && stillB.empty();
    noiseSigma_ = forget ? std::vector<double>() : measureNoise(stillA, stillB, camera_, "DynamicDeblurrer::setNoiseFrames");
    noiseType_ = forget ? -1 : stillA.type();
    weighStills();
}

void FrameCorrector::weighStills()
{
    for (Still& still : stills_)
        still.pyramid.noiseSigma = noiseSigma_.empty() ? still.estimatedNoise : noiseSigma_;
}

void FrameCorrector::clearStills()
{
    stills_[0] = stills_[1] = Still();
    referenceType_ = -1;
}

/* Without a still, a neighbouring frame serves: the motion must carry its content onto this frame. The
   patches' errors, over the interval between the two frames' exposures, are scaled to the error they
   imply in this frame's blur (× exposure / interval, the share of that interval the blur spans); a
   frame whose median exceeds both the limit and kNeighbourShare of its median blur (measurement
   under heavy blur errs in proportion to it) comes back as it was: a wrong log, axes or clock, or
   something moving across most of the view. Too few textured patches decide nothing. */
void FrameCorrector::checkAgainstNeighbour(const Mat& frame, const Ptr<CameraMotion>& motion,
                                           const RollingShutter& shutter, MotionCorrection& correction) const
{
    if (!(std::abs(neighbour_.interval(shutter)) > 0))
        CV_Error(Error::StsBadArg, "DynamicDeblurrer::deblur: the neighbour frame (setNeighbourFrame) starts when "
                                   "this frame does; it must be the frame before or after it");
    const NeighbourAgreement agreement = neighbour_.measure(frame, shutter, motion, correction);
    const double scale = shutter.exposure / std::abs(neighbour_.interval(shutter));
    const size_t patches = agreement.errorPx.size();
    if (patches < size_t(kNeighbourMinPatches))
    {
        correction.reason += format("; too few textured patches (%zu) to check against the neighbouring frame",
                                    patches);
        return;
    }
    std::vector<double> blurErrors, blurs;
    for (size_t k = 0; k < patches; k++)
        blurErrors.push_back(agreement.errorPx[k] * scale), blurs.push_back(agreement.shiftPx[k] * scale);
    std::nth_element(blurErrors.begin(), blurErrors.begin() + long(patches / 2), blurErrors.end());
    std::nth_element(blurs.begin(), blurs.begin() + long(patches / 2), blurs.end());
    correction.consistency = blurErrors[patches / 2];
    const double blur = blurs[patches / 2], limit = std::max(settings.neighbourLimitPx, kNeighbourShare * blur);
    if (correction.consistency <= limit)
        correction.reason += format("; carried from the neighbouring frame within %.2f px of blur (median of %zu "
                                    "patches)",
                                    correction.consistency, patches);
    else
    {
        correction.applied = false;
        correction.reason = format("carried from the neighbouring frame, the motion misses this frame's content by "
                                   "%.1f px of its %.1f px of blur (medians of %zu patches; limit %.1f px): the log "
                                   "does not explain the frame (its units, axes or clock, or something moving "
                                   "across the view?); returned unchanged",
                                   correction.consistency, blur, patches, limit);
    }
}

/* A frame refined against the stills comes from their stream: the reference frames' type, and the
   noise frames' (setNoiseFrames measured the noise of frames of their own type only). */
void FrameCorrector::checkStreamType(const char* fn, const Mat& input) const
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
MotionCorrection FrameCorrector::correctPlantFrame(const Mat& input, const SwitchSchedule& schedule,
                                                   const RollingShutter& shutter) const
{
    MotionCorrection correction = settings.calibration;
    if (!stills_[0].present() && !stills_[1].present())
    {
        if (settings.blind && (settings.refinement & REFINE_TIME_OFFSET))
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
    String against;
    const std::vector<int> chosen = stillsFor(window, against);
    std::vector<FitFrame> frames = pairWithStills(input, chosen, shutter);
    for (size_t i = 0; i < chosen.size(); i++)
    {
        const int k = chosen[i];
        frames[i].schedule = schedule;
        const double told = plant_->restingAngle(k == 0 ? schedule.initialLevel : schedule.finalLevel());
        frames[i].referenceAngle = std::isnan(stills_[k].angle) ? told : stills_[k].angle;
    }
    FitSettings fit;
    fit.flags = settings.refinement & REFINE_ALL;
    // From a recording's calibration only the frame's jitter is left to find: the fine level's fit alone.
    fit.coarse = !(fit.flags == REFINE_TIME_OFFSET && settings.calibrated);
    fit.deviation = false;
    return fitAgainst(frames, against, correction, fit);
}

/* The still that observed the frame's moving rows: before the move for a frame that starts at rest,
   after it for one that ends at rest, both for one moving throughout. */
std::vector<int> FrameCorrector::stillsFor(int window, String& against) const
{
    std::vector<int> chosen;
    if (window == EXPOSURE_II && stills_[0].present() && stills_[1].present())
        chosen = {0, 1};
    else
    {
        const int preferred = window == EXPOSURE_I ? 0 : 1;
        chosen.push_back(stills_[preferred].present() ? preferred : 1 - preferred);
    }
    against = single_               ? "the reference frame"
              : chosen.size() == 2 ? "the stills before and after the move"
              : chosen[0] == 0     ? "the still before the move"
                                   : "the still after the move";
    return chosen;
}

std::vector<FitFrame> FrameCorrector::pairWithStills(const Mat& input, const std::vector<int>& chosen,
                                                     const RollingShutter& shutter) const
{
    const LuminancePyramid framePyramid = buildPyramid(linearLuminance(input), camera_, kFitCoarseWidth, false);
    std::vector<FitFrame> frames;
    for (int k : chosen)
    {
        FitFrame pair;
        pair.reference = &stills_[k].pyramid;
        pair.frame = framePyramid;
        pair.shutter = shutter;
        frames.push_back(pair);
    }
    return frames;
}

/* A mount's frame as a plant's: the calibration, refined (clock, line delay, each axis's plant) against
   the still at rest that observed its moving rows, and refused as fitAgainst decides. Its stills are
   the chain at rest, every axis at its initial (before the move) or final (after) resting angle. */
MotionCorrection FrameCorrector::correctMountFrame(const Mat& input, const Ptr<CameraMotion>& motion,
                                                   const RollingShutter& shutter) const
{
    const char* fn = "DynamicDeblurrer::deblur";
    MotionCorrection correction = settings.calibration;
    correction.gyroBias = Vec3d();  // no gyro: the mount's plants make the motion
    correction.rateScale = 1;
    if (!stills_[0].present() && !stills_[1].present())
    {
        correction.reason = "a mount's motion without a reference frame: the model as told (with the calibration)";
        return correction;
    }
    checkStreamType(fn, input);
    for (const Still& still : stills_)
        if (still.present() && !(std::isnan(still.time) && std::isnan(still.angle)))
            CV_Error(Error::StsBadArg,
                     format("%s: a mount's frame (Mount::motion) is compared with stills taken at rest, every axis at "
                            "its resting angle before or after the move: set them with setReferenceFrames(before, "
                            "after) or setReferenceFrame(still), without an angle or a capture time",
                            fn));
    const int window = classifyExposure(correction.correctMotion(motion), correction.correctShutter(shutter));
    if (window == EXPOSURE_IV)
    {
        correction.reason = "still frame: nothing to refine";
        return correction;
    }
    String against;
    const std::vector<int> chosen = stillsFor(window, against);
    std::vector<FitFrame> frames = pairWithStills(input, chosen, shutter);
    for (size_t i = 0; i < chosen.size(); i++)
    {
        frames[i].motion = motion;
        frames[i].referenceOrientation = asAxisChainMotion(*motion)->restOrientation(chosen[i] == 1);
    }
    FitSettings fit;
    fit.flags = settings.refinement & refinementFlagsFor(FIT_MOUNT_MOTION);
    fit.coarse = !(fit.flags == REFINE_TIME_OFFSET && settings.calibrated);
    fit.deviation = false;
    return fitAgainst(frames, against, correction, fit);
}

/* The correction for a frame of a measured motion: the calibration (its clock offset, line delay
   and gyro bias), refined against the still placed by its capture time when there is one and the
   frame moves, and refused (applied = false) as fitAgainst decides. */
MotionCorrection FrameCorrector::correctMeasuredFrame(const Mat& input, const Ptr<CameraMotion>& motion,
                                                      const RollingShutter& shutter) const
{
    const char* fn = "DynamicDeblurrer::deblur";
    MotionCorrection correction = settings.calibration;
    correction.naturalFreqScale = correction.dampingScale = 1;  // no plant to scale
    const Still& still = stills_[0].present() ? stills_[0] : stills_[1];
    if (!still.present())
    {
        correction.reason = settings.calibrated ? "a measured motion without a reference frame: the calibration's clock "
                                          "offset, line delay and gyro bias"
                                        : "a measured motion without a reference frame: restored as given";
        if (neighbour_.present())
            checkAgainstNeighbour(input, motion, shutter, correction);
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
    FitSettings fit;
    fit.flags = settings.refinement & refinementFlagsFor(FIT_MEASURED_MOTION);
    fit.maxTimeOffset = kMeasuredMaxTimeOffset;
    fit.scanStep = kMeasuredScanStep;
    fit.coarse = !(fit.flags == REFINE_TIME_OFFSET && settings.calibrated);
    fit.deviation = false;
    const double margin = fit.flags & REFINE_TIME_OFFSET ? fit.maxTimeOffset : 0.0;
    checkMotionCoversSearch(motion, correction.correctShutter(shutter), margin, fn, "'frame'");
    const Vec2d span = motion->getTimeSpan();
    if (!(still.time + correction.timeOffset - margin >= span[0] &&
          still.time + correction.timeOffset + margin <= span[1]))
        CV_Error(Error::StsOutOfRange,
                 format("%s: the reference frame's capture time %.6f s (plus the clock offset %+.6f s, within "
                        "%.6f s of search) lies outside the time span of 'motion', [%.6f, %.6f] s",
                        fn, still.time, correction.timeOffset, margin, span[0], span[1]));
    FitFrame pair;
    pair.reference = &still.pyramid;
    pair.frame = buildPyramid(linearLuminance(input), camera_, kFitCoarseWidth, false);
    pair.shutter = shutter;
    pair.motion = motion;
    pair.referenceTime = still.time;
    return fitAgainst({pair}, "the reference frame", correction, fit);
}

/* The calibration refined against `frames` (each frame with its still) and the decision: refused
   (applied = false) when the fit stops at a search bound, or when even the best correction leaves
   the frame inconsistent with the still. */
MotionCorrection FrameCorrector::fitAgainst(const std::vector<FitFrame>& frames, const String& against,
                                            MotionCorrection correction, const FitSettings& settings) const
{
    if (settings.flags != REFINE_NONE)
    {
        const FitResult result = fitMotionCorrection(plant_, frames, correction, settings);
        correction = result.correction;
        correction.held = result.held;
        correction.heldParameters = result.heldParameters;
        correction.stillGain = result.gain;
        correction.reason = format("refined against %s (%d forward models; residual %.1f %% below the model as "
                                   "told)",
                                   against.c_str(), result.evaluations, 100 * result.improvement);
        if (result.unchanged)
            correction.reason += "; not significantly better than the model as told: kept";
        else if (result.unobserved)
            correction.reason += "; not determined by this frame, kept as told: " +
                                 parameterNames(result.unobservedParameters) +
                                 " (the frame barely depends on it, or its moving rows see little the still "
                                 "saw)";
        if (!result.unchanged && result.ridge)
            correction.reason += "; " + parameterNames(result.ridgeParameters) +
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
            meanSquaredResiduals(plant_, frames, correction, {correction}, kFitFineWidth)[0]);
        correction.reason = "checked against " + against;
    }
    const double limit = effectiveConsistencyLimit();
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
MotionCorrection FrameCorrector::blindCorrection(const Mat& input, const SwitchSchedule& schedule,
                                                 const RollingShutter& shutter, MotionCorrection correction) const
{
    if (classifyExposure(correction.correctPlant(plant_), schedule, correction.correctShutter(shutter)) ==
        EXPOSURE_IV)
    {
        correction.reason = "blind: still frame, nothing to refine";
        return correction;
    }
    const BlindResult result =
        fitBlindTimeOffset(plant_, prepareBlindFrame(input, camera_, kFitFineWidth),
                                   schedule, shutter, correction, kBlindMaxTimeOffset, kBlindDecisive);
    correction = result.correction;
    correction.consistency = result.observed ? result.score : std::numeric_limits<double>::quiet_NaN();
    if (!result.observed)
        correction.reason = format("blind: fewer than %d rows stay still (a global shutter moving throughout the "
                                   "exposure, or window II), so nothing measures the scene's statistics: the "
                                   "model as told",
                                   kBlindMinStillRows);
    else if (result.applied)
        correction.reason = format("blind: time offset %+.3f ms decided by the row variograms (criterion %.3f, "
                                   "%.0f %% better than the model as told; %d blur models)",
                                   (correction.timeOffset - settings.calibration.timeOffset) * 1e3, result.score,
                                   100 * result.decisiveness, result.candidates);
    else
        correction.reason = format("blind: the row variograms do not decide (criterion %.3f, the best offset only "
                                   "%.0f %% better, below the %.0f %% required): the model as told",
                                   result.score, 100 * result.decisiveness, 100 * kBlindDecisive);
    if (settings.refinement & (REFINE_LINE_DELAY | REFINE_PLANT))
        correction.reason += "; line delay and plant are not observable blind: as told";
    if (result.observed && !(result.score <= settings.blindLimit))
    {
        correction.applied = false;
        correction.reason = format("blind: criterion %.3f exceeds the blind limit %.3f: no time offset explains "
                                   "the frame's rows (another schedule, something moving?); returned unchanged",
                                   result.score, settings.blindLimit);
    }
    return correction;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
