// SPDX-License-Identifier: Apache-2.0
// MotionCorrection, TimingCalibration and the calls that estimate them (refinement.hpp).
#include "precomp.hpp"

#include "motion/axis_chain_motion.hpp"
#include "motion/camera_motion.hpp"
#include "motion/corrected_motion.hpp"
#include "motion/shutter_check.hpp"
#include "imaging/camera_frame.hpp"
#include "io/whole_file.hpp"
#include "refine/blind_fit.hpp"
#include "refine/motion_fit.hpp"

#include <cstdio>

namespace cv {
namespace dynblur {

MotionCorrection::MotionCorrection()
    : timeOffset(0), lineDelayScale(1), naturalFreqScale(1), dampingScale(1), axisNaturalFreqScales(1, 1),
      axisDampingScales(1, 1), rateScale(1), consistency(std::numeric_limits<double>::quiet_NaN()), held(REFINE_NONE),
      heldParameters(0), stillGain(1), applied(true)
{
}

namespace {

//! `plant` itself when both scales are 1, else the linear plant of the scaled ωn and ζ and the same gain.
Ptr<Plant> scaledPlant(const Ptr<Plant>& plant, double naturalFreqScale, double dampingScale)
{
    if (naturalFreqScale == 1 && dampingScale == 1)
        return plant;
    return Plant::create(plant->getNaturalFreqHz() * naturalFreqScale, plant->getDampingRatio() * dampingScale,
                         plant->getGain());
}

}  // namespace

RollingShutter MotionCorrection::correctShutter(const RollingShutter& shutter) const
{
    RollingShutter corrected = shutter;
    corrected.frameStart += timeOffset;
    corrected.lineDelay *= lineDelayScale;
    return corrected;
}

Ptr<Plant> MotionCorrection::correctPlant(const Ptr<Plant>& plant) const
{
    CV_Assert(!plant.empty() && "MotionCorrection::correctPlant: 'plant' is null");
    return scaledPlant(plant, naturalFreqScale, dampingScale);
}

Ptr<CameraMotion> MotionCorrection::correctMotion(const Ptr<CameraMotion>& motion) const
{
    CV_Assert(!motion.empty() && "MotionCorrection::correctMotion: 'motion' is null");
    if (const detail::PlantMotion* plantMotion = detail::asPlantMotion(*motion))
    {
        const Ptr<Plant> plant = correctPlant(plantMotion->plant());
        return plant == plantMotion->plant() ? motion
                                             : CameraMotion::fromPlant(plant, plantMotion->schedule(), plantMotion->axis());
    }
    const detail::AxisChainMotion* mount = detail::asAxisChainMotion(*motion);
    if (!mount)
        return motion;
    std::vector<Ptr<Plant>> plants;
    bool scaled = false;
    for (int i = 0; i < mount->axisCount(); i++)
    {
        const Ptr<Plant> told = mount->axisPlant(i);
        plants.push_back(i == 0   ? correctPlant(told)
                         : i <= 2 ? scaledPlant(told, axisNaturalFreqScales[i - 1], axisDampingScales[i - 1])
                                  : told);
        scaled = scaled || plants.back() != told;
    }
    return scaled ? mount->withPlants(plants) : motion;
}

void MotionCorrection::validate() const
{
    if (!std::isfinite(timeOffset))
        CV_Error(Error::StsOutOfRange, format("MotionCorrection: timeOffset = %g s must be finite", timeOffset));
    const std::pair<const char*, double> scales[] = {
        {"lineDelayScale", lineDelayScale},           {"naturalFreqScale", naturalFreqScale},
        {"dampingScale", dampingScale},               {"axisNaturalFreqScales[0]", axisNaturalFreqScales[0]},
        {"axisNaturalFreqScales[1]", axisNaturalFreqScales[1]}, {"axisDampingScales[0]", axisDampingScales[0]},
        {"axisDampingScales[1]", axisDampingScales[1]}, {"rateScale", rateScale}};
    for (const auto& scale : scales)
        if (!(scale.second > 0 && scale.second < 10))
            CV_Error(Error::StsOutOfRange,
                     format("MotionCorrection: %s = %g must be in (0, 10)", scale.first, scale.second));
    for (int i = 0; i < 3; i++)
        if (!(std::abs(gyroBias[i]) <= 1))
            CV_Error(Error::StsOutOfRange, format("MotionCorrection: gyroBias[%d] = %g rad/s must be finite and "
                                                  "within [-1, 1] rad/s",
                                                  i, gyroBias[i]));
}

TimingCalibration::TimingCalibration()
    : timeOffsetStd(0), lineDelayScaleStd(0), naturalFreqScaleStd(0), dampingScaleStd(0), axisNaturalFreqScaleStd(0, 0),
      axisDampingScaleStd(0, 0), rateScaleStd(0),
      axisCorrection(Matx33d::eye()), explainedMotion(std::numeric_limits<double>::quiet_NaN()),
      trackResidualPx(std::numeric_limits<double>::quiet_NaN())
{
}

void TimingCalibration::save(const String& filename) const
{
    correction.validate();
    // Written beside the target and renamed over it: a reader never sees half a file.
    detail::saveWhole(filename, "TimingCalibration::save", [&](FileStorage& fs) {
        fs.writeComment("dynblur timing calibration: the camera clock's offset to the actuator's (s), and scales of "
                        "the nominal line delay, natural frequency and damping ratio");
        fs << "timeOffset" << correction.timeOffset << "lineDelayScale" << correction.lineDelayScale
           << "naturalFreqScale" << correction.naturalFreqScale << "dampingScale" << correction.dampingScale;
        if (correction.gyroBias != Vec3d() || gyroBiasStd != Vec3d())  // a measured motion's (rad/s)
            fs << "gyroBias" << std::vector<double>{correction.gyroBias[0], correction.gyroBias[1],
                                                    correction.gyroBias[2]}
               << "gyroBiasStd" << std::vector<double>{gyroBiasStd[0], gyroBiasStd[1], gyroBiasStd[2]};
        if (correction.axisNaturalFreqScales != Vec2d(1, 1) || correction.axisDampingScales != Vec2d(1, 1) ||
            axisNaturalFreqScaleStd != Vec2d() || axisDampingScaleStd != Vec2d())  // a mount's axes 1 and 2
        {
            const std::pair<const char*, Vec2d> pairs[] = {{"axisNaturalFreqScales", correction.axisNaturalFreqScales},
                                                           {"axisDampingScales", correction.axisDampingScales},
                                                           {"axisNaturalFreqScaleStd", axisNaturalFreqScaleStd},
                                                           {"axisDampingScaleStd", axisDampingScaleStd}};
            for (const auto& pair : pairs)
                fs << pair.first << std::vector<double>{pair.second[0], pair.second[1]};
        }
        if (correction.rateScale != 1 || rateScaleStd != 0)  // a measured motion's
            fs << "rateScale" << correction.rateScale << "rateScaleStd" << rateScaleStd;
        if (axisCorrection != Matx33d::eye())  // a gyro log whose axes the images corrected, row-major
            fs << "axisCorrection" << std::vector<double>(axisCorrection.val, axisCorrection.val + 9);
        if (std::isfinite(explainedMotion))
            fs << "explainedMotion" << explainedMotion;
        if (std::isfinite(trackResidualPx))
            fs << "trackResidualPx" << trackResidualPx;
        if (std::isfinite(correction.consistency))
            fs << "consistency" << correction.consistency;
        fs << "timeOffsetStd" << timeOffsetStd << "lineDelayScaleStd" << lineDelayScaleStd << "naturalFreqScaleStd"
           << naturalFreqScaleStd << "dampingScaleStd" << dampingScaleStd;
        // A frame left out (still) has no consistency: written as −1, which no consistency is.
        std::vector<double> consistency = frameConsistency;
        for (double& value : consistency)
            value = std::isfinite(value) ? value : -1.0;
        fs << "frameUsed" << frameUsed << "frameConsistency" << consistency;
    });
}

namespace {

//! The `count` values of `key` in `file` (read from `filename`), or an error naming both and `what` they are.
std::vector<double> fixedReals(const ParameterFile& file, const char* key, size_t count, const char* what,
                               const String& filename)
{
    const std::vector<double> values = file.reals(key);
    if (values.size() != count)
        CV_Error(Error::StsParseError, format("TimingCalibration::load: '%s': %s has %zu values; %zu (%s) are expected",
                                              filename.c_str(), key, values.size(), count, what));
    return values;
}

}  // namespace

TimingCalibration TimingCalibration::load(const String& filename)
{
    const ParameterFile file = ParameterFile::load(filename, "TimingCalibration::load: timing file");
    TimingCalibration calibration;
    MotionCorrection& c = calibration.correction;
    c.timeOffset = file.real("timeOffset");
    c.lineDelayScale = file.real("lineDelayScale");
    c.naturalFreqScale = file.real("naturalFreqScale");
    c.dampingScale = file.real("dampingScale");
    if (file.has("consistency"))
        c.consistency = file.real("consistency");
    const std::pair<const char*, double*> deviations[] = {{"timeOffsetStd", &calibration.timeOffsetStd},
                                                          {"lineDelayScaleStd", &calibration.lineDelayScaleStd},
                                                          {"naturalFreqScaleStd", &calibration.naturalFreqScaleStd},
                                                          {"dampingScaleStd", &calibration.dampingScaleStd},
                                                          {"rateScale", &c.rateScale},
                                                          {"rateScaleStd", &calibration.rateScaleStd},
                                                          {"explainedMotion", &calibration.explainedMotion},
                                                          {"trackResidualPx", &calibration.trackResidualPx}};
    for (const auto& d : deviations)
        if (file.has(d.first))
            *d.second = file.real(d.first);
    const std::pair<const char*, Vec3d*> vectors[] = {{"gyroBias", &c.gyroBias},
                                                      {"gyroBiasStd", &calibration.gyroBiasStd}};
    for (const auto& v : vectors)
        if (file.has(v.first))
            *v.second = Vec3d(fixedReals(file, v.first, 3, "rad/s, camera axes x, y, z", filename).data());
    const std::pair<const char*, Vec2d*> pairs[] = {{"axisNaturalFreqScales", &c.axisNaturalFreqScales},
                                                    {"axisDampingScales", &c.axisDampingScales},
                                                    {"axisNaturalFreqScaleStd", &calibration.axisNaturalFreqScaleStd},
                                                    {"axisDampingScaleStd", &calibration.axisDampingScaleStd}};
    for (const auto& v : pairs)
        if (file.has(v.first))
            *v.second = Vec2d(fixedReals(file, v.first, 2, "a mount's axes 1 and 2", filename).data());
    if (file.has("axisCorrection"))
    {
        calibration.axisCorrection =
            Matx33d(fixedReals(file, "axisCorrection", 9, "a rotation matrix, row-major", filename).data());
        if (!(std::abs(determinant(calibration.axisCorrection) - 1) < 1e-6 &&
              norm(calibration.axisCorrection * calibration.axisCorrection.t() - Matx33d::eye()) < 1e-6))
            CV_Error(Error::StsParseError, format("TimingCalibration::load: '%s': axisCorrection is not a rotation "
                                                  "(orthonormal, determinant +1)",
                                                  filename.c_str()));
    }
    if (file.has("frameUsed"))
        calibration.frameUsed = file.integers("frameUsed");
    if (file.has("frameConsistency"))
        calibration.frameConsistency = file.reals("frameConsistency");
    for (double& value : calibration.frameConsistency)
        value = value < 0 ? std::numeric_limits<double>::quiet_NaN() : value;
    try
    {
        c.validate();
    }
    catch (const cv::Exception& e)
    {
        CV_Error(Error::StsParseError, "TimingCalibration::load: '" + filename + "': " + e.err);
    }
    return calibration;
}

namespace {

const int kCoarseWidth = detail::kFitCoarseWidth, kFineWidth = detail::kFitFineWidth;

/* The pyramids of one (reference, frame) pair and the frame's shutter, checked; `reference` must
   outlive the FitFrame. */
detail::FitFrame pairFrames(const Mat& reference, const Mat& frame, const Ptr<CameraModel>& camera,
                            const RollingShutter& shutter, detail::LuminancePyramid& referencePyramid, const char* fn,
                            int index, int coarsestWidth)
{
    const String referenceName = index < 0 ? String("reference") : format("references[%d]", index);
    const String frameName = index < 0 ? String("frame") : format("frames[%d]", index);
    detail::checkCameraFrame(reference, *camera, fn, referenceName.c_str());
    detail::checkCameraFrame(frame, *camera, fn, frameName.c_str());
    if (reference.type() != frame.type())
        CV_Error(Error::StsUnmatchedFormats,
                 format("%s: '%s' is %s but '%s' is %s; a still frame must come from the same camera stream", fn,
                        referenceName.c_str(), typeToString(reference.type()).c_str(), frameName.c_str(),
                        typeToString(frame.type()).c_str()));
    detail::checkShutter(shutter, fn, ("the shutter of '" + frameName + "': ").c_str(), frame.rows);
    referencePyramid = detail::buildPyramid(detail::linearLuminance(reference), camera, coarsestWidth, true);
    detail::FitFrame f;
    f.reference = &referencePyramid;
    f.frame = detail::buildPyramid(detail::linearLuminance(frame), camera, coarsestWidth, false);
    f.shutter = shutter;
    return f;
}

//! pairFrames for a plant's frame: its schedule and its still's angle, checked.
detail::FitFrame makeFitFrame(const Mat& reference, const Mat& frame, const Ptr<CameraModel>& camera,
                              const Ptr<Plant>& plant, const SwitchSchedule& schedule, const RollingShutter& shutter,
                              double referenceAngle, detail::LuminancePyramid& referencePyramid, const char* fn,
                              int index, int coarsestWidth = kCoarseWidth)
{
    schedule.validate();
    const double angle = std::isnan(referenceAngle) ? plant->restingAngle(schedule.initialLevel) : referenceAngle;
    if (!std::isfinite(angle) || std::abs(angle) > CV_PI / 2)
        CV_Error(Error::StsOutOfRange,
                 format("%s: the angle of '%s' = %g rad must be finite and within [-pi/2, pi/2]", fn,
                        (index < 0 ? String("reference") : format("references[%d]", index)).c_str(), angle));
    detail::FitFrame f =
        pairFrames(reference, frame, camera, shutter, referencePyramid, fn, index, coarsestWidth);
    f.schedule = schedule;
    f.referenceAngle = angle;
    return f;
}

/* Refuses `flags` unless they combine only flags of `allowed` (any of the table's, when
   `ignored` lists those that do not apply to this motion) and at least one of `allowed`. */
void checkFlags(int flags, int allowed, int ignored, const char* fn)
{
    const int accepted = allowed | ignored;
    if ((flags & ~accepted) != 0 || !(flags & allowed))
        CV_Error(Error::StsOutOfRange,
                 format("%s: flags = %d must combine %s, at least one of them%s: a value in [1, %d]", fn, flags,
                        detail::refinementFlagList(allowed).c_str(),
                        ignored ? format(" (%s is ignored for this motion)",
                                         detail::refinementFlagList(ignored).c_str()).c_str()
                                : "",
                        accepted));
}

void checkSearch(double maxTimeOffset, double maxConsistency, const char* fn)
{
    if (!(maxTimeOffset > 0 && maxTimeOffset <= 1))
        CV_Error(Error::StsOutOfRange, format("%s: maxTimeOffset = %g s must be in (0, 1]", fn, maxTimeOffset));
    if (!(maxConsistency > 1) || std::isnan(maxConsistency))
        CV_Error(Error::StsOutOfRange, format("%s: maxConsistency = %g must be > 1", fn, maxConsistency));
}

/* The common correction of the moving frames `fit` (`index`: their places among the `n` frames
   given), fitted again without the frames it leaves above `maxConsistency`, as a TimingCalibration
   with its offset scan. `plant` is null for a measured motion. */
TimingCalibration calibrateFrames(const Ptr<Plant>& plant, const std::vector<detail::FitFrame>& fit,
                                  const std::vector<size_t>& index, size_t n, const detail::FitSettings& settings,
                                  double maxConsistency, const char* fn)
{
    if (fit.size() < 2)
        CV_Error(Error::StsBadArg,
                 format("%s: fewer than two usable frames: %zu of the %zu frames are taken during a move (the others "
                        "are in window IV, still); give at least two moving frames",
                        fn, fit.size(), n));
    detail::FitResult result = fitMotionCorrection(plant, fit, MotionCorrection(), settings);

    // Frames the common model cannot explain (another schedule, something moving) leave the fit.
    std::vector<detail::FitFrame> kept;
    std::vector<size_t> keptIndex;
    for (size_t k = 0; k < fit.size(); k++)
        if (result.frameConsistency[k] <= maxConsistency)
            kept.push_back(fit[k]), keptIndex.push_back(index[k]);
    if (kept.size() < 2)
        CV_Error(Error::StsBadArg,
                 format("%s: fewer than two usable frames: at the best common correction only %zu of %zu moving "
                        "frames have a consistency within maxConsistency = %g",
                        fn, kept.size(), fit.size(), maxConsistency));
    if (kept.size() < fit.size())  // afresh: the first fit was pulled toward the frames now left out
        result = fitMotionCorrection(plant, kept, MotionCorrection(), settings);

    TimingCalibration calibration;
    calibration.correction = result.correction;
    calibration.correction.reason = format("calibrated over %zu frames", kept.size());
    calibration.correction.held = result.held;
    calibration.correction.heldParameters = result.heldParameters;
    if (result.held)
        calibration.correction.reason += format("; the frames do not determine %s: kept as told along what they "
                                                "do not determine (frames at different phases of their moves "
                                                "separate them; an axis no move turns is not observed)",
                                                detail::parameterNames(result.heldParameters).c_str());
    if (result.pinned)
        calibration.correction.reason += "; " + result.pinnedNote;
    for (int j = 0; j < detail::kFitParameters; j++)
        detail::kFitTable[j].deviation(calibration) = result.deviation[j];
    calibration.frameUsed.assign(n, 0);
    for (size_t i : keptIndex)
        calibration.frameUsed[i] = 1;
    calibration.frameConsistency.assign(n, std::numeric_limits<double>::quiet_NaN());
    const std::vector<double> consistency = detail::frameConsistency(plant, fit, result.correction, kFineWidth);
    for (size_t k = 0; k < fit.size(); k++)
        calibration.frameConsistency[index[k]] = consistency[k];

    std::vector<MotionCorrection> scan;
    for (int k = -40; k <= 40; k++)
    {
        scan.push_back(result.correction);
        scan.back().timeOffset += k * 1e-3 / 40;  // ±1 ms around the result
        calibration.scanTimeOffsets.push_back(scan.back().timeOffset);
    }
    calibration.scanObjective = detail::meanSquaredResiduals(plant, kept, result.correction, scan, kFineWidth);
    return calibration;
}

}  // namespace

TimingCalibration calibrateTiming(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera,
                                  InputArrayOfArrays references, InputArrayOfArrays frames,
                                  const std::vector<SwitchSchedule>& schedules,
                                  const std::vector<RollingShutter>& shutters, int flags,
                                  const std::vector<double>& referenceAngles, double maxTimeOffset,
                                  double maxConsistency)
{
    const char* fn = "calibrateTiming";
    if (plant.empty() || camera.empty())
        CV_Error(Error::StsNullPtr, format("%s: '%s' is null", fn, plant.empty() ? "plant" : "camera"));
    checkFlags(flags, detail::refinementFlagsFor(detail::FIT_PLANT_MOTION), 0, fn);
    checkSearch(maxTimeOffset, maxConsistency, fn);
    std::vector<Mat> stills, blurred;
    references.getMatVector(stills);
    frames.getMatVector(blurred);
    const size_t n = blurred.size();
    if (stills.size() != n || schedules.size() != n || shutters.size() != n ||
        (!referenceAngles.empty() && referenceAngles.size() != n))
        CV_Error(Error::StsBadSize,
                 format("%s: frames has %zu entries but references %zu, schedules %zu, shutters %zu and "
                        "referenceAngles %zu (empty or one per frame)",
                        fn, n, stills.size(), schedules.size(), shutters.size(), referenceAngles.size()));

    std::vector<detail::LuminancePyramid> pyramids(n);
    std::vector<detail::FitFrame> fit;
    std::vector<size_t> index;
    for (size_t i = 0; i < n; i++)
    {
        const double angle = referenceAngles.empty() ? std::numeric_limits<double>::quiet_NaN() : referenceAngles[i];
        detail::FitFrame f = makeFitFrame(stills[i], blurred[i], camera, plant, schedules[i], shutters[i], angle,
                                          pyramids[i], fn, int(i));
        if (classifyExposure(plant, schedules[i], shutters[i]) == EXPOSURE_IV)
            continue;  // a still frame says nothing about the motion
        fit.push_back(std::move(f));
        index.push_back(i);
    }
    detail::FitSettings settings;
    settings.flags = flags;
    settings.maxTimeOffset = maxTimeOffset;
    settings.coarseWidth = kCoarseWidth;
    settings.fineWidth = kFineWidth;
    return calibrateFrames(plant, fit, index, n, settings, maxConsistency, fn);
}

TimingCalibration calibrateTiming(const Ptr<CameraMotion>& motion, const Ptr<CameraModel>& camera,
                                  InputArrayOfArrays references, InputArrayOfArrays frames,
                                  const std::vector<RollingShutter>& shutters,
                                  const std::vector<RollingShutter>& referenceShutters, int flags,
                                  double maxTimeOffset, double maxConsistency)
{
    const char* fn = "calibrateTiming";
    if (motion.empty() || camera.empty())
        CV_Error(Error::StsNullPtr, format("%s: '%s' is null", fn, motion.empty() ? "motion" : "camera"));
    if (motion->isPlantMotion())
        CV_Error(Error::StsBadArg, format("%s: 'motion' is a plant's (CameraMotion::fromPlant); calibrate it with "
                                          "calibrateTiming(plant, camera, references, frames, schedules, shutters), "
                                          "which refines the plant too",
                                          fn));
    const int measurable = detail::refinementFlagsFor(detail::FIT_MEASURED_MOTION);
    checkFlags(flags, measurable, detail::allRefinementFlags() & ~measurable, fn);
    checkSearch(maxTimeOffset, maxConsistency, fn);
    std::vector<Mat> stills, blurred;
    references.getMatVector(stills);
    frames.getMatVector(blurred);
    const size_t n = blurred.size();
    if (stills.size() != n || shutters.size() != n || referenceShutters.size() != n)
        CV_Error(Error::StsBadSize, format("%s: frames has %zu entries but references %zu, shutters %zu and "
                                           "referenceShutters %zu (one per frame)",
                                           fn, n, stills.size(), shutters.size(), referenceShutters.size()));

    std::vector<detail::LuminancePyramid> pyramids(n);
    std::vector<detail::FitFrame> fit;
    std::vector<size_t> index;
    for (size_t i = 0; i < n; i++)
    {
        detail::FitFrame f = pairFrames(stills[i], blurred[i], camera, shutters[i], pyramids[i], fn, int(i),
                                        kCoarseWidth);
        const String stillName = format("referenceShutters[%zu]", i);
        detail::checkShutter(referenceShutters[i], fn, (stillName + ".").c_str(), stills[i].rows);
        detail::checkMotionCoversSearch(motion, shutters[i], maxTimeOffset, fn, format("'frames[%zu]'", i));
        detail::checkMotionCoversSearch(motion, referenceShutters[i], maxTimeOffset, fn, format("'references[%zu]'", i));
        if (classifyExposure(motion, shutters[i]) == EXPOSURE_IV)
            continue;  // a frame taken at rest says nothing about the clock
        f.motion = motion;
        f.referenceTime = detail::midExposure(referenceShutters[i]);
        fit.push_back(std::move(f));
        index.push_back(i);
    }
    detail::FitSettings settings;
    settings.flags = flags & measurable;
    settings.maxTimeOffset = maxTimeOffset;
    settings.coarseWidth = kCoarseWidth;
    settings.fineWidth = kFineWidth;
    return calibrateFrames(Ptr<Plant>(), fit, index, n, settings, maxConsistency, fn);
}

TimingCalibration calibrateTiming(const std::vector<Ptr<CameraMotion>>& motions, const Ptr<CameraModel>& camera,
                                  InputArrayOfArrays references, InputArrayOfArrays frames,
                                  const std::vector<RollingShutter>& shutters, int flags,
                                  const std::vector<int>& referencesAfter, double maxTimeOffset, double maxConsistency)
{
    const char* fn = "calibrateTiming";
    if (camera.empty())
        CV_Error(Error::StsNullPtr, format("%s: 'camera' is null", fn));
    checkFlags(flags, detail::refinementFlagsFor(detail::FIT_MOUNT_MOTION), 0, fn);
    checkSearch(maxTimeOffset, maxConsistency, fn);
    std::vector<Mat> stills, blurred;
    references.getMatVector(stills);
    frames.getMatVector(blurred);
    const size_t n = blurred.size();
    if (motions.size() != n || stills.size() != n || shutters.size() != n ||
        (!referencesAfter.empty() && referencesAfter.size() != n))
        CV_Error(Error::StsBadSize, format("%s: frames has %zu entries but motions %zu, references %zu, shutters %zu "
                                           "and referencesAfter %zu (empty or one per frame)",
                                           fn, n, motions.size(), stills.size(), shutters.size(),
                                           referencesAfter.size()));

    std::vector<detail::LuminancePyramid> pyramids(n);
    std::vector<detail::FitFrame> fit;
    std::vector<size_t> index;
    for (size_t i = 0; i < n; i++)
    {
        const detail::AxisChainMotion* mount = motions[i] ? detail::asAxisChainMotion(*motions[i]) : nullptr;
        if (!mount)
            CV_Error(Error::StsBadArg, format("%s: motions[%zu] is %s; each must be a mount's motion (Mount::motion): "
                                              "calibrate a plant's frames with calibrateTiming(plant, ...), a "
                                              "measured motion's with calibrateTiming(motion, ...)",
                                              fn, i, motions[i] ? "not a mount's" : "null"));
        const int axes = detail::asAxisChainMotion(*motions[0])->axisCount();
        if (mount->axisCount() != axes)
            CV_Error(Error::StsBadArg, format("%s: motions[%zu] has %d axes but motions[0] has %d; the frames must "
                                              "come from one mount",
                                              fn, i, mount->axisCount(), axes));
        detail::FitFrame f = pairFrames(stills[i], blurred[i], camera, shutters[i], pyramids[i], fn, int(i),
                                        kCoarseWidth);
        if (classifyExposure(motions[i], shutters[i]) == EXPOSURE_IV)
            continue;  // a still frame says nothing about the motion
        f.motion = motions[i];
        f.referenceOrientation = mount->restOrientation(!referencesAfter.empty() && referencesAfter[i] != 0);
        fit.push_back(std::move(f));
        index.push_back(i);
    }
    detail::FitSettings settings;
    settings.flags = flags;
    settings.maxTimeOffset = maxTimeOffset;
    settings.coarseWidth = kCoarseWidth;
    settings.fineWidth = kFineWidth;
    return calibrateFrames(Ptr<Plant>(), fit, index, n, settings, maxConsistency, fn);
}

std::vector<double> motionConsistency(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera, InputArray reference,
                                      InputArray frame, const SwitchSchedule& schedule, const RollingShutter& shutter,
                                      const std::vector<MotionCorrection>& candidates, double referenceAngle,
                                      int maxWidth)
{
    const char* fn = "motionConsistency";
    if (plant.empty() || camera.empty())
        CV_Error(Error::StsNullPtr, format("%s: '%s' is null", fn, plant.empty() ? "plant" : "camera"));
    if (maxWidth < 16)
        CV_Error(Error::StsOutOfRange, format("%s: maxWidth = %d px must be at least 16", fn, maxWidth));
    for (const MotionCorrection& c : candidates)
        c.validate();
    detail::LuminancePyramid pyramid;
    std::vector<detail::FitFrame> fit{makeFitFrame(reference.getMat(), frame.getMat(), camera, plant, schedule,
                                                   shutter, referenceAngle, pyramid, fn, -1,
                                                   std::min(kCoarseWidth, maxWidth))};
    std::vector<double> values =
        detail::meanSquaredResiduals(plant, fit, candidates.empty() ? MotionCorrection() : candidates[0], candidates,
                                     maxWidth);
    for (double& v : values)
        v = std::sqrt(v);
    return values;
}

std::vector<double> blindMotionConsistency(const Ptr<Plant>& plant, const Ptr<CameraModel>& camera, InputArray frame,
                                           const SwitchSchedule& schedule, const RollingShutter& shutter,
                                           const std::vector<MotionCorrection>& candidates, int maxWidth)
{
    const char* fn = "blindMotionConsistency";
    if (plant.empty() || camera.empty())
        CV_Error(Error::StsNullPtr, format("%s: '%s' is null", fn, plant.empty() ? "plant" : "camera"));
    CV_CheckGE(maxWidth, 64, "blindMotionConsistency: maxWidth (pixels) must be in [64, 4096]");
    CV_CheckLE(maxWidth, 4096, "blindMotionConsistency: maxWidth (pixels) must be in [64, 4096]");
    const Mat image = frame.getMat();
    detail::checkCameraFrame(image, *camera, fn, "frame");
    schedule.validate();
    detail::checkShutter(shutter, fn, "shutter.", image.rows);
    for (const MotionCorrection& c : candidates)
        c.validate();
    if (candidates.empty())
        return std::vector<double>();
    return detail::blindObjective(plant, detail::prepareBlindFrame(image, camera, maxWidth), schedule, shutter,
                                  candidates);
}

}  // namespace dynblur
}  // namespace cv
