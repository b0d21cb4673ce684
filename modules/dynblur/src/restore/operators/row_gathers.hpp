// SPDX-License-Identifier: Apache-2.0
// Private: the row gathers of one node column of a bank, both directions, float or packed.
#ifndef OPENCV_DYNBLUR_RESTORE_ROW_GATHERS_HPP
#define OPENCV_DYNBLUR_RESTORE_ROW_GATHERS_HPP

#include "restore/operators/bank_geometry.hpp"
#include "restore/operators/gather.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! Both directions' gathers of a blur whose every frame row has one kernel.
struct RowGathers
{
    Gather forward, adjoint;                     // float mode
    PackedGather packedForward, packedAdjoint;   // packed mode (the float forward is dropped once packed)
};

/** @brief The gathers of frame rows whose kernel is the tent blend (rowWeights) of their two node
rows' kernels in node column `column`: each frame row's taps merged once (forward; reads of latent
rows outside the domain, possible without padding, dropped), and their transpose (adjoint: latent
row l gathers frame row y at column x − col). Frame rows where `frameRows` is not empty and 0 get
no taps, so the adjoint of a latent row they read is incomplete: a TileBankOperator gathers only
its rows whose kernel is the same in every node column this way.
@param nodes the bank's kernels as taps; node (j, i) is nodes.taps(j · nodeCols + i).
@param packed bfloat16 packed gathers (the adjoint reads a packed frame of frame.width columns). */
RowGathers buildRowGathers(const NodeTaps& nodes, int nodeCols, int column, const std::vector<AxisWeight>& rowWeights,
                           Size frame, Size latent, Point origin, bool packed,
                           const std::vector<uchar>& frameRows = std::vector<uchar>());

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
