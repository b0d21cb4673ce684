// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/bank_operator.hpp"

#include "restore/operators/bank_geometry.hpp"
#include "restore/row_arithmetic.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>

namespace cv {
namespace dynblur {
namespace detail {

BankBlurOperator::BankBlurOperator(const PsfBank& bank, bool pad) : BlurOperator(bank.imageSize)
{
    spotGain_ = bankSpotGain(bank);
    nodeCols_ = int(bank.nodeCols.size());
    nodeRows_ = int(bank.nodeRows.size());
    nodes_.resize(bank.kernels.size());
    int dxMin = 0, dxMax = 0, dyMin = 0, dyMax = 0;
    for (size_t n = 0; n < bank.kernels.size(); n++)
    {
        Node& node = nodes_[n];
        for (const KernelTap& tap : kernelTaps(bank.kernels[n], bank.shifts[n]))
        {
            if (node.rows.empty() || node.rows.back().dy != tap.dy)
            {
                node.rows.emplace_back();
                node.rows.back().dy = tap.dy;
            }
            node.rows.back().dx.push_back(tap.dx);
            node.rows.back().weight.push_back(tap.weight);
            dxMin = std::min(dxMin, tap.dx);
            dxMax = std::max(dxMax, tap.dx);
            dyMin = std::min(dyMin, tap.dy);
            dyMax = std::max(dyMax, tap.dy);
        }
        if (!node.rows.empty())
        {
            node.dyMin = node.rows.front().dy;  // kernelTaps runs down the kernel: dy decreases
            node.dyMax = node.rows.back().dy;
            if (node.dyMin > node.dyMax)
                std::swap(node.dyMin, node.dyMax);
            node.rowOfDy.assign(size_t(node.dyMax - node.dyMin + 1), -1);
            for (size_t k = 0; k < node.rows.size(); k++)
                node.rowOfDy[size_t(node.rows[k].dy - node.dyMin)] = int(k);
        }
    }
    domain(frame_, pad, dxMin, dxMax, dyMin, dyMax, latent_, origin_);
    dyMin_ = dyMin;
    dyMax_ = dyMax;

    rowWeights_ = nodeRowWeights(bank, frame_.height);
    nodeRowSupport_ = supports(rowWeights_, nodeRows_);
    const std::vector<AxisWeight> colWeights = nodeColumnWeights(bank, frame_.width);
    nodeColSupport_ = supports(colWeights, nodeCols_);
    colWeight_ = supportWeights(colWeights, nodeColSupport_);
}

float BankBlurOperator::rowWeight(int nodeRow, int frameRow) const
{
    const AxisWeight& w = rowWeights_[size_t(frameRow)];
    return (w.node[0] == nodeRow ? w.weight[0] : 0.f) + (w.node[1] == nodeRow ? w.weight[1] : 0.f);
}

void BankBlurOperator::forward(const Mat& latent, Mat& frame)
{
    CV_DbgAssert(latent.type() == CV_32FC1 && latent.size() == latent_);
    frame.create(frame_, CV_32FC1);
    parallel_for_(Range(0, frame_.height), [&](const Range& rows) { forwardRows(latent, frame, rows); });
}

void BankBlurOperator::adjoint(const Mat& frame, Mat& latent)
{
    CV_DbgAssert(frame.type() == CV_32FC1 && frame.size() == frame_);
    latent.create(latent_, CV_32FC1);
    if (nodeCols_ > 1)
    {
        /* The frame weighted by each node column's weight, once per call rather than once per tap
           row: columns of one parity have disjoint supports, so two planes hold them all. */
        for (Mat& w : weighted_)
            w.create(frame_, CV_32FC1);
        parallel_for_(Range(0, frame_.height), [&](const Range& rows) {
            for (int r = rows.start; r < rows.end; r++)
            {
                const float* src = frame.ptr<float>(r);
                for (int i = 0; i < nodeCols_; i++)
                {
                    const Range cols = nodeColSupport_[size_t(i)];
                    multiplyInto(weighted_[i % 2].ptr<float>(r) + cols.start, colWeight_[size_t(i)].data(),
                                 src + cols.start, cols.size());
                }
            }
        });
    }
    parallel_for_(Range(0, latent_.height), [&](const Range& rows) { adjointRows(frame, latent, rows); });
}

void BankBlurOperator::forwardRows(const Mat& latent, Mat& frame, const Range& rows) const
{
    const int width = frame_.width;
    std::vector<float> tile(nodeCols_ > 1 ? size_t(width) : 0);
    for (int y = rows.start; y < rows.end; y++)
    {
        float* out = frame.ptr<float>(y);
        std::memset(out, 0, sizeof(float) * size_t(width));
        const AxisWeight& rw = rowWeights_[size_t(y)];
        for (int k = 0; k < 2; k++)
        {
            const float a = rw.weight[k];
            if (a <= 0.f)
                continue;
            const int j = rw.node[k];
            for (int i = 0; i < nodeCols_; i++)
            {
                const Node& node = nodes_[size_t(j * nodeCols_ + i)];
                const Range cols = nodeColSupport_[size_t(i)];
                // Row-variant banks (one node column) accumulate straight into the output.
                float* target = out;
                float scale = a;
                if (nodeCols_ > 1)
                {
                    target = tile.data();
                    scale = 1.f;
                    std::fill(tile.begin() + cols.start, tile.begin() + cols.end, 0.f);
                }
                for (const TapRow& tr : node.rows)
                {
                    const int ly = y + tr.dy + origin_.y;
                    if (ly < 0 || ly >= latent_.height)
                        continue;
                    const float* lrow = latent.ptr<float>(ly);
                    for (size_t t = 0; t < tr.dx.size(); t++)
                    {
                        const int off = tr.dx[t] + origin_.x;
                        const int begin = std::max(cols.start, -off);
                        const int end = std::min(cols.end, latent_.width - off);
                        if (begin < end)
                            accumulateScaled(target, lrow + off, scale * tr.weight[t], begin, end);
                    }
                }
                if (nodeCols_ > 1)
                {
                    const float* cw = colWeight_[size_t(i)].data() - cols.start;
                    for (int x = cols.start; x < cols.end; x++)
                        out[x] += a * cw[x] * tile[size_t(x)];
                }
            }
        }
    }
}

void BankBlurOperator::adjointRows(const Mat& frame, Mat& latent, const Range& rows) const
{
    for (int ly = rows.start; ly < rows.end; ly++)
    {
        float* out = latent.ptr<float>(ly);
        std::memset(out, 0, sizeof(float) * size_t(latent_.width));
        const int qy = ly - origin_.y;  // frame coordinate of this latent row
        /* Frame rows that read this latent row lie in [qy − dyMax_, qy − dyMin_]; node rows are in
           order, so only those whose support meets that range need a look. */
        const int rowLow = qy - dyMax_, rowHigh = qy - dyMin_;
        int j = int(std::lower_bound(nodeRowSupport_.begin(), nodeRowSupport_.end(), rowLow,
                                     [](const Range& r, int row) { return r.end <= row; }) -
                    nodeRowSupport_.begin());
        for (; j < nodeRows_ && nodeRowSupport_[size_t(j)].start <= rowHigh; j++)
        {
            const Range support = nodeRowSupport_[size_t(j)];
            for (int i = 0; i < nodeCols_; i++)
            {
                const Node& node = nodes_[size_t(j * nodeCols_ + i)];
                // Frame row r reads latent row r + dy: this node touches qy only if r = qy − dy
                // can fall inside its row support.
                if (node.rows.empty() || qy - node.dyMin < support.start || qy - node.dyMax >= support.end)
                    continue;
                const Range cols = nodeColSupport_[size_t(i)];
                // Only the tap rows whose frame row r = qy − dy lies in the support: look them up by dy.
                const int dyLow = std::max(node.dyMin, qy - support.end + 1);
                const int dyHigh = std::min(node.dyMax, qy - support.start);
                for (int dy = dyLow; dy <= dyHigh; dy++)
                {
                    const int k = node.rowOfDy[size_t(dy - node.dyMin)];
                    if (k < 0)
                        continue;
                    const TapRow& tr = node.rows[size_t(k)];
                    const int r = qy - tr.dy;
                    const float a = rowWeight(j, r);
                    if (a <= 0.f)
                        continue;
                    const float* src = nodeCols_ > 1 ? weighted_[i % 2].ptr<float>(r) : frame.ptr<float>(r);
                    for (size_t t = 0; t < tr.dx.size(); t++)
                    {
                        // Frame col x read latent col x + off: scatter back along the row.
                        const int off = tr.dx[t] + origin_.x;
                        const int begin = std::max(cols.start, -off);
                        const int end = std::min(cols.end, latent_.width - off);
                        if (begin < end)
                            accumulateScaled(out + off, src, a * tr.weight[t], begin, end);
                    }
                }
            }
        }
    }
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
