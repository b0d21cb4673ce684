// SPDX-License-Identifier: Apache-2.0
// Private: a frame's planes as the restoration reads them in, and their statistics.
#ifndef OPENCV_DYNBLUR_RESTORE_FRAME_PLANES_HPP
#define OPENCV_DYNBLUR_RESTORE_FRAME_PLANES_HPP

#include <opencv2/core.hpp>

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! An image's mean over every channel and its largest value.
struct ImageLevel
{
    double mean = 0, peak = 0;
};

//! The level of an image from per-row (or per-row-and-channel) sums and peaks, added in order over `count` values.
ImageLevel foldLevel(const std::vector<double>& sums, const std::vector<double>& peaks, double count);

//! A frame as the restoration reads it: see observeFrame.
struct ObservedFrame
{
    std::vector<Mat> planes;  //!< a one-channel frame itself; a color frame's planes, split into a pool
    Scalar channelMean;       //!< each channel's mean
    ImageLevel level;         //!< over every channel
    double noiseSigma = 0;    //!< Immerkær's noise standard deviation averaged over the channels; 0 when not asked
};

/** @brief Splits `frame` (CV_32F, 1–4 channels) into its planes and takes its statistics in the
same pass. RL reads each plane every iteration, and reading one from the interleaved frame would
pull in every channel; the means, the level and the noise would each read the frame once more.
Rows in parallel, per-row partial sums added in row order (the same result on every run). A color
frame's planes go to `pool`, reused when the sizes fit.
@param estimateNoise take noiseSigma @cite Immerkaer1996Noise (what an automatic damping needs). */
CV_EXPORTS ObservedFrame observeFrame(const Mat& frame, std::vector<Mat>& pool, bool estimateNoise);

/** True when every element of `image` (CV_32F, any channels) is finite; then `low` and `high`
receive the smallest and the largest. Rows in parallel. */
bool finiteRange(const Mat& image, float& low, float& high);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
