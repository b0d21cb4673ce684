// SPDX-License-Identifier: Apache-2.0
// Speed of the actuator bus (docs/reliability.md, "The actuator bus"): the start's time uncertainty
// against a bare request's round trip on the same link, measured in paired rounds of one run.
// Run by scripts/benchmark.py; a timing figure is a ratio here, never a bound in a unit test.
#include "actuator_sim.hpp"

#include <benchmark/benchmark.h>
#include <opencv2/dynblur.hpp>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

using namespace cv::dynblur;
using namespace dynblur_samples;

namespace {

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

/* Each round: a bare read of the status register (one request's round trip), then a whole
   upload-start-stop cycle, whose start reports its uncertainty. The start keeps the fastest of three
   reads (docs/actuator-bus.md), so on an unloaded link its uncertainty is about one round trip. */
void startUncertainty(benchmark::State& state, bool tcp)
{
    SimConfig cfg;
    cfg.tcp = tcp;
    cfg.rtu = !tcp;
    cfg.tcpPort = 0;
    ActuatorSim sim(cfg);
    sim.start();
    const std::string uri = tcp ? cv::format("tcp://127.0.0.1:%d", sim.tcpPort())
                                : "rtu:" + sim.ptyPath() + "?baud=115200&slave=1";
    cv::Ptr<ActuatorBus> bus = ActuatorBus::create(uri, 0.3, 2);
    cv::Ptr<ActuatorDriver> driver = ActuatorDriver::create(bus);
    driver->connect();
    const SwitchSchedule move({0.0, 0.0113, 0.0262, 0.040}, {4, 10, 7, 10}, 0);
    std::vector<double> roundTrip, uncertainty;
    for (auto _ : state)
    {
        bus->readInputRegisters(0, 1);
        roundTrip.push_back(bus->getLastRoundTrip());
        driver->upload(move);
        uncertainty.push_back(driver->start().uncertainty);
        driver->stop();
    }
    const double rtt = median(roundTrip), start = median(uncertainty);
    state.counters["round_trip_us"] = rtt * 1e6;
    state.counters["start_uncertainty_us"] = start * 1e6;
    state.counters["start_over_round_trip"] = start / rtt;
}

// Every axis switches at the same offsets: their first switches are simultaneous by the schedules.
std::vector<SwitchSchedule> sameMoves(int axes)
{
    return std::vector<SwitchSchedule>(axes, SwitchSchedule({0.0, 0.0113, 0.0262, 0.040}, {4, 10, 7, 10}, 0));
}

double spread(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()) - *std::min_element(v.begin(), v.end()); }

/* Each round: upload to every axis, one START, wait for the end, stop. The skew between the axes'
   start instants (the controller's stamps, as the driver reports them) and between the instants the
   controller's switching loop applied their first switch (the simulator's truth, host clock). */
void BM_BusStartSkewOneController(benchmark::State& state)
{
    const int axes = (int)state.range(0);
    SimConfig cfg;
    cfg.axes = axes;
    ActuatorSim sim(cfg);
    sim.start();
    cv::Ptr<MultiAxisDriver> driver = MultiAxisDriver::create(
        ActuatorBus::create(cv::format("tcp://127.0.0.1:%d", sim.tcpPort()), 0.3, 2), axes);
    driver->connect();
    std::vector<double> startSkew, switchSkew, switchLate;
    for (auto _ : state)
    {
        driver->upload(sameMoves(axes));
        const std::vector<StartReport> reports = driver->start();
        driver->waitUntilDone(1.0);
        std::vector<double> starts, switches;
        for (int k = 0; k < axes; ++k)
        {
            starts.push_back(reports[k].controllerStartTime);
            switches.push_back(sim.lastFirstSwitchHostTime(k));
        }
        startSkew.push_back(spread(starts));
        switchSkew.push_back(spread(switches));
        switchLate.push_back(switches[0] - (sim.lastStartHostTime(0) + 0.0113));
        driver->stop();
    }
    state.counters["start_skew_us"] = median(startSkew) * 1e6;
    state.counters["max_start_skew_us"] = *std::max_element(startSkew.begin(), startSkew.end()) * 1e6;
    state.counters["first_switch_skew_us"] = median(switchSkew) * 1e6;
    state.counters["max_first_switch_skew_us"] = *std::max_element(switchSkew.begin(), switchSkew.end()) * 1e6;
    state.counters["first_switch_late_us"] = median(switchLate) * 1e6;
}

/* The same axes as one-axis controllers, each started by its own START one after the other: the skew
   a host gets without one START for all (the simulators' true start instants). */
void BM_BusStartSkewSeparateControllers(benchmark::State& state)
{
    const int axes = (int)state.range(0);
    std::vector<std::unique_ptr<ActuatorSim>> sims;
    std::vector<cv::Ptr<ActuatorDriver>> drivers;
    for (int k = 0; k < axes; ++k)
    {
        sims.emplace_back(new ActuatorSim(SimConfig()));
        sims.back()->start();
        drivers.push_back(ActuatorDriver::create(
            ActuatorBus::create(cv::format("tcp://127.0.0.1:%d", sims.back()->tcpPort()), 0.3, 2)));
        drivers.back()->connect();
    }
    std::vector<double> startSkew;
    for (auto _ : state)
    {
        std::vector<double> starts;
        for (int k = 0; k < axes; ++k)
            drivers[k]->upload(sameMoves(1)[0]);
        for (int k = 0; k < axes; ++k)
            drivers[k]->start();
        for (int k = 0; k < axes; ++k)
        {
            starts.push_back(sims[k]->lastStartHostTime());
            drivers[k]->waitUntilDone(1.0);
            drivers[k]->stop();
        }
        startSkew.push_back(spread(starts));
    }
    state.counters["start_skew_us"] = median(startSkew) * 1e6;
}

void BM_BusStartTcp(benchmark::State& state) { startUncertainty(state, true); }
void BM_BusStartRtuPty(benchmark::State& state) { startUncertainty(state, false); }

}  // namespace

BENCHMARK(BM_BusStartTcp)->Iterations(41)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BusStartRtuPty)->Iterations(21)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BusStartSkewOneController)->ArgName("axes")->Arg(2)->Arg(3)->Iterations(21)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BusStartSkewSeparateControllers)->ArgName("axes")->Arg(2)->Arg(3)->Iterations(21)->Unit(benchmark::kMillisecond);
