// SPDX-License-Identifier: Apache-2.0
// The fit's images: a frame's linear luminance and its halvings, with the camera and shutter of each.
#include "precomp.hpp"

#include "pipeline/half_color.hpp"
#include "pipeline/motion_fit.hpp"
#include "restore/deconv_rl.hpp"

#include <opencv2/imgproc.hpp>

namespace cv {
namespace dynblur {
namespace detail {

Mat linearLuminance(const Mat& frame)
{
    Mat linear = frame;
    if (frame.depth() == CV_8U)
        srgbToLinear(frame, linear);
    if (linear.channels() == 1)
        return linear;
    Mat weights = Mat::zeros(1, linear.channels(), CV_32F);
    weights.colRange(0, 3).setTo(1.0 / 3);  // color only: alpha is coverage, not light
    Mat luminance;
    transform(linear, luminance, weights);
    return luminance;
}

LuminancePyramid buildPyramid(const Mat& luminance, const Ptr<CameraModel>& camera, int coarsestWidth,
                              bool estimateNoise)
{
    LuminancePyramid pyramid;
    pyramid.images.push_back(luminance);
    pyramid.cameras.push_back(camera);
    while (pyramid.images.back().cols > coarsestWidth && pyramid.images.back().cols % 2 == 0 &&
           pyramid.images.back().rows % 2 == 0)
    {
        Mat half;
        resize(pyramid.images.back(), half, Size(), 0.5, 0.5, INTER_AREA);
        pyramid.cameras.push_back(halfResolutionCamera(*pyramid.cameras.back()));
        pyramid.images.push_back(half);
    }
    if (estimateNoise)
    {
        std::vector<Mat> pool;
        for (const Mat& image : pyramid.images)
            pyramid.noiseSigma.push_back(observeFrame(image, pool, true).noiseSigma);
    }
    return pyramid;
}

RollingShutter shutterAtLevel(const RollingShutter& shutter, int halvings)
{
    RollingShutter result = shutter;
    for (int k = 0; k < halvings; k++)
        result = halfResolutionShutter(result);
    return result;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
