// SPDX-License-Identifier: Apache-2.0
#include "restore/operators/bank_geometry.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <mutex>

namespace cv {
namespace dynblur {
namespace detail {

namespace {

/* Blending weights of every integer coordinate in [0, length) between nodes `z` (increasing):
   between two nodes, linear over the middle `transition` of the interval and constant (the nearer
   node) outside it, so transition 1 is the bilinear tent; constant beyond the outermost nodes.
   They sum to 1 everywhere. */
std::vector<AxisWeight> axisWeights(const std::vector<double>& z, int length, double transition)
{
    std::vector<AxisWeight> weights(size_t(std::max(length, 0)));
    const int last = int(z.size()) - 1;
    int k = 0;
    for (int t = 0; t < length; t++)
    {
        AxisWeight& w = weights[size_t(t)];
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
        double a = (z[size_t(k + 1)] - t) / (z[size_t(k + 1)] - z[size_t(k)]);
        if (transition < 1)
            a = std::min(std::max((a - 0.5) / transition + 0.5, 0.0), 1.0);
        w.node[0] = k;
        w.node[1] = k + 1;
        w.weight[0] = float(a);
        w.weight[1] = float(1.0 - a);
    }
    return weights;
}

}  // namespace

std::vector<AxisWeight> nodeRowWeights(const PsfBank& bank, int height)
{
    return axisWeights(bank.nodeRows, height, 1.0);
}

std::vector<AxisWeight> nodeColumnWeights(const PsfBank& bank, int width)
{
    return axisWeights(bank.nodeCols, width, kColumnBlendTransition);
}

//! For each node, the range of coordinates where its weight is positive.
std::vector<Range> supports(const std::vector<AxisWeight>& weights, int nodes)
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

//! Each node's weights over its support (`support` from supports()).
std::vector<std::vector<float>> supportWeights(const std::vector<AxisWeight>& weights,
                                               const std::vector<Range>& support)
{
    std::vector<std::vector<float>> result(support.size());
    for (size_t i = 0; i < support.size(); i++)
    {
        const Range r = support[i];
        result[i].assign(size_t(r.size()), 0.f);
        for (int t = r.start; t < r.end; t++)
            for (int k = 0; k < 2; k++)
                if (weights[size_t(t)].node[k] == int(i))
                    result[i][size_t(t - r.start)] += weights[size_t(t)].weight[k];
    }
    return result;
}

KernelTap* writeKernelTaps(const Mat& kernel32f, Point shift, KernelTap* out)
{
    const int cx = (kernel32f.cols - 1) / 2, cy = (kernel32f.rows - 1) / 2;
    for (int v = kernel32f.rows - 1; v >= 0; v--)
    {
        const float* row = kernel32f.ptr<float>(v);
        for (int u = kernel32f.cols - 1; u >= 0; u--)
            if (row[u] != 0.f)  // skip, do not multiply by zero
                *out++ = {-(shift.y + v - cy), -(shift.x + u - cx), row[u]};
    }
    return out;
}

std::vector<KernelTap> kernelTaps(const Mat& kernel32f, Point shift)
{
    std::vector<KernelTap> taps(size_t(countNonZero(kernel32f)));  // motion kernels are mostly empty
    writeKernelTaps(kernel32f, shift, taps.data());
    return taps;
}

void domain(Size frame, bool pad, int dxMin, int dxMax, int dyMin, int dyMax, Size& latent, Point& origin)
{
    latent = frame;
    origin = Point();
    if (pad)
    {
        origin = Point(-dxMin, -dyMin);
        latent = Size(frame.width + dxMax - dxMin, frame.height + dyMax - dyMin);
    }
}

double spotGainOf(const PsfBank& bank, double smallestPeak)
{
    const double blended = double(std::min<size_t>(bank.nodeRows.size(), 2) * std::min<size_t>(bank.nodeCols.size(), 2));
    return smallestPeak > 0 ? blended / smallestPeak : 1.0;
}

double bankSpotGain(const PsfBank& bank)
{
    // A tile bank holds ~10⁴ kernels: their peaks in parallel.
    std::mutex mutex;
    double smallestPeak = 1;
    parallel_for_(Range(0, int(bank.kernels.size())), [&](const Range& range) {
        double smallest = 1;
        for (int n = range.start; n < range.end; n++)
        {
            double peak = 0;
            minMaxLoc(bank.kernels[size_t(n)], nullptr, &peak);
            smallest = std::min(smallest, peak);
        }
        std::lock_guard<std::mutex> lock(mutex);
        smallestPeak = std::min(smallestPeak, smallest);
    });
    return spotGainOf(bank, smallestPeak);
}

NodeTaps::NodeTaps(const PsfBank& bank, int& dxMin, int& dxMax, int& dyMin, int& dyMax)
    : nodeCols_(int(bank.nodeCols.size())), nodeRows_(int(bank.nodeRows.size())),
      start_(bank.kernels.size() + 1, 0)
{
    const int nodes = int(bank.kernels.size());
    parallel_for_(Range(0, nodes), [&](const Range& r) {
        for (int n = r.start; n < r.end; n++)
            start_[slot(n) + 1] = countNonZero(bank.kernels[size_t(n)]);
    });
    for (size_t i = 1; i < start_.size(); i++)
        start_[i] += start_[i - 1];
    // Left uninitialised: every tap is written below, and a tile bank's table is megabytes.
    taps_.reset(new KernelTap[size_t(start_.back())]);
    std::mutex mutex;
    dxMin = dxMax = dyMin = dyMax = 0;
    parallel_for_(Range(0, nodes), [&](const Range& r) {
        int reach[4] = {0, 0, 0, 0};  // dxMin, dxMax, dyMin, dyMax of these nodes
        float smallest = 1;
        for (int n = r.start; n < r.end; n++)
        {
            KernelTap* const first = taps_.get() + start_[slot(n)];
            KernelTap* const last = writeKernelTaps(bank.kernels[size_t(n)], bank.shifts[size_t(n)], first);
            float peak = 0;  // the kernel's largest element, zeros included
            for (const KernelTap* t = first; t < last; t++)
            {
                reach[0] = std::min(reach[0], t->dx);
                reach[1] = std::max(reach[1], t->dx);
                reach[2] = std::min(reach[2], t->dy);
                reach[3] = std::max(reach[3], t->dy);
                peak = std::max(peak, t->weight);
            }
            smallest = std::min(smallest, peak);
        }
        std::lock_guard<std::mutex> lock(mutex);
        dxMin = std::min(dxMin, reach[0]);
        dxMax = std::max(dxMax, reach[1]);
        dyMin = std::min(dyMin, reach[2]);
        dyMax = std::max(dyMax, reach[3]);
        smallestPeak_ = std::min(smallestPeak_, double(smallest));
    });
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
