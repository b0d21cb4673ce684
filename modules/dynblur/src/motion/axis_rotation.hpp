// SPDX-License-Identifier: Apache-2.0
// Private: a rotation about a unit axis, without cv::Rodrigues's allocations.
#ifndef OPENCV_DYNBLUR_MOTION_AXIS_ROTATION_HPP
#define OPENCV_DYNBLUR_MOTION_AXIS_ROTATION_HPP

#include <opencv2/core.hpp>

#include <cmath>

namespace cv {
namespace dynblur {

//! Rotation of `angle` radians about a unit axis (Rodrigues' formula, without cv::Rodrigues's
//! allocations: PSF generation calls it once per time sample and row).
inline Matx33d axisRotation(const Vec3d& unitAxis, double angle)
{
    const double c = std::cos(angle), s = std::sin(angle), v = 1.0 - c;
    const double x = unitAxis[0], y = unitAxis[1], z = unitAxis[2];
    return Matx33d(c + x * x * v, x * y * v - z * s, x * z * v + y * s,
                   y * x * v + z * s, c + y * y * v, y * z * v - x * s,
                   z * x * v - y * s, z * y * v + x * s, c + z * z * v);
}

}  // namespace dynblur
}  // namespace cv

#endif
