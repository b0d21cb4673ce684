// SPDX-License-Identifier: Apache-2.0
// Private: the blur of a bank with one node column, as row gathers.
#ifndef OPENCV_DYNBLUR_RESTORE_ROW_BANK_OPERATOR_HPP
#define OPENCV_DYNBLUR_RESTORE_ROW_BANK_OPERATOR_HPP

#include "restore/operators/blur_operator.hpp"
#include "restore/operators/row_gathers.hpp"

namespace cv {
namespace dynblur {
namespace detail {

/** @brief A bank with one node column (PSF_ROWS, or one kernel): every pixel of a frame row shares
one kernel, the tent blend of its two row nodes' kernels, so a row of A·x is a weighted sum of
shifted latent rows and a row of Aᵀ·y a weighted sum of shifted frame rows. Both directions are
gathers over tap lists merged once per row (the adjoint's are the forward's, transposed), summed
in registers over 64 columns at a time, a few rows at a time in column chunks that keep their
source rows in L1, so each output row is written once and a delta kernel costs one pass. Domains
and padding as BankBlurOperator. The bank is trusted (validated by the caller). */
class CV_EXPORTS RowBankOperator CV_FINAL : public BlurOperator
{
public:
    //! `packed`: bfloat16 packed planes and weights (gathersPackedRows), float otherwise.
    RowBankOperator(const PsfBank& bank, bool pad, bool packed = false);
    void forward(const Mat& latent, Mat& frame) CV_OVERRIDE { forwardByBlocks(latent, frame); }
    void adjoint(const Mat& frame, Mat& latent) CV_OVERRIDE { adjointByBlocks(frame, latent); }
    bool gathersRows() const CV_OVERRIDE { return !packed_; }
    void forwardBlock(const Mat& latent, const Range& frameRows, float* out, size_t outStep) const CV_OVERRIDE;
    void adjointBlock(const Mat& frame, const Range& latentRows, float* out, size_t outStep) const CV_OVERRIDE;
    void forwardPackedBlock(const Mat& packedLatent, const Range& frameRows, float* out,
                            size_t outStep) const CV_OVERRIDE;
    void adjointPackedBlock(const Mat& packedFrame, const Range& latentRows, float* out,
                            size_t outStep) const CV_OVERRIDE;
    /** Every row of a row bank's Aᵀ1 holds one value between the columns where all its taps read
    inside the frame: those are filled with it, and only the columns near the edges are gathered.
    The result is the full gather's to the bit (a tap's weight times one is exact, so every such
    column sums the same values in the same order). */
    void adjointOfOnes(Mat& latent, Mat& ones) CV_OVERRIDE;

private:
    RowGathers gathers_;
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
