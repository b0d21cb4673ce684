// SPDX-License-Identifier: Apache-2.0
// Private: the sample-time rule every sampled motion and gyro log shares.
#ifndef OPENCV_DYNBLUR_MOTION_SAMPLED_MOTION_HPP
#define OPENCV_DYNBLUR_MOTION_SAMPLED_MOTION_HPP

#include <cstddef>
#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! A gap is too long when it exceeds this many median sample intervals: samples were lost, and
//! interpolating across them would invent the motion in between.
constexpr double kMaxGapInMedianIntervals = 3.0;

/** Index k ≥ 1 of the first interval times[k] − times[k−1] longer than kMaxGapInMedianIntervals
    median intervals, or 0 when there is none. `times` must be strictly increasing with ≥ 2
    entries; `median` receives the median interval, seconds. */
size_t findLongGap(const std::vector<double>& times, double& median);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
