// SPDX-License-Identifier: Apache-2.0
// dynblur_calibrate_timing --gyro on a clip in continuous motion (clip_calibration.hpp).
#include "clip_calibration.hpp"

#include "atomic_file.hpp"  // samples/support
#include "gyro_timing.hpp"
#include "objective_plot.hpp"

#include <opencv2/dynblur.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;

namespace {

const double kDeg = CV_PI / 180;

//! The stretch of a clip that is calibrated: its frames' readouts on the video's clock.
struct Stretch
{
    std::vector<Vec2d> readouts;
    double start() const { return readouts.front()[0]; }
    double end() const { return readouts.back()[1]; }
};

/* The most frames of the stretch the log covers at one clock offset within ±maxOffset, and that offset:
   a frame is covered at δ when its readout, δ later, lies within the log's samples. */
size_t bestCoverage(const Stretch& stretch, const GyroLog& log, double maxOffset, double& offset)
{
    const double first = log.times.front(), last = log.times.back();
    std::vector<double> candidates{-maxOffset, maxOffset};
    for (const Vec2d& r : stretch.readouts)
        candidates.push_back(std::min(maxOffset, std::max(-maxOffset, first - r[0]))),
            candidates.push_back(std::min(maxOffset, std::max(-maxOffset, last - r[1])));
    size_t best = 0;
    offset = 0;
    for (double delta : candidates)
    {
        const size_t covered = size_t(std::count_if(stretch.readouts.begin(), stretch.readouts.end(), [&](const Vec2d& r) {
            return r[0] + delta >= first && r[1] + delta <= last;
        }));
        if (covered > best)
            best = covered, offset = delta;
    }
    return best;
}

/* Refuses a log that cannot calibrate the stretch at any offset within the window: one that covers no
   frame (another clip's, another clock's or unit's), or not all (shorter than the stretch: at the
   offset where it covers most frames, another clip's turns may match as well as this one's). */
void checkLogMeetsStretch(const Stretch& stretch, const GyroRecording& r, double maxOffset)
{
    double offset = 0;
    const size_t covered = bestCoverage(stretch, r.gyro, maxOffset, offset);
    if (covered == stretch.readouts.size())
        return;
    const std::string spans =
        format("its samples span [%.3f, %.3f] s on its clock%s, the frames calibrated [%.3f, %.3f] s on the video's "
               "(%s)",
               r.gyro.times.front(), r.gyro.times.back(),
               r.gyro.timeOrigin == 0 ? ""
                                      : format(" (counted from %.0f s: --gyro-time-origin)", r.gyro.timeOrigin).c_str(),
               stretch.start(), stretch.end(), r.timeSource.c_str());
    if (covered == 0)
        CV_Error(Error::StsBadArg,
                 format("--gyro: '%s' covers no frame of --video at any clock offset within +-%g s (--max-offset): "
                        "%s. Is it this clip's log, read in its time unit (--gyro-time-unit) from its origin "
                        "(--gyro-time-origin)? A log started long before the video needs a larger --max-offset (at most "
                        "60 s).",
                        r.gyroPath.c_str(), maxOffset, spans.c_str()));
    CV_Error(Error::StsBadArg,
             format("--gyro: '%s' does not cover the stretch calibrated: at any clock offset within +-%g s "
                    "(--max-offset) it covers at most %zu of its %zu frames (at %+.3f s); %s. Calibrate a stretch the "
                    "log covers whole (--clip-from, --clip-seconds).",
                    r.gyroPath.c_str(), maxOffset, covered, stretch.readouts.size(), offset, spans.c_str()));
}

void printCalibration(const TimingCalibration& t, const GyroRecording& r)
{
    const MotionCorrection& c = t.correction;
    const int rows = r.camera->getImageSize().height;
    const double lineDelay = r.told.lineDelay * c.lineDelayScale;
    const Vec3d bias = c.gyroBias * (1 / kDeg), biasStd = t.gyroBiasStd * (1 / kDeg);
    std::string axes = "as read";
    if (t.axisCorrection != Matx33d::eye())
    {
        axes = "corrected: w_camera = A w_log, A =";
        for (int i = 0; i < 3; i++)
            axes += format(" [%+.0f %+.0f %+.0f]", t.axisCorrection(i, 0), t.axisCorrection(i, 1), t.axisCorrection(i, 2));
        axes += " (check --gyro-orientation)";
    }
    std::printf("clock offset      %+.4f ms (sd %.4f): the log's clock minus the video's\n"
                "line delay        %.4g us, readout %.3f ms (x%.4f, sd %.4f, of the %.4g us told: %s)\n"
                "gyro bias         (%+.3f, %+.3f, %+.3f) deg/s (sd %.3f, %.3f, %.3f), beyond --gyro-bias's\n"
                "rate scale        x%.4f (sd %.4f)\n"
                "log axes          %s\n"
                "fit               the log explains %.0f %% of the image's turn; tracked features %.2f px RMS\n%s\n",
                c.timeOffset * 1e3, t.timeOffsetStd * 1e3, lineDelay * 1e6, lineDelay * rows * 1e3, c.lineDelayScale,
                t.lineDelayScaleStd, r.told.lineDelay * 1e6, r.told.lineDelayFrom.c_str(), bias[0], bias[1], bias[2],
                biasStd[0], biasStd[1], biasStd[2], c.rateScale, t.rateScaleStd, axes.c_str(), 100 * t.explainedMotion,
                t.trackResidualPx, c.reason.c_str());
}

}  // namespace

int calibrateClipTiming(const CliArgs& args, GyroRecording& r)
{
    const int measurable = REFINE_TIME_OFFSET | REFINE_LINE_DELAY | REFINE_GYRO_BIAS | REFINE_RATE_SCALE;
    int flags = 0;
    if (!parseRefinementList(args.str("refine", kGyroRefinement), measurable, flags) || !(flags & REFINE_TIME_OFFSET))
        throw std::runtime_error("--refine takes offset (always) and line-delay, bias and rate-scale on a clip, "
                                 "comma-separated");
    const double maxOffset = args.num("max-offset", 2.0);
    if (!(maxOffset > 0 && maxOffset <= 60))
        throw std::runtime_error("--max-offset must be in (0, 60] s on a clip");
    const double from = args.num("clip-from"), seconds = args.num("clip-seconds");
    if (!(from >= 0) || !(seconds > 0))
        throw std::runtime_error("--clip-from must be >= 0 and --clip-seconds > 0 (seconds)");
    const std::string out = args.str("out");
    const std::string plotPath = args.str("plot", pathStem(out) + "_objective.png");

    ClipTimingOptions options;
    options.maxTimeOffset = maxOffset;
    options.flags = flags;
    const Ptr<ClipTimingCalibrator> calibrator = ClipTimingCalibrator::create(r.camera, r.gyro, options);
    std::printf("%s\n", r.toldText().c_str());
    Stretch stretch;
    Mat image;
    FrameRecord f;
    double first = NAN;
    while (r.next(image, f))
    {
        first = std::isnan(first) ? f.frameStart : first;
        if (f.frameStart < first + from)
            continue;
        if (f.frameStart > first + from + seconds)
            break;
        const RollingShutter shutter = r.shutterOf(f);
        calibrator->addFrame(image, shutter);
        stretch.readouts.push_back(shutter.readoutInterval());
        std::printf("\rreading frame %d (%.2f s): %d frames of the stretch analysed", f.frame, f.frameStart,
                    calibrator->getFrameCount());
        std::fflush(stdout);
    }
    std::printf("\n");
    if (calibrator->getFrameCount() < 10)
        CV_Error(Error::StsBadArg,
                 format("--video: '%s' has %d frames from %g s after its first for %g s (--clip-from, --clip-seconds); "
                        "a clip's calibration needs at least 10",
                        args.str("video").c_str(), calibrator->getFrameCount(), from, seconds));
    checkLogMeetsStretch(stretch, r, maxOffset);
    std::printf("calibrating over %d frames, the clock offset within +-%g s ...\n", calibrator->getFrameCount(),
                maxOffset);
    TimingCalibration t;
    try
    {
        t = calibrator->calibrate();
    }
    catch (const cv::Exception& e)
    {
        CV_Error(e.code, "--gyro '" + r.gyroPath + "' against --video '" + args.str("video") + "': " + e.err);
    }
    saveClipCalibration(t, r.told, out);
    printCalibration(t, r);
    std::printf("wrote %s\n", out.c_str());
    if (!args.has("no-png"))
        writeOffsetScanPlot(t, "Clip timing calibration: the share of the image's turn the log explains", plotPath);
    return 0;
}
