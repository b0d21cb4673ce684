// SPDX-License-Identifier: Apache-2.0
// Private: the timing of a frame halved (DEBLUR_COLOR_HALF_RESOLUTION, the refinement's pyramid).
#ifndef OPENCV_DYNBLUR_MOTION_HALF_SHUTTER_HPP
#define OPENCV_DYNBLUR_MOTION_HALF_SHUTTER_HPP

#include <opencv2/dynblur/shutter.hpp>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The timing of a frame halved as halfResolutionCamera's: half-size row r averages sensor
rows 2r and 2r + 1, whose exposures start a line delay apart, so it starts half a line delay after
row 2r, and the next half-size row two line delays later. The pair's average exposure has the
same length (its support is a line delay longer; at a C270's 35 µs against milliseconds of
exposure the difference is not resolved by the kernels). @param shutter the frame's timing, an
even number of rows. */
CV_EXPORTS RollingShutter halfResolutionShutter(const RollingShutter& shutter);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
