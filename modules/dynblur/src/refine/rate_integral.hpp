// SPDX-License-Identifier: Apache-2.0
// Private: a gyro log's rates integrated over time, for the turns between two instants.
#ifndef OPENCV_DYNBLUR_REFINE_RATE_INTEGRAL_HPP
#define OPENCV_DYNBLUR_REFINE_RATE_INTEGRAL_HPP

#include <opencv2/core.hpp>

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** @brief ∫ω dt of sampled body rates (linear between samples), tabulated on a uniform grid so that
the integral at any instant costs one interpolation: the turn between two instants to first order,
what a clip's coarse synchronisation compares with the image's turn between two frames thousands of
times per candidate clock offset. The grid's linear interpolation errs by at most h²·|ω'|/8 (0.5 ms
and a 20 Hz shake of 1 rad/s: 4e-6 rad). */
class RateIntegral
{
public:
    /** @param times sample times, seconds, strictly increasing (≥ 2).
    @param rates N×3 CV_64F body rates, rad/s.
    @param step the grid's step, seconds, > 0 (widened so the grid holds at most 2e6 knots). */
    RateIntegral(const std::vector<double>& times, const Mat& rates, double step = 5e-4);

    //! The integral from the first sample to t, rad; t within span().
    Vec3d at(double t) const;
    //! The rotation vector from t0 to t1 to first order (their integrals' difference), rad.
    Vec3d turn(double t0, double t1) const { return at(t1) - at(t0); }
    //! The first and last sample times, seconds.
    Vec2d span() const { return span_; }
    bool covers(double t) const { return t >= span_[0] && t <= span_[1]; }

private:
    Vec2d span_;
    double step_ = 0;
    std::vector<Vec3d> grid_;  // the integral at span_[0] + k·step_
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
