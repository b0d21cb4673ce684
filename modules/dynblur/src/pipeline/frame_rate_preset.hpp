// SPDX-License-Identifier: Apache-2.0
// Private: DEBLUR_PRESET_FRAME_RATE's Richardson–Lucy settings, and its iterations by need.
#ifndef OPENCV_DYNBLUR_FRAME_RATE_PRESET_HPP
#define OPENCV_DYNBLUR_FRAME_RATE_PRESET_HPP

#include "opencv2/dynblur/deconv.hpp"
#include "opencv2/dynblur/psf.hpp"

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The preset's settings before a frame is seen: its most iterations, the automatic stop,
bfloat16 blurs, the least color iterations (frameRateIterations sets each frame's counts). */
RLParams frameRatePresetParams();

/** @brief N = 1 / Σk² of the bank's most spread kernel, pixels (at least 1): how many pixels a point's
light is spread over (a uniform line of n pixels: N ≈ n; one tap holding most of the light: N ≈ 1). */
CV_EXPORTS double mostSpreadKernelPx(const PsfBank& bank);

/** @brief The preset's iterations for a frame blurred as `bank`, from its longest kernel L (pixels)
and its most spread one's N (mostSpreadKernelPx; by Parseval 1 / N is the mean of |K(f)|², so N says
how much the blur takes away). Up to L = 8 px, 8 iterations, every one in color at full resolution;
beyond, 10 iterations where N ≤ 12 px and L ≤ 32 px, else 20, and the color takes one iteration per 6.5 px of L,
from 3 to 14, at half resolution (docs/quality.md, "PSF_AUTO and the frame-rate preset").
@param bank the frame's PSF bank.
@param params the preset's settings (frameRatePresetParams), whose other fields are kept. */
RLParams frameRateIterations(const PsfBank& bank, const RLParams& params);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
