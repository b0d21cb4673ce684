#include "deconv_operator.hpp"

#include "fft_kernel.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cstring>

namespace cv {
namespace dynblur {
namespace detail {

// ---------------------------------------------------------------------------------------------
// One kernel, FFT.

UniformBlurOperator::UniformBlurOperator(Size frameSize, const Mat& kernel32f, bool pad) : frame_(frameSize)
{
    CV_Assert(kernel32f.type() == CV_32FC1);
    if (pad)
    {
        origin_ = Point((kernel32f.cols - 1) / 2, (kernel32f.rows - 1) / 2);
        latent_ = Size(frame_.width + kernel32f.cols - 1, frame_.height + kernel32f.rows - 1);
    }
    else
    {
        latent_ = frame_;
    }
    fft_.reset(new FftKernel(FftKernel::linearSize(latent_, kernel32f.size()), kernel32f));
}

UniformBlurOperator::~UniformBlurOperator() {}

void UniformBlurOperator::forward(const Mat& latent, Mat& frame)
{
    if (latent_ == frame_)
    {
        fft_->convolve(latent, frame);
        return;
    }
    fft_->convolve(latent, scratch_);
    scratch_(Rect(origin_, frame_)).copyTo(frame);
}

void UniformBlurOperator::adjoint(const Mat& frame, Mat& latent)
{
    if (latent_ == frame_)
    {
        fft_->convolve(frame, latent, true);
        return;
    }
    scratch_.create(latent_, CV_32FC1);
    scratch_.setTo(0);
    frame.copyTo(scratch_(Rect(origin_, frame_)));
    fft_->convolve(scratch_, latent, true);
}

// ---------------------------------------------------------------------------------------------
// Bank of kernels, spatial domain.

/* Bilinear tent weights of every integer coordinate in [0, length) between nodes `z`
   (increasing): constant beyond the outermost nodes, so the weights sum to 1 everywhere. */
std::vector<BankBlurOperator::AxisWeight> tentWeights(const std::vector<double>& z, int length)
{
    std::vector<BankBlurOperator::AxisWeight> weights(size_t(std::max(length, 0)));
    const int last = int(z.size()) - 1;
    int k = 0;
    for (int t = 0; t < length; t++)
    {
        BankBlurOperator::AxisWeight& w = weights[size_t(t)];
        if (last <= 0 || t <= z[0])
        {
            w.weight[0] = 1.f;
            continue;
        }
        if (t >= z[size_t(last)])
        {
            w.node[0] = w.node[1] = last;
            w.weight[0] = 1.f;
            continue;
        }
        while (k + 1 < last && t >= z[size_t(k + 1)])
            k++;
        const double a = (z[size_t(k + 1)] - t) / (z[size_t(k + 1)] - z[size_t(k)]);
        w.node[0] = k;
        w.node[1] = k + 1;
        w.weight[0] = float(a);
        w.weight[1] = float(1.0 - a);
    }
    return weights;
}

namespace {

//! For each node, the range of coordinates where its weight is positive.
std::vector<Range> supports(const std::vector<BankBlurOperator::AxisWeight>& weights, int nodes)
{
    std::vector<Range> result(size_t(nodes), Range(0, 0));
    std::vector<bool> seen(size_t(nodes), false);
    for (int t = 0; t < int(weights.size()); t++)
        for (int k = 0; k < 2; k++)
        {
            if (weights[size_t(t)].weight[k] <= 0.f)
                continue;
            const size_t n = size_t(weights[size_t(t)].node[k]);
            if (!seen[n])
                result[n] = Range(t, t + 1);
            result[n].end = t + 1;
            seen[n] = true;
        }
    return result;
}

// The inner loops: contiguous, restrict-qualified so the compiler vectorises them.
inline void accumulateScaled(float* __restrict dst, const float* __restrict src, float w, int begin, int end)
{
    for (int x = begin; x < end; x++)
        dst[x] += w * src[x];
}

inline void multiplyInto(float* __restrict dst, const float* __restrict a, const float* __restrict b, int n)
{
    for (int x = 0; x < n; x++)
        dst[x] = a[x] * b[x];
}

}  // namespace

BankBlurOperator::BankBlurOperator(const PsfBank& bank, bool pad) : frame_(bank.imageSize)
{
    nodeCols_ = int(bank.nodeCols.size());
    nodeRows_ = int(bank.nodeRows.size());
    nodes_.resize(bank.kernels.size());
    int dxMin = 0, dxMax = 0, dyMin = 0, dyMax = 0;
    for (size_t n = 0; n < bank.kernels.size(); n++)
    {
        Mat kernel;
        bank.kernels[n].convertTo(kernel, CV_32F);
        const int cx = (kernel.cols - 1) / 2, cy = (kernel.rows - 1) / 2;
        const Point s = bank.shifts[n];
        Node& node = nodes_[n];
        bool first = true;
        for (int v = 0; v < kernel.rows; v++)
        {
            TapRow row;
            row.dy = -(s.y + v - cy);
            for (int u = 0; u < kernel.cols; u++)
            {
                const float w = kernel.at<float>(v, u);
                if (w == 0.f)
                    continue;  // motion kernels are mostly empty: skip, do not multiply by zero
                const int dx = -(s.x + u - cx);
                row.dx.push_back(dx);
                row.weight.push_back(w);
                dxMin = std::min(dxMin, dx);
                dxMax = std::max(dxMax, dx);
            }
            if (row.dx.empty())
                continue;
            node.dyMin = first ? row.dy : std::min(node.dyMin, row.dy);
            node.dyMax = first ? row.dy : std::max(node.dyMax, row.dy);
            first = false;
            dyMin = std::min(dyMin, row.dy);
            dyMax = std::max(dyMax, row.dy);
            node.rows.push_back(std::move(row));
        }
    }
    if (pad)
    {
        origin_ = Point(-dxMin, -dyMin);
        latent_ = Size(frame_.width + dxMax - dxMin, frame_.height + dyMax - dyMin);
    }
    else
    {
        latent_ = frame_;
    }

    rowWeights_ = tentWeights(bank.nodeRows, frame_.height);
    nodeRowSupport_ = supports(rowWeights_, nodeRows_);
    const std::vector<AxisWeight> colWeights = tentWeights(bank.nodeCols, frame_.width);
    nodeColSupport_ = supports(colWeights, nodeCols_);
    colWeight_.resize(size_t(nodeCols_));
    for (int i = 0; i < nodeCols_; i++)
    {
        const Range r = nodeColSupport_[size_t(i)];
        colWeight_[size_t(i)].assign(size_t(r.size()), 0.f);
        for (int x = r.start; x < r.end; x++)
            for (int k = 0; k < 2; k++)
                if (colWeights[size_t(x)].node[k] == i)
                    colWeight_[size_t(i)][size_t(x - r.start)] += colWeights[size_t(x)].weight[k];
    }
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
    const int width = frame_.width;
    std::vector<float> tile(nodeCols_ > 1 ? size_t(width) : 0);
    for (int ly = rows.start; ly < rows.end; ly++)
    {
        float* out = latent.ptr<float>(ly);
        std::memset(out, 0, sizeof(float) * size_t(latent_.width));
        const int qy = ly - origin_.y;  // frame coordinate of this latent row
        for (int j = 0; j < nodeRows_; j++)
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
                for (const TapRow& tr : node.rows)
                {
                    const int r = qy - tr.dy;
                    if (r < support.start || r >= support.end)
                        continue;
                    const float a = rowWeight(j, r);
                    if (a <= 0.f)
                        continue;
                    const float* src = frame.ptr<float>(r);
                    if (nodeCols_ > 1)
                    {
                        multiplyInto(tile.data() + cols.start, colWeight_[size_t(i)].data(), src + cols.start,
                                     cols.size());
                        src = tile.data();
                    }
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
