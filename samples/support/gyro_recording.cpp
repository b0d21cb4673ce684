// SPDX-License-Identifier: Apache-2.0
// A recording whose motion is a gyro log: its files opened and checked, its frames read.
#include "gyro_recording.hpp"

#include "cli_args.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

CliOptionGroup gyroLogOptions(const std::string& heading, const std::string& text)
{
    return {heading, text,
            {{"gyro", "LOG", "",
              "the recording's motion: a gyro log (Gyroflow gcsv; CSV t,gx,gy,gz in s and rad/s; Sensor Logger's "
              "Gyroscope.csv; OpenCamera Sensors' <video>_gyro.csv; another CSV described by --gyro-columns; "
              "docs/recording-format.md), same clock as the frame log up to the offset that dynblur_calibrate_timing "
              "--gyro finds"},
             {"gyro-orientation", "STR", "",
              "axis string taking the gyro's axes to the camera's (x right, y down, z forward; lowercase: inverted), "
              "replacing the gcsv file's (default: its own; Xyz for a phone app's CSV, XYZ for another CSV)"},
             {"gyro-columns", "T,X,Y,Z", "",
              "a CSV log's time and x, y, z rate columns, by header name or 1-based position (positions: the header "
              "row is optional); default: told by the header row"},
             {"gyro-time-unit", "UNIT", "", "a CSV log's time unit: s, ms, us or ns (default: the layout's)"},
             {"gyro-rate-unit", "UNIT", "", "a CSV log's rate unit: rad/s or deg/s (default: the layout's)"},
             {"gyro-gcsv-axes", "FRAME", "camera",
              "what a gcsv file's axis string maps to: camera (x right, y down, z forward) or gyroflow (Gyroflow's "
              "frame, x up, y left, z backward: gcsv written for Gyroflow by cameras, loggers and "
              "python -m dynblur.extract_gyro)"},
             {"gyro-time-origin", "S", "",
              "seconds subtracted from the log's clock, e.g. the Unix time the frame log counts from (default: 0 "
              "for a clock under 1e6 s, else the first sample's whole second)"},
             {"gyro-drop-repeats", "", "",
              "drop a sample that repeats the previous one whole (time and rates), as some phone loggers write"},
             {"gyro-bias", "B", "none",
              "estimate (from still intervals), none, or BX,BY,BZ in rad/s, camera axes, removed from the rates"},
             {"gyro-still-seconds", "S", "0.5", "shortest still interval the bias is estimated from"}}};
}

namespace {

//! The value of option `name`, one of `allowed` or empty; else std::runtime_error naming the option.
std::string oneOf(const CliArgs& args, const std::string& name, std::initializer_list<const char*> allowed)
{
    const std::string value = args.str(name);
    std::string list;
    for (const char* a : allowed)
    {
        if (value.empty() || value == a)
            return value;
        list += std::string(list.empty() ? "" : ", ") + a;
    }
    throw std::runtime_error("--" + name + " '" + value + "' is not one of " + list);
}

}  // namespace

GyroLogOptions gyroOptions(const CliArgs& args, Vec3d& bias)
{
    GyroLogOptions options;
    options.orientation = args.str("gyro-orientation");
    options.columns = args.str("gyro-columns");
    options.timeUnit = oneOf(args, "gyro-time-unit", {"s", "ms", "us", "ns"});
    options.rateUnit = oneOf(args, "gyro-rate-unit", {"rad/s", "deg/s"});
    options.gcsvAxes = oneOf(args, "gyro-gcsv-axes", {"camera", "gyroflow"});
    if (options.gcsvAxes.empty())
        throw std::runtime_error("--gyro-gcsv-axes takes camera or gyroflow");
    options.dropRepeatedSamples = args.has("gyro-drop-repeats");
    if (args.has("gyro-time-origin"))
        options.timeOrigin = args.num("gyro-time-origin");  // a finite number, or it names the option
    bias = Vec3d();
    const std::string mode = args.str("gyro-bias");
    if (mode == "estimate")
        options.estimateBias = true;
    else if (mode != "none")
    {
        std::istringstream in(mode);
        char comma1 = 0, comma2 = 0;
        if (!(in >> bias[0] >> comma1 >> bias[1] >> comma2 >> bias[2]) || comma1 != ',' || comma2 != ',' ||
            !in.eof() || !(std::abs(bias[0]) < 1 && std::abs(bias[1]) < 1 && std::abs(bias[2]) < 1))
            throw std::runtime_error("--gyro-bias takes estimate, none or BX,BY,BZ (rad/s, each within +-1)");
    }
    options.stillMinDuration = args.num("gyro-still-seconds");
    if (!(options.stillMinDuration > 0))
        throw std::runtime_error("--gyro-still-seconds must be > 0 (seconds)");
    return options;
}

void GyroRecording::open(const CliArgs& args, const std::string& defaultCameraPath, GyroRecording& r)
{
    if (!args.has("gyro") || !args.has("video") || !args.has("frames"))
        throw std::runtime_error("--gyro, --video and --frames are required for a recording whose motion is a "
                                 "gyro log");
    Vec3d bias;
    const GyroLogOptions options = gyroOptions(args, bias);
    r.log = readFrameLog(args.str("frames", ""), args.num("exposure", NAN), args.num("line-delay", NAN));
    const std::string camera = args.str("camera", "");
    r.camera = CameraModel::load(camera.empty() ? defaultCameraPath : camera);
    try
    {
        r.gyro = GyroLog::load(args.str("gyro", ""), options);
    }
    catch (const cv::Exception& e)
    {
        CV_Error(e.code, "--gyro: " + e.err);
    }
    if (bias != Vec3d())
        r.gyro.bias = bias;
    r.motion = r.gyro.toMotion();
    r.timingPath = args.declares("timing") ? args.str("timing") : "";
    const Vec2d span = r.motion->getTimeSpan();
    const int rows = r.camera->getImageSize().height;
    for (const FrameRecord& f : r.log)
    {
        const Vec2d readout = shutterOf(f, rows).readoutInterval();
        if (!(readout[0] >= span[0] && readout[1] <= span[1]))
            CV_Error(Error::StsOutOfRange,
                     format("--frames: frame %d is read over [%.6f, %.6f] s, outside the gyro log's time span "
                            "[%.6f, %.6f] s (--gyro): the log must cover every frame (same clock)%s",
                            f.frame, readout[0], readout[1], span[0], span[1],
                            r.gyro.timeOrigin == 0 ? ""
                                                   : format("; the log's times are counted from %.0f s on its clock "
                                                            "(GyroLog::timeOrigin), and so must the frames' be",
                                                            r.gyro.timeOrigin)
                                                         .c_str()));
    }
    const std::string video = args.str("video", "");
    if (video.find('%') == std::string::npos && !std::ifstream(video).good())
        CV_Error(Error::StsError, "--video: '" + video + "' does not exist");
    if (!r.video.open(video))
        CV_Error(Error::StsError, "--video: cannot open '" + video + "'");
    r.position = 0;
}

Mat GyroRecording::read(const FrameRecord& record)
{
    Mat image;
    while (position <= record.frame)
    {
        if (!video.read(image))
            CV_Error(Error::StsBadArg, format("--frames: line for frame %d, but the video ends after %d frames",
                                              record.frame, position));
        position++;
    }
    const Size size = camera->getImageSize();
    if (image.size() != size)
        CV_Error(Error::StsBadSize, format("--video: frame %d is %dx%d but the camera is %dx%d", record.frame,
                                           image.cols, image.rows, size.width, size.height));
    return image;
}

RollingShutter GyroRecording::shutterOf(const FrameRecord& record, int rows)
{
    return RollingShutter(record.frameStart, record.exposure, record.lineDelay, rows);
}

double GyroRecording::peakRate(const FrameRecord& record) const
{
    const Vec2d readout = shutterOf(record, camera->getImageSize().height).readoutInterval();
    const Vec2d span = motion->getTimeSpan();
    if (!(readout[0] >= span[0] && readout[1] <= span[1]))
        return std::numeric_limits<double>::infinity();
    double peak = 0;
    for (double t = readout[0]; t <= readout[1]; t += 5e-4)
        peak = std::max(peak, norm(motion->angularVelocity(t)));
    return peak;
}

}  // namespace dynblur_samples
