// dynblur_visual_servo — the system's story in one loop: a camera on the tilt positioner looks at a
// textured plane carrying an AprilTag (36h11, id 0) that starts 8° off the image centre. Each cycle
//   detect the tag in the latest RESTORED frame (vpDetectorAprilTag)
//   → vpServo (image-based, point feature of the tag centre, eye-in-hand, only ωx) → angle increment
//   → SwitchPlanner: an integer-level saccade without residual vibration
//   → plant directly, or --bus: upload + start on the actuator controller (ActuatorDriver)
//   → the rolling-shutter camera keeps taking frames while the mechanism moves: each is classified
//     (windows I–IV), restored with DynamicDeblurrer, and searched for the tag raw and restored.
// The loop itself is runVisualServo (samples/common/visual_servo.cpp), shared with the tests.
//
//   dynblur_visual_servo --cycles 10 --out servo_out
//   dynblur_actuator_sim --tcp-port 5020 --max-level 400 &
//   dynblur_visual_servo --bus tcp://127.0.0.1:5020
#include "cli_args.hpp"
#include "visual_servo.hpp"

#include <cstdio>
#include <exception>
#include <iostream>

using namespace cv::dynblur;
using namespace dynblur_samples;

namespace {

const char* const kHelp =
    "Usage: dynblur_visual_servo [options]\n"
    "Closes the loop camera -> restoration -> AprilTag -> vpServo -> planner -> positioner (headless).\n"
    "  --cycles N            servo cycles (default 10)\n"
    "  --frames-per-cycle N  frames taken during one cycle at 30 fps (default 3)\n"
    "  --start-deg D         initial tilt error of the tag, degrees (default 8)\n"
    "  --lambda L            vpServo gain per cycle, in (0, 2) (default 1: one-step correction)\n"
    "  --mode fast|robust    planner mode (default robust; fast tries every level, ~10 s per plan at 400 levels)\n"
    "  --gain-deg G          positioner gain, degrees per level (default 0.05: 0.26 px at fx 300)\n"
    "  --max-level N         largest |level| (default 400)\n"
    "  --model rows|tiles    PSF model of the restoration (default rows)\n"
    "  --iterations N        Richardson-Lucy iterations (default 20)\n"
    "  --tag-cell PX         tag cell size on the plane, pixels (default 4: a 32 px black square)\n"
    "  --latency-ms MS       from the end of the measured frame's readout to the saccade start (default 4)\n"
    "  --bus tcp://HOST:PORT drive the actuator controller (e.g. dynblur_actuator_sim) instead of the plant\n"
    "  --out DIR             output folder: cycles.csv, frames.csv, error.png, strip.png (default servo_out)\n"
    "  --help                this text\n";

const char* windowName(int window)
{
    static const char* names[] = {"?", "I", "II", "III", "IV"};
    return names[window >= 1 && window <= 4 ? window : 0];
}

}  // namespace

int main(int argc, char** argv)
{
    ServoConfig config;
    std::string outDir;
    try
    {
        const CliArgs args(argc, argv,
                           {"cycles", "frames-per-cycle", "start-deg", "lambda", "mode", "gain-deg", "max-level", "model",
                            "iterations", "bus", "out", "tag-cell", "latency-ms"},
                           {"help"});
        if (args.has("help"))
        {
            std::cout << kHelp;
            return 0;
        }
        config.cycles = args.integer("cycles", config.cycles);
        config.framesPerCycle = args.integer("frames-per-cycle", config.framesPerCycle);
        config.startOffsetDeg = args.num("start-deg", config.startOffsetDeg);
        config.lambda = args.num("lambda", config.lambda);
        config.gainDegPerLevel = args.num("gain-deg", config.gainDegPerLevel);
        config.maxLevel = args.integer("max-level", config.maxLevel);
        config.rlIterations = args.integer("iterations", config.rlIterations);
        config.busUri = args.str("bus", "");
        config.tagCellPx = args.integer("tag-cell", config.tagCellPx);
        config.latency = 1e-3 * args.num("latency-ms", 1e3 * config.latency);
        if (config.tagCellPx < 2 || config.tagCellPx > 12 || !(config.latency >= 0 && config.latency < 1))
            throw std::runtime_error("--tag-cell must be in [2, 12] px and --latency-ms in [0, 1000)");
        outDir = args.str("out", "servo_out");
        const std::string mode = args.str("mode", "robust"), model = args.str("model", "rows");
        if (mode != "fast" && mode != "robust")
            throw std::runtime_error("--mode must be fast or robust (got '" + mode + "')");
        if (model != "rows" && model != "tiles")
            throw std::runtime_error("--model must be rows or tiles (got '" + model + "')");
        config.plannerMode = mode == "fast" ? PLAN_FAST : PLAN_ROBUST;
        config.psfModel = model == "rows" ? PSF_ROWS : PSF_TILES;
        if (config.cycles < 1 || config.cycles > 1000)
            throw std::runtime_error("--cycles must be in [1, 1000]");
        if (config.framesPerCycle < 1 || config.framesPerCycle > 30)
            throw std::runtime_error("--frames-per-cycle must be in [1, 30]");
        if (!(config.lambda > 0 && config.lambda < 2))
            throw std::runtime_error("--lambda must be in (0, 2)");
        if (!(config.gainDegPerLevel > 0) || config.maxLevel < 1 || config.rlIterations < 1)
            throw std::runtime_error("--gain-deg, --max-level and --iterations must be positive");
        if (!(std::abs(config.startOffsetDeg) < config.maxLevel * config.gainDegPerLevel))
            throw std::runtime_error("--start-deg must be within the positioner's range (max-level x gain-deg)");
        if (!config.busUri.empty() && config.busUri.rfind("tcp://", 0) != 0 && config.busUri.rfind("rtu:", 0) != 0)
            throw std::runtime_error("--bus must be tcp://HOST:PORT or rtu:DEVICE (got '" + config.busUri + "')");
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "dynblur_visual_servo: %s\n", e.what());
        return 2;
    }

    try
    {
        std::printf("[servo] tag %.1f deg off; positioner %.3f deg/level, max level %d; %s; %d frames/cycle at 30 fps\n",
                    config.startOffsetDeg, config.gainDegPerLevel, config.maxLevel,
                    config.busUri.empty() ? "plant driven directly" : ("bus " + config.busUri).c_str(),
                    config.framesPerCycle);
        const ServoReport report = runVisualServo(config, [](const ServoReport& r) {
            const ServoCycle& c = r.cycles.back();
            std::printf("[servo] cycle %2d: error %6.2f px (true %6.2f), dtheta %+7.3f deg, level %4d -> %4d, frames:",
                        c.cycle, c.measuredErrorPx, c.trueErrorPx, c.deltaDeg, c.fromLevel, c.toLevel);
            for (const ServoFrame& f : r.frames)
                if (f.cycle == c.cycle)
                    std::printf(" %s[raw %s, restored %s]", windowName(f.window), f.raw.found ? "tag" : "-",
                                f.restored.found ? "tag" : "-");
            std::printf("\n");
            std::fflush(stdout);
        });
        writeServoOutputs(report, outDir);

        std::printf("[servo] error <= 1 px from cycle %d on\n", report.cyclesToWithin(1.0));
        for (int window : {int(EXPOSURE_I), int(EXPOSURE_II), int(EXPOSURE_III), 0})
        {
            int frames = 0, raw = 0, restored = 0;
            report.detectionCounts(window, frames, raw, restored);
            std::printf("[servo] window %-6s %2d frames: tag found raw %2d, restored %2d\n",
                        window ? windowName(window) : "I-III", frames, raw, restored);
        }
        std::printf("[servo] restoration %.0f ms per frame (mean); wrote %s/{cycles.csv,frames.csv,error.png,strip.png}\n",
                    1e3 * report.meanRestoreSec(), outDir.c_str());
        return report.cyclesToWithin(1.0) >= 0 ? 0 : 1;
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "dynblur_visual_servo: %s\n", e.what());
        return 1;
    }
}
