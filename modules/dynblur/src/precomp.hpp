#ifndef OPENCV_DYNBLUR_PRECOMP_HPP
#define OPENCV_DYNBLUR_PRECOMP_HPP

#include "opencv2/dynblur.hpp"

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace cv {
namespace dynblur {

//! Reads a 1-channel time vector (CV_32F or CV_64F, any shape) as doubles; names `argName` in errors.
std::vector<double> readTimeVector(InputArray t, const char* argName);

//! Throws cv::Exception naming the RLParams field that is out of range; `function` prefixes the message.
void checkRLParams(const RLParams& params, const char* function);

}  // namespace dynblur
}  // namespace cv

#endif
