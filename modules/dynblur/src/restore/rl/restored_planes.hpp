// SPDX-License-Identifier: Apache-2.0
// Private: the restored planes written out as one image, taking the luminance phase's change as they are read.
#ifndef OPENCV_DYNBLUR_RESTORE_RESTORED_PLANES_HPP
#define OPENCV_DYNBLUR_RESTORE_RESTORED_PLANES_HPP

#include <opencv2/core.hpp>

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The luminance phase's result, which the color planes take as they are read out
(applyRow), not in a pass of their own: that would read and write every plane once more. */
struct CV_EXPORTS LuminanceChange
{
    Mat restored;     //!< the restored luminance (latent size); empty when no luminance phase ran
    float black = 0;  //!< where the planes' mean is at or below it, the change is added instead of scaled
    float upper = 0;  //!< the bound the results are kept within (the color phase's projection bound)

    /** @brief Columns [x0, x0 + n) of latent row y of every plane after the change, plane c into
    out[c]. The luminance before the change is the planes' mean, taken from the planes themselves
    into `before` (n floats of scratch). */
    void applyRow(const std::vector<Mat>& planes, int y, int x0, int n, float* before, float* const* out) const;
};

/** @brief out = the planes' `roi` (CV_32F, one size; an empty roi: all of them) interleaved, rows in
parallel. With a luminance change, the planes take it as they are read; with `clampToUnit` the
output is clamped to [0, 1]. */
void writeOutput(const std::vector<Mat>& planes, OutputArray out, bool clampToUnit = false,
                 const LuminanceChange& change = LuminanceChange(), Rect roi = Rect());

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
