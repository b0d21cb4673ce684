// SPDX-License-Identifier: Apache-2.0
// The pinhole projection's out-of-line part: the mount rotation and a camera model's pinhole.
#include "precomp.hpp"

#include "imaging/pinhole.hpp"
#include "motion/axis_rotation.hpp"

namespace cv {
namespace dynblur {
namespace detail {

Matx33d Pinhole::rotation(double angle) const
{
    return axisRotation(axis, angle);
}

Pinhole pinholeOf(const CameraModel& camera)
{
    return Pinhole{camera.getFx(), camera.getFy(), camera.getCx(), camera.getCy(), camera.getKud(), camera.getKdu(),
                   camera.getMountAxis()};
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
