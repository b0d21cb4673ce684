// SPDX-License-Identifier: Apache-2.0
/* Every gather kernel of one table held to its plain C++ reference (gather_reference.hpp) on random
   taps and sources: each column width from 1 to 3 blocks of the widest vectors (every block size
   and tail), each way of folding (written, added, weighted, split mid-vector). Float kernels agree to
   1e-6 of a bound of what a column sums; so do the packed ones, whose products of bfloat16s are exact in
   float; the update of a row (update_terms.hpp) likewise. Shared by test_kernels.cpp (every instruction set
   this CPU runs, through the library's dispatch) and kernels_check.cpp (the header-only build
   scripts/arm_check.sh makes for AArch64 and for each x86 instruction set). */
#ifndef DYNBLUR_TEST_KERNEL_CHECK_HPP
#define DYNBLUR_TEST_KERNEL_CHECK_HPP

#include "restore/kernels/kernel_table.hpp"
#include "restore/kernels/gather_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace cv {
namespace dynblur {
namespace kernels {
namespace check {

struct Case
{
    int width, taps, foldKind;  // foldKind: 0 writes, 1 adds, 2 weighted, 3 split unweighted, 4 split weighted
};

//! The largest |got − want| / scale over columns [begin, end).
inline double worstError(const std::vector<float>& got, const std::vector<float>& want, double scale, int begin,
                         int end)
{
    double worst = 0;
    for (int x = begin; x < end; x++)
        worst = std::max(worst, std::fabs(double(got[size_t(x)]) - double(want[size_t(x)])) / scale);
    return worst;
}

/* The update of rows of every kind (TV or not, the row above a band's ny only, a step or not, a
   normaliser plane or one value, widths across every block and tail) against the reference: the
   largest relative difference of the row, its ny, its step (as floats) and its sums. */
inline double worstUpdateError(const KernelTable& k, std::mt19937& random)
{
    std::uniform_real_distribution<float> unit(0.f, 1.f);
    double worst = 0;
    const auto relative = [](double got, double want) { return std::fabs(got - want) / std::max(std::fabs(want), 1e-3); };
    for (int trial = 0; trial < 300; trial++)
    {
        const int n = 1 + int(random() % 90);
        const bool tv = random() % 2, step = random() % 2, plane = random() % 2, below = random() % 2;
        const bool nyOnly = tv && random() % 5 == 0, excess = random() % 2;
        const size_t count = static_cast<size_t>(n);
        std::vector<float> y(count), correction(count), norm(count), belowRow(count), nyAbove(count);
        std::vector<uint16_t> lastStep(count);
        for (int x = 0; x < n; x++)
        {
            y[size_t(x)] = unit(random);
            correction[size_t(x)] = unit(random);
            norm[size_t(x)] = unit(random) < 0.05f ? 1e-4f : unit(random) + 0.1f;  // some unobserved
            belowRow[size_t(x)] = unit(random);
            nyAbove[size_t(x)] = unit(random) - 0.5f;
            lastStep[size_t(x)] = uint16_t(roundToBfloat16(unit(random) - 0.5f));
        }
        std::vector<float> out[2], ny[2];
        std::vector<uint16_t> steps[2];
        UpdateSums sums[2];
        for (int side = 0; side < 2; side++)
        {
            out[side].assign(size_t(n), 0.f);
            ny[side].assign(size_t(n), 0.f);
            steps[side] = lastStep;
            const RowTv rowTv{below ? belowRow.data() : nullptr, nyOnly ? nullptr : nyAbove.data(), ny[side].data(),
                              3.f, 1e-6f};
            const UpdateRow row{y.data(), correction.data(), excess, plane ? norm.data() : nullptr,
                                0.7f, tv ? &rowTv : nullptr, 0.02f, 5.f, n, nyOnly ? nullptr : out[side].data(),
                                step && !nyOnly ? steps[side].data() : nullptr, 1.3f};
            if (side == 0)
                k.updateRow(row, sums[0]);
            else
                reference::updateRow(row, sums[1]);
        }
        for (int x = 0; x < n; x++)
        {
            worst = std::max({worst, relative(out[0][size_t(x)], out[1][size_t(x)]),
                              relative(ny[0][size_t(x)], ny[1][size_t(x)]),
                              relative(lowBfloat16(steps[0][size_t(x)]), lowBfloat16(steps[1][size_t(x)]))});
        }
        // Σ g·g_old is a sum of terms of either sign: its error is taken relative to Σ g_old², its size's bound.
        const double size = std::max(sums[1].stepBeforeSq, 1e-3);
        worst = std::max({worst, std::fabs(sums[0].stepDot - sums[1].stepDot) / size,
                          std::fabs(sums[0].stepBeforeSq - sums[1].stepBeforeSq) / size});
    }
    return worst;
}

/* Runs `k` against the reference over many cases; prints each kernel's worst relative error and
   returns whether all are within `tolerance`. */
inline bool checkKernels(const KernelTable& k, const char* label, double tolerance = 1e-6)
{
    std::mt19937 random(20261202u);
    std::uniform_real_distribution<float> unit(0.f, 1.f);
    constexpr int kSourceRows = 24, kMargin = 40, kBegin = 3;
    double worstRow = 0, worstPair = 0, worstPacked = 0, worstFold = 0;
    for (int width = 1; width <= 200; width += (width < 70 ? 1 : 7))
        for (int foldKind = 0; foldKind < 5; foldKind++)
        {
            const int taps = 1 + int(random() % 40), end = kBegin + width;
            const size_t step = size_t(end + 2 * kMargin);
            std::vector<float> source(step * kSourceRows), weight(static_cast<size_t>(end));
            std::vector<uint32_t> packed(step * kSourceRows);
            for (float& v : source)
                v = unit(random);
            for (uint32_t& v : packed)
                v = roundToBfloat16(unit(random)) | (roundToBfloat16(unit(random)) << 16);
            for (float& v : weight)
                v = unit(random);
            std::vector<Tap> rowTaps;
            std::vector<PairTap> pairTaps;
            std::vector<PackedTap> packedTaps;
            for (int t = 0; t < taps; t++)
            {
                const int row = int(random() % kSourceRows), col = kMargin - 20 + int(random() % 41);
                const float w0 = unit(random) - 0.25f, w1 = unit(random) - 0.25f;  // some negative, as a user's may be
                rowTaps.push_back({row, col, w0});
                pairTaps.push_back({row, col, {w0, w1}});
                packedTaps.push_back({row, col, {roundToBfloat16(w0) | (roundToBfloat16(w1) << 16),
                                                 roundToBfloat16(w1) | (roundToBfloat16(w0) << 16)}});
            }
            GatherFold fold;
            if (foldKind == 1 || foldKind == 3)
                fold.split = foldKind == 1 ? end : kBegin + width / 2;
            if (foldKind == 2 || foldKind == 4)
            {
                fold.weight = weight.data();
                fold.split = foldKind == 2 ? end : kBegin + width / 3;
            }
            /* The errors are taken relative to a bound of what a column sums: sources and folded
               values lie in [0, 1], a packed element holds two, and a fold adds at most 1. */
            double scale = 1;
            for (const PairTap& t : pairTaps)
                scale += 2 * (std::fabs(double(t.weight[0])) + std::fabs(double(t.weight[1])));
            std::vector<float> start(static_cast<size_t>(end));
            for (float& v : start)
                v = unit(random);
            std::vector<float> a0 = start, a1 = start, b0 = start, b1 = start;

            k.row(a0.data(), source.data(), step, rowTaps.data(), taps, kBegin, end);
            reference::gatherRow(b0.data(), source.data(), step, rowTaps.data(), taps, kBegin, end);
            worstRow = std::max(worstRow, worstError(a0, b0, scale, kBegin, end));

            a0 = a1 = b0 = b1 = start;
            k.pair(a0.data(), a1.data(), source.data(), step, pairTaps.data(), taps, kBegin, end, fold);
            reference::gatherPair(b0.data(), b1.data(), source.data(), step, pairTaps.data(), taps, kBegin, end, fold);
            worstPair = std::max({worstPair, worstError(a0, b0, scale, kBegin, end), worstError(a1, b1, scale, kBegin, end)});

            a0 = a1 = b0 = b1 = start;
            k.packedPair(a0.data(), a1.data(), packed.data(), step, packedTaps.data(), taps, kBegin, end, fold);
            reference::gatherPackedPair(b0.data(), b1.data(), packed.data(), step, packedTaps.data(), taps, kBegin, end,
                                        fold);
            worstPacked =
                std::max({worstPacked, worstError(a0, b0, scale, kBegin, end), worstError(a1, b1, scale, kBegin, end)});

            a0 = b0 = start;
            k.fold(source.data(), fold, kBegin, end, a0.data());
            foldColumns(source.data(), fold, kBegin, end, b0.data());
            worstFold = std::max(worstFold, worstError(a0, b0, scale, kBegin, end));
        }
    const double worstUpdate = worstUpdateError(k, random);
    bool ok = true;
    const auto report = [&](const char* kernel, double error) {
        const bool within = error <= tolerance;
        std::printf("[gather kernels] %-12s %-11s worst relative error %.3g (tolerance %.0e): %s\n", label, kernel, error,
                    tolerance, within ? "ok" : "MISMATCH");
        ok = ok && within;
    };
    report("row", worstRow);
    report("pair", worstPair);
    report("packed pair", worstPacked);
    report("fold", worstFold);
    report("update row", worstUpdate);
    return ok;
}

}  // namespace check
}  // namespace kernels
}  // namespace dynblur
}  // namespace cv

#endif
