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

static const char* const kHelp =
    "dynblur_actuator_ctl: upload, start and watch a switching schedule on the actuator controller\n"
    "\n"
    "  --bus URI           tcp://HOST:PORT or rtu:DEVICE?baud=115200&slave=1 (required)\n"
    "  --timeout S         response timeout, seconds (default 0.5)\n"
    "  --retries N         extra attempts of a failed read (default 2)\n"
    "  --max-level N       host limit on |level|, cells (default 16)\n"
    "  --min-dwell S       host limit on the time between switches, seconds (default 0.001)\n"
    "  --max-entries N     host limit on the schedule length (default 256)\n"
    "  --safe-level N      level applied on stop and on errors (default 0)\n"
    "  --upload FILE       schedule file (SwitchSchedule::save format: YAML/XML/JSON)\n"
    "  --start             start the uploaded schedule; prints the start report\n"
    "  --wait S            poll the status until the schedule is done (at most S seconds)\n"
    "  --stop              apply the safe level\n"
    "  --clear-fault       leave the FAULT state\n"
    "  --status            print the status\n"
    "  --help              this text\n"
    "Exit status: 0 success, 1 the device or the link failed (message on stderr), 2 bad usage.\n";

int main(int argc, char** argv)
{
    std::string stage = "arguments";
    try
    {
        const CliArgs args(argc, argv,
                           {"bus", "timeout", "retries", "max-level", "min-dwell", "max-entries", "safe-level", "upload",
                            "wait"},
                           {"help", "h", "start", "stop", "clear-fault", "status"});
        if (args.has("help") || args.has("h"))
        {
            std::cout << kHelp;
            return 0;
        }
        if (!args.has("bus"))
            throw std::runtime_error("--bus URI is required (see --help)");
        ActuatorLimits limits;
        limits.maxLevel = args.integer("max-level", limits.maxLevel);
        limits.minDwell = args.num("min-dwell", limits.minDwell);
        limits.maxEntries = args.integer("max-entries", limits.maxEntries);
        limits.safeLevel = args.integer("safe-level", limits.safeLevel);
        SwitchSchedule schedule;
        if (args.has("upload"))
            schedule = SwitchSchedule::load(args.str("upload", ""));

        stage = "device";
        cv::Ptr<ActuatorBus> bus = ActuatorBus::create(args.str("bus", ""), args.num("timeout", 0.5), args.integer("retries", 2));
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
            std::printf("status: %s\n", driver->waitUntilDone(args.num("wait", 0)).describe().c_str());
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
