// SPDX-License-Identifier: Apache-2.0
// Speed of the actuator bus (docs/reliability.md, "The actuator bus"): the start's time uncertainty
// against a bare request's round trip on the same link, measured in paired rounds of one run.
// Run by scripts/benchmark.py; a timing figure is a ratio here, never a bound in a unit test.
#include "actuator_sim.hpp"

#include <benchmark/benchmark.h>
#include <opencv2/dynblur.hpp>

#include <algorithm>
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

void BM_BusStartTcp(benchmark::State& state) { startUncertainty(state, true); }
void BM_BusStartRtuPty(benchmark::State& state) { startUncertainty(state, false); }

}  // namespace

BENCHMARK(BM_BusStartTcp)->Iterations(41)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BusStartRtuPty)->Iterations(21)->Unit(benchmark::kMicrosecond);
