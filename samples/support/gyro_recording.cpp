// SPDX-License-Identifier: Apache-2.0
// A recording whose motion is a gyro log: its files opened and checked, its frames read.
#include "gyro_recording.hpp"

#include "atomic_file.hpp"
#include "cli_args.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
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

GyroLog loadGyroLog(const CliArgs& args)
{
    Vec3d bias;
    const GyroLogOptions options = gyroOptions(args, bias);
    GyroLog log;
    try
    {
        log = GyroLog::load(args.str("gyro", ""), options);
    }
    catch (const cv::Exception& e)
    {
        // The reader names its options as the library spells them; the command line spells them so.
        const char* const kOptionNames[][2] = {{"options.columns:", "--gyro-columns:"},
                                               {"options.timeUnit:", "--gyro-time-unit:"},
                                               {"options.rateUnit:", "--gyro-rate-unit:"},
                                               {"options.orientation:", "--gyro-orientation:"},
                                               {"options.gcsvAxes:", "--gyro-gcsv-axes:"}};
        std::string message = e.err;
        for (const auto& name : kOptionNames)
            for (size_t at = message.find(name[0]); at != std::string::npos; at = message.find(name[0], at))
                message.replace(at, std::strlen(name[0]), name[1]);
        CV_Error(e.code, "--gyro: " + message);
    }
    if (bias != Vec3d())
        log.bias = bias;
    return log;
}

void saveClipCalibration(const TimingCalibration& calibration, const ToldShutter& told, const std::string& path)
{
    const std::string extension = path.substr(pathStem(path).size());
    if (extension != ".yml" && extension != ".yaml")
        CV_Error(Error::StsBadArg, "--out: '" + path + "': a clip's timing file is YAML (.yml or .yaml)");
    const std::string temporary = temporaryPathFor(path);
    calibration.save(temporary);
    {
        // The YAML mapping TimingCalibration::save writes takes more keys at its end.
        std::ofstream out(temporary, std::ios::app);
        // Only what was told for every frame (a frame log's columns tell it frame by frame).
        out << "# the shutter the calibration was told (s): lineDelayScale scales this lineDelay\n";
        if (std::isfinite(told.exposure))
            out << format("exposure: %.17g\n", told.exposure);
        if (std::isfinite(told.lineDelay))
            out << format("lineDelay: %.17g\n", told.lineDelay);
        if (!out)
        {
            std::remove(temporary.c_str());
            CV_Error(Error::StsError, "--out: cannot write '" + path + "'");
        }
    }
    renameIntoPlace(temporary, path);
}

ToldShutter toldShutterOf(const std::string& timingPath)
{
    ToldShutter told;
    FileStorage fs(timingPath, FileStorage::READ);
    if (!fs.isOpened())
        CV_Error(Error::StsError, "--timing: cannot read '" + timingPath + "'");
    const std::string from = "--timing '" + timingPath + "'";
    if (fs["exposure"].isReal())
        told.exposure = double(fs["exposure"]), told.exposureFrom = from;
    if (fs["lineDelay"].isReal())
        told.lineDelay = double(fs["lineDelay"]), told.lineDelayFrom = from;
    return told;
}

namespace {

//! The exposure: --exposure, else the timing file's record (a frame log's column fills in later).
void tellExposure(const CliArgs& args, const ToldShutter& recorded, ToldShutter& told)
{
    if (args.has("exposure"))
    {
        told.exposure = args.num("exposure"), told.exposureFrom = "--exposure";
        if (!(told.exposure > 0 && told.exposure < 1))
            throw std::runtime_error(format("--exposure %g must be in (0, 1) s (seconds: 1/250 s is 0.004)",
                                            told.exposure));
    }
    else if (std::isfinite(recorded.exposure))
        told.exposure = recorded.exposure, told.exposureFrom = recorded.exposureFrom;
}

/* The line delay: the timing file's record (its lineDelayScale scales that one, whatever else is
   told), else --line-delay or --readout, else the gcsv log's frame_readout_time. */
void tellLineDelay(const CliArgs& args, const GyroLog& gyro, int rows, const ToldShutter& recorded, ToldShutter& told)
{
    const double option = toldLineDelay(args, rows);
    const std::string optionName = args.has("readout") ? "--readout" : "--line-delay";
    if (std::isfinite(recorded.lineDelay))
    {
        told.lineDelay = recorded.lineDelay, told.lineDelayFrom = recorded.lineDelayFrom;
        if (std::isfinite(option) && std::abs(option - recorded.lineDelay) > 1e-3 * recorded.lineDelay)
            std::fprintf(stderr, "note: %s is not used: the calibration (%s) was told a line delay of %.4g us, which "
                                 "its line delay scale corrects\n",
                         optionName.c_str(), recorded.lineDelayFrom.c_str(), recorded.lineDelay * 1e6);
    }
    else if (std::isfinite(option))
        told.lineDelay = option, told.lineDelayFrom = optionName;
    else if (std::isfinite(gyro.frameReadoutTime))
        told.lineDelay = gyro.frameReadoutTime / rows,
        told.lineDelayFrom = "--gyro's frame_readout_time";
}

}  // namespace

void GyroRecording::open(const CliArgs& args, const std::string& defaultCameraPath, UntoldReadout untold,
                         GyroRecording& r)
{
    if (!args.has("gyro") || !args.has("video"))
        throw std::runtime_error("--gyro and --video are required for a recording whose motion is a gyro log");
    r.cameraPath = args.str("camera", "");
    if (r.cameraPath.empty())
    {
        r.cameraPath = defaultCameraPath;
        std::fprintf(stderr, "note: no --camera: using the default camera '%s'\n", defaultCameraPath.c_str());
    }
    r.camera = CameraModel::load(r.cameraPath);
    const Size size = r.camera->getImageSize();
    r.gyro = loadGyroLog(args);
    r.gyroPath = args.str("gyro");
    if (r.gyro.frameReadoutDirection != READOUT_DIRECTION_UNKNOWN &&
        r.gyro.frameReadoutDirection != READOUT_TOP_TO_BOTTOM)
        CV_Error(Error::StsBadArg,
                 format("--gyro: '%s' states frame_readout_direction %d: only a readout from the top row to the "
                        "bottom one (0) is modelled; rotate the video so that its first row is read first",
                        r.gyroPath.c_str(), r.gyro.frameReadoutDirection));
    r.timingPath = args.declares("timing") ? args.str("timing") : "";
    const ToldShutter recorded = r.timingPath.empty() ? ToldShutter() : toldShutterOf(r.timingPath);
    tellExposure(args, recorded, r.told);
    tellLineDelay(args, r.gyro, size.height, recorded, r.told);

    const std::string video = args.str("video");
    if (args.has("frames"))
    {
        const std::string frames = args.str("frames");
        r.log = readFrameLog(frames, r.told.exposure, r.told.lineDelay);
        for (FrameRecord& f : r.log)  // the line delay a calibration scales wins over the frame log's
            f.lineDelay = std::isfinite(recorded.lineDelay) ? recorded.lineDelay : f.lineDelay;
        r.told.exposureFrom = std::isnan(r.told.exposure) ? "the frame log" : r.told.exposureFrom;
        r.told.lineDelayFrom = std::isnan(r.told.lineDelay) ? "the frame log" : r.told.lineDelayFrom;
        r.timeSource = "the frame log '" + frames + "'";
        r.fps = r.log.size() > 1 ? (r.log.size() - 1) / (r.log.back().frameStart - r.log.front().frameStart) : 30.0;
        openVideo(r.video_, video, "--video");
        return;
    }
    r.clip_.open(video, "--video");
    r.timeSource = r.clip_.clockText();
    const double period = r.clip_.framePeriod();
    r.fps = 1 / period;
    if (std::isnan(r.told.exposure))
        throw std::runtime_error("--exposure: the exposure of a frame is not known: give --exposure S, the shutter "
                                 "speed the clip was taken at (lock it: docs/hand-held.md), or a --timing file that "
                                 "records it");
    if (std::isnan(r.told.lineDelay))
    {
        if (untold == UntoldReadout::Refuse)
            throw std::runtime_error("--readout: the line delay is not known: give --readout S or --line-delay S, a "
                                     "--timing file from dynblur_calibrate_timing (which measures it), or a gcsv log "
                                     "that states frame_readout_time");
        r.told.lineDelay = 0.5 * period / size.height;
        r.told.lineDelayFrom = "untold: half the frame period, searched from a quarter to twice that";
    }
    if (r.clip_.frameSize() != size)
        CV_Error(Error::StsBadSize, format("--video: '%s' is %dx%d but the camera '%s' (--camera) is %dx%d: give the "
                                           "camera that took the video",
                                           video.c_str(), r.clip_.frameSize().width, r.clip_.frameSize().height,
                                           r.cameraPath.c_str(), size.width, size.height));
    if (r.told.exposure > period)
        CV_Error(Error::StsOutOfRange,
                 format("%s: the exposure %g s is longer than the frame period %g s of '%s' (%s, %.6g fps): seconds "
                        "expected (1/250 s is 0.004)",
                        r.told.exposureFrom.c_str(), r.told.exposure, period, video.c_str(), r.timeSource.c_str(),
                        r.fps));
    if ((size.height - 1) * r.told.lineDelay > period)
        CV_Error(Error::StsOutOfRange,
                 format("%s: the readout %g s (line delay %g s over %d rows) is longer than the frame period %g s of "
                        "'%s' (%.6g fps)",
                        r.told.lineDelayFrom.c_str(), (size.height - 1) * r.told.lineDelay, r.told.lineDelay,
                        size.height, period, video.c_str(), r.fps));
}

bool GyroRecording::next(Mat& image, FrameRecord& record)
{
    if (log.empty())
    {
        double seconds = 0;
        if (!clip_.read(image, seconds))
            return false;
        record.frame = clip_.framesRead() - 1;
        record.frameStart = seconds;
        record.exposure = told.exposure;
        record.lineDelay = told.lineDelay;
    }
    else
    {
        if (logNext_ == log.size())
            return false;
        record = log[logNext_++];
        while (position_ <= record.frame)
        {
            Mat frame;  // a fresh buffer: the caller may still hold the previous frame
            if (!video_.read(frame))
                CV_Error(Error::StsBadArg, format("--frames: line for frame %d, but the video ends after %d frames",
                                                  record.frame, position_));
            image = frame;
            position_++;
        }
    }
    const Size size = camera->getImageSize();
    if (image.size() != size)
        CV_Error(Error::StsBadSize, format("--video: frame %d is %dx%d but the camera '%s' (--camera) is %dx%d",
                                           record.frame, image.cols, image.rows, cameraPath.c_str(), size.width,
                                           size.height));
    return true;
}

RollingShutter GyroRecording::shutterOf(const FrameRecord& record) const
{
    return RollingShutter(record.frameStart, record.exposure, record.lineDelay, camera->getImageSize().height);
}

std::string GyroRecording::toldText() const
{
    const int rows = camera->getImageSize().height;
    const std::string exposure =
        std::isnan(told.exposure) ? "exposure from the frame log"
                                  : format("exposure %.4g ms (%s)", told.exposure * 1e3, told.exposureFrom.c_str());
    const std::string lineDelay =
        std::isnan(told.lineDelay)
            ? "line delay from the frame log"
            : format("line delay %.4g us, readout %.2f ms (%s)", told.lineDelay * 1e6, told.lineDelay * rows * 1e3,
                     told.lineDelayFrom.c_str());
    return "frame times from " + timeSource + ", " + exposure + ", " + lineDelay;
}

}  // namespace dynblur_samples
