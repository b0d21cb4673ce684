// SPDX-License-Identifier: Apache-2.0
// Private: the bank's displacement alone, which the restoration's start undoes.
#ifndef OPENCV_DYNBLUR_RESTORE_DISPLACEMENT_HPP
#define OPENCV_DYNBLUR_RESTORE_DISPLACEMENT_HPP

#include "opencv2/dynblur/psf.hpp"

#include <functional>
#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The bank's displacement alone, which the restoration's start undoes: each node's shift
moved to its kernel's centroid (rounded to a pixel), as if the kernel were one tap there. */
std::vector<Point> displacementShifts(const PsfBank& bank);

/** @brief Bᵀ applied at once to each plane of `frames` (the bank's frame size, CV_32F) and to a
plane of ones, row by row, where B is the blur of `bank` with every kernel one tap of 1 at its
node's `shifts` (displacementShifts()): frame pixel p reads latent pixel p − shift + `origin`,
blended across node rows and columns as every bank operator blends them. The latent domain is
`latentSize` with the frame at `origin` (another operator's, so the rows land in its domain); what
falls outside it is left out. Calls rowDone(row, weight, adjoints) once per latent row, rows in
parallel: `weight` is the row of Bᵀ1 and adjoints[p] that of Bᵀ frames[p], latentSize.width values
each, valid until rowDone returns. Equals the adjoint of createBankOperator on that one-tap bank up
to float rounding, for a fraction of its cost and without a plane of its own. */
void displacementAdjoint(const PsfBank& bank, const std::vector<Point>& shifts, Size latentSize, Point origin,
                         const std::vector<Mat>& frames,
                         const std::function<void(int, const float*, const float* const*)>& rowDone);


}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
