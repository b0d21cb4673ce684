// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"

#include "imaging/camera_frame.hpp"
#include "restore/rl/frame_planes.hpp"

namespace cv {
namespace dynblur {
namespace detail {

void checkCameraFrame(const Mat& image, const CameraModel& camera, const char* function, const char* name)
{
    if (image.empty())
        CV_Error(Error::StsBadArg, format("%s: '%s' is empty", function, name));
    if (image.depth() != CV_8U && image.depth() != CV_32F)
        CV_Error(Error::StsUnsupportedFormat,
                 format("%s: '%s' type %s is not supported; use CV_8U (sRGB) or CV_32F (linear, [0,1])", function,
                        name, typeToString(image.type()).c_str()));
    if (image.channels() != 1 && image.channels() != 3 && image.channels() != 4)
        CV_Error(Error::StsUnsupportedFormat,
                 format("%s: '%s' has %d channels; 1, 3 or 4 are supported", function, name, image.channels()));
    const Size expected = camera.getImageSize();
    if (image.size() != expected)
        CV_Error(Error::StsBadSize, format("%s: '%s' is %dx%d but the camera model is %dx%d", function, name,
                                           image.cols, image.rows, expected.width, expected.height));
    if (image.depth() != CV_32F)
        return;
    // A float frame is linear intensity in [0, 1] (1 = full well), as a sensor delivers it. Only
    // float round-off (a renderer's 1 + 1e-7) passes the bounds.
    const float roundOff = 1e-4f;
    float low = 0, high = 0;
    if (!finiteRange(image, low, high))
        CV_Error(Error::StsBadArg, format("%s: '%s' holds NaN or Inf values", function, name));
    if (low < -roundOff || high > 1 + roundOff)
        CV_Error(Error::StsOutOfRange,
                 format("%s: a CV_32F '%s' must hold linear intensities in [0, 1] (clip noisy data first, as a "
                        "sensor does); its values span [%g, %g]",
                        function, name, low, high));
}

}  // namespace detail

}  // namespace dynblur
}  // namespace cv
