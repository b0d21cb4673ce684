// SPDX-License-Identifier: Apache-2.0
// dynblur_calibrate_timing --gyro: calibrateTiming on a gyro log's motion, frames paired with the
// frames the log shows held still (gyro_timing.hpp); a clip without such frames, or without a frame
// log, goes to clip_calibration.cpp.
#include "gyro_timing.hpp"

#include "atomic_file.hpp"  // samples/support
#include "cli_args.hpp"
#include "clip_calibration.hpp"
#include "gyro_recording.hpp"
#include "gyro_simulation.hpp"
#include "objective_plot.hpp"

#include <opencv2/dynblur.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;

const char* const kGyroRefinement = "offset,line-delay,bias";

namespace {
const double kDeg = CV_PI / 180;
}

dynblur_samples::CliOptionGroup gyroTimingOptions()
{
    const GyroSimulation truth;
    CliOptionGroup options = gyroLogOptions(
        "Gyro mode (--gyro LOG --video V [--frames FRAMES.csv]):",
        "A recording whose motion is a gyro log: the log's clock offset to the camera's, the line delay and the gyro "
        "bias. With a frame log whose frames the log shows held still at times (rate below --still-rate over the "
        "whole readout), from frames taken while the hand moved, each against the nearest such still (--refine " +
            std::string(kGyroRefinement) + ", the default; the offset within --max-offset, default 0.02 s). A clip in "
        "continuous motion, or a video without a frame log (its frame times then come from its container's "
        "timestamps), is calibrated from the motion between its frames (ClipTimingCalibrator, docs/hand-held.md): "
        "the offset within --max-offset, default 2 s (at most 60), the readout (searched from a quarter to twice the "
        "one told by --readout, --line-delay or a gcsv log's frame_readout_time, else half the frame period), the "
        "bias over a stretch of 2 s or more, and the log's axes; --refine may add rate-scale. --exposure is "
        "required without a frame log. Writes the timing file with the shutter it was told (dynblur_restore_video "
        "reproduces the line delay from it) and OUT_objective.png, the share of the image's turn the log explains "
        "against the offset.");
    options.options.push_back({"still-rate", "D", "2", "deg/s below which a frame is a still"});
    options.options.push_back({"max-still-gap", "S", "1", "a moving frame is used only with a still within S seconds"});
    options.options.push_back({"clip-from", "S", "0",
                               "a clip is calibrated over the frames from S seconds after its first frame ..."});
    options.options.push_back({"clip-seconds", "S", "10", "... for S seconds (streamed: only these frames are analysed)"});
    options.options.push_back(
        {"simulate-gyro", "DIR", "",
         "renders a hand-held recording with its gyro log into DIR (320x240, 2 s) and exits; its truth from "
         "--true-offset (default " + numberText(truth.timeOffset) + " here), --true-line-delay-scale (default " +
             numberText(truth.lineDelayScale) + " here) and --true-bias"});
    options.options.push_back({"true-bias", "BX,BY,BZ", format("%g,%g,%g", truth.bias[0] / kDeg, truth.bias[1] / kDeg,
                                                                 truth.bias[2] / kDeg),
                               "the simulated gyro's bias, deg/s"});
    return options;
}

int simulateGyroTiming(const CliArgs& args)
{
    GyroSimulation truth;
    truth.timeOffset = args.num("true-offset", truth.timeOffset);
    truth.lineDelayScale = args.num("true-line-delay-scale", truth.lineDelayScale);
    if (args.has("true-bias"))
    {
        const std::string text = args.str("true-bias");
        double b[3];
        if (std::sscanf(text.c_str(), "%lf,%lf,%lf", &b[0], &b[1], &b[2]) != 3 || std::abs(b[0]) > 10 ||
            std::abs(b[1]) > 10 || std::abs(b[2]) > 10)
            throw std::runtime_error("--true-bias takes BX,BY,BZ in deg/s, each within +-10");
        truth.bias = Vec3d(b[0], b[1], b[2]) * kDeg;
    }
    if (!(std::abs(truth.timeOffset) <= 0.05) || !(truth.lineDelayScale > 0.8 && truth.lineDelayScale < 1.2))
        throw std::runtime_error("--true-offset must be within +-0.05 s and --true-line-delay-scale in (0.8, 1.2)");
    const std::string dir = args.str("simulate-gyro");
    const int frames = simulateGyroRecording(dir, truth);
    std::printf("wrote %d frames (frame_%%04d.png), frames.csv, gyro.gcsv and camera.xml to %s\n"
                "truth: clock offset %+.4f ms, line delay x%.4f, bias (%.3f, %.3f, %.3f) deg/s\n",
                frames, dir.c_str(), truth.timeOffset * 1e3, truth.lineDelayScale, truth.bias[0] / kDeg,
                truth.bias[1] / kDeg, truth.bias[2] / kDeg);
    return 0;
}

namespace {

/* The largest rate of the log's motion over the frame's readout (rad/s, sampled every 0.5 ms), or +inf
   when the readout lies outside the log. */
double peakRate(const CameraMotion& motion, const RollingShutter& shutter)
{
    const Vec2d readout = shutter.readoutInterval();
    const Vec2d span = motion.getTimeSpan();
    if (!(readout[0] >= span[0] && readout[1] <= span[1]))
        return std::numeric_limits<double>::infinity();
    double peak = 0;
    for (double t = readout[0]; t <= readout[1]; t += 5e-4)
        peak = std::max(peak, norm(motion.angularVelocity(t)));
    return peak;
}

}  // namespace

int calibrateGyroTiming(const CliArgs& args, const std::string& defaultCameraPath)
{
    GyroRecording recording;
    GyroRecording::open(args, defaultCameraPath, UntoldReadout::Guess, recording);
    if (recording.log.empty())
        return calibrateClipTiming(args, recording);  // no frame log: the video's own times, seconds off the log's

    const int measurable = REFINE_TIME_OFFSET | REFINE_LINE_DELAY | REFINE_GYRO_BIAS;
    const double stillRate = args.num("still-rate") * kDeg, maxGap = args.num("max-still-gap");
    if (!(stillRate > 0) || !(maxGap > 0))
        throw std::runtime_error("--still-rate (deg/s) and --max-still-gap (s) must be > 0");
    const Ptr<CameraMotion> motion = recording.gyro.toMotion();
    // Stills: frames the log shows held still, on the frame log's clock.
    std::vector<int> stills, moving;
    bool covered = true;
    for (size_t i = 0; i < recording.log.size(); i++)
    {
        const double rate = peakRate(*motion, recording.shutterOf(recording.log[i]));
        covered = covered && std::isfinite(rate);
        (rate < stillRate ? stills : moving).push_back(int(i));
    }
    std::vector<std::pair<int, int>> pairs;  // (moving, still) indices into the log
    for (int m : moving)
    {
        int best = -1;
        for (int s : stills)
            if (best < 0 || std::abs(recording.log[s].frameStart - recording.log[m].frameStart) <
                                std::abs(recording.log[best].frameStart - recording.log[m].frameStart))
                best = s;
        if (best >= 0 && std::abs(recording.log[best].frameStart - recording.log[m].frameStart) <= maxGap)
            pairs.emplace_back(m, best);
    }
    if (!covered || pairs.size() < 2)
    {
        std::printf("%s: calibrating from the motion between the frames (no still frame needed)\n",
                    !covered ? "the log does not cover every frame on the frame log's clock"
                             : format("%zu still frames (rate below --still-rate %.2f deg/s), %zu moving frames within "
                                      "--max-still-gap %.2f s of one",
                                      stills.size(), stillRate / kDeg, pairs.size(), maxGap)
                                   .c_str());
        return calibrateClipTiming(args, recording);
    }
    int flags = 0;
    if (!parseRefinementList(args.str("refine", kGyroRefinement), measurable, flags) || flags == REFINE_NONE)
        throw std::runtime_error("--refine takes offset, line-delay and bias with --gyro against still frames, "
                                 "comma-separated");
    const int maxFrames = args.integer("max-frames");
    const double maxOffset = args.num("max-offset", 0.02);
    if (maxFrames < 2 || !(maxOffset > 0 && maxOffset <= 1))
        throw std::runtime_error("--max-frames must be >= 2 and --max-offset in (0, 1] s against still frames");
    const std::string out = args.str("out");
    const std::string plotPath = args.str("plot", pathStem(out) + "_objective.png");
    // At most maxFrames pairs, spread over the recording.
    std::vector<std::pair<int, int>> used;
    for (int k = 0; k < std::min(maxFrames, int(pairs.size())); k++)
        used.push_back(pairs[size_t(k * int(pairs.size()) / std::min(maxFrames, int(pairs.size())))]);

    std::vector<Mat> images;
    Mat image;
    for (FrameRecord record; recording.next(image, record);)
        images.push_back(image);
    std::vector<Mat> references, frames;
    std::vector<RollingShutter> shutters, stillShutters;
    for (const auto& p : used)
    {
        frames.push_back(images[size_t(p.first)]);
        references.push_back(images[size_t(p.second)]);
        shutters.push_back(recording.shutterOf(recording.log[size_t(p.first)]));
        stillShutters.push_back(recording.shutterOf(recording.log[size_t(p.second)]));
    }
    std::printf("calibrating over %zu moving frames, each against the nearest of %zu still frames ...\n", used.size(),
                stills.size());
    const TimingCalibration t =
        calibrateTiming(motion, recording.camera, references, frames, shutters, stillShutters, flags, maxOffset);
    t.save(out);
    const MotionCorrection& c = t.correction;
    const Vec3d bias = c.gyroBias * (1 / kDeg), biasStd = t.gyroBiasStd * (1 / kDeg);
    std::printf("clock offset      %+.4f ms (sd %.4f)\nline delay        x%.4f (sd %.4f)\n"
                "gyro bias         (%+.3f, %+.3f, %+.3f) deg/s (sd %.3f, %.3f, %.3f), beyond --gyro-bias's\n"
                "consistency       %.2f (noise units; about 1 when the model explains the frames)\n%s\nwrote %s\n",
                c.timeOffset * 1e3, t.timeOffsetStd * 1e3, c.lineDelayScale, t.lineDelayScaleStd, bias[0], bias[1],
                bias[2], biasStd[0], biasStd[1], biasStd[2], c.consistency, c.reason.c_str(), out.c_str());
    if (!args.has("no-png"))
        writeObjectivePlot(t, "Gyro timing calibration: objective around the result",
                           "objective over the gyro log's clock offset", plotPath);
    return 0;
}
