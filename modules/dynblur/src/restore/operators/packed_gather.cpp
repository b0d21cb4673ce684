// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/packed_gather.hpp"

#include "restore/operators/gather.hpp"
#include "restore/simd_clones.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>

namespace cv {
namespace dynblur {
namespace detail {

using kernels::highBfloat16;
using kernels::lowBfloat16;
using kernels::roundToBfloat16;

/* The packed form of a gather whose rows are filled, each row's taps in (row, col) order
   (sourceWidth: the source's columns): output rows 2k and 2k + 1 together, each term taking source
   rows 2j and 2j + 1 at one column offset, weights rounded to bfloat16. Two linear merges per pair
   (not a sort: this runs once per bank and frame): the output rows' taps by (row, col), then each
   source row pair's two runs by column. */
void buildPacked(const Gather& gather, int outWidth, int sourceWidth,
                 PackedGather& packed)
{
    typedef Tap Tap;
    typedef PairTap PairTap;
    const int rows = int(gather.rows.size());
    typedef PackedTap PackedTap;
    buildGatherRows((rows + 1) / 2, packed.taps, packed.pairs, [&](int k, std::vector<PackedTap>& taps) {
        thread_local std::vector<PairTap> merged;
        const GatherRow& first = gather.rows[size_t(2 * k)];
        const GatherRow* second = 2 * k + 1 < rows ? &gather.rows[size_t(2 * k + 1)] : nullptr;
        merged.clear();
        forUnion(gather.taps.data() + first.begin, size_t(first.end - first.begin),
                 second ? gather.taps.data() + second->begin : nullptr, second ? size_t(second->end - second->begin) : 0,
                 [](const Tap& t) { return std::make_pair(t.row, t.col); },
                 [&](const Tap& t, float w0, float w1) { merged.push_back({t.row, t.col, {w0, w1}}); });
        GatherRow g;
        g.begin = int(taps.size());
        g.safeBegin = 0;
        g.safeEnd = outWidth;
        for (size_t i = 0; i < merged.size();)
        {
            // The run of source row 2j (empty when the pair starts at an odd row), then of 2j + 1.
            const int pair = merged[i].row / 2;
            size_t even = i;
            while (even < merged.size() && merged[even].row == 2 * pair)
                even++;
            size_t odd = even;
            while (odd < merged.size() && merged[odd].row == 2 * pair + 1)
                odd++;
            for (size_t p = i, q = even; p < even || q < odd;)
            {
                const bool takeEven = p < even && (q == odd || merged[p].col <= merged[q].col);
                const bool takeOdd = q < odd && (p == even || merged[q].col <= merged[p].col);
                const int col = takeEven ? merged[p].col : merged[q].col;
                PackedTap term{pair, col, {0u, 0u}};
                for (int o = 0; o < 2; o++)
                    term.weight[o] = (takeEven ? roundToBfloat16(merged[p].weight[o]) : 0u) |
                                     (takeOdd ? roundToBfloat16(merged[q].weight[o]) << 16 : 0u);
                taps.push_back(term);
                g.safeBegin = std::max(g.safeBegin, -col);
                g.safeEnd = std::min(g.safeEnd, sourceWidth - col);
                p += takeEven;
                q += takeOdd;
            }
            i = odd;
        }
        g.end = int(taps.size());
        g.safeBegin = std::min(g.safeBegin, outWidth);
        g.safeEnd = std::max(g.safeEnd, g.safeBegin);
        return g;
    });
}

/* The packed adjoint transposed from the packed forward gather: a forward tap (frame pair k, latent
   pair g, column colBase + dx) holds the 2×2 block of A between frame rows 2k + o and latent rows
   2g + h, so Aᵀ's block between latent pair g and frame pair k is the same four weights with o and
   h swapped, read at column adjointColBase − dx. Both gathers list a pair's taps by source pair,
   then by column ascending: a forward block's run (dx ascending) goes in reversed. The adjoint is
   then the packed forward's to the bit, in the time of a counting sort, with no float lists to
   transpose, sort and pack again, and no second walk of a tile column's kernels. */
void transposePackedGather(const PackedGather& forward, int colBase, int outRows, int adjointColBase,
                           int outWidth, int sourceWidth, PackedGather& adjoint)
{
    const size_t pairs = size_t((outRows + 1) / 2);
    std::vector<int> start(pairs + 1, 0);  // each adjoint pair's first tap
    for (const PackedTap& t : forward.taps)
        start[size_t(t.pair) + 1]++;
    for (size_t g = 0; g < pairs; g++)
        start[g + 1] += start[g];
    adjoint.taps.resize(forward.taps.size());
    adjoint.pairs.assign(pairs, GatherRow());
    std::vector<int> next(start.begin(), start.end() - 1);
    std::vector<int> safeBegin(pairs, 0), safeEnd(pairs, outWidth);
    for (int k = 0; k < int(forward.pairs.size()); k++)
    {
        const GatherRow& row = forward.pairs[size_t(k)];
        for (int runEnd = row.begin; runEnd < row.end;)
        {
            const int runBegin = runEnd, g = forward.taps[size_t(runBegin)].pair;
            while (runEnd < row.end && forward.taps[size_t(runEnd)].pair == g)
                runEnd++;
            int& at = next[size_t(g)];
            for (int t = runEnd - 1; t >= runBegin; t--)
            {
                const PackedTap& f = forward.taps[size_t(t)];
                const int col = adjointColBase - (f.col - colBase);
                adjoint.taps[size_t(at++)] = {k, col,
                                              {(f.weight[0] & 0xFFFFu) | (f.weight[1] << 16),
                                               (f.weight[0] >> 16) | (f.weight[1] & 0xFFFF0000u)}};
                safeBegin[size_t(g)] = std::max(safeBegin[size_t(g)], -col);
                safeEnd[size_t(g)] = std::min(safeEnd[size_t(g)], sourceWidth - col);
            }
        }
    }
    for (size_t g = 0; g < pairs; g++)
    {
        GatherRow& row = adjoint.pairs[g];
        row.begin = start[g];
        row.end = start[g + 1];
        row.safeBegin = std::min(safeBegin[g], outWidth);
        row.safeEnd = std::max(safeEnd[g], row.safeBegin);
    }
}

//! dst = src ⊙ weight over n packed pairs (both halves of element x times weight[x]), re-rounded.
DYNBLUR_SIMD_CLONES
void scalePackedRow(const uint32_t* __restrict src, const float* __restrict weight, int n, uint32_t* __restrict dst)
{
    for (int x = 0; x < n; x++)
        dst[x] = roundToBfloat16(lowBfloat16(src[x]) * weight[x]) |
                 (roundToBfloat16(highBfloat16(src[x]) * weight[x]) << 16);
}

DYNBLUR_SIMD_CLONES
void packRowPair(const float* __restrict first, const float* __restrict second, float offset, int n,
                 uint32_t* __restrict out)
{
    if (second)
        for (int x = 0; x < n; x++)
            out[x] = roundToBfloat16(first[x] + offset) | (roundToBfloat16(second[x] + offset) << 16);
    else
        for (int x = 0; x < n; x++)
            out[x] = roundToBfloat16(first[x] + offset);
}

void packPlane(const Mat& plane, Mat& packed)
{
    packed.create((plane.rows + 1) / 2, plane.cols, CV_32SC1);
    parallel_for_(Range(0, packed.rows), [&](const Range& pairs) {
        for (int k = pairs.start; k < pairs.end; k++)
            packRowPair(plane.ptr<float>(2 * k), 2 * k + 1 < plane.rows ? plane.ptr<float>(2 * k + 1) : nullptr, 0.f,
                        plane.cols, packed.ptr<uint32_t>(k));
    });
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
