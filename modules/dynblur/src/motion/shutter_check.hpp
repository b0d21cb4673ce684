// SPDX-License-Identifier: Apache-2.0
// Private: the one check of a RollingShutter's fields, shared by its validate() and the functions
// that take a shutter for a camera's frame.
#ifndef OPENCV_DYNBLUR_MOTION_SHUTTER_CHECK_HPP
#define OPENCV_DYNBLUR_MOTION_SHUTTER_CHECK_HPP

#include "opencv2/dynblur/shutter.hpp"

namespace cv {
namespace dynblur {
namespace detail {

/** @brief Throws cv::Exception naming the first field of `shutter` out of range: frameStart not
finite, exposure or lineDelay not finite and >= 0 (seconds), rows not > 0 or, when imageRows > 0,
not equal to imageRows (the image's height: the camera's, or the frame's). Messages read "<where>: <prefix><field> = ...".
@param where the function named in the message.
@param prefix written before each field's name ("shutter." for an argument, "" for the shutter's own check). */
void checkShutter(const RollingShutter& shutter, const char* where, const char* prefix, int imageRows = 0);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
