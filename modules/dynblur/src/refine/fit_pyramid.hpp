// SPDX-License-Identifier: Apache-2.0
// Private: the images a fit compares, a frame's linear luminance and its halvings, and their noise.
#ifndef OPENCV_DYNBLUR_REFINE_FIT_PYRAMID_HPP
#define OPENCV_DYNBLUR_REFINE_FIT_PYRAMID_HPP

#include <opencv2/dynblur/camera.hpp>
#include <opencv2/dynblur/shutter.hpp>

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! The fit's two resolutions: the scan and a first fit at most this wide, pixels, then the last fit.
const int kFitCoarseWidth = 160, kFitFineWidth = 320;

/** @brief A linear luminance image and its halvings (cv::resize, INTER_AREA), with the camera of
each: level k is the frame halved k times, as halfResolutionCamera describes it. */
struct LuminancePyramid
{
    std::vector<Mat> images;                  //!< CV_32FC1, level 0 the full size
    std::vector<Ptr<CameraModel>> cameras;    //!< the camera of each level
    std::vector<double> noiseSigma;           //!< Immerkær's noise estimate of each level @cite Immerkaer1996Noise

    int levels() const { return int(images.size()); }
};

/** @brief The linear luminance (mean of the color channels; alpha dropped) of an 8-bit sRGB or
linear CV_32F frame. */
Mat linearLuminance(const Mat& frame);

/** @brief Halves `luminance` while its width exceeds `coarsestWidth` and both sides are even.
@param estimateNoise take each level's noise (what a reference needs). */
LuminancePyramid buildPyramid(const Mat& luminance, const Ptr<CameraModel>& camera, int coarsestWidth,
                              bool estimateNoise);

/** @brief The noise of one frame at each level of the fit's pyramid (buildPyramid down to
kFitCoarseWidth), measured from two stills at rest at the same view: the robust standard deviation
(1.4826 × the median absolute deviation) of their pyramids' difference over √2, over the pixels
neither clips. Throws cv::Exception prefixed by `function` and naming the argument when either is not
a frame of `camera` (checkCameraFrame), their types differ, or they agree in at least half of those
pixels at a level the fit runs at (at most kFitFineWidth wide, or the smallest). */
std::vector<double> measureNoise(const Mat& stillA, const Mat& stillB, const Ptr<CameraModel>& camera,
                                 const char* function);

/** @brief The level of `pyramid` whose width is the largest at or below `width` (the coarsest when
none is). */
int levelAtMostWide(const LuminancePyramid& pyramid, int width);

//! The shutter of a frame halved `halvings` times (halfResolutionShutter applied that often).
RollingShutter shutterAtLevel(const RollingShutter& shutter, int halvings);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
