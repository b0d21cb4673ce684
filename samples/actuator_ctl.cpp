// SPDX-License-Identifier: Apache-2.0
// dynblur_actuator_ctl: drives the actuator controller from the command line with
// cv::dynblur::ActuatorDriver: connect, upload a schedule (checked against the safety limits,
// read back and verified), start it and print when it started on the host's clock.
//
//     dynblur_actuator_ctl --bus tcp://127.0.0.1:1502 --upload move.yml --start --wait 2
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
        .description("Uploads, starts and watches a switching schedule on the actuator controller.")
        .option("bus", "URI", "", "tcp://HOST:PORT or rtu:DEVICE?baud=115200&slave=1 (required)")
        .option("timeout", "S", "0.5", "response timeout, seconds")
        .option("retries", "N", "2", "extra attempts of a failed read")
        .option("max-level", "N", std::to_string(limits.maxLevel), "host limit on |level|, cells")
        .option("min-dwell", "S", numberText(limits.minDwell), "host limit on the time between switches, seconds")
        .option("max-entries", "N", std::to_string(limits.maxEntries), "host limit on the schedule length")
        .option("safe-level", "N", std::to_string(limits.safeLevel), "level applied on stop and on errors")
        .option("upload", "FILE", "", "schedule file (SwitchSchedule::save format: YAML/XML/JSON)")
        .flag("start", "start the uploaded schedule; prints the start report")
        .option("wait", "S", "", "poll the status until the schedule is done (at most S seconds)")
        .flag("stop", "apply the safe level")
        .flag("clear-fault", "leave the FAULT state")
        .flag("status", "print the status")
        .alias("h", "help")
        .footer("Exit status: 0 success, 1 the device or the link failed (message on stderr), 2 bad usage.");
    return options;
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
        SwitchSchedule schedule;
        if (args.has("upload"))
            schedule = SwitchSchedule::load(args.str("upload"));

        stage = "device";
        cv::Ptr<ActuatorBus> bus = ActuatorBus::create(args.str("bus"), args.num("timeout"), args.integer("retries"));
        cv::Ptr<ActuatorDriver> driver = ActuatorDriver::create(bus, limits);
        const ActuatorInfo info = driver->connect();
        std::printf("device: protocol %d.%d, max level %d, min dwell %.6f s, capacity %d, round trip %.6f s\n",
                    info.protocolMajor, info.protocolMinor, info.maxLevel, info.minDwell, info.capacity,
                    bus->getLastRoundTrip());
        if (args.has("clear-fault"))
            driver->clearFault();
        if (args.has("upload"))
        {
            driver->upload(schedule);
            std::printf("uploaded: %d entries, verified\n", (int)schedule.times.size());
        }
        if (args.has("start"))
        {
            const StartReport r = driver->start();
            std::printf("start: hostStartTime=%.6f uncertainty=%.6f controllerStartTime=%.6f scheduleOrigin=%.6f "
                        "commandRoundTrip=%.6f\n",
                        r.hostStartTime, r.uncertainty, r.controllerStartTime, r.scheduleOrigin, r.commandRoundTrip);
        }
        if (args.has("wait"))
            std::printf("status: %s\n", driver->waitUntilDone(args.num("wait")).describe().c_str());
        if (args.has("stop"))
            driver->stop();
        if (args.has("status"))
            std::printf("status: %s\n", driver->status().describe().c_str());
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
