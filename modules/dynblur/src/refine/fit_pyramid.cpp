// SPDX-License-Identifier: Apache-2.0
// The fit's images: a frame's linear luminance and its halvings, with the camera and shutter of each.
#include "precomp.hpp"

#include "imaging/camera_frame.hpp"
#include "imaging/half_camera.hpp"
#include "motion/half_shutter.hpp"
#include "refine/fit_pyramid.hpp"
#include "restore/deconv_rl.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

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

int levelAtMostWide(const LuminancePyramid& pyramid, int width)
{
    for (int level = 0; level < pyramid.levels(); level++)
        if (pyramid.images[size_t(level)].cols <= width)
            return level;
    return pyramid.levels() - 1;
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

std::vector<double> measureNoise(const Mat& stillA, const Mat& stillB, const Ptr<CameraModel>& camera,
                                 const char* function)
{
    checkCameraFrame(stillA, *camera, function, "stillA");
    checkCameraFrame(stillB, *camera, function, "stillB");
    if (stillA.type() != stillB.type())
        CV_Error(Error::StsUnmatchedFormats,
                 format("%s: 'stillA' is %s but 'stillB' is %s; both must come from the frames' stream", function,
                        typeToString(stillA.type()).c_str(), typeToString(stillB.type()).c_str()));
    const LuminancePyramid a = buildPyramid(linearLuminance(stillA), camera, kFitCoarseWidth, false);
    const LuminancePyramid b = buildPyramid(linearLuminance(stillB), camera, kFitCoarseWidth, false);
    // At or above this (linear) a pixel may be clipped: the difference there is not the noise.
    const float saturated = 0.99f;
    std::vector<double> sigma;
    std::vector<float> values;
    for (int level = 0; level < a.levels(); level++)
    {
        const Mat& first = a.images[size_t(level)];
        const Mat& second = b.images[size_t(level)];
        values.clear();
        for (int y = 0; y < first.rows; y++)
        {
            const float* p = first.ptr<float>(y);
            const float* q = second.ptr<float>(y);
            for (int x = 0; x < first.cols; x++)
                if (p[x] < saturated && q[x] < saturated)
                    values.push_back(p[x] - q[x]);
        }
        double deviation = 0;
        if (!values.empty())
        {
            const auto middle = values.begin() + std::ptrdiff_t(values.size() / 2);
            std::nth_element(values.begin(), middle, values.end());
            const float median = *middle;
            for (float& v : values)
                v = std::abs(v - median);
            std::nth_element(values.begin(), middle, values.end());
            // 1.4826 × MAD is a normal distribution's standard deviation; the difference holds two frames' noise.
            deviation = 1.4826 * double(*middle) / std::sqrt(2.0);
        }
        // Only the levels the fit runs at count: a clean camera's 8-bit stills may agree at full size.
        if (!(deviation > 0) && (first.cols <= kFitFineWidth || level + 1 == a.levels()))
            CV_Error(Error::StsBadArg,
                     format("%s: 'stillA' and 'stillB' are equal in at least half of their unclipped pixels at "
                            "%dx%d px: their difference measures no noise; give two separate captures of the same "
                            "view",
                            function, first.cols, first.rows));
        sigma.push_back(deviation);
    }
    return sigma;
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
