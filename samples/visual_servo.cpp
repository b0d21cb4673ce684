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
// With --mount pan-tilt (or a mount file) the camera sits on a mount of two axes: vpServo asks for ωx
// and ωy, the mount's chain turns them into pan and tilt increments, MountPlanner moves both axes
// together (over the bus: MultiAxisDriver), and each frame is restored with the mount's CameraMotion;
// the target jumps along diagonals (--scenario track) or steps along a circle (--scenario circle).
// The loops themselves are runVisualServo and runPanTiltServo (samples/simulation/), shared with the tests.
//
//   dynblur_visual_servo --cycles 10 --out servo_out
//   dynblur_visual_servo --scenario track --targets 16
//   dynblur_actuator_sim --tcp-port 5020 --max-level 400 &
//   dynblur_visual_servo --bus tcp://127.0.0.1:5020
//   dynblur_visual_servo --mount pan-tilt --scenario track --targets 10
//   dynblur_visual_servo --mount pan-tilt --scenario circle --targets 12 --radius-deg 5
#include "cli_args.hpp"
#include "pan_tilt_servo.hpp"
#include "restoration_options.hpp"
#include "frame_timing.hpp"
#include "visual_servo.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>

using namespace cv;
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
        .option("scenario", "step|track|circle", "step",
                "step: the target sits --start-deg off and stays; track: it jumps to --targets places, --jump-deg each "
                "way, --cycles-per-target cycles each, and the saccade's phase against the frames varies (--jitter-ms); "
                "circle (with --mount): it steps along a circle of --radius-deg, --targets places per turn")
        .option("mount", "pan-tilt|FILE", "",
                "turn a mount of two axes or more instead of the tilt positioner: pan-tilt (a pan carrying a tilt, each "
                "the positioner of --gain-deg and --max-level) or a mount file (e.g. samples/data/pan_tilt.yml); its "
                "first two axes point the camera. step and track then move the target along diagonals")
        .option("radius-deg", "R", "5", "radius of the circle, degrees, --scenario circle, in (0, 10]")
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

//! What the command line asks for: the one-axis loop, or (--mount) the pan-tilt loop.
struct ServoRun
{
    ServoConfig config;      // the one-axis loop's, or the pan-tilt loop's camera, target, control and restoration
    bool mount = false;
    PanTiltConfig panTilt;   // with --mount (its loop is `config`)
    std::string outDir;
};

//! The --jump-deg range, degrees.
Vec2d jumpRange(const CliArgs& args)
{
    double minJump = 0, maxJump = 0;
    if (std::sscanf(args.str("jump-deg").c_str(), "%lf,%lf", &minJump, &maxJump) != 2 ||
        !(0 <= minJump && minJump <= maxJump && maxJump <= 12))
        throw std::runtime_error("--jump-deg must be MIN,MAX with 0 <= MIN <= MAX <= 12 (got '" + args.str("jump-deg") +
                                 "')");
    return Vec2d(minJump, maxJump);
}

// The scenario's places and cycles: on the tilt positioner, or (with --mount) the pan-tilt's.
void parseScenario(const CliArgs& args, ServoRun& run)
{
    const std::string scenario = args.str("scenario");
    if (scenario != "step" && scenario != "track" && scenario != "circle")
        throw std::runtime_error("--scenario must be step, track or circle (got '" + scenario + "')");
    run.mount = args.has("mount");
    if (scenario == "circle" && !run.mount)
        throw std::runtime_error("--scenario circle needs --mount (a target on a circle needs a pan and a tilt)");
    const std::map<std::string, std::vector<const char*>> foreign = {
        {"step", {"targets", "cycles-per-target", "seed", "jump-deg", "radius-deg"}},
        {"track", {"cycles", "radius-deg"}},
        {"circle", {"cycles", "jump-deg", "start-deg"}}};
    for (const char* name : foreign.at(scenario))
        if (args.has(name))
            throw std::runtime_error(std::string("--") + name + " is not for --scenario " + scenario);
    if (scenario == "step")
    {
        const double startDeg = args.num("start-deg", run.config.startOffsetDeg);
        run.config.startOffsetDeg = startDeg;
        run.panTilt.targetsDeg = {Vec2d::all(startDeg / std::sqrt(2.0))};  // along the diagonal
        return;
    }
    const int targets = args.integer("targets"), perTarget = args.integer("cycles-per-target");
    const int seed = args.integer("seed");
    if (targets < 1 || targets > 200 || perTarget < 1 || perTarget > 20 || seed < 0)
        throw std::runtime_error("--targets must be in [1, 200], --cycles-per-target in [1, 20], --seed >= 0");
    if (scenario == "circle")
    {
        const double radius = args.num("radius-deg");
        if (targets < 3 || !(radius > 0 && radius <= 10))
            throw std::runtime_error("--scenario circle needs --targets >= 3 and --radius-deg in (0, 10]");
        run.panTilt = circleScenario(targets, radius, perTarget, static_cast<unsigned>(seed));
        run.config = run.panTilt.loop;
        return;
    }
    const double startDeg = args.num("start-deg", kTrackStartDeg);
    if (!(std::abs(startDeg) <= 12))
        throw std::runtime_error("--start-deg must be within +-12 deg for --scenario track");
    const Vec2d jump = jumpRange(args);
    if (run.mount)
    {
        run.panTilt = diagonalJumps(targets, perTarget, static_cast<unsigned>(seed),
                                    Vec2d::all(startDeg / std::sqrt(2.0)), jump[0], jump[1]);
        run.config = run.panTilt.loop;
    }
    else
    {
        run.config = trackingScenario(targets, perTarget, static_cast<unsigned>(seed), startDeg, jump[0], jump[1]);
    }
}

ServoRun parseOptions(int argc, char** argv)
{
    const CliOptions options = servoOptions();
    const CliArgs args = options.parse(argc, argv);
    if (options.printHelp(args))
        std::exit(0);
    ServoRun run;
    parseScenario(args, run);
    ServoConfig& config = run.config;
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
    run.outDir = args.str("out");
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
    if (!config.busUri.empty() && config.busUri.rfind("tcp://", 0) != 0 && config.busUri.rfind("rtu:", 0) != 0)
        throw std::runtime_error("--bus must be tcp://HOST:PORT or rtu:DEVICE (got '" + config.busUri + "')");
    if (run.mount)
    {
        run.panTilt.loop = config;
        const std::string mount = args.str("mount");
        run.panTilt.mount = mount == "pan-tilt" ? panTiltMount(config) : Mount::load(mount);
        checkPanTiltConfig(run.panTilt);  // names the axis and its range of a place it cannot reach
        return run;
    }
    double farthest = std::abs(config.startOffsetDeg);
    for (double deg : config.targetsDeg)
        farthest = std::max(farthest, std::abs(deg));
    if (!(farthest < config.maxLevel * config.gainDegPerLevel))
        throw std::runtime_error("the tag's places must be within the positioner's range (max-level x gain-deg)");
    return run;
}

// Convergence (cycles from each place's arrival until the error stays <= 1 px) and the detection
// figure; returns the number of places never reached.
int printSummary(const ServoReport& report, const std::string& outDir)
{
    int worst = 0, never = 0;
    for (size_t t = 0; t < report.targetsDeg.size(); ++t)
    {
        const int n = report.cyclesToWithin(1.0, static_cast<int>(t));
        if (n < 0)
            ++never;
        worst = std::max(worst, n);
    }
    if (report.targetsDeg.size() > 1)
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
    return never;
}

void printFrames(const ServoReport& report, int cycle)
{
    for (const ServoFrame& f : report.frames)
        if (f.cycle == cycle)
            std::printf(" %s[raw %s, restored %s]", exposureWindowName(f.window), f.raw.found ? "found" : "-",
                        f.restored.found ? "found" : "-");
    std::printf("\n");
    std::fflush(stdout);
}

int runTilt(const ServoConfig& config, const std::string& outDir)
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
        printFrames(r, c.cycle);
    });
    writeServoOutputs(report, outDir);
    return printSummary(report, outDir) == 0 ? 0 : 1;
}

int runPanTilt(const PanTiltConfig& config, const std::string& outDir)
{
    const ServoConfig& loop = config.loop;
    std::printf("[servo] mount of %d axes; the target visits %zu places (%d cycles each), first at pan %.1f, tilt %.1f "
                "deg; dead band %.2f px; %s; %d frames/cycle at 30 fps, exposure %.1f ms; latency %.0f ms + 0..%.0f ms\n",
                config.mount->getAxisCount(), config.targetsDeg.size(), std::max(loop.cyclesPerTarget, 1),
                config.targetsDeg[0][0], config.targetsDeg[0][1], loop.deadbandPx,
                loop.busUri.empty() ? "plants driven directly" : ("bus " + loop.busUri).c_str(), loop.framesPerCycle,
                1e3 * loop.exposure, 1e3 * loop.latency, 1e3 * loop.latencyJitter);
    const int cycles = loop.cycles;
    const PanTiltReport report = runPanTiltServo(config, [cycles](const PanTiltReport& r) {
        const ServoCycle& c = r.loop.cycles.back();
        const PanTiltMove& m = r.moves.back();
        std::printf("[servo] cycle %2d/%d: place %d, error %6.2f px (true %6.2f), dpan %+7.3f dtilt %+7.3f deg, levels "
                    "(%d, %d) -> (%d, %d), frames:",
                    c.cycle + 1, cycles, c.target, c.measuredErrorPx, c.trueErrorPx, m.deltaDeg[0], m.deltaDeg[1],
                    m.fromLevels[0], m.fromLevels[1], m.toLevels[0], m.toLevels[1]);
        printFrames(r.loop, c.cycle);
    });
    writePanTiltOutputs(report, outDir);
    return printSummary(report.loop, outDir) == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv)
{
    ServoRun run;
    try
    {
        run = parseOptions(argc, argv);
    }
    catch (const std::exception& e)
    {
        const cv::Exception* cvError = dynamic_cast<const cv::Exception*>(&e);
        const std::string message = cvError ? cvError->err : e.what();  // a mount file's or a place's refusal
        const bool hinted = message.find("--help") != std::string::npos;
        std::fprintf(stderr, "dynblur_visual_servo: %s%s\n", message.c_str(), hinted ? "" : " (see --help)");
        return 2;
    }
    try
    {
        return run.mount ? runPanTilt(run.panTilt, run.outDir) : runTilt(run.config, run.outDir);
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "dynblur_visual_servo: %s\n", e.what());
        return 1;
    }
}
