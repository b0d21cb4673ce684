// SPDX-License-Identifier: Apache-2.0
// Timing several workloads against each other on a machine whose speed drifts by ±20 % over
// minutes: each round runs every workload once, in an order that rotates from round to round, so a
// ratio taken within a round sees nearly the same machine, and the figures are medians over rounds.
#ifndef DYNBLUR_PERF_PAIRED_ROUNDS_HPP
#define DYNBLUR_PERF_PAIRED_ROUNDS_HPP

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <vector>

namespace dynblur_perf {

//! The median of `values`.
inline double median(std::vector<double> values)
{
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    return values[values.size() / 2];
}

/* Runs each workload once (to warm buffers and thread pools), then one round per iteration of
   `state`; returns each workload's times, milliseconds, one per round. */
inline std::vector<std::vector<double>> timePairedRounds(benchmark::State& state,
                                                         const std::vector<std::function<void()>>& work)
{
    for (const auto& w : work)
        w();
    const size_t n = work.size();
    std::vector<std::vector<double>> ms(n);
    size_t round = 0;
    for (auto _ : state)
    {
        for (size_t k = 0; k < n; k++)
        {
            const size_t which = (round + k) % n;
            const auto start = std::chrono::steady_clock::now();
            work[which]();
            ms[which].push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        }
        round++;
    }
    return ms;
}

//! The median over the rounds of numerator[r] / denominator[r].
inline double medianRatio(const std::vector<double>& numerator, const std::vector<double>& denominator)
{
    std::vector<double> ratio(numerator.size());
    for (size_t r = 0; r < ratio.size(); r++)
        ratio[r] = numerator[r] / denominator[r];
    return median(ratio);
}

}  // namespace dynblur_perf

#endif
