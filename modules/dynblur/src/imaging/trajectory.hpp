// SPDX-License-Identifier: Apache-2.0
// Private: the plant's trajectory over one frame's readout, sampled at knots and interpolated.
#ifndef OPENCV_DYNBLUR_IMAGING_TRAJECTORY_HPP
#define OPENCV_DYNBLUR_IMAGING_TRAJECTORY_HPP

#include "opencv2/dynblur/camera_motion.hpp"
#include "opencv2/dynblur/plant.hpp"

#include "imaging/cubic.hpp"

#include <vector>

namespace cv {
namespace dynblur {
namespace detail {

/** The motion a frame's views follow, relative to the reference view, in one of two forms: a
one-axis plant (the form the one-axis API always used, kept so its results stay the same to the
bit), or any CameraMotion with its reference orientation. */
struct ViewMotion
{
    // One axis: θ(t) of `plant` under `schedule`, about the unit `axis`, relative to thetaRef (radians).
    Ptr<Plant> plant;
    SwitchSchedule schedule;
    Vec3d axis;
    double thetaRef = 0;
    // Any rotation: R(t) = referenceᵀ·Q(t) of `motion`.
    Ptr<CameraMotion> motion;
    Matx33d reference;

    bool oneAxis() const { return !plant.empty(); }

    /** The view motion of `motion` for a frame read by `shutter`, relative to its orientation at
        tRef (seconds; NaN: CameraMotion::referenceOrientation's default): the one-axis form for a
        plant's motion, the general one otherwise. */
    static ViewMotion of(const Ptr<CameraMotion>& motion, double tRef, const RollingShutter& shutter);

    /** The one-axis view motion of `plant` under `schedule` about `axis`, relative to thetaRef
        (radians; NaN: the schedule's final resting angle). Throws naming thetaRef, in the message of
        `where`, when it is infinite or more than a quarter turn from every angle the schedule holds
        (degrees given as radians: the view would turn behind the camera). */
    static ViewMotion ofPlant(const char* where, const Ptr<Plant>& plant, const SwitchSchedule& schedule,
                              const Vec3d& axis, double thetaRef);
};

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
