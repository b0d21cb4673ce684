// SPDX-License-Identifier: Apache-2.0
// Private: the check that an image is a frame of a camera, shared by every entry point that takes frames.
#ifndef OPENCV_DYNBLUR_IMAGING_CAMERA_FRAME_HPP
#define OPENCV_DYNBLUR_IMAGING_CAMERA_FRAME_HPP

#include <opencv2/dynblur/camera.hpp>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief Throws cv::Exception naming the argument when `image` is not a frame of `camera`: empty,
not CV_8U or CV_32F, not 1, 3 or 4 channels, another size, or (CV_32F) NaN, Inf or outside [0, 1].
@param function prefixes the message. @param name the argument's name. */
void checkCameraFrame(const Mat& image, const CameraModel& camera, const char* function, const char* name);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
