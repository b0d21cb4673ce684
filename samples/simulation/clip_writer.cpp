// SPDX-License-Identifier: Apache-2.0
// A simulated clip on disk (clip_writer.hpp): video, gyro log, camera, frame log, truth.
#include "clip_writer.hpp"

#include "atomic_file.hpp"  // samples/support
#include "recording.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

namespace dynblur_samples {

using namespace cv;
using namespace cv::dynblur;

namespace {

std::string extensionOf(const std::string& name)
{
    const size_t dot = name.find_last_of('.');
    std::string ext = dot == std::string::npos ? "" : name.substr(dot);
    for (char& c : ext)
        c = char(std::tolower(c));
    return ext;
}

/** A printf pattern with exactly one integer conversion (%d, %04d) and no other '%': an image
sequence's name. */
bool isImagePattern(const std::string& name)
{
    const size_t percent = name.find('%');
    if (percent == std::string::npos || name.find('%', percent + 1) != std::string::npos)
        return false;
    size_t i = percent + 1;
    while (i < name.size() && std::isdigit((unsigned char)name[i]))
        i++;
    return i < name.size() && name[i] == 'd';
}

/** The frames' destination: a video file (written to a temporary name, renamed at commit) or an image
sequence (each image written whole as it comes). */
class FrameSink
{
public:
    FrameSink(const std::string& path, double fps, Size size, int quality) : path_(path)
    {
        if (isImagePattern(path))
        {
            images_ = true;
            return;
        }
        const int fourcc = extensionOf(path) == ".avi" ? VideoWriter::fourcc('M', 'J', 'P', 'G')
                                                       : VideoWriter::fourcc('m', 'p', '4', 'v');
        temporary_ = temporaryPathFor(path);
        writer_.open(temporary_, fourcc, fps, size, true);
        if (!writer_.isOpened())
            CV_Error(Error::StsError, "ClipFiles.video: OpenCV cannot write a video to '" + path + "'");
        writer_.set(VIDEOWRITER_PROP_QUALITY, quality);
    }
    ~FrameSink()
    {
        if (!temporary_.empty())
        {
            writer_.release();
            std::remove(temporary_.c_str());
        }
    }

    void write(const Mat& frame, int index)
    {
        if (!images_)
        {
            writer_.write(frame);
            return;
        }
        const std::string name = format(path_.c_str(), index), temporary = temporaryPathFor(name);
        if (!imwrite(temporary, frame))
        {
            std::remove(temporary.c_str());
            CV_Error(Error::StsError, "ClipFiles.video: cannot write '" + name + "'");
        }
        renameIntoPlace(temporary, name);
    }
    void commit()
    {
        if (images_)
            return;
        writer_.release();
        renameIntoPlace(temporary_, path_);
        temporary_.clear();
    }

private:
    std::string path_, temporary_;
    VideoWriter writer_;
    bool images_ = false;
};

void writeTruth(const HandHeldSimulator& simulator, const std::string& path, const ClipFiles& files,
                const std::string& gyroName, const std::vector<FrameTruth>& frames)
{
    const HandHeldClip& c = simulator.clip();
    const std::string temporary = temporaryPathFor(path);
    {
        FileStorage fs(temporary, FileStorage::WRITE);
        if (!fs.isOpened())
            CV_Error(Error::StsError, "cannot write '" + path + "'");
        fs.writeComment("dynblur_simulate_clip: the truth of a simulated hand-held clip. SI units (s, rad, "
                        "rad/s, m, m/s); pixels. Camera clock: frame k starts (row 0's exposure) at k / fps, the "
                        "video's timestamp. Log clock: camera time + timeOffset.");
        fs << "video" << files.video << "truthFrames" << files.truth << "gyroLog" << gyroName << "gyroFormat"
           << gyroFormatName(files.gyro.format) << "camera" << "camera.xml";
        fs << "frameWidth" << c.frameSize.width << "frameHeight" << c.frameSize.height << "focalPx" << c.focalPx;
        fs << "fps" << c.fps << "frameCount" << c.frames << "exposure" << c.exposure << "readoutTime"
           << c.readoutTime << "lineDelay" << c.lineDelay();
        fs << "timeOffset" << c.gyro.timeOffset << "gyroRateHz" << c.gyro.rateHz << "gyroNoise" << c.gyro.noise
           << "gyroBias" << c.gyro.bias << "gyroRateScale" << c.gyro.rateScale;
        fs.writeComment("the file holds S^T w_camera, S the matrix of gyroAxes (w_camera = S w_sensor)");
        fs << "gyroAxes" << files.gyro.axes << "gyroTimeUnit" << files.gyro.timeUnit << "gyroRateUnit"
           << files.gyro.rateUnit;
        if (files.gyro.format == GyroFormat::SensorLogger)
        {
            fs.writeComment("Sensor Logger: time = logEpoch + log time (ns); seconds_elapsed = log time - "
                            "firstLogTime");
            fs << "logEpoch" << files.gyro.logEpoch << "firstLogTime" << simulator.gyroLog().times.front();
        }
        fs << "rotation" << "{" << "lowHz" << c.rotation.lowHz << "highHz" << c.rotation.highHz << "axisWeights"
           << c.rotation.axisWeights << "peakRate" << simulator.peakRate() << "}";
        fs << "translation" << "{" << "planeDepth" << c.translation.planeDepth;
        if (c.translation.planeDepth > 0)
            fs << "lowHz" << c.translation.lowHz << "highHz" << c.translation.highHz << "axisWeights"
               << c.translation.axisWeights << "peakSpeed" << simulator.peakSpeed();
        fs << "}";
        fs << "stretches" << "{" << "stillSeconds" << c.stretches.stillSeconds << "shakySeconds"
           << c.stretches.shakySeconds << "rampSeconds" << c.stretches.rampSeconds << "}";
        fs << "image" << (c.image.empty() ? std::string("(generated)") : c.image) << "seed" << std::to_string(c.seed)
           << "sceneMargin" << simulator.margin();
        fs.writeComment("per frame: start and reference time (camera clock, s), blur (px; rotationBlur: the "
                        "rotation's alone), still (1: the hand held still over the readout)");
        fs << "frames" << "[";
        for (const FrameTruth& f : frames)
            fs << "{:" << "index" << f.index << "frameStart" << f.shutter.frameStart << "referenceTime"
               << f.referenceTime << "blur" << f.blurPx << "rotationBlur" << f.rotationBlurPx << "still"
               << int(f.still) << "}";
        fs << "]";
    }
    renameIntoPlace(temporary, path);
}

std::string defaultGyroName(GyroFormat format)
{
    return format == GyroFormat::Gcsv ? "gyro.gcsv" : format == GyroFormat::Csv ? "gyro.csv" : "Gyroscope.csv";
}

/** Throws naming `field` unless `name` is a file name in the clip's folder: a lossless image sequence,
or (with `videos`) a video. */
void checkFrameName(const std::string& name, const char* field, bool videos)
{
    const std::string ext = extensionOf(name);
    if (name.find('/') != std::string::npos)
        CV_Error(Error::StsBadArg,
                 format("%s: '%s' must be a name in the clip's folder, without '/'", field, name.c_str()));
    if (isImagePattern(name))
    {
        if (ext != ".png" && ext != ".tif" && ext != ".tiff" && ext != ".bmp")
            CV_Error(Error::StsBadArg, format("%s: an image sequence '%s' must be .png, .tif or .bmp (lossless)", field,
                                              name.c_str()));
    }
    else if (!videos || (ext != ".avi" && ext != ".mp4"))
        CV_Error(Error::StsBadArg, format("%s: '%s' must %san image sequence such as frame_%%04d.png", field,
                                          name.c_str(), videos ? "end in .avi (MJPG) or .mp4 (mp4v), or be " : "be "));
}

}  // namespace

const char* gyroFormatName(GyroFormat format)
{
    return format == GyroFormat::Gcsv ? "gcsv" : format == GyroFormat::Csv ? "csv" : "sensor-logger";
}

GyroFormat gyroFormatFromName(const std::string& name)
{
    for (GyroFormat f : {GyroFormat::Gcsv, GyroFormat::Csv, GyroFormat::SensorLogger})
        if (name == gyroFormatName(f))
            return f;
    CV_Error(Error::StsBadArg, "gyro format '" + name + "' must be gcsv, csv or sensor-logger");
}

void writeGyroLog(const GyroLog& log, const std::string& path, const GyroFileOptions& options)
{
    const double unitLimit = 1e6;  // seconds or rad/s per unit: anything larger is a mistake
    if (!(options.timeUnit > 0 && options.timeUnit < unitLimit) ||
        !(options.rateUnit > 0 && options.rateUnit < unitLimit))
        CV_Error(Error::StsBadArg, format("writeGyroLog: timeUnit = %g and rateUnit = %g must be in (0, 1e6) (seconds "
                                          "and rad/s per unit)",
                                          options.timeUnit, options.rateUnit));
    if (!(options.logEpoch >= 0 && options.logEpoch < 9e9))  // its nanoseconds must fit in 64 bits
        CV_Error(Error::StsBadArg,
                 format("writeGyroLog: logEpoch = %g must be in [0, 9e9) (Unix seconds)", options.logEpoch));
    CV_Assert(log.rates.type() == CV_64F && log.rates.cols == 3 && log.rates.rows == int(log.times.size()));
    const Matx33d S = GyroLog::orientationMatrix(options.axes);  // names the string when it is refused
    std::ostringstream out;
    const bool sensorLogger = options.format == GyroFormat::SensorLogger;
    if (options.format == GyroFormat::Gcsv)
        out << "GYROFLOW IMU LOG\nversion,1.3\nid,dynblur_simulation\norientation," << options.axes << "\n"
            << format("tscale,%.17g\ngscale,%.17g\n", options.timeUnit, options.rateUnit) << "t,gx,gy,gz\n";
    else if (options.format == GyroFormat::Csv)
        out << format("# dynblur_simulation gyro log: t in units of %.17g s, gx,gy,gz in units of %.17g rad/s, "
                      "sensor axes %s\n", options.timeUnit, options.rateUnit, options.axes.c_str())
            << "t,gx,gy,gz\n";
    else
        out << "time,seconds_elapsed,z,y,x\n";
    const long long epochNs = (long long)std::llround(options.logEpoch * 1e9);
    for (size_t k = 0; k < log.times.size(); k++)
    {
        const double* r = log.rates.ptr<double>(int(k));
        const Vec3d w = S.t() * Vec3d(r[0], r[1], r[2]);
        const double t = log.times[k];
        if (sensorLogger)
            out << format("%lld,%.9f,%.9g,%.9g,%.9g\n", epochNs + (long long)std::llround(t * 1e9), t - log.times[0],
                          w[2], w[1], w[0]);
        else
            out << format("%.12g,%.9g,%.9g,%.9g\n", t / options.timeUnit, w[0] / options.rateUnit,
                          w[1] / options.rateUnit, w[2] / options.rateUnit);
    }
    writeTextFile(path, out.str());
}

void ClipFiles::validate() const
{
    checkFrameName(video, "ClipFiles.video", true);
    if (!truth.empty())
        checkFrameName(truth, "ClipFiles.truth", false);
    if (!(videoQuality >= 1 && videoQuality <= 100))
        CV_Error(Error::StsBadArg, format("ClipFiles.videoQuality = %d must be in [1, 100]", videoQuality));
    try
    {
        GyroLog::orientationMatrix(gyro.axes);
    }
    catch (const cv::Exception& e)
    {
        CV_Error(Error::StsBadArg, "ClipFiles.gyro.axes: " + e.err);
    }
    if (!std::isnan(frameLogLineDelay) && !(frameLogLineDelay >= 0 && frameLogLineDelay < 0.01))
        CV_Error(Error::StsBadArg, format("ClipFiles.frameLogLineDelay = %g must be in [0, 0.01) (seconds) or NaN",
                                          frameLogLineDelay));
}

WrittenClip writeClip(const HandHeldSimulator& simulator, const std::string& dir, const ClipFiles& files,
                      const std::function<void(const ClipFrame&, double)>& progress)
{
    files.validate();  // before hours of rendering
    const HandHeldClip& clip = simulator.clip();
    const std::string gyroName = files.gyroName.empty() ? defaultGyroName(files.gyro.format) : files.gyroName;
    WrittenClip written;
    FrameSink sink(dir + "/" + files.video, clip.fps, clip.frameSize, files.videoQuality);
    std::unique_ptr<FrameSink> truthSink;
    if (!files.truth.empty())
        truthSink.reset(new FrameSink(dir + "/" + files.truth, clip.fps, clip.frameSize, files.videoQuality));
    std::vector<FrameTruth> truths;
    for (int k = 0; k < clip.frames; k++)
    {
        const auto start = std::chrono::steady_clock::now();
        const ClipFrame frame = simulator.render(k);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        written.renderSeconds += seconds;
        sink.write(frame.image, k);
        if (truthSink)
            truthSink->write(frame.truth, k);
        truths.push_back(frame);
        written.minBlurPx = k == 0 ? frame.blurPx : std::min(written.minBlurPx, frame.blurPx);
        written.maxBlurPx = std::max(written.maxBlurPx, frame.blurPx);
        if (progress)
            progress(frame, seconds);
    }
    written.paths.push_back(dir + "/" + files.video);
    if (truthSink)
        written.paths.push_back(dir + "/" + files.truth);
    written.paths.push_back(dir + "/" + gyroName);
    writeGyroLog(simulator.gyroLog(), written.paths.back(), files.gyro);
    written.paths.push_back(dir + "/camera.xml");
    const std::string cameraTemporary = temporaryPathFor(written.paths.back());
    simulator.camera()->save(cameraTemporary);
    renameIntoPlace(cameraTemporary, written.paths.back());
    if (files.frameLog)
    {
        std::vector<FrameRecord> log;
        for (const FrameTruth& f : truths)
        {
            FrameRecord r;
            r.frame = f.index;
            r.frameStart = f.shutter.frameStart;
            r.exposure = f.shutter.exposure;
            r.lineDelay = std::isnan(files.frameLogLineDelay) ? f.shutter.lineDelay : files.frameLogLineDelay;
            log.push_back(r);
        }
        written.paths.push_back(dir + "/frames.csv");
        writeFrameLog(written.paths.back(), log);
    }
    written.paths.push_back(dir + "/truth.yml");
    writeTruth(simulator, written.paths.back(), files, gyroName, truths);
    sink.commit();  // last: a clip whose video is in place is complete
    return written;
}

}  // namespace dynblur_samples
