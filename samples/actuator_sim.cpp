// SPDX-License-Identifier: Apache-2.0
// dynblur_actuator_sim: a stand-in for the actuator controller. Serves the register map of
// docs/actuator-bus.md over Modbus TCP on 127.0.0.1 and Modbus RTU on a pseudo-terminal, runs the
// plant in real time while a schedule runs and logs θ(t) to CSV (t,theta,level).
//
//     dynblur_actuator_sim --tcp-port 1502 --rtu --csv theta.csv --max-seconds 60
#include "actuator_sim.hpp"
#include "cli_args.hpp"
#include "plant_file.hpp"

#include <atomic>
#include <chrono>
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

static const char* const kHelp =
    "dynblur_actuator_sim: simulated actuator controller (Modbus TCP on 127.0.0.1 and RTU on a pty)\n"
    "\n"
    "  --tcp-port P        TCP port on 127.0.0.1 (default 1502; 0 = any free port)\n"
    "  --no-tcp            do not serve TCP\n"
    "  --rtu               also serve Modbus RTU on a new pseudo-terminal (its path is printed)\n"
    "  --slave N           RTU slave address (default 1)\n"
    "  --plant FILE        plant file (naturalFreqHz, dampingRatio, gain, maxLevel); default: seed\n"
    "                      14.4 Hz, zeta 0.12, 1 deg/level, max level 16\n"
    "  --true-hz-scale X, --true-zeta-scale X  the simulated plant's natural frequency and damping ratio\n"
    "                      are X times the plant file's (hardware that drifted from its model; default 1)\n"
    "  --start-latency S   the plant moves S seconds after each level is applied (default 0)\n"
    "  --max-level N       advertised max |level| (default: the plant file's, else 16)\n"
    "  --min-dwell-us N    advertised minimum dwell, microseconds (default 1000)\n"
    "  --capacity N        advertised schedule capacity, entries (default 256)\n"
    "  --csv FILE          log t,theta,level (s, rad, cells) while a schedule runs (default actuator_sim.csv;\n"
    "                      '' = none)\n"
    "  --log-rate HZ       sample rate of the log and of the switching loop (default 1000)\n"
    "  --log-tail S        keep logging S seconds after the last switch (default 1.0)\n"
    "  --max-seconds S     exit after S seconds (default: run until SIGINT/SIGTERM)\n"
    "  --status-every S    print a status line every S seconds (default 1; 0 = never)\n"
    "fault injection (requests counted from program start, 1-based):\n"
    "  --drop-after N      close the connection instead of answering request N (once)\n"
    "  --delay-ms D        delay every reply by D milliseconds\n"
    "  --exception FC[:REG[:CODE]]  answer function FC (3,4,6,16) touching register REG (default any)\n"
    "                      with Modbus exception CODE (default 4)\n"
    "  --garbage-after N   answer request N with random bytes (once)\n"
    "  --short-after N     answer request N with a truncated reply (once)\n"
    "  --random-faults P   give each request a random fault with probability P in [0, 1] (kinds below)\n"
    "  --fault-seed N      seed of the random faults (default 1)\n"
    "  --fault-kinds LIST  comma-separated kinds drawn by --random-faults (default all): drop-request,\n"
    "                      drop-reply, delay, exception, garbage, short\n"
    "  --random-delay-ms D delay of a random 'delay' fault, milliseconds (default 300; choose it beyond\n"
    "                      the host's response timeout)\n"
    "  The injected faults are counted by kind in the status lines and at exit.\n"
    "  --help              this text\n";

int main(int argc, char** argv)
{
    try
    {
        const CliArgs args(argc, argv,
                           {"tcp-port", "slave", "plant", "max-level", "min-dwell-us", "capacity", "csv", "log-rate",
                            "log-tail", "max-seconds", "status-every", "drop-after", "delay-ms", "exception",
                            "garbage-after", "short-after", "random-faults", "fault-seed", "fault-kinds",
                            "random-delay-ms", "true-hz-scale", "true-zeta-scale", "start-latency"},
                           {"help", "h", "no-tcp", "rtu"});
        if (args.has("help") || args.has("h"))
        {
            std::cout << kHelp;
            return 0;
        }
        SimConfig cfg;
        if (args.has("plant"))
        {
            const PlantFile pf = loadPlantFile(args.str("plant", ""));
            cfg.plant = pf.plant;
            cfg.maxLevel = pf.maxLevel;
        }
        // Hardware that is not the model its host plans with: the plant drifted, the motion late.
        const double hzScale = args.num("true-hz-scale", 1.0), zetaScale = args.num("true-zeta-scale", 1.0);
        if (!(hzScale > 0.5 && hzScale < 2) || !(zetaScale > 0.1 && zetaScale < 5))
            throw std::runtime_error("--true-hz-scale must be in (0.5, 2) and --true-zeta-scale in (0.1, 5)");
        cv::dynblur::MotionCorrection drift;
        drift.naturalFreqScale = hzScale;
        drift.dampingScale = zetaScale;
        cfg.plant = drift.correctPlant(cfg.plant ? cfg.plant : cv::dynblur::Plant::create(14.4, 0.12, CV_PI / 180));
        cfg.startLatency = args.num("start-latency", 0.0);
        if (!(cfg.startLatency >= 0 && cfg.startLatency < 1))
            throw std::runtime_error("--start-latency must be in [0, 1) s");
        cfg.maxLevel = args.integer("max-level", cfg.maxLevel);
        cfg.minDwellUs = args.integer("min-dwell-us", cfg.minDwellUs);
        cfg.capacity = args.integer("capacity", cfg.capacity);
        cfg.tcp = !args.has("no-tcp");
        cfg.tcpPort = args.integer("tcp-port", 1502);
        cfg.rtu = args.has("rtu");
        cfg.rtuSlave = args.integer("slave", 1);
        cfg.csvPath = args.str("csv", "actuator_sim.csv");
        cfg.logRateHz = args.num("log-rate", 1000);
        cfg.logTail = args.num("log-tail", 1.0);
        if (!cfg.tcp && !cfg.rtu)
            throw std::runtime_error("nothing to serve: --no-tcp without --rtu");
        const double maxSeconds = args.num("max-seconds", -1);
        const double statusEvery = args.num("status-every", 1.0);

        SimFaults faults;
        faults.dropAfter = args.integer("drop-after", -1);
        faults.delayMs = args.integer("delay-ms", 0);
        faults.garbageAfter = args.integer("garbage-after", -1);
        faults.shortAfter = args.integer("short-after", -1);
        if (args.has("exception"))
        {
            int fc = -1, reg = -1, code = 4;
            const std::string spec = args.str("exception", "");
            if (std::sscanf(spec.c_str(), "%d:%d:%d", &fc, &reg, &code) < 1)
                throw std::runtime_error("--exception expects FC[:REG[:CODE]], got '" + spec + "'");
            faults.exceptionFunction = fc;
            faults.exceptionRegister = reg;
            faults.exceptionCode = code;
        }

        faults.randomRate = args.num("random-faults", 0.0);
        if (!(faults.randomRate >= 0 && faults.randomRate <= 1))
            throw std::runtime_error(cv::format("--random-faults = %g must be in [0, 1]", faults.randomRate));
        faults.randomSeed = static_cast<unsigned>(args.integer("fault-seed", 1));
        faults.randomDelayMs = args.integer("random-delay-ms", 300);
        if (faults.randomDelayMs < 0 || faults.delayMs < 0)
            throw std::runtime_error("--delay-ms and --random-delay-ms must be >= 0");
        if (args.has("fault-kinds"))
        {
            faults.randomKinds = 0;
            std::stringstream list(args.str("fault-kinds", ""));
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
