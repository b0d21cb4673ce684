// SPDX-License-Identifier: Apache-2.0
// Private: the sRGB curve's table and row encoder, for passes that decode or encode 8-bit frames in their own rows.
#ifndef OPENCV_DYNBLUR_IMAGING_SRGB_HPP
#define OPENCV_DYNBLUR_IMAGING_SRGB_HPP

#include <opencv2/core.hpp>

namespace cv {
namespace dynblur {
namespace detail {

//! The linear intensity of each 8-bit sRGB code, 256 values (srgbToLinear's table).
const float* srgbDecodingTable();

/** out[x] = the 8-bit sRGB code of linear[x] (clamped to [0, 1], NaN as 0), 255·srgb rounded to
nearest: linearToSrgb's rows, for passes that write an 8-bit frame straight from their own rows. */
void encodeSrgbRow(const float* linear, int n, uchar* out);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
