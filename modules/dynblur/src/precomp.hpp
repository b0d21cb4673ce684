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

/** Reads the time argument `t` of a Plant evaluation and allocates `out` as CV_64F of t's shape.
    Returns the output's data (nullptr, with `out` released, when t is empty). */
double* allocateTimeOutput(InputArray t, OutputArray out, std::vector<double>& times);

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


namespace detail {

//! The linear intensity of each 8-bit sRGB code, 256 values (srgbToLinear's table).
const float* srgbDecodingTable();

/** out[x] = the 8-bit sRGB code of linear[x] (clamped to [0, 1], NaN as 0), 255·srgb rounded to
nearest: linearToSrgb's rows, for passes that write an 8-bit frame straight from their own rows. */
void encodeSrgbRow(const float* linear, int n, uchar* out);

}  // namespace detail

}  // namespace dynblur
}  // namespace cv

#endif
