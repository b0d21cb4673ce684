// SPDX-License-Identifier: Apache-2.0
// ClipTimingCalibrator: a clip in continuous motion calibrated against its gyro log from the frames
// alone, coarse (the image's turn between frames) to fine (tracked features).
#include "precomp.hpp"

#include "imaging/camera_frame.hpp"
#include "motion/shutter_check.hpp"
#include "refine/clip_sync.hpp"
#include "refine/track_fit.hpp"

#include <algorithm>

namespace cv {
namespace dynblur {

namespace {

const char* const kCreate = "ClipTimingCalibrator::create";
// A clip needs this many frames.
const int kMinFrames = 10;
/* The log explains at least this share of the image's turn when it is the clip's: measured 0.94 to
   0.98 on rendered hand-held clips, 0.12 for another clip's log; a real clip's parallax and moving
   objects lower the first, hence the margin. */
const double kMinExplained = 0.3;
// ... and no other offset explains nearly as much (a periodic motion, or a clip too short to tell).
const double kMaxRunnerUp = 0.85;
// The image's turn over the log's, outside which the units are wrong (a translation scales it
// within ±50 %, the rate scale's search).
const double kMinScale = 0.5, kMaxScale = 2.0;
// The told axes are kept unless another mapping explains this much more of the image's turn.
const double kAxesMargin = 0.05;
// The fine stage's search around the coarse offset, seconds (the coarse stage lands within a few ms).
const double kFineTimeOffset = 0.02;
/* A gyro bias and a rate scale the clip does not observe keep their values as told (0 and 1); the clock
   and the readout, which the coarse stage only roughed out, always take the tracks' best. */
const int kHoldable = REFINE_GYRO_BIAS | REFINE_RATE_SCALE;
/* A clip shorter than this, seconds, does not observe a gyro bias: its slowest shake and the trackers'
   drift look alike over it. Over 1 s the bias came out up to 0.17 °/s off where its deviation said
   0.03 °/s; over 3 s within 0.03 °/s (ClipTiming tests). */
const double kMinBiasSpan = 2.0;
// The fine stage starts again from its line delay when that moved beyond this fraction, at most this often.
const double kReadoutRecentre = 0.1;
const int kReadoutPasses = 4;
// Frames further apart than this many frame periods start a new run.
const double kMaxGapPeriods = 1.5;
// The log's samples, seconds apart, outside which its time unit is misread.
const double kMinSampleInterval = 1e-5, kMaxSampleInterval = 0.05;

String axisString(const Matx33d& M)
{
    String s;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (M(i, j) != 0)
                s += char(M(i, j) > 0 ? 'X' + j : 'x' + j);
    return s;
}

void checkOptions(const ClipTimingOptions& o)
{
    if (!(o.maxTimeOffset > 0 && o.maxTimeOffset <= 60))
        CV_Error(Error::StsOutOfRange,
                 format("%s: options.maxTimeOffset = %g s must be in (0, 60]", kCreate, o.maxTimeOffset));
    const int allowed = REFINE_TIME_OFFSET | REFINE_LINE_DELAY | REFINE_GYRO_BIAS | REFINE_RATE_SCALE;
    if ((o.flags & ~allowed) != 0 || !(o.flags & REFINE_TIME_OFFSET))
        CV_Error(Error::StsOutOfRange,
                 format("%s: options.flags = %d must include REFINE_TIME_OFFSET (1) and may add REFINE_LINE_DELAY (2), "
                        "REFINE_GYRO_BIAS (8) and REFINE_RATE_SCALE (16)",
                        kCreate, o.flags));
    if (!(o.analysisWidth >= 160 && o.analysisWidth <= 4096))
        CV_Error(Error::StsOutOfRange,
                 format("%s: options.analysisWidth = %d px must be in [160, 4096]", kCreate, o.analysisWidth));
}

//! The log's rates less its bias, checked: a time unit misread shows as samples too far apart or too close.
Mat checkedRates(const GyroLog& log)
{
    if (log.times.size() < 2 || log.rates.rows != int(log.times.size()) || log.rates.cols != 3 ||
        log.rates.channels() != 1)
        CV_Error(Error::StsBadArg, format("%s: 'log' must hold at least 2 samples and one N×3 row of rates per time "
                                          "(it has %zu times and a %d×%d rates matrix)",
                                          kCreate, log.times.size(), log.rates.rows, log.rates.cols));
    std::vector<double> steps;
    for (size_t k = 1; k < log.times.size(); k++)
    {
        if (!(log.times[k] > log.times[k - 1]))
            CV_Error(Error::StsBadArg, format("%s: log.times[%zu] = %.9g s is not after the previous sample; times "
                                              "must be strictly increasing",
                                              kCreate, k, log.times[k]));
        steps.push_back(log.times[k] - log.times[k - 1]);
    }
    std::nth_element(steps.begin(), steps.begin() + long(steps.size() / 2), steps.end());
    const double interval = steps[steps.size() / 2];
    if (interval > kMaxSampleInterval)
        CV_Error(Error::StsBadArg, format("%s: the log's samples are %.3g s apart (%.3g Hz); a gyroscope samples at 50 Hz "
                                          "or more: is its time unit misread (milliseconds read as seconds)?",
                                          kCreate, interval, 1 / interval));
    if (interval < kMinSampleInterval)
        CV_Error(Error::StsBadArg, format("%s: the log's samples are %.3g s apart (%.3g kHz); is its time unit "
                                          "misread (microseconds or nanoseconds read as milliseconds or seconds)?",
                                          kCreate, interval, 1e-3 / interval));
    Mat rates;
    log.rates.convertTo(rates, CV_64F);
    for (int k = 0; k < rates.rows; k++)
        for (int i = 0; i < 3; i++)
            rates.at<double>(k, i) -= log.bias[i];
    return rates;
}

class ClipTimingCalibratorImpl CV_FINAL : public ClipTimingCalibrator
{
public:
    ClipTimingCalibratorImpl(const Ptr<CameraModel>& camera, const GyroLog& log, const ClipTimingOptions& options)
        : camera_(camera), times_(log.times), rates_(checkedRates(log)), options_(options),
          meter_(camera, options.analysisWidth)
    {
    }

    void addFrame(InputArray frame, const RollingShutter& shutter) CV_OVERRIDE
    {
        const char* fn = "ClipTimingCalibrator::addFrame";
        const Mat image = frame.getMat();
        detail::checkCameraFrame(image, *camera_, fn, "frame");
        detail::checkShutter(shutter, fn, "shutter.", image.rows);
        const int index = int(frames_.size());
        if (index > 0 && !(shutter.frameStart > frames_.back().frameStart))
            CV_Error(Error::StsBadArg, format("%s: frame %d's frameStart %.6f s is not after the previous frame's %.6f "
                                              "s; add the frames in order",
                                              fn, index, shutter.frameStart, frames_.back().frameStart));
        bool follows = index > 0;
        if (index > 1)
        {
            const double period = (frames_.back().frameStart - frames_.front().frameStart) / (index - 1);
            follows = shutter.frameStart - frames_.back().frameStart <= kMaxGapPeriods * period;
        }
        detail::ClipFrame f;
        f.frameStart = shutter.frameStart, f.exposure = shutter.exposure, f.lineDelay = shutter.lineDelay;
        f.rows = shutter.rows;
        frames_.push_back(f);
        meter_.add(image, index, follows, &turns_, pairs_);
    }

    int getFrameCount() const CV_OVERRIDE { return int(frames_.size()); }

    TimingCalibration calibrate() CV_OVERRIDE
    {
        const char* fn = "ClipTimingCalibrator::calibrate";
        if (int(frames_.size()) < kMinFrames)
            CV_Error(Error::StsBadArg, format("%s: %zu frames added; a clip's calibration needs at least %d", fn,
                                              frames_.size(), kMinFrames));
        if (turns_.size() < size_t(kMinFrames))
            CV_Error(Error::StsError, format("%s: only %zu bands of rows showed a measurable turn over %zu frames: too "
                                             "little texture or too much blur to follow the image",
                                             fn, turns_.size(), frames_.size()));
        const detail::RateIntegral integral(times_, rates_);
        const detail::ClipSync sync =
            detail::synchronize(integral, turns_, frames_, options_.maxTimeOffset, options_.scanReadout);
        const Matx33d axes = checkSync(sync, fn);

        // The fine stage: the log's motion with the axes found, the frames' line delay scaled by the coarse readout.
        Mat mapped = rates_ * Mat(axes).t();
        const Ptr<CameraMotion> motion = CameraMotion::fromAngularVelocity(times_, mapped);
        /* The line delay is searched within the table's ±15 % of the coarse stage's, which the band
           model finds only within a step of its scan: where the fit ends near a bound, it starts again
           from there. */
        const double span = frames_.back().frameStart - frames_.front().frameStart;
        const int unobservedBias = span < kMinBiasSpan ? options_.flags & REFINE_GYRO_BIAS : 0;
        double lineDelayScale = sync.lineDelayScale;
        MotionCorrection start;
        start.timeOffset = sync.timeOffset;
        detail::TrackFit fit;
        for (int pass = 0; pass < kReadoutPasses; pass++)
        {
            std::vector<detail::ClipFrame> frames = frames_;
            for (detail::ClipFrame& f : frames)
                f.lineDelay *= lineDelayScale;
            fit = detail::fitTracks(motion, camera_, pairs_, frames, start, options_.flags & ~unobservedBias, kHoldable,
                                    kFineTimeOffset);
            lineDelayScale *= fit.correction.lineDelayScale;
            if (std::abs(fit.correction.lineDelayScale - 1) < kReadoutRecentre)
                break;
            start.timeOffset = fit.correction.timeOffset;
        }
        if (fit.inliers < size_t(4 * kMinFrames))
            CV_Error(Error::StsError, format("%s: only %zu of %zu tracked features follow the log's rotation: the "
                                             "frames show too few steady features (moving objects, too much blur?)",
                                             fn, fit.inliers, fit.pairs));

        TimingCalibration calibration;
        calibration.correction = fit.correction;
        calibration.correction.lineDelayScale = lineDelayScale;
        calibration.correction.held = fit.held | unobservedBias;
        calibration.correction.heldParameters = fit.heldParameters;
        for (int j = 0; j < detail::kFitParameters; j++)
            if (detail::kFitTable[j].flag & unobservedBias)
                calibration.correction.heldParameters |= 1 << j;
        for (int j = 0; j < detail::kFitParameters; j++)
            detail::kFitTable[j].deviation(calibration) = fit.deviation[j];
        calibration.lineDelayScaleStd *= lineDelayScale / fit.correction.lineDelayScale;
        calibration.axisCorrection = axes;
        calibration.explainedMotion = sync.explained;
        calibration.trackResidualPx = fit.rms;
        calibration.frameConsistency = fit.frameRms;
        for (double rms : fit.frameRms)
            calibration.frameUsed.push_back(std::isfinite(rms) ? 1 : 0);
        calibration.scanTimeOffsets = sync.scanOffsets;
        calibration.scanObjective = sync.scanExplained;
        calibration.correction.reason =
            format("calibrated over %zu frames without stills: offset %+.4f s found over +-%g s (the log explains %.0f %% "
                   "of the image's turn; the next best offset %.0f %%), %s; %zu of %zu tracked features within the "
                   "log's rotation, %.2f px RMS",
                   frames_.size(), sync.timeOffset, options_.maxTimeOffset, 100 * sync.explained, 100 * sync.runnerUp,
                   axes == Matx33d::eye() ? "the log's axes as read"
                                          : ("the log's axes corrected by '" + axisString(axes) + "'").c_str(),
                   fit.inliers, fit.pairs, fit.rms);
        if (calibration.correction.held)
            calibration.correction.reason += "; not determined by this clip, kept as told: " +
                                             detail::refinementFlagNames(calibration.correction.held);
        return calibration;
    }

    String getDefaultName() const CV_OVERRIDE { return "dynblur.ClipTimingCalibrator"; }

private:
    /* The coarse stage's verdict: the axes to use, or an exception naming what the images contradict. */
    Matx33d checkSync(const detail::ClipSync& sync, const char* fn) const
    {
        if (sync.explained < kMinExplained)
            CV_Error(Error::StsError,
                     format("%s: at no clock offset within +-%g s does the log explain the image's turn between "
                            "frames (at best %.0f %%, at %+.3f s; at least %.0f %% is needed): is it this clip's log? "
                            "(its clock must be within the offset searched: ClipTimingOptions::maxTimeOffset)",
                            fn, options_.maxTimeOffset, 100 * sync.explained, sync.timeOffset, 100 * kMinExplained));
        if (sync.runnerUp > kMaxRunnerUp * sync.explained)
            CV_Error(Error::StsError,
                     format("%s: the log explains the image's turn about as well at two clock offsets more than %g s "
                            "apart (%.0f %% and %.0f %%): the clip's motion is too regular or too short to synchronise; "
                            "give a longer stretch of hand-held motion",
                            fn, detail::kDistinctOffset, 100 * sync.explained, 100 * sync.runnerUp));
        if (!(sync.rateScale >= kMinScale && sync.rateScale <= kMaxScale))
        {
            const double perDegree = CV_PI / 180;
            const String hint = std::abs(std::log(sync.rateScale / perDegree)) < 0.3
                                    ? " The log's rates look like degrees per second read as radians per second."
                                : std::abs(std::log(sync.rateScale * perDegree)) < 0.3
                                    ? " The log's rates look like radians per second read as degrees per second."
                                    : String();
            CV_Error(Error::StsError,
                     format("%s: the image turns %.3g times as far as the log says (%.1f to %.1f expected).%s", fn,
                            sync.rateScale, kMinScale, kMaxScale, hint.c_str()));
        }
        if (determinant(sync.axes) < 0)
            CV_Error(Error::StsError,
                     format("%s: the image's turns match the log's only with a mirrored mapping of its axes ('%s' of the "
                            "axes as read, determinant -1): one axis of the log has the wrong sign",
                            fn, axisString(sync.axes).c_str()));
        if (sync.axes == Matx33d::eye() || sync.explainedAsTold + kAxesMargin >= sync.explained)
            return Matx33d::eye();
        if (!options_.detectAxes)
            CV_Error(Error::StsError,
                     format("%s: the images contradict the log's axes: as read they explain %.0f %% of the image's turn, "
                            "mapped by '%s' %.0f %%; give the gyro's orientation, or let the calibration detect it "
                            "(ClipTimingOptions::detectAxes)",
                            fn, 100 * sync.explainedAsTold, axisString(sync.axes).c_str(), 100 * sync.explained));
        return sync.axes;
    }

    Ptr<CameraModel> camera_;
    std::vector<double> times_;
    Mat rates_;  // the log's, bias removed, camera axes as read
    ClipTimingOptions options_;
    detail::FrameMotionMeter meter_;
    std::vector<detail::ClipFrame> frames_;
    std::vector<detail::BandTurn> turns_;
    std::vector<detail::TrackPair> pairs_;
};

}  // namespace

ClipTimingOptions::ClipTimingOptions()
    : maxTimeOffset(2.0), flags(REFINE_TIME_OFFSET | REFINE_LINE_DELAY | REFINE_GYRO_BIAS), scanReadout(true),
      detectAxes(true), analysisWidth(640)
{
}

Ptr<ClipTimingCalibrator> ClipTimingCalibrator::create(const Ptr<CameraModel>& camera, const GyroLog& log,
                                                       const ClipTimingOptions& options)
{
    if (camera.empty())
        CV_Error(Error::StsNullPtr, format("%s: 'camera' is null", kCreate));
    checkOptions(options);
    return makePtr<ClipTimingCalibratorImpl>(camera, log, options);
}

TimingCalibration calibrateTiming(const GyroLog& log, const Ptr<CameraModel>& camera, InputArrayOfArrays frames,
                                  const std::vector<RollingShutter>& shutters, const ClipTimingOptions& options)
{
    std::vector<Mat> images;
    frames.getMatVector(images);
    if (images.size() != shutters.size())
        CV_Error(Error::StsBadSize, format("calibrateTiming: frames has %zu entries but shutters %zu (one per frame)",
                                           images.size(), shutters.size()));
    const Ptr<ClipTimingCalibrator> calibrator = ClipTimingCalibrator::create(camera, log, options);
    for (size_t i = 0; i < images.size(); i++)
        calibrator->addFrame(images[i], shutters[i]);
    return calibrator->calibrate();
}

}  // namespace dynblur
}  // namespace cv
