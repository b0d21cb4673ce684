// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/row_bank_operator.hpp"

#include "restore/operators/bank_geometry.hpp"
#include "restore/operators/gather.hpp"
#include "restore/operators/packed_gather.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

//! Output columns [begin, end) of a row of `width` where every tap reads inside [0, sourceWidth).
void safeColumns(const Tap* taps, int count, int width, int sourceWidth, int& begin, int& end)
{
    begin = 0;
    end = width;
    for (int k = 0; k < count; k++)
    {
        begin = std::max(begin, -taps[k].col);
        end = std::min(end, sourceWidth - taps[k].col);
    }
    begin = std::min(begin, width);
    end = std::max(end, begin);
}

/* The row pairs (2k, 2k+1) of a gather whose rows are filled, each row's taps in (row, col) order:
   each pair's taps are the union of its rows' taps, with both rows' weights (0 where a row has no
   such tap). */
void buildPairs(Gather& gather)
{
    const int pairCount = int(gather.rows.size()) / 2;
    gather.pairs.assign(size_t(pairCount), GatherRow());
    gather.pairTaps.clear();
    // A pair's union holds at most both rows' taps; the list is trimmed to what it holds after.
    gather.pairTaps.reserve(gather.taps.size());
    for (int k = 0; k < pairCount; k++)
    {
        const GatherRow &first = gather.rows[size_t(2 * k)], &second = gather.rows[size_t(2 * k + 1)];
        GatherRow& g = gather.pairs[size_t(k)];
        g.begin = int(gather.pairTaps.size());
        forUnion(gather.taps.data() + first.begin, size_t(first.end - first.begin), gather.taps.data() + second.begin,
                 size_t(second.end - second.begin),
                 [](const Tap& t) { return std::make_pair(t.row, t.col); },
                 [&](const Tap& t, float w0, float w1) {
                     gather.pairTaps.push_back({t.row, t.col, {w0, w1}});
                 });
        g.end = int(gather.pairTaps.size());
    }
    gather.pairTaps.shrink_to_fit();
}

}  // namespace

RowBankOperator::RowBankOperator(const PsfBank& bank, bool pad, bool packed)
    : BlurOperator(bank.imageSize, packed)
{
    CV_Assert(bank.nodeCols.size() == 1 && bank.kernels.size() == bank.nodeRows.size());
    int dxMin, dxMax, dyMin, dyMax;
    const NodeTaps nodes(bank, dxMin, dxMax, dyMin, dyMax);
    spotGain_ = spotGainOf(bank, nodes.smallestPeak());
    domain(frame_, pad, dxMin, dxMax, dyMin, dyMax, latent_, origin_);

    // Each frame row's kernel: its row nodes' taps, weighted and merged; reads of latent rows
    // outside the domain (possible without padding) read zero and are dropped.
    const std::vector<AxisWeight> rowWeights = nodeRowWeights(bank, frame_.height);
    buildGatherRows(frame_.height, forward_.taps, forward_.rows, [&](int y, std::vector<Tap>& taps) {
        GatherRow g;
        g.begin = int(taps.size());
        const AxisWeight& w = rowWeights[size_t(y)];
        // Both node kernels are in (dy, dx) order, so their union is a merge, not a sort.
        forUnion(nodes.taps(w.node[0]), w.weight[0] > 0.f ? nodes.count(w.node[0]) : 0, nodes.taps(w.node[1]),
                 w.weight[1] > 0.f ? nodes.count(w.node[1]) : 0,
                 [](const KernelTap& t) { return std::make_pair(t.dy, t.dx); },
                 [&](const KernelTap& t, float wa, float wb) {
                     const int ly = y + t.dy + origin_.y;
                     if (ly >= 0 && ly < latent_.height)
                         taps.push_back({ly, t.dx + origin_.x, w.weight[0] * wa + w.weight[1] * wb});
                 });
        g.end = int(taps.size());
        safeColumns(taps.data() + g.begin, g.end - g.begin, frame_.width, latent_.width, g.safeBegin, g.safeEnd);
        return g;
    });

    if (packed_)
    {
        buildPacked(forward_, frame_.width, latent_.width, packedForward_);
        transposePackedGather(packedForward_, 0, latent_.height, 0, latent_.width, frame_.width, packedAdjoint_);
        forward_ = Gather();
        return;
    }
    // Transpose: frame pixel (x, y) reads latent (x + col, row) with weight w, so latent row `row`
    // gathers frame row y at column x − col with the same weight.
    std::vector<int> count(size_t(latent_.height) + 1, 0);
    for (const Tap& t : forward_.taps)
        count[size_t(t.row) + 1]++;
    for (size_t l = 1; l < count.size(); l++)
        count[l] += count[l - 1];
    adjoint_.taps.resize(forward_.taps.size());
    adjoint_.rows.resize(size_t(latent_.height));
    std::vector<int> fill(count.begin(), count.end() - 1);
    for (int y = 0; y < frame_.height; y++)
    {
        const GatherRow& g = forward_.rows[size_t(y)];
        for (int i = g.begin; i < g.end; i++)
        {
            const Tap& t = forward_.taps[size_t(i)];
            adjoint_.taps[size_t(fill[size_t(t.row)]++)] = {y, -t.col, t.weight};
        }
    }
    parallel_for_(Range(0, latent_.height), [&](const Range& rows) {
        for (int l = rows.start; l < rows.end; l++)
        {
            GatherRow& g = adjoint_.rows[size_t(l)];
            g.begin = count[size_t(l)];
            g.end = count[size_t(l) + 1];
            std::sort(adjoint_.taps.begin() + g.begin, adjoint_.taps.begin() + g.end,
                      [](const Tap& a, const Tap& b) { return a.row != b.row ? a.row < b.row : a.col < b.col; });
            safeColumns(adjoint_.taps.data() + g.begin, g.end - g.begin, latent_.width, frame_.width, g.safeBegin,
                        g.safeEnd);
        }
    });
    // The two directions' pairs are built side by side.
    parallel_for_(Range(0, 2), [&](const Range& directions) {
        for (int d = directions.start; d < directions.end; d++)
            buildPairs(d == 0 ? forward_ : adjoint_);
    });
}

void RowBankOperator::forwardBlock(const Mat& latent, const Range& frameRows, float* out, size_t outStep) const
{
    gatherBlock(latent, forward_, frameRows, Range(0, frame_.width), out, outStep);
}

void RowBankOperator::adjointBlock(const Mat& frame, const Range& latentRows, float* out, size_t outStep) const
{
    gatherBlock(frame, adjoint_, latentRows, Range(0, latent_.width), out, outStep);
}

void RowBankOperator::forwardPackedBlock(const Mat& packedLatent, const Range& frameRows, float* out,
                                         size_t outStep) const
{
    CV_DbgAssert(packedLatent.type() == CV_32SC1 && packedLatent.rows == (latent_.height + 1) / 2);
    gatherPackedBlock(packedLatent, packedForward_, frameRows, Range(0, frame_.width), out, outStep);
}

void RowBankOperator::adjointPackedBlock(const Mat& packedFrame, const Range& latentRows, float* out,
                                         size_t outStep) const
{
    CV_DbgAssert(packedFrame.type() == CV_32SC1 && packedFrame.rows == (frame_.height + 1) / 2);
    gatherPackedBlock(packedFrame, packedAdjoint_, latentRows, Range(0, latent_.width), out, outStep);
}

void RowBankOperator::adjointOfOnes(Mat& latent, Mat& ones)
{
    onesFrame(ones);
    latent.create(latent_, CV_32FC1);
    const int width = latent_.width;
    /* Columns gathered inside the safe span at each end: enough for a vector of the gather, so the
       value copied across comes from the same kernel as the full gather's, at a fraction of the
       full gather's work on a wide frame. */
    constexpr int kEdge = 16;
    forRowPairs(latent_.height, [&](const Range& rows) {
        const auto gather = [&](const Range& cols) {
            if (packed_)
                gatherPackedBlock(ones, packedAdjoint_, rows, cols, latent.ptr<float>(rows.start), latent.step1());
            else
                gatherBlock(ones, adjoint_, rows, cols, latent.ptr<float>(rows.start), latent.step1());
        };
        int begin = 0, end = width;  // where every row's taps read inside, in this block
        for (int r = rows.start; r < rows.end; r++)
        {
            const GatherRow& g = packed_ ? packedAdjoint_.pairs[size_t(r / 2)] : adjoint_.rows[size_t(r)];
            begin = std::max(begin, g.safeBegin);
            end = std::min(end, g.safeEnd);
        }
        if (end - begin <= 2 * kEdge)
        {
            gather(Range(0, width));
            return;
        }
        gather(Range(0, begin + kEdge));
        gather(Range(end - kEdge, width));
        for (int r = rows.start; r < rows.end; r++)
        {
            float* row = latent.ptr<float>(r);
            std::fill(row + begin + kEdge, row + end - kEdge, row[begin]);
        }
    });
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
