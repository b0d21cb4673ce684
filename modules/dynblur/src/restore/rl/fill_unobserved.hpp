// SPDX-License-Identifier: Apache-2.0
// Private: unobserved pixels of a restoration filled from the nearest observed ones.
#ifndef OPENCV_DYNBLUR_RESTORE_FILL_UNOBSERVED_HPP
#define OPENCV_DYNBLUR_RESTORE_FILL_UNOBSERVED_HPP

#include <opencv2/core.hpp>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief Pixels where `valid` is 0 take the value of the nearest valid pixel (Euclidean, as
OpenCV's labelled distance transform with its 5×5 mask measures it), so unobserved content reads
as a smooth continuation instead of a hole. Nothing changes when no pixel is valid.
@param image CV_32F, any number of channels. @param valid CV_8U, image's size, nonzero where valid. */
CV_EXPORTS void fillFromNearest(Mat& image, const Mat& valid);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
