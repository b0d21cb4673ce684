// SPDX-License-Identifier: Apache-2.0
// Private: the camera of a frame halved (DEBLUR_COLOR_HALF_RESOLUTION, the refinement's pyramid).
#ifndef OPENCV_DYNBLUR_IMAGING_HALF_CAMERA_HPP
#define OPENCV_DYNBLUR_IMAGING_HALF_CAMERA_HPP

#include <opencv2/dynblur/camera.hpp>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief The camera that records `camera`'s frames halved by cv::resize with INTER_AREA: pixel
(u', v') averages pixels 2u'..2u'+1 × 2v'..2v'+1, so its centre is at (2u' + 0.5, 2v' + 0.5) and
u' = (u − 0.5) / 2. Focal lengths halve; the radial coefficients act on normalised coordinates
and stay; the mount axis is copied. @param camera a camera whose image size is even. */
CV_EXPORTS Ptr<CameraModel> halfResolutionCamera(const CameraModel& camera);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
