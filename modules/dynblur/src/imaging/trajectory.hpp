// Private: the plant's trajectory over one frame's readout, sampled at knots and interpolated.
#ifndef OPENCV_DYNBLUR_IMAGING_TRAJECTORY_HPP
#define OPENCV_DYNBLUR_IMAGING_TRAJECTORY_HPP

#include "opencv2/dynblur/plant.hpp"

#include "imaging/cubic.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! The trajectory θ(t) − θ_ref over the frame readout, shared by all nodes of a bank: exact plant
//! samples (angle and rate) at knots, a cubic Hermite curve between them. The knots include every
//! switch inside the readout, where θ'' jumps, so each piece interpolates an analytic function.
struct Trajectory
{
    std::vector<double> t;      // knot times, seconds, strictly increasing
    std::vector<double> angle;  // θ − θ_ref at each knot, radians
    std::vector<double> rate;   // dθ/dt at each knot, rad/s
    std::vector<Matx33d> rot;   // R_axis(angle) at each knot
    std::vector<double> invStep;  // 1 / (t[k+1] − t[k]), 1/seconds
    Vec3d axis;

    //! R_axis(a): the view turned by `a` radians about the mount axis.
    Matx33d rotation(double a) const;
    //! Index k of the knot interval [t[k], t[k+1]] holding `time` (clamped to the first/last one).
    int segment(double time) const
    {
        const int n = (int)t.size();
        if (n < 2)
            return 0;
        const int k = (int)(std::upper_bound(t.begin(), t.end(), time) - t.begin()) - 1;
        return std::min(n - 2, std::max(0, k));
    }
    //! θ − θ_ref at any time of the readout (Hermite interpolation between knots).
    double angleAt(double time) const
    {
        if (t.size() < 2)
            return angle[0];
        const int k = segment(time);
        const double h = t[k + 1] - t[k];
        return Cubic::hermite(angle[k], rate[k], angle[k + 1], rate[k + 1], h)(std::min(h, std::max(0.0, time - t[k])));
    }
};

/** @brief The trajectory of `plant` under `schedule` over `readout` (start, end of the frame's
readout, seconds), relative to thetaRef (radians, finite), for a camera turning about the unit
`axis`: knots kKnotsPerPeriod per natural period and at every switch inside the readout, refined
until no two knots are more than kMaxKnotAngleStep apart. */
Trajectory sampleTrajectory(const Plant& plant, const SwitchSchedule& schedule, const Vec2d& readout,
                            double thetaRef, const Vec3d& axis);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
