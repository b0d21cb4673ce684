// SPDX-License-Identifier: Apache-2.0
// Private: the linear blur A that Richardson–Lucy inverts, and its exact adjoint.
#ifndef OPENCV_DYNBLUR_RESTORE_BLUR_OPERATOR_HPP
#define OPENCV_DYNBLUR_RESTORE_BLUR_OPERATOR_HPP

#include "opencv2/dynblur/deconv.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cstdint>
#include <memory>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief A linear blur A from a latent domain (the frame, possibly extended by margins) to the
frame. Latent pixel (x, y) of the array is frame coordinate (x − origin.x, y − origin.y).
Planes are CV_32FC1. */
class CV_EXPORTS BlurOperator
{
public:
    virtual ~BlurOperator() {}
    Size frameSize() const { return frame_; }
    Size latentSize() const { return latent_; }
    Point origin() const { return origin_; }
    //! frame = A · latent
    virtual void forward(const Mat& latent, Mat& frame) = 0;
    //! latent = Aᵀ · frame
    virtual void adjoint(const Mat& frame, Mat& latent) = 0;
    /** The most a latent pixel can hold per unit of the brightest frame pixel: 1 / (the smallest
    weight with which it reaches its most-weighted frame pixel), bounded from the kernels' peaks
    and the number of kernels blended at a pixel. For data A x, x ≤ spotGain · max(A x). */
    double spotGain() const { return spotGain_; }

    /** True when a few rows of A·x (or of Aᵀ·y) can be computed on their own: the RL loop then
    fuses each block of blurred rows with the element-wise work that follows it while the block is
    still in cache. */
    virtual bool gathersRows() const { return false; }
    //! Rows `frameRows` of A · latent, row r at out + (r − frameRows.start)·outStep. Only when gathersRows().
    virtual void forwardBlock(const Mat& /*latent*/, const Range& /*frameRows*/, float* /*out*/, size_t /*outStep*/) const {}
    /** Rows `latentRows` of Aᵀ · frame, laid out likewise. Only when gathersRows(), and after
    prepareAdjoint(frame) for this `frame`. */
    virtual void adjointBlock(const Mat& /*frame*/, const Range& /*latentRows*/, float* /*out*/, size_t /*outStep*/) const {}
    //! Whatever adjointBlock needs of the whole `frame` first (before any block runs).
    virtual void prepareAdjoint(const Mat& /*frame*/) {}

    /** True when the operator works on packed planes (packRowPair: rows 2k and 2k + 1 as the
    bfloat16 halves of one CV_32SC1 row) with bfloat16 weights, summing in float: with AVX512-BF16
    one instruction takes two multiply-adds per lane, twice a float FMA, from half the bytes.
    forward() and adjoint() then pack their input first; gathersRows() is false, and the RL loop
    uses the packed blocks below. */
    bool gathersPackedRows() const { return packed_; }
    /** Rows `frameRows` (starting on an even row) of A · latent, from `packedLatent`, laid out as
    forwardBlock's. Only when gathersPackedRows(). */
    virtual void forwardPackedBlock(const Mat& /*packedLatent*/, const Range& /*frameRows*/, float* /*out*/,
                                    size_t /*outStep*/) const {}
    /** Rows `latentRows` (starting on an even row) of Aᵀ · frame, from the packed frame, after
    prepareAdjointPacked(packedFrame). Only when gathersPackedRows(). */
    virtual void adjointPackedBlock(const Mat& /*packedFrame*/, const Range& /*latentRows*/, float* /*out*/,
                                    size_t /*outStep*/) const {}
    //! Whatever adjointPackedBlock needs of the whole packed frame first.
    virtual void prepareAdjointPacked(const Mat& /*packedFrame*/) {}
    /** True when the RL loop may hand the packed frame over one row pair at a time as it computes
    it (takePackedPair, every pair before the next adjointPackedBlock) instead of as a plane
    through prepareAdjointPacked: the tile operator weights each pair into its node columns'
    copies while the pair is in cache, and no packed plane is written and read back. */
    virtual bool takesPackedPairs() const { return false; }
    /** Row pair `pair` (frame rows 2·pair and 2·pair + 1, packRowPair's layout, frame width) of the
    packed frame the next adjointPackedBlock calls read. Calls for different pairs may run at once.
    Only when takesPackedPairs(). */
    virtual void takePackedPair(int /*pair*/, const uint32_t* /*packedRow*/) {}

    /** latent = Aᵀ1, the adjoint of a frame of ones (RL's normaliser). A packed operator reads the
    ones packed as packPlane would pack them, written straight into `ones` without a float frame.
    @param ones scratch: the frame of ones (packed when gathersPackedRows()), reused when it fits. */
    virtual void adjointOfOnes(Mat& latent, Mat& ones);

protected:
    //! The latent domain starts as the frame; operators with padding grow it.
    explicit BlurOperator(Size frameSize, bool packed = false)
        : frame_(frameSize), latent_(frameSize), packed_(packed)
    {
    }
    /** forward() of an operator that gathers rows: its blocks, in parallel over the frame (packed:
    the latent packed first, then the packed blocks over row pairs). */
    void forwardByBlocks(const Mat& latent, Mat& frame) const;
    //! adjoint() of an operator that gathers rows: prepareAdjoint, then its blocks in parallel (packed: likewise).
    void adjointByBlocks(const Mat& frame, Mat& latent);
    //! adjointByBlocks from the packed frame (gathersPackedRows()).
    void adjointOfPacked(const Mat& packedFrame, Mat& latent);
    //! `ones` = a frame of ones, packed as packPlane packs it when gathersPackedRows().
    void onesFrame(Mat& ones) const;
    Size frame_, latent_;
    bool packed_;
    Point origin_;
    double spotGain_ = 1;
};

//! Row pairs of `rows` in parallel, each part's rows starting on an even row.
template <typename Body>
void forRowPairs(int rows, const Body& body)
{
    parallel_for_(Range(0, (rows + 1) / 2),
                  [&](const Range& pairs) { body(Range(2 * pairs.start, std::min(2 * pairs.end, rows))); });
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
