// SPDX-License-Identifier: Apache-2.0
// Private: planes and gathers packed as bfloat16 row pairs.
#ifndef OPENCV_DYNBLUR_RESTORE_PACKED_GATHER_HPP
#define OPENCV_DYNBLUR_RESTORE_PACKED_GATHER_HPP

#include "restore/operators/gather.hpp"

#include <opencv2/core.hpp>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief packRowPair over every row pair of `plane` (CV_32FC1) into `packed` (CV_32SC1,
⌈rows / 2⌉ × cols), pairs in parallel. */
CV_EXPORTS void packPlane(const Mat& plane, Mat& packed);

/** @brief Rows 2k and 2k + 1 of a plane, plus `offset`, as bfloat16 (rounded to nearest even) in
the low and high halves of out[x], x in [0, n): the packed sources of gathersPackedRows().
`second` null: the high halves are 0 (the last row of an odd height). */
CV_EXPORTS void packRowPair(const float* first, const float* second, float offset, int n, uint32_t* out);

/** @brief The packed form of a float gather whose rows are filled, each row's taps in (row, col)
order: output rows 2k and 2k + 1 together, each term taking source rows 2j and 2j + 1 at one column
offset, weights rounded to bfloat16. `sourceWidth`: the source's columns. */
void buildPacked(const Gather& gather, int outWidth, int sourceWidth, PackedGather& packed);

/** @brief The packed adjoint of a packed forward gather whose columns are frame column + colBase
(the adjoint's: latent column + adjointColBase), to the bit, in the time of a counting sort. */
void transposePackedGather(const PackedGather& forward, int colBase, int outRows, int adjointColBase, int outWidth,
                           int sourceWidth, PackedGather& adjoint);

//! dst = src ⊙ weight over n packed pairs (both halves of element x times weight[x]), re-rounded.
void scalePackedRow(const uint32_t* src, const float* weight, int n, uint32_t* dst);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
