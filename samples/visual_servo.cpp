// SPDX-License-Identifier: Apache-2.0
// dynblur_visual_servo — the system's story in one loop: a camera on the tilt positioner looks at a
// textured plane carrying a target (a column of three AprilTags 36h11) that starts 8° off the image
// centre (--scenario step), or that jumps to a new place 3..6° away every few cycles (--scenario
// track). Each cycle
//   detect the target in the latest RESTORED frame (vpDetectorAprilTag)
//   → vpServo (image-based, point feature of the target's centre, eye-in-hand, only ωx) → angle increment
//   → SwitchPlanner: an integer-level saccade without residual vibration
//   → plant directly, or --bus: upload + start on the actuator controller (ActuatorDriver)
//   → the rolling-shutter camera keeps taking frames while the mechanism moves: each is classified
//     (windows I–IV), restored with DynamicDeblurrer, and searched for the target raw and restored.
// The loop itself is runVisualServo (samples/simulation/visual_servo.cpp), shared with the tests.
//
//   dynblur_visual_servo --cycles 10 --out servo_out
//   dynblur_visual_servo --scenario track --targets 16
//   dynblur_actuator_sim --tcp-port 5020 --max-level 400 &
//   dynblur_visual_servo --bus tcp://127.0.0.1:5020
#include "cli_args.hpp"
#include "restoration_options.hpp"
#include "frame_timing.hpp"
#include "visual_servo.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

using namespace cv::dynblur;
using namespace dynblur_samples;

namespace {

// The track scenario's first place, degrees off (its later places are jumps from there).
const double kTrackStartDeg = 5.0;

CliOptions servoOptions()
{
    const ServoConfig config;
    CliOptions options("dynblur_visual_servo");
    options.synopsis("[options]")
        .description("Closes the loop camera -> restoration -> AprilTag -> vpServo -> planner -> positioner (headless).")
        .option("scenario", "step|track", "step",
                "step: the target sits --start-deg off and stays; track: it jumps to --targets places, --jump-deg each "
                "way, --cycles-per-target cycles each, and the saccade's phase against the frames varies (--jitter-ms)")
        .option("cycles", "N", std::to_string(config.cycles), "servo cycles, step scenario")
        .option("targets", "N", "16", "places the target visits, track scenario")
        .option("cycles-per-target", "N", "3", "cycles per place, track scenario")
        .option("jump-deg", "MIN,MAX", "3,6", "size of each jump, degrees, track scenario (at most 12)")
        .option("seed", "N", "1", "track scenario: places, jitter and sensor noise")
        .option("frames-per-cycle", "N", std::to_string(config.framesPerCycle), "frames taken during one cycle at 30 fps")
        .option("start-deg", "D", "",
                "initial tilt error of the target, degrees (default " + numberText(config.startOffsetDeg) +
                    " for step, " + numberText(kTrackStartDeg) + " for track)")
        .option("lambda", "L", numberText(config.lambda), "vpServo gain per cycle, in (0, 2) (1: one-step correction)")
        .option("deadband-px", "PX", numberText(config.deadbandPx),
                "hold still while the measured error is at most PX, in [0, 5]")
        .option("mode", "fast|robust", "robust", "planner mode (fast tries every level, ~10 s per plan at 400 levels)")
        .option("gain-deg", "G", numberText(config.gainDegPerLevel),
                "positioner gain, degrees per level (0.05: 0.26 px at fx 300)")
        .option("max-level", "N", std::to_string(config.maxLevel), "largest |level|")
        .option(modelOption("rows"))
        .option("iterations", "N", std::to_string(config.rlIterations), "Richardson-Lucy iterations")
        .option("tags", "N", std::to_string(config.targetTags),
                "AprilTags in the target, a column of ids 0..N-1, N in [1, 3]")
        .option("tag-cell", "PX", std::to_string(config.tagCellPx),
                "tag cell size on the plane, pixels, in [2, 12] (4: a 32 px black square); the target must fit in "
                "half the frame's height (120 px)")
        .option("exposure-ms", "MS", numberText(1e3 * config.exposure), "exposure of each row, in [0.1, 33.3]")
        .option("latency-ms", "MS", numberText(1e3 * config.latency),
                "from the end of the measured frame's readout to the saccade start")
        .option("jitter-ms", "MS", "",
                "plus a random 0..MS per cycle (default " + numberText(1e3 * config.latencyJitter) +
                    " for step, one frame period for track)")
        .option("bus", "tcp://HOST:PORT", "", "drive the actuator controller (e.g. dynblur_actuator_sim) instead of the plant")
        .option("true-hz-scale", "X", numberText(config.trueFreqScale),
                "hardware that drifted from its model: the positioner moves with X times the natural frequency the "
                "loop plans with (with --bus, give the simulator the same option)")
        .option("true-zeta-scale", "X", numberText(config.trueDampingScale),
                "the same for the damping ratio")
        .option("clock-offset-ms", "MS", numberText(1e3 * config.clockOffset),
                "the camera's frames start MS later than their timestamps")
        .flag("no-refine", "restore with the nominal model (by default each moving frame is refined against the last "
                           "still frame)")
        .option("out", "DIR", "servo_out", "output folder: cycles.csv, frames.csv, error.png, strip.png, detection.png");
    return options;
}

ServoConfig parseOptions(int argc, char** argv, std::string& outDir)
{
    const CliOptions options = servoOptions();
    const CliArgs args = options.parse(argc, argv);
    if (options.printHelp(args))
        std::exit(0);
    const std::string scenario = args.str("scenario");
    if (scenario != "step" && scenario != "track")
        throw std::runtime_error("--scenario must be step or track (got '" + scenario + "')");
    const bool track = scenario == "track";
    for (const char* name : track ? std::vector<const char*>{"cycles"}
                                  : std::vector<const char*>{"targets", "cycles-per-target", "seed", "jump-deg"})
        if (args.has(name))
            throw std::runtime_error(std::string("--") + name + " is for --scenario " + (track ? "step" : "track"));

    ServoConfig config;
    if (track)
    {
        const int targets = args.integer("targets"), perTarget = args.integer("cycles-per-target");
        const int seed = args.integer("seed");
        if (targets < 1 || targets > 200 || perTarget < 1 || perTarget > 20 || seed < 0)
            throw std::runtime_error("--targets must be in [1, 200], --cycles-per-target in [1, 20], --seed >= 0");
        const double startDeg = args.num("start-deg", kTrackStartDeg);
        if (!(std::abs(startDeg) <= 12))
            throw std::runtime_error("--start-deg must be within +-12 deg for --scenario track");
        double minJump = 0, maxJump = 0;
        if (std::sscanf(args.str("jump-deg").c_str(), "%lf,%lf", &minJump, &maxJump) != 2 ||
            !(0 <= minJump && minJump <= maxJump && maxJump <= 12))
            throw std::runtime_error("--jump-deg must be MIN,MAX with 0 <= MIN <= MAX <= 12 (got '" +
                                     args.str("jump-deg") + "')");
        config = trackingScenario(targets, perTarget, static_cast<unsigned>(seed), startDeg, minJump, maxJump);
    }
    else
    {
        config.startOffsetDeg = args.num("start-deg", config.startOffsetDeg);
    }
    config.cycles = args.integer("cycles", config.cycles);
    config.framesPerCycle = args.integer("frames-per-cycle");
    config.lambda = args.num("lambda");
    config.gainDegPerLevel = args.num("gain-deg");
    config.maxLevel = args.integer("max-level");
    config.rlIterations = args.integer("iterations");
    config.busUri = args.str("bus");
    config.tagCellPx = args.integer("tag-cell");
    config.latency = 1e-3 * args.num("latency-ms");
    config.latencyJitter = 1e-3 * args.num("jitter-ms", 1e3 * config.latencyJitter);
    config.exposure = 1e-3 * args.num("exposure-ms");
    config.deadbandPx = args.num("deadband-px");
    config.trueFreqScale = args.num("true-hz-scale");
    config.trueDampingScale = args.num("true-zeta-scale");
    config.clockOffset = 1e-3 * args.num("clock-offset-ms");
    config.refine = !args.has("no-refine");
    if (!(config.trueFreqScale > 0.5 && config.trueFreqScale < 2) ||
        !(config.trueDampingScale > 0.1 && config.trueDampingScale < 5) || !(std::abs(config.clockOffset) < 0.02))
        throw std::runtime_error("--true-hz-scale must be in (0.5, 2), --true-zeta-scale in (0.1, 5) and "
                                 "--clock-offset-ms within +-20");
    config.targetTags = args.integer("tags");
    if (config.targetTags < 1 || config.targetTags > kTagIds)
        throw std::runtime_error("--tags must be in [1, " + std::to_string(kTagIds) + "]");
    if (!(config.deadbandPx >= 0 && config.deadbandPx <= 5))
        throw std::runtime_error("--deadband-px must be in [0, 5]");
    if (config.tagCellPx < 2 || config.tagCellPx > 12)
        throw std::runtime_error("--tag-cell must be in [2, 12] px");
    const int targetHeight = (9 * (config.targetTags - 1) + 10) * config.tagCellPx;
    if (targetHeight > config.imageSize.height / 2)
        throw std::runtime_error("--tags x --tag-cell: the target would be " + std::to_string(targetHeight) +
                                 " px tall; it must fit in half the frame's height (" +
                                 std::to_string(config.imageSize.height / 2) + " px)");
    if (!(config.latency >= 0 && config.latency < 1) || !(config.latencyJitter >= 0 && config.latencyJitter < 1))
        throw std::runtime_error("--latency-ms and --jitter-ms must be in [0, 1000)");
    if (!(config.exposure >= 1e-4 && config.exposure <= 1.0 / config.fps))
        throw std::runtime_error("--exposure-ms must be in [0.1, 33.3] (at most one frame period at 30 fps)");
    outDir = args.str("out");
    const std::string mode = args.str("mode"), model = args.str("model");
    if (mode != "fast" && mode != "robust")
        throw std::runtime_error("--mode must be fast or robust (got '" + mode + "')");
    config.plannerMode = mode == "fast" ? PLAN_FAST : PLAN_ROBUST;
    config.psfModel = psfModelFromName(model);
    if (config.cycles < 1 || config.cycles > 1000)
        throw std::runtime_error("--cycles must be in [1, 1000]");
    if (config.framesPerCycle < 1 || config.framesPerCycle > 30)
        throw std::runtime_error("--frames-per-cycle must be in [1, 30]");
    if (!(config.lambda > 0 && config.lambda < 2))
        throw std::runtime_error("--lambda must be in (0, 2)");
    if (!(config.gainDegPerLevel > 0) || config.maxLevel < 1 || config.rlIterations < 1)
        throw std::runtime_error("--gain-deg, --max-level and --iterations must be positive");
    double farthest = std::abs(config.startOffsetDeg);
    for (double deg : config.targetsDeg)
        farthest = std::max(farthest, std::abs(deg));
    if (!(farthest < config.maxLevel * config.gainDegPerLevel))
        throw std::runtime_error("the tag's places must be within the positioner's range (max-level x gain-deg)");
    if (!config.busUri.empty() && config.busUri.rfind("tcp://", 0) != 0 && config.busUri.rfind("rtu:", 0) != 0)
        throw std::runtime_error("--bus must be tcp://HOST:PORT or rtu:DEVICE (got '" + config.busUri + "')");
    return config;
}

}  // namespace

int main(int argc, char** argv)
{
    ServoConfig config;
    std::string outDir;
    try
    {
        config = parseOptions(argc, argv, outDir);
    }
    catch (const std::exception& e)
    {
        const bool hinted = std::string(e.what()).find("--help") != std::string::npos;
        std::fprintf(stderr, "dynblur_visual_servo: %s%s\n", e.what(), hinted ? "" : " (see --help)");
        return 2;
    }

    try
    {
        const bool track = config.targetsDeg.size() > 1;
        if (track)
            std::printf("[servo] track: the target visits %zu places (%d cycles each), first %.1f deg off",
                        config.targetsDeg.size(), config.cyclesPerTarget, config.targetsDeg[0]);
        else
            std::printf("[servo] step: target %.1f deg off", config.startOffsetDeg);
        std::printf("; target: %d tag(s) of %d px cells; dead band %.2f px; positioner %.3f deg/level, max level %d; %s; "
                    "%d frames/cycle at 30 fps, exposure %.1f ms; latency %.0f ms + 0..%.0f ms\n",
                    config.targetTags, config.tagCellPx, config.deadbandPx, config.gainDegPerLevel, config.maxLevel,
                    config.busUri.empty() ? "plant driven directly" : ("bus " + config.busUri).c_str(),
                    config.framesPerCycle, 1e3 * config.exposure, 1e3 * config.latency, 1e3 * config.latencyJitter);
        const int cycles = config.cycles;
        const ServoReport report = runVisualServo(config, [cycles](const ServoReport& r) {
            const ServoCycle& c = r.cycles.back();
            std::printf("[servo] cycle %2d/%d: place %d, error %6.2f px (true %6.2f), dtheta %+7.3f deg, level %4d -> %4d, frames:",
                        c.cycle + 1, cycles, c.target, c.measuredErrorPx, c.trueErrorPx, c.deltaDeg, c.fromLevel, c.toLevel);
            for (const ServoFrame& f : r.frames)
                if (f.cycle == c.cycle)
                    std::printf(" %s[raw %s, restored %s]", exposureWindowName(f.window), f.raw.found ? "found" : "-",
                                f.restored.found ? "found" : "-");
            std::printf("\n");
            std::fflush(stdout);
        });
        writeServoOutputs(report, outDir);

        // Convergence: cycles from each place's arrival until the error stays <= 1 px.
        int worst = 0, never = 0;
        for (size_t t = 0; t < report.targetsDeg.size(); ++t)
        {
            const int n = report.cyclesToWithin(1.0, static_cast<int>(t));
            if (n < 0)
                ++never;
            worst = std::max(worst, n);
        }
        if (track)
            std::printf("[servo] error <= 1 px within %d cycle(s) of each jump; %d of %zu places never reached it\n", worst,
                        never, report.targetsDeg.size());
        else
            std::printf("[servo] error <= 1 px from cycle %d on\n", report.cyclesToWithin(1.0));
        std::printf("[servo] target found while moving    all frames: found raw / restored | a tag moved >= %.0f px: raw / restored\n",
                    kTagBlurredPx);
        for (const DetectionRow& row : detectionSummary(report))
            std::printf("[servo]   window %-5s %3d frames: %3d (%3.0f%%) / %3d (%3.0f%%) | %3d frames: %3d (%3.0f%%) / %3d (%3.0f%%)\n",
                        row.window.c_str(), row.all.frames, row.all.raw, 100 * row.all.rawRate(), row.all.restored,
                        100 * row.all.restoredRate(), row.tagBlurred.frames, row.tagBlurred.raw,
                        100 * row.tagBlurred.rawRate(), row.tagBlurred.restored, 100 * row.tagBlurred.restoredRate());
        std::printf("[servo] restoration %.0f ms per frame (mean); wrote %s/{cycles.csv,frames.csv,error.png,strip.png,"
                    "detection.png}\n",
                    1e3 * report.meanRestoreSec(), outDir.c_str());
        return never == 0 ? 0 : 1;
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "dynblur_visual_servo: %s\n", e.what());
        return 1;
    }
}
