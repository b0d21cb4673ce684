// SPDX-License-Identifier: Apache-2.0
// dynblur_actuator_ctl: drives the actuator controller from the command line with
// cv::dynblur::ActuatorDriver: connect, upload a schedule (checked against the safety limits,
// read back and verified), start it and print when it started on the host's clock. With one
// --schedule per axis it drives a controller of several axes: every schedule verified, then one START.
//
//     dynblur_actuator_ctl --bus tcp://127.0.0.1:1502 --upload move.yml --start --wait 2
//     dynblur_actuator_ctl --bus tcp://127.0.0.1:1502 --schedule pan.yml --schedule tilt.yml --start --wait 2
#include "cli_args.hpp"

#include <opencv2/dynblur.hpp>

#include <cstdio>
#include <iostream>

using namespace cv::dynblur;
using namespace dynblur_samples;

static CliOptions actuatorCtlOptions()
{
    const ActuatorLimits limits;
    CliOptions options("dynblur_actuator_ctl");
    options.synopsis("--bus URI [--upload FILE] [--start] [--wait S] [options]")
        .synopsis("--bus URI --schedule FILE [--schedule FILE ...] [--start] [--wait S] [options]")
        .description("Uploads, starts and watches a switching schedule on the actuator controller, or one schedule "
                     "per axis on a controller of several axes.")
        .option("bus", "URI", "", "tcp://HOST:PORT or rtu:DEVICE?baud=115200&slave=1 (required)")
        .option("timeout", "S", "0.5", "response timeout, seconds")
        .option("retries", "N", "2", "extra attempts of a failed read")
        .option("max-level", "N", std::to_string(limits.maxLevel), "host limit on |level|, cells")
        .option("min-dwell", "S", numberText(limits.minDwell), "host limit on the time between switches, seconds")
        .option("max-entries", "N", std::to_string(limits.maxEntries), "host limit on the schedule length")
        .option("safe-level", "N", std::to_string(limits.safeLevel), "level applied on stop and on errors")
        .option("upload", "FILE", "", "schedule file (SwitchSchedule::save format: YAML/XML/JSON)")
        .option("schedule", "FILE", "",
                "the schedule of one axis; repeat it once per axis, in axis order: every one is verified before one "
                "START starts them all (not with --upload)")
        .flag("start", "start the uploaded schedule(s); prints the start report (one line per axis)")
        .option("wait", "S", "", "poll the status until the schedule is done (at most S seconds)")
        .flag("stop", "apply the safe level")
        .flag("clear-fault", "leave the FAULT state")
        .flag("status", "print the status")
        .alias("h", "help")
        .footer("Exit status: 0 success, 1 the device or the link failed (message on stderr), 2 bad usage.");
    return options;
}

static void printInfo(const ActuatorInfo& info, const ActuatorBus& bus)
{
    std::printf("device: protocol %d.%d, max level %d, min dwell %.6f s, capacity %d, axes %d, round trip %.6f s\n",
                info.protocolMajor, info.protocolMinor, info.maxLevel, info.minDwell, info.capacity, info.axes,
                bus.getLastRoundTrip());
}

static void printStart(const char* label, const StartReport& r)
{
    std::printf("start%s: hostStartTime=%.6f uncertainty=%.6f controllerStartTime=%.6f scheduleOrigin=%.6f "
                "commandRoundTrip=%.6f\n",
                label, r.hostStartTime, r.uncertainty, r.controllerStartTime, r.scheduleOrigin, r.commandRoundTrip);
}

static void printStatus(const std::vector<ActuatorStatus>& all)
{
    for (size_t k = 0; k < all.size(); ++k)
        std::printf("status axis %d: %s\n", (int)k, all[k].describe().c_str());
}

// One axis (any device, axis 0 of a controller of several): ActuatorDriver.
static void driveOneAxis(const cv::Ptr<ActuatorDriver>& driver, const std::vector<SwitchSchedule>& schedules,
                         const CliArgs& args)
{
    printInfo(driver->connect(), *driver->getBus());
    if (args.has("clear-fault"))
        driver->clearFault();
    if (!schedules.empty())
    {
        driver->upload(schedules[0]);
        std::printf("uploaded: %d entries, verified\n", (int)schedules[0].times.size());
    }
    if (args.has("start"))
        printStart("", driver->start());
    if (args.has("wait"))
        std::printf("status: %s\n", driver->waitUntilDone(args.num("wait")).describe().c_str());
    if (args.has("stop"))
        driver->stop();
    if (args.has("status"))
        std::printf("status: %s\n", driver->status().describe().c_str());
}

// One schedule per axis: MultiAxisDriver, every axis verified before the one START.
static void driveAxes(const cv::Ptr<MultiAxisDriver>& driver, const std::vector<SwitchSchedule>& schedules,
                      const CliArgs& args)
{
    printInfo(driver->connect(), *driver->getBus());
    if (args.has("clear-fault"))
        driver->clearFault();
    driver->upload(schedules);
    for (size_t k = 0; k < schedules.size(); ++k)
        std::printf("uploaded axis %d: %d entries, verified\n", (int)k, (int)schedules[k].times.size());
    if (args.has("start"))
    {
        const std::vector<StartReport> reports = driver->start();
        for (size_t k = 0; k < reports.size(); ++k)
            printStart(cv::format(" axis %d", (int)k).c_str(), reports[k]);
    }
    if (args.has("wait"))
        printStatus(driver->waitUntilDone(args.num("wait")));
    if (args.has("stop"))
        driver->stop();
    if (args.has("status"))
        printStatus(driver->statusAll());
}

int main(int argc, char** argv)
{
    std::string stage = "arguments";
    try
    {
        const CliOptions options = actuatorCtlOptions();
        const CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        if (!args.has("bus"))
            throw std::runtime_error("--bus URI is required (see --help)");
        ActuatorLimits limits;
        limits.maxLevel = args.integer("max-level");
        limits.minDwell = args.num("min-dwell");
        limits.maxEntries = args.integer("max-entries");
        limits.safeLevel = args.integer("safe-level");
        if (args.has("upload") && args.has("schedule"))
            throw std::runtime_error("--upload (one axis) and --schedule (one per axis) exclude each other");
        const bool severalAxes = args.has("schedule");
        std::vector<SwitchSchedule> schedules;
        if (args.has("upload"))
            schedules.push_back(SwitchSchedule::load(args.str("upload")));
        for (const std::string& file : args.all("schedule"))
            schedules.push_back(SwitchSchedule::load(file));

        stage = "device";
        cv::Ptr<ActuatorBus> bus = ActuatorBus::create(args.str("bus"), args.num("timeout"), args.integer("retries"));
        if (severalAxes)
            driveAxes(MultiAxisDriver::create(bus, (int)schedules.size(), limits), schedules, args);
        else
            driveOneAxis(ActuatorDriver::create(bus, limits), schedules, args);
        std::fflush(stdout);
        return 0;
    }
    catch (const cv::Exception& e)
    {
        std::cerr << "error: " << e.err << "\n";
    }
    catch (const std::exception& e)
    {
        std::cerr << "error: " << e.what() << "\n";
    }
    return stage == "arguments" ? 2 : 1;
}
