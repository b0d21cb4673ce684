// SPDX-License-Identifier: Apache-2.0
// dynblur_record: records what the other programs read (docs/recording-format.md): the frames of a
// camera with their timestamps, and the actuator's commands on the same clock, into one folder.
//
//     dynblur_record --source 0 --exposure 0.008 --line-delay 34.7e-6 --camera camera.xml --plant plant.yml
//                    --bus tcp://127.0.0.1:1502 --moves 10,0,10,0 --still 1 --out rec
//
// The camera is anything cv::VideoCapture opens: a device index, a GStreamer pipeline, or a video
// file or image sequence played at its frame rate as a virtual camera. Both logs are on the host's
// steady clock (seconds from the recording's start): a V4L2 buffer's timestamp where the backend
// gives one on that clock, else the time the frame was grabbed; the constant part of the camera's
// latency is what dynblur_calibrate_timing finds.
#include "atomic_file.hpp"  // samples/support
#include "cli_args.hpp"
#include "plant_file.hpp"
#include "recording.hpp"

#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/dynblur.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

using namespace cv;
using namespace cv::dynblur;
using namespace dynblur_samples;

static CliOptions recordOptions()
{
    CliOptions options("dynblur_record");
    options.synopsis("--source SRC --exposure S --line-delay S --out DIR [options]")
        .description("Records a camera's frames with their timestamps and the actuator's commands, on one clock, as a "
                     "recording folder (frame_%04d.png, frames.csv, commands.csv, camera.xml, plant.yml or mount.yml) that "
                     "dynblur_calibrate_timing and dynblur_restore_video read (docs/recording-format.md).")
        .option("source", "SRC", "",
                "a device index (0), a GStreamer pipeline (with '!'), or a video file or image sequence "
                "(frame_%04d.png) played at its rate as a virtual camera")
        .option("fps", "F", "", "frame rate asked of a device, or a virtual camera's (default: the source's, else 30)")
        .option("exposure", "S", "",
                "exposure of one row, seconds; a device is asked to lock it (the tool says when its backend cannot: "
                "lock it outside, see docs/your-rig.md)")
        .option("line-delay", "S", "",
                "row-to-row readout delay, seconds (0: global shutter; docs/your-rig.md measures it)")
        .option("frames", "N", "", "stop after N frames (default: when the moves are done, or the source ends)")
        .option("camera", "FILE.xml", "", "the camera (dynblur_calibrate_camera), copied into the folder")
        .option("plant", "FILE.yml", "", "the plant (dynblur_identify_plant), copied into the folder; plans the moves")
        .option("mount", "FILE.yml", "",
                "a mount (Mount::save, dynblur_identify_plant --mount) in place of --plant: --commands logs every "
                "axis's levels (t,level0,level1,...); copied into the folder as mount.yml")
        .option("out", "DIR", "", "the recording folder to write")
        .heading("Actuator (one of):")
        .option("bus", "URI", "",
                "drive the controller (tcp://HOST:PORT or rtu:DEVICE?baud=..&slave=..) with --moves")
        .option("moves", "LIST", "",
                "target angles, degrees, comma-separated: each planned from the last (the first from the level the "
                "actuators hold), started after --still seconds of rest")
        .option("still", "S", "1",
                "rest before the first move, between moves and after the last, seconds: the still frames each moving "
                "frame is refined against")
        .option("commands", "FILE", "",
                "a command log (t,level) a script wrote while the camera ran, on the same clock as this recording "
                "(seconds from its start); copied into the folder")
        .footer("Exit status: 0 recorded, 1 the camera, the bus or a file failed (the message says which), 2 bad usage.");
    return options;
}

static double steadyNow()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

//! The source as cv::VideoCapture opens it; `isVirtual` for a file or an image sequence.
static void openSource(const std::string& source, VideoCapture& capture, bool& isVirtual)
{
    const bool isIndex = !source.empty() && source.find_first_not_of("0123456789") == std::string::npos;
    const bool isPipeline = source.find('!') != std::string::npos;
    isVirtual = !isIndex && !isPipeline;
    if (isVirtual && source.find('%') == std::string::npos && !std::ifstream(source).good())
        CV_Error(Error::StsError, "--source: the file '" + source + "' does not exist");
    const bool opened = isIndex ? capture.open(std::stoi(source)) :
                        isPipeline ? capture.open(source, CAP_GSTREAMER) : capture.open(source);
    if (!opened)
        CV_Error(Error::StsError, "--source: cannot open '" + source + "' as a camera (" +
                                      (isIndex ? "device index" : isPipeline ? "GStreamer pipeline" : "video file or image sequence") +
                                      ")");
}

/* Asks a device for a fixed exposure. V4L2 takes manual mode as 1 and the exposure in 100 us units;
   other backends are asked in seconds. Says what happened: an exposure left automatic changes the
   blur from frame to frame. */
static void lockExposure(VideoCapture& capture, double exposure)
{
    const std::string backend = capture.getBackendName();
    const bool v4l2 = backend == "V4L2";
    const bool manual = capture.set(CAP_PROP_AUTO_EXPOSURE, v4l2 ? 1 : 0.25);
    const bool set = capture.set(CAP_PROP_EXPOSURE, v4l2 ? exposure / 100e-6 : exposure);
    if (manual && set)
        std::printf("exposure locked through %s: asked %.6g s, the device reports %g (%s)\n", backend.c_str(), exposure,
                    capture.get(CAP_PROP_EXPOSURE), v4l2 ? "units of 100 us" : "backend units");
    else
        std::printf("note: the %s backend cannot lock the exposure (%s refused): lock it outside this tool "
                    "(v4l2-ctl, docs/your-rig.md); the frame log says --exposure %.6g s\n",
                    backend.c_str(), manual ? "CAP_PROP_EXPOSURE" : "CAP_PROP_AUTO_EXPOSURE", exposure);
}

int main(int argc, char** argv)
{
    int stage = 2;  // the exit status of an error: 2 while the arguments are read, 1 after
    try
    {
        const CliOptions options = recordOptions();
        const CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        for (const char* required : {"source", "exposure", "line-delay", "out"})
            if (!args.has(required))
                throw std::runtime_error(std::string("--") + required + " is required");
        if (args.has("bus") != args.has("moves"))
            throw std::runtime_error("--bus and --moves go together (the moves are driven over the bus)");
        if (args.has("mount") && (args.has("plant") || args.has("bus")))
            throw std::runtime_error("--mount records the axes of a command log a script wrote (--commands): give it "
                                     "without --plant and --bus");
        if (args.has("commands") && args.has("bus"))
            throw std::runtime_error("give --commands (a script drove the actuator) or --bus with --moves, not both");
        const double exposure = args.num("exposure"), lineDelay = args.num("line-delay");
        const double still = args.num("still");
        const int maxFrames = args.integer("frames", 0);
        if (!(exposure > 0 && exposure <= 1))
            throw std::runtime_error(format("--exposure %g must be in (0, 1] seconds (8 ms is 0.008)", exposure));
        if (!(lineDelay >= 0 && lineDelay < 1e-3))
            throw std::runtime_error(format("--line-delay %g must be in [0, 0.001) seconds (34.7 us is 34.7e-6)", lineDelay));
        if (!(still >= 0))
            throw std::runtime_error("--still must be >= 0 seconds");
        const std::vector<double> moves = args.has("moves") ? args.numbers("moves") : std::vector<double>();
        if (!args.has("bus") && !args.has("commands") && maxFrames <= 0)
            std::printf("note: no actuator (--bus with --moves, or --commands): recording until the source ends\n");
        const std::string out = args.str("out");
        stage = 1;

        PlantFile plant;
        plant.plant = Plant::create(14.4, 0.12, CV_PI / 180);
        if (args.has("plant"))
            plant = loadPlantFile(args.str("plant"));
        else if (!moves.empty())
            std::printf("note: no --plant: planning the moves for the seed's plant (14.4 Hz, zeta 0.12, 1 deg per level)\n");
        const Ptr<Mount> mount = args.has("mount") ? Mount::load(args.str("mount")) : Ptr<Mount>();
        CommandLog commands;
        if (args.has("commands"))
            commands = readCommandLog(args.str("commands"));
        const int axes = mount ? mount->getAxisCount() : 1;
        if (args.has("commands") && commands.axisCount() != axes)
            CV_Error(Error::StsBadArg,
                     format("--commands: '%s' logs %d axis(es) but %s: a mount's log has one level column per axis "
                            "(t,level0,level1,...), one axis's t,level (docs/recording-format.md)",
                            args.str("commands").c_str(), commands.axisCount(),
                            mount ? format("the mount '%s' (--mount) has %d", args.str("mount").c_str(), axes).c_str()
                                  : "no --mount was given (one axis)"));

        // The actuator first: a bus that does not answer must not leave a half-made recording.
        Ptr<ActuatorDriver> driver;
        Ptr<SwitchPlanner> planner;
        double startAngle = 0;  // radians
        if (args.has("bus"))
        {
            driver = ActuatorDriver::create(ActuatorBus::create(args.str("bus")));
            const ActuatorInfo info = driver->connect();
            planner = SwitchPlanner::create(plant.plant, std::min(plant.maxLevel, info.maxLevel), PLAN_ROBUST,
                                            std::max(0.002, info.minDwell));
            // The moves start where the actuators rest; each is planned (and its reach checked) before
            // the camera runs.
            const int restLevel = driver->status().currentLevel;
            startAngle = plant.plant->restingAngle(restLevel);
            for (double target : moves)
                planner->plan(startAngle, target * CV_PI / 180, 0.0);
            commands.times = {0.0};
            commands.levels = {{restLevel}};
            std::printf("actuators at level %d (%.3g deg)\n", restLevel, startAngle * 180 / CV_PI);
        }

        VideoCapture capture;
        bool isVirtual = false;
        openSource(args.str("source"), capture, isVirtual);
        const double sourceFps = capture.get(CAP_PROP_FPS);
        double fps = args.num("fps", sourceFps > 0 && sourceFps < 1000 ? sourceFps : 30.0);
        if (!(fps > 0 && fps < 1000))
            throw std::runtime_error("--fps must be in (0, 1000) frames per second");
        if (isVirtual)
            std::printf("virtual camera '%s' at %.3g fps: frames are timed by their index, exposure as --exposure says\n",
                        args.str("source").c_str(), fps);
        else
        {
            if (args.has("fps"))
                capture.set(CAP_PROP_FPS, fps);
            lockExposure(capture, exposure);
        }
        utils::fs::createDirectories(out);

        std::vector<FrameRecord> log;
        const double origin = steadyNow();
        double nextMove = still, angle = startAngle, lastEnd = 0;
        size_t moveIndex = 0;
        bool hostClockNoted = false;
        Mat image;
        Size size;
        for (int frame = 0; maxFrames <= 0 || frame < maxFrames; frame++)
        {
            double stamp;  // seconds from the origin
            if (isVirtual)
            {
                stamp = frame / fps;  // played at its rate: frame i is due i/fps after the start
                const double wait = origin + stamp - steadyNow();
                if (wait > 0)
                    std::this_thread::sleep_for(std::chrono::duration<double>(wait));
                if (!capture.read(image))
                    break;
            }
            else
            {
                if (!capture.grab())
                    break;
                const double grabbed = steadyNow();
                const double buffer = capture.get(CAP_PROP_POS_MSEC) * 1e-3;  // V4L2: CLOCK_MONOTONIC, as steady_clock
                const bool sameClock = buffer > 0 && std::abs(buffer - grabbed) < 1.0;
                if (!sameClock && !hostClockNoted)
                    std::printf("note: the backend gives no timestamp on the host's clock: frames are timed when grabbed\n");
                hostClockNoted = hostClockNoted || !sameClock;
                stamp = (sameClock ? buffer : grabbed) - origin;
                capture.retrieve(image);
            }
            size = image.size();
            if (!imwrite(format("%s/frame_%04d.png", out.c_str(), frame), image))
                CV_Error(Error::StsError, "--out: cannot write frames into '" + out + "'");
            FrameRecord record;
            record.frame = frame;
            record.frameStart = stamp;
            record.exposure = exposure;
            record.lineDelay = lineDelay;
            log.push_back(record);

            const double now = steadyNow() - origin;
            if (driver && moveIndex < moves.size() && now >= nextMove)
            {
                const double target = moves[moveIndex++] * CV_PI / 180;
                const SwitchSchedule move = planner->plan(angle, target, 0.0);
                angle = target;
                if (!move.times.empty())
                {
                    driver->upload(move);
                    const StartReport started = driver->start();
                    for (size_t i = 0; i < move.times.size(); i++)
                    {
                        commands.times.push_back(started.hostStartTime + (move.times[i] - started.scheduleOrigin) - origin);
                        commands.levels[0].push_back(move.levels[i]);
                    }
                    std::printf("move %zu to %.3g deg started at %.3f s (%zu switches, settles in %.0f ms)\n", moveIndex,
                                target * 180 / CV_PI, commands.times[commands.times.size() - move.times.size()],
                                move.times.size(), move.settleTime * 1e3);
                    nextMove = commands.times.back() + move.settleTime + still;
                }
                lastEnd = nextMove;
            }
            if (driver && maxFrames <= 0 && moveIndex == moves.size() && now >= lastEnd)
                break;  // the still after the last move is recorded
        }
        if (log.size() < 2)
            CV_Error(Error::StsError, format("--source: the camera gave %zu frame(s); a recording needs more", log.size()));
        if (driver && moveIndex < moves.size())
            std::printf("note: the source ended before move %zu of %zu\n", moveIndex + 1, moves.size());
        writeFrameLog(out + "/frames.csv", log);
        if (commands.times.empty())
        {
            commands.times = {0.0};
            commands.levels.assign(size_t(axes), std::vector<int>{0});
            std::printf("note: no actuator: commands.csv holds the rest level 0 only\n");
        }
        writeCommandLog(out + "/commands.csv", commands);
        if (args.has("camera"))
            CameraModel::load(args.str("camera"))->save(out + "/camera.xml");
        if (mount)
            mount->save(out + "/mount.yml");
        if (args.has("plant"))
            savePlantFile(out + "/plant.yml", *plant.plant, plant.maxLevel, "copied by dynblur_record from " + args.str("plant"));
        std::printf("recorded %zu frames (%.2f s, %dx%d) and %zu commands into %s\n", log.size(),
                    log.back().frameStart - log.front().frameStart, size.width, size.height, commands.times.size(), out.c_str());
        return 0;
    }
    catch (const std::runtime_error& e)
    {
        std::cerr << "error: " << e.what() << "\n(see dynblur_record --help)\n";
        return 2;
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "error: " << e.err << "\n";
        return stage;
    }
}
