// SPDX-License-Identifier: Apache-2.0
// Private: a PsfBank's blur in its plainest form, each node's taps scattered: what the gathering operators are held to.
#ifndef OPENCV_DYNBLUR_RESTORE_BANK_OPERATOR_HPP
#define OPENCV_DYNBLUR_RESTORE_BANK_OPERATOR_HPP

#include "restore/operators/blur_operator.hpp"
#include "restore/operators/bank_geometry.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The PsfBank's blended blur B(p) = Σ_n w_n(p) Σ_u k_n(u) L(p − s_n − (u − c)), applied
in the spatial domain as sparse taps (zero taps skipped, shifts are index offsets), rows in
parallel. With `pad` the latent domain is the bounding box of every pixel any tap reads (the
kernels' reach, shifts included); otherwise it is the frame and reads outside it are zero.
The bank is trusted (validated by the caller). This is the operator in its plainest form (each
node's taps scattered); createBankOperator picks the gathering ones below, and the tests hold them
to it. */
class CV_EXPORTS BankBlurOperator CV_FINAL : public BlurOperator
{
public:
    BankBlurOperator(const PsfBank& bank, bool pad);
    void forward(const Mat& latent, Mat& frame) CV_OVERRIDE;
    void adjoint(const Mat& frame, Mat& latent) CV_OVERRIDE;

    struct TapRow
    {
        int dy = 0;               // latent row read = frame row + dy
        std::vector<int> dx;      // latent col read = frame col + dx
        std::vector<float> weight;
    };
    struct Node
    {
        std::vector<TapRow> rows;
        int dyMin = 0, dyMax = 0;
        std::vector<int> rowOfDy;  // index into rows of each dy in [dyMin, dyMax], -1 where none
    };
private:
    void forwardRows(const Mat& latent, Mat& frame, const Range& rows) const;
    void adjointRows(const Mat& frame, Mat& latent, const Range& rows) const;
    float rowWeight(int nodeRow, int frameRow) const;

    int nodeCols_ = 1, nodeRows_ = 1;
    int dyMin_ = 0, dyMax_ = 0;  // the bank's range of row offsets (latent row − frame row)
    std::vector<Node> nodes_;                 // row-major, nodeRows_ × nodeCols_
    std::vector<AxisWeight> rowWeights_;      // per frame row
    std::vector<Range> nodeRowSupport_;       // frame rows where each node row's weight > 0
    std::vector<Range> nodeColSupport_;       // frame cols where each node col's weight > 0
    std::vector<std::vector<float>> colWeight_;  // per node col, weights over its support
    Mat weighted_[2];  // adjoint's input times the even / odd node columns' weights
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
