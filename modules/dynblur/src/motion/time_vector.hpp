// SPDX-License-Identifier: Apache-2.0
// Private: the time arguments of the plant's evaluations, read and allocated alike for every one.
#ifndef OPENCV_DYNBLUR_MOTION_TIME_VECTOR_HPP
#define OPENCV_DYNBLUR_MOTION_TIME_VECTOR_HPP

#include <opencv2/core.hpp>

#include <vector>

namespace cv {
namespace dynblur {

//! Reads a 1-channel time vector (CV_32F or CV_64F, any shape) as doubles; names `argName` in errors.
std::vector<double> readTimeVector(InputArray t, const char* argName);

/** Reads the time argument `t` of a Plant evaluation and allocates `out` as CV_64F of t's shape.
    Returns the output's data (nullptr, with `out` released, when t is empty). */
double* allocateTimeOutput(InputArray t, OutputArray out, std::vector<double>& times);

}  // namespace dynblur
}  // namespace cv

#endif
