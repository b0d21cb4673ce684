// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/gather.hpp"

#include "restore/kernels/kernel_table.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

/* The columns a gather takes at a time, across all rows of a block before the next chunk: a
   chunk's ~60 source rows (~30 packed pairs) fit a 32 KiB L1, and a 512-bit kernel keeps its
   sixteen sums in registers. A remainder of up to kGatherChunkSlack columns joins the chunk before
   it: alone, its single vector per row would wait on each tap's multiply-add latency (BM_TileVsRows
   in perf/perf_deconv.cpp measures the tile adjoint whose node columns are that narrow). */
constexpr int kGatherChunk = 128, kGatherChunkSlack = 32;

//! Where the chunk of [x, end) that starts at x ends.
inline int chunkEnd(int x, int end)
{
    const int next = std::min(x + kGatherChunk, end);
    return end - next <= kGatherChunkSlack ? end : next;
}

/* For the gathers that cannot fold their sums in themselves: gather(sums0, sums1) writes columns
   [begin, end) of two rows (the second may be unused) into a per-thread buffer, then both are
   folded into out0 and out1 (out1 may be null). */
template <typename GatherSums>
void gatherThenFold(const kernels::KernelTable& k, const GatherFold& fold, int begin, int end, float* out0,
                    float* out1, const GatherSums& gather)
{
    thread_local std::vector<float> sums;
    sums.resize(std::max(sums.size(), 2 * size_t(end)));
    gather(sums.data(), sums.data() + end);
    k.fold(sums.data(), fold, begin, end, out0);
    if (out1)
        k.fold(sums.data() + end, fold, begin, end, out1);
}

//! Columns [begin, end) of one gathered row whose taps may read outside `source` (those reads are zero).
void gatherBorder(const Mat& source, const Tap* taps, int count, int begin, int end, float* out)
{
    const float* base = source.ptr<float>();
    const size_t step = source.step1();
    for (int x = begin; x < end; x++)
    {
        float s = 0.f;
        for (int t = 0; t < count; t++)
        {
            const int c = x + taps[t].col;
            if (c >= 0 && c < source.cols)
                                s = std::fma(taps[t].weight, base[size_t(taps[t].row) * step + size_t(c)], s);
        }
        out[x] = s;
    }
}

//! Columns [begin, end) of one gathered row: where every tap reads inside, the kernel; elsewhere checked.
void gatherRowRange(const kernels::KernelTable& k, const Mat& source, const Tap* taps, int count,
                    const GatherRow& row, int begin, int end, float* out, const GatherFold& fold)
{
    if (begin >= end)
        return;
    const auto sums = [&](float* o, float*) {
        const int safeBegin = std::max(begin, row.safeBegin), safeEnd = std::max(safeBegin, std::min(end, row.safeEnd));
        if (safeBegin < safeEnd)
            k.row(o, source.ptr<float>(), source.step1(), taps, count, safeBegin, safeEnd);
        gatherBorder(source, taps, count, begin, safeBegin, o);
        gatherBorder(source, taps, count, safeEnd, end, o);
    };
    if (fold.writes())
        sums(out, nullptr);
    else
        gatherThenFold(k, fold, begin, end, out, nullptr, sums);
}

//! The packed pair gather's columns [begin, end) whose taps may read outside `packed` (those reads are zero).
void gatherPackedBorder(const Mat& packed, const PackedTap* taps, int count, int begin, int end, float* out0,
                        float* out1, const GatherFold& fold)
{
    const uint32_t* base = packed.ptr<uint32_t>();
    const size_t step = packed.step1();
    for (int x = begin; x < end; x++)
    {
        float a = 0.f, b = 0.f;
        for (int t = 0; t < count; t++)
        {
            const int c = x + taps[t].col;
            if (c < 0 || c >= packed.cols)
                continue;
            const uint32_t l = base[size_t(taps[t].pair) * step + size_t(c)];
            a = kernels::packedDot(taps[t].weight[0], l, a);
            b = kernels::packedDot(taps[t].weight[1], l, b);
        }
        kernels::foldColumn(a, fold, x, out0);
        kernels::foldColumn(b, fold, x, out1);
    }
}

}  // namespace

/* Two rows at a time where a pair (2k, 2k+1) lies inside. Columns run in chunks across all the
   rows before the next chunk: neighbouring rows read nearly the same source rows, so a chunk's
   source stays in L1 for the whole block instead of every row pulling its ~kernel-height source
   rows from L2 again. */
void gatherBlock(const Mat& source, const Gather& gather, const Range& rows, const Range& cols, float* out,
                 size_t outStep, const GatherFold& fold)
{
    const kernels::KernelTable& k = kernels::kernelTable();
    int commonBegin = cols.start, commonEnd = cols.end;
    for (int r = rows.start; r < rows.end; r++)
    {
        commonBegin = std::max(commonBegin, gather.rows[size_t(r)].safeBegin);
        commonEnd = std::min(commonEnd, gather.rows[size_t(r)].safeEnd);
    }
    commonEnd = std::max(commonEnd, commonBegin);
    const float* base = source.ptr<float>();
    const size_t step = source.step1();
    const auto single = [&](int r, int begin, int end) {
        const GatherRow& g = gather.rows[size_t(r)];
        gatherRowRange(k, source, gather.taps.data() + g.begin, g.end - g.begin, g, begin, end,
                       out + size_t(r - rows.start) * outStep, fold);
    };
    for (int x = commonBegin, end; x < commonEnd; x = end)
    {
        end = chunkEnd(x, commonEnd);
        int r = rows.start;
        if (r % 2 != 0)
            single(r++, x, end);
        for (; r + 1 < rows.end; r += 2)
        {
            const GatherRow& g = gather.pairs[size_t(r / 2)];
            float* o = out + size_t(r - rows.start) * outStep;
            k.pair(o, o + outStep, base, step, gather.pairTaps.data() + g.begin, g.end - g.begin, x, end, fold);
        }
        if (r < rows.end)
            single(r, x, end);
    }
    for (int r = rows.start; r < rows.end; r++)
    {
        single(r, cols.start, commonBegin);
        single(r, commonEnd, cols.end);
    }
}

/* In the same column chunks as gatherBlock; the second row of an odd last pair goes to a scratch row. */
void gatherPackedBlock(const Mat& packed, const PackedGather& gather, const Range& rows, const Range& cols, float* out,
                       size_t outStep, const GatherFold& fold)
{
    const kernels::KernelTable& k = kernels::kernelTable();
    CV_DbgAssert(rows.start % 2 == 0);
    const int pairBegin = rows.start / 2, pairEnd = (rows.end + 1) / 2;
    std::vector<float> scratch(rows.size() % 2 ? size_t(cols.end) : 0);
    const auto outputs = [&](int pair, float*& o0, float*& o1) {
        o0 = out + size_t(2 * pair - rows.start) * outStep;
        o1 = 2 * pair + 1 < rows.end ? o0 + outStep : scratch.data();
    };
    int commonBegin = cols.start, commonEnd = cols.end;
    for (int pair = pairBegin; pair < pairEnd; pair++)
    {
        commonBegin = std::max(commonBegin, gather.pairs[size_t(pair)].safeBegin);
        commonEnd = std::min(commonEnd, gather.pairs[size_t(pair)].safeEnd);
    }
    commonEnd = std::max(commonEnd, commonBegin);
    const uint32_t* base = packed.ptr<uint32_t>();
    const size_t step = packed.step1();
    float *o0, *o1;
    for (int x = commonBegin, end; x < commonEnd; x = end)
    {
        end = chunkEnd(x, commonEnd);
        for (int pair = pairBegin; pair < pairEnd; pair++)
        {
            const GatherRow& g = gather.pairs[size_t(pair)];
            outputs(pair, o0, o1);
            k.packedPair(o0, o1, base, step, gather.taps.data() + g.begin, g.end - g.begin, x, end, fold);
        }
    }
    for (int pair = pairBegin; pair < pairEnd; pair++)
    {
        const GatherRow& g = gather.pairs[size_t(pair)];
        outputs(pair, o0, o1);
        gatherPackedBorder(packed, gather.taps.data() + g.begin, g.end - g.begin, cols.start, commonBegin, o0, o1, fold);
        gatherPackedBorder(packed, gather.taps.data() + g.begin, g.end - g.begin, commonEnd, cols.end, o0, o1, fold);
    }
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
