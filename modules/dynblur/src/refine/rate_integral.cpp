// SPDX-License-Identifier: Apache-2.0
#include "precomp.hpp"

#include "refine/rate_integral.hpp"

#include <algorithm>

namespace cv {
namespace dynblur {
namespace detail {

RateIntegral::RateIntegral(const std::vector<double>& times, const Mat& rates, double step)
{
    CV_Assert(times.size() >= 2 && rates.rows == int(times.size()) && rates.cols == 3 && rates.type() == CV_64F);
    span_ = Vec2d(times.front(), times.back());
    step_ = std::max(step, (span_[1] - span_[0]) / 2e6);
    const size_t knots = size_t(std::ceil((span_[1] - span_[0]) / step_)) + 1;
    grid_.resize(knots);
    // Exact integral of the piecewise linear rates at each knot, walking the samples once.
    Vec3d before;  // the integral at times[k]
    size_t k = 0;
    for (size_t i = 0; i < knots; i++)
    {
        const double t = std::min(span_[1], span_[0] + double(i) * step_);
        while (k + 2 < times.size() && times[k + 1] <= t)
        {
            const Vec3d w0(rates.ptr<double>(int(k))), w1(rates.ptr<double>(int(k) + 1));
            before += 0.5 * (times[k + 1] - times[k]) * (w0 + w1);
            k++;
        }
        const double h = times[k + 1] - times[k], u = std::min(1.0, std::max(0.0, (t - times[k]) / h));
        const Vec3d w0(rates.ptr<double>(int(k))), w1(rates.ptr<double>(int(k) + 1));
        // ∫ from times[k] to t of the linear rate: h·(u·w0 + u²/2·(w1 − w0)).
        grid_[i] = before + h * (u * w0 + 0.5 * u * u * (w1 - w0));
    }
}

Vec3d RateIntegral::at(double t) const
{
    const double x = std::min(double(grid_.size() - 1), std::max(0.0, (t - span_[0]) / step_));
    const size_t i = std::min(grid_.size() - 2, size_t(x));
    const double u = x - double(i);
    return grid_[i] * (1 - u) + grid_[i + 1] * u;
}

}  // namespace detail
}  // namespace dynblur
}  // namespace cv
