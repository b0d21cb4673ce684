// SPDX-License-Identifier: Apache-2.0
// How long SwitchPlanner::plan takes: a first (uncached) search per move, and a cached repeat.
#include <benchmark/benchmark.h>
#include <opencv2/dynblur.hpp>

namespace {

using namespace cv::dynblur;

const double kDegree = CV_PI / 180.0;

// A fresh planner every iteration, so each plan() searches (nothing cached). Argument: move, levels.
void plannerSearch(benchmark::State& state, int mode)
{
    const cv::Ptr<Plant> plant = Plant::create(14.4, 0.12, kDegree);
    const double target = static_cast<double>(state.range(0)) * kDegree;
    for (auto _ : state)
    {
        state.PauseTiming();
        const cv::Ptr<SwitchPlanner> planner = SwitchPlanner::create(plant, 16, mode, 0.002);
        state.ResumeTiming();
        benchmark::DoNotOptimize(planner->plan(0.0, target, 0.0));
    }
}

void BM_PlanFastUncached(benchmark::State& state) { plannerSearch(state, PLAN_FAST); }
void BM_PlanRobustUncached(benchmark::State& state) { plannerSearch(state, PLAN_ROBUST); }

// The same move again: the search result is cached, only the schedule figures are recomputed.
void BM_PlanRobustCached(benchmark::State& state)
{
    const cv::Ptr<SwitchPlanner> planner =
        SwitchPlanner::create(Plant::create(14.4, 0.12, kDegree), 16, PLAN_ROBUST, 0.002);
    planner->plan(0.0, 10 * kDegree, 0.0);
    for (auto _ : state)
        benchmark::DoNotOptimize(planner->plan(0.0, 10 * kDegree, 0.0));
}

}  // namespace

BENCHMARK(BM_PlanFastUncached)->Arg(1)->Arg(10)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanRobustUncached)->Arg(1)->Arg(10)->Arg(16)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanRobustCached)->Unit(benchmark::kMicrosecond);
