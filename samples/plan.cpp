// SPDX-License-Identifier: Apache-2.0
// dynblur_plan: plans one point-to-point move as an integer-level switching schedule, prints it,
// and writes the schedule (PREFIX.yml, which dynblur_actuator_ctl --upload and the demo's --schedule
// read), the predicted trajectory (PREFIX.csv) and a plot of it (PREFIX.png).
//
//     dynblur_plan --deg --from 0 --to 10 --mode robust --plant plant.yml --out move
//
// With --mount, a move of every axis of a mount (MountPlanner), one schedule file per axis:
//
//     dynblur_plan --mount samples/data/pan_tilt.yml --from 0,0 --to 10,6
#include "cli_args.hpp"  // samples/support
#include "plant_file.hpp"
#include "plot.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/dynblur.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

using namespace cv;
using namespace cv::dynblur;

static dynblur_samples::CliOptions planOptions()
{
    dynblur_samples::CliOptions options("dynblur_plan");
    options.synopsis("--to ANGLE [options]")
        .description("Plans a vibration-free move of the piezo-driven camera positioner. Options take --name value or "
                     "--name=value, e.g. --deg --from -5 --to 5 --mode robust.")
        .option("from", "ANGLE", "0", "start angle, radians (degrees with --deg); with --mount one per axis, degrees, "
                                      "comma-separated (default: 0 on every axis)")
        .option("to", "ANGLE", "", "target angle, radians (degrees with --deg); with --mount one per axis, degrees, "
                                   "comma-separated (e.g. 10,6 pans 10 and tilts 6); required")
        .flag("deg", "read --from and --to in degrees")
        .option("mode", "NAME", "fast", "fast (shortest settle) or robust (tolerates +-10% error in wn)")
        .option("plant", "FILE.yml", "", "the plant (dynblur_identify_plant writes it; its maxLevel too); otherwise:")
        .option("hz", "HZ", "14.4", "plant natural frequency, Hz")
        .option("zeta", "Z", "0.12", "plant damping ratio")
        .option("gain-deg", "G", "1", "plant static gain, degrees per level (one cell)")
        .option("max-level", "N", "16", "largest |level|, cells (with --plant: the plant file's)")
        .option("min-dwell", "S", "0.002", "shortest time between two switches, seconds")
        .option("start", "S", "0", "time of the first switch, seconds")
        .flag("step", "a plain step (one switch to the target level at --start), the response dynblur_identify_plant "
                      "fits, instead of a vibration-free move")
        .option("out", "PREFIX", "move", "writes PREFIX.yml (the schedule), PREFIX.csv and PREFIX.png; with --mount "
                                         "PREFIX_axis0.yml, PREFIX_axis1.yml, ... (default PREFIX: schedule)")
        .heading("Several axes:")
        .option("mount", "FILE.yml", "", "a mount file (Mount::save, e.g. samples/data/pan_tilt.yml): plans every "
                                         "axis from --from to --to (degrees, one per axis); the file gives the plants "
                                         "and level ranges")
        .flag("independent", "with --mount: each axis as fast as it can (by default the axes arrive together along a "
                             "near-straight path)")
        .footer("Exit status: 0 planned, 2 bad usage or a move that cannot be planned (the message says why).");
    return options;
}

static int fail(const std::string& message)
{
    std::cerr << "error: " << message << "\n(see dynblur_plan --help)\n";
    return 2;
}

//! The planners name their arguments (fromAngle(s), toAngle(s)); the user typed --from and --to.
static std::string withOptionNames(std::string message)
{
    for (const auto& names : {std::make_pair(std::string("fromAngles"), std::string("--from")),
                              std::make_pair(std::string("toAngles"), std::string("--to")),
                              std::make_pair(std::string("fromAngle"), std::string("--from")),
                              std::make_pair(std::string("toAngle"), std::string("--to"))})
        for (size_t at = message.find(names.first); at != std::string::npos; at = message.find(names.first, at))
            message.replace(at, names.first.size(), names.second);
    return message;
}

static std::string inOptionNames(const std::string& message, bool degrees)
{
    return withOptionNames(message) +
           (degrees ? " (--from and --to were read in degrees)" : " (--from and --to are radians; --deg reads degrees)");
}

//! "10,-6" -> radians, one per axis; throws naming `option` when it is not `count` numbers.
static std::vector<double> degreeList(const std::string& text, const char* option, size_t count)
{
    std::vector<double> radians;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');)
    {
        char* end = nullptr;
        const double value = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !std::isfinite(value))
            throw std::runtime_error(std::string(option) + " '" + text + "': '" + item + "' is not a number (degrees)");
        radians.push_back(value * CV_PI / 180.0);
    }
    if (radians.size() != count)
        throw std::runtime_error(format("%s '%s' has %zu angles for the mount's %zu axes (degrees, comma-separated, "
                                        "base first)",
                                        option, text.c_str(), radians.size(), count));
    return radians;
}

//! Plans a move of every axis of --mount, prints the report and writes one schedule file per axis.
static int planMount(const dynblur_samples::CliArgs& args)
{
    for (const char* option : {"plant", "hz", "zeta", "gain-deg", "max-level", "step", "deg"})
        if (args.has(option))
            return fail(std::string("--") + option + " does not apply to --mount (the mount file gives every axis's "
                                                     "plant and levels; --from and --to are degrees)");
    if (!args.has("to"))
        return fail("--to is required (the target angles, degrees, one per axis)");
    const std::string mode = args.str("mode"), prefix = args.str("out", "schedule");
    if (mode != "fast" && mode != "robust")
        return fail("--mode must be 'fast' or 'robust', not '" + mode + "'");
    Ptr<Mount> mount;
    MountMove move;
    try
    {
        mount = Mount::load(args.str("mount"));
        const size_t count = size_t(mount->getAxisCount());
        const std::vector<double> from =
            args.has("from") ? degreeList(args.str("from"), "--from", count) : std::vector<double>(count, 0.0);
        const std::vector<double> to = degreeList(args.str("to"), "--to", count);
        const Ptr<MountPlanner> planner =
            MountPlanner::create(mount, mode == "robust" ? PLAN_ROBUST : PLAN_FAST, args.num("min-dwell"),
                                 args.has("independent") ? MOUNT_INDEPENDENT : MOUNT_COORDINATED);
        move = planner->plan(from, to, args.num("start"));
    }
    catch (const cv::Exception& e)
    {
        return fail(withOptionNames(e.err));
    }
    const double degree = CV_PI / 180.0;
    std::printf("mount %s: %s move, %s\n", args.str("mount").c_str(), mode.c_str(),
                args.has("independent") ? "axes independent" : "axes coordinated");
    for (size_t i = 0; i < move.schedules.size(); i++)
    {
        const SwitchSchedule& s = move.schedules[i];
        std::printf("axis %zu: %.3f -> %.3f deg, settles in %.2f ms, residual vibration %.3g %%; levels", i,
                    move.fromAngles[i] / degree, move.toAngles[i] / degree, move.axisSettleTimes[i] * 1e3,
                    move.residualVibration[i] * 100);
        for (size_t k = 0; k < s.times.size(); k++)
            std::printf(" %d at %.3f ms%s", s.levels[k], s.times[k] * 1e3, k + 1 < s.times.size() ? "," : "\n");
    }
    std::printf("settle time: %.2f ms (the last axis)\npeak angular rate: %.1f deg/s\n"
                "path off a straight image line: %.3f deg\n",
                move.settleTime * 1e3, move.peakRate / degree, move.pathDeviation / degree);
    for (size_t i = 0; i < move.schedules.size(); i++)
    {
        const std::string name = format("%s_axis%zu.yml", prefix.c_str(), i);
        try
        {
            move.schedules[i].save(name);
        }
        catch (const cv::Exception& e)
        {
            return fail("--out: " + e.err);
        }
        std::printf("wrote %s\n", name.c_str());
    }
    return 0;
}

int main(int argc, char** argv)
{
    bool degrees = false, step = false;
    double from = 0, to = 0, hz = 0, zeta = 0, gainDeg = 0, minDwell = 0, start = 0;
    int maxLevel = 0;
    std::string modeName, prefix, plantPath;
    dynblur_samples::PlantFile plantFile;
    try
    {
        const dynblur_samples::CliOptions options = planOptions();
        const dynblur_samples::CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        if (args.has("mount"))
            return planMount(args);
        if (args.has("independent"))
            return fail("--independent applies to --mount only");
        if (!args.has("to"))
            return fail("--to is required (the target angle)");
        if (args.has("plant") && (args.has("hz") || args.has("zeta") || args.has("gain-deg")))
            return fail("--plant gives the plant: leave out --hz, --zeta and --gain-deg");
        degrees = args.has("deg");
        step = args.has("step");
        from = args.num("from");
        to = args.num("to");
        modeName = args.str("mode");
        plantPath = args.str("plant");
        hz = args.num("hz");
        zeta = args.num("zeta");
        gainDeg = args.num("gain-deg");
        maxLevel = args.integer("max-level");
        minDwell = args.num("min-dwell");
        start = args.num("start");
        prefix = args.str("out");
        if (!plantPath.empty())
        {
            plantFile = dynblur_samples::loadPlantFile(plantPath);
            if (!args.has("max-level"))
                maxLevel = plantFile.maxLevel;
        }
    }
    catch (const std::runtime_error& e)
    {
        return fail(e.what());
    }
    catch (const cv::Exception& e)
    {
        return fail("--plant: " + e.err);
    }
    if (modeName != "fast" && modeName != "robust")
        return fail("--mode must be 'fast' or 'robust', not '" + modeName + "'");
    if (prefix.empty())
        return fail("--out must not be empty");
    const double degree = CV_PI / 180.0;
    if (degrees)
    {
        from *= degree;
        to *= degree;
    }

    Ptr<Plant> plant;
    Ptr<SwitchPlanner> planner;
    SwitchSchedule schedule;
    double planMs = 0;
    try
    {
        plant = plantPath.empty() ? Plant::create(hz, zeta, gainDeg * degree) : plantFile.plant;
        hz = plant->getNaturalFreqHz();
        zeta = plant->getDampingRatio();
        gainDeg = plant->getGain() / degree;
    }
    catch (const cv::Exception& e)
    {
        return fail("--hz, --zeta, --gain-deg: " + e.err);
    }
    try
    {
        planner = SwitchPlanner::create(plant, maxLevel, modeName == "robust" ? PLAN_ROBUST : PLAN_FAST, minDwell);
        const auto begin = std::chrono::steady_clock::now();
        schedule = planner->plan(from, to, start);
        if (step && !schedule.times.empty())
            schedule = SwitchSchedule({start}, {schedule.finalLevel()}, schedule.initialLevel);
        planMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
    }
    catch (const cv::Exception& e)
    {
        return fail(inOptionNames(e.err, degrees));
    }
    // A move asked for that rounds to no level at all is a unit mistake (radians for degrees, or a
    // gain per level far too large), not "nothing to do".
    if (schedule.finalLevel() == schedule.initialLevel && std::abs(to - from) > 0.25 * std::abs(plant->getGain()))
        return fail(format("the move from --from %g to --to %g %s rounds to zero levels of %g deg each: is the unit "
                           "right (--deg reads degrees), and the gain (degrees per level)?",
                           degrees ? from / degree : from, degrees ? to / degree : to, degrees ? "deg" : "rad",
                           gainDeg));

    // --- The schedule and its predicted figures.
    const double gain = plant->getGain();
    const int move = schedule.finalLevel() - schedule.initialLevel;
    std::printf("move: level %d -> %d (%.3f -> %.3f deg), %s, planned in %.1f ms\n", schedule.initialLevel,
                schedule.finalLevel(), gain * schedule.initialLevel / degree, gain * schedule.finalLevel() / degree,
                step ? "step (not vibration-free)" : (modeName + " mode").c_str(), planMs);
    std::printf("plant: %.3f Hz, zeta %.3f, %.4f deg/level; max level %d, min dwell %.2f ms\n", hz, zeta, gainDeg,
                maxLevel, minDwell * 1e3);
    if (move == 0)
    {
        std::printf("nothing to do: already at the target level\n");
        return 0;
    }
    std::printf("%10s %8s\n", "t (ms)", "level");
    for (size_t i = 0; i < schedule.times.size(); ++i)
        std::printf("%10.3f %8d\n", schedule.times[i] * 1e3, schedule.levels[i]);
    if (step)
        std::printf("residual vibration: %.3g %% of the move (a step rings: the response to identify)\n",
                    residualVibration(schedule, hz, zeta) * 100);
    else
    {
        std::printf("settle time (+-%.0f%% band): %.2f ms\n", planner->getSettleBand() * 100, schedule.settleTime * 1e3);
        std::printf("peak velocity: %.1f deg/s\n", schedule.peakVelocity / degree);
        std::printf("residual vibration: %.3g %% of the move\n", schedule.residualVibration * 100);
    }
    if (modeName == "robust" && !step)
    {
        double worst = 0;
        const double range = planner->getRobustRange();
        for (int k = -20; k <= 20; ++k)
            worst = std::max(worst, residualVibration(schedule, hz * (1 + range * k / 20.0), zeta));
        std::printf("worst residual vibration for wn within +-%.0f%%: %.2f %%\n", range * 100, worst * 100);
    }

    // --- Trajectory, sampled every 0.1 ms from 10 ms before the move to a damped period after it.
    const double margin = 0.010;
    const double end = schedule.times.back() + std::max(margin, 1.0 / hz);
    std::vector<double> t;
    for (double x = start - margin; x <= end + 1e-12; x += 1e-4)
        t.push_back(x);
    Mat theta, omega;
    plant->response(schedule, t, theta);
    plant->velocity(schedule, t, omega);

    const std::string scheduleName = prefix + ".yml";
    try
    {
        schedule.save(scheduleName);
    }
    catch (const cv::Exception& e)
    {
        return fail("--out: " + e.err);
    }
    const std::string csvName = prefix + ".csv";
    std::ofstream csv(csvName);
    if (!csv)
        return fail("--out: cannot write " + csvName);
    csv << "t_s,theta_rad,omega_rad_per_s,level\n";
    csv.precision(10);
    for (size_t i = 0; i < t.size(); ++i)
        csv << t[i] << ',' << theta.at<double>(static_cast<int>(i)) << ',' << omega.at<double>(static_cast<int>(i))
            << ',' << schedule.levelAt(t[i]) << '\n';
    if (!csv)
        return fail("--out: cannot write " + csvName);

    // --- Plot: angle with the settle band, velocity, command levels; time in ms from the start.
    std::vector<double> timeMs(t.size()), thetaDeg(t.size()), omegaDeg(t.size()), level(t.size());
    for (size_t i = 0; i < t.size(); ++i)
    {
        timeMs[i] = (t[i] - start) * 1e3;
        thetaDeg[i] = theta.at<double>(static_cast<int>(i)) / degree;
        omegaDeg[i] = omega.at<double>(static_cast<int>(i)) / degree;
        level[i] = schedule.levelAt(t[i]);
    }
    const double targetDeg = gain * schedule.finalLevel() / degree;
    const double bandDeg = planner->getSettleBand() * std::abs(gain * move) / degree;
    const double settleMs = schedule.settleTime * 1e3;

    dynblur_plot::Figure figure(1000, step ? format("step %.2f -> %.2f deg (for plant identification)",
                                                   gain * schedule.initialLevel / degree, targetDeg)
                                           : format("%s move %.2f -> %.2f deg: settles in %.1f ms, peak %.0f deg/s",
                                                    modeName.c_str(), gain * schedule.initialLevel / degree, targetDeg,
                                                    settleMs, schedule.peakVelocity / degree));
    const std::string bandLabel = format("+-%.0f%% band", planner->getSettleBand() * 100);
    figure.addPanel("angle", "theta (deg)")
        .xSpan(0, settleMs, "settling", Scalar(235, 206, 135), 0.18)
        .yBand(targetDeg - bandDeg, targetDeg + bandDeg, bandLabel)
        .hLine(targetDeg, "target")
        .line(timeMs, thetaDeg, "theta", dynblur_plot::paletteColor(0));
    figure.addPanel("angular velocity", "omega (deg/s)")
        .xSpan(0, settleMs, "", Scalar(235, 206, 135), 0.18)
        .hLine(0)
        .line(timeMs, omegaDeg, "dtheta/dt", dynblur_plot::paletteColor(1));
    figure.addPanel("command", "u (levels)")
        .hLine(0)
        .line(timeMs, level, "active cells", dynblur_plot::paletteColor(2));
    figure.xLabel("time from the first switch (ms)");
    const std::string pngName = prefix + ".png";
    if (!figure.save(pngName))
        return fail("--out: cannot write " + pngName);
    std::printf("wrote %s (the schedule: dynblur_actuator_ctl --upload, dynblur_demo --schedule), %s and %s\n",
                scheduleName.c_str(), csvName.c_str(), pngName.c_str());
    return 0;
}
