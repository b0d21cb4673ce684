// SPDX-License-Identifier: Apache-2.0
// Private: the plant's trajectory over one frame's readout, sampled at knots and interpolated.
#ifndef OPENCV_DYNBLUR_IMAGING_TRAJECTORY_HPP
#define OPENCV_DYNBLUR_IMAGING_TRAJECTORY_HPP

#include "imaging/cubic.hpp"
#include "motion/view_motion.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

//! The view's rotation relative to the reference over the frame readout, shared by all nodes of a
//! bank, sampled at knots (rotation and rate) and interpolated in between. One axis: exact plant
//! samples of θ − θ_ref, a cubic Hermite curve between them; the knots include every switch inside
//! the readout, where θ'' jumps, so each piece interpolates an analytic function. Any rotation: the
//! motion's own R(t) and spatial rates at knots dense enough that a pixel's path between two is a
//! cubic to far below a hundredth of a pixel.
struct Trajectory
{
    std::vector<double> t;      // knot times, seconds, strictly increasing
    std::vector<double> angle;  // one axis: θ − θ_ref at each knot, radians
    std::vector<double> rate;   // one axis: dθ/dt at each knot, rad/s
    std::vector<Matx33d> rot;   // R(t) at each knot (one axis: R_axis(angle))
    std::vector<Vec3d> spin;    // any rotation: the spatial rate R(t)·ω(t) at each knot, rad/s (empty for one axis)
    std::vector<double> invStep;  // 1 / (t[k+1] − t[k]), 1/seconds
    Vec3d axis;                 // one axis: the unit rotation axis
    Ptr<CameraMotion> motion;   // any rotation: the motion, and
    Matx33d reference;          // its reference orientation

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
    //! The view's rotation R(t) at any time of the readout.
    Matx33d rotationAt(double time) const
    {
        return motion ? Matx33d(reference.t() * motion->orientation(time)) : rotation(angleAt(time));
    }
    //! One axis: θ − θ_ref at any time of the readout (Hermite interpolation between knots).
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

/** @brief The trajectory of `motion` over `readout` (start, end, seconds): the one-axis form above
for a plant, else knots at most kMaxKnotStepSec apart and refined until no two are more than
kMaxKnotRotation apart. */
Trajectory sampleTrajectory(const ViewMotion& motion, const Vec2d& readout);

}  // namespace detail
}  // namespace dynblur
}  // namespace cv

#endif
