// SPDX-License-Identifier: Apache-2.0
// Private: the cubic polynomials of a trajectory's knot intervals and of a kernel's path.
#ifndef OPENCV_DYNBLUR_IMAGING_CUBIC_HPP
#define OPENCV_DYNBLUR_IMAGING_CUBIC_HPP

#include <algorithm>
#include <cmath>
#include <utility>

namespace cv {
namespace dynblur {
namespace detail {

//! c0 + c1·s + c2·s² + c3·s³ for s in seconds from the start of a knot interval.
struct Cubic
{
    double c0, c1, c2, c3;

    //! The Hermite cubic with values p0, p1 and slopes v0, v1 at s = 0 and s = h.
    static Cubic hermite(double p0, double v0, double p1, double v1, double h) { return hermiteInv(p0, v0, p1, v1, 1 / h); }
    //! The same, given ih = 1/h.
    static Cubic hermiteInv(double p0, double v0, double p1, double v1, double ih)
    {
        const double slope = (p1 - p0) * ih;
        return Cubic{p0, v0, (3 * slope - 2 * v0 - v1) * ih, (v0 + v1 - 2 * slope) * ih * ih};
    }
    double operator()(double s) const { return c0 + s * (c1 + s * (c2 + s * c3)); }
    double slope(double s) const { return c1 + s * (2 * c2 + s * (3 * c3)); }
    //! Zeros of the slope strictly inside (lo, hi), increasing; returns their count.
    int turns(double lo, double hi, double z[2]) const
    {
        const double A = 3 * c3, B = 2 * c2, C = c1;
        // the slope A s² + B s + C keeps its sign on [lo, hi] when it does at both ends and its
        // own extremum (2 A s + B = 0) is outside: the common case, without a square root
        if (slope(lo) * slope(hi) > 0 && (2 * A * lo + B) * (2 * A * hi + B) >= 0)
            return 0;
        double r[2];
        int n = 0;
        if (A == 0)
        {
            if (B != 0)
                r[n++] = -C / B;
        }
        else
        {
            const double disc = B * B - 4 * A * C;
            if (disc >= 0)
            {
                const double q = -0.5 * (B + (B >= 0 ? 1 : -1) * std::sqrt(disc));
                r[n++] = q / A;
                if (q != 0)
                    r[n++] = C / q;
            }
        }
        int m = 0;
        for (int i = 0; i < n; i++)
            if (r[i] > lo && r[i] < hi)
                z[m++] = r[i];
        if (m == 2 && z[0] > z[1])
            std::swap(z[0], z[1]);
        return m;
    }
    /** The s in [lo, hi] where the cubic equals `target` to within 1e-9 (pixels), given that it is
    monotonic there and `target` lies between its values at lo and hi (safeguarded Newton). */
    double solve(double target, double lo, double hi) const
    {
        const double sign = (*this)(lo) < target ? 1.0 : -1.0;  // the cubic increases (+1) or decreases (−1)
        double s = lo;
        for (int it = 0; it < 60; it++)
        {
            const double f = (*this)(s) - target;
            if (std::abs(f) <= 1e-9)
                return s;
            if (f * sign < 0)
                lo = s;
            else
                hi = s;
            const double g = slope(s);
            double next = g != 0 ? s - f / g : 0.5 * (lo + hi);
            if (!(next > lo && next < hi))
                next = 0.5 * (lo + hi);
            if (next == s)
                return s;
            s = next;
        }
        return s;
    }
};

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
