// SPDX-License-Identifier: Apache-2.0
// Private: DynamicDeblurrer's color phase at half resolution (DEBLUR_COLOR_HALF_RESOLUTION).
#ifndef OPENCV_DYNBLUR_HALF_COLOR_HPP
#define OPENCV_DYNBLUR_HALF_COLOR_HPP

#include "imaging/half_camera.hpp"
#include "motion/half_shutter.hpp"

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The two images the color and the luminance are restored from, in one pass over the
frame (reading it twice would cost several times one pass): the frame
halved as cv::resize with INTER_AREA halves it (each 2×2 block's mean), and the mean of each
pixel's channels at full size, the luminance; an 8-bit frame is decoded as it is read, as
srgbToLinear decodes it.
@param frame CV_32FC3 (linear intensity) or CV_8UC3 (sRGB), size W×H (both even).
@param halfColor output, CV_32FC3, (W/2)×(H/2).
@param luminance output, CV_32FC1, W×H. */
CV_EXPORTS void halveAndAverageChannels(const Mat& frame, Mat& halfColor, Mat& luminance);

/** @brief The restored frame from its restored luminance and its color restored at half
resolution: the color is upsampled as cv::resize with INTER_LINEAR does (weights 3/4 and 1/4 at
a factor of 2, edges replicated), and each pixel's channels are scaled by the luminance over their
mean, which keeps the color's chromaticity and gives the pixel the luminance's detail. Where the
mean is at or below `black` the difference is added instead. The result is clamped to [0, 1]. One
pass over rows in parallel: the upsampled color is never stored, nor an 8-bit result's linear values.
@param luminance CV_32FC1, size W×H (both even), linear intensity.
@param halfColor CV_32FC3, size (W/2)×(H/2).
@param black mean below which a pixel takes the luminance's change as a difference, ≥ 0.
@param depth CV_32F: the result in linear intensity; CV_8U: encoded as linearToSrgb encodes it.
@param restored output, W×H, 3 channels of `depth`. */
CV_EXPORTS void combineLuminanceAndHalfColor(const Mat& luminance, const Mat& halfColor, float black, int depth,
                                              const _OutputArray& restored);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
