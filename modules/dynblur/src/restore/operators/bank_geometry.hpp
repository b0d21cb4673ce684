// SPDX-License-Identifier: Apache-2.0
// Private: where a PsfBank's kernels apply (blending weights along node rows and columns), its kernels as read offsets, and its latent domain.
#ifndef OPENCV_DYNBLUR_RESTORE_BANK_GEOMETRY_HPP
#define OPENCV_DYNBLUR_RESTORE_BANK_GEOMETRY_HPP

#include "opencv2/dynblur/psf.hpp"

#include <memory>
#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! Blending weight along one axis: up to two (node index, weight) pairs per coordinate.
struct AxisWeight
{
    int node[2] = {0, 0};
    float weight[2] = {0.f, 0.f};
};

/** @brief The PsfBank blending weights along its node rows of every row in [0, height): the bilinear
tent between the two nodes around it, constant beyond the outermost nodes. Shared by the spatial
operators and the Wiener path, like nodeColumnWeights. */
std::vector<AxisWeight> nodeRowWeights(const PsfBank& bank, int height);

/** @brief The PsfBank blending weights along its node columns of every column in [0, width): 1 for
the nearer node column except over the middle half of the interval between two, where they move
linearly from one to the other (kColumnBlendTransition); constant beyond the outermost nodes. */
std::vector<AxisWeight> nodeColumnWeights(const PsfBank& bank, int width);

/** The fraction of each interval between node columns over which the blend moves from one node's
kernel to the next (1 would be the bilinear tent). A tile gather computes every pixel once per
node column whose weight there is positive: two node columns for every pixel with the tent, 1.5 on
average with a transition over half the interval (BM_FrameRatePaired's tile-wise frame measures
it). PsfGenerator spaces an automatic bank's node columns for neighbouring paths to differ by
0.4 px (up to 16 columns); DeblurQuality's tile-wise figures moved by at most 0.07 dB against the
tent. Node rows (one to two pixels apart in an automatic bank) keep the tent. */
constexpr double kColumnBlendTransition = 0.5;

//! For each node, the range of coordinates where its weight is positive.
std::vector<Range> supports(const std::vector<AxisWeight>& weights, int nodes);

//! Each node's weights over its support (`support` from supports()).
std::vector<std::vector<float>> supportWeights(const std::vector<AxisWeight>& weights, const std::vector<Range>& support);

//! One non-zero kernel element as a read offset: frame pixel p reads latent p + (dx, dy).
struct KernelTap
{
    int dy, dx;
    float weight;
};

/* The non-zero taps of a kernel with its shift, in (dy, dx) order, written from `out` on: the
   kernel walked backwards, since a read offset is the negated kernel position. Returns the end. */
KernelTap* writeKernelTaps(const Mat& kernel32f, Point shift, KernelTap* out);

//! writeKernelTaps into a list of its own.
std::vector<KernelTap> kernelTaps(const Mat& kernel32f, Point shift);

/* Every node's kernel as taps (writeKernelTaps) in one table, node columns one after the other (a
   tile operator walks down one node column at a time), nodes in parallel; the offsets' reach
   (each range includes 0) and the kernels' smallest peak (bankSpotGain's, without a pass of its
   own). One table instead of a list per node: a tile bank holds ~10⁴ kernels, and a list each
   would be as many allocations, read from all over the heap by the walk down a column. */
class NodeTaps
{
public:
    NodeTaps(const PsfBank& bank, int& dxMin, int& dxMax, int& dyMin, int& dyMax);
    //! The smallest of the kernels' peaks (their largest elements), at most 1.
    double smallestPeak() const { return smallestPeak_; }
    //! Node n's taps (n = node row · node columns + node column, as in the bank).
    const KernelTap* taps(int n) const { return taps_.get() + start_[slot(n)]; }
    size_t count(int n) const { return size_t(start_[slot(n) + 1] - start_[slot(n)]); }

private:
    size_t slot(int n) const { return size_t(n % nodeCols_) * size_t(nodeRows_) + size_t(n / nodeCols_); }
    int nodeCols_, nodeRows_;
    double smallestPeak_ = 1;
    std::vector<int> start_;  // by slot
    std::unique_ptr<KernelTap[]> taps_;
};

/* The latent domain: with padding, the bounding box of every pixel a tap reads (offsets in
   [dxMin, dxMax] × [dyMin, dyMax], which include 0); otherwise the frame. */
void domain(Size frame, bool pad, int dxMin, int dxMax, int dyMin, int dyMax, Size& latent, Point& origin);

//! bankSpotGain, given the smallest of the kernels' peaks.
double spotGainOf(const PsfBank& bank, double smallestPeak);

/** @brief spotGain of a bank: blended kernels per pixel / the smallest kernel peak. */
double bankSpotGain(const PsfBank& bank);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
