// SPDX-License-Identifier: Apache-2.0
// dynblur_simulate_clip: renders a hand-held clip (samples/simulation/handheld_clip.hpp) and writes it
// as a device would: the video, the gyro log in a chosen layout, the camera, a frame log, and the
// truth (clip_writer.hpp).
//
//     dynblur_simulate_clip --out clip --image building.jpg --size 1920x1080 --frames 1800 --max-blur 40
//                           --still 2 --shaky 5 --gyro-rate 200 --gyro-bias 0.5,-0.3,0.2 --offset 1.2
#include "cli_args.hpp"  // samples/support
#include "clip_writer.hpp"  // samples/simulation

#include <opencv2/core/utils/filesystem.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

using namespace cv;
using namespace dynblur_samples;

namespace {

const double kDeg = CV_PI / 180;

CliOptions simulateClipOptions()
{
    const HandHeldClip d;
    CliOptions options("dynblur_simulate_clip");
    options.synopsis("--out DIR [options]")
        .description("Renders a camera held by a shaking hand: its rotation is band-limited noise (flat rate spectrum "
                     "between the band's edges, no drift), optionally with still and shaky stretches and a translation "
                     "in front of a plane; each frame is the physical forward model of a rolling (or global) shutter "
                     "with sensor noise. Writes into DIR the video (frame k at k / fps, its start on the camera's "
                     "clock), the gyro log (on a clock --offset ahead, with noise, bias and scale), camera.xml, "
                     "frames.csv and truth.yml (every true value, each frame's blur).")
        .heading("Scene and camera:")
        .option("image", "FILE", "", "the scene, scaled and cropped to cover the view (default: a generated scene)")
        .option("size", "WxH", format("%dx%d", d.frameSize.width, d.frameSize.height), "frame size, pixels")
        .option("focal", "PX", numberText(d.focalPx), "focal length, pixels")
        .option("fps", "HZ", numberText(d.fps), "frames per second")
        .option("frames", "N", std::to_string(d.frames), "number of frames")
        .option("exposure", "S", numberText(d.exposure), "exposure of a row, seconds")
        .option("readout", "S", numberText(d.readoutTime), "readout time of a frame, seconds (0: global shutter)")
        .option("full-well", "E", numberText(d.fullWellElectrons), "sensor noise: electrons at full scale (0: none)")
        .option("max-step", "PX", numberText(d.maxStepPx),
                "the renderer's time step, pixels of image motion, in (0, 1]: the time per frame grows as 1/PX")
        .heading("Motion:")
        .option("band", "LO,HI", "1,20", "the shake's band, Hz")
        .option("max-blur", "PX", "20", "the largest rotation blur of a frame, pixels (unless --peak-rate)")
        .option("peak-rate", "DEG/S", "", "the largest rotation rate instead, deg/s")
        .option("axis-weights", "WX,WY,WZ", "1,1,0.5", "relative shake about x (tilt), y (pan), z (roll)")
        .option("still", "S", "0", "still stretches of S seconds (0: shaky throughout), from the first frame on")
        .option("shaky", "S", numberText(d.stretches.shakySeconds), "shaky stretches between them, seconds")
        .option("depth", "M", "0", "a translation in front of a plane at M metres (0: rotation only)")
        .option("translation-speed", "M/S", numberText(d.translation.peakSpeed), "its peak speed, m/s")
        .option("pivot", "M", "0", "with --depth, a sweep about the arm instead: the camera turns about a pivot M "
                                   "metres behind it (the image moves about 1 + M / depth times as far as the gyro "
                                   "says)")
        .option("translation-band", "LO,HI", "1,20", "its band, Hz")
        .option("seed", "N", "1", "random seed of the motion and the noise")
        .heading("Gyro log:")
        .option("gyro-rate", "HZ", numberText(d.gyro.rateHz), "samples per second")
        .option("gyro-noise", "DEG/S", "0.1", "white noise of a sample, deg/s (standard deviation per axis)")
        .option("gyro-bias", "BX,BY,BZ", "0,0,0", "bias, deg/s, camera axes")
        .option("gyro-scale", "K", "1", "the gyro's sensitivity over the truth")
        .option("offset", "S", "0", "the log's clock minus the camera's, seconds")
        .option("gyro-lead", "S", numberText(d.gyro.leadSeconds), "the log runs S seconds before and after the frames")
        .option("gyro-format", "NAME", "gcsv", "gcsv (Gyroflow), csv (t,gx,gy,gz) or sensor-logger (Gyroscope.csv)")
        .option("gyro-axes", "STR", "XYZ",
                "the sensor's axes: letter i names the sensor axis giving camera axis i, lowercase reversed "
                "(GyroLog::orientationMatrix); a phone's rear camera held upright is Xyz")
        .option("gyro-units", "T,R", "ms,deg/s", "gcsv and csv units: time s, ms or us; rate rad/s or deg/s")
        .heading("Output:")
        .option("out", "DIR", "", "the folder (created); required")
        .option("video", "NAME", "clip.avi", ".avi (MJPG), .mp4 (mp4v) or an image sequence (frame_%04d.png)")
        .option("quality", "Q", "95", "MJPG quality, 1-100")
        .option("truth-frames", "NAME", "",
                "also each frame's truth view, the sharp view at its middle row's mid-exposure, as an image sequence "
                "(truth_%04d.png)")
        .option("stated-line-delay", "S", "", "the line delay frames.csv states, seconds (default: the true one)")
        .footer("Exit status: 0 written, 2 bad usage (the message names the option), 1 the clip cannot be made or "
                "written.");
    return options;
}

//! "A,B" or "A,B,C" as numbers; throws naming the option.
std::vector<double> numbers(const CliArgs& args, const std::string& name, size_t count)
{
    const std::string text = args.str(name);
    std::vector<double> values;
    std::stringstream fields(text);
    std::string field;
    bool numeric = !text.empty() && text.back() != ',';
    while (numeric && std::getline(fields, field, ','))
    {
        char* end = nullptr;
        values.push_back(std::strtod(field.c_str(), &end));
        numeric = !field.empty() && *end == '\0' && std::isfinite(values.back());
    }
    if (!numeric || values.size() != count)
        throw std::runtime_error("--" + name + " takes " + std::to_string(count) + " comma-separated numbers, not '" +
                                 text + "'");
    return values;
}

Vec3d vec3(const std::vector<double>& v, double scale)
{
    return Vec3d(v[0], v[1], v[2]) * scale;
}

//! The fields of the description and of the files, and the options that set them, so that a refusal names the option.
const char* const kOptionOfField[][2] = {
    {"frameSize", "--size"},      {"focalPx", "--focal"},           {"fps", "--fps"},
    {"exposure", "--exposure"},   {"readoutTime", "--readout"},     {"frames", "--frames"},
    {"rotation.lowHz", "--band"}, {"rotation.highHz", "--band"},    {"rotation.peakRate", "--peak-rate"},
    {"rotation.maxBlurPx", "--max-blur"}, {"rotation.axisWeights", "--axis-weights"},
    {"translation.planeDepth", "--depth"}, {"translation.peakSpeed", "--translation-speed"},
    {"translation.pivotDistance", "--pivot"},
    {"translation.lowHz", "--translation-band"}, {"translation.highHz", "--translation-band"},
    {"translation.axisWeights", "--axis-weights"}, {"stretches.stillSeconds", "--still"},
    {"stretches.shakySeconds", "--shaky"}, {"stretches.rampSeconds", "--shaky"}, {"gyro.rateHz", "--gyro-rate"},
    {"gyro.noise", "--gyro-noise"}, {"gyro.bias", "--gyro-bias"},   {"gyro.rateScale", "--gyro-scale"},
    {"gyro.timeOffset", "--offset"}, {"gyro.leadSeconds", "--gyro-lead"}, {"fullWellElectrons", "--full-well"},
    {"maxStepPx", "--max-step"}, {"image", "--image"}, {"ClipFiles.videoQuality", "--quality"},
    {"ClipFiles.video", "--video"}, {"ClipFiles.truth", "--truth-frames"}, {"ClipFiles.gyro.axes", "--gyro-axes"},
    {"ClipFiles.frameLogLineDelay", "--stated-line-delay"},
};

//! Whether the message names `field` with its value ("field = 3", "field[2] = 3") or as its subject ("field: ...").
bool namesField(const std::string& message, const std::string& field)
{
    for (size_t at = message.find(field); at != std::string::npos; at = message.find(field, at + 1))
    {
        const char before = at == 0 ? ' ' : message[at - 1];
        const std::string after = message.substr(at + field.size(), 3);
        if ((before == ' ' || before == '(') && (after == " = " || after[0] == '[' || after[0] == ':'))
            return true;
    }
    return false;
}

//! The message, after the options that set the fields it names (values in the description's SI units).
std::string withOption(const std::string& message)
{
    std::string options;
    for (const auto& row : kOptionOfField)
        if (namesField(message, row[0]) && options.find(row[1]) == std::string::npos)
            options += (options.empty() ? "" : ", ") + std::string(row[1]);
    const size_t at = std::min(message.find("HandHeldClip: "), message.find("ClipFiles."));
    const std::string text = at == std::string::npos ? message : message.substr(at);
    return options.empty() ? text : options + ": " + text;
}

HandHeldClip describe(const CliArgs& args)
{
    HandHeldClip clip;
    clip.image = args.str("image");
    int width = 0, height = 0;
    char rest = 0;
    if (std::sscanf(args.str("size").c_str(), "%dx%d%c", &width, &height, &rest) != 2)
        throw std::runtime_error("--size takes WxH in pixels, such as 1920x1080, not '" + args.str("size") + "'");
    clip.frameSize = Size(width, height);
    clip.focalPx = args.num("focal");
    clip.fps = args.num("fps");
    clip.frames = args.integer("frames");
    clip.exposure = args.num("exposure");
    clip.readoutTime = args.num("readout");
    clip.fullWellElectrons = args.num("full-well");
    clip.maxStepPx = args.num("max-step");
    const std::vector<double> band = numbers(args, "band", 2);
    clip.rotation.lowHz = band[0];
    clip.rotation.highHz = band[1];
    if (args.has("peak-rate"))
    {
        if (args.has("max-blur"))
            throw std::runtime_error("--peak-rate and --max-blur both scale the shake: give one");
        clip.rotation.peakRate = args.num("peak-rate") * kDeg;
    }
    else
        clip.rotation.maxBlurPx = args.num("max-blur");
    clip.rotation.axisWeights = clip.translation.axisWeights = vec3(numbers(args, "axis-weights", 3), 1.0);
    clip.stretches.stillSeconds = args.num("still");
    clip.stretches.shakySeconds = args.num("shaky");
    clip.stretches.rampSeconds = std::min(clip.stretches.rampSeconds, 0.5 * clip.stretches.shakySeconds);
    clip.translation.planeDepth = args.num("depth");
    clip.translation.peakSpeed = args.num("translation-speed");
    clip.translation.pivotDistance = args.num("pivot");
    const std::vector<double> moveBand = numbers(args, "translation-band", 2);
    clip.translation.lowHz = moveBand[0];
    clip.translation.highHz = moveBand[1];
    clip.gyro.rateHz = args.num("gyro-rate");
    clip.gyro.noise = args.num("gyro-noise") * kDeg;
    clip.gyro.bias = vec3(numbers(args, "gyro-bias", 3), kDeg);
    clip.gyro.rateScale = args.num("gyro-scale");
    clip.gyro.timeOffset = args.num("offset");
    clip.gyro.leadSeconds = args.num("gyro-lead");
    const double seed = args.num("seed");
    if (!(seed >= 0 && seed < 4e9 && seed == std::floor(seed)))
        throw std::runtime_error("--seed must be an integer in [0, 4e9)");
    clip.seed = uint64(seed);
    return clip;
}

ClipFiles files(const CliArgs& args)
{
    ClipFiles files;
    files.video = args.str("video");
    files.truth = args.str("truth-frames");
    files.videoQuality = args.integer("quality");
    try
    {
        files.gyro.format = gyroFormatFromName(args.str("gyro-format"));
    }
    catch (const cv::Exception& e)
    {
        throw std::runtime_error("--gyro-format: " + e.err);
    }
    files.gyro.axes = args.str("gyro-axes");
    const std::string units = args.str("gyro-units");
    const size_t comma = units.find(',');
    const std::string time = units.substr(0, comma), rate = comma == std::string::npos ? "" : units.substr(comma + 1);
    files.gyro.timeUnit = time == "s" ? 1.0 : time == "ms" ? 1e-3 : time == "us" ? 1e-6 : 0.0;
    files.gyro.rateUnit = rate == "rad/s" ? 1.0 : rate == "deg/s" ? kDeg : 0.0;
    if (files.gyro.timeUnit == 0 || files.gyro.rateUnit == 0)
        throw std::runtime_error("--gyro-units takes T,R with T s, ms or us and R rad/s or deg/s, not '" + units + "'");
    if (args.has("stated-line-delay"))
        files.frameLogLineDelay = args.num("stated-line-delay");
    return files;
}

int usageError(const std::string& message)
{
    std::cerr << "error: " << message << "\n(see dynblur_simulate_clip --help)\n";
    return 2;
}

}  // namespace

int main(int argc, char** argv)
{
    HandHeldClip clip;
    ClipFiles output;
    std::string dir;
    try
    {
        const CliOptions options = simulateClipOptions();
        const CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        dir = args.str("out");
        if (dir.empty())
            return usageError("--out DIR is required");
        clip = describe(args);
        output = files(args);
        clip.validate();
        output.validate();
    }
    catch (const std::runtime_error& e)
    {
        return usageError(e.what());
    }
    catch (const cv::Exception& e)
    {
        return usageError(withOption(e.err));
    }
    try
    {
        const HandHeldSimulator simulator(clip);
        std::printf("motion: peak rate %.1f deg/s, the view strays up to %d px (the scene's margin)\n",
                    simulator.peakRate() / kDeg, simulator.margin());
        if (!utils::fs::createDirectories(dir))
            CV_Error(Error::StsError, "--out: cannot create the folder '" + dir + "'");
        const WrittenClip written = writeClip(simulator, dir, output, [&](const ClipFrame& f, double seconds) {
            std::printf("\rframe %d of %d: blur %.1f px, rendered in %.2f s", f.index + 1, clip.frames, f.blurPx,
                        seconds);
            std::fflush(stdout);
        });
        std::printf("\nwrote to %s:", dir.c_str());
        for (const std::string& path : written.paths)
            std::printf(" %s", path.substr(dir.size() + 1).c_str());
        std::printf("\nblur %.2f to %.2f px per frame; %.3f s of rendering per frame\n", written.minBlurPx,
                    written.maxBlurPx, written.renderSeconds / clip.frames);
        return 0;
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "\nerror: " << withOption(e.err) << "\n";
        return 1;
    }
}
