// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/row_bank_operator.hpp"

#include "restore/operators/bank_geometry.hpp"
#include "restore/operators/gather.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>

namespace cv {
namespace dynblur {
namespace detail {

RowBankOperator::RowBankOperator(const PsfBank& bank, bool pad, bool packed)
    : BlurOperator(bank.imageSize, packed)
{
    CV_Assert(bank.nodeCols.size() == 1 && bank.kernels.size() == bank.nodeRows.size());
    int dxMin, dxMax, dyMin, dyMax;
    const NodeTaps nodes(bank, dxMin, dxMax, dyMin, dyMax);
    spotGain_ = spotGainOf(bank, nodes.smallestPeak());
    domain(frame_, pad, dxMin, dxMax, dyMin, dyMax, latent_, origin_);
    gathers_ = buildRowGathers(nodes, 1, 0, nodeRowWeights(bank, frame_.height), frame_, latent_, origin_, packed_);
}

void RowBankOperator::forwardBlock(const Mat& latent, const Range& frameRows, float* out, size_t outStep) const
{
    gatherBlock(latent, gathers_.forward, frameRows, Range(0, frame_.width), out, outStep);
}

void RowBankOperator::adjointBlock(const Mat& frame, const Range& latentRows, float* out, size_t outStep) const
{
    gatherBlock(frame, gathers_.adjoint, latentRows, Range(0, latent_.width), out, outStep);
}

void RowBankOperator::forwardPackedBlock(const Mat& packedLatent, const Range& frameRows, float* out,
                                         size_t outStep) const
{
    CV_DbgAssert(packedLatent.type() == CV_32SC1 && packedLatent.rows == (latent_.height + 1) / 2);
    gatherPackedBlock(packedLatent, gathers_.packedForward, frameRows, Range(0, frame_.width), out, outStep);
}

void RowBankOperator::adjointPackedBlock(const Mat& packedFrame, const Range& latentRows, float* out,
                                         size_t outStep) const
{
    CV_DbgAssert(packedFrame.type() == CV_32SC1 && packedFrame.rows == (frame_.height + 1) / 2);
    gatherPackedBlock(packedFrame, gathers_.packedAdjoint, latentRows, Range(0, latent_.width), out, outStep);
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
                gatherPackedBlock(ones, gathers_.packedAdjoint, rows, cols, latent.ptr<float>(rows.start),
                                  latent.step1());
            else
                gatherBlock(ones, gathers_.adjoint, rows, cols, latent.ptr<float>(rows.start), latent.step1());
        };
        int begin = 0, end = width;  // where every row's taps read inside, in this block
        for (int r = rows.start; r < rows.end; r++)
        {
            const GatherRow& g =
                packed_ ? gathers_.packedAdjoint.pairs[size_t(r / 2)] : gathers_.adjoint.rows[size_t(r)];
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
