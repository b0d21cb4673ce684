// SPDX-License-Identifier: Apache-2.0
// dynblur_actuator_sim: a stand-in for the actuator controller of one axis or several. Serves the
// register map of docs/actuator-bus.md over Modbus TCP on 127.0.0.1 and Modbus RTU on a
// pseudo-terminal, runs each axis's plant in real time while a schedule runs and logs θ(t) to CSV
// (t,theta,level; with several axes t,theta0,level0,theta1,level1,...).
//
//     dynblur_actuator_sim --tcp-port 1502 --rtu --csv theta.csv --max-seconds 60
//     dynblur_actuator_sim --axes 2 --plant pan.yml --plant tilt.yml --drift-wn 0.03,-0.02
#include "actuator_sim.hpp"
#include "cli_args.hpp"
#include "plant_file.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <thread>

using namespace dynblur_samples;

static std::atomic<int> gSignal{0};

// Option spelling of a SimFaultKind: drop-request, drop-reply, delay, exception, garbage, short.
static std::string kindOption(int kind)
{
    static const char* const names[SIM_FAULT_KINDS] = {"drop-request", "drop-reply", "delay", "exception", "garbage", "short"};
    return names[kind];
}

// "  faults=N (kind n, ...)", or "" while none was injected.
static std::string faultLine(const ActuatorSim& sim)
{
    const SimFaultCounts c = sim.faultCounts();
    if (c.total == 0)
        return "";
    std::string s = cv::format("  faults=%d (", c.total);
    for (int k = 0; k < SIM_FAULT_KINDS; ++k)
        s += cv::format("%s%s %d", k ? ", " : "", simFaultName(k), c.byKind[k]);
    return s + ")";
}

static void onSignal(int sig) { gSignal = sig; }

// "0.03,-0.02" as numbers; throws naming the option.
static std::vector<double> numberList(const std::string& option, const std::string& text)
{
    std::vector<double> values;
    std::stringstream list(text);
    std::string item;
    while (std::getline(list, item, ','))
    {
        char* end = nullptr;
        const double v = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !std::isfinite(v))
            throw std::runtime_error("--" + option + " expects comma-separated numbers, got '" + text + "'");
        values.push_back(v);
    }
    return values;
}

/* Each axis's model: the mount file's axes (--mount), or its plant file (one per axis, or one for all,
   else the seed's). maxLevel becomes the smallest of the files'. */
static std::vector<cv::Ptr<cv::dynblur::Plant>> modelPlants(const CliArgs& args, int axes, int& maxLevel)
{
    std::vector<cv::Ptr<cv::dynblur::Plant>> plants;
    if (args.has("mount"))
    {
        const cv::Ptr<cv::dynblur::Mount> mount = cv::dynblur::Mount::load(args.str("mount"));
        for (int k = 0; k < axes; ++k)
        {
            plants.push_back(mount->getPlant(k));
            maxLevel = k == 0 ? mount->getLevelRange(k)[1] : std::min(maxLevel, mount->getLevelRange(k)[1]);
        }
        return plants;
    }
    const std::vector<std::string> files = args.all("plant");
    if (files.size() > 1 && (int)files.size() != axes)
        throw std::runtime_error(cv::format("%d --plant files for --axes %d: give one per axis, or one for all",
                                            (int)files.size(), axes));
    for (int k = 0; k < axes; ++k)
    {
        cv::Ptr<cv::dynblur::Plant> plant = cv::dynblur::Plant::create(14.4, 0.12, CV_PI / 180);
        if (!files.empty())
        {
            const PlantFile pf = loadPlantFile(files[files.size() == 1 ? 0 : k]);
            plant = pf.plant;
            maxLevel = k == 0 ? pf.maxLevel : std::min(maxLevel, pf.maxLevel);
        }
        plants.push_back(plant);
    }
    return plants;
}

/* Each axis's true plant: its model (modelPlants) scaled by --true-hz-scale and --true-zeta-scale and
   by the axis's --drift-wn: hardware that drifted from the model its host plans with. */
static std::vector<cv::Ptr<cv::dynblur::Plant>> axisPlants(const CliArgs& args, int axes, int& maxLevel)
{
    std::vector<double> drift(axes, 0.0);
    if (args.has("drift-wn"))
    {
        drift = numberList("drift-wn", args.str("drift-wn"));
        if ((int)drift.size() != axes)
            throw std::runtime_error(cv::format("--drift-wn has %d values for --axes %d: give one per axis",
                                                (int)drift.size(), axes));
    }
    const double hzScale = args.num("true-hz-scale"), zetaScale = args.num("true-zeta-scale");
    if (!(hzScale > 0.5 && hzScale < 2) || !(zetaScale > 0.1 && zetaScale < 5))
        throw std::runtime_error("--true-hz-scale must be in (0.5, 2) and --true-zeta-scale in (0.1, 5)");
    const std::vector<cv::Ptr<cv::dynblur::Plant>> models = modelPlants(args, axes, maxLevel);
    std::vector<cv::Ptr<cv::dynblur::Plant>> plants;
    for (int k = 0; k < axes; ++k)
    {
        if (!(drift[k] > -0.5 && drift[k] < 1))
            throw std::runtime_error(cv::format("--drift-wn value %d = %g must be in (-0.5, 1)", k, drift[k]));
        cv::dynblur::MotionCorrection truth;
        truth.naturalFreqScale = hzScale * (1 + drift[k]);
        truth.dampingScale = zetaScale;
        plants.push_back(truth.correctPlant(models[k]));
    }
    return plants;
}

static CliOptions actuatorSimOptions()
{
    const SimConfig config;
    const SimFaults faults;
    CliOptions options("dynblur_actuator_sim");
    options.synopsis("[options]")
        .description("Simulated actuator controller (Modbus TCP on 127.0.0.1 and RTU on a pty).")
        .option("tcp-port", "P", "1502", "TCP port on 127.0.0.1 (0 = any free port)")
        .flag("no-tcp", "do not serve TCP")
        .flag("rtu", "also serve Modbus RTU on a new pseudo-terminal (its path is printed)")
        .option("slave", "N", std::to_string(config.rtuSlave), "RTU slave address")
        .option("axes", "N", "1", cv::format("axes the controller drives, 1 to %d", (int)cv::dynblur::busmap::MAX_AXES))
        .option("plant", "FILE", "",
                "plant file (naturalFreqHz, dampingRatio, gain, maxLevel); repeat it once per axis, in axis order, or "
                "give one for every axis; default: seed 14.4 Hz, zeta 0.12, 1 deg/level, max level 16")
        .option("mount", "FILE.yml", "",
                "a mount file (Mount::save, e.g. samples/data/pan_tilt.yml) in place of --axes and --plant: one axis per "
                "mount axis, each with its plant and level range")
        .option("drift-wn", "LIST", "",
                "comma-separated relative errors of each axis's natural frequency, one per axis (0.03 = the hardware "
                "is 3 % stiffer than its plant file)")
        .option("true-hz-scale", "X", "1",
                "the simulated plant's natural frequency is X times the plant file's (hardware that drifted from its "
                "model)")
        .option("true-zeta-scale", "X", "1", "the simulated plant's damping ratio is X times the plant file's")
        .option("start-latency", "S", numberText(config.startLatency),
                "the plant moves S seconds after each level is applied")
        .option("max-level", "N", "", "advertised max |level| (default: the plant file's, else 16)")
        .option("min-dwell-us", "N", std::to_string(config.minDwellUs), "advertised minimum dwell, microseconds")
        .option("capacity", "N", std::to_string(config.capacity), "advertised schedule capacity, entries")
        .option("csv", "FILE", "actuator_sim.csv", "log t,theta,level (s, rad, cells) while a schedule runs ('' = none)")
        .option("log-rate", "HZ", numberText(config.logRateHz), "sample rate of the log and of the switching loop")
        .option("log-tail", "S", numberText(config.logTail), "keep logging S seconds after the last switch")
        .option("max-seconds", "S", "", "exit after S seconds (default: run until SIGINT/SIGTERM)")
        .option("status-every", "S", "1", "print a status line every S seconds (0 = never)")
        .heading("Fault injection (requests counted from program start, 1-based; the injected faults are counted by "
                 "kind in the status lines and at exit):")
        .option("drop-after", "N", "", "close the connection instead of answering request N (once)")
        .option("delay-ms", "D", std::to_string(faults.delayMs), "delay every reply by D milliseconds")
        .option("exception", "FC[:REG[:CODE]]", "",
                "answer function FC (3,4,6,16) touching register REG (default any) with Modbus exception CODE "
                "(default 4)")
        .option("garbage-after", "N", "", "answer request N with random bytes (once)")
        .option("short-after", "N", "", "answer request N with a truncated reply (once)")
        .option("random-faults", "P", numberText(faults.randomRate),
                "give each request a random fault with probability P in [0, 1] (kinds below)")
        .option("fault-seed", "N", std::to_string(faults.randomSeed), "seed of the random faults")
        .option("fault-kinds", "LIST", "",
                "comma-separated kinds drawn by --random-faults (default all): drop-request, drop-reply, delay, "
                "exception, garbage, short")
        .option("random-delay-ms", "D", std::to_string(faults.randomDelayMs),
                "delay of a random 'delay' fault, milliseconds (choose it beyond the host's response timeout)")
        .alias("h", "help");
    return options;
}

int main(int argc, char** argv)
{
    try
    {
        const CliOptions options = actuatorSimOptions();
        const CliArgs args = options.parse(argc, argv);
        if (options.printHelp(args))
            return 0;
        SimConfig cfg;
        if (args.has("mount") && args.has("plant"))
            throw std::runtime_error("--mount gives every axis's plant: give it without --plant");
        cfg.axes = args.has("mount") ? cv::dynblur::Mount::load(args.str("mount"))->getAxisCount() : args.integer("axes");
        if (args.has("mount") && args.has("axes") && args.integer("axes") != cfg.axes)
            throw std::runtime_error(cv::format("--axes %d but the mount '%s' (--mount) has %d axes", args.integer("axes"),
                                                args.str("mount").c_str(), cfg.axes));
        if (cfg.axes < 1 || cfg.axes > cv::dynblur::busmap::MAX_AXES)
            throw std::runtime_error(cv::format("--axes = %d must be in [1, %d]", cfg.axes, (int)cv::dynblur::busmap::MAX_AXES));
        cfg.axisPlants = axisPlants(args, cfg.axes, cfg.maxLevel);
        cfg.startLatency = args.num("start-latency");
        if (!(cfg.startLatency >= 0 && cfg.startLatency < 1))
            throw std::runtime_error("--start-latency must be in [0, 1) s");
        cfg.maxLevel = args.integer("max-level", cfg.maxLevel);
        cfg.minDwellUs = args.integer("min-dwell-us");
        cfg.capacity = args.integer("capacity");
        if (cfg.axes > 1 && (cfg.capacity < 1 || cfg.capacity > cv::dynblur::busmap::MAX_AXIS_CAPACITY))
            throw std::runtime_error(cv::format("--capacity = %d must be in [1, %d] with several axes (an axis's block of "
                                                "registers)", cfg.capacity, (int)cv::dynblur::busmap::MAX_AXIS_CAPACITY));
        cfg.tcp = !args.has("no-tcp");
        cfg.tcpPort = args.integer("tcp-port");
        cfg.rtu = args.has("rtu");
        cfg.rtuSlave = args.integer("slave");
        cfg.csvPath = args.str("csv");
        cfg.logRateHz = args.num("log-rate");
        cfg.logTail = args.num("log-tail");
        if (!cfg.tcp && !cfg.rtu)
            throw std::runtime_error("nothing to serve: --no-tcp without --rtu");
        const double maxSeconds = args.num("max-seconds", -1);
        const double statusEvery = args.num("status-every");

        SimFaults faults;
        faults.dropAfter = args.integer("drop-after", -1);
        faults.delayMs = args.integer("delay-ms");
        faults.garbageAfter = args.integer("garbage-after", -1);
        faults.shortAfter = args.integer("short-after", -1);
        if (args.has("exception"))
        {
            int fc = -1, reg = -1, code = 4;
            const std::string spec = args.str("exception");
            if (std::sscanf(spec.c_str(), "%d:%d:%d", &fc, &reg, &code) < 1)
                throw std::runtime_error("--exception expects FC[:REG[:CODE]], got '" + spec + "'");
            faults.exceptionFunction = fc;
            faults.exceptionRegister = reg;
            faults.exceptionCode = code;
        }

        faults.randomRate = args.num("random-faults");
        if (!(faults.randomRate >= 0 && faults.randomRate <= 1))
            throw std::runtime_error(cv::format("--random-faults = %g must be in [0, 1]", faults.randomRate));
        faults.randomSeed = static_cast<unsigned>(args.integer("fault-seed"));
        faults.randomDelayMs = args.integer("random-delay-ms");
        if (faults.randomDelayMs < 0 || faults.delayMs < 0)
            throw std::runtime_error("--delay-ms and --random-delay-ms must be >= 0");
        if (args.has("fault-kinds"))
        {
            faults.randomKinds = 0;
            std::stringstream list(args.str("fault-kinds"));
            std::string name;
            while (std::getline(list, name, ','))
            {
                int k = 0;
                while (k < SIM_FAULT_KINDS && kindOption(k) != name)
                    ++k;
                if (k == SIM_FAULT_KINDS)
                    throw std::runtime_error("--fault-kinds: unknown kind '" + name +
                                             "' (allowed: drop-request, drop-reply, delay, exception, garbage, short)");
                faults.randomKinds |= 1 << k;
            }
        }

        std::signal(SIGINT, onSignal);
        std::signal(SIGTERM, onSignal);
        std::signal(SIGPIPE, SIG_IGN);

        ActuatorSim sim(cfg);
        sim.setFaults(faults);
        sim.start();
        if (cfg.tcp)
            std::cout << "tcp: 127.0.0.1:" << sim.tcpPort() << "  (uri tcp://127.0.0.1:" << sim.tcpPort() << ")\n";
        if (cfg.rtu)
            std::cout << "rtu: " << sim.ptyPath() << "  (uri rtu:" << sim.ptyPath() << "?baud=115200&slave="
                      << cfg.rtuSlave << ")\n";
        std::cout << "ready" << std::endl;

        const auto t0 = std::chrono::steady_clock::now();
        auto nextStatus = t0;
        while (!gSignal)
        {
            const auto now = std::chrono::steady_clock::now();
            const double elapsed = std::chrono::duration<double>(now - t0).count();
            if (maxSeconds >= 0 && elapsed >= maxSeconds)
                break;
            if (statusEvery > 0 && now >= nextStatus)
            {
                std::cout << "[sim] " << sim.statusLine() << faultLine(sim) << std::endl;
                nextStatus = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                       std::chrono::duration<double>(statusEvery));
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
        sim.stop();
        std::cout << "[sim] stopped (" << (gSignal ? "signal" : "max-seconds") << "): " << sim.statusLine() << faultLine(sim) << std::endl;
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
    return 2;
}
